#pragma once
// RGB-D visual odometry with GMC: frame-to-keyframe tracking whose pose is refined on
// the matches GMC labels static. One call per frame; no I/O.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/gmc/gmc.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [Odometry].
struct OdometryOptions {
  int min_static_inliers = 20;          ///< fewer static inliers after refinement = lost
  int min_matches = 30;                 ///< fewer guided matches: retry with a wider window
  int wide_match_radius = 100;          ///< px, second attempt of guided matching
  int ransac_iterations = 150;          ///< 3-point 3-D/3-D hypotheses per frame
  double inlier_base = 0.005;           ///< m, 3-D inlier threshold at 0 m ...
  double inlier_per_m2 = 0.002;         ///< ... plus this times depth^2 (Kinect noise)
  double prediction_support = 0.5;      ///< keep the motion prediction while its support is
                                        ///< at least this fraction of RANSAC's best
  bool use_motion_model = true;         ///< constant-velocity prediction
  double keyframe_min_overlap = 0.6;    ///< new keyframe when static matches fall below this
                                        ///< fraction of the keyframe's static matches at creation
  double keyframe_max_translation = 0.25;  ///< m from the keyframe
  double keyframe_max_rotation = 15.0;     ///< deg from the keyframe
  bool previous_frame_labels = true;    ///< also run GMC against the previous frame, so
                                        ///< walkers too fast to match over the keyframe gap
                                        ///< are labelled (for masks; not for the pose)
  int reanchor_after_lost = 3;          ///< consecutive lost frames before a new keyframe
                                        ///< is anchored at the predicted pose
  int local_map_keyframes = 2;          ///< keyframes tracked jointly (1 = the last only)
  int dynamic_memory_frames = 0;        ///< a keypoint labelled dynamic stays dynamic this
                                        ///< many frames while it is matched frame to frame
  double max_position_sigma = 0.10;     ///< m; a pose whose camera position is less well
                                        ///< determined than this (standard deviation along
                                        ///< its weakest direction) is lost (0 = no check)

  template <class V>
  void visit(V& v) {
    v("min_static_inliers", min_static_inliers, 3, 100000, "fewer static inliers = lost");
    v("min_matches", min_matches, 3, 100000, "fewer matches: retry with a wider window");
    v("wide_match_radius", wide_match_radius, 1, 2000, "px, second guided-matching window");
    v("ransac_iterations", ransac_iterations, 0, 100000, "3-point 3-D/3-D hypotheses per frame");
    v("inlier_base", inlier_base, 1e-4, 10.0, "m, 3-D inlier threshold at zero depth");
    v("inlier_per_m2", inlier_per_m2, 0.0, 10.0, "inlier threshold growth per depth^2");
    v("prediction_support", prediction_support, 0.0, 10.0,
      "keep the prediction while its support >= this * RANSAC's");
    v("use_motion_model", use_motion_model, "constant-velocity motion prediction");
    v("keyframe_min_overlap", keyframe_min_overlap, 0.0, 1.0,
      "new keyframe below this fraction of the keyframe's static matches");
    v("keyframe_max_translation", keyframe_max_translation, 0.0, 100.0, "m from the keyframe");
    v("keyframe_max_rotation", keyframe_max_rotation, 0.0, 180.0, "deg from the keyframe");
    v("previous_frame_labels", previous_frame_labels,
      "label keypoints unmatched to the keyframe by GMC against the previous frame");
    v("reanchor_after_lost", reanchor_after_lost, 1, 100000,
      "lost frames before re-anchoring a keyframe at the predicted pose");
    v("local_map_keyframes", local_map_keyframes, 1, 64,
      "recent keyframes whose static matches refine the pose jointly");
    v("dynamic_memory_frames", dynamic_memory_frames, 0, 100000,
      "frames a dynamic label is remembered along frame-to-frame matches (0 = off)");
    v("max_position_sigma", max_position_sigma, 0.0, 100.0,
      "m, lost when the position's standard deviation along its weakest direction exceeds this (0 = off)");
  }
};

/// Everything the odometry is configured with, section by section.
struct OdometryConfig {
  features::FrontendOptions frontend;  ///< [Frontend]
  GmsParams gms;                       ///< [GMS]
  GmcParams gmc;                       ///< [GMC]
  OdometryOptions odometry;            ///< [Odometry]
  RefinementOptions refinement;        ///< [Refinement]
};

/// Milliseconds spent per stage for one frame.
struct StageTimes {
  double frontend = 0;  ///< extraction + matching + GMS
  double guess = 0;     ///< motion prediction check + RANSAC
  double gmc = 0;       ///< GMC classification
  double refine = 0;    ///< robust refinement on static matches
  double total = 0;     ///< the odometry: the stages above
  double mask = 0;      ///< per-pixel dynamic mask (built after the odometry, not in total)
};

enum class TrackingState { Initialized, Tracking, Lost, Reanchored };
const char* toString(TrackingState s);

struct FrameTracking {
  double stamp = 0;
  Isometry T_world_camera = Isometry::Identity();
  TrackingState state = TrackingState::Initialized;
  std::string lost_reason;              ///< why the frame is Lost, empty otherwise
  bool pose_undetermined = false;       ///< Lost with enough inliers: max_position_sigma
  bool new_keyframe = false;
  int local_map_keyframes = 0;          ///< keyframes that contributed static matches
  int num_features = 0, num_matches = 0, num_static = 0, num_dynamic = 0, num_inliers = 0;
  double position_sigma = 0;            ///< m, camera position's standard deviation along
                                        ///< its least constrained direction (refinement)
  StageTimes times;
  /// Current keypoints and their labels (Undecided when unmatched), for overlays/masks.
  std::vector<cv::Point2f> keypoints;
  std::vector<MotionLabel> keypoint_labels;
  GmcResult gmc;                        ///< cells and clusters of this frame (vs keyframe)
  GmcResult gmc_previous;               ///< the same against the previous frame (masks)

  bool tracked() const {
    return state == TrackingState::Tracking || state == TrackingState::Initialized;
  }
};

class RgbdOdometry {
 public:
  explicit RgbdOdometry(const OdometryConfig& config = {});
  const OdometryConfig& config() const { return config_; }

  /// gray: CV_8UC1; depth: CV_16UC1 raw units.
  FrameTracking process(const cv::Mat& gray, const cv::Mat& depth, double depth_units,
                        const PinholeCamera& camera, double stamp);

 private:
  struct Keyframe {
    features::FeatureSet features;
    std::vector<MotionLabel> labels;  ///< labels at creation (dynamic ones are not trusted)
    Isometry T_world_kf = Isometry::Identity();
    int static_matches = 0;
  };
  struct Guess {
    Isometry T_kf_cur = Isometry::Identity();
    bool from_ransac = false;
    int support = 0;
  };

  /// Matches of the frame against one keyframe with depth on both sides, the initial
  /// guess of their relative motion and GMC's labels.
  struct KeyframeTrack {
    std::vector<MotionMatch> motion;
    std::vector<int> cur_index;          ///< keypoint index in the current frame per match
    std::vector<std::uint8_t> trusted;   ///< keyframe feature not labelled dynamic
    int num_matches = 0;                 ///< after GMS, with or without depth
    Guess guess;
    GmcResult gmc;
  };
  /// `fallbacks`: widen the window, then match exhaustively when guided matching finds
  /// too few (the primary keyframe only).
  void trackAgainst(const Keyframe& kf, const features::FeatureSet& cur, const Isometry& T_world_guess,
                    const PinholeCamera& camera, bool fallbacks, GmcClassifier& gmc,
                    KeyframeTrack& track, StageTimes& times);
  Guess initialGuess(const std::vector<MotionMatch>& matches,
                     const std::vector<std::uint8_t>& trusted, const Isometry& predicted);
  int countSupport(const std::vector<MotionMatch>& matches, const Isometry& T_kf_cur,
                   const std::vector<std::uint8_t>* mask) const;
  void makeKeyframe(features::FeatureSet&& features, std::vector<MotionLabel> labels,
                    const Isometry& T_world_cur, int static_matches);
  Isometry predictPose() const;

  OdometryConfig config_;
  features::Frontend frontend_;
  GmcClassifier gmc_;
  void labelAgainstPreviousFrame(const features::FeatureSet& cur, const Isometry& T_world_cur,
                                 FrameTracking& out);

  std::vector<Keyframe> local_map_;     ///< oldest first; back() is the current keyframe
  Keyframe& keyframe() { return local_map_.back(); }
  KeyframeTrack primary_, secondary_;   ///< reused per frame
  features::FeatureSet previous_;       ///< last frame's features (shared descriptor data)
  Isometry T_world_previous_ = Isometry::Identity();
  std::vector<features::FeatureMatch> previous_matches_;  ///< previous frame -> this frame
  std::vector<int> previous_memory_;    ///< frames each previous keypoint stays dynamic
  std::vector<int> memory_;             ///< the same for the current frame's keypoints
  std::vector<std::uint8_t> fresh_dynamic_;  ///< labelled dynamic by GMC in this frame
  GmcClassifier gmc_previous_;
  bool initialized_ = false;
  Isometry T_world_last_ = Isometry::Identity();
  Isometry velocity_ = Isometry::Identity();  ///< T_last_prev^-1 style: last frame-to-frame motion
  int lost_streak_ = 0;
  std::uint64_t rng_state_ = 0x9E3779B97F4A7C15ull;
};

}  // namespace gmc::vo
