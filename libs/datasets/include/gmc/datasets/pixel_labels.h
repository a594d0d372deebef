#pragma once
// Pixel labels of an RGB-D observation (CObservation3DRangeScan::pixelLabels), written
// without losing the labels an earlier stage or the recording put there.
#include <mrpt/math/CMatrixDynamic.h>  // TPixelLabelInfo.h uses it without including it
#include <mrpt/obs/TPixelLabelInfo.h>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace gmc::datasets {

/// A copy of `labels` (null: none yet) where the label `name` is set exactly on the
/// non-zero pixels of `mask` (CV_8UC1) and every other label is kept as it was. The label
/// takes its existing index, else the first free one; a full bit field is copied into one
/// twice as wide (up to MRPT's 64 labels). The input is not modified: observations may
/// share it. Throws std::runtime_error when the labels' size differs from the mask's or all
/// 64 labels are taken.
mrpt::obs::TPixelLabelInfoBase::Ptr withLabel(const mrpt::obs::TPixelLabelInfoBase::Ptr& labels, const cv::Mat& mask,
                                              const std::string& name);

/// CV_8UC1 of rows x cols, 255 where a pixel carries any label named in `names` (zeros
/// when `labels` is null or defines none of them). Throws std::runtime_error when the
/// labels' size differs.
cv::Mat pixelsLabelled(const mrpt::obs::TPixelLabelInfoBase::Ptr& labels, const std::vector<std::string>& names,
                       int rows, int cols);

}  // namespace gmc::datasets
