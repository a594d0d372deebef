#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "random_frame.h"
#include "test_data.h"
#include "wrong_class_rawlog.h"

namespace {

using namespace gmc::datasets;
namespace fs = std::filesystem;

using gmc::testdata::randomFrame;

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

/// Writes `n` random frames to `path` with our writer; returns them.
std::vector<RgbdFrame> writeFrames(const std::string& path, int n, bool externalize = false) {
  std::vector<RgbdFrame> frames;
  RawlogWriter w(path, externalize);
  for (int i = 0; i < n; ++i) {
    frames.push_back(randomFrame(2000.0 + i / 30.0, static_cast<unsigned>(20 + i)));
    w.write(frames.back());
  }
  w.close();
  return frames;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Rawlog, CutMidObjectIsAnInputErrorNamingFileAndObject) {
  const auto dir = gmc::testdata::scratchDir("rawlog_cut");
  const std::string good = dir + "/good.rawlog", cut = dir + "/cut.rawlog";
  writeFrames(good, 3);
  // Uncompressed copy, so the cut lands at a known place: in the middle of the third object.
  std::string bytes;
  {
    mrpt::io::CFileGZInputStream in(good);
    char buf[4096];
    for (size_t n; (n = in.Read(buf, sizeof buf)) > 0;) bytes.append(buf, n);
  }
  std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() * 5 / 6));
  auto src = openRgbdSource(cut, {});
  RgbdFrame f;
  ASSERT_TRUE(src->next(f));
  ASSERT_TRUE(src->next(f));
  try {
    src->next(f);
    FAIL() << "truncated rawlog read to the end";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), cut + ": object 2: truncated or corrupt rawlog")) << e.what();
  }
  // The compressed file cut short: the same error, wherever the cut lands.
  for (double fraction : {0.1, 0.5, 0.9}) {
    const auto size = fs::file_size(good);
    std::string gz(size, '\0');
    std::ifstream(good, std::ios::binary).read(gz.data(), static_cast<std::streamsize>(size));
    std::ofstream(cut, std::ios::binary | std::ios::trunc)
        .write(gz.data(), static_cast<std::streamsize>(static_cast<double>(size) * fraction));
    const std::string msg = messageOf([&] {
      auto s = openRgbdSource(cut, {});
      RgbdFrame g;
      while (s->next(g)) {
      }
    });
    EXPECT_TRUE(contains(msg, cut + ": object ")) << fraction << ": " << msg;
    EXPECT_TRUE(contains(msg, "truncated or corrupt")) << fraction << ": " << msg;
  }
}

TEST(Rawlog, RawlogWithoutRgbdObservationsIsNamed) {
  const auto dir = gmc::testdata::scratchDir("rawlog_wrong_class");
  const std::string path = gmc::testdata::writeWrongClassRawlog(dir + "/scan2d.rawlog");
  const std::string msg = messageOf([&] {
    auto s = openRgbdSource(path, {});
    RgbdFrame f;
    s->next(f);
  });
  EXPECT_TRUE(contains(msg, path + ": no CObservation3DRangeScan in the rawlog (found "
                                   "mrpt::obs::CObservation2DRangeScan, mrpt::obs::CObservationOdometry)"))
      << msg;
  {
    mrpt::io::CFileGZOutputStream out(dir + "/empty.rawlog");
  }
  EXPECT_TRUE(contains(messageOf([&] {
                         RgbdFrame f;
                         openRgbdSource(dir + "/empty.rawlog", {})->next(f);
                       }),
                       "empty.rawlog: empty rawlog"));
  // Garbage that is no MRPT object at all.
  std::ofstream(dir + "/text.rawlog") << "this is not a rawlog\n";
  EXPECT_TRUE(contains(messageOf([&] {
                         RgbdFrame f;
                         openRgbdSource(dir + "/text.rawlog", {})->next(f);
                       }),
                       "text.rawlog: object 0: truncated or corrupt rawlog"));
}

TEST(Rawlog, MissingExternalImageSkipsThatFrameAndNamesTheFile) {
  const auto dir = gmc::testdata::scratchDir("rawlog_ext_missing");
  const auto frames = writeFrames(dir + "/seq.rawlog", 3, true);
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(dir + "/seq_Images")) images.push_back(e.path());
  std::sort(images.begin(), images.end());
  ASSERT_EQ(images.size(), 3u);
  fs::remove(images[1]);
  auto src = openRgbdSource(dir + "/seq.rawlog", {});
  RgbdFrame f;
  ASSERT_TRUE(src->next(f));
  expectSame(frames[0], f);
  try {
    src->next(f);
    FAIL() << "missing image not reported";
  } catch (const FrameReadError& e) {
    EXPECT_TRUE(contains(e.what(), dir + "/seq.rawlog#1: external image ")) << e.what();
    EXPECT_TRUE(contains(e.what(), images[1].filename().string() + " is missing")) << e.what();
  }
  ASSERT_TRUE(src->next(f));
  expectSame(frames[2], f);
  EXPECT_FALSE(src->next(f));
}

// Fuzz finding (fuzz_rawlog): a corrupt JPEG-compressed image inside a rawlog makes MRPT's
// libjpeg error handler call exit(1) mid-read. The reader cannot catch that; it names the
// file and object on the way out, and the exit status stays non-zero.
TEST(RawlogDeathTest, CorruptJpegImageEndsTheProcessNamingFileAndObject) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto dir = gmc::testdata::scratchDir("rawlog_jpeg");
  const std::string path = dir + "/jpeg.rawlog";
  {
    const bool was = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);  // as some MRPT grabbers write them
    mrpt::io::CFileOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    auto f = randomFrame(1.0, 5);
    f.rgb = cv::Mat(240, 320, CV_8UC3, cv::Scalar(40, 90, 200));
    f.depth = cv::Mat(240, 320, CV_16UC1, cv::Scalar(5000));
    archive << *toObservation(f);
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(was);
  }
  std::string bytes(fs::file_size(path), '\0');
  std::ifstream(path, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const auto soi = bytes.find("\xFF\xD8\xFF");
  ASSERT_NE(soi, std::string::npos) << "image not stored as JPEG";
  bytes[soi] = bytes[soi + 1] = '\0';  // "Not a JPEG file"
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  EXPECT_EXIT(
      {
        auto src = openRgbdSource(path, {});
        RgbdFrame f;
        while (src->next(f)) {
        }
      },
      testing::ExitedWithCode(1), "jpeg.rawlog: object 0: corrupt object; MRPT ended the process");
}

TEST(Rawlog, ObservationsThatAreNoRgbdFrameAreRejectedWithTheReason) {
  auto obs = [] { return toObservation(randomFrame(1.0, 7)); };
  auto reason = [](const mrpt::obs::CObservation3DRangeScan& o) {
    return messageOf([&] { fromObservation(o); });
  };
  auto o = obs();
  o->intensityImage = mrpt::img::CImage(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(0)), mrpt::img::DEEP_COPY);
  EXPECT_TRUE(contains(reason(*o), "intensity image is 32x24, range image is 64x48")) << reason(*o);
  o = obs();
  o->intensityImage = mrpt::img::CImage(cv::Mat(48, 64, CV_16UC1, cv::Scalar::all(0)), mrpt::img::DEEP_COPY);
  EXPECT_TRUE(contains(reason(*o), "8-bit grey or colour")) << reason(*o);
  o = obs();
  o->cameraParamsIntensity.fx(std::nan(""));
  EXPECT_TRUE(contains(reason(*o), "intrinsics")) << reason(*o);
  o = obs();
  o->rangeUnits = 0;
  EXPECT_TRUE(contains(reason(*o), "rangeUnits")) << reason(*o);
  o = obs();
  o->rangeImage.resize(0, 0);
  EXPECT_TRUE(contains(reason(*o), "empty range image")) << reason(*o);
  o = obs();
  o->range_is_depth = false;
  EXPECT_TRUE(contains(reason(*o), "range_is_depth")) << reason(*o);
  // Fuzz finding: MRPT reads a corrupt file's byte straight into a bool member; ours now
  // reads that byte instead of using a bool that is neither true nor false.
  o = obs();
  std::memset(static_cast<void*>(&o->hasRangeImage), 98, 1);
  EXPECT_EQ(reason(*o), "hasRangeImage holds 98, not a bool (corrupt observation)");
  o = obs();
  std::memset(static_cast<void*>(&o->hasIntensityImage), 6, 1);
  EXPECT_TRUE(contains(reason(*o), "hasIntensityImage holds 6")) << reason(*o);
  o = obs();
  EXPECT_EQ(reason(*o), "(no exception)");
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
