#include "gmc/vo/start_consensus.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace gmc::vo {

void StartConsensus::start(const std::vector<std::pair<int, Eigen::Vector3d>>& anchors) {
  stop();
  if (!options_.enabled) return;
  for (const auto& [id, world] : anchors) {
    anchor_of_[id] = static_cast<int>(anchor_id_.size());
    anchor_id_.push_back(id);
    anchor_world_.push_back(world);
  }
  rng_ = Xorshift64(seed_);
  active_ = anchor_id_.size() >= 3;
}

void StartConsensus::stop() {
  active_ = false;
  anchor_id_.clear();
  anchor_of_.clear();
  anchor_world_.clear();
  frames_.clear();
  slot_.clear();
}

void StartConsensus::add(const ConsensusFrame& frame) {
  if (!active_) return;
  ConsensusFrame kept = frame;
  kept.observations.clear();
  std::vector<int> slot(anchor_id_.size(), -1);
  for (const auto& [id, point] : frame.observations) {
    const auto it = anchor_of_.find(id);
    if (it == anchor_of_.end() || slot[static_cast<size_t>(it->second)] >= 0) continue;
    slot[static_cast<size_t>(it->second)] = static_cast<int>(kept.observations.size());
    kept.observations.emplace_back(it->second, point);
  }
  frames_.push_back(std::move(kept));
  slot_.push_back(std::move(slot));
  if (static_cast<int>(frames_.size()) >= options_.frames) active_ = false;
}

void StartConsensus::revise(const std::vector<Isometry>& T_world_camera) {
  for (size_t f = 0; f < frames_.size() && f < T_world_camera.size(); ++f) frames_[f].T_world_given = T_world_camera[f];
}

void StartConsensus::remap(const std::vector<int>& new_id) {
  anchor_of_.clear();
  for (size_t a = 0; a < anchor_id_.size(); ++a) {
    int& id = anchor_id_[a];
    id = id >= 0 && static_cast<size_t>(id) < new_id.size() ? new_id[static_cast<size_t>(id)] : -1;
    if (id >= 0) anchor_of_[id] = static_cast<int>(a);
  }
}

int StartConsensus::countInliers(size_t f, const Isometry& T, const InPlaceThreshold& threshold,
                                 const PinholeCamera* pixels, std::vector<int>* in) const {
  int n = 0;
  const Isometry T_camera_world = pixels ? Isometry(T.inverse()) : Isometry::Identity();
  const double max_px2 = options_.inlier_pixels * options_.inlier_pixels;
  for (const auto& [a, point] : frames_[f].observations) {
    const double thr = threshold.at(point.z());
    const Eigen::Vector3d& world = anchor_world_[static_cast<size_t>(a)];
    if (pixels) {
      // A pixel locates a point across the ray far better than its depth along it: 2 cm
      // sideways at 3 m is inside the 3-D threshold and 4 px off.
      const Eigen::Vector3d expected = T_camera_world * world;
      if (expected.z() <= 0 || std::abs(expected.z() - point.z()) >= thr ||
          (pixels->project(expected) - pixels->project(point)).squaredNorm() >= max_px2)
        continue;
    } else if ((world - T * point).squaredNorm() >= thr * thr) {
      continue;
    }
    ++n;
    if (in) in->push_back(a);
  }
  return n;
}

namespace {

/// world <- camera from the observations of `anchors` in one frame (false: fewer than `min_points`).
bool fitFrame(const std::vector<int>& anchors, const std::vector<int>& slot, const ConsensusFrame& frame,
              const std::vector<Eigen::Vector3d>& world, size_t min_points, Isometry& T) {
  std::vector<int> seen;
  for (int a : anchors)
    if (slot[static_cast<size_t>(a)] >= 0) seen.push_back(a);
  if (seen.size() < min_points) return false;
  Eigen::Matrix3Xd src(3, seen.size()), dst(3, seen.size());
  for (size_t k = 0; k < seen.size(); ++k) {
    src.col(static_cast<Eigen::Index>(k)) =
        frame.observations[static_cast<size_t>(slot[static_cast<size_t>(seen[k])])].second;
    dst.col(static_cast<Eigen::Index>(k)) = world[static_cast<size_t>(seen[k])];
  }
  return fitRigid(src, dst, T);
}

/// The same for exactly three anchors, without allocating (the sampling loop's fit).
bool fitSample(const std::array<int, 3>& sample, const std::vector<int>& slot, const ConsensusFrame& frame,
               const std::vector<Eigen::Vector3d>& world, Isometry& T) {
  Eigen::Matrix3d src, dst;
  for (int k = 0; k < 3; ++k) {
    const int a = sample[static_cast<size_t>(k)];
    const int ob = slot[static_cast<size_t>(a)];
    if (ob < 0) return false;
    src.col(k) = frame.observations[static_cast<size_t>(ob)].second;
    dst.col(k) = world[static_cast<size_t>(a)];
  }
  return fitRigid(src, dst, T);
}

}  // namespace

bool StartConsensus::plausibleStep(const Isometry& a, const Isometry& b, int frames) const {
  const Isometry step = a.inverse() * b;
  return step.translation().norm() <= options_.max_step * frames &&
         Eigen::AngleAxisd(step.linear()).angle() * 180.0 / M_PI <= options_.max_turn * frames;
}

bool StartConsensus::clearlyBetter(const ConsensusResult& result) const {
  if (!result.found) return false;
  const double score = result.score, given = result.given_score;
  if (score >= options_.min_gain * given) return true;
  // Inlier counts scatter like counts: a tenth more of a thousand is evidence, of thirty it is not.
  return options_.min_significance > 0 && score - given >= options_.min_significance * std::sqrt(score + given);
}

bool StartConsensus::mayReplace(const ConsensusResult& result, int min_inliers) const {
  if (!result.found || static_cast<int>(result.inliers_latest.size()) < min_inliers) return false;
  // The consensus corrects poses that a rigid body held, possibly the wrong one. Over lost
  // frames (the room too little seen to hold a pose) it has nothing to beat, and a walker
  // rigid over a few frames wins (doc/odometry.md, fifty-sixth round: off by default).
  return !options_.only_over_held_poses ||
         result.given_score >= static_cast<double>(min_inliers) * static_cast<double>(frames_.size());
}

void StartConsensus::polishPose(size_t f, const std::vector<int>& anchors, const PinholeCamera& camera,
                                Isometry& T) const {
  // The points were back-projected from their pixels: projecting them gives the pixels back.
  std::vector<PointObservation> obs;
  for (int a : anchors) {
    const int ob = slot_[f][static_cast<size_t>(a)];
    if (ob < 0) continue;
    const Eigen::Vector3d& point = frames_[f].observations[static_cast<size_t>(ob)].second;
    obs.push_back({anchor_world_[static_cast<size_t>(a)], camera.project(point), point.z(), 1.0});
  }
  if (obs.size() < 6) return;
  const RefinementResult refined = refinePose(obs, T.inverse(), camera, refinement_);
  if (2 * refined.inliers >= static_cast<int>(obs.size())) T = refined.T_cur_ref.inverse();
}

ConsensusResult StartConsensus::solve(const InPlaceThreshold& threshold, const PinholeCamera* camera) {
  const PinholeCamera* pixels = options_.inlier_pixels > 0 ? camera : nullptr;
  ConsensusResult result;
  const size_t n = frames_.size();
  if (static_cast<int>(n) < options_.min_frames || anchor_id_.size() < 3) return result;
  for (size_t f = 0; f < n; ++f)
    result.given_score += countInliers(f, frames_[f].T_world_given, threshold, pixels, nullptr);

  // Samples come from landmarks seen in at least half the frames: a set the frames share.
  std::vector<int> seen_in(anchor_id_.size(), 0), pool;
  for (const auto& slot : slot_)
    for (size_t a = 0; a < slot.size(); ++a) seen_in[a] += slot[a] >= 0;
  for (size_t a = 0; a < seen_in.size(); ++a)
    if (anchor_id_[a] >= 0 && 2 * seen_in[a] >= static_cast<int>(n)) pool.push_back(static_cast<int>(a));
  if (pool.size() < 3) return result;

  // A sample stops being scored once the observations left cannot lift it above the
  // K-th best (K = refit_samples: the best samples are settled on their members below).
  std::vector<int> left(n + 1, 0);
  for (size_t f = n; f-- > 0;) left[f] = left[f + 1] + static_cast<int>(frames_[f].observations.size());
  const size_t keep = static_cast<size_t>(std::max(1, options_.refit_samples));
  std::vector<std::pair<int, std::array<int, 3>>> best;  // (score, sample), best first
  for (int it = 0; it < options_.iterations; ++it) {
    std::array<int, 3> sample;
    for (int& a : sample) a = pool[rng_.next() % pool.size()];
    if (sample[0] == sample[1] || sample[0] == sample[2] || sample[1] == sample[2]) continue;
    const auto& w = anchor_world_;
    if ((w[sample[1]] - w[sample[0]]).cross(w[sample[2]] - w[sample[0]]).norm() < 1e-3) continue;
    const int bar = best.size() < keep ? -1 : best.back().first;
    int score = 0;
    Isometry before = Isometry::Identity();  // the previous frame's pose, when it had one
    bool chained = false;
    Isometry first_pose = Isometry::Identity();
    int first_frame = -1, last_frame = -1;
    for (size_t f = 0; f < n && score >= 0; ++f) {
      if (score + left[f] <= bar) {
        score = -1;
        break;
      }
      Isometry T;
      if (!fitSample(sample, slot_[f], frames_[f], anchor_world_, T)) {
        chained = false;
        continue;
      }
      if (!options_.sample_mean_step && chained && !plausibleStep(before, T)) score = -1;
      else score += countInliers(f, T, threshold, pixels, nullptr);
      if (first_frame < 0) first_pose = T, first_frame = static_cast<int>(f);
      last_frame = static_cast<int>(f);
      before = T;
      chained = true;
    }
    // Three far points pose a frame centimetres and degrees off; their mean step over
    // the frames is what tells a camera from a group that walks faster than one.
    if (options_.sample_mean_step && last_frame > first_frame &&
        !plausibleStep(first_pose, before, last_frame - first_frame))
      score = -1;
    if (score <= bar) continue;
    auto at = std::find_if(best.begin(), best.end(), [&](const auto& b) { return score > b.first; });
    best.insert(at, {score, sample});
    if (best.size() > keep) best.pop_back();
  }
  for (const auto& [score, sample] : best) {
    ConsensusResult settled = settle(std::vector<int>(sample.begin(), sample.end()), threshold, camera);
    settled.given_score = result.given_score;
    if (settled.found && (!result.found || settled.score > result.score)) result = std::move(settled);
  }
  return result;
}

ConsensusResult StartConsensus::settle(std::vector<int> seed, const InPlaceThreshold& threshold,
                                       const PinholeCamera* camera) const {
  const PinholeCamera* pixels = options_.inlier_pixels > 0 ? camera : nullptr;
  ConsensusResult result;
  const size_t n = frames_.size();
  // Membership from the seed's poses, then every frame refitted on the members it saw;
  // with refit_rounds > 1 the membership is judged again from the refitted poses.
  std::vector<Isometry> pose(n, Isometry::Identity());
  std::vector<std::uint8_t> posed(n, 0);
  size_t min_points = 3;
  std::vector<int> members;
  for (int round = 0; round < std::max(1, options_.refit_rounds); ++round) {
    // A frame that sees too few members to be refitted keeps its last round's pose.
    std::vector<int> inlier_in(anchor_id_.size(), 0), observed_in(anchor_id_.size(), 0);
    for (size_t f = 0; f < n; ++f) {
      if (!fitFrame(seed, slot_[f], frames_[f], anchor_world_, min_points, pose[f])) continue;
      posed[f] = 1;
      std::vector<int> in;
      countInliers(f, pose[f], threshold, pixels, &in);
      for (int a : in) ++inlier_in[static_cast<size_t>(a)];
      for (const auto& ob : frames_[f].observations) ++observed_in[static_cast<size_t>(ob.first)];
    }
    members.clear();
    result.consensus.clear();
    result.outside.clear();
    for (size_t a = 0; a < anchor_id_.size(); ++a) {
      if (anchor_id_[a] < 0 || observed_in[a] == 0) continue;
      if (inlier_in[a] > 0 && inlier_in[a] >= options_.min_share * observed_in[a]) {
        members.push_back(static_cast<int>(a));
        result.consensus.emplace_back(anchor_id_[a], anchor_world_[a]);
      } else if (observed_in[a] >= 2) {
        result.outside.push_back(anchor_id_[a]);
      }
    }
    seed = members;
    min_points = 6;
  }
  result.score = 0;
  for (size_t f = 0; f < n; ++f) {
    Isometry T = pose[f];
    if (fitFrame(members, slot_[f], frames_[f], anchor_world_, 6, T)) {
      // Members that moved in this frame alone (a walker's corner that stood still so far) out.
      std::vector<int> in;
      countInliers(f, T, threshold, pixels, &in);
      std::sort(in.begin(), in.end());
      std::vector<int> kept;
      std::set_intersection(members.begin(), members.end(), in.begin(), in.end(), std::back_inserter(kept));
      Isometry refit = T;
      if (fitFrame(kept, slot_[f], frames_[f], anchor_world_, 6, refit)) T = refit;
      if (options_.polish && camera) polishPose(f, kept, *camera, T);
      posed[f] = 1;
    }
    if (!posed[f]) return result;  // a frame no pose explains: nothing to revise it with
    pose[f] = T;
    std::vector<int> in;
    result.score += countInliers(f, T, threshold, pixels, f + 1 == n ? &in : nullptr);
    for (int a : in) result.inliers_latest.push_back(anchor_id_[static_cast<size_t>(a)]);
  }
  // The newest step becomes the velocity: it must be a camera's.
  if (n >= 2 && !plausibleStep(pose[n - 2], pose[n - 1])) return result;
  result.T_world_camera = pose;
  result.found = true;
  return result;
}

}  // namespace gmc::vo
