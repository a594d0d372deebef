#include <gtest/gtest.h>

#include "gmc/vo/keyframe_policy.h"

namespace {

using gmc::Isometry;
using gmc::vo::KeyframeDecision;
using gmc::vo::KeyframeOptions;
using gmc::vo::KeyframePolicy;

/// A policy just past its keyframe, whose first tracked frame had 100 static inliers and
/// 400 landmarks in view.
KeyframePolicy afterReferenceFrame(const KeyframeOptions& options) {
  KeyframePolicy policy(options);
  policy.reset(Isometry::Identity());
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 400, 0), KeyframeDecision::None);
  return policy;
}

TEST(KeyframePolicy, WalkersHidingTheBackgroundTakeNoKeyframeUntilTheInliersAreWeak) {
  // Occlusion: the map's landmarks stay in view, the static inliers fall.
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 61, 400, 0), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 59, 400, 0), KeyframeDecision::Insert);
}

TEST(KeyframePolicy, AMapLeavingTheViewTakesAKeyframeWhileTheInliersHold) {
  // A camera turning into unmapped space: fewer landmarks project into the image while
  // the inliers (relative to a weak reference frame) are still plenty.
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 361, 0), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 359, 0), KeyframeDecision::Insert);
  // The next reference is the first frame after the new keyframe.
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 359, 0), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 330, 0), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 320, 0), KeyframeDecision::Insert);
}

TEST(KeyframePolicy, TheViewCriterionIsOffAtZero) {
  KeyframeOptions options;
  options.min_view_overlap = 0;
  KeyframePolicy policy = afterReferenceFrame(options);
  EXPECT_EQ(policy.decide(true, Isometry::Identity(), 100, 10, 0), KeyframeDecision::None);
}

TEST(KeyframePolicy, DistanceFromTheKeyframeAndLongLossesDecideToo) {
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  Isometry far = Isometry::Identity();
  far.translation().x() = 0.3;
  EXPECT_EQ(policy.decide(true, far, 100, 400, 0), KeyframeDecision::Insert);
  const int reanchor = KeyframeOptions{}.reanchor_after_lost;
  EXPECT_EQ(policy.decide(false, far, 0, 0, reanchor - 1), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(false, far, 0, 0, reanchor), KeyframeDecision::Reanchor);
}

}  // namespace
