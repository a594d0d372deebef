#pragma once
#include <optional>

#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-map-export <map.bt> [--ply OUT.ply] [--grid OUT.png] [--grid-yaml OUT.yaml]
///                [--height-band zmin,zmax] [--scene OUT.3Dscene] [--top-view OUT.png]
///                [--up z|-y] [--ply-format binary|ascii] [--compare OTHER.bt [--titles "A,B"]]
class MapExportApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::vector<std::string> titles_;
  std::string compare_;  ///< second map drawn beside the first in the top view
  std::string map_, ply_, grid_, grid_yaml_, scene_, top_view_, up_ = "z", ply_format_ = "binary";
  double zmin_ = -1e9, zmax_ = 1e9;
};

}  // namespace gmc::apps
