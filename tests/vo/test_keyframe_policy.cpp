#include <gtest/gtest.h>

#include "gmc/vo/keyframe_policy.h"

namespace {

using gmc::Isometry;
using namespace gmc::vo;  // the policy's few types, all used below

KeyframeFrame tracked(int static_inliers, int landmarks_in_view, double dynamic_share = 0) {
  KeyframeFrame f;
  f.tracked = true;
  f.static_inliers = static_inliers;
  f.landmarks_in_view = landmarks_in_view;
  f.dynamic_share = dynamic_share;
  return f;
}

/// A policy just past its keyframe, whose first tracked frame (the overlap reference) had
/// 100 static inliers and 400 landmarks in view.
KeyframePolicy afterReferenceFrame(const KeyframeOptions& options) {
  KeyframePolicy policy(options);
  policy.reset(Isometry::Identity());
  EXPECT_EQ(policy.decide(tracked(100, 400)), KeyframeDecision::None);
  return policy;
}

TEST(KeyframePolicy, WalkersHidingTheBackgroundTakeNoKeyframeUntilTheInliersAreWeak) {
  // Occlusion: the map's landmarks stay in view, the static inliers fall.
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  EXPECT_EQ(policy.decide(tracked(61, 400, 0.5)), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(tracked(59, 400, 0.5)), KeyframeDecision::Insert);
}

TEST(KeyframePolicy, AThinningMapTakesAKeyframeWhileTheInliersHold) {
  // The camera turns away or the map erodes: fewer landmarks in view, while the inliers
  // (measured against a weak reference frame) are still plenty.
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  EXPECT_EQ(policy.decide(tracked(100, 361)), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(tracked(100, 359)), KeyframeDecision::Insert);
  // The next reference is the first tracked frame after the new keyframe.
  EXPECT_EQ(policy.decide(tracked(100, 300)), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(tracked(100, 271)), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(tracked(100, 269)), KeyframeDecision::Insert);
}

TEST(KeyframePolicy, AThinningMapAmongWalkersTakesNoKeyframe) {
  // Walkers' landmarks dropping thin the map too, and a keyframe among walkers seeds the
  // map with them: the view criterion waits for a frame with few dynamic labels.
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  EXPECT_EQ(policy.decide(tracked(100, 300, 0.1)), KeyframeDecision::None);
  EXPECT_EQ(policy.decide(tracked(100, 300, 0.09)), KeyframeDecision::Insert);
}

TEST(KeyframePolicy, TheViewCriterionIsOffAtZero) {
  KeyframeOptions options;
  options.min_view_overlap = 0;
  KeyframePolicy policy = afterReferenceFrame(options);
  EXPECT_EQ(policy.decide(tracked(100, 10)), KeyframeDecision::None);
}

TEST(KeyframePolicy, ReturningToTheKeyframeKeepsItsReferenceAResetDoesNot) {
  // An unheld start undone: back at the first keyframe, the frame after the return holds
  // on 40 inliers. Against the first frame's 100 that is weak: a keyframe is taken.
  KeyframePolicy returned = afterReferenceFrame(KeyframeOptions{});
  returned.returnTo(Isometry::Identity());
  EXPECT_EQ(returned.decide(tracked(40, 400, 0.5)), KeyframeDecision::Insert);
  // A reset makes that weak frame the reference, and the map never renews itself.
  KeyframePolicy reset = afterReferenceFrame(KeyframeOptions{});
  reset.reset(Isometry::Identity());
  EXPECT_EQ(reset.decide(tracked(40, 400, 0.5)), KeyframeDecision::None);
  EXPECT_EQ(reset.decide(tracked(30, 400, 0.5)), KeyframeDecision::None);
}

TEST(KeyframePolicy, DistanceFromTheKeyframeAndLongLossesDecideToo) {
  KeyframePolicy policy = afterReferenceFrame(KeyframeOptions{});
  KeyframeFrame far = tracked(100, 400);
  far.T_world_cur.translation().x() = 0.3;
  EXPECT_EQ(policy.decide(far), KeyframeDecision::Insert);
  KeyframeFrame lost;
  lost.lost_streak = KeyframeOptions{}.reanchor_after_lost - 1;
  EXPECT_EQ(policy.decide(lost), KeyframeDecision::None);
  ++lost.lost_streak;
  EXPECT_EQ(policy.decide(lost), KeyframeDecision::Reanchor);
}

}  // namespace
