#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "gmc/features/frontend.h"

namespace {

using gmc::PinholeCamera;
using gmc::features::Frontend;
using gmc::features::FrontendOptions;

/// A fronto-parallel textured plane at `depth` seen by the camera, shifted by (dx, dy) px.
struct PlaneScene {
  cv::Mat texture;  // larger than the image, so shifted views stay inside
  PlaneScene() {
    std::mt19937 rng(7);
    texture = cv::Mat(600, 760, CV_8UC1, cv::Scalar(128));
    std::uniform_int_distribution<int> x(0, 740), y(0, 580), s(4, 30), c(0, 255);
    for (int k = 0; k < 900; ++k)
      cv::rectangle(texture, cv::Rect(x(rng), y(rng), s(rng), s(rng)), cv::Scalar(c(rng)), cv::FILLED);
  }
  cv::Mat view(int dx, int dy) const { return texture(cv::Rect(40 + dx, 40 + dy, 640, 480)).clone(); }
};

cv::Mat flatDepth(double metres) {
  return cv::Mat(480, 640, CV_16UC1, cv::Scalar(static_cast<int>(metres * 5000)));
}

TEST(Frontend, ExtractSpreadsCornersAndBackProjects) {
  PlaneScene scene;
  PinholeCamera cam;
  FrontendOptions opt;
  opt.max_features = 800;
  opt.subpixel = false;  // GFTT's own guarantees: border and spacing on integer pixels
  Frontend fe(opt);
  const auto set = fe.extract(scene.view(0, 0), flatDepth(2.0), 1.0 / 5000, cam);
  ASSERT_GT(set.size(), 400u);
  EXPECT_EQ(set.descriptors.rows, static_cast<int>(set.size()));
  for (size_t i = 0; i < set.size(); ++i) {
    const auto& kp = set.keypoints[i].pt;
    EXPECT_GE(kp.x, opt.border);
    EXPECT_LT(kp.x, 640 - opt.border);
    ASSERT_TRUE(set.hasDepth(static_cast<int>(i)));
    EXPECT_NEAR(set.points[i].z(), 2.0, 1e-9);
    const Eigen::Vector2d back = cam.project(set.points[i]);
    EXPECT_NEAR(back.x(), kp.x, 1e-6);
    EXPECT_NEAR(back.y(), kp.y, 1e-6);
  }
  // Minimum distance between corners is respected.
  for (size_t i = 0; i < set.size(); ++i)
    for (size_t j = i + 1; j < set.size(); ++j)
      ASSERT_GE(cv::norm(set.keypoints[i].pt - set.keypoints[j].pt), opt.min_distance - 1e-3);
}

TEST(Frontend, InvalidDepthGivesNoPoint) {
  PlaneScene scene;
  Frontend fe;
  cv::Mat depth = flatDepth(2.0);
  depth(cv::Rect(0, 0, 320, 480)).setTo(0);     // no reading on the left half
  depth(cv::Rect(320, 0, 160, 480)).setTo(60000);  // 12 m: beyond max_depth
  const auto set = fe.extract(scene.view(0, 0), depth, 1.0 / 5000, PinholeCamera{});
  for (size_t i = 0; i < set.size(); ++i) {
    const float x = set.keypoints[i].pt.x;
    if (x < 318 || (x > 322 && x < 478)) {
      EXPECT_FALSE(set.hasDepth(static_cast<int>(i))) << x;
    }
    if (x > 482) {
      EXPECT_TRUE(set.hasDepth(static_cast<int>(i))) << x;
    }
  }
}

TEST(Frontend, GuidedAndExhaustiveMatchingRecoverAShift) {
  PlaneScene scene;
  PinholeCamera cam;
  Frontend fe;
  const double z = 2.0;
  const auto ref = fe.extract(scene.view(0, 0), flatDepth(z), 1.0 / 5000, cam);
  const auto cur = fe.extract(scene.view(6, -4), flatDepth(z), 1.0 / 5000, cam);
  // The current view is the reference shifted by (6,-4) px: a camera translation.
  gmc::Isometry T_cur_ref = gmc::Isometry::Identity();
  T_cur_ref.translation() = Eigen::Vector3d(-6 * z / cam.fx, 4 * z / cam.fy, 0);
  for (int pass = 0; pass < 2; ++pass) {
    const auto matches = pass == 0 ? fe.matchGuided(ref, cur, T_cur_ref, cam, 20)
                                   : fe.matchExhaustive(ref, cur);
    ASSERT_GT(matches.size(), ref.size() / 2) << "pass " << pass;
    int correct = 0;
    for (const auto& m : matches) {
      const auto d = ref.keypoints[static_cast<size_t>(m.ref)].pt -
                     cur.keypoints[static_cast<size_t>(m.cur)].pt - cv::Point2f(6, -4);
      correct += (std::abs(d.x) < 0.6f && std::abs(d.y) < 0.6f);
    }
    EXPECT_GT(correct, 0.97 * matches.size()) << "pass " << pass;
  }
}

TEST(Frontend, EmptyAndTinyImagesGiveNoFeatures) {
  Frontend fe;
  const auto a = fe.extract(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), cv::Mat(), 1.0, PinholeCamera{});
  EXPECT_EQ(a.size(), 0u);
  const auto b = fe.extract(cv::Mat(20, 20, CV_8UC1, cv::Scalar(0)), cv::Mat(), 1.0, PinholeCamera{});
  EXPECT_EQ(b.size(), 0u);
  EXPECT_TRUE(fe.matchExhaustive(a, b).empty());
}

TEST(Frontend, DepthAtKeypointUsesNeighbourMedian) {
  cv::Mat d = cv::Mat::zeros(10, 10, CV_16UC1);
  d.at<std::uint16_t>(4, 5) = 10000;
  d.at<std::uint16_t>(5, 4) = 10500;
  d.at<std::uint16_t>(6, 6) = 11000;
  EXPECT_NEAR(gmc::features::depthAtKeypoint(d, 1.0 / 5000, 5, 5, 0.1, 5), 2.1, 1e-12);
  d.at<std::uint16_t>(5, 5) = 5000;
  EXPECT_NEAR(gmc::features::depthAtKeypoint(d, 1.0 / 5000, 5, 5, 0.1, 5), 1.0, 1e-12);
  EXPECT_EQ(gmc::features::depthAtKeypoint(d, 1.0 / 5000, -3, 5, 0.1, 5), 0.0);
}

}  // namespace
