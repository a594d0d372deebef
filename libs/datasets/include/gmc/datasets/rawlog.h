#pragma once
// MRPT rawlogs of CObservation3DRangeScan (observation-only format).
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <memory>
#include <string>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/frame.h"

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

/// Writes a rawlog to a temporary file; close() renames it into place, and destruction
/// without close() removes it (and the images folder when this writer created it). With
/// externalize_images, colour images go to "<name>_Images/" next to the rawlog, as MRPT's
/// rawlog-grabber does for long sequences.
class RawlogWriter {
 public:
  explicit RawlogWriter(const std::string& path, bool externalize_images = false);
  ~RawlogWriter();
  void write(const RgbdFrame& frame, const std::string& sensor_label = "RGBD");
  void write(mrpt::obs::CObservation3DRangeScan& obs);
  void close();
  size_t count() const { return count_; }

 private:
  std::string path_, images_dir_;
  bool externalize_, created_images_dir_ = false;
  AtomicFile file_;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> out_;
  size_t count_ = 0;
};

}  // namespace gmc::datasets
