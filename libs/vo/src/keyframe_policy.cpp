#include "gmc/vo/keyframe_policy.h"

#include <cmath>

namespace gmc::vo {

KeyframeDecision KeyframePolicy::decide(const KeyframeFrame& frame) {
  if (!frame.tracked) {
    if (frame.lost_streak < options_.reanchor_after_lost) return KeyframeDecision::None;
    reset(frame.T_world_cur);
    return KeyframeDecision::Reanchor;
  }
  // The overlap reference is the first tracked frame after the keyframe: the keyframe
  // itself matches nothing new against the landmarks it has just created.
  if (reference_inliers_ == 0) {
    reference_inliers_ = frame.static_inliers;
    reference_in_view_ = frame.landmarks_in_view;
  }
  const Isometry T_kf_cur = T_world_kf_.inverse() * frame.T_world_cur;
  const double rotation_deg = Eigen::AngleAxisd(T_kf_cur.linear()).angle() * 180.0 / M_PI;
  const bool far = T_kf_cur.translation().norm() > options_.max_translation ||
                   rotation_deg > options_.max_rotation;
  const bool weak = frame.static_inliers < options_.min_overlap * reference_inliers_;
  // Inliers alone miss a map that erodes (landmarks dropped after recurring wrong
  // matches, teddy) or leaves the view while enough inliers remain for a while (the
  // reference may be a weak frame): without new landmarks, tracking is then lost for good.
  const bool map_thins = frame.dynamic_share < options_.view_max_dynamic_share &&
                         frame.landmarks_in_view < options_.min_view_overlap * reference_in_view_;
  if (!far && !weak && !map_thins) return KeyframeDecision::None;
  reset(frame.T_world_cur);
  return KeyframeDecision::Insert;
}

}  // namespace gmc::vo
