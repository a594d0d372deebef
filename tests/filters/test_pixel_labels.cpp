// Pixel labels: the gmc filter's 'dynamic' label joins the labels an observation already carries.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include "gmc/datasets/rawlog.h"
#include "gmc/config/ini.h"
#include "gmc/datasets/pixel_labels.h"
#include "gmc/filters/filter.h"

namespace {

using namespace gmc::filters;
using gmc::datasets::withLabel;
using gmc::datasets::pixelsLabelled;
using mrpt::obs::TPixelLabelInfo;

/// A 6x4 mask with the given pixels set.
cv::Mat maskOf(std::initializer_list<cv::Point> pixels) {
  cv::Mat m = cv::Mat::zeros(4, 6, CV_8UC1);
  for (const auto& p : pixels) m.at<std::uint8_t>(p) = 255;
  return m;
}

/// 8 labels "l0".."l7" on a 6x4 image, label k set on pixel (k % 6, k / 6 % 4).
std::shared_ptr<TPixelLabelInfo<1>> fullByte() {
  auto labels = std::make_shared<TPixelLabelInfo<1>>();
  labels->setSize(4, 6);
  for (int k = 0; k < 8; ++k) {
    labels->setLabelName(static_cast<unsigned>(k), "l" + std::to_string(k));
    labels->setLabel(k / 6 % 4, k % 6, static_cast<std::uint8_t>(k));
  }
  return labels;
}

int indexOf(const mrpt::obs::TPixelLabelInfoBase& labels, const std::string& name) {
  for (const auto& [index, label] : labels.pixelLabelNames)
    if (label == name) return static_cast<int>(index);
  return -1;
}

TEST(PixelLabels, ANewLabelTakesAFreeIndexAndKeepsTheOthers) {
  auto person = std::make_shared<TPixelLabelInfo<1>>();
  person->setSize(4, 6);
  person->setLabelName(0, "person");
  person->setLabel(1, 2, 0);
  const auto out = withLabel(person, maskOf({{2, 1}, {5, 3}}), "dynamic");
  ASSERT_EQ(indexOf(*out, "dynamic"), 1);
  EXPECT_TRUE(out->checkLabel(1, 2, 0)) << "person kept";
  EXPECT_TRUE(out->checkLabel(1, 2, 1));
  EXPECT_TRUE(out->checkLabel(3, 5, 1));
  EXPECT_FALSE(out->checkLabel(3, 5, 0));
  EXPECT_FALSE(out->checkLabel(0, 0, 1));
  EXPECT_FALSE(person->checkLabel(1, 2, 1)) << "the input is not modified (observations may share it)";
}

TEST(PixelLabels, AnExistingLabelOfTheSameNameIsReplaced) {
  auto old = withLabel(nullptr, maskOf({{0, 0}, {1, 1}}), "dynamic");
  ASSERT_EQ(indexOf(*old, "dynamic"), 0);
  const auto out = withLabel(old, maskOf({{1, 1}, {4, 2}}), "dynamic");
  EXPECT_EQ(out->pixelLabelNames.size(), 1u);
  EXPECT_FALSE(out->checkLabel(0, 0, 0)) << "cleared where the new mask is empty";
  EXPECT_TRUE(out->checkLabel(1, 1, 0));
  EXPECT_TRUE(out->checkLabel(2, 4, 0));
}

TEST(PixelLabels, AFullFieldIsWidenedWithEveryBitKept) {
  const auto full = fullByte();
  const auto out = withLabel(full, maskOf({{3, 3}}), "dynamic");
  EXPECT_EQ(out->BITFIELD_BYTES, 2u);
  ASSERT_EQ(indexOf(*out, "dynamic"), 8);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(indexOf(*out, "l" + std::to_string(k)), k);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 6; ++c)
        EXPECT_EQ(out->checkLabel(r, c, static_cast<std::uint8_t>(k)), full->checkLabel(r, c, static_cast<std::uint8_t>(k)))
            << "label " << k << " at " << r << "," << c;
  }
  EXPECT_TRUE(out->checkLabel(3, 3, 8));
  EXPECT_FALSE(out->checkLabel(0, 0, 8));
}

TEST(PixelLabels, SizeMismatchAndSixtyFourLabelsAreErrors) {
  auto small = std::make_shared<TPixelLabelInfo<1>>();
  small->setSize(2, 3);
  EXPECT_THROW(withLabel(small, maskOf({}), "dynamic"), std::runtime_error);
  auto all = std::make_shared<TPixelLabelInfo<8>>();
  all->setSize(4, 6);
  for (unsigned k = 0; k < 64; ++k) all->setLabelName(k, "l" + std::to_string(k));
  try {
    withLabel(all, maskOf({}), "dynamic");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("64 labels"), std::string::npos) << e.what();
  }
}

/// A 64x48 frame of a flat wall 2 m away.
gmc::datasets::RgbdFrame wallFrame() {
  gmc::datasets::RgbdFrame f;
  f.stamp = 1;
  f.rgb = cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  f.depth = cv::Mat(48, 64, CV_16UC1, cv::Scalar(10000));
  f.camera.fx = f.camera.fy = 50, f.camera.cx = 32, f.camera.cy = 24;
  return f;
}

TEST(PixelLabels, TheGmcFilterKeepsTheLabelsAnObservationCarries) {
  auto obs = gmc::datasets::toObservation(wallFrame());
  auto floor = std::make_shared<TPixelLabelInfo<1>>();
  floor->setSize(48, 64);
  floor->setLabelName(0, "floor");
  for (int c = 0; c < 64; ++c) floor->setLabel(47, c, 0);
  obs->pixelLabels = floor;
  auto chain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = gmc\n"), "t.ini");
  FilterContext ctx;
  ASSERT_TRUE(applyChain(chain, *obs, ctx));
  ASSERT_TRUE(obs->hasPixelLabels());
  EXPECT_EQ(indexOf(*obs->pixelLabels, "floor"), 0);
  EXPECT_EQ(indexOf(*obs->pixelLabels, kDynamicLabel), 1);
  for (int c = 0; c < 64; ++c) EXPECT_TRUE(obs->pixelLabels->checkLabel(47, c, 0)) << c;
}

// [GmcFilter] known_dynamic_labels: pixels an earlier stage labelled (here "person", the
// left third) are dynamic in the filter's mask and for the odometry.
TEST(PixelLabels, KnownDynamicLabelsJoinTheDynamicMask) {
  gmc::datasets::RgbdFrame f = wallFrame();
  cv::Mat person = cv::Mat::zeros(48, 64, CV_8UC1);
  person.colRange(0, 20).setTo(255);
  f.pixel_labels.emplace_back("person", person);
  auto run = [&](const std::string& ini) {
    auto obs = gmc::datasets::observationOf(f);
    auto chain = buildChain(mrpt::config::CConfigFileMemory(ini), "t.ini");
    FilterContext ctx;
    EXPECT_TRUE(applyChain(chain, *obs, ctx));
    return cv::countNonZero(ctx.dynamic_mask(cv::Rect(0, 0, 20, 48)));
  };
  EXPECT_EQ(run("[Filters]\nchain = gmc\n[GmcFilter]\nknown_dynamic_labels = chair, person\n"), 20 * 48);
  EXPECT_EQ(run("[Filters]\nchain = gmc\n"), 0) << "not named: not known";
  try {
    buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = gmc\n[GmcFilter]\nknown_dynamic_labels = person,,chair\n"),
               "t.ini");
    FAIL();
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("known_dynamic_labels"), std::string::npos) << e.what();
  }
}

}  // namespace
