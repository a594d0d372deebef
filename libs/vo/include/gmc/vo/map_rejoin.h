#pragma once
// Finding the way back into the map that tracking lost. After a long lost stretch the
// odometry re-anchors a keyframe at its predicted pose and starts a new local map; that
// guess is off by whatever the prediction drifted, and every pose after it keeps the
// offset. The landmarks of the old map not seen moving are kept here, frozen
// in the old world frame; while the camera tracks in the new map, its frames are matched
// against them by descriptor over the whole image (the offset is what the prediction
// drifted while lost: decimetres and up to 15 degrees in the generated crowds). Once two
// attempts in a row find the same correction (old world <- new world) on enough of
// them, the odometry moves its new map into the old frame and takes the frozen
// landmarks back. No I/O.
#include <optional>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/vo/background.h"
#include "gmc/vo/landmark_map.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [Rejoin].
struct RejoinOptions {
  bool enabled = true;            ///< keep the old map's landmarks at a re-anchor
  int every_frames = 1;           ///< attempt on every N-th tracked frame (matching costs)
  int min_inliers = 15;           ///< old landmarks agreeing with a correction
  double agree_translation = 0.03;  ///< m, two attempts' corrections agree within this ...
  double agree_rotation = 2.0;    ///< ... and this many degrees
  double max_seconds = 60.0;      ///< s after the re-anchor the old map is given up
  int max_landmarks = 3000;       ///< frozen landmarks kept (most often re-observed first)
  int ransac_iterations = 1000;   ///< 3-point hypotheses per attempt (few inliers: walkers
                                  ///< and look-alike corners share the matches)

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "after a re-anchor, look for the old map's landmarks and move back into its frame");
    v("every_frames", every_frames, 1, 100000, "attempt on every N-th tracked frame");
    v("min_inliers", min_inliers, 3, 100000, "old landmarks that must agree with a correction");
    v("agree_translation", agree_translation, 0.0, 10.0,
      "m, two attempts in a row must find corrections within this translation ...");
    v("agree_rotation", agree_rotation, 0.0, 180.0, "... and within this many degrees");
    v("max_seconds", max_seconds, 0.0, 1e6, "s after the re-anchor the old map is given up");
    v("max_landmarks", max_landmarks, 3, 10000000, "old landmarks kept (most re-observed first)");
    v("ransac_iterations", ransac_iterations, 1, 100000, "3-point hypotheses per attempt");
  }
};

/// What one attempt found (for logs and tests).
struct RejoinAttempt {
  int matches = 0;  ///< descriptor matches with depth against the frozen landmarks
  int inliers = 0;  ///< of which consistent with the best correction
  bool confirmed = false;
};

class MapRejoin {
 public:
  MapRejoin(const RejoinOptions& options, const RefinementOptions& refinement, const InPlaceThreshold& threshold)
      : options_(options), refinement_(refinement), threshold_(threshold) {}
  const RejoinOptions& options() const { return options_; }

  /// Waiting for the old map (frozen landmarks held and not yet given up).
  bool active() const { return !frozen_.empty(); }

  /// Keeps `landmarks` (world frame of the map being left) at a re-anchor at `stamp`:
  /// at most max_landmarks, the most often re-observed.
  /// While an older map is still waiting it stays: it is the frame the trajectory
  /// started in, and the map in between is then lost.
  void freeze(std::vector<Landmark> landmarks, double stamp);

  /// One tracked frame of the new map at T_world_cur (new world frame). Returns the
  /// correction T_old_new once confirmed (then take the landmarks with release()).
  std::optional<Isometry> attempt(const features::Frontend& frontend, const features::FeatureSet& cur,
                                  const Isometry& T_world_cur, const PinholeCamera& camera, double stamp,
                                  RejoinAttempt* report = nullptr);

  /// The frozen landmarks (old world frame); the rejoin is over.
  std::vector<Landmark> release();

 private:
  std::optional<Isometry> correction(const features::Frontend& frontend, const features::FeatureSet& cur,
                                     const Isometry& T_world_cur, const PinholeCamera& camera,
                                     RejoinAttempt& report);

  RejoinOptions options_;
  RefinementOptions refinement_;
  InPlaceThreshold threshold_;
  std::vector<Landmark> frozen_;     ///< old world frame
  features::FeatureSet frozen_set_;  ///< their descriptors, for matching
  double frozen_at_ = 0;
  int tracked_frames_ = 0;
  std::optional<Isometry> candidate_;  ///< the last attempt's correction, awaiting confirmation
  Xorshift64 rng_{0x2545F4914F6CDD1Dull};
};

}  // namespace gmc::vo
