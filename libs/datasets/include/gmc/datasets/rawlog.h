#pragma once
// MRPT rawlogs of CObservation3DRangeScan (observation-only format).
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <deque>
#include <memory>
#include <string>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/frame.h"
#include "gmc/datasets/rawlog_stream.h"

namespace mrpt::io {
class CFileGZOutputStream;
}

namespace gmc::datasets {

/// RGB-D frame -> observation: intensity image (BGR), range image holding the raw depth
/// values with rangeUnits = depth_units, range_is_depth, intrinsics, timestamp.
mrpt::obs::CObservation3DRangeScan::Ptr toObservation(const RgbdFrame& frame,
                                                      const std::string& sensor_label = "RGBD");
/// Observation -> frame (loads externally stored images). Throws std::runtime_error
/// naming the problem when the observation is not a usable RGB-D frame: no range or no
/// intensity image, ranges instead of depth, an external image file that is missing,
/// intensity and range images of different sizes, an image that is not 8-bit grey or
/// colour, non-positive rangeUnits or intrinsics.
RgbdFrame fromObservation(const mrpt::obs::CObservation3DRangeScan& obs);

/// The observation to filter for `frame`: the rawlog's own (so every field it carries
/// passes on), or a new one from the frame (folders; a frame whose stamp was changed).
mrpt::obs::CObservation3DRangeScan::Ptr observationOf(const RgbdFrame& frame);

/// Writes a rawlog to a temporary file; close() renames it into place, and destruction
/// without close() removes it (and the images folder when this writer created it). With
/// externalize_images, colour images go to "<name>_Images/" next to the rawlog, as MRPT's
/// rawlog-grabber does for long sequences.
///
/// As the object sink of a rawlog source it loses nothing: every object read is queued
/// and written unchanged and in order; a scan in it that became a frame is settled by
/// write(scan) (written as the filters left it) or drop(scan) (removed from its sensory
/// frame, or the whole observation). An object goes out once a scan of a later object is
/// settled, or at close(); a scan never settled (a frame the app skipped) goes out as read. Images stored outside the input rawlog are copied
/// into this rawlog's "<name>_Images/" under the same relative names.
class RawlogWriter : public RawlogObjectSink {
 public:
  explicit RawlogWriter(const std::string& path, bool externalize_images = false);
  ~RawlogWriter() override;
  void write(const RgbdFrame& frame, const std::string& sensor_label = "RGBD");
  /// A scan of a queued object: settles it; any other observation is written now.
  void write(mrpt::obs::CObservation3DRangeScan& obs);
  /// A scan of a queued object that a filter dropped; nothing for any other.
  void drop(const mrpt::obs::CObservation3DRangeScan& obs);
  void objectRead(const mrpt::serialization::CSerializable::Ptr& object) override;
  /// Writes what is still queued, then renames the rawlog into place.
  void close();
  /// Objects written (sensory frames and action collections count one each).
  size_t count() const { return count_; }

 private:
  struct Queued {
    mrpt::serialization::CSerializable::Ptr object;
    bool dropped = false;  ///< a bare observation a filter dropped
  };
  /// Index in queue_ of the object holding `obs`, or queue_.size().
  size_t queuedIndexOf(const mrpt::obs::CObservation3DRangeScan& obs) const;
  /// Writes the queued objects before queue_[index]: a scan of a later object was settled,
  /// so theirs are final. The object holding that scan waits, others in it may follow.
  void flushBefore(size_t index);
  void writeObject(const mrpt::serialization::CSerializable& object);
  void copyExternalImages(const mrpt::serialization::CSerializable::Ptr& object);
  void ensureImagesDir();

  std::string path_, images_dir_;
  bool externalize_, created_images_dir_ = false;
  AtomicFile file_;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> out_;
  std::deque<Queued> queue_;
  size_t count_ = 0;
};

}  // namespace gmc::datasets
