#include "gmc/datasets/source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"

namespace gmc::datasets {
namespace fs = std::filesystem;
namespace {

// MRPT decodes JPEG-compressed images (CImage serialised with JPEG) with libjpeg's default
// error handler, which calls exit(1) on corrupt data: such an object ends the process from
// inside MRPT, and no exception reaches us. While an object is being deserialised this
// names it, so the process still ends with one line naming the file and object. A fixed
// buffer, not a std::string: it must outlive static destructors.
char g_reading_object[1024];

void reportExitWhileReading() {
  if (g_reading_object[0])
    std::fprintf(stderr,
                 "error: %s: corrupt object; MRPT ended the process while decoding it "
                 "(its JPEG decoder exits on bad data)\n",
                 g_reading_object);
}

class ReadingObjectGuard {
 public:
  ReadingObjectGuard(const std::string& path, size_t object) {
    static std::once_flag registered;
    std::call_once(registered, [] { std::atexit(reportExitWhileReading); });
    std::snprintf(g_reading_object, sizeof g_reading_object, "%s: object %zu", path.c_str(), object);
  }
  ~ReadingObjectGuard() { g_reading_object[0] = '\0'; }
  ReadingObjectGuard(const ReadingObjectGuard&) = delete;
  ReadingObjectGuard& operator=(const ReadingObjectGuard&) = delete;
};

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
    // One object at a time rather than CRawlog::getActionObservationPairOrObservation():
    // that one prints and swallows every read error, so a truncated file looked complete.
    // Both rawlog formats are covered: bare observations, and (actions, sensory frame) pairs.
    auto archive = mrpt::serialization::archiveFrom(in_);
    while (true) {
      const size_t object = objects_;
      const uint64_t start = in_.getPosition();
      mrpt::serialization::CSerializable::Ptr obj;
      try {
        const ReadingObjectGuard guard(path_, object);
        archive >> obj;
      } catch (const mrpt::serialization::CExceptionEOF& e) {
        if (in_.getPosition() != start) throw corrupt(object, e);  // cut inside the object
        return atEnd();
      } catch (const std::exception& e) {
        // Truncated or corrupt: the stream position is lost and nothing after it can be
        // trusted, so the file cannot be read as a whole (std::bad_alloc lands here too,
        // when a corrupt size field asks MRPT for an absurd buffer).
        throw corrupt(object, e);
      }
      ++objects_;
      mrpt::obs::CObservation3DRangeScan::Ptr scan;
      if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
        for (const auto& o : *sf) {
          if (!scan) scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o);
          if (o && !std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
            noteOtherClass(o->GetRuntimeClass()->className);
        }
      } else if (!std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
        scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obj);
        if (!scan && obj) noteOtherClass(obj->GetRuntimeClass()->className);
      }
      if (!scan) continue;  // actions, odometry, other sensors: not ours
      seen_rgbd_ = true;
      try {
        frame = fromObservation(*scan);
      } catch (const std::exception& e) {
        throw FrameReadError(path_ + "#" + std::to_string(object) + ": " + firstLine(e.what()));
      }
      frame.name = path_ + "#" + std::to_string(object);
      return true;
    }
  }
  size_t sizeHint() const override { return 0; }

 private:
  static std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }
  InputError corrupt(size_t object, const std::exception& e) const {
    return InputError(path_ + ": object " + std::to_string(object) +
                      ": truncated or corrupt rawlog (" + firstLine(e.what()) + ")");
  }
  bool atEnd() const {
    if (seen_rgbd_) return false;
    if (other_classes_.empty()) throw InputError(path_ + ": empty rawlog (no observation)");
    throw InputError(path_ + ": no CObservation3DRangeScan in the rawlog (found " + other_classes_ + ")");
  }
  void noteOtherClass(const std::string& name) {
    if (other_classes_.find(name) == std::string::npos)
      other_classes_ += (other_classes_.empty() ? "" : ", ") + name;
  }
  std::string path_;
  mrpt::io::CFileGZInputStream in_;
  size_t objects_ = 0;  ///< objects read so far (the index in messages)
  bool seen_rgbd_ = false;
  std::string other_classes_;  ///< classes of the observations skipped, for the error
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
