#include "gmc/datasets/source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <filesystem>

#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/rawlog_stream.h"
#include "gmc/datasets/tum.h"
#include "gmc/datasets/undistort.h"

namespace gmc::datasets {
namespace fs = std::filesystem;
namespace {

/// CObservation3DRangeScan's own frame is +X forward, +Y left, +Z up (its sensorPose is
/// given for that frame); ours is the optical frame (x right, y down, z forward).
Isometry mrptCameraFromOptical() {
  Isometry T = Isometry::Identity();
  T.linear() << 0, 0, 1,  //
      -1, 0, 0,           //
      0, -1, 0;
  return T;
}

/// T_base_camera (optical) of a scan mounted with a sensorPose other than the identity.
std::optional<Isometry> baseCameraOf(const mrpt::obs::CObservation3DRangeScan& scan) {
  const auto& p = scan.sensorPose;
  if (p == mrpt::poses::CPose3D()) return std::nullopt;
  Isometry T_base_mrpt = Isometry::Identity();
  T_base_mrpt.matrix() = p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  return T_base_mrpt * mrptCameraFromOptical();
}

class RawlogSource : public RgbdSource {
 public:
  RawlogSource(const std::string& path, SensorSelection sensors)
      : reader_(path), selector_(sensors), labels_(sensors.labels) {}

  void setObjectSink(RawlogObjectSink* sink) override { sink_ = sink; }

  bool next(RgbdFrame& frame) override {
    while (pending_.empty()) {
      mrpt::serialization::CSerializable::Ptr obj;
      if (!reader_.next(obj)) return atEnd();
      if (sink_) sink_->objectRead(obj);
      const size_t object = reader_.objectsRead() - 1;
      noteClasses(obj);
      for (const auto& scan : rgbdScansOf(obj))
        if (selector_.selects(scan->sensorLabel)) pending_.push_back({scan, object});
    }
    const auto [scan, object] = pending_.front();
    pending_.erase(pending_.begin());
    seen_rgbd_ = true;
    const std::string name = reader_.path() + "#" + std::to_string(object);
    try {
      frame = fromObservation(*scan);
    } catch (const std::exception& e) {
      throw FrameReadError(name + ": " + firstLine(e.what()));
    }
    frame.name = name;
    frame.sensor_label = scan->sensorLabel;
    frame.base_camera = baseCameraOf(*scan);
    frame.observation = scan;
    base_camera_ = frame.base_camera;
    return true;
  }
  size_t sizeHint() const override { return 0; }

 private:
  static std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }
  bool atEnd() const {
    if (seen_rgbd_) return false;
    const std::string& path = reader_.path();
    if (!any_observation_) throw InputError(path + ": empty rawlog (no observation)");
    if (!labels_.empty() && !scan_labels_.empty())
      throw InputError(path + ": no CObservation3DRangeScan labelled " + joined(labels_) +
                       " (the rawlog's RGB-D sensors: " + joined(scan_labels_) + ")");
    throw InputError(path + ": no CObservation3DRangeScan in the rawlog (found " + joined(classes_) + ")");
  }
  /// Classes and RGB-D labels met, for the message when nothing was selected.
  void noteClasses(const mrpt::serialization::CSerializable::Ptr& obj) {
    auto note = [](std::vector<std::string>& list, const std::string& name) {
      if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
    };
    std::vector<mrpt::serialization::CSerializable::Ptr> members;
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
      members.assign(sf->begin(), sf->end());
    else if (obj && !std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
      members.push_back(obj);
    any_observation_ = any_observation_ || !members.empty();
    for (const auto& m : members)
      if (m && !std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(m))
        note(classes_, m->GetRuntimeClass()->className);
    for (const auto& scan : rgbdScansOf(obj)) note(scan_labels_, "'" + scan->sensorLabel + "'");
  }
  static std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
    return out;
  }

  struct Pending {
    mrpt::obs::CObservation3DRangeScan::Ptr scan;
    size_t object;
  };
  RawlogReader reader_;
  SensorSelector selector_;
  std::vector<std::string> labels_;  ///< as configured, for messages
  RawlogObjectSink* sink_ = nullptr;
  std::vector<Pending> pending_;     ///< selected scans of the last object not yet returned
  bool seen_rgbd_ = false, any_observation_ = false;
  std::vector<std::string> classes_, scan_labels_;
};

class TumFolderSource : public RgbdSource {
 public:
  TumFolderSource(const std::string& dir, const PinholeCamera& camera, const LensDistortion& distortion,
                  const LabelMasks& label_masks)
      : dir_(dir), camera_(camera), label_masks_(label_masks), pairs_(pairTumFolder(dir).pairs) {
    if (!label_masks_.folder.empty() && !distortion.none())
      throw InputError(dir + ": [Dataset] label_masks need undistort = none (masks are not undistorted)");
    if (!distortion.none()) undistorter_.emplace(camera, distortion);
    if (pairs_.empty())
      throw InputError(dir + ": no RGB frame has a depth frame within 0.02 s");
  }

  bool next(RgbdFrame& frame) override {
    if (index_ >= pairs_.size()) return false;
    const auto& [rgb, depth] = pairs_[index_++];
    const std::string rgb_path = (fs::path(dir_) / rgb.path).string();
    const std::string depth_path = (fs::path(dir_) / depth.path).string();
    // Messages name the image and the list line it came from.
    const std::string rgb_name = rgb_path + " (rgb.txt:" + std::to_string(rgb.line) + ")";
    const std::string depth_name = depth_path + " (depth.txt:" + std::to_string(depth.line) + ")";
    frame.rgb = cv::imread(rgb_path, cv::IMREAD_COLOR);
    if (frame.rgb.empty()) throw FrameReadError(rgb_name + ": missing or unreadable image");
    frame.depth = cv::imread(depth_path, cv::IMREAD_ANYDEPTH);
    if (frame.depth.empty()) throw FrameReadError(depth_name + ": missing or unreadable depth image");
    if (frame.depth.type() != CV_16UC1)
      throw FrameReadError(depth_name + ": depth must be a 16-bit single-channel PNG");
    if (frame.depth.size() != frame.rgb.size())
      throw FrameReadError(depth_name + ": depth is " + std::to_string(frame.depth.cols) + "x" +
                           std::to_string(frame.depth.rows) + ", RGB is " +
                           std::to_string(frame.rgb.cols) + "x" + std::to_string(frame.rgb.rows));
    frame.stamp = rgb.stamp;
    frame.depth_units = 1.0 / 5000.0;
    frame.camera = camera_;
    frame.camera.width = frame.rgb.cols;
    frame.camera.height = frame.rgb.rows;
    frame.name = rgb.path;
    frame.pixel_labels.clear();
    if (!label_masks_.folder.empty()) {
      const std::string mask_path =
          (fs::path(dir_) / label_masks_.folder / fs::path(rgb.path).filename()).string();
      cv::Mat mask = cv::imread(mask_path, cv::IMREAD_GRAYSCALE);
      if (mask.empty()) throw FrameReadError(mask_path + ": missing or unreadable label mask");
      if (mask.size() != frame.rgb.size())
        throw FrameReadError(mask_path + ": label mask is " + std::to_string(mask.cols) + "x" +
                             std::to_string(mask.rows) + ", RGB is " + std::to_string(frame.rgb.cols) + "x" +
                             std::to_string(frame.rgb.rows));
      frame.pixel_labels.emplace_back(label_masks_.label, mask);
    }
    if (undistorter_) undistorter_->apply(frame);
    return true;
  }
  size_t sizeHint() const override { return pairs_.size(); }

 private:
  std::string dir_;
  PinholeCamera camera_;
  LabelMasks label_masks_;
  std::vector<std::pair<TumListEntry, TumListEntry>> pairs_;
  std::optional<Undistorter> undistorter_;
  size_t index_ = 0;
};

}  // namespace

std::unique_ptr<RgbdSource> openRgbdSource(const std::string& path, const PinholeCamera& camera,
                                           const SensorSelection& sensors, const LensDistortion& distortion,
                                           const LabelMasks& label_masks) {
  if (fs::is_directory(path)) return std::make_unique<TumFolderSource>(path, camera, distortion, label_masks);
  if (!fs::exists(path)) throw InputError(path + ": no such file or folder");
  if (!label_masks.folder.empty())
    throw InputError(path + ": [Dataset] label_masks applies to TUM folders (a rawlog's scans carry their own "
                            "pixelLabels)");
  return std::make_unique<RawlogSource>(path, sensors);
}

}  // namespace gmc::datasets
