#include <gtest/gtest.h>

#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "gmc/mapping/export.h"
#include "test_data.h"

namespace {

using namespace gmc::mapping;
namespace fs = std::filesystem;

/// A 1 m x 1 m wall in the x-z plane at y = 2.05 (voxel centres, 0.1 m voxels), seen
/// from (0, 0, 0.5): occupied wall, free space in front of it.
octomap::OcTree wallMap() {
  octomap::OcTree tree(0.1);
  octomap::Pointcloud cloud;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) cloud.push_back(-0.45 + 0.1 * i, 2.05, 0.05 + 0.1 * j);
  tree.insertPointCloud(cloud, octomap::point3d(0, 0, 0.5));
  return tree;
}

std::string scratch(const std::string& name) { return gmc::testdata::scratchDir("mapping_" + name); }

struct Vertex {
  float x, y, z;
  int r, g, b;
};

/// Minimal PLY reader for what writePly declares: header, then x y z red green blue.
std::vector<Vertex> readPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  size_t count = 0;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
    if (line.rfind("format ", 0) == 0) format = line.substr(7);
  }
  std::vector<Vertex> v(count);
  for (auto& p : v) {
    if (format == "ascii 1.0") {
      in >> p.x >> p.y >> p.z >> p.r >> p.g >> p.b;
    } else {
      EXPECT_EQ(format, "binary_little_endian 1.0");
      float xyz[3];
      std::uint8_t rgb[3];
      in.read(reinterpret_cast<char*>(xyz), sizeof xyz);
      in.read(reinterpret_cast<char*>(rgb), sizeof rgb);
      p = {xyz[0], xyz[1], xyz[2], rgb[0], rgb[1], rgb[2]};
    }
  }
  EXPECT_TRUE(in.good()) << path << " shorter than its header says";
  if (format != "ascii 1.0") {
    EXPECT_EQ(in.peek(), EOF) << path << " longer than its header says";
  }
  return v;
}

TEST(Export, PlyHoldsEveryOccupiedVoxelCentreInBothFormats) {
  const auto dir = scratch("ply");
  const auto tree = wallMap();
  for (auto format : {PlyFormat::BinaryLittleEndian, PlyFormat::Ascii}) {
    const std::string path = dir + "/m.ply";
    EXPECT_EQ(writePly(tree, path, UpAxis::Z, format), 100u);
    const auto v = readPly(path);
    ASSERT_EQ(v.size(), 100u);
    for (const auto& p : v) {
      EXPECT_NEAR(p.y, 2.05, 1e-5);
      const double cells = (p.x - 0.05) / 0.1;  // voxel centres: whole cells from 0.05
      EXPECT_NEAR(cells, std::round(cells), 1e-4);
    }
    // Coloured by height: the bottom and top rows differ.
    auto lowest = std::min_element(v.begin(), v.end(), [](auto& a, auto& b) { return a.z < b.z; });
    auto highest = std::max_element(v.begin(), v.end(), [](auto& a, auto& b) { return a.z < b.z; });
    EXPECT_NE(std::tie(lowest->r, lowest->g, lowest->b), std::tie(highest->r, highest->g, highest->b));
  }
  // -y up (camera optical frames): heights become -y, the wall then lies at z = -2.05.
  writePly(tree, dir + "/y.ply", UpAxis::MinusY);
  for (const auto& p : readPly(dir + "/y.ply")) EXPECT_NEAR(p.z, -2.05, 1e-5);
}

TEST(Export, GridFollowsTheMapServerConvention) {
  const auto tree = wallMap();
  const OccupancyGrid g = occupancyGrid(tree, {0.2, 0.8}, UpAxis::Z);
  ASSERT_EQ(g.image.type(), CV_8UC1);
  EXPECT_DOUBLE_EQ(g.resolution, 0.1);
  EXPECT_EQ(cv::countNonZero(g.image == 0), 10);  // one row of wall cells
  EXPECT_GT(cv::countNonZero(g.image == 254), 20);
  EXPECT_EQ(cv::countNonZero(g.image == 0) + cv::countNonZero(g.image == 254) + cv::countNonZero(g.image == 205),
            g.image.rows * g.image.cols);
  // origin = world position of the lower-left pixel's corner; rows go north to south.
  for (int r = 0; r < g.image.rows; ++r)
    for (int c = 0; c < g.image.cols; ++c) {
      if (g.image.at<std::uint8_t>(r, c) != 0) continue;
      const double x = g.origin_x + (c + 0.5) * g.resolution;
      const double y = g.origin_y + (g.image.rows - 1 - r + 0.5) * g.resolution;
      EXPECT_NEAR(y, 2.05, 1e-6);
      EXPECT_LT(std::abs(x), 0.5);
    }
  // A band above the wall has no occupied cell.
  EXPECT_EQ(cv::countNonZero(occupancyGrid(tree, {1.5, 2.0}, UpAxis::Z).image == 0), 0);

  const auto dir = scratch("grid");
  writeGrid(g, dir + "/g.png", dir + "/g.yaml");
  const cv::Mat back = cv::imread(dir + "/g.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(back != g.image), 0);
  std::stringstream yaml;
  yaml << std::ifstream(dir + "/g.yaml").rdbuf();
  std::ostringstream origin;
  origin << "origin: [" << g.origin_x << ", " << g.origin_y << ", 0.0]";
  for (const std::string& key : {std::string("image: g.png"), std::string("resolution: 0.1"), origin.str(),
                                std::string("negate: 0"), std::string("occupied_thresh: 0.65"),
                                std::string("free_thresh: 0.196")})
    EXPECT_NE(yaml.str().find(key), std::string::npos) << key << " in\n" << yaml.str();
}

TEST(Export, SceneReloadsWithEveryOccupiedVoxel) {
  const auto dir = scratch("scene");
  writeScene(wallMap(), dir + "/m.3Dscene", UpAxis::Z);
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(dir + "/m.3Dscene"));
  const auto cloud = scene.getByClass<mrpt::opengl::CPointCloudColoured>();
  ASSERT_TRUE(cloud);
  EXPECT_EQ(cloud->size(), 100u);
}

TEST(Export, TopViewShowsTheWallRow) {
  const cv::Mat top = topView(wallMap(), {}, UpAxis::Z, 2);
  const OccupancyGrid g = occupancyGrid(wallMap(), {}, UpAxis::Z);
  ASSERT_EQ(top.type(), CV_8UC3);
  EXPECT_EQ(top.size(), cv::Size(g.image.cols * 2, g.image.rows * 2));
  // Coloured exactly where the grid is occupied, white where it is free.
  cv::Mat occupied_big, free_big;
  cv::resize(g.image == 0, occupied_big, top.size(), 0, 0, cv::INTER_NEAREST);
  cv::resize(g.image == 254, free_big, top.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat grey, white;
  cv::inRange(top, cv::Scalar(235, 235, 235), cv::Scalar(235, 235, 235), grey);
  cv::inRange(top, cv::Scalar(255, 255, 255), cv::Scalar(255, 255, 255), white);
  const cv::Mat coloured = ~(grey | white);
  EXPECT_EQ(cv::countNonZero(coloured), 10 * 4);
  EXPECT_EQ(cv::countNonZero(coloured != occupied_big), 0);
  EXPECT_EQ(cv::countNonZero(white != free_big), 0);
}

TEST(Export, UnwritablePathsThrowAndLeaveNothing) {
  const auto tree = wallMap();
  EXPECT_THROW(writePly(tree, "/nonexistent/dir/m.ply", UpAxis::Z), std::runtime_error);
  EXPECT_THROW(writeScene(tree, "/nonexistent/dir/m.3Dscene", UpAxis::Z), std::runtime_error);
  EXPECT_THROW(writeGrid(occupancyGrid(tree, {}, UpAxis::Z), "/nonexistent/dir/g.png", std::nullopt),
               std::runtime_error);
  EXPECT_FALSE(fs::exists("/nonexistent/dir"));
}

}  // namespace
