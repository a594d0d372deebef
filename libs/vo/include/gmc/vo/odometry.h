#pragma once
// RGB-D visual odometry with GMC: frame-to-keyframe tracking whose pose is refined on
// the matches GMC labels static. One call per frame; no I/O.
#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/gmc/gmc.h"
#include "gmc/vo/background.h"
#include "gmc/vo/depth_alignment.h"
#include "gmc/vo/feature_tracks.h"
#include "gmc/vo/free_space.h"
#include "gmc/vo/hindsight.h"
#include "gmc/vo/keyframe_policy.h"
#include "gmc/vo/landmark_map.h"
#include "gmc/vo/map_records.h"
#include "gmc/vo/map_rejoin.h"
#include "gmc/vo/pose_refinement.h"
#include "gmc/vo/start_consensus.h"
#include "gmc/vo/trajectory_smoother.h"
#include "gmc/vo/window_optimizer.h"

namespace gmc::vo {

/// INI section [Odometry].
struct OdometryOptions {
  int min_static_inliers = 20;          ///< fewer static inliers after refinement = lost
  int min_matches = 30;                 ///< fewer map matches: retry with a wider window
  int wide_match_radius = 100;          ///< px, second attempt of guided matching
  bool relocalize_static = true;        ///< after a lost frame, landmarks with static
                                        ///< evidence are also matched over the whole image
  bool use_motion_model = true;         ///< constant-velocity prediction
  bool motion_prior = false;            ///< the prediction also joins the refinement as a
                                        ///< Gaussian prior ([Background] prior_* widths)
  bool previous_frame_labels = true;    ///< also run GMC against the previous frame, so
                                        ///< walkers too fast to match to the map are
                                        ///< labelled (for masks; not for the pose)
  int dynamic_memory_frames = 0;        ///< a keypoint labelled dynamic stays dynamic this
                                        ///< many frames while it is matched frame to frame
  double max_position_sigma = 0.10;     ///< m; a pose whose camera position is less well
                                        ///< determined than this (standard deviation along
                                        ///< its weakest direction) is lost (0 = no check)
  bool revise_lost = true;              ///< once tracking resumes on the same map, the lost
                                        ///< frames' poses are revised (FrameTracking::revised)
  int random_seed = 0;                  ///< 0: the built-in RANSAC sampling streams; another
                                        ///< value: other, equally valid streams (how much a
                                        ///< figure owes to chance: doc/odometry.md)
  int smoothing_frames = 6;             ///< the trajectory's poses: a quadratic fit over this
                                        ///< many tracked frames on each side, given out as
                                        ///< revisions that many frames later (0 = live poses)
  double smoothing_break = 0.1;         ///< m (and rad): a step that differs from the one
                                        ///< before by more than this starts a new smoothing
                                        ///< run (a jump is not smoothed over)
  bool smoothing_edges = true;          ///< a run's first and last smoothing_frames frames
                                        ///< are fitted too, over its first or last full window
  double young_map_lost_still_share = 0.2;  ///< a lost frame stands still instead of
                                        ///< extrapolating the velocity when the map holds no
                                        ///< static evidence yet and at least this share of the
                                        ///< last tracked frame's labelled matches were dynamic
  int unheld_start_frames = 12;         ///< a map lost within this many frames of its start,
                                        ///< before any static evidence and with walkers in
                                        ///< view, revises its tracked frames to its start
                                        ///< pose: nothing held them (0 = off)
  int track_frames = 0;                 ///< a keyframe's new landmark whose frame-to-frame track
                                        ///< over up to this many tracked frames moved on in the
                                        ///< world starts suspect (0 = off; FeatureTracks)
  double track_moved_factor = 5.0;      ///< ... moved on: further than this many inlier
                                        ///< thresholds ([Background] inlier_*)
  double track_min_dynamic_share = 0.1; ///< ... judged only on keyframes where GMC labels at
                                        ///< least this share of the matches dynamic
  bool mask_new_landmarks = false;      ///< a keyframe's new landmark inside the frame's dynamic
                                        ///< mask (given by distrustMaskedLandmarks, as the gmc
                                        ///< filter does) starts suspect
  double mask_min_dynamic_share = 0.1;  ///< ... only on keyframes where GMC labels at least this
                                        ///< share of the matches dynamic
  double mask_front_margin = 0.3;       ///< ... and only landmarks nearer by this much (m) than the
                                        ///< median depth of the points that held the pose
  int mask_min_static_landmarks = 20;   ///< ... and only where the frame matched at least this
                                        ///< many landmarks with static evidence

  template <class V>
  void visit(V& v) {
    v("min_static_inliers", min_static_inliers, 3, 100000, "fewer static inliers = lost");
    v("min_matches", min_matches, 3, 100000, "fewer map matches: retry with a wider window");
    v("wide_match_radius", wide_match_radius, 1, 2000, "px, second guided-matching window");
    v("relocalize_static", relocalize_static,
      "after a lost frame, also match the landmarks with static evidence over the whole image");
    v("use_motion_model", use_motion_model, "constant-velocity motion prediction");
    v("motion_prior", motion_prior, "the prediction joins the refinement as a prior ([Background] prior_*)");
    v("previous_frame_labels", previous_frame_labels,
      "label keypoints unmatched to the map by GMC against the previous frame");
    v("dynamic_memory_frames", dynamic_memory_frames, 0, 100000,
      "frames a dynamic label is remembered along frame-to-frame matches (0 = off)");
    v("max_position_sigma", max_position_sigma, 0.0, 100.0,
      "m, lost when the position's standard deviation along its weakest direction exceeds this (0 = off)");
    v("revise_lost", revise_lost,
      "when tracking resumes on the same map, revise the lost frames' poses along the path between the tracked ones");
    v("random_seed", random_seed, 0, 1000000000,
      "0 = the built-in RANSAC sampling streams; another value gives other, equally valid ones");
    v("smoothing_frames", smoothing_frames, 0, 100,
      "tracked frames on each side of a pose whose quadratic fit replaces it in the trajectory, that many frames "
      "later (0 = the live poses)");
    v("smoothing_break", smoothing_break, 0.0, 100.0,
      "m (and rad): a frame whose step differs from the step before by more than this starts a new smoothing run");
    v("smoothing_edges", smoothing_edges,
      "fit a smoothing run's first and last smoothing_frames frames too, over its first or last full window");
    v("young_map_lost_still_share", young_map_lost_still_share, 0.0, 2.0,
      "lost frames in a map without static evidence stand still when this share of the last tracked "
      "frame's labelled matches were dynamic (0 = always, above 1 = never)");
    v("unheld_start_frames", unheld_start_frames, 0, 1000,
      "a map lost this few frames after its start, without static evidence and with walkers in view, revises "
      "its tracked frames to its start pose (0 = off)");
    v("track_frames", track_frames, 0, FeatureTracks::kMaxLength,
      "a keyframe's new landmark whose frame-to-frame track over up to this many tracked frames moved on in the "
      "world starts suspect, once a new map's start is judged (0 = off)");
    v("track_moved_factor", track_moved_factor, 0.1, 1000.0,
      "moved on: the track's two halves go one way, the shorter one doubled further than this many inlier "
      "thresholds ([Background] inlier_*)");
    v("track_min_dynamic_share", track_min_dynamic_share, 0.0, 1.0,
      "tracks are judged only on keyframes where at least this share of the labelled matches is dynamic");
    v("mask_new_landmarks", mask_new_landmarks,
      "a keyframe's new landmark inside the frame's dynamic mask ([DynamicMask]) starts suspect, once a new map's "
      "start is judged");
    v("mask_min_dynamic_share", mask_min_dynamic_share, 0.0, 1.0,
      "the mask is applied only on keyframes where at least this share of the labelled matches is dynamic");
    v("mask_front_margin", mask_front_margin, -100.0, 100.0,
      "m: the mask judges only new landmarks nearer by this much than the median depth of the pose's points "
      "(walkers pass in front of the room; -100 judges every one)");
    v("mask_min_static_landmarks", mask_min_static_landmarks, 0, 100000,
      "the mask is applied only on keyframes matching at least this many landmarks with static evidence");
  }
};

/// Everything the odometry is configured with, section by section.
struct OdometryConfig {
  features::FrontendOptions frontend;  ///< [Frontend]
  GmsParams gms;                       ///< [GMS]
  GmcParams gmc;                       ///< [GMC]
  OdometryOptions odometry;            ///< [Odometry]
  RefinementOptions refinement;        ///< [Refinement]
  LocalMapOptions local_map;           ///< [LocalMap]
  BackgroundOptions background;        ///< [Background]
  KeyframeOptions keyframes;           ///< [Keyframes]
  WindowOptions window;                ///< [Window]
  RejoinOptions rejoin;                ///< [Rejoin]
  StartConsensusOptions start_consensus;  ///< [StartConsensus]
  HindsightOptions hindsight;          ///< [Hindsight]
  FreeSpaceOptions free_space;         ///< [FreeSpace]
  DepthAlignmentOptions depth_alignment;  ///< [DepthAlignment]
};

/// Milliseconds spent per stage for one frame.
struct StageTimes {
  double frontend = 0;  ///< extraction + matching + GMS
  double guess = 0;     ///< hypotheses (prediction, RANSAC) and their GMC judgement; a young
                        ///< map's start consensus
  double gmc = 0;       ///< GMC classification against the previous frame (masks)
  double refine = 0;    ///< robust refinement on static matches
  double window = 0;    ///< windowed optimisation (keyframes only)
  double total = 0;     ///< the odometry: the stages above
  double mask = 0;      ///< per-pixel dynamic mask (built after the odometry, not in total)
};

enum class TrackingState { Initialized, Tracking, Lost, Reanchored };
const char* toString(TrackingState s);

/// One match of a frame against the landmark map, with what a ground truth needs to
/// judge it: the matched point now and the observation that placed the landmark (both in
/// their cameras' frames, so the estimated poses play no part; scripts/match_truth.py).
struct MapMatchRecord {
  int keypoint = -1;                                       ///< index into FrameTracking::keypoints
  Eigen::Vector3d point_cur = Eigen::Vector3d::Zero();      ///< current camera frame (m)
  Eigen::Vector3d landmark_origin = Eigen::Vector3d::Zero();  ///< Landmark::origin_point
  double landmark_origin_stamp = 0;                         ///< Landmark::origin_stamp
  MotionLabel label = MotionLabel::Undecided;               ///< GMC's label for the pose
  bool established = false;                                 ///< the landmark has static evidence
  bool in_pose = false;                                     ///< went into the pose refinement
  bool pose_inlier = false;                                 ///< ... and is an inlier at its result
};

struct FrameTracking {
  double stamp = 0;
  long frame_number = 0;                ///< 1 for the first frame processed, then one more per frame
  Isometry T_world_camera = Isometry::Identity();  ///< live: a lost frame's is the prediction
  std::vector<RevisedPose> revised;     ///< on the first tracked frame after lost ones (same
                                        ///< map): their poses, on the path between the two
                                        ///< tracked poses around them ([Odometry] revise_lost)
  TrackingState state = TrackingState::Initialized;
  std::string lost_reason;              ///< why the frame is Lost, empty otherwise
  bool pose_undetermined = false;       ///< Lost with enough inliers: max_position_sigma
  bool background_untrusted = false;    ///< Lost: the static landmarks disagree with every hypothesis
  bool new_keyframe = false;
  bool window_discarded = false;        ///< the windowed optimisation's result was implausible
  bool start_consensus = false;         ///< this frame took its young map's start consensus:
                                        ///< it and the map's earlier frames are revised
  bool rejoined = false;                ///< this frame found the map left at a re-anchor: its
                                        ///< pose and the map moved back into that map's frame
  double window_shift = 0;              ///< m the windowed optimisation moved this keyframe
                                        ///< (also when discarded; 0 when it did not run)
  int map_landmarks = 0;                ///< live landmarks in the local map
  int landmarks_in_view = 0;            ///< landmarks projected into this frame
  int static_landmarks_matched = 0;     ///< matches on landmarks with static evidence ...
  int static_landmarks_agreeing = 0;    ///< ... of which the chosen background labels static
  int landmarks_to_refind = 0;          ///< landmarks that held the previous tracked frame's pose
                                        ///< (static, trusted) and are still in the map ...
  int landmarks_refound = 0;            ///< ... of which this frame matched again
  const char* background_source = "";   ///< hypothesis chosen: prediction | ransac_static | ransac_all
  int num_features = 0, num_matches = 0, num_static = 0, num_dynamic = 0, num_inliers = 0;
  double position_sigma = 0;            ///< m, camera position's standard deviation along
                                        ///< its least constrained direction (refinement)
  double pixel_error_median = 0;        ///< px, refinement's median reprojection error
  double depth_error_median = 0;        ///< m, refinement's median depth error
  StageTimes times;
  /// Current keypoints and their labels (Undecided when unmatched), for overlays/masks.
  std::vector<cv::Point2f> keypoints;
  std::vector<MotionLabel> keypoint_labels;
  /// 1 where the keypoint's observation went into the pose refinement (static, trusted);
  /// with ground-truth masks it tells how much of the pose rests on people.
  std::vector<std::uint8_t> keypoint_in_pose;
  /// The frame's matches against the map (with depth), as the pose step judged them.
  std::vector<MapMatchRecord> map_matches;
  GmcResult gmc;                        ///< cells and clusters of this frame (vs the map)
  GmcResult gmc_previous;               ///< the same against the previous frame (masks)

  bool tracked() const {
    return state == TrackingState::Tracking || state == TrackingState::Initialized;
  }
};

/// The per-frame recipe: predict, match to the landmark map, choose the background
/// (hypotheses judged by GMC and static evidence), refine on static matches, decide
/// lost, update the map's evidence, keyframe policy (+ windowed optimisation).
class RgbdOdometry {
 public:
  explicit RgbdOdometry(const OdometryConfig& config = {});
  const OdometryConfig& config() const { return config_; }
  const LandmarkMap& landmarks() const { return map_; }

  /// gray: CV_8UC1; depth: CV_16UC1 raw units. known_dynamic (optional, CV_8UC1, the
  /// image's size): non-zero pixels are known to show moving objects (a person
  /// segmenter's output, or a simulator's truth): their matches are dynamic under every
  /// hypothesis and the landmarks placed on them are never trusted (doc/odometry.md,
  /// "Known dynamic pixels").
  FrameTracking process(const cv::Mat& gray, const cv::Mat& depth, double depth_units,
                        const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic = cv::Mat());

  /// The last processed frame's dynamic mask (CV_8UC1, non-zero = dynamic, pixels as the
  /// image's), built after process() from its result (DynamicMaskBuilder): a landmark the
  /// frame's keyframe made inside it starts suspect (when [Odometry] mask_new_landmarks is
  /// on and the frame was such a keyframe), and the dense depth term's reference, when it
  /// is this frame, leaves it out ([DepthAlignment]).
  void distrustMaskedLandmarks(const cv::Mat& mask);

  /// The input has ended: the trajectory's revisions still held back, i.e. the last run's
  /// last smoothing_frames frames fitted over its last full window (with smoothing_edges;
  /// FrameTracking::revised for frames that follow none). The live poses stand. Call once,
  /// after the last process().
  std::vector<RevisedPose> finish();

 private:
  /// The frame's matches against the landmarks visible from the predicted pose.
  struct MapTrack {
    LandmarkView view;
    std::vector<MotionMatch> motion;     ///< point_ref in the predicted camera frame
    std::vector<int> cur_index;          ///< keypoint index in the current frame per match
    std::vector<int> landmark;           ///< landmark id per match
    MatchTrust trust;
    std::vector<std::uint8_t> matched;   ///< per current keypoint: matched to a landmark
    int num_matches = 0;                 ///< after GMS, with or without depth
  };

  /// A keyframe of the optimisation window: its pose and the landmarks it observed.
  struct WindowKeyframe {
    Isometry T_world_kf = Isometry::Identity();
    std::vector<WindowObservation> observations;  ///< keyframe field unused; landmark = map id
    std::vector<int> pose_landmarks;              ///< the landmarks that held its tracked pose
  };

  /// A frame's depth image and known-dynamic mask, as process() was given them.
  struct FrameDepth {
    const cv::Mat& depth;
    double depth_units;
    const cv::Mat& known_dynamic;
  };

  // The steps of process(), in order.
  /// The frame's features (known-dynamic ones marked) and out's per-keypoint fields.
  features::FeatureSet extractFeatures(const cv::Mat& gray, const FrameDepth& frame_depth, const PinholeCamera& camera,
                                       double stamp, FrameTracking& out);
  /// 1. Matches to the previous frame (labels) and to the map (pose), at the prediction.
  void matchFrame(const features::FeatureSet& cur, const Isometry& T_world_pred, const PinholeCamera& camera,
                  double stamp, FrameTracking& out);
  /// 2. The background's motion and GMC's labels under it (choice_).
  void selectBackground(const features::FeatureSet& cur, double stamp, FrameTracking& out);
  /// 3-4. The pose refined on the background; tracked or lost; a young map's start
  /// judged; a rejoin tried.
  void poseFrame(const features::FeatureSet& cur, const FrameDepth& frame_depth, const PinholeCamera& camera,
                 double stamp, const Isometry& T_world_pred, FrameTracking& out);
  /// 5. Labels against the previous frame for the mask; the dynamic memory.
  void labelForMask(const features::FeatureSet& cur, FrameTracking& out);
  /// 6. Static evidence, keyframes, the window; the velocity of a tracked frame.
  void updateMapAndWindow(const features::FeatureSet& cur, const FrameDepth& frame_depth,
                          const PinholeCamera& camera, double stamp, bool after_lost_frames, FrameTracking& out);
  /// 7. Revisions of earlier poses (bridged, smoothed, in hindsight); the frame becomes
  /// the previous one.
  void finishFrame(features::FeatureSet&& cur, const PinholeCamera& camera, double stamp, FrameTracking& out);

  /// known_dynamic_ for the frame's keypoints (2 px margin); throws on a wrong mask.
  void markKnownDynamic(const features::FeatureSet& cur, const cv::Mat& known_dynamic);
  void initialize(features::FeatureSet&& cur, const PinholeCamera& camera, double stamp, FrameTracking& out);
  void bridgeLostFrames(FrameTracking& out);
  /// The pose smoothing_frames back, fitted over the tracked frames around it (a revision).
  void smoothTrajectory(FrameTracking& out);
  /// The frame kept for a judgement in hindsight; the revisions of earlier frames it makes.
  void reviseInHindsight(features::FeatureSet&& cur, const PinholeCamera& camera, FrameTracking& out);
  void bridge(const std::vector<std::pair<long, double>>& lost, const RevisedPose& from, const RevisedPose& to,
              FrameTracking& out);
  /// A young map's frames judged together; taken, it revises their poses and the
  /// landmarks outside it become suspect.
  void judgeStart(double stamp, const PinholeCamera& camera, FrameTracking& out);
  void adoptConsensus(const ConsensusResult& consensus, double stamp, FrameTracking& out);
  /// The window and keyframe policy keep the map's first keyframe only (its later ones were
  /// placed from poses now revised).
  void keepFirstKeyframeOnly();
  void revertUnheldStart(FrameTracking& out);
  /// The start consensus begins with a new map's first keyframe.
  void startConsensus(const features::FeatureSet& cur, double stamp);
  void matchToMap(const features::FeatureSet& cur, const Isometry& T_world_pred, const PinholeCamera& camera,
                  double stamp, MapTrack& track) const;
  void addStaticLandmarkMatches(const features::FeatureSet& ref, const features::FeatureSet& cur, double stamp,
                                const std::vector<int>& ids, std::vector<features::FeatureMatch>& matches) const;
  void matchPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_pred,
                          const PinholeCamera& camera);
  RefinementResult refineOnBackground(const Isometry& T_world_guess, const Isometry& T_world_pred,
                                      double frame_gap, const PinholeCamera& camera, FrameTracking& out);
  MotionPrior motionPrior(const Isometry& T_world_pred, double frame_gap) const;
  /// The frame's depth for the pose's dense term, away from its walkers and (with
  /// guess_gate) near its reference planes at the keypoints' guess ([DepthAlignment]).
  void sampleDepthForPose(const features::FeatureSet& cur, const cv::Mat& depth, double depth_units,
                          const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic,
                          const Isometry& T_world_guess);
  /// A tracked frame's depth, away from its walkers, as the next frame's dense reference.
  void keepDepthReference(const FrameTracking& out, const cv::Mat& depth, double depth_units,
                          const PinholeCamera& camera, double stamp, const cv::Mat& known_dynamic);
  void decideTracking(const RefinementResult& refined, Isometry T_world_cur, bool trustworthy,
                      const Isometry& T_world_pred, FrameTracking& out);
  void updateMap(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp, FrameTracking& out);
  void addKeyframe(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp,
                   const FrameTracking& out);
  /// Re-anchoring: the old landmarks and window go (the static ones wait in rejoin_),
  /// the keyframe seeds a new map.
  void startNewMap(const features::FeatureSet& cur, double stamp);
  /// A tracked frame of a new map looks for the maps left before; found, the younger of
  /// the two moves into the older one's world frame.
  void tryRejoin(const features::FeatureSet& cur, const PinholeCamera& camera, double stamp, FrameTracking& out);
  /// Windowed optimisation over the last keyframes; returns the newest keyframe's pose
  /// (unchanged, and out.window_discarded set, when the result is implausible).
  Isometry optimizeWindow(const PinholeCamera& camera, double stamp, FrameTracking& out);
  void labelAgainstPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_cur,
                                 FrameTracking& out);
  Isometry predictPose() const;
  /// A lost frame in a map without static evidence, after walkers: the velocity may be theirs.
  bool standStillWhileLost() const;
  /// How many of the landmarks that held the last tracked pose this frame found again.
  void countRefound(FrameTracking& out) const;
  /// What a tracked frame leaves for the next: the landmarks that held its pose, its static
  /// landmarks matched and its dynamic share (standStillWhileLost). After a lost frame no
  /// landmark is to be re-found; the last tracked frame's figures stay.
  void rememberTrackedFrame(const FrameTracking& out);

  OdometryConfig config_;
  features::Frontend frontend_;
  BackgroundSelector background_;
  KeyframePolicy keyframe_policy_;
  WindowOptimizer window_;
  LandmarkMap map_;
  MapRejoin rejoin_;
  StartConsensus consensus_;
  HindsightPoser hindsight_;
  int map_first_keyframe_ = 0;          ///< keyframe_count_ of the current map's first keyframe
  RevisedPose consensus_start_;         ///< and its frame (a taken consensus bridges from it)
  features::FeatureSet map_anchor_features_;  ///< that frame's features ([Rejoin] young_map_anchor)
  std::vector<std::pair<long, double>> map_frames_;  ///< the current map's frames after its first (number, stamp)
  /// A map left after more frames than this (30 s at 30 Hz) is not bridged from its first
  /// keyframe even without static evidence: a stretch that long is no straight path.
  static constexpr size_t kMaxYoungMapFrames = 900;
  std::vector<std::pair<long, double>> start_frames_;  ///< tracked frames since the map's start
                                                       ///< (unheld_start_frames; none once held)
  std::vector<std::uint8_t> known_dynamic_;  ///< per current keypoint: on a known dynamic pixel
  MapTrack track_;                      ///< reused per frame
  BackgroundChoice choice_;             ///< reused per frame
  features::FeatureSet previous_;       ///< last frame's features (shared descriptor data)
  Isometry T_world_previous_ = Isometry::Identity();
  std::vector<features::FeatureMatch> previous_matches_;  ///< previous frame -> this frame
  std::vector<int> previous_memory_;    ///< frames each previous keypoint stays dynamic
  std::vector<int> memory_;             ///< the same for the current frame's keypoints
  std::vector<std::uint8_t> fresh_dynamic_;  ///< labelled dynamic by GMC in this frame
  GmcClassifier gmc_previous_;
  bool initialized_ = false;
  Isometry T_world_last_ = Isometry::Identity();
  double last_stamp_ = 0;
  RevisedPose last_tracked_;                               ///< the last tracked (or first) frame
  long frame_number_ = 0;                                  ///< frames processed
  std::vector<std::pair<long, double>> lost_frames_;       ///< the lost frames since (number, stamp), same map
  MapRecords records_;                                      ///< frames of the maps that may be rejoined
  TrajectorySmoother smoother_;                             ///< the trajectory's fixed-lag smoothing
  int map_id_ = 0;                                          ///< the current map (0: the first; one more per re-anchor)
  bool map_restarted_ = false;                              ///< this frame's re-anchor started a new map
  Isometry velocity_ = Isometry::Identity();  ///< last frame-to-frame motion
  bool velocity_known_ = false;               ///< false until a map's first tracked step
  double map_start_stamp_ = 0;                ///< when the current map started (young map)
  int lost_streak_ = 0;
  int last_tracked_static_landmarks_ = 0;   ///< landmarks with static evidence the last tracked
                                            ///< frame matched ...
  double last_tracked_dynamic_share_ = 0;   ///< ... and the dynamic share of its labels
  int keyframe_count_ = 0;
  std::vector<WindowKeyframe> window_keyframes_;  ///< oldest first
  std::vector<int> pose_landmarks_;     ///< landmarks that held the last tracked pose (ids)
  FeatureTracks tracks_;                ///< the keypoints' frame-to-frame tracks in the world
  FreeSpaceHistory free_space_;         ///< where recent views saw through
  DepthAlignment depth_alignment_;      ///< the last tracked frame's depth as planes, for the pose
  std::vector<std::pair<int, cv::Point2f>> maskable_;  ///< this frame's new landmarks (id, pixel)
                                                      ///< that its dynamic mask may distrust
};

}  // namespace gmc::vo
