#include "gmc/vo/trajectory_smoother.h"

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Dense>

namespace gmc::vo {

namespace {

// The SO(3) exponential and logarithm of MRPT, as the frame refinement's expSE3 uses.
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  return mrpt::poses::Lie::SO<3>::log(mrpt::math::CMatrixDouble33(R)).asEigen();
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w) {
  return mrpt::poses::Lie::SO<3>::exp(mrpt::math::CVectorFixedDouble<3>(w)).asEigen();
}

}  // namespace

Isometry smoothedPoseAt(const std::deque<RevisedPose>& window, size_t index) {
  const size_t n = window.size();
  const RevisedPose& centre = window[index];
  // Rows [1, dt, dt^2] around the frame's stamp: the fit's value at dt = 0 is the
  // first coefficient. Time in frames of 1/30 s keeps the columns alike in scale.
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), 3);
  Eigen::MatrixXd values(static_cast<Eigen::Index>(n), 6);
  const Eigen::Matrix3d R_centre_inv = centre.T_world_camera.linear().transpose();
  for (size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    const double dt = (window[i].stamp - centre.stamp) * 30.0;
    A.row(row) << 1.0, dt, dt * dt;
    values.block<1, 3>(row, 0) = window[i].T_world_camera.translation().transpose();
    values.block<1, 3>(row, 3) = logSO3(R_centre_inv * window[i].T_world_camera.linear()).transpose();
  }
  const Eigen::MatrixXd coefficients = A.colPivHouseholderQr().solve(values);
  Isometry out = Isometry::Identity();
  out.translation() = coefficients.block<1, 3>(0, 0).transpose();
  out.linear() = centre.T_world_camera.linear() * expSO3(coefficients.block<1, 3>(0, 3).transpose());
  return out;
}

bool TrajectorySmoother::continuesRun(const RevisedPose& frame) const {
  if (window_.empty()) return true;
  const Isometry& last = window_.back().T_world_camera;
  const Isometry before = window_.size() > 1 ? window_[window_.size() - 2].T_world_camera : last;
  const Eigen::Vector3d step = frame.T_world_camera.translation() - last.translation();
  const Eigen::Vector3d step_before = last.translation() - before.translation();
  // Rotation steps in the camera's own frame: the change between the two is a rotation.
  const Eigen::Matrix3d turn = last.linear().transpose() * frame.T_world_camera.linear();
  const Eigen::Matrix3d turn_before = before.linear().transpose() * last.linear();
  const double turn_change = Eigen::AngleAxisd(turn_before.transpose() * turn).angle();
  return (step - step_before).norm() <= max_step_change_ && turn_change <= max_step_change_;
}

RevisedPose TrajectorySmoother::fitted(size_t index) const {
  const RevisedPose& frame = window_[index];
  return {frame.frame_number, frame.stamp, smoothedPoseAt(window_, index)};
}

std::vector<RevisedPose> TrajectorySmoother::endRun() {
  std::vector<RevisedPose> out;
  const auto k = static_cast<size_t>(half_window_);
  if (fit_edges_ && half_window_ > 0 && window_.size() == 2 * k + 1)
    for (size_t i = k + 1; i < window_.size(); ++i) out.push_back(fitted(i));
  window_.clear();
  return out;
}

std::vector<RevisedPose> TrajectorySmoother::add(const RevisedPose& frame) {
  std::vector<RevisedPose> out;
  if (half_window_ <= 0) return out;
  if (!continuesRun(frame)) out = endRun();
  window_.push_back(frame);
  const auto k = static_cast<size_t>(half_window_);
  const bool first_full = window_.size() == 2 * k + 1;
  if (window_.size() > 2 * k + 1) window_.pop_front();
  if (window_.size() < 2 * k + 1) return out;
  if (first_full && fit_edges_)
    for (size_t i = 0; i < k; ++i) out.push_back(fitted(i));
  out.push_back(fitted(k));
  return out;
}

}  // namespace gmc::vo
