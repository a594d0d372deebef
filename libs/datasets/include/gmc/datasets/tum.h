#pragma once
// TUM RGB-D text formats: file lists (rgb.txt, depth.txt), trajectories
// (timestamp tx ty tz qx qy qz qw), and timestamp association.
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gmc/gmc/types.h"

namespace gmc::datasets {

/// A malformed or unreadable input file; the message names the file and line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TumListEntry {
  double stamp = 0;
  std::string path;  ///< as written in the list (relative to the list's folder)
  size_t line = 0;   ///< line in the list file, for messages (0: not read from a file)
};

/// Reads rgb.txt / depth.txt. Comment lines start with '#'.
std::vector<TumListEntry> readTumList(const std::string& path);
void writeTumList(const std::string& path, const std::vector<TumListEntry>& entries,
                  const std::string& header_comment);

/// The RGB frames of a TUM-layout folder (rgb.txt, depth.txt) paired with depth frames as
/// associate.py does (see associate()), in RGB stamp order.
struct TumFolderPairs {
  std::vector<std::pair<TumListEntry, TumListEntry>> pairs;  ///< (rgb, depth)
  std::vector<TumListEntry> unpaired_rgb;                    ///< no depth within max_dt
};
TumFolderPairs pairTumFolder(const std::string& dir, double max_dt = 0.02);

struct StampedPose {
  double stamp = 0;
  Isometry pose = Isometry::Identity();  ///< T_world_camera (optical frame)
};

/// Reads a TUM trajectory; separators may be spaces, tabs or commas (as TUM's tools).
/// Poses are sorted by stamp. InputError naming file and line for a malformed line, a
/// quaternion that is not unit length or a coordinate beyond 1e9 m.
std::vector<StampedPose> readTumTrajectory(const std::string& path);
/// Writes atomically, stamps with 6 decimals, poses with 9 significant digits.
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

/// The frame a ground-truth file gives poses of: "camera" (TUM: the optical frame) or
/// "bonn" (the Bonn RGB-D Dynamic dataset: the motion-capture marker body).
inline const std::vector<std::string> kGroundTruthFrames = {"camera", "bonn"};

/// Bonn marker-body poses -> camera optical-frame poses, as the dataset publishes:
/// T_camera = T_ros · T_gt · T_ros · T_m, T_m's rotation projected onto the nearest
/// rotation (the published block is not orthonormal). See doc/evaluation.md.
std::vector<StampedPose> bonnBodyToCamera(const std::vector<StampedPose>& body_poses);

/// readTumTrajectory() in the camera frame: converted by `frame` ("camera": as read).
/// Throws std::invalid_argument for another frame name.
std::vector<StampedPose> readGroundTruth(const std::string& path, const std::string& frame);

/// The robot base's trajectory from the camera's: T_w'_base = T_base_camera · T_w_camera ·
/// T_base_camera⁻¹, whose world w' is the base at the pose where the camera's world w
/// was (the first base pose when w is the first camera pose).
std::vector<StampedPose> baseTrajectory(const std::vector<StampedPose>& camera_trajectory,
                                        const Isometry& T_base_camera);
/// Writes baseTrajectory() to `path` when the camera has a base (a sensorPose other than
/// the identity); does nothing otherwise.
void writeBaseTrajectory(const std::string& path, const std::vector<StampedPose>& camera_trajectory,
                         const std::optional<Isometry>& T_base_camera);

/// TUM's associate.py: candidate pairs with |a - b| < max_dt, taken greedily by
/// increasing |a - b|, each stamp used once; result sorted by the first stamp.
std::vector<std::pair<size_t, size_t>> associate(const std::vector<double>& first,
                                                 const std::vector<double>& second,
                                                 double max_dt = 0.02);

/// Pose at `stamp`, interpolated between the neighbouring poses (slerp); nullopt outside
/// the trajectory or across a gap longer than max_gap seconds.
std::optional<Isometry> interpolatePose(const std::vector<StampedPose>& trajectory, double stamp,
                                        double max_gap = 0.1);

}  // namespace gmc::datasets
