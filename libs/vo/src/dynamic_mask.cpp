#include "gmc/vo/dynamic_mask.h"

#include <opencv2/imgproc.hpp>

#include <vector>

namespace gmc::vo {

cv::Mat buildDynamicMask(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                         const DynamicMaskOptions& options) {
  cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8UC1);
  if (depth.empty() || tracking.num_dynamic == 0) return mask;
  const int s = options.scale;
  const cv::Size small((depth.cols + s - 1) / s, (depth.rows + s - 1) / s);

  // Region the growth may reach: dynamic leaf cells, dilated by a margin of cells.
  cv::Mat allowed = cv::Mat::zeros(small, CV_8UC1);
  for (const GmcResult* result : {&tracking.gmc, &tracking.gmc_previous}) {
    for (const auto& cell : result->cells) {
      if (cell.cluster < 0 || result->clusters[static_cast<size_t>(cell.cluster)].is_static) continue;
      const int mx = options.cell_margin * (cell.x1 - cell.x0), my = options.cell_margin * (cell.y1 - cell.y0);
      cv::Rect r(cv::Point((cell.x0 - mx) / s, (cell.y0 - my) / s),
                 cv::Point((cell.x1 + mx + s - 1) / s, (cell.y1 + my + s - 1) / s));
      allowed(r & cv::Rect(cv::Point(0, 0), small)).setTo(255);
    }
  }

  // Seeds: discs around dynamic keypoints.
  cv::Mat small_mask = cv::Mat::zeros(small, CV_8UC1);
  std::vector<cv::Point> stack;
  const int rad = std::max(1, options.seed_radius / s);
  for (size_t i = 0; i < tracking.keypoints.size(); ++i) {
    if (tracking.keypoint_labels[i] != MotionLabel::Dynamic) continue;
    const cv::Point p(static_cast<int>(tracking.keypoints[i].x) / s,
                      static_cast<int>(tracking.keypoints[i].y) / s);
    cv::circle(small_mask, p, rad, cv::Scalar(255), cv::FILLED);
    stack.push_back(p);
  }

  if (options.flood_fill) {
    cv::Mat small_depth;
    cv::resize(depth, small_depth, small, 0, 0, cv::INTER_NEAREST);
    const double step = options.depth_step / depth_units;
    cv::Mat visited = cv::Mat::zeros(small, CV_8UC1);
    // Four-connected growth over depth-continuous pixels inside the allowed region.
    static const int kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
    while (!stack.empty()) {
      const cv::Point p = stack.back();
      stack.pop_back();
      if (p.x < 0 || p.y < 0 || p.x >= small.width || p.y >= small.height) continue;
      const double zp = small_depth.at<std::uint16_t>(p.y, p.x);
      if (zp <= 0) continue;
      small_mask.at<std::uint8_t>(p.y, p.x) = 255;
      for (int k = 0; k < 4; ++k) {
        const int x = p.x + kDx[k], y = p.y + kDy[k];
        if (x < 0 || y < 0 || x >= small.width || y >= small.height) continue;
        if (visited.at<std::uint8_t>(y, x) || !allowed.at<std::uint8_t>(y, x)) continue;
        const double zq = small_depth.at<std::uint16_t>(y, x);
        if (zq <= 0 || std::abs(zq - zp) > step) continue;
        visited.at<std::uint8_t>(y, x) = 1;
        stack.emplace_back(x, y);
      }
    }
  }

  cv::resize(small_mask, mask, depth.size(), 0, 0, cv::INTER_NEAREST);
  if (options.dilate > 0) {
    const cv::Mat k = cv::getStructuringElement(
        cv::MORPH_ELLIPSE, cv::Size(2 * options.dilate + 1, 2 * options.dilate + 1));
    cv::dilate(mask, mask, k);
  }
  return mask;
}

}  // namespace gmc::vo
