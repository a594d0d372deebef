#include "gmc/vo/odometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace gmc::vo {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The share of a frame's labelled matches that GMC labelled dynamic.
double dynamicShare(const FrameTracking& t) {
  return static_cast<double>(t.num_dynamic) / std::max(1, t.num_static + t.num_dynamic);
}

/// Median depth of the keypoints that held the frame's pose (0 when none did).
double medianPoseDepth(const features::FeatureSet& cur, const FrameTracking& t) {
  std::vector<double> z;
  for (size_t i = 0; i < cur.size(); ++i)
    if (t.keypoint_in_pose[i]) z.push_back(cur.points[i].z());
  if (z.empty()) return 0;
  std::nth_element(z.begin(), z.begin() + static_cast<long>(z.size() / 2), z.end());
  return z[z.size() / 2];
}

/// After a cull that compacted the map (remap: old id -> new id, -1 = dropped): keeps the
/// items whose landmark survived, renumbered; `landmark_of` names an item's landmark id.
template <class T, class LandmarkOf>
void renumberLandmarks(std::vector<T>& items, const std::vector<int>& remap, LandmarkOf landmark_of) {
  std::vector<T> kept;
  kept.reserve(items.size());
  for (T item : items) {
    int& id = landmark_of(item);
    id = remap[static_cast<size_t>(id)];
    if (id >= 0) kept.push_back(std::move(item));
  }
  items.swap(kept);
}

/// The GMC input of one feature match: current pixel, reference and current 3-D points.
MotionMatch motionMatch(const features::FeatureSet& ref, const features::FeatureSet& cur,
                        const features::FeatureMatch& m) {
  const auto& kp = cur.keypoints[static_cast<size_t>(m.cur)].pt;
  return {Eigen::Vector2f(kp.x, kp.y), ref.points[static_cast<size_t>(m.ref)],
          cur.points[static_cast<size_t>(m.cur)]};
}

/// Free space is dynamic evidence: none without GMC (the paper's baseline run).
FreeSpaceOptions freeSpaceOptions(const OdometryConfig& config) {
  FreeSpaceOptions o = config.free_space;
  o.enabled = o.enabled && config.gmc.enabled;
  return o;
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
    : config_(config),
      frontend_(config.frontend, config.gms),
      background_(config.background, config.gmc),
      keyframe_policy_(config.keyframes),
      window_(config.window, config.refinement),
      map_(config.local_map),
      rejoin_(config.rejoin, config.refinement,
              config.background.inPlace()),
      consensus_(config.start_consensus, config.refinement),
      hindsight_(config.hindsight, config.refinement, config.background.inPlace()),
      gmc_previous_(config.gmc),
      smoother_(config.odometry.smoothing_frames, config.odometry.smoothing_break, config.odometry.smoothing_edges),
      tracks_(config.odometry.track_frames),
      free_space_(freeSpaceOptions(config)),
      depth_alignment_(config.depth_alignment) {
  const auto seed = static_cast<std::uint64_t>(config.odometry.random_seed);
  background_.reseed(seed);
  rejoin_.reseed(seed);
  consensus_.reseed(seed);
  hindsight_.reseed(seed);
}

Isometry RgbdOdometry::predictPose() const {
  return config_.odometry.use_motion_model && !standStillWhileLost() ? T_world_last_ * velocity_ : T_world_last_;
}

bool RgbdOdometry::standStillWhileLost() const {
  // A lost frame extrapolates the last velocity, halved each frame. Before any landmark
  // has static evidence, and with walkers in view, that velocity may be one the estimate
  // learnt by following a walker (301_460's start drifted 6 cm on while lost); with no
  // evidence to tell, standing still is the safer guess for a hand-held camera. Tracked
  // frames keep extrapolating: a still prediction makes a group walking in step with the
  // camera look like background (doc/odometry.md, seventh round).
  return lost_streak_ > 0 && last_tracked_static_landmarks_ < config_.background.min_static_landmarks &&
         last_tracked_dynamic_share_ >= config_.odometry.young_map_lost_still_share;
}

// ------------------------------------------------------------------ the recipe
FrameTracking RgbdOdometry::process(const cv::Mat& gray, const cv::Mat& depth, double depth_units,
                                    const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic) {
  const auto t_start = Clock::now();
  FrameTracking out;
  const FrameDepth frame_depth{depth, depth_units, known_dynamic};
  features::FeatureSet cur = extractFeatures(gray, frame_depth, camera, stamp, out);
  if (!initialized_) {
    initialize(std::move(cur), camera, stamp, out);
    out.times.total = msSince(t_start);
    return out;
  }
  // 1. Predict, and match the frame to the previous one (labels) and to the map (pose).
  const Isometry T_world_pred = predictPose();
  matchFrame(cur, T_world_pred, camera, stamp, out);
  // 2. The background: motion hypotheses judged by GMC and the landmarks' static evidence.
  selectBackground(cur, stamp, out);
  // 3. Refinement on the static matches (and the room's depth), 4. tracked or lost.
  const bool after_lost_frames = lost_streak_ > 0;
  poseFrame(cur, frame_depth, camera, stamp, T_world_pred, out);
  // 5. Labels for the mask from the previous frame; dynamic memory.
  labelForMask(cur, out);
  // 6. Static evidence, keyframes, windowed optimisation.
  updateMapAndWindow(cur, frame_depth, camera, stamp, after_lost_frames, out);
  // 7. The trajectory's revisions, and what the next frame starts from.
  finishFrame(std::move(cur), camera, stamp, out);
  out.times.total = msSince(t_start);
  return out;
}

features::FeatureSet RgbdOdometry::extractFeatures(const cv::Mat& gray, const FrameDepth& frame_depth,
                                                   const PinholeCamera& camera, double stamp, FrameTracking& out) {
  const auto t0 = Clock::now();
  maskable_.clear();
  out.stamp = stamp;
  out.frame_number = ++frame_number_;
  features::FeatureSet cur = frontend_.extract(gray, frame_depth.depth, frame_depth.depth_units, camera);
  out.num_features = static_cast<int>(cur.size());
  markKnownDynamic(cur, frame_depth.known_dynamic);
  for (const auto& kp : cur.keypoints) out.keypoints.push_back(kp.pt);
  out.keypoint_labels.assign(cur.size(), MotionLabel::Undecided);
  out.keypoint_in_pose.assign(cur.size(), 0);
  out.times.frontend = msSince(t0);
  return cur;
}

void RgbdOdometry::matchFrame(const features::FeatureSet& cur, const Isometry& T_world_pred,
                              const PinholeCamera& camera, double stamp, FrameTracking& out) {
  const auto t0 = Clock::now();
  matchPreviousFrame(cur, T_world_pred, camera);
  matchToMap(cur, T_world_pred, camera, stamp, track_);
  out.num_matches = track_.num_matches;
  out.landmarks_in_view = static_cast<int>(track_.view.ids.size());
  countRefound(out);
  out.times.frontend += msSince(t0);
}

void RgbdOdometry::selectBackground(const features::FeatureSet& cur, double stamp, FrameTracking& out) {
  const auto t0 = Clock::now();
  // The prior widens with every lost frame: their poses are guesses.
  SelectionContext context;
  context.frame_gap = (stamp - last_stamp_) * (1 + lost_streak_);
  context.velocity_known = velocity_known_;
  context.young_map = stamp - map_start_stamp_ < config_.background.young_map_seconds;
  context.image_width = cur.width;
  context.image_height = cur.height;
  background_.select(track_.motion, track_.trust, context, choice_);
  out.gmc = choice_.gmc;
  out.background_source = choice_.source;
  out.static_landmarks_matched = choice_.established_matched;
  out.static_landmarks_agreeing = choice_.established_agreeing;
  out.times.guess += msSince(t0);
}

void RgbdOdometry::poseFrame(const features::FeatureSet& cur, const FrameDepth& frame_depth,
                             const PinholeCamera& camera, double stamp, const Isometry& T_world_pred,
                             FrameTracking& out) {
  auto t0 = Clock::now();
  const Isometry T_world_guess = T_world_pred * choice_.T_ref_cur;
  sampleDepthForPose(cur, frame_depth.depth, frame_depth.depth_units, camera, stamp, frame_depth.known_dynamic,
                     T_world_guess);
  const RefinementResult refined = refineOnBackground(T_world_guess, T_world_pred, stamp - last_stamp_, camera, out);
  out.times.refine += msSince(t0);
  decideTracking(refined, orthonormalized(refined.T_cur_ref).inverse(), choice_.trustworthy, T_world_pred, out);
  revertUnheldStart(out);
  t0 = Clock::now();
  judgeStart(stamp, camera, out);  // a young map's frames judged together: with the hypotheses' time
  out.times.guess += msSince(t0);
  if (out.state == TrackingState::Tracking && rejoin_.active()) tryRejoin(cur, camera, stamp, out);
}

void RgbdOdometry::labelForMask(const features::FeatureSet& cur, FrameTracking& out) {
  if (!previous_matches_.empty() && config_.odometry.previous_frame_labels)
    labelAgainstPreviousFrame(cur, out.T_world_camera, out);
  for (size_t i = 0; i < cur.size(); ++i)
    if (fresh_dynamic_[i]) memory_[i] = config_.odometry.dynamic_memory_frames;
}

void RgbdOdometry::updateMapAndWindow(const features::FeatureSet& cur, const FrameDepth& frame_depth,
                                      const PinholeCamera& camera, double stamp, bool after_lost_frames,
                                      FrameTracking& out) {
  rememberTrackedFrame(out);
  // Re-posed frames (a start consensus, a rejoin) do not continue the poses before them.
  tracks_.extend(cur, previous_matches_, out.T_world_camera,
                 out.state == TrackingState::Tracking && !out.start_consensus && !out.rejoined);
  const auto t0 = Clock::now();
  updateMap(cur, camera, stamp, out);
  if (out.new_keyframe && out.state == TrackingState::Tracking && config_.window.keyframes > 1)
    out.T_world_camera = orthonormalized(optimizeWindow(camera, stamp, out));
  // The velocity of a tracked frame, once its pose is final. After lost frames the last
  // pose was a prediction: the step from it corrects the prediction, it is no velocity.
  if (out.state == TrackingState::Tracking && !after_lost_frames) {
    velocity_ = T_world_last_.inverse() * out.T_world_camera;
    velocity_known_ = true;
  }
  out.map_landmarks = static_cast<int>(map_.numAlive());
  if (out.state == TrackingState::Tracking) {
    free_space_.push(frame_depth.depth, frame_depth.depth_units, out.T_world_camera, stamp);
    keepDepthReference(out, frame_depth.depth, frame_depth.depth_units, camera, stamp, frame_depth.known_dynamic);
  }
  out.times.window = msSince(t0);
}

void RgbdOdometry::finishFrame(features::FeatureSet&& cur, const PinholeCamera& camera, double stamp,
                               FrameTracking& out) {
  bridgeLostFrames(out);
  smoothTrajectory(out);
  if (hindsight_.options().enabled) {
    previous_ = cur;  // the descriptors are shared; the hindsight keeps the frame
    reviseInHindsight(std::move(cur), camera, out);
  } else {
    previous_ = std::move(cur);
  }
  previous_memory_ = memory_;
  T_world_previous_ = out.T_world_camera;
  T_world_last_ = out.T_world_camera;
  last_stamp_ = stamp;
}

void RgbdOdometry::distrustMaskedLandmarks(const cv::Mat& mask) {
  // A walker's untextured parts and its corners that GMC left undecided are in the mask
  // (free space, depth-continuous growth from its dynamic keypoints) though not labelled.
  for (const auto& [id, kp] : maskable_) {
    const int u = static_cast<int>(std::lround(kp.x)), v = static_cast<int>(std::lround(kp.y));
    if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows || mask.at<std::uint8_t>(v, u) == 0) continue;
    map_.distrust(id, last_stamp_);  // the keyframe's stamp: process() ends with it
  }
  maskable_.clear();
  depth_alignment_.maskReference(mask, last_stamp_);  // only when the reference is this frame
}

// ------------------------------------------------------------------ steps
void RgbdOdometry::initialize(features::FeatureSet&& cur, const PinholeCamera& camera, double stamp,
                              FrameTracking& out) {
  out.state = TrackingState::Initialized;
  out.new_keyframe = true;
  map_.clear();
  window_keyframes_.clear();
  pose_landmarks_.clear();
  keyframe_count_ = 0;
  track_ = MapTrack{};
  track_.matched.assign(cur.size(), 0);
  keyframe_policy_.reset(Isometry::Identity());
  addKeyframe(cur, camera, stamp, out);
  startConsensus(cur, stamp);
  hindsight_.reset();
  hindsight_.add({frame_number_, stamp, cur, Isometry::Identity(), {}, false}, map_, Isometry::Identity(), camera,
                 frontend_, config_.frontend.max_depth);
  out.map_landmarks = static_cast<int>(map_.numAlive());
  previous_ = std::move(cur);
  previous_memory_.assign(previous_.size(), 0);
  T_world_previous_ = T_world_last_ = velocity_ = Isometry::Identity();
  velocity_known_ = false;
  map_start_stamp_ = last_stamp_ = stamp;
  last_tracked_ = {frame_number_, stamp, Isometry::Identity()};
  lost_frames_.clear();
  records_.clear();
  map_id_ = 0;
  lost_streak_ = 0;
  last_tracked_static_landmarks_ = 0;
  last_tracked_dynamic_share_ = 0;
  initialized_ = true;
}

void RgbdOdometry::bridge(const std::vector<std::pair<long, double>>& lost, const RevisedPose& from,
                          const RevisedPose& to, FrameTracking& out) {
  // The camera went from one pose to the other: the lost frames lie on that path (at
  // constant velocity between the two), not where they were guessed.
  const size_t first = out.revised.size();
  bridgePoses(lost, from, to, out.revised);
  for (size_t k = first; k < out.revised.size(); ++k) records_.revise(out.revised[k]);
}

void RgbdOdometry::startConsensus(const features::FeatureSet& cur, double stamp) {
  std::vector<std::pair<int, Eigen::Vector3d>> anchors;
  for (size_t id = 0; id < map_.size(); ++id)
    if (map_[static_cast<int>(id)].alive) anchors.emplace_back(static_cast<int>(id), map_[static_cast<int>(id)].position);
  consensus_.start(anchors);
  consensus_start_ = {frame_number_, stamp, window_keyframes_.back().T_world_kf};
  if (config_.rejoin.young_map_anchor) map_anchor_features_ = cur;
  map_frames_.clear();
  start_frames_.clear();
  map_first_keyframe_ = keyframe_count_ - 1;
}

void RgbdOdometry::judgeStart(double stamp, const PinholeCamera& camera, FrameTracking& out) {
  if (!consensus_.active()) return;
  ConsensusFrame frame;
  frame.frame_number = frame_number_;
  frame.stamp = stamp;
  frame.T_world_given = out.T_world_camera;
  for (size_t k = 0; k < track_.motion.size(); ++k)
    frame.observations.emplace_back(track_.landmark[k], track_.motion[k].point_cur);
  consensus_.add(frame);
  const ConsensusResult consensus = consensus_.solve(config_.background.inPlace(), &camera);
  if (consensus_.clearlyBetter(consensus) && consensus_.mayReplace(consensus, config_.odometry.min_static_inliers))
    adoptConsensus(consensus, stamp, out);
}

void RgbdOdometry::adoptConsensus(const ConsensusResult& consensus, double stamp, FrameTracking& out) {
  // The earlier frames lie on the path from the first keyframe to this frame, as lost
  // frames are bridged: a frame that saw a handful of the consensus' landmarks is fitted
  // centimetres off (synchronous seed 1: up to 10 cm fitted, 2.7 cm bridged).
  const auto& frames = consensus_.frames();
  const size_t n = frames.size();
  out.T_world_camera = orthonormalized(consensus.T_world_camera.back());
  std::vector<std::pair<long, double>> earlier;
  for (size_t f = 0; f + 1 < n; ++f) earlier.push_back({frames[f].frame_number, frames[f].stamp});
  const size_t first_revised = out.revised.size();
  bridge(earlier, consensus_start_, {frame_number_, stamp, out.T_world_camera}, out);
  std::vector<Isometry> given;
  for (size_t k = first_revised; k < out.revised.size(); ++k) given.push_back(out.revised[k].T_world_camera);
  given.push_back(out.T_world_camera);
  consensus_.revise(given);
  out.num_inliers = static_cast<int>(consensus.inliers_latest.size());
  if (out.state == TrackingState::Lost) {
    out.state = TrackingState::Tracking;
    out.lost_reason.clear();
    out.background_untrusted = out.pose_undetermined = false;
  }
  out.start_consensus = true;
  lost_streak_ = 0;
  // Every earlier frame of this map is revised: none is left to bridge, and the velocity
  // is the last bridged step.
  lost_frames_.clear();
  const Isometry& T_world_before = out.revised.back().T_world_camera;
  last_tracked_ = out.revised.back();
  T_world_last_ = T_world_previous_ = T_world_before;
  velocity_ = T_world_before.inverse() * out.T_world_camera;
  velocity_known_ = true;
  // The landmarks: the consensus is where the first keyframe put them; the rest moved.
  map_.judgeStart(consensus.consensus, consensus.outside, map_first_keyframe_, map_start_stamp_, stamp);
  keepFirstKeyframeOnly();
  keyframe_policy_.reset(window_keyframes_.front().T_world_kf);
  pose_landmarks_ = consensus.inliers_latest;
  start_frames_.clear();
}

void RgbdOdometry::keepFirstKeyframeOnly() {
  // Only when the window still holds the map's first keyframe: every keyframe of this map is in it.
  const int map_keyframes = keyframe_count_ - map_first_keyframe_;
  if (window_keyframes_.size() > 1 && map_keyframes <= static_cast<int>(window_keyframes_.size()))
    window_keyframes_.erase(window_keyframes_.begin() + 1, window_keyframes_.end());
}

void RgbdOdometry::revertUnheldStart(FrameTracking& out) {
  // A map lost a few frames after its start, before any landmark gained evidence and with
  // walkers in view (standStillWhileLost), was never held by the room: its tracked frames
  // followed one frame's clusters, and on a crowd standing still is never worse than
  // following a walker. They become lost frames at the start pose, bridged if the map
  // holds again.
  const int limit = config_.odometry.unheld_start_frames;
  if (limit <= 0) return;
  const bool young = frame_number_ - consensus_start_.frame_number <= limit;
  if (out.state == TrackingState::Tracking) {
    if (young && lost_frames_.empty() &&
        (!start_frames_.empty() || last_tracked_.frame_number == consensus_start_.frame_number))
      start_frames_.push_back({frame_number_, out.stamp});
    return;
  }
  if (out.state != TrackingState::Lost || lost_streak_ != 1 || !young || start_frames_.empty() ||
      !standStillWhileLost())
    return;
  const Isometry& anchor = consensus_start_.T_world_camera;
  bridge(start_frames_, consensus_start_, {frame_number_, out.stamp, anchor}, out);  // all at the start pose
  std::vector<Isometry> given(consensus_.frames().size(), anchor);
  consensus_.revise(given);
  lost_frames_ = start_frames_;
  start_frames_.clear();
  last_tracked_ = consensus_start_;
  out.T_world_camera = anchor;
  velocity_ = Isometry::Identity();
  map_.dropKeyframesAfter(map_first_keyframe_);
  keepFirstKeyframeOnly();
  keyframe_policy_.returnTo(window_keyframes_.front().T_world_kf);
}

void RgbdOdometry::bridgeLostFrames(FrameTracking& out) {
  // A lost frame's pose is a guess given out live. Once a frame is measured on the same
  // map again, the camera went from the last tracked pose to this one (revisions are in
  // order: a later one for the same frame supersedes an earlier one).
  const RevisedPose current{frame_number_, out.stamp, out.T_world_camera};
  // A map's frames after its first, to bridge them if it is left young (startNewMap); at
  // most kMaxYoungMapFrames: memory stays bounded, and a map that old is not treated so.
  if (frame_number_ != consensus_start_.frame_number && map_frames_.size() <= kMaxYoungMapFrames)
    map_frames_.push_back({frame_number_, out.stamp});
  // Frames are kept only while some map may still be rejoined.
  if (!rejoin_.active()) records_.clear();
  if (out.state == TrackingState::Lost) {
    lost_frames_.push_back({frame_number_, out.stamp});
    records_.add(current);
    return;
  }
  if (out.state == TrackingState::Tracking && config_.odometry.revise_lost && !lost_frames_.empty())
    bridge(lost_frames_, last_tracked_, current, out);
  // A re-anchored frame starts from a guess: the lost frames before it are bridged only
  // once its map is joined with the one they left (MapRecords, recorded at the re-anchor).
  map_restarted_ = false;
  lost_frames_.clear();
  last_tracked_ = current;
  records_.add(current);
}

void RgbdOdometry::smoothTrajectory(FrameTracking& out) {
  // Revised otherwise (bridged lost frames, a start consensus, a rejoin), the poses of the
  // run so far are not the ones given out: a new run starts with this frame.
  // A lost frame ends the run with its poses standing: its last frames are fitted too.
  std::vector<RevisedPose> smoothed;
  if (!out.revised.empty() || out.rejoined || out.start_consensus)
    smoother_.reset();
  else if (out.state != TrackingState::Tracking)
    smoothed = smoother_.endRun();
  if (out.state == TrackingState::Tracking) smoothed = smoother_.add({frame_number_, out.stamp, out.T_world_camera});
  for (const RevisedPose& revision : smoothed) {
    out.revised.push_back(revision);
    records_.revise(revision);
  }
}

std::vector<RevisedPose> RgbdOdometry::finish() {
  std::vector<RevisedPose> last = smoother_.endRun();
  for (const RevisedPose& revision : last) records_.revise(revision);
  return last;
}

void RgbdOdometry::reviseInHindsight(features::FeatureSet&& cur, const PinholeCamera& camera, FrameTracking& out) {
  // A frame that moved the world frame (a new map, a start consensus, a rejoin) ends what
  // can be compared with today's landmarks.
  const bool posed = out.state == TrackingState::Tracking || out.state == TrackingState::Lost;
  if (!posed || out.start_consensus || out.rejoined) {
    hindsight_.reset();
    return;
  }
  HindsightFrame frame{frame_number_, out.stamp, std::move(cur), out.T_world_camera, pose_landmarks_,
                       out.state == TrackingState::Lost};
  for (const RevisedPose& revision : hindsight_.add(std::move(frame), map_, out.T_world_camera, camera, frontend_,
                                                    config_.frontend.max_depth)) {
    out.revised.push_back(revision);
    records_.revise(revision);
  }
}

void RgbdOdometry::countRefound(FrameTracking& out) const {
  // Each one missed here is re-found later or replaced at the next keyframe by a landmark
  // carrying that keyframe's pose error (doc/odometry.md, "Seventh round").
  std::vector<std::uint8_t> matched(map_.size(), 0);
  for (int id : track_.landmark) matched[static_cast<size_t>(id)] = 1;
  for (int id : pose_landmarks_) {
    if (!map_[id].alive) continue;
    ++out.landmarks_to_refind;
    out.landmarks_refound += matched[static_cast<size_t>(id)];
  }
}

void RgbdOdometry::rememberTrackedFrame(const FrameTracking& out) {
  // Taken before the map update: the ids are this frame's (a keyframe's cull may renumber
  // them, addKeyframe then renumbers these too).
  pose_landmarks_.clear();
  if (out.state != TrackingState::Tracking) return;
  last_tracked_static_landmarks_ = out.static_landmarks_matched;
  last_tracked_dynamic_share_ = dynamicShare(out);
  for (size_t k = 0; k < track_.motion.size(); ++k)
    if (choice_.gmc.labels[k] == MotionLabel::Static && track_.trust.weight[k] > 0)
      pose_landmarks_.push_back(track_.landmark[k]);
}

void RgbdOdometry::markKnownDynamic(const features::FeatureSet& cur, const cv::Mat& known_dynamic) {
  known_dynamic_.assign(cur.size(), 0);
  if (known_dynamic.empty()) return;
  if (known_dynamic.type() != CV_8UC1 || known_dynamic.cols != cur.width || known_dynamic.rows != cur.height)
    throw std::invalid_argument("known dynamic mask must be CV_8UC1 of the image's size");
  // A corner on an object's outline belongs to it or to what is behind: 2 px of margin
  // (the generator's masks end at the silhouette; a segmenter's are no sharper).
  constexpr int kMargin = 2;
  for (size_t i = 0; i < cur.size(); ++i) {
    const int u = static_cast<int>(std::lround(cur.keypoints[i].pt.x));
    const int v = static_cast<int>(std::lround(cur.keypoints[i].pt.y));
    for (int y = std::max(0, v - kMargin); y <= std::min(known_dynamic.rows - 1, v + kMargin) && !known_dynamic_[i]; ++y)
      for (int x = std::max(0, u - kMargin); x <= std::min(known_dynamic.cols - 1, u + kMargin); ++x)
        if (known_dynamic.at<std::uint8_t>(y, x)) {
          known_dynamic_[i] = 1;
          break;
        }
  }
}

void RgbdOdometry::matchPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_pred,
                                      const PinholeCamera& camera) {
  // Frame-to-frame matches (guided by the prediction) carry remembered dynamic labels
  // forward and let GMC label walkers too fast to match to the map.
  previous_matches_.clear();
  memory_.assign(cur.size(), 0);
  fresh_dynamic_.assign(cur.size(), 0);
  const bool wanted = config_.gmc.enabled && previous_.size() > 0 &&
                      (config_.odometry.previous_frame_labels || config_.odometry.dynamic_memory_frames > 0);
  if (!wanted) return;
  const Isometry T_prev_pred = T_world_previous_.inverse() * T_world_pred;
  previous_matches_ = frontend_.filterGms(
      previous_, cur,
      frontend_.matchGuided(previous_, cur, T_prev_pred.inverse(), camera, config_.frontend.match_radius));
  for (const auto& m : previous_matches_)
    if (previous_memory_[static_cast<size_t>(m.ref)] > 0)
      memory_[static_cast<size_t>(m.cur)] = previous_memory_[static_cast<size_t>(m.ref)] - 1;
}

void RgbdOdometry::matchToMap(const features::FeatureSet& cur, const Isometry& T_world_pred,
                              const PinholeCamera& camera, double stamp, MapTrack& track) const {
  map_.view(T_world_pred, camera, config_.frontend.max_depth, track.view);
  const features::FeatureSet& ref = track.view.set;
  const Isometry identity = Isometry::Identity();  // ref points are in the predicted frame
  auto matches = frontend_.matchGuided(ref, cur, identity, camera, config_.frontend.match_radius);
  if (static_cast<int>(matches.size()) < config_.odometry.min_matches)
    matches = frontend_.matchGuided(ref, cur, identity, camera, config_.odometry.wide_match_radius);
  if (static_cast<int>(matches.size()) < config_.odometry.min_matches) matches = frontend_.matchExhaustive(ref, cur);
  if (config_.odometry.relocalize_static && lost_streak_ > 0)
    addStaticLandmarkMatches(ref, cur, stamp, track.view.ids, matches);
  matches = frontend_.filterGms(ref, cur, matches);
  track.num_matches = static_cast<int>(matches.size());

  track.motion.clear();
  track.cur_index.clear();
  track.landmark.clear();
  track.trust.weight.clear();
  track.trust.established.clear();
  track.trust.known_dynamic.clear();
  track.matched.assign(cur.size(), 0);
  for (const auto& m : matches) {
    track.matched[static_cast<size_t>(m.cur)] = 1;
    if (!cur.hasDepth(m.cur)) continue;
    const int id = track.view.ids[static_cast<size_t>(m.ref)];
    track.motion.push_back(motionMatch(ref, cur, m));
    track.cur_index.push_back(m.cur);
    track.landmark.push_back(id);
    // A keypoint remembered as a walker, or known to lie on one, is not trusted whatever
    // its landmark says.
    const bool known = known_dynamic_[static_cast<size_t>(m.cur)] || map_[id].known_dynamic;
    const bool distrusted = known || memory_[static_cast<size_t>(m.cur)] > 0;
    track.trust.weight.push_back(distrusted ? 0.0 : map_.weight(id, stamp));
    track.trust.established.push_back(!distrusted && map_.evidence(id, stamp) == Evidence::Static);
    track.trust.known_dynamic.push_back(known);
  }
}

void RgbdOdometry::addStaticLandmarkMatches(const features::FeatureSet& ref, const features::FeatureSet& cur,
                                            double stamp, const std::vector<int>& ids,
                                            std::vector<features::FeatureMatch>& matches) const {
  // After a lost frame the prediction has drifted off the camera and guided matching
  // finds mostly what moved with it. The landmarks with static evidence (the few that
  // held the pose for seconds) are searched over the whole image as well: cheap (tens
  // to hundreds of them) and independent of the prediction.
  features::FeatureSet established;
  std::vector<int> index;
  established.width = ref.width;
  established.height = ref.height;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (map_.evidence(ids[i], stamp) != Evidence::Static) continue;
    index.push_back(static_cast<int>(i));
    established.keypoints.push_back(ref.keypoints[i]);
    established.points.push_back(ref.points[i]);
  }
  if (index.empty()) return;
  established.descriptors.create(static_cast<int>(index.size()), 32, CV_8UC1);
  for (size_t k = 0; k < index.size(); ++k)
    ref.descriptors.row(index[k]).copyTo(established.descriptors.row(static_cast<int>(k)));
  std::vector<std::uint8_t> ref_used(ref.size(), 0), cur_used(cur.size(), 0);
  for (const auto& m : matches) ref_used[static_cast<size_t>(m.ref)] = cur_used[static_cast<size_t>(m.cur)] = 1;
  for (auto m : frontend_.matchExhaustive(established, cur)) {
    m.ref = index[static_cast<size_t>(m.ref)];
    if (ref_used[static_cast<size_t>(m.ref)] || cur_used[static_cast<size_t>(m.cur)]) continue;
    matches.push_back(m);
  }
}

RefinementResult RgbdOdometry::refineOnBackground(const Isometry& T_world_guess, const Isometry& T_world_pred,
                                                  double frame_gap, const PinholeCamera& camera, FrameTracking& out) {
  std::vector<PointObservation> obs;
  std::vector<size_t> obs_match;  // the match of each observation (map_matches)
  out.num_static = out.num_dynamic = 0;
  double max_weight = 0;
  for (size_t k = 0; k < track_.motion.size(); ++k) {
    const size_t cur_index = static_cast<size_t>(track_.cur_index[k]);
    MotionLabel& label = out.keypoint_labels[cur_index];
    label = choice_.gmc.labels[k];
    if (label == MotionLabel::Dynamic) {
      ++out.num_dynamic;
      fresh_dynamic_[cur_index] = 1;
      continue;
    }
    if (label != MotionLabel::Static) continue;
    ++out.num_static;
    // A landmark seen moving (or a remembered walker) stays out of the pose even when
    // it stands still in this frame; its label stays GMC's (a depth-edge corner that
    // flipped is background for the mask).
    if (track_.trust.weight[k] <= 0) continue;
    if (!choice_.inlier.empty() && !choice_.inlier[k]) continue;  // a young map: the chosen motion's inliers
    const auto& m = track_.motion[k];
    out.keypoint_in_pose[cur_index] = 1;
    obs_match.push_back(k);
    obs.push_back({map_[track_.landmark[k]].position, m.pixel.cast<double>(), m.point_cur.z(),
                   track_.trust.weight[k]});
    max_weight = std::max(max_weight, track_.trust.weight[k]);
  }
  out.map_matches.clear();
  out.map_matches.reserve(track_.motion.size());
  for (size_t k = 0; k < track_.motion.size(); ++k) {
    const int keypoint = track_.cur_index[k];
    const Landmark& l = map_[track_.landmark[k]];
    out.map_matches.push_back({keypoint, track_.motion[k].point_cur, l.origin_point, l.origin_stamp,
                               choice_.gmc.labels[k], track_.trust.established[k] != 0,
                               out.keypoint_in_pose[static_cast<size_t>(keypoint)] != 0, false});
  }
  // Relative trust: young landmarks count less only next to landmarks with evidence.
  for (auto& o : obs) o.weight /= max_weight;
  RefinementResult refined =
      refinePose(obs, T_world_guess.inverse(), camera, config_.refinement, motionPrior(T_world_pred, frame_gap),
                 depth_alignment_.currentSize() > 0 ? &depth_alignment_ : nullptr);
  for (size_t j = 0; j < refined.inlier_flags.size(); ++j)
    out.map_matches[obs_match[j]].pose_inlier = refined.inlier_flags[j] != 0;
  return refined;
}

void RgbdOdometry::sampleDepthForPose(const features::FeatureSet& cur, const cv::Mat& depth, double depth_units,
                                      const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic,
                                      const Isometry& T_world_guess) {
  if (!depth_alignment_.options().enabled) return;
  // Pixels near the frame's walkers (GMC's dynamic matches, landmarks seen moving,
  // remembered walkers) stay out of the dense term.
  std::vector<cv::Point2f> dynamic;
  for (size_t k = 0; k < track_.motion.size(); ++k) {
    const auto i = static_cast<size_t>(track_.cur_index[k]);
    if (choice_.gmc.labels[k] == MotionLabel::Dynamic || track_.trust.weight[k] <= 0 || memory_[i] > 0)
      dynamic.push_back(cur.keypoints[i].pt);
  }
  depth_alignment_.setCurrent(depth, depth_units, camera, stamp, dynamic, known_dynamic);
  depth_alignment_.keepAgreeing(T_world_guess.inverse(), camera, config_.refinement);
}

void RgbdOdometry::keepDepthReference(const FrameTracking& out, const cv::Mat& depth, double depth_units,
                                      const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic) {
  const auto& options = depth_alignment_.options();
  if (!options.enabled || (options.keyframe_reference && !out.new_keyframe)) return;
  std::vector<cv::Point2f> dynamic;
  for (size_t i = 0; i < out.keypoints.size(); ++i)
    if (out.keypoint_labels[i] == MotionLabel::Dynamic || memory_[i] > 0) dynamic.push_back(out.keypoints[i]);
  depth_alignment_.setReference(depth, depth_units, camera, out.T_world_camera, stamp, dynamic, known_dynamic);
}

MotionPrior RgbdOdometry::motionPrior(const Isometry& T_world_pred, double frame_gap) const {
  // The constant-velocity prediction as a soft constraint: per-frame measurement noise
  // of a few hundred static points on noisy depth is ~1 cm, the same order as what a
  // hand-held camera's velocity can change in 1/30 s. Widened over gaps and lost frames.
  MotionPrior prior;
  if (!config_.odometry.motion_prior) return prior;
  const double frames = std::max(1.0, frame_gap * 30.0) * (1 + lost_streak_);
  prior.T_cur_ref = T_world_pred.inverse();
  prior.sigma_translation = config_.background.prior_translation * frames;
  prior.sigma_rotation = config_.background.prior_rotation * M_PI / 180.0 * frames;
  return prior;
}

void RgbdOdometry::decideTracking(const RefinementResult& refined, Isometry T_world_cur, bool trustworthy,
                                  const Isometry& T_world_pred, FrameTracking& out) {
  const auto& o = config_.odometry;
  out.num_inliers = refined.inliers;
  out.position_sigma = positionStdDev(refined);
  out.pixel_error_median = refined.median_pixel_error;
  out.depth_error_median = refined.median_depth_error;
  // Enough inliers can still leave the pose undetermined: points on a narrow strip of one
  // wall let translation and rotation trade off (doc/robustness.md).
  const bool enough = refined.inliers >= o.min_static_inliers;
  const bool determined = o.max_position_sigma <= 0 || out.position_sigma <= o.max_position_sigma;
  if (enough && determined && trustworthy) {
    out.state = TrackingState::Tracking;
    lost_streak_ = 0;
    out.T_world_camera = T_world_cur;
    return;
  }
  char reason[200];
  if (!enough) {
    std::snprintf(reason, sizeof reason, "only %d static inliers (of %zu matches with depth)", refined.inliers,
                  track_.motion.size());
  } else if (!determined) {
    out.pose_undetermined = true;
    std::snprintf(reason, sizeof reason,
                  "pose not determined by its %d static inliers (position standard deviation %.2f m > %.2f)",
                  refined.inliers, out.position_sigma, o.max_position_sigma);
  } else {
    out.background_untrusted = true;
    std::snprintf(reason, sizeof reason,
                  "no trustworthy background: %d of %d matched static landmarks agree with the best hypothesis",
                  choice_.established_agreeing, choice_.established_matched);
  }
  out.lost_reason = reason;
  out.state = TrackingState::Lost;
  out.T_world_camera = T_world_pred;
  ++lost_streak_;
  // A lost frame's velocity may be the one that lost tracking: extrapolated less each frame.
  velocity_ = scaledMotion(velocity_, 0.5);
}

void RgbdOdometry::labelAgainstPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_cur,
                                             FrameTracking& out) {
  // A walker near the camera moves out of the map's search window; one frame apart it is
  // still matchable. Only keypoints the map pass left undecided take these labels, so
  // the pose (already refined) is unaffected.
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
    if (out.gmc_previous.labels[k] != MotionLabel::Dynamic) continue;
    auto& label = out.keypoint_labels[static_cast<size_t>(cur_index[k])];
    fresh_dynamic_[static_cast<size_t>(cur_index[k])] = 1;
    if (label == MotionLabel::Undecided) {
      label = MotionLabel::Dynamic;
      ++out.num_dynamic;
    }
  }
}

void RgbdOdometry::updateMap(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp,
                             FrameTracking& out) {
  if (out.state == TrackingState::Tracking) {
    std::vector<LandmarkObservation> seen;
    seen.reserve(track_.motion.size());
    // GMC's own decision: a suspect landmark relabelled dynamic for the pose must not
    // renew its own suspicion while it stays in place.
    for (size_t k = 0; k < track_.motion.size(); ++k)
      seen.push_back({track_.landmark[k], track_.motion[k].point_cur, choice_.gmc.labels[k]});
    map_.observe(seen, track_.view.ids, out.T_world_camera, stamp, config_.background.inPlace());
  }
  KeyframeFrame frame;
  frame.tracked = out.state == TrackingState::Tracking;
  frame.T_world_cur = out.T_world_camera;
  frame.static_inliers = out.num_inliers;
  frame.landmarks_in_view = out.landmarks_in_view;
  frame.dynamic_share = dynamicShare(out);
  frame.lost_streak = lost_streak_;
  const KeyframeDecision decision = keyframe_policy_.decide(frame);
  if (decision == KeyframeDecision::None) return;
  if (decision == KeyframeDecision::Reanchor) {
    out.state = TrackingState::Reanchored;
    velocity_ = Isometry::Identity();
    velocity_known_ = false;
    lost_streak_ = 0;
    if (config_.keyframes.reanchor_new_map) startNewMap(cur, stamp);
  }
  out.new_keyframe = true;
  addKeyframe(cur, camera, stamp, out);
  if (map_restarted_) startConsensus(cur, stamp);
}

void RgbdOdometry::startNewMap(const features::FeatureSet& cur, double stamp) {
  // A frame that cannot seed a map keeps the old one: it may still be found again.
  int with_depth = 0;
  for (size_t i = 0; i < cur.size(); ++i) with_depth += cur.hasDepth(static_cast<int>(i)) ? 1 : 0;
  if (with_depth < config_.odometry.min_matches) return;
  map_restarted_ = true;
  const int left = map_id_;
  ++map_id_;
  // A map that never held the room (too few landmarks with static evidence) followed one
  // frame's clusters after its first keyframe: that keyframe is what can be found again,
  // and every frame after it is as uncertain as a lost one.
  const bool young = config_.rejoin.young_map_anchor && map_frames_.size() <= kMaxYoungMapFrames &&
                     map_.numStatic(stamp) < static_cast<size_t>(config_.background.min_static_landmarks);
  std::optional<MapAnchor> anchor;
  if (young) anchor = MapAnchor{map_anchor_features_, consensus_start_.T_world_camera};
  rejoin_.freeze(left, map_.landmarksNotSeenMoving(stamp), stamp, std::move(anchor));
  // The frames from here on are kept while a map left may be found again.
  if (rejoin_.active()) {
    if (young)
      records_.reanchor(left, consensus_start_, map_id_, map_frames_);
    else
      records_.reanchor(left, last_tracked_, map_id_, lost_frames_);
  }
  map_start_stamp_ = stamp;
  map_.clear();
  free_space_.clear();  // the views' poses and the new map's are not known relative to each other
  depth_alignment_.clear();
  window_keyframes_.clear();
  pose_landmarks_.clear();
  // This frame's matches point into the old map: none of them is an observation now.
  track_.motion.clear();
  track_.cur_index.clear();
  track_.landmark.clear();
  track_.matched.assign(cur.size(), 0);
}

void RgbdOdometry::tryRejoin(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp,
                             FrameTracking& out) {
  for (int map : rejoin_.giveUpExpired(stamp)) records_.forget(map);
  if (!rejoin_.active()) return;
  const auto t0 = Clock::now();  // descriptor matching, mostly: counted with the frontend
  // Joins grow the oldest frame still waiting (the trajectory's, while its map waits):
  // until the current map is in it, only the map waiting in it is tried. A young
  // intermediate map may itself be off (it started among walkers); joined first, it would
  // carry the current map off with it (Bonn 301-460 without GMC: 0.231 -> 0.300 m). Once
  // in it, every waiting map is tried in turn.
  int only = -1;
  for (int map : rejoin_.waitingMaps())
    if (records_.frameOf(map) < records_.frameOf(only < 0 ? map_id_ : only)) only = map;
  const std::optional<RejoinFound> found =
      rejoin_.attempt(frontend_, cur, out.T_world_camera, camera, nullptr, only, &map_, stamp);
  out.times.frontend += msSince(t0);
  if (!found) return;
  // The younger of the two frames moves into the older (the trajectory's first frame
  // stays): usually the current map into the one it left.
  const bool current_moves = records_.frameOf(map_id_) > records_.frameOf(found->map);
  std::vector<RevisedPose> revised;
  records_.join(found->map, map_id_, found->T_map_current, revised);
  if (config_.odometry.revise_lost) out.revised.insert(out.revised.end(), revised.begin(), revised.end());
  std::vector<Landmark> landmarks = rejoin_.release(found->map);
  out.rejoined = true;
  if (!current_moves) {
    const Isometry T_current_map = found->T_map_current.inverse();
    for (auto& l : landmarks) l.position = T_current_map * l.position;
    map_.adopt(std::move(landmarks));
    return;
  }
  // Everything of the current map moves; velocities are relative and stay.
  const Isometry& T = found->T_map_current;
  out.T_world_camera = orthonormalized(T * out.T_world_camera);
  T_world_last_ = T * T_world_last_;
  T_world_previous_ = T * T_world_previous_;
  last_tracked_.T_world_camera = T * last_tracked_.T_world_camera;
  consensus_start_.T_world_camera = T * consensus_start_.T_world_camera;
  for (auto& kf : window_keyframes_) kf.T_world_kf = T * kf.T_world_kf;
  keyframe_policy_.transform(T);
  map_.transform(T);
  map_.adopt(std::move(landmarks));
  consensus_.stop();  // the map joins one with evidence
}

void RgbdOdometry::addKeyframe(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp,
                               const FrameTracking& out) {
  WindowKeyframe kf;
  kf.T_world_kf = out.T_world_camera;
  kf.pose_landmarks = pose_landmarks_;
  // Static matches with trust join the window's observations; the rest of the frame's
  // features with depth become new landmarks.
  for (size_t k = 0; k < track_.motion.size(); ++k) {
    if (out.keypoint_labels[static_cast<size_t>(track_.cur_index[k])] != MotionLabel::Static) continue;
    const auto& kp = cur.keypoints[static_cast<size_t>(track_.cur_index[k])].pt;
    kf.observations.push_back({0, track_.landmark[k], Eigen::Vector2d(kp.x, kp.y), track_.motion[k].point_cur.z()});
  }
  // A keypoint whose track moved on in the world makes its landmark start suspect, as
  // GMC's dynamic label does. Tracks are measured through the poses: not while a new
  // map's start is still judged (a group walking with the camera makes the room's corners
  // look as if they moved), and only among walkers (on a static scene a new landmark is as
  // good as an old one). Measured, off by default: doc/odometry.md, thirty-second round.
  std::vector<MotionLabel> labels = out.keypoint_labels;
  const auto& o = config_.odometry;
  if (tracks_.enabled() && !consensus_.active() && dynamicShare(out) >= o.track_min_dynamic_share) {
    const InPlaceThreshold threshold = config_.background.inPlace();
    for (size_t i = 0; i < labels.size(); ++i)
      if (tracks_.movedOn(i) > o.track_moved_factor * threshold.at(cur.points[i].z())) labels[i] = MotionLabel::Dynamic;
  }
  // The dynamic mask (given after process()) judges the same new landmarks under the same
  // conditions, and only where landmarks with static evidence hold the pose (the mask is
  // drawn with it). Measured, off by default: doc/odometry.md, thirty-third round.
  const bool maskable = o.mask_new_landmarks && !consensus_.active() && out.state == TrackingState::Tracking &&
                        dynamicShare(out) >= o.mask_min_dynamic_share &&
                        out.static_landmarks_matched >= o.mask_min_static_landmarks;
  // Walkers pass in front of the room: only a new landmark in front of what holds the pose
  // is judged. A pose that follows walkers sees the room move and masks it; behind the
  // walkers it holds on, the room is not taken out of the map.
  const double masked_in_front_of = maskable ? medianPoseDepth(cur, out) - o.mask_front_margin : 0.0;
  for (const auto& [feature, id] : map_.addFeatures(cur, track_.matched, labels, out.T_world_camera,
                                                    stamp, keyframe_count_)) {
    const auto& kp = cur.keypoints[static_cast<size_t>(feature)].pt;
    if (known_dynamic_[static_cast<size_t>(feature)]) map_.markKnownDynamic(id);
    kf.observations.push_back({0, id, Eigen::Vector2d(kp.x, kp.y), cur.points[static_cast<size_t>(feature)].z()});
    if (maskable && cur.points[static_cast<size_t>(feature)].z() < masked_in_front_of) maskable_.emplace_back(id, kp);
    // Recent views saw the room through its place: it arrived since, on something that
    // moves (a standing person too, until the suspicion ends).
    if (free_space_.arrivedSince(map_[id].position, camera, stamp)) map_.distrust(id, stamp);
  }
  ++keyframe_count_;
  window_keyframes_.push_back(std::move(kf));
  const size_t capacity = window_.keptKeyframes();
  if (window_keyframes_.size() > capacity)
    window_keyframes_.erase(window_keyframes_.begin(),
                            window_keyframes_.begin() + static_cast<long>(window_keyframes_.size() - capacity));
  const std::vector<int> remap = map_.cull(stamp);
  if (remap.empty()) return;
  renumberLandmarks(pose_landmarks_, remap, [](int& id) -> int& { return id; });
  hindsight_.renumber(remap);
  renumberLandmarks(maskable_, remap, [](std::pair<int, cv::Point2f>& m) -> int& { return m.first; });
  consensus_.remap(remap);
  for (auto& w : window_keyframes_) {
    renumberLandmarks(w.observations, remap, [](WindowObservation& ob) -> int& { return ob.landmark; });
    renumberLandmarks(w.pose_landmarks, remap, [](int& id) -> int& { return id; });
  }
}

Isometry RgbdOdometry::optimizeWindow(const PinholeCamera& camera, double stamp, FrameTracking& out) {
  // The keyframes taking part (the fixed ones first), chosen by the landmarks they observe
  // among those whose pose is still held: a keyframe posed on a group walking in step with
  // the camera, once the map holds the room, would pull every newer one back onto the group
  // (generated synchronous seed 1: the newest keyframe 6-17 cm off a right tracked pose).
  const auto usable = [&](int id) { return map_[id].alive && map_.evidence(id, stamp) != Evidence::Suspect; };
  std::vector<size_t> candidates;  // indices into window_keyframes_
  std::vector<std::vector<int>> observed;
  for (size_t k = 0; k < window_keyframes_.size(); ++k) {
    const WindowKeyframe& kf = window_keyframes_[k];
    if (config_.window.skip_unheld && !map_.stillHold(kf.pose_landmarks, stamp)) continue;
    candidates.push_back(k);
    observed.emplace_back();
    for (const auto& ob : kf.observations)
      if (usable(ob.landmark)) observed.back().push_back(ob.landmark);
    std::sort(observed.back().begin(), observed.back().end());
  }
  // The newest keyframe is this frame, held by the landmarks it was just posed on; the
  // window's last pose must be it.
  if (candidates.empty() || candidates.back() + 1 != window_keyframes_.size())
    return window_keyframes_.back().T_world_kf;
  const std::vector<size_t> chosen = selectWindowKeyframes(observed, config_.window);  // into candidates
  // Static landmarks seen from at least min_observations keyframes of the window.
  std::map<int, int> index_of;  // landmark id -> point index
  std::map<int, int> count;
  std::vector<size_t> window;  // into window_keyframes_
  for (size_t c : chosen) {
    for (int id : observed[c]) ++count[id];
    window.push_back(candidates[c]);
  }
  WindowProblem problem;
  for (const auto& [id, n] : count) {
    if (n < config_.window.min_observations) continue;
    index_of[id] = static_cast<int>(problem.points.size());
    problem.points.push_back(map_[id].position);
  }
  for (size_t k = 0; k < window.size(); ++k) {
    problem.poses.push_back(window_keyframes_[window[k]].T_world_kf.inverse());
    for (auto ob : window_keyframes_[window[k]].observations) {
      const auto it = index_of.find(ob.landmark);
      if (it == index_of.end()) continue;
      ob.keyframe = static_cast<int>(k);
      ob.landmark = it->second;
      problem.observations.push_back(ob);
    }
  }
  // Every keyframe it moves must be held by enough static landmarks, or the window would
  // let a weakly observed pose swing.
  std::vector<int> per_keyframe(window.size(), 0);
  for (const auto& ob : problem.observations) ++per_keyframe[static_cast<size_t>(ob.keyframe)];
  const int min_per_keyframe = config_.odometry.min_static_inliers;
  const size_t fixed = window_.fixedPoses();
  if (problem.poses.size() <= fixed ||
      *std::min_element(per_keyframe.begin() + static_cast<long>(fixed), per_keyframe.end()) < min_per_keyframe)
    return window_keyframes_.back().T_world_kf;
  window_.optimize(problem, camera);
  const Isometry& T_world_tracked = window_keyframes_.back().T_world_kf;
  const Isometry T_world_optimized = problem.poses.back().inverse();
  out.window_shift = (T_world_optimized.translation() - T_world_tracked.translation()).norm();
  if (!plausibleWindowShift(T_world_tracked, T_world_optimized, out.position_sigma, config_.window)) {
    out.window_discarded = true;
    return window_keyframes_.back().T_world_kf;
  }
  for (size_t k = 0; k < window.size(); ++k) window_keyframes_[window[k]].T_world_kf = problem.poses[k].inverse();
  for (const auto& [id, j] : index_of) map_.setPosition(id, problem.points[static_cast<size_t>(j)]);
  return window_keyframes_.back().T_world_kf;
}

}  // namespace gmc::vo
