#pragma once
// Sequential RGB-D input: an MRPT rawlog or a TUM-layout folder, one frame at a time.
#include <memory>
#include <stdexcept>
#include <string>

#include "gmc/datasets/camera.h"
#include "gmc/datasets/frame.h"
#include "gmc/datasets/rawlog_stream.h"

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
  /// Rawlogs: hands every object read to `sink` (a RawlogWriter that passes them on)
  /// before its scans become frames. Folders have nothing else to pass on.
  virtual void setObjectSink(RawlogObjectSink* /*sink*/) {}
  /// T_base_camera of the camera read last (see RgbdFrame::base_camera).
  const std::optional<Isometry>& baseCamera() const { return base_camera_; }

 protected:
  std::optional<Isometry> base_camera_;
};

/// Opens a ".rawlog" file or a TUM-layout folder (rgb.txt, depth.txt, rgb/, depth/;
/// RGB paired with the nearest depth within 0.02 s). `camera` gives the intrinsics of
/// TUM folders; rawlogs carry their own. Throws InputError when the input cannot be
/// opened as a whole. Rawlogs in either format (observations; actions and sensory
/// frames): the CObservation3DRangeScans that `sensors` selects become frames, in order;
/// other objects are passed over (or to the object sink). A rawlog without any selected
/// scan is an InputError when its end is reached. `distortion` (TUM folders): the lens
/// distortion of `camera`, removed from every frame (see Undistorter); rawlog frames are
/// used as recorded.
/// Per-frame masks stored next to a TUM folder's images ([Dataset] label_masks): frame
/// rgb/<name>.png has <folder>/<name>.png (CV_8UC1, non-zero where `label` applies, e.g.
/// the generator's person masks), given to the frame as a pixel label.
struct LabelMasks {
  std::string folder;            ///< relative to the input folder; empty = none
  std::string label = "person";  ///< the pixel label's name
};

/// `label_masks` (TUM folders only; an InputError for a rawlog, whose scans carry their
/// own pixelLabels): a missing or unreadable mask, or one sized unlike the image, is a
/// FrameReadError naming the file.
std::unique_ptr<RgbdSource> openRgbdSource(const std::string& path, const PinholeCamera& camera,
                                           const SensorSelection& sensors = {},
                                           const LensDistortion& distortion = {},
                                           const LabelMasks& label_masks = {});

}  // namespace gmc::datasets
