#include "gmc/vo/odometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>

namespace gmc::vo {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double rotationDeg(const Isometry& T) {
  return Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
}

/// Rigid transform mapping src onto dst (least squares, no scale).
bool fitRigid(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, Isometry& T) {
  if (src.cols() < 3) return false;
  const Eigen::Matrix4d M = Eigen::umeyama(src, dst, false);
  if (!M.allFinite()) return false;
  T.matrix() = M;
  return true;
}

}  // namespace

const char* toString(TrackingState s) {
  switch (s) {
    case TrackingState::Initialized: return "initialized";
    case TrackingState::Tracking: return "tracking";
    case TrackingState::Lost: return "lost";
    case TrackingState::Reanchored: return "reanchored";
  }
  return "?";
}

RgbdOdometry::RgbdOdometry(const OdometryConfig& config)
    : config_(config), frontend_(config.frontend, config.gms), gmc_(config.gmc), gmc_previous_(config.gmc) {}

void RgbdOdometry::labelAgainstPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_cur,
                                             const PinholeCamera& camera, FrameTracking& out) {
  // A walker near the camera moves more between keyframe and frame than the guided
  // window; one frame apart it is still matchable. Only keypoints the keyframe pass left
  // undecided take these labels, so the pose (already refined) is unaffected.
  const Isometry T_prev_cur = T_world_previous_.inverse() * T_world_cur;
  auto matches = frontend_.matchGuided(previous_, cur, T_prev_cur.inverse(), camera,
                                       config_.frontend.match_radius);
  matches = frontend_.filterGms(previous_, cur, matches);
  std::vector<MotionMatch> motion;
  std::vector<int> cur_index;
  for (const auto& m : matches) {
    if (!cur.hasDepth(m.cur)) continue;
    const auto& kp = cur.keypoints[static_cast<size_t>(m.cur)].pt;
    motion.push_back({Eigen::Vector2f(kp.x, kp.y), previous_.points[static_cast<size_t>(m.ref)],
                      cur.points[static_cast<size_t>(m.cur)]});
    cur_index.push_back(m.cur);
  }
  const auto t_gmc = Clock::now();
  out.gmc_previous = gmc_previous_.classify(motion, T_prev_cur, cur.width, cur.height);
  out.times.gmc += msSince(t_gmc);
  for (size_t k = 0; k < motion.size(); ++k) {
    auto& label = out.keypoint_labels[static_cast<size_t>(cur_index[k])];
    if (label == MotionLabel::Undecided && out.gmc_previous.labels[k] == MotionLabel::Dynamic) {
      label = MotionLabel::Dynamic;
      ++out.num_dynamic;
    }
  }
}

Isometry RgbdOdometry::predictPose() const {
  return config_.odometry.use_motion_model ? T_world_last_ * velocity_ : T_world_last_;
}

int RgbdOdometry::countSupport(const std::vector<MotionMatch>& matches, const Isometry& T_kf_cur,
                               const std::vector<std::uint8_t>* mask) const {
  const auto& o = config_.odometry;
  int n = 0;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (mask && !(*mask)[i]) continue;
    const auto& m = matches[i];
    const double z = m.point_cur.z();
    const double thr = o.inlier_base + o.inlier_per_m2 * z * z;
    if ((m.point_ref - T_kf_cur * m.point_cur).squaredNorm() < thr * thr) ++n;
  }
  return n;
}

RgbdOdometry::Guess RgbdOdometry::initialGuess(const std::vector<MotionMatch>& matches,
                                               const std::vector<std::uint8_t>& trusted,
                                               const Isometry& predicted) {
  // The prediction comes from motion refined on static points only, so walkers cannot
  // corrupt it; RANSAC only replaces it when it explains clearly fewer matches (sudden
  // motion). RANSAC samples only matches not known to be dynamic at the keyframe.
  Guess guess;
  guess.T_kf_cur = predicted;
  guess.support = countSupport(matches, predicted, nullptr);

  std::vector<int> pool;
  for (size_t i = 0; i < matches.size(); ++i)
    if (trusted[i]) pool.push_back(static_cast<int>(i));

  auto next = [this]() {  // xorshift64*: deterministic, cheap
    rng_state_ ^= rng_state_ >> 12;
    rng_state_ ^= rng_state_ << 25;
    rng_state_ ^= rng_state_ >> 27;
    return rng_state_ * 2685821657736338717ull;
  };
  Isometry best_T = predicted;
  int best_support = -1;
  Eigen::Matrix3Xd src(3, 3), dst(3, 3);
  const int iterations = pool.size() < 3 ? 0 : config_.odometry.ransac_iterations;
  for (int it = 0; it < iterations; ++it) {
    int idx[3];
    for (int k = 0; k < 3; ++k) idx[k] = pool[next() % pool.size()];
    if (idx[0] == idx[1] || idx[0] == idx[2] || idx[1] == idx[2]) continue;
    for (int k = 0; k < 3; ++k) {
      src.col(k) = matches[static_cast<size_t>(idx[k])].point_cur;
      dst.col(k) = matches[static_cast<size_t>(idx[k])].point_ref;
    }
    // Degenerate (nearly collinear) samples give unstable rotations.
    if ((src.col(1) - src.col(0)).cross(src.col(2) - src.col(0)).norm() < 1e-3) continue;
    Isometry T;
    if (!fitRigid(src, dst, T)) continue;
    const int support = countSupport(matches, T, &trusted);
    if (support > best_support) {
      best_support = support;
      best_T = T;
    }
  }
  const int pred_support_trusted = countSupport(matches, predicted, &trusted);
  if (best_support > 0 &&
      pred_support_trusted < config_.odometry.prediction_support * best_support) {
    guess.T_kf_cur = best_T;
    guess.from_ransac = true;
  }
  // Polish on the hypothesis' inliers: GMC measures residuals against this guess, and a
  // centimetre of error would shift the whole background off the zero-motion pattern.
  const auto& o = config_.odometry;
  for (int round = 0; round < 3; ++round) {
    std::vector<int> in;
    for (size_t i = 0; i < matches.size(); ++i) {
      if (!trusted[i]) continue;
      const auto& m = matches[i];
      const double thr = o.inlier_base + o.inlier_per_m2 * m.point_cur.z() * m.point_cur.z();
      if ((m.point_ref - guess.T_kf_cur * m.point_cur).squaredNorm() < thr * thr)
        in.push_back(static_cast<int>(i));
    }
    if (in.size() < 6) break;
    Eigen::Matrix3Xd src(3, in.size()), dst(3, in.size());
    for (size_t k = 0; k < in.size(); ++k) {
      src.col(static_cast<Eigen::Index>(k)) = matches[static_cast<size_t>(in[k])].point_cur;
      dst.col(static_cast<Eigen::Index>(k)) = matches[static_cast<size_t>(in[k])].point_ref;
    }
    fitRigid(src, dst, guess.T_kf_cur);
  }
  guess.support = countSupport(matches, guess.T_kf_cur, nullptr);
  return guess;
}

void RgbdOdometry::makeKeyframe(features::FeatureSet&& features, std::vector<MotionLabel> labels,
                                const Isometry& T_world_cur, int static_matches) {
  keyframe_.features = std::move(features);
  keyframe_.labels = std::move(labels);
  keyframe_.T_world_kf = T_world_cur;
  keyframe_.static_matches = static_matches;
}

FrameTracking RgbdOdometry::process(const cv::Mat& gray, const cv::Mat& depth,
                                    double depth_units, const PinholeCamera& camera,
                                    double stamp) {
  const auto t_start = Clock::now();
  FrameTracking out;
  out.stamp = stamp;

  features::FeatureSet cur = frontend_.extract(gray, depth, depth_units, camera);
  out.num_features = static_cast<int>(cur.size());
  out.keypoints.reserve(cur.size());
  for (const auto& kp : cur.keypoints) out.keypoints.push_back(kp.pt);
  out.keypoint_labels.assign(cur.size(), MotionLabel::Undecided);

  if (!initialized_) {
    out.times.frontend = msSince(t_start);
    out.state = TrackingState::Initialized;
    out.new_keyframe = true;
    previous_ = cur;
    T_world_previous_ = Isometry::Identity();
    makeKeyframe(std::move(cur), std::vector<MotionLabel>(out.num_features, MotionLabel::Undecided),
                 Isometry::Identity(), 0);
    initialized_ = true;
    T_world_last_ = Isometry::Identity();
    velocity_ = Isometry::Identity();
    out.times.total = msSince(t_start);
    return out;
  }

  // 1. Guided matching against the keyframe, from the predicted pose.
  const Isometry T_world_pred = predictPose();
  const Isometry T_kf_pred = keyframe_.T_world_kf.inverse() * T_world_pred;
  std::vector<features::FeatureMatch> matches = frontend_.matchGuided(
      keyframe_.features, cur, T_kf_pred.inverse(), camera, config_.frontend.match_radius);
  if (static_cast<int>(matches.size()) < config_.odometry.min_matches)
    matches = frontend_.matchGuided(keyframe_.features, cur, T_kf_pred.inverse(), camera,
                                    config_.odometry.wide_match_radius);
  if (static_cast<int>(matches.size()) < config_.odometry.min_matches)
    matches = frontend_.matchExhaustive(keyframe_.features, cur);
  matches = frontend_.filterGms(keyframe_.features, cur, matches);
  out.num_matches = static_cast<int>(matches.size());

  // Matches with depth on both sides feed GMC and the initial guess.
  std::vector<MotionMatch> motion;
  std::vector<int> motion_to_match;
  std::vector<std::uint8_t> trusted;
  motion.reserve(matches.size());
  for (size_t i = 0; i < matches.size(); ++i) {
    const auto& m = matches[i];
    if (!cur.hasDepth(m.cur)) continue;
    const auto& kp = cur.keypoints[static_cast<size_t>(m.cur)].pt;
    motion.push_back({Eigen::Vector2f(kp.x, kp.y), keyframe_.features.points[static_cast<size_t>(m.ref)],
                      cur.points[static_cast<size_t>(m.cur)]});
    motion_to_match.push_back(static_cast<int>(i));
    trusted.push_back(keyframe_.labels[static_cast<size_t>(m.ref)] != MotionLabel::Dynamic);
  }
  out.times.frontend = msSince(t_start);

  // 2. Initial guess not corrupted by walkers.
  auto t0 = Clock::now();
  const Guess guess = initialGuess(motion, trusted, T_kf_pred);
  out.times.guess = msSince(t0);

  // 3. GMC labels.
  t0 = Clock::now();
  out.gmc = gmc_.classify(motion, guess.T_kf_cur, gray.cols, gray.rows);
  out.times.gmc = msSince(t0);

  // 4. Refinement on static matches only (reprojection + depth).
  t0 = Clock::now();
  std::vector<PointObservation> obs;
  obs.reserve(motion.size());
  for (size_t k = 0; k < motion.size(); ++k) {
    const auto& fm = matches[static_cast<size_t>(motion_to_match[k])];
    out.keypoint_labels[static_cast<size_t>(fm.cur)] = out.gmc.labels[k];
    if (out.gmc.labels[k] != MotionLabel::Static) continue;
    obs.push_back({motion[k].point_ref, motion[k].pixel.cast<double>(), motion[k].point_cur.z()});
  }
  out.num_static = out.gmc.num_static;
  out.num_dynamic = out.gmc.num_dynamic;
  RefinementResult refined =
      refinePose(obs, guess.T_kf_cur.inverse(), camera, config_.refinement);
  out.num_inliers = refined.inliers;
  out.times.refine = msSince(t0);

  Isometry T_world_cur;
  if (refined.inliers >= config_.odometry.min_static_inliers) {
    T_world_cur = keyframe_.T_world_kf * refined.T_cur_ref.inverse();
    out.state = TrackingState::Tracking;
    lost_streak_ = 0;
    velocity_ = T_world_last_.inverse() * T_world_cur;
  } else {
    // Lost: keep predicting, re-anchor on a new keyframe when loss persists.
    T_world_cur = T_world_pred;
    out.state = TrackingState::Lost;
    out.lost_reason = "only " + std::to_string(refined.inliers) + " static inliers (of " +
                      std::to_string(motion.size()) + " matches with depth)";
    ++lost_streak_;
  }
  out.T_world_camera = T_world_cur;
  if (config_.odometry.previous_frame_labels && config_.gmc.enabled && previous_.size() > 0) {
    const auto t_prev = Clock::now();
    const double gmc_before = out.times.gmc;
    labelAgainstPreviousFrame(cur, T_world_cur, camera, out);
    out.times.frontend += msSince(t_prev) - (out.times.gmc - gmc_before);  // the matching part
  }
  previous_ = cur;
  T_world_previous_ = T_world_cur;

  // 5. Keyframe management.
  const Isometry T_kf_cur = keyframe_.T_world_kf.inverse() * T_world_cur;
  const bool far = T_kf_cur.translation().norm() > config_.odometry.keyframe_max_translation ||
                   rotationDeg(T_kf_cur) > config_.odometry.keyframe_max_rotation;
  if (out.state == TrackingState::Tracking) {
    if (keyframe_.static_matches == 0) keyframe_.static_matches = refined.inliers;
    const bool weak =
        refined.inliers < config_.odometry.keyframe_min_overlap * keyframe_.static_matches;
    if (far || weak) {
      out.new_keyframe = true;
      makeKeyframe(std::move(cur), out.keypoint_labels, T_world_cur, 0);
    }
  } else if (lost_streak_ >= config_.odometry.reanchor_after_lost) {
    out.state = TrackingState::Reanchored;
    out.new_keyframe = true;
    velocity_ = Isometry::Identity();
    lost_streak_ = 0;
    makeKeyframe(std::move(cur), out.keypoint_labels, T_world_cur, 0);
  }
  T_world_last_ = T_world_cur;
  out.times.total = msSince(t_start);
  return out;
}

}  // namespace gmc::vo
