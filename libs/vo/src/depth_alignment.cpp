#include "gmc/vo/depth_alignment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/imgproc.hpp>

namespace gmc::vo {
namespace {

/// The sampled pixel of grid cell (col, row): the centre of its stride x stride block.
inline double sampleCoordinate(int index, int stride) { return index * stride + 0.5 * stride; }

}  // namespace

cv::Mat1b DepthAlignment::excludedCells(const cv::Mat& depth, const std::vector<cv::Point2f>& dynamic_pixels) const {
  const int c = options_.exclusion_cell_px;
  cv::Mat1b cells = cv::Mat1b::zeros((depth.rows + c - 1) / c, (depth.cols + c - 1) / c);
  for (const auto& p : dynamic_pixels) {
    const int x = static_cast<int>(p.x) / c, y = static_cast<int>(p.y) / c;
    if (x >= 0 && y >= 0 && x < cells.cols && y < cells.rows) cells(y, x) = 255;
  }
  cv::dilate(cells, cells, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 0);
  return cells;
}

std::vector<DepthAlignment::Plane> DepthAlignment::samplePlanes(const cv::Mat& depth, double depth_units,
                                                                const PinholeCamera& camera,
                                                                const std::vector<cv::Point2f>& dynamic_pixels,
                                                                const cv::Mat& known_dynamic, int& cols,
                                                                int& rows) const {
  const int s = options_.stride, e = options_.exclusion_cell_px;
  cols = depth.cols / s;
  rows = depth.rows / s;
  // The camera-frame points of the grid first (z = 0: none), then normals from the
  // neighbouring samples where the depth is continuous and flat.
  std::vector<Eigen::Vector3d> points(static_cast<size_t>(cols * rows), Eigen::Vector3d::Zero());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double u = sampleCoordinate(c, s), v = sampleCoordinate(r, s);
      if (!known_dynamic.empty() && known_dynamic.at<std::uint8_t>(static_cast<int>(v), static_cast<int>(u))) continue;
      const double z = depth.at<std::uint16_t>(static_cast<int>(v), static_cast<int>(u)) * depth_units;
      if (z > 0) points[static_cast<size_t>(r * cols + c)] = camera.unproject(u, v, z);
    }
  const cv::Mat1b excluded = excludedCells(depth, dynamic_pixels);
  std::vector<Plane> planes(points.size());
  const auto at = [&](int rr, int cc) -> const Eigen::Vector3d& { return points[static_cast<size_t>(rr * cols + cc)]; };
  for (int r = 1; r + 1 < rows; ++r)
    for (int c = 1; c + 1 < cols; ++c) {
      const Eigen::Vector3d& p = at(r, c);
      if (p.z() <= 0) continue;
      if (excluded(static_cast<int>(sampleCoordinate(r, s)) / e, static_cast<int>(sampleCoordinate(c, s)) / e))
        continue;
      const Eigen::Vector3d* nb[4] = {&at(r, c - 1), &at(r, c + 1), &at(r - 1, c), &at(r + 1, c)};
      // A depth edge (a walker in front of the wall) gives no plane.
      const double step = 0.05 + 0.02 * p.z() * p.z();
      bool continuous = true;
      for (const auto* q : nb) continuous = continuous && q->z() > 0 && std::abs(q->z() - p.z()) < step;
      if (!continuous) continue;
      Eigen::Vector3d n = (*nb[1] - *nb[0]).cross(*nb[3] - *nb[2]);
      if (n.norm() < 1e-12) continue;
      n.normalize();
      if (std::abs(n.dot(p.normalized())) < 0.2) continue;  // grazing: the depth is unreliable there
      // A fold (a corner of two walls, a walker's edge) is no plane: the point must lie on
      // the plane of its neighbours.
      const double fold = 0.01 + 0.005 * p.z() * p.z();
      if (std::abs(n.dot(p - 0.5 * (*nb[0] + *nb[1]))) > fold || std::abs(n.dot(p - 0.5 * (*nb[2] + *nb[3]))) > fold)
        continue;
      Plane& plane = planes[static_cast<size_t>(r * cols + c)];
      plane.point = p.cast<float>();
      plane.normal = n.cast<float>();
    }
  return planes;
}

void DepthAlignment::setReference(const cv::Mat& depth, double depth_units, const PinholeCamera& camera,
                                  const Isometry& T_world_camera, double stamp,
                                  const std::vector<cv::Point2f>& dynamic_pixels, const cv::Mat& known_dynamic) {
  reference_.clear();
  if (!options_.enabled) return;
  reference_ =
      samplePlanes(depth, depth_units, camera, dynamic_pixels, known_dynamic, reference_cols_, reference_rows_);
  T_reference_world_ = T_world_camera.inverse();
  reference_centre_ = T_world_camera.translation();
  reference_stamp_ = stamp;
  const Eigen::Affine3f T_wc = T_world_camera.cast<float>();
  for (Plane& plane : reference_) {
    if (plane.normal.isZero()) continue;
    plane.point = T_wc * plane.point;
    plane.normal = T_wc.linear() * plane.normal;
  }
}

void DepthAlignment::maskReference(const cv::Mat& mask, double stamp) {
  if (mask.empty() || reference_.empty() || stamp != reference_stamp_) return;
  const int s = options_.stride;
  for (int r = 0; r < reference_rows_; ++r)
    for (int c = 0; c < reference_cols_; ++c)
      if (mask.at<std::uint8_t>(static_cast<int>(sampleCoordinate(r, s)), static_cast<int>(sampleCoordinate(c, s))))
        reference_[static_cast<size_t>(r * reference_cols_ + c)].normal.setZero();
}

void DepthAlignment::setCurrent(const cv::Mat& depth, double depth_units, const PinholeCamera& camera, double stamp,
                                const std::vector<cv::Point2f>& dynamic_pixels, const cv::Mat& known_dynamic) {
  current_.clear();
  if (!options_.enabled || reference_.empty() || stamp - reference_stamp_ > options_.max_age_seconds) return;
  int cols = 0, rows = 0;
  for (const Plane& plane : samplePlanes(depth, depth_units, camera, dynamic_pixels, known_dynamic, cols, rows))
    if (!plane.normal.isZero()) current_.push_back(plane);
}

bool DepthAlignment::associate(const Plane& sample, const Isometry& T_world_cur, const PinholeCamera& camera,
                               const RefinementOptions& noise, Association& out) const {
  const Eigen::Vector3d p = sample.point.cast<double>();
  const Eigen::Vector3d x = T_world_cur * p;
  const Eigen::Vector3d in_ref = T_reference_world_ * x;
  if (in_ref.z() <= 0.1) return false;
  const int s = options_.stride;
  const Eigen::Vector2d uv = camera.project(in_ref);
  const int c = static_cast<int>(std::lround((uv.x() - 0.5 * s) / s));
  const int r = static_cast<int>(std::lround((uv.y() - 0.5 * s) / s));
  if (c < 0 || r < 0 || c >= reference_cols_ || r >= reference_rows_) return false;
  const Plane& plane = reference_[static_cast<size_t>(r * reference_cols_ + c)];
  if (plane.normal.isZero()) return false;
  const Eigen::Vector3d n = plane.normal.cast<double>();
  // Surfaces that face another way are other surfaces (a wall across a corner, a walker).
  if (n.dot(T_world_cur.linear() * sample.normal.cast<double>()) < options_.min_normal_agreement) return false;
  const Eigen::Vector3d q = plane.point.cast<double>();
  const Eigen::Vector3d d = x - q;
  // Across the plane at most max_distance; along it within a sample spacing or two (the
  // samples of a wall seen at a grazing angle lie far apart).
  const double along_normal = n.dot(d);
  const Eigen::Vector3d view = q - reference_centre_;
  const double spacing = s * view.norm() / camera.fx / std::max(0.2, std::abs(n.dot(view.normalized())));
  if (std::abs(along_normal) > options_.max_distance || (d - along_normal * n).norm() > 2 * spacing) return false;
  // Both frames' depth noise (the reference's point is a reading too).
  out.sigma = std::sqrt(2.0) * noise.depthSigma(p.z());
  out.whitened = along_normal / out.sigma;
  out.normal = n;
  return std::abs(out.whitened) <= options_.max_whitened;
}

void DepthAlignment::keepAgreeing(const Isometry& T_cur_world, const PinholeCamera& camera,
                                  const RefinementOptions& noise) {
  if (options_.guess_gate <= 0 || current_.empty()) return;
  const Isometry T_world_cur = T_cur_world.inverse();
  Association a;
  current_.erase(std::remove_if(current_.begin(), current_.end(),
                                [&](const Plane& sample) {
                                  return !associate(sample, T_world_cur, camera, noise, a) ||
                                         std::abs(a.whitened) > options_.guess_gate;
                                }),
                 current_.end());
}

int DepthAlignment::accumulate(const Isometry& T_cur_world, const PinholeCamera& camera, const RefinementOptions& noise,
                               Mat6& H, Vec6& g) const {
  if (current_.empty()) return 0;
  const Isometry T_world_cur = T_cur_world.inverse();
  const Eigen::Matrix3d& R_wc = T_world_cur.linear();
  int associated = 0;
  Association a;
  for (const Plane& sample : current_) {
    if (!associate(sample, T_world_cur, camera, noise, a)) continue;
    const Eigen::Vector3d p = sample.point.cast<double>();
    // x(xi) = T_world_cur exp(-xi) p ~ x + R_wc (-rho + [p]x phi) for a left perturbation xi of T_cur_world.
    const Eigen::Vector3d nr = R_wc.transpose() * a.normal;
    Eigen::Matrix<double, 1, 6> J;
    J.leftCols<3>() = -nr.transpose();
    J.rightCols<3>() = nr.cross(p).transpose();  // n^T R (p x phi) = (R^T n x p) . phi
    J /= a.sigma;
    const double t = a.whitened / options_.max_whitened;
    const double w = options_.weight * (1 - t * t) * (1 - t * t);  // Tukey: no pull from the far tail
    H.noalias() += w * J.transpose() * J;
    g.noalias() += w * J.transpose() * a.whitened;
    ++associated;
  }
  return associated;
}

}  // namespace gmc::vo
