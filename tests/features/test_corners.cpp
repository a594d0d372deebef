// The frontend's parallel corners against OpenCV's single-threaded calls: the same
// corners, in the same order, to the bit (gmc/features/corners.h promises it).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "../common/test_data.h"
#include "gmc/features/corners.h"

namespace {

using gmc::features::CornerParams;

std::vector<cv::Point2f> openCvCorners(const cv::Mat& gray, int border, const CornerParams& p) {
  cv::Mat mask = cv::Mat::zeros(gray.size(), CV_8UC1);
  mask(cv::Rect(border, border, gray.cols - 2 * border, gray.rows - 2 * border)).setTo(255);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(gray, corners, p.max_corners, p.quality_level, p.min_distance, mask, p.block_size, false);
  return corners;
}

/// Bit-identical: the same count, and every coordinate equal as a float.
void expectSameCorners(const std::vector<cv::Point2f>& ours, const std::vector<cv::Point2f>& reference,
                       const std::string& what) {
  ASSERT_EQ(ours.size(), reference.size()) << what;
  for (size_t i = 0; i < ours.size(); ++i) {
    ASSERT_EQ(ours[i].x, reference[i].x) << what << ", corner " << i;
    ASSERT_EQ(ours[i].y, reference[i].y) << what << ", corner " << i;
  }
}

/// Detection then sub-pixel refinement, ours against OpenCV's, split several ways.
void expectAsOpenCv(const cv::Mat& gray, const CornerParams& p, int border, const std::string& what) {
  const auto reference = openCvCorners(gray, border, p);
  std::vector<cv::Point2f> refined = reference;
  if (!refined.empty())
    cv::cornerSubPix(gray, refined, cv::Size(3, 3), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 10, 0.01));
  for (int parts : {0, 2, 3, 7}) {  // 0: one per OpenCV thread
    auto ours = gmc::features::detectCornersInside(gray, border, p, parts);
    expectSameCorners(ours, reference, what + ", " + std::to_string(parts) + " strips, detection");
    gmc::features::refineCornersSubPixel(gray, ours, 3, parts);
    expectSameCorners(ours, refined, what + ", " + std::to_string(parts) + " chunks, sub-pixel");
  }
}

cv::Mat rectangles(unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat img(480, 640, CV_8UC1, cv::Scalar(128));
  std::uniform_int_distribution<int> x(0, 630), y(0, 470), s(4, 40), c(0, 255);
  for (int k = 0; k < 700; ++k)
    cv::rectangle(img, cv::Rect(x(rng), y(rng), s(rng), s(rng)), cv::Scalar(c(rng)), cv::FILLED);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

TEST(Corners, GeneratedImagesAsOpenCv) {
  const CornerParams defaults;
  for (unsigned seed : {1u, 2u, 3u}) expectAsOpenCv(rectangles(seed), defaults, 20, "rectangles " + std::to_string(seed));
  CornerParams all;  // every local maximum, no spacing: the sort's whole order matters
  all.max_corners = 0;
  all.min_distance = 0;
  expectAsOpenCv(rectangles(4), all, 20, "rectangles 4, all corners");
  CornerParams wide;
  wide.block_size = 7;
  wide.min_distance = 25;
  wide.quality_level = 0.05;
  expectAsOpenCv(rectangles(5), wide, 16, "rectangles 5, block 7");
  cv::Mat noise(480, 640, CV_8UC1);
  cv::randu(noise, 0, 256);
  expectAsOpenCv(noise, defaults, 20, "noise");
}

TEST(Corners, TiesFollowOpenCvsOrder) {
  // A checkerboard: every inner corner has the same eigenvalue, so only the tie rule
  // (later pixel first) decides which ones are kept.
  cv::Mat board(480, 640, CV_8UC1);
  for (int y = 0; y < board.rows; ++y)
    for (int x = 0; x < board.cols; ++x) board.at<uchar>(y, x) = ((x / 16 + y / 16) % 2) ? 220 : 30;
  CornerParams few;
  few.max_corners = 50;
  expectAsOpenCv(board, few, 20, "checkerboard");
  const auto corners = gmc::features::detectCornersInside(board, 20, few);
  ASSERT_FALSE(corners.empty());
  EXPECT_GT(corners.front().y, 400.f) << "ties: the last rows come first";
}

TEST(Corners, FlatAndTinyImagesGiveNothing) {
  const CornerParams p;
  EXPECT_TRUE(gmc::features::detectCornersInside(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), 20, p).empty());
  EXPECT_TRUE(gmc::features::detectCornersInside(cv::Mat(30, 30, CV_8UC1, cv::Scalar(90)), 20, p).empty());
  std::vector<cv::Point2f> none;
  gmc::features::refineCornersSubPixel(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), none, 3);
  EXPECT_TRUE(none.empty());
}

/// The first `count` colour images of a TUM-layout folder, as gray.
std::vector<cv::Mat> firstGrayFrames(const std::string& folder, size_t count) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(folder + "/rgb")) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::vector<cv::Mat> out;
  for (size_t i = 0; i < files.size() && out.size() < count; ++i) {
    cv::Mat gray = cv::imread(files[i], cv::IMREAD_GRAYSCALE);
    if (!gray.empty()) out.push_back(gray);
  }
  return out;
}

TEST(Corners, RealFramesAsOpenCv) {
  GMC_REQUIRE_DATA(bonn, "bonn_crowd_301_460");
  GMC_REQUIRE_DATA(teddy, "tum_fr3_teddy_1_100");
  const CornerParams defaults;
  for (const auto& folder : {bonn, teddy}) {
    const auto frames = firstGrayFrames(folder, 10);
    ASSERT_EQ(frames.size(), 10u) << folder;
    for (size_t i = 0; i < frames.size(); ++i)
      expectAsOpenCv(frames[i], defaults, 20, folder + " frame " + std::to_string(i));
  }
}

}  // namespace
