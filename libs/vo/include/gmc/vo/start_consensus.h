#pragma once
// A new map's first frames judged together. One frame pair cannot tell the room from
// walkers that outnumber it and move slowly: both are rigid motions close to the
// prediction. Over a few frames they part. The room stays one rigid body in every
// frame; walkers deform, turn and go their own ways. The start consensus keeps what
// each of a young map's first frames matched of its first keyframe's landmarks and
// finds the landmark set that one rigid pose per frame explains best over all of
// them (3-point RANSAC, each sample fitted in every frame). When that set explains
// the frames clearly better than the poses given out, the odometry takes it: the
// poses are revised, the landmarks outside it become suspect. No I/O.
#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gmc/vo/background.h"
#include "gmc/vo/landmark_map.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [StartConsensus].
struct StartConsensusOptions {
  bool enabled = true;
  int frames = 12;          ///< frames after a map starts that are judged together
  int min_frames = 4;       ///< frames kept before the first judgement
  int iterations = 200;     ///< 3-point samples per judgement
  double min_gain = 1.5;    ///< taken when it explains this many times the given poses' inliers
  double min_significance = 3.0;  ///< or when it explains more by this many standard deviations of
                                  ///< a count (S - G >= z sqrt(S + G); 0 = off)
  double max_step = 0.05;   ///< m per frame: a sample whose poses step further is no camera
  double max_turn = 5.0;    ///< deg per frame, the same for rotation
  bool polish = false;      ///< each frame's pose refined on its members' pixels and depths
                            ///< (as a tracked pose), not only fitted to their 3-D points
  double inlier_pixels = 0;  ///< px: an inlier also reprojects within this (0: 3-D test only)
  double min_share = 0.5;   ///< a landmark is in the consensus when an inlier in this share
                            ///< of the frames that observed it
  int refit_samples = 5;    ///< the best samples settled on their members; the best settled set wins
  int refit_rounds = 2;     ///< membership judged this many times, each from the poses refitted on the last
  bool sample_mean_step = true;  ///< a sample's poses judged by their mean step over the frames, not step by step
  bool only_over_held_poses = false;  ///< taken only over given poses that held their frames (on average
                                      ///< [Odometry] min_static_inliers a frame), not over lost frames

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "judge a new map's first frames together (rigid consensus over time)");
    v("frames", frames, 2, 1000, "frames after a map starts that are judged together");
    v("min_frames", min_frames, 2, 1000, "frames kept before the first judgement");
    v("iterations", iterations, 1, 100000, "3-point samples per judgement");
    v("min_gain", min_gain, 1.0, 100.0,
      "the consensus is taken when its inliers over the frames are this many times the given poses'");
    v("min_significance", min_significance, 0.0, 100.0,
      "or taken when its inliers exceed the given poses' by this many count standard deviations, "
      "(S - G) >= z sqrt(S + G) (0 = off)");
    v("max_step", max_step, 0.0, 100.0, "m per frame; a consensus whose poses step further is no camera");
    v("max_turn", max_turn, 0.0, 180.0, "deg per frame; the same for rotation");
    v("polish", polish,
      "refine each frame's consensus pose on its members' pixels and depths, as tracked poses are, instead of "
      "only fitting their 3-D points (which depth quantisation dominates)");
    v("inlier_pixels", inlier_pixels, 0.0, 1000.0,
      "px; an observation is an inlier of a frame's pose only when it also reprojects within this many pixels, "
      "as well as within the 3-D threshold along the ray (0 = the 3-D threshold alone)");
    v("min_share", min_share, 0.0, 1.0,
      "a landmark belongs to the consensus when it is an inlier in this share of the frames that saw it");
    v("refit_samples", refit_samples, 1, 1000,
      "the best samples settled on their members (membership, refit); the best settled set wins");
    v("refit_rounds", refit_rounds, 1, 10,
      "membership judged this many times, each from the poses refitted on the last round's members");
    v("sample_mean_step", sample_mean_step,
      "judge a sample's poses by their mean step over the frames (max_step, max_turn), not step by step: three "
      "far points pose a frame centimetres and degrees off");
    v("only_over_held_poses", only_over_held_poses,
      "take a consensus only over given poses that held their frames (on average [Odometry] min_static_inliers "
      "inliers a frame): over lost frames it has nothing to beat, and a walker rigid over a few frames wins");
  }
};

/// One frame of a young map: what it matched of the first keyframe's landmarks.
struct ConsensusFrame {
  long frame_number = 0;
  double stamp = 0;
  Isometry T_world_given = Isometry::Identity();  ///< the pose given out (lost: the prediction)
  std::vector<std::pair<int, Eigen::Vector3d>> observations;  ///< landmark id, point in the camera frame
};

struct ConsensusResult {
  bool found = false;
  int score = 0;                       ///< inliers summed over the frames
  int given_score = 0;                 ///< the same for the poses given out
  std::vector<Isometry> T_world_camera;  ///< per kept frame, oldest first
  std::vector<int> inliers_latest;     ///< inlier landmarks in the newest frame
  std::vector<std::pair<int, Eigen::Vector3d>> consensus;  ///< landmarks in the consensus (min_share),
                                                           ///< with their first keyframe's position
  std::vector<int> outside;            ///< landmarks seen twice or more, outside it
};

class StartConsensus {
 public:
  /// `refinement`: the tracked poses' noise model, which polish refines with.
  explicit StartConsensus(const StartConsensusOptions& options = {}, const RefinementOptions& refinement = {})
      : options_(options), refinement_(refinement) {}

  /// Another sampling stream from the next map on (Xorshift64::seedFor); 0 = the built-in one.
  void reseed(std::uint64_t run_seed) { seed_ = Xorshift64::seedFor(kSeed, run_seed); }
  /// A map starts: its first keyframe's landmarks (id, world position).
  void start(const std::vector<std::pair<int, Eigen::Vector3d>>& anchors);
  void stop();
  /// Still collecting: the map is younger than `frames` frames.
  bool active() const { return active_; }
  /// Keeps a frame (observations of other landmarks are ignored); the last one stops it.
  void add(const ConsensusFrame& frame);
  const std::vector<ConsensusFrame>& frames() const { return frames_; }
  /// The best rigid consensus over the kept frames; not found before min_frames.
  /// Deterministic: the sampler restarts with every map.
  /// `camera`: the one the frames' points were back-projected with; polish and
  /// inlier_pixels need it (without it both are off).
  ConsensusResult solve(const InPlaceThreshold& threshold, const PinholeCamera* camera = nullptr);
  /// The consensus explains the kept frames clearly better than the poses given out.
  bool clearlyBetter(const ConsensusResult& result) const;
  /// The consensus may replace the given poses: its newest pose holds `min_inliers` (as a
  /// tracked pose must) and, with only_over_held_poses, the given poses held as many a frame.
  bool mayReplace(const ConsensusResult& result, int min_inliers) const;
  /// The kept frames' poses were revised (to a consensus taken): they are the given ones now.
  void revise(const std::vector<Isometry>& T_world_camera);
  /// Landmark ids renumbered by a cull (-1 = dropped).
  void remap(const std::vector<int>& new_id);

 private:
  /// Inliers of frame f at pose T (world <- camera); appends their anchor indices. With
  /// `pixels`, an inlier also reprojects within inlier_pixels and its depth is judged along the ray.
  int countInliers(size_t f, const Isometry& T, const InPlaceThreshold& threshold, const PinholeCamera* pixels,
                   std::vector<int>* in) const;

  /// b within `frames` camera steps (max_step, max_turn each) of a.
  bool plausibleStep(const Isometry& a, const Isometry& b, int frames = 1) const;
  /// Membership and per-frame poses of the set grown from `seed` (anchor indices).
  ConsensusResult settle(std::vector<int> seed, const InPlaceThreshold& threshold, const PinholeCamera* camera) const;
  /// T (world <- camera of frame f) refined on the pixels and depths of `anchors` there.
  void polishPose(size_t f, const std::vector<int>& anchors, const PinholeCamera& camera, Isometry& T) const;

  StartConsensusOptions options_;
  RefinementOptions refinement_;
  bool active_ = false;
  std::unordered_map<int, int> anchor_of_;    ///< anchor index per landmark id (built at start, remap)
  std::vector<int> anchor_id_;                 ///< landmark id per anchor
  std::vector<Eigen::Vector3d> anchor_world_;  ///< world position per anchor (as created)
  std::vector<ConsensusFrame> frames_;         ///< kept frames, observations as (anchor index, point)
  std::vector<std::vector<int>> slot_;         ///< per frame, per anchor: observation index or -1
  static constexpr std::uint64_t kSeed = 0x5eed5eedULL;
  std::uint64_t seed_ = kSeed;
  Xorshift64 rng_{kSeed};
};

}  // namespace gmc::vo
