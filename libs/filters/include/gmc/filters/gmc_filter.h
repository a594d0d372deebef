#pragma once
// The GMC observation filter: tracks the camera (frontend, initial guess, GMC,
// refinement on static matches), labels dynamic pixels and optionally removes their
// depth, so any MRPT map built from the filtered rawlog ignores walkers.
#include "gmc/filters/filter.h"
#include "gmc/vo/dynamic_mask.h"
#include "gmc/vo/odometry.h"

namespace gmc::filters {

/// INI section [GmcFilter].
struct GmcFilterOptions {
  bool write_pixel_labels = true;   ///< pixelLabels with a label named "dynamic"
  bool zero_dynamic_depth = false;  ///< set dynamic pixels' range to 0 (no reading)
  /// Pixel labels the incoming scan may carry that mark moving objects (comma-separated
  /// names, e.g. "person" from a segmenter, or [Dataset] label_masks): known dynamic for
  /// the odometry and the mask. Empty = none.
  std::string known_dynamic_labels;

  template <class V>
  void visit(V& v) {
    v("write_pixel_labels", write_pixel_labels, "write MRPT pixelLabels with label 'dynamic'");
    v("zero_dynamic_depth", zero_dynamic_depth, "remove the depth of dynamic pixels");
    v("known_dynamic_labels", known_dynamic_labels,
      "pixel labels of the incoming scans that mark moving objects (comma-separated names; empty = none): "
      "their pixels are dynamic for the odometry and the mask (doc/odometry.md, known dynamic pixels)");
  }
};

class GmcFilter : public ObservationFilter {
 public:
  std::string name() const override { return "gmc"; }
  std::string defaultSection() const override { return "GmcFilter"; }
  /// Reads its own section, and [Frontend], [GMS], [GMC], [Odometry], [Refinement],
  /// [LocalMap], [Background], [Keyframes], [Window], [Rejoin], [StartConsensus],
  /// [FreeSpace], [DepthAlignment], [DynamicMask] shared by every gmc filter.
  void initialize(const mrpt::config::CConfigFileBase& ini, const std::string& section,
                  const std::string& source) override;
  std::vector<std::string> sections(const std::string& section) const override;
  void save(mrpt::config::CConfigFileBase& out, const std::string& section) const override;
  /// kTracking (a vo::FrameTracking) and the dynamic mask.
  std::vector<std::string> provides() const override { return {kTracking}; }
  bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) override;
  /// kFinalRevisions: the odometry's revisions held back at the input's end.
  void finish(FilterContext& context) override;

  const vo::OdometryConfig& odometryConfig() const { return odometry_config_; }

 private:
  GmcFilterOptions options_;
  std::vector<std::string> known_dynamic_labels_;  ///< options_.known_dynamic_labels, split
  vo::OdometryConfig odometry_config_;
  vo::DynamicMaskOptions mask_options_;
  std::unique_ptr<vo::RgbdOdometry> odometry_;
  std::unique_ptr<vo::DynamicMaskBuilder> mask_builder_;
};

/// The gmc filter's result for this frame, or nullptr when no gmc filter ran.
inline vo::FrameTracking* trackingOf(FilterContext& context) {
  return context.product<vo::FrameTracking>(kTracking);
}

/// The gmc filter's revisions at the input's end (finishChain), or nullptr.
inline std::vector<vo::RevisedPose>* finalRevisionsOf(FilterContext& context) {
  return context.product<std::vector<vo::RevisedPose>>(kFinalRevisions);
}

/// INI section [DepthRange]: readings outside [min_depth, max_depth] become "no reading".
class DepthRangeFilter : public ObservationFilter {
 public:
  struct Options {
    double min_depth = 0.3;
    double max_depth = 5.0;
    template <class V>
    void visit(V& v) {
      v("min_depth", min_depth, 0.0, 1000.0, "m, closer readings are removed");
      v("max_depth", max_depth, 0.0, 1000.0, "m, farther readings are removed");
    }
  };
  std::string name() const override { return "depth_range"; }
  std::string defaultSection() const override { return "DepthRange"; }
  void initialize(const mrpt::config::CConfigFileBase& ini, const std::string& section,
                  const std::string& source) override;
  void save(mrpt::config::CConfigFileBase& out, const std::string& section) const override;
  bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) override;

 private:
  Options options_;
};

/// INI section [Decimate]: keeps one observation in every `keep_every`.
class DecimateFilter : public ObservationFilter {
 public:
  struct Options {
    int keep_every = 1;
    template <class V>
    void visit(V& v) { v("keep_every", keep_every, 1, 1000000, "keep one frame in every N"); }
  };
  std::string name() const override { return "decimate"; }
  std::string defaultSection() const override { return "Decimate"; }
  void initialize(const mrpt::config::CConfigFileBase& ini, const std::string& section,
                  const std::string& source) override;
  void save(mrpt::config::CConfigFileBase& out, const std::string& section) const override;
  bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) override;

 private:
  Options options_;
  std::size_t seen_ = 0;
};

}  // namespace gmc::filters
