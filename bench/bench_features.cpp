// The feature stage of the odometry (gmc::features::Frontend::extract) and its three parts
// on the first 40 frames of the real Bonn 301-460 folder (GMC_DATA_DIR, default
// ../shared/data; skip with a message when absent), with [Frontend]'s default options
// (config/default.ini): GFTT (cv::goodFeaturesToTrack inside the border), sub-pixel
// refinement (cv::cornerSubPix) and ORB descriptors, and the frontend's parallel versions
// of the first two (BM_CornersInStrips, BM_SubPixelInChunks). The frontend is most of the
// odometry's time (doc/performance.md); this says which part of it.
//   GMC_DATA_DIR=../shared/data build/bin/features_benchmarks
#include <benchmark/benchmark.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "bench_data.h"
#include "gmc/apps/app.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/features/corners.h"
#include "gmc/features/frontend.h"

namespace {

using gmc::features::Frontend;
using gmc::features::FrontendOptions;

struct Frame {
  cv::Mat gray, depth;
  double depth_units = 0;
  gmc::PinholeCamera camera;
  std::vector<cv::Point2f> corners;  ///< GFTT's, before sub-pixel refinement
};

const FrontendOptions kOptions{};

cv::Mat borderMask(cv::Size size) {
  const int b = kOptions.border;
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  mask(cv::Rect(b, b, size.width - 2 * b, size.height - 2 * b)).setTo(255);
  return mask;
}

void detect(const cv::Mat& gray, const cv::Mat& mask, std::vector<cv::Point2f>& corners) {
  cv::goodFeaturesToTrack(gray, corners, kOptions.max_features, kOptions.quality_level, kOptions.min_distance, mask,
                          kOptions.block_size, false);
}

const std::vector<Frame>& bonnFrames() {
  static const std::vector<Frame> frames = [] {
    std::vector<Frame> out;
    const std::string dir = gmc::bench::sharedDataFolder("bonn_crowd_301_460");
    if (dir.empty() || !std::filesystem::exists(dir + "/rgb.txt")) return out;
    auto source = gmc::datasets::openRgbdSource(dir, gmc::datasets::cameraPreset("bonn"));
    gmc::datasets::RgbdFrame f;
    while (out.size() < 40 && source->next(f)) {
      Frame frame;
      cv::cvtColor(f.rgb, frame.gray, cv::COLOR_BGR2GRAY);
      frame.depth = f.depth.clone();  // the source may reuse its buffers
      frame.depth_units = f.depth_units;
      frame.camera = f.camera;
      detect(frame.gray, borderMask(frame.gray.size()), frame.corners);
      out.push_back(std::move(frame));
    }
    return out;
  }();
  return frames;
}

bool haveBonn(benchmark::State& state) {
  if (!bonnFrames().empty()) return true;
  state.SkipWithError("no bonn_crowd_301_460 under GMC_DATA_DIR (default ../shared/data)");
  return false;
}

/// Each iteration one frame, in turn; items/s = frames per second.
template <class Body>
void overFrames(benchmark::State& state, Body body) {
  if (!haveBonn(state)) return;
  size_t i = 0;
  for (auto _ : state) body(bonnFrames()[i++ % bonnFrames().size()]);
  state.SetItemsProcessed(state.iterations());
}

void BM_FrontendExtract(benchmark::State& state) {
  const Frontend frontend(kOptions);
  overFrames(state, [&](const Frame& f) {
    benchmark::DoNotOptimize(frontend.extract(f.gray, f.depth, f.depth_units, f.camera));
  });
}
BENCHMARK(BM_FrontendExtract)->Unit(benchmark::kMillisecond);

void BM_Gftt(benchmark::State& state) {
  if (!haveBonn(state)) return;
  const cv::Mat mask = borderMask(bonnFrames().front().gray.size());
  std::vector<cv::Point2f> corners;
  overFrames(state, [&](const Frame& f) { detect(f.gray, mask, corners); });
}
BENCHMARK(BM_Gftt)->Unit(benchmark::kMillisecond);

void BM_CornerSubPix(benchmark::State& state) {
  const cv::Size window(kOptions.subpixel_window, kOptions.subpixel_window);
  const cv::TermCriteria stop(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 10, 0.01);
  std::vector<cv::Point2f> corners;
  overFrames(state, [&](const Frame& f) {
    corners = f.corners;
    cv::cornerSubPix(f.gray, corners, window, cv::Size(-1, -1), stop);
  });
}
BENCHMARK(BM_CornerSubPix)->Unit(benchmark::kMillisecond);

// The frontend's own calls: the same corners as the two above, in row strips and corner
// chunks on OpenCV's threads (gmc/features/corners.h; tests/features checks the identity).
void BM_CornersInStrips(benchmark::State& state) {
  const gmc::features::CornerParams params = kOptions.corners();
  overFrames(state, [&](const Frame& f) {
    benchmark::DoNotOptimize(gmc::features::detectCornersInside(f.gray, kOptions.border, params));
  });
}
BENCHMARK(BM_CornersInStrips)->Unit(benchmark::kMillisecond);

void BM_SubPixelInChunks(benchmark::State& state) {
  std::vector<cv::Point2f> corners;
  overFrames(state, [&](const Frame& f) {
    corners = f.corners;
    gmc::features::refineCornersSubPixel(f.gray, corners, kOptions.subpixel_window);
  });
}
BENCHMARK(BM_SubPixelInChunks)->Unit(benchmark::kMillisecond);

void BM_OrbDescriptors(benchmark::State& state) {
  const auto orb = gmc::features::makeDescriptorExtractor(kOptions);  // as the frontend makes it
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  overFrames(state, [&](const Frame& f) {
    keypoints.clear();
    for (const auto& c : f.corners) keypoints.emplace_back(c, 31.f, 0.f);
    orb->compute(f.gray, keypoints, descriptors);
  });
}
BENCHMARK(BM_OrbDescriptors)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  gmc::apps::tuneAllocator();  // as every app: image buffers stay off mmap (doc/performance.md)
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
