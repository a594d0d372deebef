#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "test_data.h"

namespace {

using namespace gmc::datasets;
namespace fs = std::filesystem;

RgbdFrame randomFrame(double stamp, unsigned seed) {
  std::mt19937 rng(seed);
  RgbdFrame f;
  f.stamp = stamp;
  f.rgb.create(48, 64, CV_8UC3);
  f.depth.create(48, 64, CV_16UC1);
  cv::randu(f.rgb, 0, 255);
  cv::randu(f.depth, 0, 30000);
  f.camera.fx = 60, f.camera.fy = 61, f.camera.cx = 31.5, f.camera.cy = 23.5;
  f.camera.width = 64, f.camera.height = 48;
  return f;
}

void expectSame(const RgbdFrame& a, const RgbdFrame& b) {
  EXPECT_NEAR(a.stamp, b.stamp, 1e-6);  // microseconds
  EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0);
  EXPECT_DOUBLE_EQ(a.depth_units, b.depth_units);  // 1/5000 exactly, though MRPT stores a float
  EXPECT_DOUBLE_EQ(a.camera.fx, b.camera.fx);
  EXPECT_DOUBLE_EQ(a.camera.cy, b.camera.cy);
}

/// The rawlog at `path` reads back as exactly `frames`.
void expectSequence(const std::string& path, const std::vector<RgbdFrame>& frames) {
  auto src = openRgbdSource(path, {});
  RgbdFrame f;
  for (const auto& expected : frames) {
    ASSERT_TRUE(src->next(f));
    expectSame(expected, f);
  }
  EXPECT_FALSE(src->next(f));
}

TEST(Rawlog, WriteThenReadGivesTheSameFrames) {
  for (bool externalize : {false, true}) {
    const auto dir = gmc::testdata::scratchDir(externalize ? "rawlog_ext" : "rawlog");
    const std::string path = dir + "/seq.rawlog";
    std::vector<RgbdFrame> frames;
    {
      RawlogWriter w(path, externalize);
      for (int i = 0; i < 3; ++i) {
        frames.push_back(randomFrame(1305031102.175304 + i / 30.0, static_cast<unsigned>(i)));
        w.write(frames.back());
      }
      EXPECT_FALSE(fs::exists(path)) << "visible before close()";
      w.close();
    }
    ASSERT_TRUE(fs::exists(path));
    EXPECT_EQ(fs::exists(dir + "/seq_Images"), externalize);
    expectSequence(path, frames);
  }
}

TEST(Rawlog, UnclosedWriterLeavesNoFile) {
  for (bool externalize : {false, true}) {
    const auto dir = gmc::testdata::scratchDir("rawlog_unclosed");
    {
      RawlogWriter w(dir + "/x.rawlog", externalize);
      w.write(randomFrame(1.0, 1));
      EXPECT_EQ(fs::exists(dir + "/x_Images"), externalize);
    }
    EXPECT_TRUE(fs::is_empty(dir)) << "externalize " << externalize;
  }
}

TEST(Rawlog, SensoryFrameFormatIsReadAndOtherObservationsSkipped) {
  const auto dir = gmc::testdata::scratchDir("rawlog_sf");
  const std::string path = dir + "/sf.rawlog";
  std::vector<RgbdFrame> frames;
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    for (int i = 0; i < 2; ++i) {
      frames.push_back(randomFrame(1000.0 + i, static_cast<unsigned>(10 + i)));
      mrpt::obs::CActionCollection actions;
      mrpt::obs::CSensoryFrame sf;
      auto odo = std::make_shared<mrpt::obs::CObservationOdometry>();
      odo->timestamp = mrpt::Clock::fromDouble(frames.back().stamp);
      sf.insert(odo);  // not an RGB-D observation: skipped by the reader
      sf.insert(toObservation(frames.back()));
      archive << actions << sf;
    }
  }
  expectSequence(path, frames);
}

TEST(Rawlog, MrptSampleLoadsThroughTheSameReader) {
  const std::string sample = "/usr/share/mrpt/datasets/tests_rgbd.rawlog";
  if (!fs::exists(sample)) GTEST_SKIP() << sample << " missing (Debian package mrpt-common)";
  auto src = openRgbdSource(sample, {});
  RgbdFrame f;
  ASSERT_TRUE(src->next(f));
  EXPECT_EQ(f.depth.cols, 640);
  EXPECT_EQ(f.depth.rows, 480);
  EXPECT_EQ(f.rgb.type(), CV_8UC3);
  EXPECT_GT(cv::countNonZero(f.depth), 1000);
  EXPECT_GT(f.camera.fx, 100);
}

TEST(Source, TumFolderPairsAndReportsBadFrames) {
  const auto dir = gmc::testdata::scratchDir("tum_folder");
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  const auto f = randomFrame(0, 3);
  cv::imwrite(dir + "/rgb/1.000000.png", f.rgb);
  cv::imwrite(dir + "/depth/1.004000.png", f.depth);
  cv::imwrite(dir + "/rgb/2.000000.png", f.rgb);
  cv::imwrite(dir + "/depth/2.001000.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(3)));  // 8-bit
  cv::imwrite(dir + "/rgb/3.000000.png", f.rgb);  // no depth within 0.02 s
  std::ofstream(dir + "/rgb.txt") << "# rgb\n1.000000 rgb/1.000000.png\n2.000000 rgb/2.000000.png\n3.000000 rgb/3.000000.png\n";
  std::ofstream(dir + "/depth.txt") << "1.004000 depth/1.004000.png\n2.001000 depth/2.001000.png\n3.100000 depth/missing.png\n";
  auto src = openRgbdSource(dir, gmc::PinholeCamera{});
  EXPECT_EQ(src->sizeHint(), 2u);
  RgbdFrame out;
  ASSERT_TRUE(src->next(out));
  EXPECT_EQ(cv::norm(out.depth, f.depth, cv::NORM_INF), 0);
  EXPECT_DOUBLE_EQ(out.stamp, 1.0);
  try {
    src->next(out);
    FAIL() << "8-bit depth accepted";
  } catch (const FrameReadError& e) {
    EXPECT_NE(std::string(e.what()).find("depth/2.001000.png (depth.txt:2)"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(src->next(out));
  const auto pairing = pairTumFolder(dir);
  ASSERT_EQ(pairing.unpaired_rgb.size(), 1u);
  EXPECT_EQ(pairing.unpaired_rgb[0].path, "rgb/3.000000.png");
  EXPECT_EQ(pairing.unpaired_rgb[0].line, 4u);  // after the comment line
}

TEST(Source, MissingInputsAreNamed) {
  EXPECT_THROW(openRgbdSource("/nonexistent/seq.rawlog", {}), InputError);
  const auto dir = gmc::testdata::scratchDir("tum_empty");
  try {
    openRgbdSource(dir, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/rgb.txt"), std::string::npos) << e.what();
  }
}

TEST(Source, RealTumFolderDepthIsPngOver5000) {
  GMC_REQUIRE_DATA(dir, "tum_fr3_teddy_1_100");
  auto src = openRgbdSource(dir, {});
  RgbdFrame f;
  ASSERT_TRUE(src->next(f));
  const auto list = readTumList(dir + "/depth.txt");
  const cv::Mat png = cv::imread(dir + "/" + list[0].path, cv::IMREAD_ANYDEPTH);
  for (auto [u, v] : {std::pair{100, 100}, {320, 240}, {500, 400}})
    EXPECT_DOUBLE_EQ(f.depthAt(u, v), png.at<std::uint16_t>(v, u) / 5000.0);
}

TEST(AtomicFile, FailedWriteLeavesNothing) {
  const auto dir = gmc::testdata::scratchDir("atomic");
  writeTextAtomic(dir + "/a.txt", "hello");
  EXPECT_TRUE(fs::exists(dir + "/a.txt"));
  EXPECT_THROW(writeTextAtomic(dir + "/no/such/dir/b.txt", "x"), std::runtime_error);
  EXPECT_THROW(writeImageAtomic(dir + "/c.png", cv::Mat()), std::runtime_error);
  size_t files = 0;
  for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
}

}  // namespace
