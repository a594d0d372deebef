#pragma once
// Poses revised in hindsight. A frame's pose can rest on landmarks that are later seen
// moving: a young map that followed a group walking in step with the camera, until the
// room it uncovered took over (generated `synchronous`: 20 frames of standing still while
// the camera walked 0.6 m). Its map then holds the room, and the frames before can be
// posed again on it. Each given pose waits lag_frames (a second: the time landmarks need
// for static evidence); then, if more of the landmarks that held it have been seen moving
// since than are still trusted (dropped ones say nothing: a moving camera leaves what it
// saw), its frame is matched by descriptor against the landmarks in today's view not
// seen moving, and the pose that most of them agree with replaces the given one
// when it is clearly better supported (the start consensus' gain and significance test)
// and moves it by more than min_shift. The frames before a revised one that could not be
// judged on their own (too few of today's landmarks in their view) are posed from it,
// frame by frame on the room it found, back to the first frame whose pose that room
// already holds, or to a lost frame: lost frames are left to the bridging of lost
// stretches ([Odometry] revise_lost), since posing them one from the next follows what
// made them lost (Bonn 240-389, frames 80-87: 26 cm). Only the written trajectory changes
// (revisions); the live pose, the map and the masks keep what was given. No I/O.
#include <deque>
#include <optional>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/vo/background.h"
#include "gmc/vo/in_place_threshold.h"
#include "gmc/vo/landmark_map.h"
#include "gmc/vo/map_records.h"
#include "gmc/vo/point_correspondences.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [Hindsight].
struct HindsightOptions {
  bool enabled = true;
  int lag_frames = 30;           ///< frames a pose waits before it is judged again
  double min_shift = 0.03;       ///< m: a revision nearer than this to the given pose is not made
  int min_inliers = 20;          ///< today's landmarks agreeing with a revised pose, at least ...
  double min_gain = 1.5;         ///< ... this many times those agreeing with the given pose ...
  double min_significance = 3;   ///< ... and S - G >= z sqrt(S + G) (count standard deviations)
  int chain_min_inliers = 10;    ///< room points an earlier frame's pose must agree with
  int ransac_iterations = 300;   ///< 3-point samples per judgement
  int max_reference = 800;       ///< today's landmarks matched per judgement (static evidence first)

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "revise given poses once the map shows what held them was moving");
    v("lag_frames", lag_frames, 1, 100000, "frames a pose waits before it is judged again");
    v("min_shift", min_shift, 0.0, 100.0, "m: a revision nearer than this to the given pose is not made");
    v("min_inliers", min_inliers, 3, 100000, "landmarks that must agree with a revised pose");
    v("min_gain", min_gain, 1.0, 1000.0, "a revised pose needs this many times the given pose's agreeing landmarks");
    v("min_significance", min_significance, 0.0, 100.0,
      "and S - G >= z sqrt(S + G) agreeing landmarks (count standard deviations)");
    v("chain_min_inliers", chain_min_inliers, 3, 100000,
      "room points an earlier frame's pose must agree with when posed from a revised one");
    v("ransac_iterations", ransac_iterations, 1, 100000, "3-point samples per judgement");
    v("max_reference", max_reference, 3, 10000000, "landmarks matched per judgement (static evidence first)");
  }
};

/// A frame as given out, kept for a later judgement.
struct HindsightFrame {
  long frame_number = 0;
  double stamp = 0;
  features::FeatureSet features;
  Isometry T_world_camera = Isometry::Identity();
  std::vector<int> pose_landmarks;  ///< landmark ids that held its pose (-1: dropped since)
  bool lost = false;                ///< no pose measured: never judged, and nothing is posed through it
};

class HindsightPoser {
 public:
  HindsightPoser(const HindsightOptions& options, const RefinementOptions& refinement,
                 const InPlaceThreshold& threshold)
      : options_(options), refinement_(refinement), threshold_(threshold) {}
  const HindsightOptions& options() const { return options_; }
  /// Another sampling stream (Xorshift64::seedFor); 0 = the built-in one.
  void reseed(std::uint64_t run_seed) { run_seed_ = run_seed; }

  /// The world frame moved (a new map, a start consensus, a rejoin): the frames kept can
  /// no longer be compared with today's landmarks.
  void reset();
  /// A cull compacted the map (remap: old id -> new id, -1 = dropped).
  void renumber(const std::vector<int>& remap);
  /// A frame given out at `T_world_current` (its own pose: today's view); returns the
  /// revisions it makes, of the frame lag_frames back and of frames before it, in order.
  std::vector<RevisedPose> add(HindsightFrame&& frame, const LandmarkMap& map, const Isometry& T_world_current,
                               const PinholeCamera& camera, const features::Frontend& frontend, double max_depth);
  size_t kept() const { return waiting_.size() + passed_.size(); }  ///< frames held (tests)

 private:
  /// Of the landmarks that held its pose and still live, no more are suspect at `stamp`
  /// than trusted (a map's first frame, held by none, is not held).
  bool stillHeld(const HindsightFrame& frame, const LandmarkMap& map, double stamp) const;
  /// The frame's pose on today's trusted landmarks, when clearly better than the given one;
  /// `room` gets the frame's features that agree with it.
  std::optional<Isometry> judge(const HindsightFrame& frame, const LandmarkMap& map, const Isometry& T_world_current,
                                const PinholeCamera& camera, const features::Frontend& frontend, double max_depth,
                                double stamp, std::vector<int>& room);
  /// The passed frames before `from` (newest first), each posed from the next on its room.
  std::vector<RevisedPose> chainBack(HindsightFrame from, std::vector<int> room, const PinholeCamera& camera,
                                     const features::Frontend& frontend);
  /// fitCorrespondences with this judgement's own sampling stream; the pose (T_world_camera).
  Isometry fit(const PointCorrespondences& c, const std::vector<int>& pool, const Isometry& fallback,
               const PinholeCamera& camera, std::uint64_t sample_seed) const;

  HindsightOptions options_;
  RefinementOptions refinement_;
  InPlaceThreshold threshold_;
  std::uint64_t run_seed_ = 0;
  std::deque<HindsightFrame> waiting_;  ///< given, not judged yet (newest last)
  std::deque<HindsightFrame> passed_;   ///< judged, not revised: a later revision may pose them
};

}  // namespace gmc::vo
