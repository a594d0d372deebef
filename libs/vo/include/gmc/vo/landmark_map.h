#pragma once
// A persistent local map of 3-D landmarks (keyframe features with world positions and
// ORB descriptors) and the static evidence each one gathers over time: re-observed at
// the same world position over seconds, a landmark is static; seen moving, it is
// dynamic and stays suspect for a while. The odometry matches every frame against the
// landmarks visible from its predicted pose and trusts them by their evidence.
// No I/O; one map per odometry.
#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/gmc/gmc.h"
#include "gmc/vo/in_place_threshold.h"

namespace gmc::vo {

/// INI section [LocalMap].
struct LocalMapOptions {
  int max_landmarks = 20000;      ///< oldest-seen landmarks are dropped beyond this
  double static_seconds = 1.0;    ///< re-observed in place over at least this long ...
  int static_min_hits = 5;        ///< ... and in this many frames: static evidence
  double suspect_seconds = 3.0;   ///< a landmark seen moving is distrusted this long
  double young_weight = 0.1;      ///< trust in a landmark without evidence yet (static = 1)
  double in_place_factor = 2.0;   ///< re-observed within this x the inlier threshold = in place
  double moved_factor = 4.0;      ///< displaced above this x the inlier threshold twice in a
                                  ///< row (not labelled dynamic): dropped
  int cull_after_visible = 20;    ///< judge a landmark's re-finding rate after this many views
  double cull_found_ratio = 0.2;  ///< ... and drop it when found in fewer of them
  int view_margin_px = 10;        ///< landmarks projecting this far outside still count as visible

  template <class V>
  void visit(V& v) {
    v("max_landmarks", max_landmarks, 100, 10000000, "landmarks kept (least recently seen dropped)");
    v("static_seconds", static_seconds, 0.0, 3600.0,
      "s a landmark must be re-observed in place before it counts as static");
    v("static_min_hits", static_min_hits, 1, 100000,
      "frames a landmark must be re-observed in place before it counts as static");
    v("suspect_seconds", suspect_seconds, 0.0, 3600.0, "s a landmark seen moving stays distrusted");
    v("young_weight", young_weight, 0.0, 1.0, "trust in a landmark without static evidence (static = 1)");
    v("in_place_factor", in_place_factor, 0.1, 1000.0,
      "re-observed within this many inlier thresholds of its position: in place");
    v("moved_factor", moved_factor, 1.0, 1000.0,
      "displaced above this many inlier thresholds twice in a row (not labelled dynamic): dropped");
    v("cull_after_visible", cull_after_visible, 1, 100000,
      "views after which a rarely re-found landmark is dropped");
    v("cull_found_ratio", cull_found_ratio, 0.0, 1.0,
      "landmarks re-found in fewer than this fraction of their views are dropped");
    v("view_margin_px", view_margin_px, 0, 1000, "px outside the image still searched");
  }
};

/// How far a landmark is trusted to be part of the static world.
enum class Evidence : std::uint8_t { Suspect = 0, Young = 1, Static = 2 };

struct Landmark {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world frame (m)
  std::array<std::uint8_t, 32> descriptor{};           ///< ORB of the creating keyframe
  double evidence_since = 0;     ///< stamp from which it has been seen in place
  double last_seen_in_place = 0;  ///< last stamp it was re-observed in place
  double suspect_until = -std::numeric_limits<double>::infinity();
  int hits_in_place = 0;         ///< frames re-observed in place since evidence_since
  int moved_streak = 0;          ///< consecutive observations out of place
  int visible = 0, found = 0;    ///< projected into a tracked frame / matched there
  int keyframe = -1;             ///< keyframe that created it
  /// The observation that placed it (camera frame) and its stamp: a ground truth judges
  /// its matches with these, independent of the estimated poses (map_matches.csv).
  Eigen::Vector3d origin_point = Eigen::Vector3d::Zero();
  double origin_stamp = 0;
  bool alive = true;
  bool known_dynamic = false;    ///< placed on a pixel given as known dynamic: never trusted
};

/// One match of a frame against the map, as the evidence update needs it.
struct LandmarkObservation {
  int landmark = -1;
  Eigen::Vector3d point_cur = Eigen::Vector3d::Zero();  ///< current camera frame (m)
  MotionLabel label = MotionLabel::Undecided;           ///< GMC's decision this frame
};

/// The landmarks visible from a pose, as a reference FeatureSet for guided matching:
/// points in that pose's camera frame, keypoints at their projections.
struct LandmarkView {
  features::FeatureSet set;
  std::vector<int> ids;  ///< landmark id per entry of `set`
};

class LandmarkMap {
 public:
  explicit LandmarkMap(const LocalMapOptions& options = {}) : options_(options) {}
  const LocalMapOptions& options() const { return options_; }

  void clear() { landmarks_.clear(); }
  size_t size() const { return landmarks_.size(); }  ///< including dropped slots
  size_t numAlive() const;
  size_t numStatic(double stamp) const;  ///< landmarks with static evidence at `stamp`
  const Landmark& operator[](int id) const { return landmarks_[static_cast<size_t>(id)]; }
  /// The landmark lies on a moving object by outside knowledge: suspect for good.
  void markKnownDynamic(int id) { landmarks_[static_cast<size_t>(id)].known_dynamic = true; }

  Evidence evidence(int id, double stamp) const;
  /// Trust used to weigh a match: 0 suspect, young_weight young, 1 static.
  double weight(int id, double stamp) const;
  /// Whether the landmarks that held a pose still hold it at `stamp`: no more of them are
  /// alive and seen moving since (suspect) than alive and trusted. Dropped ones (culled,
  /// or id < 0) say nothing: a moving camera leaves most of what it saw.
  bool stillHold(const std::vector<int>& ids, double stamp) const;

  /// Landmarks in front of a camera at T_world_camera and inside its image.
  void view(const Isometry& T_world_camera, const PinholeCamera& camera, double max_depth,
            LandmarkView& out) const;

  /// Adds every feature with depth that `matched` does not flag, at T_world_camera.
  /// Features labelled Dynamic start suspect. Returns (feature index, landmark id) pairs.
  std::vector<std::pair<int, int>> addFeatures(const features::FeatureSet& features, const std::vector<std::uint8_t>& matched,
                               const std::vector<MotionLabel>& labels, const Isometry& T_world_camera,
                               double stamp, int keyframe);

  /// Evidence update from a tracked frame at T_world_camera: in place (within
  /// in_place_factor thresholds, not labelled dynamic) adds evidence; out of place and
  /// labelled dynamic, it moved: it becomes suspect and its evidence restarts where it
  /// was seen. A suspect landmark follows what it is seen on. Beyond moved_factor
  /// thresholds twice in a row without GMC's dynamic label, it is dropped (a recurring
  /// wrong match, or a walker GMC did not see). `visible` are the ids searched for.
  void observe(const std::vector<LandmarkObservation>& observations, const std::vector<int>& visible,
               const Isometry& T_world_camera, double stamp, const InPlaceThreshold& threshold);

  /// The live landmarks not suspect at `stamp`, young or static (kept when a map is left).
  std::vector<Landmark> landmarksNotSeenMoving(double stamp) const;
  /// The same, in place (valid until the map changes).
  std::vector<const Landmark*> notSeenMoving(double stamp) const;
  /// Moves every landmark into another world frame: p <- T_new_old * p.
  void transform(const Isometry& T_new_old);
  /// Appends landmarks as they are (positions in this map's frame, evidence kept).
  void adopt(const std::vector<Landmark>& landmarks);

  /// Landmarks made by keyframes after `keyframe` go (placed from poses since revised).
  void dropKeyframesAfter(int keyframe);
  /// A young map's start consensus (StartConsensus) was taken: its landmarks go back to
  /// where the first keyframe put them, in place since `since`; those outside it are
  /// suspect; landmarks of later keyframes were placed from poses now revised and go.
  void judgeStart(const std::vector<std::pair<int, Eigen::Vector3d>>& consensus, const std::vector<int>& outside,
                  int first_keyframe, double since, double stamp);

  /// A landmark found on something that moves: suspect from `stamp` on.
  void distrust(int id, double stamp);
  /// Moves a landmark (windowed optimisation).
  void setPosition(int id, const Eigen::Vector3d& p) { landmarks_[static_cast<size_t>(id)].position = p; }

  /// Drops landmarks rarely re-found (static ones excepted: occluded by a crowd they are
  /// in view without being found), then the least recently seen beyond max_landmarks.
  /// When dropped slots outnumber live ones the storage is compacted and ids change:
  /// the result then maps every old id to its new one (-1 = dropped); empty otherwise.
  std::vector<int> cull(double stamp);

 private:
  LocalMapOptions options_;
  std::vector<Landmark> landmarks_;
};

}  // namespace gmc::vo
