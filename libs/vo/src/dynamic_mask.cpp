#include "gmc/vo/dynamic_mask.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gmc::vo {
namespace {

cv::Size downscaled(const cv::Size& size, int s) {
  return {(size.width + s - 1) / s, (size.height + s - 1) / s};
}

/// Depth in metres (CV_32F) at 1/s resolution; pixel (x, y) is full-resolution (x*s, y*s).
cv::Mat depthMetres(const cv::Mat& depth, double depth_units, int s) {
  cv::Mat small, metres;
  cv::resize(depth, small, downscaled(depth.size(), s), 0, 0, cv::INTER_NEAREST);
  small.convertTo(metres, CV_32F, depth_units);
  return metres;
}

/// Groups of fewer than `min_area` pixels are removed (isolated violations are noise:
/// flying pixels at depth edges, single bad readings).
void removeSmallGroups(cv::Mat& binary, int min_area) {
  if (min_area <= 1) return;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  std::vector<std::uint8_t> keep(static_cast<size_t>(n), 0);
  for (int i = 1; i < n; ++i) keep[static_cast<size_t>(i)] = stats.at<int>(i, cv::CC_STAT_AREA) >= min_area;
  for (int y = 0; y < binary.rows; ++y) {
    auto* row = binary.ptr<std::uint8_t>(y);
    const auto* label = labels.ptr<int>(y);
    for (int x = 0; x < binary.cols; ++x)
      if (row[x] && !keep[static_cast<size_t>(label[x])]) row[x] = 0;
  }
}

/// Keypoint evidence (dynamic keypoints, growth bounded by dynamic GMC cells) and
/// free-space evidence (`violations` at 1/options.free_space_scale, may be empty; growth
/// bounded to `violation_margin` around it), grown over depth-continuous pixels.
cv::Mat growMask(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                 const DynamicMaskOptions& options, const cv::Mat& violations) {
  cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8UC1);
  const bool any_violation = !violations.empty() && cv::countNonZero(violations) > 0;
  if (depth.empty() || (tracking.num_dynamic == 0 && !any_violation)) return mask;
  const int s = options.scale;
  const cv::Size small = downscaled(depth.size(), s);

  // Region the growth may reach: dynamic leaf cells, dilated by a margin of cells ...
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
  // ... and the surroundings of the free-space violations.
  cv::Mat small_violations;
  if (any_violation) {
    cv::resize(violations, small_violations, small, 0, 0, cv::INTER_NEAREST);
    cv::Mat near_violations;
    const int r = std::max(0, options.violation_margin / s);
    cv::dilate(small_violations, near_violations,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
    allowed |= near_violations;
  }

  // Seeds: discs around dynamic keypoints, and every violating pixel.
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
  if (any_violation) {
    // A coarse violation pixel also covers its neighbours at this scale: only those at
    // the violating sample's depth are seeds (not the wall beside a person's edge).
    const int fs = options.free_space_scale;
    const double step = options.depth_step / depth_units;
    for (int y = 0; y < small.height; ++y) {
      const auto* row = small_violations.ptr<std::uint8_t>(y);
      for (int x = 0; x < small.width; ++x) {
        if (!row[x]) continue;
        const int u = std::min(x * s, depth.cols - 1), v = std::min(y * s, depth.rows - 1);
        const double z = depth.at<std::uint16_t>(v, u);
        const double z_sample = depth.at<std::uint16_t>(v / fs * fs, u / fs * fs);
        if (z <= 0 || std::abs(z - z_sample) > step) continue;
        small_mask.at<std::uint8_t>(y, x) = 255;
        stack.emplace_back(x, y);
      }
    }
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

}  // namespace

cv::Mat buildDynamicMask(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                         const DynamicMaskOptions& options) {
  return growMask(tracking, depth, depth_units, options, cv::Mat());
}

DynamicMaskBuilder::DynamicMaskBuilder(const DynamicMaskOptions& options) : options_(options) {}

cv::Mat DynamicMaskBuilder::freeSpaceViolations(const cv::Mat& small_depth, const PinholeCamera& camera,
                                                const Isometry& T_world_camera) const {
  cv::Mat violations = cv::Mat::zeros(small_depth.size(), CV_8UC1);
  const int s = options_.free_space_scale;
  const int available = static_cast<int>(history_.size());
  for (int r = 0; r < options_.references; ++r) {
    const int gap = std::clamp(static_cast<int>(std::lround(
                                   static_cast<double>(options_.history_frames) * (r + 1) / options_.references)),
                               1, available);
    const Reference& ref = history_[static_cast<size_t>(available - gap)];
    const Eigen::Isometry3f T_ref_cur = (ref.T_camera_world * T_world_camera).cast<float>();
    const float fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
    const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
    const float m0 = static_cast<float>(options_.free_space_margin);
    const float m2 = static_cast<float>(options_.free_space_margin_z2);
    for (int y = 0; y < small_depth.rows; ++y) {
      const float* z_row = small_depth.ptr<float>(y);
      auto* out = violations.ptr<std::uint8_t>(y);
      for (int x = 0; x < small_depth.cols; ++x) {
        const float z = z_row[x];
        if (z <= 0 || out[x]) continue;
        const Eigen::Vector3f p((static_cast<float>(x * s) - cx) * z / fx,
                                (static_cast<float>(y * s) - cy) * z / fy, z);
        const Eigen::Vector3f q = T_ref_cur * p;
        if (q.z() <= 0.05f) continue;
        const int u = static_cast<int>(std::lround((fx * q.x() / q.z() + cx) / s));
        const int v = static_cast<int>(std::lround((fy * q.y() / q.z() + cy) / s));
        if (u < 0 || v < 0 || u >= ref.min_depth.cols || v >= ref.min_depth.rows) continue;
        const float z_ref = ref.min_depth.at<float>(v, u);
        // The reference's ray along this pixel went past q: q was free space then.
        if (z_ref > 0 && q.z() < z_ref - (m0 + m2 * z_ref * z_ref)) out[x] = 255;
      }
    }
  }
  removeSmallGroups(violations, options_.min_violation_area);
  return violations;
}

cv::Mat DynamicMaskBuilder::build(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                                  const PinholeCamera& camera) {
  violations_.release();
  if (options_.free_space_check && tracking.tracked() && !depth.empty()) {
    const cv::Mat small_depth = depthMetres(depth, depth_units, options_.free_space_scale);
    if (!history_.empty() && history_.back().min_depth.size() != small_depth.size()) history_.clear();
    if (!history_.empty()) violations_ = freeSpaceViolations(small_depth, camera, tracking.T_world_camera);
    // A reference's 3x3 minimum: projections land within a pixel, and a missing reading
    // next to the landing pixel gives no evidence (0).
    Reference ref;
    cv::erode(small_depth, ref.min_depth, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    ref.T_camera_world = tracking.T_world_camera.inverse();
    history_.push_back(std::move(ref));
    while (static_cast<int>(history_.size()) > options_.history_frames) history_.pop_front();
  }
  return growMask(tracking, depth, depth_units, options_, violations_);
}

}  // namespace gmc::vo
