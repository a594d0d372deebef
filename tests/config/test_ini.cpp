#include <gtest/gtest.h>

#include <fstream>

#include "gmc/config/ini.h"
#include "gmc/gmc/options.h"

namespace {

struct DemoOptions {
  int cells = 20;
  double ratio = 0.5;
  bool enabled = true;
  std::string mode = "fast";
  template <class V>
  void visit(V& v) {
    v("cells", cells, 1, 100, "cell count");
    v("ratio", ratio, 0.0, 1.0, "a ratio");
    v("enabled", enabled, "switch");
    v.choice("mode", mode, {"fast", "exact"}, "how");
  }
};

mrpt::config::CConfigFileMemory ini(const std::string& text) {
  return mrpt::config::CConfigFileMemory(text);
}

TEST(Ini, LoadsValuesAndKeepsDefaults) {
  DemoOptions o;
  gmc::cfg::loadSection(ini("[Demo]\ncells = 7\nmode = exact ; comment\n"), "Demo", o);
  EXPECT_EQ(o.cells, 7);
  EXPECT_DOUBLE_EQ(o.ratio, 0.5);
  EXPECT_TRUE(o.enabled);
  EXPECT_EQ(o.mode, "exact");
}

struct PathOptions {
  std::string path;
  template <class V>
  void visit(V& v) {
    v("path", path, "a file");
  }
};

std::string loadedPath(const std::string& value_line) {
  PathOptions o;
  gmc::cfg::loadSection(ini("[P]\npath = " + value_line + "\n"), "P", o);
  return o.path;
}

// A comment starts only at the beginning of the value or after whitespace, as in MRPT:
// '#', ';' and '//' inside a value are part of it (was: truncated at the first one).
TEST(Ini, CommentMarkersInsideAValueArePartOfIt) {
  EXPECT_EQ(loadedPath("/data/run#2/gt.txt"), "/data/run#2/gt.txt");
  EXPECT_EQ(loadedPath("/data/a;b/gt.txt"), "/data/a;b/gt.txt");
  EXPECT_EQ(loadedPath("http://host/gt.txt"), "http://host/gt.txt");
  EXPECT_EQ(loadedPath("/data/run#2/gt.txt # the ground truth"), "/data/run#2/gt.txt");
  EXPECT_EQ(loadedPath("/data/gt.txt ; comment"), "/data/gt.txt");
  EXPECT_EQ(loadedPath("/data/gt.txt\t// comment # with ; markers"), "/data/gt.txt");
  EXPECT_EQ(loadedPath("# only a comment"), "");
}

TEST(Ini, RejectsUnknownKeyNamingIt) {
  DemoOptions o;
  try {
    gmc::cfg::loadSection(ini("[Demo]\ncels = 7\n"), "Demo", o, "my.ini");
    FAIL() << "no error";
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_STREQ(e.what(), "my.ini: [Demo] cels: unknown key");
  }
}

TEST(Ini, RejectsOutOfRangeAndMalformed) {
  DemoOptions o;
  EXPECT_THROW(gmc::cfg::loadSection(ini("[Demo]\ncells = -3\n"), "Demo", o),
               gmc::cfg::ConfigError);
  EXPECT_THROW(gmc::cfg::loadSection(ini("[Demo]\nratio = 1.5\n"), "Demo", o),
               gmc::cfg::ConfigError);
  EXPECT_THROW(gmc::cfg::loadSection(ini("[Demo]\ncells = 3x\n"), "Demo", o),
               gmc::cfg::ConfigError);
  EXPECT_THROW(gmc::cfg::loadSection(ini("[Demo]\nenabled = maybe\n"), "Demo", o),
               gmc::cfg::ConfigError);
  EXPECT_THROW(gmc::cfg::loadSection(ini("[Demo]\nmode = slow\n"), "Demo", o),
               gmc::cfg::ConfigError);
}

TEST(Ini, SaveThenLoadRoundTrips) {
  DemoOptions a;
  a.cells = 42;
  a.ratio = 0.125;
  a.enabled = false;
  a.mode = "exact";
  mrpt::config::CConfigFileMemory mem;
  gmc::cfg::saveSection(mem, "Demo", a);
  DemoOptions b;
  gmc::cfg::loadSection(mem, "Demo", b);
  EXPECT_EQ(b.cells, 42);
  EXPECT_DOUBLE_EQ(b.ratio, 0.125);
  EXPECT_FALSE(b.enabled);
  EXPECT_EQ(b.mode, "exact");
}

TEST(Ini, OverridesApplyAndMalformedOnesFail) {
  auto mem = ini("[Demo]\ncells = 7\n");
  gmc::cfg::applyOverrides(mem, {"Demo.cells=9", "Demo.enabled = false"});
  DemoOptions o;
  gmc::cfg::loadSection(mem, "Demo", o);
  EXPECT_EQ(o.cells, 9);
  EXPECT_FALSE(o.enabled);
  EXPECT_THROW(gmc::cfg::applyOverrides(mem, {"cells=9"}), gmc::cfg::ConfigError);
}

TEST(Ini, RangeValidatorNamesKey) {
  DemoOptions o;
  EXPECT_EQ(gmc::validateOptions(o, "Demo"), "");
  o.ratio = 2;
  EXPECT_NE(gmc::validateOptions(o, "Demo").find("[Demo] ratio"), std::string::npos);
}

TEST(Ini, MissingFileIsNamed) {
  try {
    gmc::cfg::loadIniFile("/nonexistent/x.ini");
    FAIL();
  } catch (const gmc::cfg::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.ini"), std::string::npos);
  }
}

// Fuzz finding (fuzz_ini): MRPT's preprocessor threw std::runtime_error ("Line 27:
// Expected closing `}`") out of loadIniFile, so the apps printed it without the file name.
TEST(Ini, MalformedMrptDirectiveIsAConfigErrorNamingTheFile) {
  const std::string path = testing::TempDir() + "/gmc_bad_directive.ini";
  for (const char* text : {"[GMC]\np_min = $env{HOME\n", "[GMC]\np_min = ${undefined_var\n"}) {
    { std::ofstream(path) << text; }
    try {
      gmc::cfg::loadIniFile(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const gmc::cfg::ConfigError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    }
  }
}

}  // namespace
