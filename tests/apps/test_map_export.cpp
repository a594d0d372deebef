#include <gtest/gtest.h>

#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "gmc/apps/map_export_app.h"
#include "run_app.h"
#include "test_data.h"

namespace {

namespace fs = std::filesystem;

int runExport(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::MapExportApp>("gmc-map-export", std::move(args));
}

/// A 1 m x 1 m wall (x, z) at y = 2.05 and free space in front of it, 0.1 m voxels.
std::string makeMap(const std::string& dir) {
  octomap::OcTree tree(0.1);
  octomap::Pointcloud cloud;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) cloud.push_back(-0.45 + 0.1 * i, 2.05, 0.05 + 0.1 * j);
  tree.insertPointCloud(cloud, octomap::point3d(0, 0, 0.5));
  const std::string path = dir + "/map.bt";
  tree.writeBinary(path);
  return path;
}

TEST(MapExport, WritesPlyGridYamlSceneAndTopView) {
  const auto dir = gmc::testdata::scratchDir("map_export");
  const auto map = makeMap(dir);
  ASSERT_EQ(runExport({map, "--ply", dir + "/m.ply", "--grid", dir + "/g.png", "--grid-yaml", dir + "/g.yaml",
                       "--height-band", "0.2,0.8", "--scene", dir + "/m.3Dscene", "--top-view", dir + "/t.png"}),
            0);
  std::ifstream ply(dir + "/m.ply", std::ios::binary);
  std::string line;
  size_t vertices = 0;
  while (std::getline(ply, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
  EXPECT_EQ(vertices, 100u);  // 10 x 10 wall voxels
  const cv::Mat grid = cv::imread(dir + "/g.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(cv::countNonZero(grid == 0), 10);        // one row of wall cells
  EXPECT_GT(cv::countNonZero(grid == 254), 20);      // free space in front
  std::stringstream yaml;
  yaml << std::ifstream(dir + "/g.yaml").rdbuf();
  EXPECT_NE(yaml.str().find("image: g.png"), std::string::npos);
  EXPECT_NE(yaml.str().find("resolution: 0.1"), std::string::npos);
  EXPECT_GT(fs::file_size(dir + "/m.3Dscene"), 100u);
  EXPECT_FALSE(cv::imread(dir + "/t.png").empty());
}

TEST(MapExport, WritesAsciiPly) {
  const auto dir = gmc::testdata::scratchDir("map_export_ascii");
  ASSERT_EQ(runExport({makeMap(dir), "--ply", dir + "/m.ply", "--ply-format", "ascii"}), 0);
  std::ifstream ply(dir + "/m.ply");
  std::string line;
  while (std::getline(ply, line) && line != "end_header") {
  }
  size_t rows = 0;
  double x, y, z;
  int r, g, b;
  while (ply >> x >> y >> z >> r >> g >> b) {
    ++rows;
    EXPECT_NEAR(y, 2.05, 1e-5);
  }
  EXPECT_EQ(rows, 100u);
}

TEST(MapExport, ComparesTwoMapsSideBySide) {
  const auto dir = gmc::testdata::scratchDir("map_export_compare");
  const auto map = makeMap(dir);
  ASSERT_EQ(runExport({map, "--top-view", dir + "/one.png"}), 0);
  ASSERT_EQ(runExport({map, "--top-view", dir + "/two.png", "--compare", map, "--titles", "with GMC,without GMC"}),
            0);
  const cv::Mat one = cv::imread(dir + "/one.png"), two = cv::imread(dir + "/two.png");
  ASSERT_FALSE(one.empty());
  ASSERT_FALSE(two.empty());
  EXPECT_EQ(two.cols, 2 * one.cols + 10);  // both views and the gap between them
  EXPECT_GT(two.rows, one.rows);           // and a title line above
  EXPECT_EQ(runExport({map, "--compare", map}), 2);  // nothing to compare on
  EXPECT_EQ(runExport({map, "--top-view", dir + "/x.png", "--titles", "a,b"}), 2);
  EXPECT_EQ(runExport({map, "--top-view", dir + "/x.png", "--compare", map, "--titles", "a"}), 2);
  EXPECT_EQ(runExport({map, "--top-view", dir + "/x.png", "--compare", dir + "/none.bt"}), 1);
  EXPECT_FALSE(fs::exists(dir + "/x.png"));
}

TEST(MapExport, BadInputsFailCleanly) {
  const auto dir = gmc::testdata::scratchDir("map_export_bad");
  EXPECT_EQ(runExport({}), 2);
  EXPECT_EQ(runExport({dir + "/none.bt", "--ply", dir + "/x.ply"}), 1);
  std::ofstream(dir + "/junk.bt") << "not an octree";
  EXPECT_EQ(runExport({dir + "/junk.bt", "--ply", dir + "/x.ply"}), 1);
  const auto map = makeMap(dir);
  EXPECT_EQ(runExport({map}), 2);  // nothing to export
  EXPECT_EQ(runExport({map, "--grid", dir + "/g.png", "--height-band", "2,1"}), 2);
  EXPECT_EQ(runExport({map, "--grid", dir + "/g.png", "--height-band", "0,1junk"}), 2);
  EXPECT_EQ(runExport({map, "--grid-yaml", dir + "/g.yaml"}), 2);
  EXPECT_EQ(runExport({map, "--ply", dir + "/x.ply", "--ply-format", "xml"}), 2);
  EXPECT_EQ(runExport({map, "--ply", dir + "/x.ply", "--bogus"}), 2);
  EXPECT_EQ(runExport({map, "--ply", dir + "/missing_dir/x.ply"}), 1);
  EXPECT_FALSE(fs::exists(dir + "/x.ply"));
  EXPECT_FALSE(fs::exists(dir + "/g.png"));
  EXPECT_FALSE(fs::exists(dir + "/missing_dir"));
  for (const auto& entry : fs::directory_iterator(dir))  // no temporary left behind
    EXPECT_TRUE(entry.path().filename() == "junk.bt" || entry.path().filename() == "map.bt") << entry.path();
}

// Command-line errors (TCLAP) are one line naming the argument, then the usage; exit 2.
TEST(MapExport, UsageErrorsAreOneLineNamingTheArgument) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{}, {"m.bt", "--ply"}, {"m.bt", "--bogus"}, {"m.bt", "other.bt"}}) {
    gmc::apps::MapExportApp app;
    try {
      app.initialize(args);
      ADD_FAILURE() << "no usage error";
    } catch (const gmc::apps::AppError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.exitCode(), 2) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find("usage: gmc-map-export"), std::string::npos) << what;
      if (args.size() == 2 && args[1] == "--ply") {
        EXPECT_EQ(what.rfind("--ply: ", 0), 0u) << what;
      }
    }
  }
}

}  // namespace
