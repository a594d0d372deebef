#pragma once
// A dense depth term for the frame's pose: the last tracked frame's depth, sampled on a
// grid, with normals, as small planes in the world; the current frame's sampled pixels
// away from dynamic keypoints are pulled onto them (point to plane, robust). Bare walls
// hold no keypoints but do hold depth: where walkers fill the view, the room's depth is
// what is left (doc/odometry.md, thirty-ninth round). No I/O.
#include <vector>

#include <opencv2/core.hpp>

#include "gmc/gmc/types.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [DepthAlignment]. Off by default (doc/odometry.md, thirty-ninth round).
struct DepthAlignmentOptions {
  bool enabled = false;
  int stride = 8;               ///< px between sampled pixels (both frames)
  double weight = 0.1;          ///< each sampled pixel's weight next to a keypoint's (neighbours' noise is shared)
  double max_distance = 0.1;    ///< m: a pixel farther than this from its reference plane has none
  double max_whitened = 3.0;    ///< point-to-plane residuals beyond this many sigmas count nothing
  double max_age_seconds = 0.5; ///< an older reference (lost frames in between) is dropped
  int exclusion_cell_px = 32;   ///< px: cells with a dynamic keypoint, and their neighbours, give no pixels
  double min_normal_agreement = 0.9;  ///< cosine: surfaces facing further apart are not associated
  double guess_gate = 0;        ///< sigmas: keep only pixels this close at the keypoints' guess (0: all)
  bool keyframe_reference = false;  ///< the reference is the last keyframe, not the last tracked frame

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "pull the frame's depth onto the last tracked frame's (point to plane) in the pose");
    v("stride", stride, 1, 64, "px between sampled pixels");
    v("weight", weight, 0.0, 100.0, "weight of one sampled pixel next to one keypoint");
    v("max_distance", max_distance, 0.001, 10.0, "m: farther from its reference plane, a pixel has none");
    v("max_whitened", max_whitened, 0.1, 100.0, "residuals beyond this many depth sigmas count nothing");
    v("max_age_seconds", max_age_seconds, 0.0, 60.0, "s: an older reference frame is dropped");
    v("exclusion_cell_px", exclusion_cell_px, 1, 640,
      "px: cells holding a dynamic keypoint, and their neighbours, give no pixels");
    v("min_normal_agreement", min_normal_agreement, -1.0, 1.0,
      "cosine between the two frames' normals below which a pixel has no reference");
    v("keyframe_reference", keyframe_reference,
      "the reference depth is the last keyframe's (held by the map), not the last tracked frame's");
    v("guess_gate", guess_gate, 0.0, 100.0,
      "depth sigmas: only pixels this close to their plane at the keypoints' pose guess join (0: all)");
  }
};

class DepthAlignment {
 public:
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;

  explicit DepthAlignment(const DepthAlignmentOptions& options = {}) : options_(options) {}
  const DepthAlignmentOptions& options() const { return options_; }
  void clear() {
    reference_.clear();
    current_.clear();
  }

  /// Keeps a tracked frame (CV_16UC1 depth, raw units) as the reference: sampled points
  /// with normals, in the world. Nothing when disabled.
  void setReference(const cv::Mat& depth, double depth_units, const PinholeCamera& camera,
                    const Isometry& T_world_camera, double stamp, const std::vector<cv::Point2f>& dynamic_pixels,
                    const cv::Mat& known_dynamic = cv::Mat());
  /// Drops the reference's samples inside the dynamic mask (CV_8UC1, nonzero = dynamic;
  /// the walkers' untextured parts, which no keypoint marks) of the frame at `stamp`, when
  /// that frame is the reference: a pixel of the next frame that lands there has no
  /// reference. An empty mask, or another frame's, changes nothing.
  void maskReference(const cv::Mat& mask, double stamp);
  /// Samples the current frame's pixels (camera frame) away from its dynamic keypoints
  /// and off the known dynamic pixels (optional CV_8UC1 mask, nonzero = dynamic); none
  /// when disabled or without a reference younger than max_age_seconds.
  void setCurrent(const cv::Mat& depth, double depth_units, const PinholeCamera& camera, double stamp,
                  const std::vector<cv::Point2f>& dynamic_pixels, const cv::Mat& known_dynamic = cv::Mat());
  /// Keeps only the current pixels within guess_gate sigmas of their reference plane at
  /// T_cur_world (the keypoints' guess): the depth then refines the keypoints' motion and
  /// cannot lead it onto a walker that moved (nothing when guess_gate is 0).
  void keepAgreeing(const Isometry& T_cur_world, const PinholeCamera& camera, const RefinementOptions& noise);
  /// Sampled current pixels that will be used (on a flat surface, away from walkers).
  size_t currentSize() const { return current_.size(); }

  /// Adds the weighted, whitened point-to-plane residuals at T_cur_world (a left
  /// perturbation of it, as in refinePose) to H and g; returns the pixels associated.
  int accumulate(const Isometry& T_cur_world, const PinholeCamera& camera, const RefinementOptions& noise, Mat6& H,
                 Vec6& g) const;

 private:
  /// Cells of exclusion_cell_px holding a dynamic pixel, dilated by one cell.
  cv::Mat1b excludedCells(const cv::Mat& depth, const std::vector<cv::Point2f>& dynamic_pixels) const;

  struct Association {
    double sigma = 0, whitened = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< the reference plane's, world
  };
  struct Plane {
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();  ///< unit; zero = none
  };
  /// The depth's grid of samples (row-major, cols x rows) with the normals of those on a
  /// flat, continuous surface away from dynamic pixels (others have none), camera frame.
  std::vector<Plane> samplePlanes(const cv::Mat& depth, double depth_units, const PinholeCamera& camera,
                                  const std::vector<cv::Point2f>& dynamic_pixels, const cv::Mat& known_dynamic,
                                  int& cols, int& rows) const;
  /// The sample's reference plane at T_world_cur, and its residual; false when it has
  /// none (outside, no plane, facing away, too far) or lies beyond max_whitened.
  bool associate(const Plane& sample, const Isometry& T_world_cur, const PinholeCamera& camera,
                 const RefinementOptions& noise, Association& out) const;
  DepthAlignmentOptions options_;
  std::vector<Plane> reference_;  ///< the reference's samplePlanes(), in the world
  int reference_cols_ = 0, reference_rows_ = 0;
  Isometry T_reference_world_ = Isometry::Identity();
  Eigen::Vector3d reference_centre_ = Eigen::Vector3d::Zero();  ///< world
  double reference_stamp_ = 0;
  std::vector<Plane> current_;  ///< camera frame
};

}  // namespace gmc::vo
