#pragma once
// Rawlogs object by object, in both formats (bare observations; action collections and
// sensory frames), so that tools can pass on every object they do not filter.
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CSerializable.h>

#include <memory>
#include <string>
#include <vector>

namespace gmc::datasets {

/// Which RGB-D scans become frames, by CObservation::sensorLabel.
struct SensorSelection {
  std::vector<std::string> labels;  ///< empty = every CObservation3DRangeScan
  /// One camera only: the first label of `labels` (or, when empty, the first scan's label).
  bool single_camera = false;
};

/// Reads a rawlog one object at a time. Externalised images resolve against
/// "<name>_Images" next to the rawlog (MRPT's own guess builds another path).
class RawlogReader {
 public:
  /// Throws InputError when the file is missing or cannot be opened.
  explicit RawlogReader(const std::string& path);
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// Next object; false at a clean end. Throws InputError naming the object when the file
  /// is truncated or corrupt there (nothing after it can be trusted).
  bool next(mrpt::serialization::CSerializable::Ptr& object);
  /// Index of the next object (objects read so far).
  size_t objectsRead() const { return objects_; }
  const std::string& path() const { return path_; }

 private:
  struct Stream;
  std::string path_;
  std::unique_ptr<Stream> stream_;
  size_t objects_ = 0;
};

/// The RGB-D scans `object` holds (itself, or the observations of a sensory frame), in order.
std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> rgbdScansOf(
    const mrpt::serialization::CSerializable::Ptr& object);

/// Applies a SensorSelection to the scans met in order (remembers the first label for
/// single_camera with no label given).
class SensorSelector {
 public:
  explicit SensorSelector(SensorSelection selection) : selection_(std::move(selection)) {}
  bool selects(const std::string& label);

 private:
  SensorSelection selection_;
};

/// Receives every object a rawlog source reads, before the scans in it become frames
/// (RawlogWriter passes them on, see there).
class RawlogObjectSink {
 public:
  virtual ~RawlogObjectSink() = default;
  virtual void objectRead(const mrpt::serialization::CSerializable::Ptr& object) = 0;
};

/// Comma-separated list -> trimmed, non-empty items ("a, b" -> {"a", "b"}).
std::vector<std::string> splitList(const std::string& text);

}  // namespace gmc::datasets
