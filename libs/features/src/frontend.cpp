#include "gmc/features/frontend.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace gmc::features {
namespace {

constexpr int kDescriptorBytes = 32;

inline int hamming(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int k = 0; k < kDescriptorBytes; k += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a + k, 8);
    std::memcpy(&y, b + k, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

/// Bucket grid over the current image for windowed searches.
class KeypointGrid {
 public:
  KeypointGrid(const std::vector<cv::KeyPoint>& kps, int width, int height, int cell)
      : cell_(cell), cols_((width + cell - 1) / cell), rows_((height + cell - 1) / cell),
        start_(static_cast<size_t>(cols_ * rows_ + 1), 0), items_(kps.size()) {
    std::vector<int> cell_of(kps.size());
    for (size_t i = 0; i < kps.size(); ++i) {
      cell_of[i] = cellIndex(kps[i].pt.x, kps[i].pt.y);
      ++start_[static_cast<size_t>(cell_of[i]) + 1];
    }
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < kps.size(); ++i)
      items_[static_cast<size_t>(fill[static_cast<size_t>(cell_of[i])]++)] = static_cast<int>(i);
  }

  template <class F>
  void forEachNear(float x, float y, int radius, F&& f) const {
    const int cx0 = std::max(0, static_cast<int>((x - radius) / cell_));
    const int cx1 = std::min(cols_ - 1, static_cast<int>((x + radius) / cell_));
    const int cy0 = std::max(0, static_cast<int>((y - radius) / cell_));
    const int cy1 = std::min(rows_ - 1, static_cast<int>((y + radius) / cell_));
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) {
        const size_t c = static_cast<size_t>(cy * cols_ + cx);
        for (int k = start_[c]; k < start_[c + 1]; ++k) f(items_[static_cast<size_t>(k)]);
      }
  }

 private:
  int cellIndex(float x, float y) const {
    const int cx = std::clamp(static_cast<int>(x / cell_), 0, cols_ - 1);
    const int cy = std::clamp(static_cast<int>(y / cell_), 0, rows_ - 1);
    return cy * cols_ + cx;
  }
  int cell_, cols_, rows_;
  std::vector<int> start_;
  std::vector<int> items_;
};

/// Keeps, for every current feature, only its best reference match.
std::vector<FeatureMatch> uniqueByCurrent(std::vector<FeatureMatch> matches, size_t num_cur) {
  std::vector<int> best(num_cur, -1);
  for (size_t i = 0; i < matches.size(); ++i) {
    int& b = best[static_cast<size_t>(matches[i].cur)];
    if (b < 0 || matches[i].distance < matches[static_cast<size_t>(b)].distance)
      b = static_cast<int>(i);
  }
  std::vector<FeatureMatch> out;
  out.reserve(matches.size());
  for (size_t i = 0; i < matches.size(); ++i)
    if (best[static_cast<size_t>(matches[i].cur)] == static_cast<int>(i)) out.push_back(matches[i]);
  return out;
}

}  // namespace

double depthAtKeypoint(const cv::Mat& depth, double depth_units, float u, float v,
                       double min_depth, double max_depth) {
  if (depth.empty()) return 0;
  // Sub-pixel keypoints on one surface: interpolate (corners on a slanted plane would
  // otherwise take the depth of the neighbouring pixel centre).
  const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < depth.cols && y0 + 1 < depth.rows) {
    const double a = depth.at<std::uint16_t>(y0, x0), b = depth.at<std::uint16_t>(y0, x0 + 1),
                 c = depth.at<std::uint16_t>(y0 + 1, x0), d = depth.at<std::uint16_t>(y0 + 1, x0 + 1);
    const double lo = std::min({a, b, c, d}), hi = std::max({a, b, c, d});
    if (lo > 0 && hi - lo <= 0.02 * lo) {
      const double fx = u - x0, fy = v - y0;
      const double z = ((a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy) * depth_units;
      return z >= min_depth && z <= max_depth ? z : 0.0;
    }
  }
  const int x = static_cast<int>(u + 0.5f), y = static_cast<int>(v + 0.5f);
  if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return 0;
  auto valid = [&](std::uint16_t raw) {
    const double z = raw * depth_units;
    return raw != 0 && z >= min_depth && z <= max_depth;
  };
  const std::uint16_t centre = depth.at<std::uint16_t>(y, x);
  if (valid(centre)) return centre * depth_units;
  std::array<std::uint16_t, 9> around{};
  int n = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= depth.cols || yy >= depth.rows) continue;
      const std::uint16_t raw = depth.at<std::uint16_t>(yy, xx);
      if (valid(raw)) around[static_cast<size_t>(n++)] = raw;
    }
  if (n == 0) return 0;
  std::nth_element(around.begin(), around.begin() + n / 2, around.begin() + n);
  return around[static_cast<size_t>(n / 2)] * depth_units;
}

cv::Ptr<cv::ORB> makeDescriptorExtractor(const FrontendOptions& options) {
  // Single pyramid level: GFTT corners come at one scale, and frame-to-frame or
  // frame-to-keyframe motion is small. Keypoint angles are set to 0 (upright BRIEF),
  // which is more discriminative than steered BRIEF for small in-plane rotations.
  return cv::ORB::create(options.max_features, 1.2f, 1, options.border - 1, 0, 2, cv::ORB::HARRIS_SCORE, 31);
}

Frontend::Frontend(const FrontendOptions& options, const GmsParams& gms)
    : options_(options), gms_(gms), orb_(makeDescriptorExtractor(options)) {}

FeatureSet Frontend::extract(const cv::Mat& gray, const cv::Mat& depth, double depth_units,
                             const PinholeCamera& camera) const {
  CV_Assert(gray.type() == CV_8UC1);
  FeatureSet set;
  set.width = gray.cols;
  set.height = gray.rows;
  const int b = options_.border;
  if (gray.cols <= 2 * b || gray.rows <= 2 * b) return set;

  // Row strips and corner chunks on OpenCV's threads, the same corners as
  // cv::goodFeaturesToTrack and cv::cornerSubPix (gmc/features/corners.h).
  std::vector<cv::Point2f> corners = detectCornersInside(gray, b, options_.corners());
  if (options_.subpixel) refineCornersSubPixel(gray, corners, options_.subpixel_window);
  set.keypoints.reserve(corners.size());
  for (const auto& c : corners) set.keypoints.emplace_back(c, 31.f, 0.f);
  if (set.keypoints.empty()) return set;

  orb_->compute(gray, set.keypoints, set.descriptors);  // may drop border keypoints
  set.points.resize(set.keypoints.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < set.keypoints.size(); ++i) {
    const auto& pt = set.keypoints[i].pt;
    const double z = depthAtKeypoint(depth, depth_units, pt.x, pt.y, options_.min_depth,
                                     options_.max_depth);
    if (z > 0) set.points[i] = camera.unproject(pt.x, pt.y, z);
  }
  return set;
}

std::vector<FeatureMatch> Frontend::matchGuided(const FeatureSet& ref, const FeatureSet& cur,
                                                const Isometry& T_cur_ref,
                                                const PinholeCamera& camera, int radius) const {
  std::vector<FeatureMatch> matches;
  if (ref.size() == 0 || cur.size() == 0) return matches;
  const KeypointGrid grid(cur.keypoints, cur.width, cur.height, 16);
  const float r2 = static_cast<float>(radius) * static_cast<float>(radius);
  matches.reserve(ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!ref.hasDepth(static_cast<int>(i))) continue;
    const Eigen::Vector3d p = T_cur_ref * ref.points[i];
    if (p.z() <= 1e-3) continue;
    const Eigen::Vector2d uv = camera.project(p);
    if (uv.x() < -radius || uv.y() < -radius || uv.x() > cur.width + radius ||
        uv.y() > cur.height + radius)
      continue;
    const std::uint8_t* d_ref = ref.descriptors.ptr<std::uint8_t>(static_cast<int>(i));
    int best = std::numeric_limits<int>::max(), second = best, best_j = -1;
    grid.forEachNear(static_cast<float>(uv.x()), static_cast<float>(uv.y()), radius, [&](int j) {
      const auto& kp = cur.keypoints[static_cast<size_t>(j)].pt;
      const float dx = kp.x - static_cast<float>(uv.x()), dy = kp.y - static_cast<float>(uv.y());
      if (dx * dx + dy * dy > r2) return;
      const int d = hamming(d_ref, cur.descriptors.ptr<std::uint8_t>(j));
      if (d < best) {
        second = best;
        best = d;
        best_j = j;
      } else if (d < second) {
        second = d;
      }
    });
    if (best_j < 0 || best > options_.max_hamming) continue;
    if (second != std::numeric_limits<int>::max() && best > options_.ratio * second) continue;
    matches.push_back({static_cast<int>(i), best_j, best});
  }
  return uniqueByCurrent(std::move(matches), cur.size());
}

std::vector<FeatureMatch> Frontend::matchExhaustive(const FeatureSet& ref,
                                                    const FeatureSet& cur) const {
  std::vector<FeatureMatch> matches;
  if (ref.size() == 0 || cur.size() == 0) return matches;
  // Best current match of every reference feature, then keep mutual bests.
  std::vector<int> best_ref_for_cur(cur.size(), -1);
  std::vector<int> best_dist_for_cur(cur.size(), std::numeric_limits<int>::max());
  std::vector<FeatureMatch> candidates;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!ref.hasDepth(static_cast<int>(i))) continue;
    const std::uint8_t* d_ref = ref.descriptors.ptr<std::uint8_t>(static_cast<int>(i));
    int best = std::numeric_limits<int>::max(), second = best, best_j = -1;
    for (size_t j = 0; j < cur.size(); ++j) {
      const int d = hamming(d_ref, cur.descriptors.ptr<std::uint8_t>(static_cast<int>(j)));
      if (d < best_dist_for_cur[j]) {
        best_dist_for_cur[j] = d;
        best_ref_for_cur[j] = static_cast<int>(i);
      }
      if (d < best) {
        second = best;
        best = d;
        best_j = static_cast<int>(j);
      } else if (d < second) {
        second = d;
      }
    }
    if (best_j < 0 || best > options_.max_hamming) continue;
    if (second != std::numeric_limits<int>::max() && best > options_.ratio * second) continue;
    candidates.push_back({static_cast<int>(i), best_j, best});
  }
  for (const auto& m : candidates)
    if (best_ref_for_cur[static_cast<size_t>(m.cur)] == m.ref) matches.push_back(m);
  return matches;
}

std::vector<FeatureMatch> Frontend::filterGms(const FeatureSet& ref, const FeatureSet& cur,
                                              const std::vector<FeatureMatch>& matches) const {
  if (!options_.use_gms || static_cast<int>(matches.size()) < options_.min_matches_for_gms)
    return matches;
  auto toGms = [](const std::vector<cv::KeyPoint>& kps) {
    std::vector<GmsKeypoint> out(kps.size());
    for (size_t i = 0; i < kps.size(); ++i)
      out[i] = {kps[i].pt.x, kps[i].pt.y, kps[i].size, kps[i].angle};
    return out;
  };
  std::vector<GmsMatch> gm(matches.size());
  for (size_t i = 0; i < matches.size(); ++i) gm[i] = {matches[i].ref, matches[i].cur};
  const auto keep = gmsFilter(toGms(ref.keypoints), ref.width, ref.height, toGms(cur.keypoints),
                              cur.width, cur.height, gm, gms_);
  std::vector<FeatureMatch> out;
  out.reserve(matches.size());
  for (size_t i = 0; i < matches.size(); ++i)
    if (keep[i]) out.push_back(matches[i]);
  return out;
}

}  // namespace gmc::features
