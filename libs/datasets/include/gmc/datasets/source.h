#pragma once
// Sequential RGB-D input: an MRPT rawlog or a TUM-layout folder, one frame at a time.
#include <memory>
#include <stdexcept>
#include <string>

#include "gmc/datasets/frame.h"

namespace gmc::datasets {

/// One frame could not be read; the sequence can go on (the message names the frame).
class FrameReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RgbdSource {
 public:
  virtual ~RgbdSource() = default;
  /// Next frame; false at the end. Throws FrameReadError for a bad frame (skippable),
  /// InputError when the rest of the input cannot be read (a rawlog truncated or corrupt
  /// mid-object: its stream cannot be resynchronised) or holds no RGB-D observation.
  virtual bool next(RgbdFrame& frame) = 0;
  /// Number of frames when known in advance, else 0.
  virtual size_t sizeHint() const = 0;
};

/// Opens a ".rawlog" file or a TUM-layout folder (rgb.txt, depth.txt, rgb/, depth/;
/// RGB paired with the nearest depth within 0.02 s). `camera` gives the intrinsics of
/// TUM folders; rawlogs carry their own. Throws InputError when the input cannot be
/// opened as a whole. In a rawlog, observations of other classes (odometry, other
/// sensors) are passed over; a rawlog without any CObservation3DRangeScan is an
/// InputError when its end is reached.
std::unique_ptr<RgbdSource> openRgbdSource(const std::string& path, const PinholeCamera& camera);

}  // namespace gmc::datasets
