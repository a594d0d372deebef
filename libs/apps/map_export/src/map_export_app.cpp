#include "gmc/apps/map_export_app.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include "gmc/apps/command_line.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/mapping/export.h"

namespace gmc::apps {
namespace {
const char* kUsage =
    "usage: gmc-map-export <map.bt> [--ply OUT.ply] [--grid OUT.png] [--grid-yaml OUT.yaml] "
    "[--height-band zmin,zmax] [--scene OUT.3Dscene] [--top-view OUT.png] [--up z|-y] [--ply-format binary|ascii] "
    "[--compare OTHER.bt [--titles \"A,B\"]]";

std::unique_ptr<octomap::OcTree> readMap(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw AppError(path + ": no such map file");
  std::unique_ptr<octomap::OcTree> tree(new octomap::OcTree(0.05));
  if (!tree->readBinary(path)) throw AppError(path + ": not a readable OctoMap .bt file");
  return tree;
}
}

namespace {
using StringArg = TCLAP::ValueArg<std::string>;
}

void MapExportApp::initialize(const std::vector<std::string>& args) {
  TCLAP::CmdLine cmd("static map exports from an OctoMap", ' ', "", false);
  TCLAP::UnlabeledValueArg<std::string> map("map", "OctoMap .bt file", true, "", "map.bt", cmd);
  StringArg ply("", "ply", "occupied voxel centres as a coloured PLY", false, "", "OUT.ply", cmd);
  StringArg grid("", "grid", "2-D occupancy grid (ROS map_server PNG)", false, "", "OUT.png", cmd);
  StringArg grid_yaml("", "grid-yaml", "map_server YAML for --grid", false, "", "OUT.yaml", cmd);
  StringArg band_arg("", "height-band", "height band of the grid and top view", false, "", "zmin,zmax", cmd);
  StringArg scene("", "scene", "MRPT scene", false, "", "OUT.3Dscene", cmd);
  StringArg top_view("", "top-view", "top view coloured by height", false, "", "OUT.png", cmd);
  StringArg up("", "up", "world up axis", false, up_, "z|-y", cmd);
  StringArg ply_format("", "ply-format", "PLY encoding", false, ply_format_, "binary|ascii", cmd);
  StringArg compare("", "compare", "second map beside the first in --top-view", false, "", "OTHER.bt", cmd);
  StringArg titles_arg("", "titles", "titles of the two top views", false, "", "A,B", cmd);
  parseCommandLine(cmd, "gmc-map-export", args, kUsage);
  map_ = map.getValue(), ply_ = ply.getValue(), grid_ = grid.getValue(), grid_yaml_ = grid_yaml.getValue();
  scene_ = scene.getValue(), top_view_ = top_view.getValue(), up_ = up.getValue();
  ply_format_ = ply_format.getValue(), compare_ = compare.getValue();
  const std::string band = band_arg.getValue(), titles = titles_arg.getValue();
  if (ply_.empty() && grid_.empty() && scene_.empty() && top_view_.empty())
    throw AppError("nothing to export: give --ply, --grid, --scene or --top-view\n" + std::string(kUsage), 2);
  if (!grid_yaml_.empty() && grid_.empty()) throw AppError("--grid-yaml needs --grid", 2);
  if (up_ != "z" && up_ != "-y") throw AppError("--up: expected z or -y", 2);
  if (ply_format_ != "binary" && ply_format_ != "ascii") throw AppError("--ply-format: expected binary or ascii", 2);
  if (!compare_.empty() && top_view_.empty()) throw AppError("--compare needs --top-view", 2);
  if (!titles.empty()) {
    if (compare_.empty()) throw AppError("--titles needs --compare", 2);
    const auto comma = titles.find(',');
    if (comma == std::string::npos || titles.find(',', comma + 1) != std::string::npos)
      throw AppError("--titles: expected two titles separated by one comma", 2);
    titles_ = {titles.substr(0, comma), titles.substr(comma + 1)};
  }
  if (!band.empty()) {
    char comma = 0;
    int used = 0;
    if (std::sscanf(band.c_str(), "%lf%c%lf%n", &zmin_, &comma, &zmax_, &used) != 3 || comma != ',' ||
        used != static_cast<int>(band.size()) || !(zmin_ < zmax_))
      throw AppError("--height-band: expected zmin,zmax with zmin < zmax", 2);
  }
}

int MapExportApp::run() {
  const auto tree = readMap(map_);
  const auto other = compare_.empty() ? nullptr : readMap(compare_);
  const auto up = up_ == "z" ? mapping::UpAxis::Z : mapping::UpAxis::MinusY;
  const mapping::HeightBand band{zmin_, zmax_};
  if (!ply_.empty()) {
    const auto format = ply_format_ == "ascii" ? mapping::PlyFormat::Ascii : mapping::PlyFormat::BinaryLittleEndian;
    std::printf("%s: %zu occupied voxels\n", ply_.c_str(), mapping::writePly(*tree, ply_, up, format));
  }
  if (!grid_.empty()) {
    const auto grid = mapping::occupancyGrid(*tree, band, up);
    mapping::writeGrid(grid, grid_, grid_yaml_.empty() ? std::nullopt : std::optional<std::string>(grid_yaml_));
    std::printf("%s: %dx%d cells of %.3f m\n", grid_.c_str(), grid.image.cols, grid.image.rows, grid.resolution);
  }
  if (!top_view_.empty() && other) {
    const std::vector<std::string> titles =
        titles_.empty() ? std::vector<std::string>{map_, compare_} : titles_;
    datasets::writeImageAtomic(top_view_, mapping::besideWithTitles({mapping::topView(*tree, band, up),
                                                                     mapping::topView(*other, band, up)},
                                                                    titles));
  } else if (!top_view_.empty()) {
    datasets::writeImageAtomic(top_view_, mapping::topView(*tree, band, up));
  }
  if (!scene_.empty()) {
    mapping::writeScene(*tree, scene_, up);
    std::printf("%s: MRPT scene\n", scene_.c_str());
  }
  return 0;
}

}  // namespace gmc::apps
