// [GMC] and [GMS] sections through the strict INI loader (built when libs/config is).
#include <gtest/gtest.h>

#include "gmc/config/ini.h"
#include "gmc/gmc/gmc.h"
#include "gmc/gmc/gms.h"

namespace {

mrpt::config::CConfigFileMemory ini(const std::string& text) {
  return mrpt::config::CConfigFileMemory(text);
}

/// The message of the ConfigError that loading `text` into a GmcParams throws ("" if none).
std::string gmcLoadError(const std::string& text) {
  gmc::GmcParams p;
  try {
    gmc::cfg::loadSection(ini(text), "GMC", p, "test.ini");
  } catch (const gmc::cfg::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(GmcIni, PaperSymbolsFillTheParameters) {
  gmc::GmcParams p;
  gmc::cfg::loadSection(ini("[GMC]\nenabled = false\ngrid_cols = 16\ngrid_rows = 12\n"
                            "e_int_x = 0.8\ne_int_z = 1.2\nalpha = 50\np_min = 0.7\n"
                            "n_min = 10\nmin_cluster_size = 12\n"),
                        "GMC", p);
  EXPECT_FALSE(p.enabled);
  EXPECT_EQ(p.grid_cols, 16);
  EXPECT_EQ(p.grid_rows, 12);
  EXPECT_DOUBLE_EQ(p.e_int_x, 0.8);
  EXPECT_DOUBLE_EQ(p.e_int_z, 1.2);
  EXPECT_DOUBLE_EQ(p.alpha, 50);
  EXPECT_DOUBLE_EQ(p.p_min, 0.7);
  EXPECT_EQ(p.n_min, 10);
  EXPECT_EQ(p.min_cluster_size, 12);
  EXPECT_EQ(p.max_depth, gmc::GmcParams{}.max_depth);  // absent keys keep their default
}

TEST(GmcIni, OutOfRangeValuesAreRejectedNamingTheKey) {
  EXPECT_EQ(gmcLoadError("[GMC]\np_min = 0.5\n"), "");
  EXPECT_NE(gmcLoadError("[GMC]\np_min = 1.5\n").find("[GMC] p_min"), std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\ngrid_cols = 0\n").find("[GMC] grid_cols"), std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\ne_int_x = 0\n").find("[GMC] e_int_x"), std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\nalpha = -1\n").find("[GMC] alpha"), std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\nn_min = 0\n").find("[GMC] n_min"), std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\nmin_cluster_size = 0\n").find("[GMC] min_cluster_size"),
            std::string::npos);
  EXPECT_NE(gmcLoadError("[GMC]\ne_int = 1\n").find("[GMC] e_int: unknown key"), std::string::npos);
}

TEST(GmcIni, SaveThenLoadRoundTripsEveryKey) {
  gmc::GmcParams a;
  a.grid_cols = 8;
  a.use_y = true;
  a.static_tolerance = 0.75;
  mrpt::config::CConfigFileMemory mem;
  gmc::cfg::saveSection(mem, "GMC", a);
  gmc::GmcParams b;
  gmc::cfg::loadSection(mem, "GMC", b);
  EXPECT_EQ(b.grid_cols, 8);
  EXPECT_TRUE(b.use_y);
  EXPECT_DOUBLE_EQ(b.static_tolerance, 0.75);
}

TEST(GmsIni, LoadsAndRangeChecks) {
  gmc::GmsParams p;
  gmc::cfg::loadSection(ini("[GMS]\nalpha = 4\nwith_rotation = true\n"), "GMS", p);
  EXPECT_DOUBLE_EQ(p.alpha, 4);
  EXPECT_TRUE(p.with_rotation);
  EXPECT_THROW(gmc::cfg::loadSection(ini("[GMS]\ngrid_rows = 0\n"), "GMS", p),
               gmc::cfg::ConfigError);
}

}  // namespace
