#pragma once
// Static map exports: coloured point cloud (PLY), 2-D occupancy grid (PNG + ROS
// map_server YAML), MRPT .3Dscene, and a top-view picture.
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace gmc::mapping {

/// Which world axis points up; maps anchored to TUM/Bonn ground truth or from gmc-sim are
/// z-up, maps in the first camera's optical frame are "-y" up.
enum class UpAxis { Z, MinusY };

struct HeightBand {
  double min = -1e9, max = 1e9;  ///< along the up axis (m)
};

enum class PlyFormat { BinaryLittleEndian, Ascii };

/// Occupied voxel centres (float x y z, up axis as z) coloured by height (uchar red green
/// blue), written atomically. Returns the number of vertices.
size_t writePly(const octomap::OcTree& tree, const std::string& path, UpAxis up,
                PlyFormat format = PlyFormat::BinaryLittleEndian);

/// Occupancy grid in the ROS map_server convention: 0 = occupied (any occupied voxel in
/// the band), 254 = free (known free in the band), 205 = unknown; north (+y or -z) up.
struct OccupancyGrid {
  cv::Mat image;                 ///< CV_8UC1
  double resolution = 0.05;      ///< m per pixel
  double origin_x = 0, origin_y = 0;  ///< world position of the lower-left pixel
};
OccupancyGrid occupancyGrid(const octomap::OcTree& tree, const HeightBand& band, UpAxis up);
void writeGrid(const OccupancyGrid& grid, const std::string& png_path,
               const std::optional<std::string>& yaml_path);

/// Top view coloured by height (highest occupied voxel per cell), for pictures.
cv::Mat topView(const octomap::OcTree& tree, const HeightBand& band, UpAxis up, int scale = 4);

/// Pictures side by side (CV_8UC3, padded to the tallest) with a title on each, for
/// comparisons such as a map with and without GMC.
cv::Mat besideWithTitles(const std::vector<cv::Mat>& pictures, const std::vector<std::string>& titles);

/// MRPT scene (SceneViewer3D) with the occupied voxels as a coloured point cloud.
void writeScene(const octomap::OcTree& tree, const std::string& path, UpAxis up);

}  // namespace gmc::mapping
