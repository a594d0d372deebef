#pragma once
// A TUM-layout sequence with exact ground truth, without the simulator.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace gmc::testdata {

/// A TUM-layout sequence of a textured wall 2 m in front of a camera that slides 1 cm per
/// frame along x (fr3 intrinsics): exact ground truth without the simulator.
inline std::string makeWallSequence(const std::string& dir, int frames) {
  std::filesystem::create_directories(dir + "/rgb");
  std::filesystem::create_directories(dir + "/depth");
  std::mt19937 rng(5);
  cv::Mat texture(560, 900, CV_8UC3, cv::Scalar(120, 120, 120));
  std::uniform_int_distribution<int> x(0, 880), y(0, 540), s(4, 28), c(0, 255);
  for (int k = 0; k < 2500; ++k)
    cv::rectangle(texture, cv::Rect(x(rng), y(rng), s(rng), s(rng)),
                  cv::Scalar(c(rng), c(rng), c(rng)), cv::FILLED);
  const double fx = 535.4, z = 2.0, step = 0.01;
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt"), gt(dir + "/groundtruth.txt");
  const cv::Mat depth_img(480, 640, CV_16UC1, cv::Scalar(static_cast<int>(z * 5000)));
  for (int i = 0; i < frames; ++i) {
    const double shift = 20 + fx * step * i / z;  // camera +x: the wall moves left in the image
    const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, -shift, 0, 1, -40);
    cv::Mat view;
    cv::warpAffine(texture, view, M, cv::Size(640, 480), cv::INTER_LINEAR);
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", 1000.0 + i / 30.0);
    cv::imwrite(dir + "/rgb/" + stamp + ".png", view);
    cv::imwrite(dir + "/depth/" + stamp + ".png", depth_img);
    rgb << stamp << " rgb/" << stamp << ".png\n";
    depth << stamp << " depth/" << stamp << ".png\n";
    gt << stamp << " " << step * i << " 0 0 0 0 0 1\n";
  }
  return dir;
}

}  // namespace gmc::testdata
