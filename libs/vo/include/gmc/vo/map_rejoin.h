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
// landmarks back. Several maps can wait (max_maps): a crowd that loses the camera twice
// leaves an intermediate map whose frames are revised only if some map finds it; the
// attempts take the waiting maps in turn. A map left before it held the room (no static
// evidence: it followed one frame's clusters among walkers) has little of the room to be
// found by; its first keyframe, posed before any walker could mislead it, is looked for the
// other way: its features against the current map's landmarks not seen moving
// (`young_map_anchor`; generated `crowd` 16: a first map of four frames, lost for thirty,
// kept the re-anchored map 25 cm off the trajectory's start). No I/O.
#include <optional>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/vo/background.h"
#include "gmc/vo/landmark_map.h"
#include "gmc/vo/point_correspondences.h"
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
  int max_maps = 3;               ///< maps waiting at once (when full, the second oldest goes)
  bool young_map_anchor = true;   ///< a map left without static evidence is also looked for by its first keyframe

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
    v("max_maps", max_maps, 1, 100,
      "maps waiting at once, tried in turn; when full, the oldest (the trajectory's frame) stays and the second "
      "oldest makes room (1: the oldest only)");
    v("young_map_anchor", young_map_anchor,
      "a map left before it held [Background] min_static_landmarks landmarks with static evidence is also found "
      "by its first keyframe's features matched against the current map's landmarks not seen moving; its frames "
      "after that keyframe are then bridged as lost frames");
  }
};

/// What one attempt found (for logs and tests).
struct RejoinAttempt {
  int map = -1;     ///< the waiting map tried
  int matches = 0;  ///< descriptor matches with depth against its frozen landmarks
  int inliers = 0;  ///< of which consistent with the best correction
  bool by_anchor = false;  ///< found by the map's first keyframe (young_map_anchor)
  bool confirmed = false;
};

/// A waiting map's first keyframe: its features and its pose in that map's world frame.
struct MapAnchor {
  features::FeatureSet features;
  Isometry T_world_camera = Isometry::Identity();
};

/// A confirmed rejoin: the waiting map found, and T_map_current (the current map's world
/// frame -> that map's).
struct RejoinFound {
  int map = -1;
  Isometry T_map_current = Isometry::Identity();
};

class MapRejoin {
 public:
  MapRejoin(const RejoinOptions& options, const RefinementOptions& refinement, const InPlaceThreshold& threshold)
      : options_(options), refinement_(refinement), threshold_(threshold) {}
  const RejoinOptions& options() const { return options_; }
  /// Another sampling stream (Xorshift64::seedFor); 0 = the built-in one.
  void reseed(std::uint64_t run_seed) { rng_ = Xorshift64(Xorshift64::seedFor(kSeed, run_seed)); }

  /// Some map waits to be found (frozen landmarks held and not yet given up).
  bool active() const { return !waiting_.empty(); }
  bool waiting(int map) const;

  /// Keeps `landmarks` (world frame of map `map`, left at a re-anchor at `stamp`): at
  /// most max_landmarks, the most often re-observed, and the map's `anchor` when it is a
  /// young one (young_map_anchor). Returns false when not kept (disabled, too few
  /// landmarks and no anchor, or max_maps waiting already with max_maps 1).
  bool freeze(int map, std::vector<Landmark> landmarks, double stamp, std::optional<MapAnchor> anchor = std::nullopt);

  /// One tracked frame of the current map at T_world_cur (its world frame), tried against
  /// the next waiting map in turn, or against map `only` when it is one (-1: any); a map
  /// with an anchor is also tried by it against `current`'s landmarks not seen moving at
  /// `stamp` (when given); the correction with more inliers counts. Returns the map and correction once confirmed
  /// (take its landmarks with release()).
  std::optional<RejoinFound> attempt(const features::Frontend& frontend, const features::FeatureSet& cur,
                                     const Isometry& T_world_cur, const PinholeCamera& camera,
                                     RejoinAttempt* report = nullptr, int only = -1,
                                     const LandmarkMap* current = nullptr, double stamp = 0);
  /// The ids of the maps waiting, oldest first.
  std::vector<int> waitingMaps() const;

  /// The waiting maps older than max_seconds, given up (their ids).
  std::vector<int> giveUpExpired(double stamp);

  /// A waiting map's frozen landmarks (its world frame); it waits no more.
  std::vector<Landmark> release(int map);

 private:
  struct WaitingMap {
    int id = -1;
    std::vector<Landmark> frozen;     ///< its world frame
    features::FeatureSet frozen_set;  ///< their descriptors, for matching
    double frozen_at = 0;
    std::optional<MapAnchor> anchor;    ///< a young map's first keyframe
    std::optional<Isometry> candidate;  ///< its last attempt's correction, awaiting confirmation
  };
  std::optional<Isometry> correction(const features::Frontend& frontend, const WaitingMap& map,
                                     const features::FeatureSet& cur, const Isometry& T_world_cur,
                                     const PinholeCamera& camera, RejoinAttempt& report);
  /// The correction (map's world <- current world) that poses the map's anchor on the
  /// current map's landmarks not seen moving.
  std::optional<Isometry> anchorCorrection(const features::Frontend& frontend, const MapAnchor& anchor,
                                           const LandmarkMap& current, double stamp, const PinholeCamera& camera,
                                           RejoinAttempt& report);
  /// 3-point RANSAC and refinement; the fitted T_cur_ref when min_inliers agree.
  std::optional<Isometry> fitCorrection(const PointCorrespondences& c, const PinholeCamera& camera,
                                        RejoinAttempt& report);

  RejoinOptions options_;
  RefinementOptions refinement_;
  InPlaceThreshold threshold_;
  std::vector<WaitingMap> waiting_;  ///< oldest first
  int tracked_frames_ = 0;           ///< since the first map began to wait
  size_t turn_ = 0;                  ///< the waiting map tried next
  static constexpr std::uint64_t kSeed = 0x2545F4914F6CDD1Dull;
  Xorshift64 rng_{kSeed};
};

}  // namespace gmc::vo
