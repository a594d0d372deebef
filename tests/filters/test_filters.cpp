#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/TPixelLabelInfo.h>

#include <algorithm>

#include "gmc/config/ini.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/filters/filter.h"
#include "gmc/filters/gmc_filter.h"

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
  ASSERT_NE(trackingOf(ctx), nullptr);
  EXPECT_EQ(trackingOf(ctx)->state, gmc::vo::TrackingState::Initialized);
  ASSERT_TRUE(obs->hasPixelLabels());
  EXPECT_EQ(obs->pixelLabels->getLabelName(0), kDynamicLabel);
  EXPECT_EQ(ctx.dynamic_mask.size(), cv::Size(64, 48));

  auto no_depth = makeObs(2.0);
  no_depth->hasRangeImage = false;
  EXPECT_THROW(applyChain(chain, *no_depth, ctx), std::runtime_error);
}

TEST(Filters, FinishingTheChainGivesTheGmcFiltersLastRevisions) {
  auto chain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = depth_range, gmc\n"), "t.ini");
  auto obs = makeObs(1.0);
  FilterContext ctx;
  ASSERT_TRUE(applyChain(chain, *obs, ctx));
  FilterContext end;
  finishChain(chain, end);
  ASSERT_NE(finalRevisionsOf(end), nullptr) << "the gmc filter set no final revisions";
  EXPECT_TRUE(finalRevisionsOf(end)->empty());  // one frame: no run to fit
  FilterContext none;
  auto plain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = depth_range\n"), "t.ini");
  finishChain(plain, none);
  EXPECT_EQ(finalRevisionsOf(none), nullptr);
}

/// Frames kept by a chain out of `n`.
int keptOf(FilterChain& chain, int n) {
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    auto obs = makeObs(i);
    FilterContext ctx;
    kept += applyChain(chain, *obs, ctx) ? 1 : 0;
  }
  return kept;
}

TEST(Filters, EachInstanceReadsItsOwnSection) {
  auto chain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate, decimate@DecimateMore\n"
                                                          "[Decimate]\nkeep_every = 2\n[DecimateMore]\nkeep_every = 3\n"),
                          "t.ini");
  ASSERT_EQ(chain.size(), 2u);
  EXPECT_EQ(keptOf(chain, 12), 2) << "12 frames -> 6 (every 2nd) -> 2 (every 3rd)";
  auto single = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate@DecimateMore\n"
                                                           "[DecimateMore]\nkeep_every = 3\n"),
                           "t.ini");
  EXPECT_EQ(keptOf(single, 12), 4) << "[Decimate]'s default (1) is not what it reads";
  try {
    buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate@Slow\n[Slow]\nkeep = 3\n"), "t.ini");
    FAIL() << "unknown key in the instance's section";
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[Slow]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate@\n"), "t.ini"),
               gmc::cfg::ConfigError);
}

/// A filter from outside the library: drops observations whose depth at the centre is 0.
class CentreDepthFilter : public ObservationFilter {
 public:
  std::string name() const override { return "test_centre_depth"; }
  std::string defaultSection() const override { return "CentreDepth"; }
  void initialize(const mrpt::config::CConfigFileBase&, const std::string& section, const std::string&) override {
    section_ = section;
  }
  std::vector<std::string> needs() const override { return {kTracking}; }
  bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext&) override {
    return obs.rangeImage(obs.rangeImage.rows() / 2, obs.rangeImage.cols() / 2) != 0;
  }
  std::string section_;
};

const bool kRegistered = registerFilter("test_centre_depth", [] { return std::make_unique<CentreDepthFilter>(); });

TEST(Filters, RegistryIsExtendedFromOutsideTheLibrary) {
  ASSERT_TRUE(kRegistered);
  const auto names = availableFilters();
  EXPECT_NE(std::find(names.begin(), names.end(), "test_centre_depth"), names.end());
  EXPECT_THROW(registerFilter("test_centre_depth", [] { return std::make_unique<CentreDepthFilter>(); }),
               std::invalid_argument);
  auto chain = buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = gmc, test_centre_depth@Mine\n"), "t.ini");
  ASSERT_EQ(chain.size(), 2u);
  EXPECT_EQ(dynamic_cast<CentreDepthFilter&>(*chain[1]).section_, "Mine");
  auto obs = makeObs(1.0);
  obs->rangeImage(24, 32) = 0;
  FilterContext ctx;
  EXPECT_FALSE(applyChain(chain, *obs, ctx));
  const auto sections = filterSections(mrpt::config::CConfigFileMemory("[Filters]\nchain = test_centre_depth@Mine\n"), "t.ini");
  EXPECT_NE(std::find(sections.begin(), sections.end(), "Mine"), sections.end());
  EXPECT_NE(std::find(sections.begin(), sections.end(), "CentreDepth"), sections.end());
}

TEST(Filters, ChainIsCheckedWhenBuilt) {
  try {
    buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = test_centre_depth, gmc\n"), "t.ini");
    FAIL() << "a need not met by an earlier filter";
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'test_centre_depth' needs 'tracking' from a filter before it"),
              std::string::npos) << e.what();
  }
  try {
    buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate\n"), "t.ini", {kTracking});
    FAIL() << "the caller needs the tracking";
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.ini: [Filters] chain must contain a filter that provides 'tracking' (gmc)"),
              std::string::npos) << e.what();
  }
  EXPECT_EQ(buildChain(mrpt::config::CConfigFileMemory("[Filters]\nchain = decimate, gmc\n"), "t.ini", {kTracking}).size(), 2u);
}

TEST(Filters, SettingsAreSavedAsRead) {
  mrpt::config::CConfigFileMemory ini("[Filters]\nchain = gmc, decimate@Half\n[Half]\nkeep_every = 2\n[GMC]\ngrid_cols = 16\n");
  mrpt::config::CConfigFileMemory out;
  saveFilterSettings(ini, "t.ini", out);
  EXPECT_EQ(out.read_string("Filters", "chain", ""), "gmc, decimate@Half");
  EXPECT_EQ(out.read_int("Half", "keep_every", 0), 2);
  EXPECT_EQ(out.read_int("Decimate", "keep_every", 0), 1);
  EXPECT_EQ(out.read_int("GMC", "grid_cols", 0), 16);
  EXPECT_DOUBLE_EQ(out.read_double("DepthRange", "max_depth", 0), 5.0);
}

}  // namespace
