#include "gmc/datasets/rawlog_stream.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <sstream>

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

std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }

}  // namespace

struct RawlogReader::Stream {
  mrpt::io::CFileGZInputStream in;
};

RawlogReader::RawlogReader(const std::string& path) : path_(path), stream_(std::make_unique<Stream>()) {
  if (!fs::is_regular_file(path)) throw InputError(path + ": no such rawlog file");
  if (!stream_->in.open(path)) throw InputError(path + ": cannot open rawlog");
  const fs::path p(path);
  mrpt::img::CImage::setImagesPathBase((p.parent_path() / (p.stem().string() + "_Images")).string());
}

RawlogReader::~RawlogReader() = default;

bool RawlogReader::next(mrpt::serialization::CSerializable::Ptr& object) {
  // One object at a time rather than CRawlog::getActionObservationPairOrObservation():
  // that one prints and swallows every read error, so a truncated file looked complete.
  auto archive = mrpt::serialization::archiveFrom(stream_->in);
  const uint64_t start = stream_->in.getPosition();
  auto corrupt = [&](const std::exception& e) {
    return InputError(path_ + ": object " + std::to_string(objects_) +
                      ": truncated or corrupt rawlog (" + firstLine(e.what()) + ")");
  };
  try {
    const ReadingObjectGuard guard(path_, objects_);
    archive >> object;
  } catch (const mrpt::serialization::CExceptionEOF& e) {
    if (stream_->in.getPosition() != start) throw corrupt(e);  // cut inside the object
    return false;
  } catch (const std::exception& e) {
    // Truncated or corrupt: the stream position is lost and nothing after it can be
    // trusted (std::bad_alloc lands here too, when a corrupt size field asks MRPT for an
    // absurd buffer).
    throw corrupt(e);
  }
  ++objects_;
  return true;
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> rgbdScansOf(
    const mrpt::serialization::CSerializable::Ptr& object) {
  using Scan = mrpt::obs::CObservation3DRangeScan;
  std::vector<Scan::Ptr> scans;
  if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
    for (const auto& o : *sf)
      if (auto scan = std::dynamic_pointer_cast<Scan>(o)) scans.push_back(scan);
  } else if (auto scan = std::dynamic_pointer_cast<Scan>(object)) {
    scans.push_back(scan);
  }
  return scans;
}

bool SensorSelector::selects(const std::string& label) {
  auto& labels = selection_.labels;
  if (labels.empty()) {
    if (!selection_.single_camera) return true;
    labels.push_back(label);  // the first camera met is the one
  }
  if (selection_.single_camera) return label == labels.front();
  return std::find(labels.begin(), labels.end(), label) != labels.end();
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

}  // namespace gmc::datasets
