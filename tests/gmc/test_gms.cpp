#include <gtest/gtest.h>

#include <cstdio>

#include "synthetic_matches.h"

namespace {

struct Rates {
  double kept_true, rejected_false;
};

Rates evaluate(const gmc::synth::GmsCase& c, const gmc::GmsParams& p) {
  const auto keep = gmc::gmsFilter(c.kp1, 640, 480, c.kp2, 640, 480, c.matches, p);
  int t = 0, tk = 0, f = 0, fr = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (c.is_true[i]) {
      ++t;
      tk += keep[i];
    } else {
      ++f;
      fr += !keep[i];
    }
  }
  return {static_cast<double>(tk) / t, f ? static_cast<double>(fr) / f : 1.0};
}

TEST(Gms, KeepsTrueMatchesAndRejectsOutliers) {
  for (double outliers : {0.3, 0.5, 0.7}) {
    const auto c = gmc::synth::makeGmsCase(1500, outliers, 7);
    const auto r = evaluate(c, {});
    std::printf("  outliers %.0f %%: kept %.3f of true matches, rejected %.3f of outliers\n",
                outliers * 100, r.kept_true, r.rejected_false);
    EXPECT_GE(r.kept_true, 0.90) << outliers;
    EXPECT_GE(r.rejected_false, 0.90) << outliers;
  }
}

TEST(Gms, RotationVariantHandlesARotatedImage) {
  auto c = gmc::synth::makeGmsCase(1500, 0.5, 9, 0, 0, 230);
  for (size_t i = 0; i < c.kp2.size(); ++i) {
    if (!c.is_true[i]) continue;
    // Rotate the second image by 90 degrees about its centre.
    const float x = c.kp2[i].x - 320, y = c.kp2[i].y - 240;
    c.kp2[i].x = 320 - y;
    c.kp2[i].y = 240 + x;
  }
  gmc::GmsParams p;
  const auto plain = evaluate(c, p);
  p.with_rotation = true;
  const auto rotated = evaluate(c, p);
  std::printf("  90 deg rotation: kept %.3f without, %.3f with the rotation variant\n",
              plain.kept_true, rotated.kept_true);
  EXPECT_GE(rotated.kept_true, 0.9);
  EXPECT_GE(rotated.rejected_false, 0.9);
  EXPECT_LT(plain.kept_true, 0.5);
}

TEST(Gms, EmptyAndMalformedInputKeepNothing) {
  EXPECT_TRUE(gmc::gmsFilter({}, 640, 480, {}, 640, 480, {}).empty());
  const std::vector<gmc::GmsKeypoint> kp = {{1, 1, 31, 0}};
  const auto keep = gmc::gmsFilter(kp, 640, 480, kp, 640, 480, {{0, 5}});
  ASSERT_EQ(keep.size(), 1u);
  EXPECT_EQ(keep[0], 0);
}

}  // namespace
