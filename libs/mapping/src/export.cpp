#include "gmc/mapping/export.h"

#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "gmc/datasets/atomic_file.h"

namespace gmc::mapping {
namespace {

/// Voxel centre in a z-up frame (x east, y north, z up).
struct Cell {
  double x, y, z, size;
  bool occupied;
};

template <class F>
void forEachLeaf(const octomap::OcTree& tree, UpAxis up, F&& f) {
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    Cell c{it.getX(), it.getY(), it.getZ(), it.getSize(), tree.isNodeOccupied(*it)};
    if (up == UpAxis::MinusY) c = {it.getX(), it.getZ(), -it.getY(), it.getSize(), c.occupied};
    f(c);
  }
}

cv::Vec3b heightColour(double z, double lo, double hi) {
  // One colour-map call for all 256 levels, not one per voxel.
  static const cv::Mat lut = [] {
    cv::Mat levels(1, 256, CV_8UC1), colours;
    for (int i = 0; i < 256; ++i) levels.at<std::uint8_t>(0, i) = static_cast<std::uint8_t>(i);
    cv::applyColorMap(levels, colours, cv::COLORMAP_TURBO);
    return colours;
  }();
  const double t = hi > lo ? std::clamp((z - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  return lut.at<cv::Vec3b>(0, static_cast<int>(t * 255));
}

struct Bounds {
  double x0 = 1e18, y0 = 1e18, z0 = 1e18, x1 = -1e18, y1 = -1e18, z1 = -1e18;
  void add(const Cell& c) {
    x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), z0 = std::min(z0, c.z);
    x1 = std::max(x1, c.x), y1 = std::max(y1, c.y), z1 = std::max(z1, c.z);
  }
};

bool overlapsBand(const Cell& c, const HeightBand& band) {
  return c.z + c.size / 2 >= band.min && c.z - c.size / 2 <= band.max;
}

/// Calls f(col, row) for every grid pixel under the voxel's footprint (a pruned voxel
/// covers several); rows run north to south.
template <class F>
void forEachPixel(const cv::Mat& image, double origin_x, double origin_y, double resolution, const Cell& c,
                  F&& f) {
  const int n = std::max(1, static_cast<int>(std::lround(c.size / resolution)));
  const int cx = static_cast<int>(std::lround((c.x - c.size / 2 - origin_x) / resolution));
  const int cy = static_cast<int>(std::lround((c.y - c.size / 2 - origin_y) / resolution));
  for (int dy = 0; dy < n; ++dy)
    for (int dx = 0; dx < n; ++dx) {
      const int px = cx + dx, py = image.rows - 1 - (cy + dy);
      if (px >= 0 && py >= 0 && px < image.cols && py < image.rows) f(px, py);
    }
}

}  // namespace

// Not MRPT's PLY_Exporter: on MRPT 2.5.8 CPointCloudColoured writes zero coordinates and
// CColouredPointsMap one "intensity" float instead of the colour (doc/mapping.md).
size_t writePly(const octomap::OcTree& tree, const std::string& path, UpAxis up, PlyFormat format) {
  std::vector<Cell> cells;
  Bounds b;
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (c.occupied) cells.push_back(c), b.add(c);
  });
  const bool ascii = format == PlyFormat::Ascii;
  datasets::AtomicFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary);
    out << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian")
        << " 1.0\ncomment GMC-RGBD static map, occupied voxel centres\n"
        << "element vertex " << cells.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    out.precision(7);
    for (const auto& c : cells) {
      const float xyz[3] = {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
      const cv::Vec3b bgr = heightColour(c.z, b.z0, b.z1);
      const std::uint8_t rgb[3] = {bgr[2], bgr[1], bgr[0]};
      if (ascii) {
        out << xyz[0] << ' ' << xyz[1] << ' ' << xyz[2] << ' ' << int(rgb[0]) << ' ' << int(rgb[1]) << ' '
            << int(rgb[2]) << '\n';
      } else {  // x86/ARM hosts are little-endian, as the header declares
        out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
        out.write(reinterpret_cast<const char*>(rgb), sizeof rgb);
      }
    }
    if (!out) throw std::runtime_error(path + ": cannot write");
  }
  file.commit();
  return cells.size();
}

OccupancyGrid occupancyGrid(const octomap::OcTree& tree, const HeightBand& band, UpAxis up) {
  OccupancyGrid g;
  g.resolution = tree.getResolution();
  // Footprint of the voxels in the band, by their corners (pixel edges = voxel edges).
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (!overlapsBand(c, band)) return;
    x0 = std::min(x0, c.x - c.size / 2), y0 = std::min(y0, c.y - c.size / 2);
    x1 = std::max(x1, c.x + c.size / 2), y1 = std::max(y1, c.y + c.size / 2);
  });
  if (x1 < x0) {
    g.image = cv::Mat(1, 1, CV_8UC1, cv::Scalar(205));
    return g;
  }
  // One unknown cell of border on every side.
  const int w = static_cast<int>(std::lround((x1 - x0) / g.resolution)) + 2;
  const int h = static_cast<int>(std::lround((y1 - y0) / g.resolution)) + 2;
  g.origin_x = x0 - g.resolution;
  g.origin_y = y0 - g.resolution;
  g.image = cv::Mat(h, w, CV_8UC1, cv::Scalar(205));
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (!overlapsBand(c, band)) return;
    forEachPixel(g.image, g.origin_x, g.origin_y, g.resolution, c, [&](int px, int py) {
      auto& v = g.image.at<std::uint8_t>(py, px);
      if (c.occupied || v == 205) v = c.occupied ? 0 : 254;  // occupied wins over free
    });
  });
  return g;
}

void writeGrid(const OccupancyGrid& grid, const std::string& png_path,
               const std::optional<std::string>& yaml_path) {
  datasets::writeImageAtomic(png_path, grid.image);
  if (!yaml_path) return;
  std::ostringstream os;
  os << "image: " << std::string(png_path).substr(png_path.find_last_of('/') + 1) << "\n"
     << "resolution: " << grid.resolution << "\n"
     << "origin: [" << grid.origin_x << ", " << grid.origin_y << ", 0.0]\n"
     << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  datasets::writeTextAtomic(*yaml_path, os.str());
}

cv::Mat topView(const octomap::OcTree& tree, const HeightBand& band, UpAxis up, int scale) {
  const OccupancyGrid g = occupancyGrid(tree, band, up);
  cv::Mat img(g.image.rows, g.image.cols, CV_8UC3, cv::Scalar(235, 235, 235));
  cv::Mat top(g.image.rows, g.image.cols, CV_64FC1, cv::Scalar(-1e18));
  Bounds b;
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (c.occupied && overlapsBand(c, band)) b.add(c);
  });
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (!overlapsBand(c, band)) return;
    forEachPixel(img, g.origin_x, g.origin_y, g.resolution, c, [&](int px, int py) {
      double& highest = top.at<double>(py, px);
      if (!c.occupied) {
        if (highest < -1e17) img.at<cv::Vec3b>(py, px) = cv::Vec3b(255, 255, 255);
      } else if (c.z > highest) {
        highest = c.z;
        img.at<cv::Vec3b>(py, px) = heightColour(c.z, b.z0, b.z1);
      }
    });
  });
  cv::resize(img, img, cv::Size(), scale, scale, cv::INTER_NEAREST);
  return img;
}

cv::Mat besideWithTitles(const std::vector<cv::Mat>& pictures, const std::vector<std::string>& titles) {
  const int gap = 10, title_height = 28;
  int width = 0, height = 0;
  for (const auto& p : pictures) width += p.cols + gap, height = std::max(height, p.rows);
  cv::Mat out(height + title_height, std::max(1, width - gap), CV_8UC3, cv::Scalar(255, 255, 255));
  int x = 0;
  for (size_t i = 0; i < pictures.size(); ++i) {
    pictures[i].copyTo(out(cv::Rect(x, title_height, pictures[i].cols, pictures[i].rows)));
    if (i < titles.size())
      cv::putText(out, titles[i], {x + 4, title_height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1,
                  cv::LINE_AA);
    x += pictures[i].cols + gap;
  }
  return out;
}

void writeScene(const octomap::OcTree& tree, const std::string& path, UpAxis up) {
  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  Bounds b;
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (c.occupied) b.add(c);
  });
  forEachLeaf(tree, up, [&](const Cell& c) {
    if (!c.occupied) return;
    const cv::Vec3b bgr = heightColour(c.z, b.z0, b.z1);
    cloud->push_back(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z),
                     bgr[2] / 255.f, bgr[1] / 255.f, bgr[0] / 255.f);
  });
  cloud->setPointSize(3.0f);
  mrpt::opengl::COpenGLScene scene;
  scene.insert(cloud);
  datasets::AtomicFile file(path);
  if (!scene.saveToFile(file.tempPath())) throw std::runtime_error(path + ": cannot write scene");
  file.commit();
}

}  // namespace gmc::mapping
