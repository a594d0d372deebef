#include "gmc/vo/keyframe_policy.h"

#include <cmath>

namespace gmc::vo {

KeyframeDecision KeyframePolicy::decide(bool tracked, const Isometry& T_world_cur, int static_inliers,
                                        int landmarks_in_view, int lost_streak) {
  if (!tracked) {
    if (lost_streak < options_.reanchor_after_lost) return KeyframeDecision::None;
    reset(T_world_cur);
    return KeyframeDecision::Reanchor;
  }
  // The overlap reference is the first tracked frame after the keyframe: the keyframe
  // itself matches nothing new against the landmarks it has just created.
  if (reference_inliers_ == 0) {
    reference_inliers_ = static_inliers;
    reference_in_view_ = landmarks_in_view;
  }
  const Isometry T_kf_cur = T_world_kf_.inverse() * T_world_cur;
  const double rotation_deg = Eigen::AngleAxisd(T_kf_cur.linear()).angle() * 180.0 / M_PI;
  const bool far = T_kf_cur.translation().norm() > options_.max_translation ||
                   rotation_deg > options_.max_rotation;
  const bool weak = static_inliers < options_.min_overlap * reference_inliers_;
  // Inliers alone miss a camera that turns slowly into unmapped space while enough
  // inliers remain for a while (the reference may be a weak frame): the map falls behind
  // and tracking is lost for good. Walkers hiding the background do not change this count.
  const bool map_left_view = landmarks_in_view < options_.min_view_overlap * reference_in_view_;
  if (!far && !weak && !map_left_view) return KeyframeDecision::None;
  reset(T_world_cur);
  return KeyframeDecision::Insert;
}

}  // namespace gmc::vo
