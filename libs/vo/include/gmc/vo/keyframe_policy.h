#pragma once
// When the odometry takes a keyframe: its landmarks are created and the windowed
// optimisation runs there. No I/O.
#include "gmc/gmc/types.h"

namespace gmc::vo {

/// INI section [Keyframes].
struct KeyframeOptions {
  double min_overlap = 0.6;        ///< new keyframe when static inliers fall below this
                                   ///< fraction of those of the first frame after the last one
  double min_view_overlap = 0.9;   ///< new keyframe when the map's landmarks in view fall
                                   ///< below this fraction of those of that frame (the
                                   ///< camera turns away, or the map erodes: landmarks
                                   ///< dropped after recurring wrong matches) ...
  double view_max_dynamic_share = 0.1;  ///< ... unless this share or more of the frame's
                                   ///< labelled matches are dynamic: walkers' landmarks
                                   ///< dropping lower the count too, and keyframes among
                                   ///< walkers seed the map with them (eighth round)
  double max_translation = 0.25;   ///< m from the last keyframe
  double max_rotation = 15.0;      ///< deg from the last keyframe
  int reanchor_after_lost = 30;    ///< consecutive lost frames before a keyframe is
                                   ///< anchored at the predicted pose: late, because
                                   ///< landmarks made at a guessed pose in a crowd
                                   ///< teach the map the crowd (doc/odometry.md)
  bool reanchor_new_map = true;    ///< the re-anchored keyframe starts a new local map
                                   ///< (when it has features to seed one): the old map
                                   ///< is off by the guess's error, and tracking on both
                                   ///< slides between them (doc/odometry.md, fourth round)

  template <class V>
  void visit(V& v) {
    v("min_overlap", min_overlap, 0.0, 1.0,
      "new keyframe below this fraction of the static inliers seen just after the last one");
    v("min_view_overlap", min_view_overlap, 0.0, 1.0,
      "new keyframe below this fraction of the map's landmarks in view just after the last one (0 = off)");
    v("view_max_dynamic_share", view_max_dynamic_share, 0.0, 1.0,
      "the view criterion applies only below this share of dynamic labelled matches");
    v("max_translation", max_translation, 0.0, 100.0, "m from the last keyframe");
    v("max_rotation", max_rotation, 0.0, 180.0, "deg from the last keyframe");
    v("reanchor_after_lost", reanchor_after_lost, 1, 100000,
      "lost frames before re-anchoring a keyframe at the predicted pose");
    v("reanchor_new_map", reanchor_new_map,
      "a re-anchored keyframe with features to seed it starts a new local map (false: joins the old one)");
  }
};

enum class KeyframeDecision { None, Insert, Reanchor };

/// What the keyframe policy knows of a frame.
struct KeyframeFrame {
  bool tracked = false;
  Isometry T_world_cur = Isometry::Identity();
  int static_inliers = 0;
  int landmarks_in_view = 0;   ///< the map's landmarks projecting into the image
  double dynamic_share = 0;    ///< dynamic share of the labelled matches
  int lost_streak = 0;         ///< lost frames in a row (when not tracked)
};

class KeyframePolicy {
 public:
  explicit KeyframePolicy(const KeyframeOptions& options = {}) : options_(options) {}
  const KeyframeOptions& options() const { return options_; }

  /// The first keyframe (or a re-anchored one) at T_world_kf.
  void reset(const Isometry& T_world_kf) {
    T_world_kf_ = T_world_kf;
    reference_inliers_ = 0;
    reference_in_view_ = 0;
  }

  /// Back to an earlier keyframe of the same map (an unheld start undone): the overlap
  /// reference measured after it still holds; a weak frame after the return must not
  /// replace it, or no keyframe is taken while the map holds on a few inliers.
  void returnTo(const Isometry& T_world_kf) { T_world_kf_ = T_world_kf; }

  KeyframeDecision decide(const KeyframeFrame& frame);

  /// The map moved into another world frame (a rejoin): so does the keyframe.
  void transform(const Isometry& T_new_old) { T_world_kf_ = T_new_old * T_world_kf_; }

 private:
  KeyframeOptions options_;
  Isometry T_world_kf_ = Isometry::Identity();
  int reference_inliers_ = 0;
  int reference_in_view_ = 0;
};

}  // namespace gmc::vo
