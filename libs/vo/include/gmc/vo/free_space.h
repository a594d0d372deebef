#pragma once
// Where the camera has seen through: a short history of depth images (min-pooled into
// cells, with their poses). A point where past views saw the room behind cannot have
// stood there then: a new landmark there arrived since, on something that moves. A cue
// that does not come from the frame pair's motion (doc/odometry.md, thirty-eighth
// round). No I/O.
#include <deque>

#include <opencv2/core.hpp>

#include "gmc/gmc/types.h"

namespace gmc::vo {

/// INI section [FreeSpace]. Off by default: measured, it moves the generated crowds both
/// ways and does not help Bonn (doc/odometry.md, thirty-eighth round).
struct FreeSpaceOptions {
  bool enabled = false;
  int cell_px = 4;                ///< depth min-pooled over cell_px x cell_px pixels
  double spacing_seconds = 0.1;   ///< views kept at least this far apart ...
  double history_seconds = 2.0;   ///< ... for this long
  double min_age_seconds = 0.3;   ///< only views at least this much older than the point count
  double margin_base = 0.2;       ///< m: seen farther than the point by this ...
  double margin_per_m2 = 0.02;    ///< ... plus this x depth^2: seen through there
  int min_views = 4;              ///< seen through from this many views: arrived since

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "new landmarks where recent views saw through start suspect");
    v("cell_px", cell_px, 1, 64, "px: depth kept as the nearest reading per cell of this size");
    v("spacing_seconds", spacing_seconds, 0.0, 10.0, "s between the views kept");
    v("history_seconds", history_seconds, 0.0, 60.0, "s of views kept");
    v("min_age_seconds", min_age_seconds, 0.0, 60.0,
      "s: only views at least this much older than the new landmark judge it");
    v("margin_base", margin_base, 0.0, 10.0, "m: a view saw through a point when it read this much farther ...");
    v("margin_per_m2", margin_per_m2, 0.0, 10.0, "... plus this x the point's depth^2 (depth noise)");
    v("min_views", min_views, 1, 1000, "views that saw through a new landmark's place: it starts suspect");
  }
};

class FreeSpaceHistory {
 public:
  explicit FreeSpaceHistory(const FreeSpaceOptions& options = {}) : options_(options) {}
  const FreeSpaceOptions& options() const { return options_; }
  void clear() { views_.clear(); }
  /// Keeps a tracked frame's depth (CV_16UC1, raw units) as seen from T_world_camera
  /// (nothing when disabled).
  void push(const cv::Mat& depth, double depth_units, const Isometry& T_world_camera, double stamp);
  /// Views taken at or before `before` whose depth around the point's pixel (the cell and
  /// its eight neighbours: pose error and depth edges) lies everywhere beyond the point
  /// by the margin. A cell without reading decides nothing.
  int seenThrough(const Eigen::Vector3d& p_world, const PinholeCamera& camera, double before) const;
  /// The point arrived after the views old enough to judge it saw through its place
  /// (never when disabled).
  bool arrivedSince(const Eigen::Vector3d& p_world, const PinholeCamera& camera, double stamp) const {
    return options_.enabled && seenThrough(p_world, camera, stamp - options_.min_age_seconds) >= options_.min_views;
  }

 private:
  struct View {
    double stamp = 0;
    Isometry T_camera_world = Isometry::Identity();
    cv::Mat1f nearest;  ///< m per cell, 0 = no reading in the cell
  };
  FreeSpaceOptions options_;
  std::deque<View> views_;
};

}  // namespace gmc::vo
