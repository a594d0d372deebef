#include "gmc/datasets/source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"

namespace gmc::datasets {
namespace fs = std::filesystem;
namespace {

class RawlogSource : public RgbdSource {
 public:
  explicit RawlogSource(const std::string& path) : path_(path) {
    if (!fs::is_regular_file(path)) throw InputError(path + ": no such rawlog file");
    if (!in_.open(path)) throw InputError(path + ": cannot open rawlog");
    // Externalized images live in "<name>_Images" next to the rawlog (MRPT's
    // CRawlog::detectImagesDirectory builds a different path, so set it here).
    const fs::path p(path);
    mrpt::img::CImage::setImagesPathBase((p.parent_path() / (p.stem().string() + "_Images")).string());
  }

  bool next(RgbdFrame& frame) override {
    auto archive = mrpt::serialization::archiveFrom(in_);
    while (true) {
      mrpt::obs::CActionCollection::Ptr actions;
      mrpt::obs::CSensoryFrame::Ptr sf;
      mrpt::obs::CObservation::Ptr obs;
      bool more = false;
      try {
        more = mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, sf, obs, entry_);
      } catch (const std::exception& e) {
        // A corrupt object mid-file: the stream position is lost, nothing after it can be
        // trusted. Report it once, then end the sequence.
        if (failed_) return false;
        failed_ = true;
        throw FrameReadError(path_ + ": entry " + std::to_string(entry_) + ": corrupt object (" +
                             firstLine(e.what()) + ")");
      }
      if (!more) return false;
      if (sf) {
        for (const auto& o : *sf)
          if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
            obs = scan;
            break;
          }
      }
      auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obs);
      if (!scan) continue;  // other sensors, odometry, ground truth: not ours
      try {
        frame = fromObservation(*scan);
      } catch (const std::exception& e) {
        throw FrameReadError(path_ + ": entry " + std::to_string(entry_) + ": " + firstLine(e.what()));
      }
      frame.name = path_ + "#" + std::to_string(entry_);
      if (frame.camera.fx <= 0) throw FrameReadError(frame.name + ": no intrinsics");
      return true;
    }
  }
  size_t sizeHint() const override { return 0; }

 private:
  static std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }
  std::string path_;
  mrpt::io::CFileGZInputStream in_;
  size_t entry_ = 0;
  bool failed_ = false;
};

class TumFolderSource : public RgbdSource {
 public:
  TumFolderSource(const std::string& dir, const PinholeCamera& camera)
      : dir_(dir), camera_(camera), pairs_(pairTumFolder(dir).pairs) {
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
    return true;
  }
  size_t sizeHint() const override { return pairs_.size(); }

 private:
  std::string dir_;
  PinholeCamera camera_;
  std::vector<std::pair<TumListEntry, TumListEntry>> pairs_;
  size_t index_ = 0;
};

}  // namespace

std::unique_ptr<RgbdSource> openRgbdSource(const std::string& path, const PinholeCamera& camera) {
  if (fs::is_directory(path)) return std::make_unique<TumFolderSource>(path, camera);
  if (!fs::exists(path)) throw InputError(path + ": no such file or folder");
  return std::make_unique<RawlogSource>(path);
}

}  // namespace gmc::datasets
