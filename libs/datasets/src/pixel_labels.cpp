#include "gmc/datasets/pixel_labels.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace gmc::datasets {
namespace {

template <unsigned B>
using Labels = mrpt::obs::TPixelLabelInfo<B>;

/// Calls f with `labels` as its concrete width (MRPT's 1, 2, 4 or 8 bytes).
template <class F>
decltype(auto) withConcrete(const mrpt::obs::TPixelLabelInfoBase& labels, F&& f) {
  if (auto* p1 = dynamic_cast<const Labels<1>*>(&labels)) return f(*p1);
  if (auto* p2 = dynamic_cast<const Labels<2>*>(&labels)) return f(*p2);
  if (auto* p4 = dynamic_cast<const Labels<4>*>(&labels)) return f(*p4);
  if (auto* p8 = dynamic_cast<const Labels<8>*>(&labels)) return f(*p8);
  throw std::runtime_error("pixel labels of an unknown width (" + std::to_string(labels.BITFIELD_BYTES) + " bytes)");
}

/// Rows and columns of a label matrix of any width.
cv::Size sizeOf(const mrpt::obs::TPixelLabelInfoBase& labels) {
  return withConcrete(labels, [](const auto& l) {
    return cv::Size(static_cast<int>(l.pixelLabels.cols()), static_cast<int>(l.pixelLabels.rows()));
  });
}

/// Throws when the labels are not sized as the images.
void checkSize(const cv::Size& labels, const cv::Size& images) {
  if (labels != images)
    throw std::runtime_error("pixel labels are " + std::to_string(labels.width) + "x" + std::to_string(labels.height) +
                             ", the images " + std::to_string(images.width) + "x" + std::to_string(images.height));
}

/// The label matrix of `in` as one B bytes wide (B at least as wide as `in`'s).
template <unsigned B>
std::shared_ptr<Labels<B>> widened(const mrpt::obs::TPixelLabelInfoBase& in) {
  auto out = std::make_shared<Labels<B>>();
  out->pixelLabelNames = in.pixelLabelNames;
  withConcrete(in, [&](const auto& src) {
    out->setSize(static_cast<int>(src.pixelLabels.rows()), static_cast<int>(src.pixelLabels.cols()));
    for (int r = 0; r < static_cast<int>(src.pixelLabels.rows()); ++r)
      for (int c = 0; c < static_cast<int>(src.pixelLabels.cols()); ++c)
        out->pixelLabels(r, c) = static_cast<typename Labels<B>::bitmask_t>(src.pixelLabels(r, c));
  });
  return out;
}

/// The index `name` has, else the first one a B-byte field leaves free.
std::optional<unsigned> indexFor(const mrpt::obs::TPixelLabelInfoBase& labels, const std::string& name, unsigned bytes) {
  for (const auto& [index, label] : labels.pixelLabelNames)
    if (label == name) return index;
  for (unsigned index = 0; index < 8 * bytes; ++index)
    if (!labels.pixelLabelNames.count(index)) return index;
  return std::nullopt;
}

template <unsigned B>
mrpt::obs::TPixelLabelInfoBase::Ptr write(std::shared_ptr<Labels<B>> out, const cv::Mat& mask, unsigned index,
                                          const std::string& name) {
  checkSize(sizeOf(*out), mask.size());
  out->setLabelName(index, name);
  for (int r = 0; r < mask.rows; ++r) {
    const auto* row = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < mask.cols; ++c) {
      out->unsetLabel(r, c, static_cast<std::uint8_t>(index));
      if (row[c]) out->setLabel(r, c, static_cast<std::uint8_t>(index));
    }
  }
  return out;
}

}  // namespace

cv::Mat pixelsLabelled(const mrpt::obs::TPixelLabelInfoBase::Ptr& labels, const std::vector<std::string>& names,
                       int rows, int cols) {
  cv::Mat out = cv::Mat::zeros(rows, cols, CV_8UC1);
  if (!labels) return out;
  std::vector<std::uint8_t> indices;
  for (const auto& [index, label] : labels->pixelLabelNames)
    if (std::find(names.begin(), names.end(), label) != names.end()) indices.push_back(static_cast<std::uint8_t>(index));
  if (indices.empty()) return out;
  checkSize(sizeOf(*labels), cv::Size(cols, rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      for (auto index : indices)
        if (labels->checkLabel(r, c, index)) {
          out.at<std::uint8_t>(r, c) = 255;
          break;
        }
  return out;
}

mrpt::obs::TPixelLabelInfoBase::Ptr withLabel(const mrpt::obs::TPixelLabelInfoBase::Ptr& labels, const cv::Mat& mask,
                                              const std::string& name) {
  if (!labels) {
    auto out = std::make_shared<Labels<1>>();
    out->setSize(mask.rows, mask.cols);
    return write<1>(out, mask, 0, name);
  }
  // The narrowest width, no narrower than the input's, with an index for the label.
  for (unsigned bytes : {1u, 2u, 4u, 8u}) {
    if (bytes < labels->BITFIELD_BYTES) continue;
    const auto index = indexFor(*labels, name, bytes);
    if (!index) continue;
    switch (bytes) {
      case 1: return write<1>(widened<1>(*labels), mask, *index, name);
      case 2: return write<2>(widened<2>(*labels), mask, *index, name);
      case 4: return write<4>(widened<4>(*labels), mask, *index, name);
      default: return write<8>(widened<8>(*labels), mask, *index, name);
    }
  }
  throw std::runtime_error("pixel labels already hold 64 labels, none named '" + name + "'");
}

}  // namespace gmc::datasets
