#pragma once
// The poses given out on maps that may still be rejoined, kept to revise them once they
// are. Each re-anchor starts a new map in a frame of its own (a guess); a rejoin measures
// one map's frame in another's. A crowd that loses the camera twice leaves three maps:
// the current one may find either earlier map, and every map it is joined with, directly
// or through another, has its frames revised into the frame that is kept (the older
// one's: the trajectory's first frame wins). Between two maps that end up in one frame,
// the lost frames that led from one to the other are bridged. No I/O.
#include <utility>
#include <vector>

#include "gmc/gmc/types.h"

namespace gmc::vo {

/// A pose given out earlier, now known better.
struct RevisedPose {
  long frame_number = 0;  ///< FrameTracking::frame_number of that frame (stamps may repeat)
  double stamp = 0;
  Isometry T_world_camera = Isometry::Identity();
};

/// A fraction of a motion (rotation angle and translation scaled alike).
Isometry scaledMotion(const Isometry& motion, double fraction);

/// The pose at `stamp` on the path from `from` to `to` at constant velocity (translation
/// linear in time, rotation by the same fraction of the angle).
Isometry poseBetween(const RevisedPose& from, const RevisedPose& to, double stamp);

/// Appends the poses of `lost` (number, stamp) on the path between two known poses.
void bridgePoses(const std::vector<std::pair<long, double>>& lost, const RevisedPose& from, const RevisedPose& to,
                 std::vector<RevisedPose>& out);

class MapRecords {
 public:
  /// Keeping anything (a map may still be rejoined).
  bool empty() const { return maps_.empty(); }
  void clear() { maps_.clear(); }

  /// A re-anchor: the current map (id `left`, its last tracked frame `last_tracked`) is
  /// left for a new one (id `started`), reached through the lost frames `lost_between`
  /// (guessed in the left map's frame).
  void reanchor(int left, const RevisedPose& last_tracked, int started,
                std::vector<std::pair<long, double>> lost_between);
  /// A frame of the current map, as given out (tracked, lost or re-anchored).
  void add(const RevisedPose& frame);
  /// A frame of the current map revised in place (a bridge or a start consensus).
  void revise(const RevisedPose& frame);

  /// The frame a map's poses are in now: the oldest map it has been joined with.
  int frameOf(int map) const;
  /// The current map's frame.
  int currentFrame() const;

  /// A rejoin measured T_a_b (b's frame -> a's frame) between the frames of maps `a` and
  /// `b`. The younger frame moves into the older; the poses that change (moved, and
  /// lost frames newly bridged) are appended to `revised` in frame order. Returns the
  /// frame kept.
  int join(int a, int b, const Isometry& T_a_b, std::vector<RevisedPose>& revised);

  /// Forget a map that will not be rejoined (its poses stay as given out).
  void forget(int map);

 private:
  struct MapRecord {
    int id = 0;
    int frame = 0;                                   ///< the map whose frame the poses are in
    int left = -1;                                   ///< the map left for this one
    std::vector<RevisedPose> frames;                 ///< as given out or last revised
    std::vector<std::pair<long, double>> lost_before;  ///< lost frames leading to this map
    bool bridged = false;                            ///< lost_before revised already
  };
  MapRecord* find(int map);
  const MapRecord* find(int map) const;

  std::vector<MapRecord> maps_;  ///< in the order they started
};

}  // namespace gmc::vo
