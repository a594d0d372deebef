// [Dataset] label_masks: per-frame masks next to a TUM folder's images become the scans'
// pixel labels.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/tum.h"
#include "test_data.h"
#include "tum_folder.h"

namespace {

using namespace gmc::datasets;

std::vector<RgbdFrame> twoFrames() {
  std::vector<RgbdFrame> frames(2);
  for (int i = 0; i < 2; ++i) {
    frames[i].stamp = 10 + i / 30.0;
    frames[i].rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(40, 80, 120));
    frames[i].depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(5000));
  }
  return frames;
}

std::string folderWithMasks(const std::string& name, int masks) {
  const std::string dir = gmc::testdata::scratchDir("label_masks_" + name);
  gmc::testdata::writeTumFolder(dir, twoFrames());
  std::filesystem::create_directories(dir + "/masks");
  for (int i = 0; i < masks; ++i) {
    cv::Mat mask = cv::Mat::zeros(24, 32, CV_8UC1);
    mask.at<std::uint8_t>(5, 7 + i) = 255;
    cv::imwrite(dir + "/masks/" + std::to_string(i) + ".png", mask);
  }
  return dir;
}

TEST(LabelMasks, AFoldersMasksBecomeTheScansPixelLabel) {
  const auto dir = folderWithMasks("read", 2);
  auto source = openRgbdSource(dir, gmc::PinholeCamera{}, {}, {}, LabelMasks{"masks", "person"});
  RgbdFrame frame;
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(source->next(frame));
    ASSERT_EQ(frame.pixel_labels.size(), 1u);
    EXPECT_EQ(frame.pixel_labels[0].first, "person");
    EXPECT_EQ(cv::countNonZero(frame.pixel_labels[0].second), 1);
    const auto obs = observationOf(frame);
    ASSERT_TRUE(obs->hasPixelLabels());
    EXPECT_EQ(obs->pixelLabels->getLabelName(0), "person");
    EXPECT_TRUE(obs->pixelLabels->checkLabel(5, 7 + i, 0));
    EXPECT_FALSE(obs->pixelLabels->checkLabel(5, 8 - i, 0));
  }
  auto without = openRgbdSource(dir, gmc::PinholeCamera{});
  ASSERT_TRUE(without->next(frame));
  EXPECT_TRUE(frame.pixel_labels.empty());
  EXPECT_FALSE(observationOf(frame)->hasPixelLabels());
}

TEST(LabelMasks, AMissingMaskNamesItsFile) {
  const auto dir = folderWithMasks("missing", 1);
  auto source = openRgbdSource(dir, gmc::PinholeCamera{}, {}, {}, LabelMasks{"masks", "person"});
  RgbdFrame frame;
  ASSERT_TRUE(source->next(frame));
  try {
    source->next(frame);
    FAIL() << "frame 1 has no mask";
  } catch (const FrameReadError& e) {
    EXPECT_NE(std::string(e.what()).find("masks/1.png"), std::string::npos) << e.what();
  }
}

TEST(LabelMasks, RawlogsAndUndistortedFoldersRefuseThem) {
  const auto dir = folderWithMasks("refused", 2);
  EXPECT_THROW(openRgbdSource(dir, gmc::PinholeCamera{}, {}, presetDistortion("fr1"), LabelMasks{"masks", "person"}),
               InputError);
  const std::string rawlog = dir + "/x.rawlog";
  std::ofstream(rawlog) << "";
  EXPECT_THROW(openRgbdSource(rawlog, gmc::PinholeCamera{}, {}, {}, LabelMasks{"masks", "person"}), InputError);
}

}  // namespace
