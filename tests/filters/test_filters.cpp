#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/TPixelLabelInfo.h>

#include "gmc/config/ini.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/filters/filter.h"

namespace {

using namespace gmc::filters;

mrpt::obs::CObservation3DRangeScan::Ptr makeObs(double stamp) {
  gmc::datasets::RgbdFrame f;
  f.stamp = stamp;
  f.rgb = cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  f.depth = cv::Mat(48, 64, CV_16UC1, cv::Scalar(10000));  // 2 m
  f.depth.at<std::uint16_t>(0, 0) = 500;                      // 0.1 m
  f.depth.at<std::uint16_t>(0, 1) = 40000;                    // 8 m
  f.camera.fx = f.camera.fy = 50, f.camera.cx = 32, f.camera.cy = 24;
  return gmc::datasets::toObservation(f);
}

TEST(Filters, ChainIsBuiltInOrderFromIni) {
  mrpt::config::CConfigFileMemory ini("[Filters]\nchain = depth_range, decimate, gmc\n[Decimate]\nkeep_every = 2\n");
  const auto chain = buildChain(ini, "t.ini");
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[0]->name(), "depth_range");
  EXPECT_EQ(chain[1]->name(), "decimate");
  EXPECT_EQ(chain[2]->name(), "gmc");
}

TEST(Filters, UnknownFiltersAndKeysAreNamed) {
  try {
    buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = gmc, blur\n"), "t.ini");
    FAIL();
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown filter 'blur'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate\n[Decimate]\nevery = 2\n"), "t.ini"),
               gmc::cfg::ConfigError);
  EXPECT_THROW(buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = depth_range\n[DepthRange]\nmin_depth = 3\nmax_depth = 2\n"), "t.ini"),
               gmc::cfg::ConfigError);
}

TEST(Filters, DepthRangeAndDecimate) {
  auto chain = buildChain(mrpt::config::CConfigFileMemory(
                              "[Filters]\nchain = depth_range, decimate\n[DepthRange]\nmin_depth = 0.3\n"
                              "max_depth = 5\n[Decimate]\nkeep_every = 3\n"),
                          "t.ini");
  int kept = 0;
  for (int i = 0; i < 9; ++i) {
    auto obs = makeObs(i);
    FilterContext ctx;
    if (!applyChain(chain, *obs, ctx)) continue;
    ++kept;
    EXPECT_EQ(obs->rangeImage(0, 0), 0);      // too close
    EXPECT_EQ(obs->rangeImage(0, 1), 0);      // too far
    EXPECT_EQ(obs->rangeImage(5, 5), 10000);  // kept
  }
  EXPECT_EQ(kept, 3);
}

TEST(Filters, GmcFilterTracksAndWritesDynamicPixelLabels) {
  auto chain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = gmc\n[GmcFilter]\nzero_dynamic_depth = true\n"), "t.ini");
  auto obs = makeObs(1.0);
  FilterContext ctx;
  ASSERT_TRUE(applyChain(chain, *obs, ctx));
  ASSERT_TRUE(ctx.tracking.has_value());
  EXPECT_EQ(ctx.tracking->state, gmc::vo::TrackingState::Initialized);
  ASSERT_TRUE(obs->hasPixelLabels());
  EXPECT_EQ(obs->pixelLabels->getLabelName(0), kDynamicLabel);
  EXPECT_EQ(ctx.dynamic_mask.size(), cv::Size(64, 48));

  auto no_depth = makeObs(2.0);
  no_depth->hasRangeImage = false;
  EXPECT_THROW(applyChain(chain, *no_depth, ctx), std::runtime_error);
}

}  // namespace
