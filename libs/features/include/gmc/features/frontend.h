#pragma once
// Feature frontend: GFTT (Shi-Tomasi) keypoints spread with a minimum distance, ORB
// (rBRIEF) descriptors, back-projection with registered depth, and matching between
// two frames: guided by a predicted motion (windowed search) or exhaustive, then
// filtered by GMS. Works on plain OpenCV images; no file I/O.
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <cstdint>
#include <vector>

#include "gmc/features/corners.h"
#include "gmc/gmc/gms.h"
#include "gmc/gmc/types.h"

namespace gmc::features {

/// INI section [Frontend].
struct FrontendOptions {
  int max_features = 1200;        ///< GFTT corners per frame
  double quality_level = 0.005;   ///< GFTT quality relative to the strongest corner
  double min_distance = 10.0;     ///< px between corners (the paper's setting)
  int block_size = 3;             ///< GFTT covariance window
  bool subpixel = true;           ///< refine corners to sub-pixel (cv::cornerSubPix)
  int subpixel_window = 3;        ///< px half-size of cornerSubPix's window (3: 7x7)
  int border = 20;                ///< px kept free at the image border (descriptor patch)
  double min_depth = 0.2;         ///< m; closer depth readings are ignored
  double max_depth = 6.0;         ///< m; farther depth readings are ignored
  int match_radius = 40;          ///< px search window around the predicted position
  int max_hamming = 64;           ///< reject matches with a larger descriptor distance
  double ratio = 0.9;             ///< best/second-best distance ratio (1 = off)
  bool use_gms = true;            ///< GMS match filtering before GMC
  int min_matches_for_gms = 60;   ///< GMS statistics need enough matches

  /// The GFTT settings among these.
  CornerParams corners() const { return {max_features, quality_level, min_distance, block_size}; }

  template <class V>
  void visit(V& v) {
    v("max_features", max_features, 10, 20000, "GFTT corners per frame");
    v("quality_level", quality_level, 1e-6, 1.0, "GFTT quality relative to the strongest corner");
    v("min_distance", min_distance, 0.0, 200.0, "minimum px between corners");
    v("block_size", block_size, 3, 15, "GFTT covariance window (px)");
    v("subpixel", subpixel, "refine corners to sub-pixel accuracy");
    v("subpixel_window", subpixel_window, 1, 10, "px half-size of the sub-pixel refinement window");
    v("border", border, 16, 200, "px kept free at the image border");
    v("min_depth", min_depth, 0.0, 100.0, "ignore depth below (m)");
    v("max_depth", max_depth, 0.01, 100.0, "ignore depth beyond (m)");
    v("match_radius", match_radius, 1, 1000, "guided-search window radius (px)");
    v("max_hamming", max_hamming, 1, 256, "max descriptor distance of a match");
    v("ratio", ratio, 0.1, 1.0, "best/second-best ratio test (1 = off)");
    v("use_gms", use_gms, "GMS match filtering");
    v("min_matches_for_gms", min_matches_for_gms, 0, 100000, "skip GMS below this many matches");
  }
};

/// Keypoints of one frame with descriptors and 3-D points (camera optical frame).
struct FeatureSet {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;                  ///< one 32-byte ORB row per keypoint
  std::vector<Eigen::Vector3d> points;  ///< back-projected; z == 0 when depth is invalid
  int width = 0, height = 0;

  bool hasDepth(int i) const { return points[static_cast<size_t>(i)].z() > 0; }
  size_t size() const { return keypoints.size(); }
};

struct FeatureMatch {
  int ref = 0;       ///< index in the reference FeatureSet
  int cur = 0;       ///< index in the current FeatureSet
  int distance = 0;  ///< Hamming distance
};

/// The frontend's ORB descriptor extractor: one pyramid level, upright keypoints, a patch
/// that fits inside `border`.
cv::Ptr<cv::ORB> makeDescriptorExtractor(const FrontendOptions& options);

class Frontend {
 public:
  explicit Frontend(const FrontendOptions& options = {}, const GmsParams& gms = {});
  const FrontendOptions& options() const { return options_; }

  /// gray: CV_8UC1; depth: CV_16UC1 raw units (0 = none) or empty.
  FeatureSet extract(const cv::Mat& gray, const cv::Mat& depth, double depth_units,
                     const PinholeCamera& camera) const;

  /// Matches reference features that have depth to current features near the pixel
  /// predicted by T_cur_ref (maps reference points into the current frame).
  std::vector<FeatureMatch> matchGuided(const FeatureSet& ref, const FeatureSet& cur,
                                        const Isometry& T_cur_ref, const PinholeCamera& camera,
                                        int radius) const;

  /// Exhaustive matching (mutual best, ratio test); used when no prediction is trusted.
  std::vector<FeatureMatch> matchExhaustive(const FeatureSet& ref, const FeatureSet& cur) const;

  /// GMS filtering of matches (keeps all when there are too few for statistics).
  std::vector<FeatureMatch> filterGms(const FeatureSet& ref, const FeatureSet& cur,
                                      const std::vector<FeatureMatch>& matches) const;

 private:
  FrontendOptions options_;
  GmsParams gms_;
  cv::Ptr<cv::ORB> orb_;
};

/// Depth in metres at a keypoint: bilinear between the four surrounding readings when they
/// agree within 2 % (one surface), else the nearest pixel's reading, else the median of
/// the valid readings in its 3x3 neighbourhood; 0 when none is within [min_depth, max_depth].
double depthAtKeypoint(const cv::Mat& depth, double depth_units, float u, float v,
                       double min_depth, double max_depth);

}  // namespace gmc::features
