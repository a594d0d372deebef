#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "gmc/vo/depth_alignment.h"
#include "gmc/vo/pose_refinement.h"

namespace {

using gmc::Isometry;
using gmc::PinholeCamera;
using gmc::vo::DepthAlignment;
using gmc::vo::DepthAlignmentOptions;

constexpr double kUnits = 1.0 / 5000;  // TUM's depth scale

/// An axis-aligned box in the world (a walker's torso).
struct Box {
  Eigen::Vector3d lo, hi;
};

/// A room corner seen from about 2-3 m: a floor (y = 1.2, y down), a back wall (z = 3)
/// and a side wall (x = -1), world frame = the first camera's; optionally a box in front.
cv::Mat renderRoom(const Isometry& T_world_camera, const PinholeCamera& camera, const Box* box = nullptr) {
  cv::Mat depth(camera.height, camera.width, CV_16UC1, cv::Scalar(0));
  const Eigen::Vector3d o = T_world_camera.translation();
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray_cam = camera.unproject(u, v, 1.0);
      const Eigen::Vector3d d = T_world_camera.linear() * ray_cam;
      double t = std::numeric_limits<double>::infinity();
      const auto hit = [&](double origin, double dir, double plane) {
        if (std::abs(dir) < 1e-9) return;
        const double s = (plane - origin) / dir;
        if (s > 0.1) t = std::min(t, s);
      };
      hit(o.y(), d.y(), 1.2);
      hit(o.z(), d.z(), 3.0);
      hit(o.x(), d.x(), -1.0);
      if (box) {  // slab test
        double t0 = 0, t1 = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
          if (std::abs(d[a]) < 1e-12) {
            if (o[a] < box->lo[a] || o[a] > box->hi[a]) t1 = -1;
            continue;
          }
          double s0 = (box->lo[a] - o[a]) / d[a], s1 = (box->hi[a] - o[a]) / d[a];
          if (s0 > s1) std::swap(s0, s1);
          t0 = std::max(t0, s0);
          t1 = std::min(t1, s1);
        }
        if (t0 <= t1 && t0 > 0.1) t = std::min(t, t0);
      }
      if (std::isfinite(t)) depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(t / kUnits));
    }
  return depth;
}

DepthAlignmentOptions enabled() {
  DepthAlignmentOptions o;
  o.enabled = true;
  o.weight = 1.0;
  return o;
}

Isometry motion(double tx, double ty, double tz, double yaw_deg) {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(tx, ty, tz);
  return T;
}

/// Gauss-Newton on the dense term alone from `T_cur_world`; returns the result.
Isometry align(const DepthAlignment& dense, Isometry T_cur_world, const PinholeCamera& camera) {
  for (int it = 0; it < 15; ++it) {
    DepthAlignment::Mat6 H = DepthAlignment::Mat6::Zero();
    DepthAlignment::Vec6 g = DepthAlignment::Vec6::Zero();
    if (dense.accumulate(T_cur_world, camera, {}, H, g) < 6) break;
    const DepthAlignment::Vec6 delta = -H.ldlt().solve(g);
    T_cur_world = gmc::vo::expSE3(delta) * T_cur_world;
  }
  return T_cur_world;
}

double positionError(const Isometry& T_cur_world, const Isometry& T_world_cur_true) {
  return (T_cur_world.inverse().translation() - T_world_cur_true.translation()).norm();
}

TEST(DepthAlignment, PullsAFrameThatMovedBackOntoTheRoomsPlanes) {
  const PinholeCamera camera;
  DepthAlignment dense(enabled());
  dense.setReference(renderRoom(Isometry::Identity(), camera), kUnits, camera, Isometry::Identity(), 0.0, {});
  const Isometry T_world_cur = motion(0.02, -0.01, 0.015, 1.0);
  dense.setCurrent(renderRoom(T_world_cur, camera), kUnits, camera, 1.0 / 30, {});
  ASSERT_GT(dense.currentSize(), 1000u);
  // Started at the reference's pose (no motion): 2.7 cm and 1 deg off.
  const Isometry result = align(dense, Isometry::Identity(), camera);
  EXPECT_LT(positionError(result, T_world_cur), 0.002);
  const Eigen::AngleAxisd rotation_error(result.linear() * T_world_cur.linear());
  EXPECT_LT(rotation_error.angle() * 180 / M_PI, 0.1);
}

TEST(DepthAlignment, AWalkerThatMovedDoesNotPullTheFrameAlong) {
  const PinholeCamera camera;
  DepthAlignment dense(enabled());
  const Box walker{{-0.2, -0.2, 1.8}, {0.3, 1.2, 2.1}};
  dense.setReference(renderRoom(Isometry::Identity(), camera, &walker), kUnits, camera, Isometry::Identity(), 0.0,
                     {});
  // The camera stands still; the walker (a fifth of the image, with no keypoint to
  // exclude it) stepped 4 cm sideways and 4 cm nearer.
  const Box stepped{walker.lo + Eigen::Vector3d(0.04, 0, -0.04), walker.hi + Eigen::Vector3d(0.04, 0, -0.04)};
  dense.setCurrent(renderRoom(Isometry::Identity(), camera, &stepped), kUnits, camera, 1.0 / 30, {});
  const Isometry result = align(dense, Isometry::Identity(), camera);
  EXPECT_LT(positionError(result, Isometry::Identity()), 0.003);
}

TEST(DepthAlignment, AGateAtTheKeypointsGuessLeavesOutAWalkerThatCameNearer) {
  const PinholeCamera camera;
  DepthAlignmentOptions options = enabled();
  options.guess_gate = 1.5;
  DepthAlignment dense(options);
  const Box walker{{-0.2, -0.2, 1.8}, {0.3, 1.2, 2.1}};
  dense.setReference(renderRoom(Isometry::Identity(), camera, &walker), kUnits, camera, Isometry::Identity(), 0.0,
                     {});
  // The camera stands still and the keypoints say so; the walker's front came 3 cm nearer.
  const Box nearer{walker.lo - Eigen::Vector3d(0, 0, 0.03), walker.hi - Eigen::Vector3d(0, 0, 0.03)};
  dense.setCurrent(renderRoom(Isometry::Identity(), camera, &nearer), kUnits, camera, 1.0 / 30, {});
  const size_t all = dense.currentSize();
  dense.keepAgreeing(Isometry::Identity(), camera, {});
  // The walker's front in view (0.5 m wide at 1.77 m, from 0.2 m above the axis to the
  // image's bottom: about 150 x 300 px, ~700 samples at 8 px, fewer at its edges) goes;
  // the room stays.
  const size_t left_out = all - dense.currentSize();
  EXPECT_GT(left_out, 450u);
  EXPECT_LT(left_out, 750u);
  // Without the gate the walker's pixels stay in (within max_whitened at 1.8 m).
  DepthAlignment ungated(enabled());
  ungated.setReference(renderRoom(Isometry::Identity(), camera, &walker), kUnits, camera, Isometry::Identity(), 0.0,
                       {});
  ungated.setCurrent(renderRoom(Isometry::Identity(), camera, &nearer), kUnits, camera, 1.0 / 30, {});
  ungated.keepAgreeing(Isometry::Identity(), camera, {});
  EXPECT_EQ(ungated.currentSize(), all);
}

TEST(DepthAlignment, PixelsNearDynamicKeypointsAreLeftOut) {
  const PinholeCamera camera;
  DepthAlignment dense(enabled());
  const cv::Mat depth = renderRoom(Isometry::Identity(), camera);
  dense.setReference(depth, kUnits, camera, Isometry::Identity(), 0.0, {});
  dense.setCurrent(depth, kUnits, camera, 0.1, {});
  const size_t all = dense.currentSize();
  // One dynamic keypoint removes its 32 px cell and the eight around it: 96 x 96 px.
  dense.setCurrent(depth, kUnits, camera, 0.1, {cv::Point2f(320, 240)});
  EXPECT_EQ(all - dense.currentSize(), static_cast<size_t>((96 / 8) * (96 / 8)));
  // Dynamic keypoints everywhere leave nothing.
  std::vector<cv::Point2f> everywhere;
  for (int y = 0; y < 480; y += 32)
    for (int x = 0; x < 640; x += 32) everywhere.emplace_back(x, y);
  dense.setCurrent(depth, kUnits, camera, 0.1, everywhere);
  EXPECT_EQ(dense.currentSize(), 0u);
}

TEST(DepthAlignment, DisabledOrWithAStaleReferenceItAddsNothing) {
  const PinholeCamera camera;
  const cv::Mat depth = renderRoom(Isometry::Identity(), camera);
  DepthAlignment off;  // disabled by default
  off.setReference(depth, kUnits, camera, Isometry::Identity(), 0.0, {});
  off.setCurrent(depth, kUnits, camera, 0.1, {});
  EXPECT_EQ(off.currentSize(), 0u);

  DepthAlignment dense(enabled());
  dense.setReference(depth, kUnits, camera, Isometry::Identity(), 0.0, {});
  dense.setCurrent(depth, kUnits, camera, 0.6, {});  // max_age_seconds 0.5: lost frames in between
  EXPECT_EQ(dense.currentSize(), 0u);
  dense.setCurrent(depth, kUnits, camera, 0.4, {});
  EXPECT_GT(dense.currentSize(), 0u);
  dense.clear();  // a new map
  dense.setCurrent(depth, kUnits, camera, 0.4, {});
  EXPECT_EQ(dense.currentSize(), 0u);
}

}  // namespace
