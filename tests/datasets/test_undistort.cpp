#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <fstream>
#include <random>

#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/undistort.h"
#include "test_data.h"

namespace {

using namespace gmc::datasets;

/// What a camera with distortion `d` records of the ideal pinhole image `ideal`: each
/// recorded pixel shows the ideal pixel its ray goes through (OpenCV's model, inverted by
/// cv::undistortPoints).
cv::Mat distort(const cv::Mat& ideal, const gmc::PinholeCamera& c, const LensDistortion& d, int interpolation) {
  const cv::Matx33d K(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  std::vector<cv::Point2f> pixels, ideal_pixels;
  for (int v = 0; v < ideal.rows; ++v)
    for (int u = 0; u < ideal.cols; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  cv::undistortPoints(pixels, ideal_pixels, K, cv::Vec<double, 5>(d.k1, d.k2, d.p1, d.p2, d.k3), cv::noArray(), K);
  cv::Mat map(ideal.size(), CV_32FC2, ideal_pixels.data());
  cv::Mat recorded;
  cv::remap(ideal, recorded, map.clone(), cv::noArray(), interpolation, cv::BORDER_CONSTANT);
  return recorded;
}

TEST(Undistort, TumFr1FrameIsRestoredToThePinholeImage) {
  const auto camera = cameraPreset("fr1");
  const auto d = presetDistortion("fr1");
  ASSERT_FALSE(d.none());
  EXPECT_TRUE(presetDistortion("fr3").none());
  EXPECT_TRUE(presetDistortion("bonn").none());
  // Ideal scene: smooth blobs (so bilinear resampling twice stays close) and depth blocks.
  std::mt19937 rng(4);
  cv::Mat ideal(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(10000));
  std::uniform_int_distribution<int> x(0, 639), y(0, 479), r(10, 40), c(0, 255);
  for (int k = 0; k < 300; ++k)
    cv::circle(ideal, {x(rng), y(rng)}, r(rng), cv::Scalar(c(rng), c(rng), c(rng)), cv::FILLED);
  cv::GaussianBlur(ideal, ideal, cv::Size(0, 0), 2.0);
  for (int k = 0; k < 40; ++k)
    cv::rectangle(depth, cv::Rect(x(rng), y(rng), 60, 60), cv::Scalar(5000 + 200 * k), cv::FILLED);
  const auto dir = gmc::testdata::scratchDir("undistort");
  std::filesystem::create_directories(dir + "/rgb");
  std::filesystem::create_directories(dir + "/depth");
  cv::imwrite(dir + "/rgb/1.png", distort(ideal, camera, d, cv::INTER_LINEAR));
  cv::imwrite(dir + "/depth/1.png", distort(depth, camera, d, cv::INTER_NEAREST));
  std::ofstream(dir + "/rgb.txt") << "1.0 rgb/1.png\n";
  std::ofstream(dir + "/depth.txt") << "1.0 depth/1.png\n";

  const cv::Rect inner(60, 60, 520, 360);  // pixels whose rays stay inside the image
  auto read = [&](const LensDistortion& distortion) {
    RgbdFrame f;
    EXPECT_TRUE(openRgbdSource(dir, camera, {}, distortion)->next(f));
    return f;
  };
  auto colourError = [&](const cv::Mat& rgb) { return cv::norm(rgb(inner), ideal(inner), cv::NORM_L1) / (inner.area() * 3.0); };
  auto depthAgreement = [&](const cv::Mat& d16) {
    return cv::countNonZero(d16(inner) == depth(inner)) / static_cast<double>(inner.area());
  };
  const RgbdFrame as_recorded = read({}), restored = read(d);
  std::printf("  fr1 frame: colour error %.2f -> %.2f grey levels, depth equal on %.3f -> %.3f of the pixels\n",
              colourError(as_recorded.rgb), colourError(restored.rgb), depthAgreement(as_recorded.depth),
              depthAgreement(restored.depth));
  // The interior is the mildly distorted part (up to ~4 px displacement there).
  EXPECT_GT(colourError(as_recorded.rgb), 4.0);
  EXPECT_LT(colourError(restored.rgb), 0.1 * colourError(as_recorded.rgb));
  EXPECT_LT(depthAgreement(as_recorded.depth), 0.97);
  EXPECT_GT(depthAgreement(restored.depth), 0.995);
}

// A flat wall 3 m away as a sensor with a radial depth bias reads it (corners 7 % short
// at k = -0.14): removing the bias gives the wall back everywhere; k = 0 changes nothing;
// no reading is invented where there was none.
TEST(Undistort, RadialDepthBiasIsRemovedAcrossTheImage) {
  RgbdFrame f;
  f.camera = cameraPreset("bonn");
  f.depth_units = 1.0 / 5000.0;
  const double k = -0.14;
  f.depth = cv::Mat(480, 640, CV_16UC1);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const double x = (u - f.camera.cx) / f.camera.fx, y = (v - f.camera.cy) / f.camera.fy;
      f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(3.0 * 5000 * (1 + k * (x * x + y * y))));
    }
  f.depth.at<std::uint16_t>(10, 10) = 0;
  const cv::Mat recorded = f.depth.clone();
  EXPECT_LT(recorded.at<std::uint16_t>(0, 0), 0.94 * 15000);  // the corner reads short
  RadialDepthBias(0.0).apply(f);
  EXPECT_EQ(cv::countNonZero(f.depth != recorded), 0);
  RadialDepthBias(k).apply(f);
  double worst = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
      if (u != 10 || v != 10) worst = std::max(worst, std::abs(f.depth.at<std::uint16_t>(v, u) - 15000.0));
  EXPECT_LE(worst, 1.0);  // rounding of the 16-bit readings
  EXPECT_EQ(f.depth.at<std::uint16_t>(10, 10), 0);
}

}  // namespace
