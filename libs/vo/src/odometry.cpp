#include "gmc/vo/odometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

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

/// The GMC input of one feature match: current pixel, reference and current 3-D points.
MotionMatch motionMatch(const features::FeatureSet& ref, const features::FeatureSet& cur,
                        const features::FeatureMatch& m) {
  const auto& kp = cur.keypoints[static_cast<size_t>(m.cur)].pt;
  return {Eigen::Vector2f(kp.x, kp.y), ref.points[static_cast<size_t>(m.ref)],
          cur.points[static_cast<size_t>(m.cur)]};
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
                                             FrameTracking& out) {
  // A walker near the camera moves more between keyframe and frame than the guided
  // window; one frame apart it is still matchable. Only keypoints the keyframe pass left
  // undecided take these labels, so the pose (already refined) is unaffected.
  const Isometry T_prev_cur = T_world_previous_.inverse() * T_world_cur;
  std::vector<MotionMatch> motion;
  std::vector<int> cur_index;
  for (const auto& m : previous_matches_) {
    if (!cur.hasDepth(m.cur) || !previous_.hasDepth(m.ref)) continue;
    motion.push_back(motionMatch(previous_, cur, m));
    cur_index.push_back(m.cur);
  }
  const auto t_gmc = Clock::now();
  out.gmc_previous = gmc_previous_.classify(motion, T_prev_cur, cur.width, cur.height);
  out.times.gmc += msSince(t_gmc);
  for (size_t k = 0; k < motion.size(); ++k) {
    auto& label = out.keypoint_labels[static_cast<size_t>(cur_index[k])];
    if (out.gmc_previous.labels[k] != MotionLabel::Dynamic) continue;
    fresh_dynamic_[static_cast<size_t>(cur_index[k])] = 1;
    if (label == MotionLabel::Undecided) {
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
  Keyframe kf;
  kf.features = std::move(features);
  kf.labels = std::move(labels);
  kf.T_world_kf = T_world_cur;
  kf.static_matches = static_matches;
  const size_t capacity = static_cast<size_t>(std::max(1, config_.odometry.local_map_keyframes));
  if (local_map_.size() >= capacity)
    local_map_.erase(local_map_.begin(), local_map_.begin() + static_cast<long>(local_map_.size() - capacity + 1));
  local_map_.push_back(std::move(kf));
}

void RgbdOdometry::trackAgainst(const Keyframe& kf, const features::FeatureSet& cur,
                                const Isometry& T_world_guess, const PinholeCamera& camera,
                                bool fallbacks, GmcClassifier& gmc, KeyframeTrack& track,
                                StageTimes& times) {
  auto t0 = Clock::now();
  const Isometry T_kf_guess = kf.T_world_kf.inverse() * T_world_guess;
  std::vector<features::FeatureMatch> matches = frontend_.matchGuided(
      kf.features, cur, T_kf_guess.inverse(), camera, config_.frontend.match_radius);
  if (fallbacks && static_cast<int>(matches.size()) < config_.odometry.min_matches)
    matches = frontend_.matchGuided(kf.features, cur, T_kf_guess.inverse(), camera,
                                    config_.odometry.wide_match_radius);
  if (fallbacks && static_cast<int>(matches.size()) < config_.odometry.min_matches)
    matches = frontend_.matchExhaustive(kf.features, cur);
  matches = frontend_.filterGms(kf.features, cur, matches);
  track.num_matches = static_cast<int>(matches.size());

  // Matches with depth on both sides feed GMC and the initial guess.
  track.motion.clear();
  track.cur_index.clear();
  track.trusted.clear();
  for (const auto& m : matches) {
    if (!cur.hasDepth(m.cur)) continue;
    track.motion.push_back(motionMatch(kf.features, cur, m));
    track.cur_index.push_back(m.cur);
    track.trusted.push_back(kf.labels[static_cast<size_t>(m.ref)] != MotionLabel::Dynamic);
  }
  times.frontend += msSince(t0);

  // Initial guess not corrupted by walkers, then GMC's labels against it.
  t0 = Clock::now();
  if (fallbacks) {
    track.guess = initialGuess(track.motion, track.trusted, T_kf_guess);
  } else {  // older keyframes: the pose refined on the current keyframe is the guess
    track.guess = Guess{};
    track.guess.T_kf_cur = T_kf_guess;
  }
  times.guess += msSince(t0);
  t0 = Clock::now();
  gmc.classify(track.motion, track.guess.T_kf_cur, cur.width, cur.height, track.gmc);
  times.gmc += msSince(t0);
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
  out.times.frontend = msSince(t_start);

  if (!initialized_) {
    out.state = TrackingState::Initialized;
    out.new_keyframe = true;
    previous_ = cur;
    previous_memory_.assign(cur.size(), 0);
    T_world_previous_ = Isometry::Identity();
    local_map_.clear();
    makeKeyframe(std::move(cur), std::vector<MotionLabel>(out.num_features, MotionLabel::Undecided),
                 Isometry::Identity(), 0);
    initialized_ = true;
    T_world_last_ = Isometry::Identity();
    velocity_ = Isometry::Identity();
    out.times.total = msSince(t_start);
    return out;
  }

  const Isometry T_world_pred = predictPose();
  // Frame-to-frame matches (guided by the prediction): they carry remembered dynamic
  // labels forward, so a walker who pauses or walks along the viewing ray stays dynamic
  // while GMC cannot see its motion over a short keyframe gap.
  const bool frame_to_frame = config_.gmc.enabled && previous_.size() > 0 &&
                              (config_.odometry.previous_frame_labels ||
                               config_.odometry.dynamic_memory_frames > 0);
  previous_matches_.clear();
  memory_.assign(cur.size(), 0);
  fresh_dynamic_.assign(cur.size(), 0);
  if (frame_to_frame) {
    const auto t_match = Clock::now();
    const Isometry T_prev_pred = T_world_previous_.inverse() * T_world_pred;
    previous_matches_ = frontend_.filterGms(
        previous_, cur,
        frontend_.matchGuided(previous_, cur, T_prev_pred.inverse(), camera, config_.frontend.match_radius));
    for (const auto& m : previous_matches_)
      if (previous_memory_[static_cast<size_t>(m.ref)] > 0)
        memory_[static_cast<size_t>(m.cur)] = previous_memory_[static_cast<size_t>(m.ref)] - 1;
    out.times.frontend += msSince(t_match);
  }
  auto remembered = [&](int cur_index) { return memory_[static_cast<size_t>(cur_index)] > 0; };

  // 1-3. The current keyframe: guided matching from the prediction, guess, GMC labels.
  trackAgainst(keyframe(), cur, T_world_pred, camera, true, gmc_, primary_, out.times);
  out.num_matches = primary_.num_matches;
  out.gmc = primary_.gmc;

  // 4. Refinement on static matches only (reprojection + depth).
  auto t0 = Clock::now();
  std::vector<PointObservation> obs;
  obs.reserve(primary_.motion.size());
  out.num_static = primary_.gmc.num_static;
  out.num_dynamic = primary_.gmc.num_dynamic;
  for (size_t k = 0; k < primary_.motion.size(); ++k) {
    MotionLabel& label = out.keypoint_labels[static_cast<size_t>(primary_.cur_index[k])];
    label = primary_.gmc.labels[k];
    if (label == MotionLabel::Dynamic) fresh_dynamic_[static_cast<size_t>(primary_.cur_index[k])] = 1;
    if (label != MotionLabel::Static) continue;
    // Remembered walkers and keyframe features labelled dynamic stay out of the pose.
    if (remembered(primary_.cur_index[k]) || !primary_.trusted[k]) {
      label = MotionLabel::Dynamic;
      --out.num_static;
      ++out.num_dynamic;
      continue;
    }
    const auto& m = primary_.motion[k];
    obs.push_back({m.point_ref, m.pixel.cast<double>(), m.point_cur.z()});
  }
  const Isometry T_world_kf = keyframe().T_world_kf;
  const RefinementResult refined =
      refinePose(obs, primary_.guess.T_kf_cur.inverse(), camera, config_.refinement);
  out.times.refine += msSince(t0);
  const bool primary_tracked = refined.inliers >= config_.odometry.min_static_inliers;
  Isometry T_world_cur = primary_tracked ? T_world_kf * refined.T_cur_ref.inverse() : T_world_pred;
  int inliers = refined.inliers;
  out.position_sigma = positionStdDev(refined);

  // 4b. Local map: the older keyframes' static matches join the refinement, expressed in
  // the world frame. They hold static structure seen before walkers covered it and carry
  // no drift accumulated since, so tracking survives a crowded view and snaps back when
  // the background reappears.
  if (local_map_.size() > 1) {
    for (auto& o : obs) o.point_ref = T_world_kf * o.point_ref;
    out.local_map_keyframes = primary_tracked ? 1 : 0;
    for (size_t i = 0; i + 1 < local_map_.size(); ++i) {
      const Keyframe& kf = local_map_[i];
      trackAgainst(kf, cur, T_world_cur, camera, false, gmc_previous_, secondary_, out.times);
      t0 = Clock::now();
      int added = 0;
      for (size_t k = 0; k < secondary_.motion.size(); ++k) {
        auto& label = out.keypoint_labels[static_cast<size_t>(secondary_.cur_index[k])];
        const MotionLabel l = secondary_.gmc.labels[k];
        if (l == MotionLabel::Dynamic) fresh_dynamic_[static_cast<size_t>(secondary_.cur_index[k])] = 1;
        if (label == MotionLabel::Undecided && l == MotionLabel::Dynamic) {
          label = MotionLabel::Dynamic;
          ++out.num_dynamic;
        }
        if (l != MotionLabel::Static || label == MotionLabel::Dynamic || !secondary_.trusted[k]) continue;
        const auto& m = secondary_.motion[k];
        obs.push_back({kf.T_world_kf * m.point_ref, m.pixel.cast<double>(), m.point_cur.z()});
        ++added;
      }
      if (added >= config_.odometry.min_static_inliers) ++out.local_map_keyframes;
      out.times.refine += msSince(t0);
    }
    t0 = Clock::now();
    const RefinementResult joint = refinePose(obs, T_world_cur.inverse(), camera, config_.refinement);
    out.times.refine += msSince(t0);
    if (joint.inliers >= config_.odometry.min_static_inliers) {
      T_world_cur = joint.T_cur_ref.inverse();
      inliers = joint.inliers;
      out.position_sigma = positionStdDev(joint);
    } else {
      inliers = std::max(inliers, joint.inliers);
    }
  }
  out.num_inliers = inliers;
  // Enough inliers can still leave the pose undetermined: points on a narrow strip of one
  // wall under a narrow field of view let translation and rotation trade off, and the
  // estimate can be decimetres off with every residual small (measured in
  // doc/robustness.md: a walker covering all but a strip of the view). Lost, not tracked.
  const double max_sigma = config_.odometry.max_position_sigma;
  const bool determined = max_sigma <= 0 || out.position_sigma <= max_sigma;

  if (inliers >= config_.odometry.min_static_inliers && determined) {
    out.state = TrackingState::Tracking;
    lost_streak_ = 0;
    velocity_ = T_world_last_.inverse() * T_world_cur;
  } else {
    // Lost: keep predicting, re-anchor on a new keyframe when loss persists.
    T_world_cur = T_world_pred;
    out.state = TrackingState::Lost;
    if (inliers >= config_.odometry.min_static_inliers) {
      out.pose_undetermined = true;
      char reason[160];
      std::snprintf(reason, sizeof reason,
                    "pose not determined by its %d static inliers (position standard deviation %.2f m > %.2f)",
                    inliers, out.position_sigma, max_sigma);
      out.lost_reason = reason;
    } else {
      out.lost_reason = "only " + std::to_string(inliers) + " static inliers (of " +
                        std::to_string(primary_.motion.size()) + " matches with depth)";
    }
    ++lost_streak_;
    // The last velocity may be the one that lost tracking: extrapolate it less each frame.
    const Eigen::AngleAxisd half_turn(0.5 * Eigen::AngleAxisd(velocity_.linear()).angle(),
                                      Eigen::AngleAxisd(velocity_.linear()).axis());
    velocity_.linear() = half_turn.toRotationMatrix();
    velocity_.translation() *= 0.5;
  }
  out.T_world_camera = T_world_cur;
  if (frame_to_frame && config_.odometry.previous_frame_labels)
    labelAgainstPreviousFrame(cur, T_world_cur, out);
  // Only GMC's own decisions of this frame renew the memory, so remembered labels fade.
  for (size_t i = 0; i < cur.size(); ++i)
    if (fresh_dynamic_[i]) memory_[i] = config_.odometry.dynamic_memory_frames;
  previous_ = cur;
  previous_memory_ = memory_;
  T_world_previous_ = T_world_cur;

  // 5. Keyframe management (overlap judged against the current keyframe).
  const Isometry T_kf_cur = keyframe().T_world_kf.inverse() * T_world_cur;
  const bool far = T_kf_cur.translation().norm() > config_.odometry.keyframe_max_translation ||
                   rotationDeg(T_kf_cur) > config_.odometry.keyframe_max_rotation;
  if (out.state == TrackingState::Tracking) {
    if (keyframe().static_matches == 0) keyframe().static_matches = refined.inliers;
    const bool weak =
        refined.inliers < config_.odometry.keyframe_min_overlap * keyframe().static_matches;
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
