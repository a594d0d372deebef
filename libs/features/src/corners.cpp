#include "gmc/features/corners.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace gmc::features {
namespace {

/// OpenCV's order of GFTT candidates: stronger first, ties by later address (a strict
/// total order, so that a partial sort and a full sort agree).
struct StrongerFirst {
  bool operator()(const float* a, const float* b) const {
    return *a > *b ? true : *a < *b ? false : a > b;
  }
};

/// The `index`-th of `count` near-equal parts of [0, total).
cv::Range evenPart(int index, int count, int total) {
  return {static_cast<int>(static_cast<long>(total) * index / count),
          static_cast<int>(static_cast<long>(total) * (index + 1) / count)};
}

/// Walks the candidates from strongest to weakest, sorting them in growing batches: a
/// frame keeps its max_corners long before the tens of thousands of local maxima run out.
class StrongestFirst {
 public:
  StrongestFirst(std::vector<const float*>& items, size_t first_batch)
      : items_(items), batch_(std::max<size_t>(first_batch, 256)) {}
  const float* at(size_t i) {
    while (i >= sorted_) {
      const size_t end = std::min(items_.size(), sorted_ + batch_);
      std::partial_sort(items_.begin() + static_cast<long>(sorted_), items_.begin() + static_cast<long>(end),
                        items_.end(), StrongerFirst());
      sorted_ = end;
      batch_ *= 2;
    }
    return items_[i];
  }

 private:
  std::vector<const float*>& items_;
  size_t sorted_ = 0, batch_;
};

/// OpenCV's spacing rule: a candidate is kept when no kept corner in the 3x3 grid cells
/// around it is closer than min_distance (cells of min_distance px).
std::vector<cv::Point2f> keepSpaced(std::vector<const float*>& candidates, const cv::Mat& eig,
                                    const CornerParams& params) {
  std::vector<cv::Point2f> corners;
  const size_t max_corners = params.max_corners > 0 ? static_cast<size_t>(params.max_corners) : candidates.size();
  corners.reserve(std::min(max_corners, candidates.size()));
  const bool spaced = params.min_distance >= 1;
  const int cell = spaced ? cvRound(params.min_distance) : 1;
  const int grid_w = (eig.cols + cell - 1) / cell, grid_h = (eig.rows + cell - 1) / cell;
  std::vector<std::vector<cv::Point2f>> grid(spaced ? static_cast<size_t>(grid_w * grid_h) : 0);
  const double min_d2 = params.min_distance * params.min_distance;
  StrongestFirst order(candidates, 4 * max_corners);
  for (size_t i = 0; i < candidates.size() && corners.size() < max_corners; ++i) {
    const auto offset = reinterpret_cast<const uchar*>(order.at(i)) - eig.data;
    const int y = static_cast<int>(offset / static_cast<long>(eig.step));
    const int x = static_cast<int>((offset - y * static_cast<long>(eig.step)) / static_cast<long>(sizeof(float)));
    if (spaced) {
      const int cx = x / cell, cy = y / cell;
      bool good = true;
      for (int gy = std::max(0, cy - 1); good && gy <= std::min(grid_h - 1, cy + 1); ++gy)
        for (int gx = std::max(0, cx - 1); good && gx <= std::min(grid_w - 1, cx + 1); ++gx)
          for (const auto& p : grid[static_cast<size_t>(gy * grid_w + gx)]) {
            const float dx = static_cast<float>(x) - p.x, dy = static_cast<float>(y) - p.y;
            if (dx * dx + dy * dy < min_d2) {
              good = false;
              break;
            }
          }
      if (!good) continue;
      grid[static_cast<size_t>(cy * grid_w + cx)].emplace_back(static_cast<float>(x), static_cast<float>(y));
    }
    corners.emplace_back(static_cast<float>(x), static_cast<float>(y));
  }
  return corners;
}

}  // namespace

std::vector<cv::Point2f> detectCornersInside(const cv::Mat& gray, int border, const CornerParams& params,
                                             int strips) {
  CV_Assert(gray.type() == CV_8UC1 && params.quality_level > 0 && params.min_distance >= 0);
  const int w = gray.cols, h = gray.rows;
  // The mask's inside, and OpenCV's own one-pixel frame where a 3x3 maximum is defined.
  const int x0 = std::max(1, border), x1 = std::min(w - 1, w - border);
  const int y0 = std::max(1, border), y1 = std::min(h - 1, h - border);
  if (x0 >= x1 || y0 >= y1) return {};

  // The minimum eigenvalue in strips. Each strip is computed with `margin` extra rows on
  // either side: the derivative reads the neighbouring rows of the whole image, but the
  // covariance window of a strip's own first and last rows would be mirrored.
  strips = std::max(1, std::min(strips > 0 ? strips : cv::getNumThreads(), h / 32));
  const int margin = params.block_size / 2 + 2;
  cv::Mat eig(h, w, CV_32F);
  std::vector<double> strip_max(static_cast<size_t>(strips), 0.0);
  cv::parallel_for_(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const cv::Range rows = evenPart(s, strips, h);
      const cv::Range padded(std::max(0, rows.start - margin), std::min(h, rows.end + margin));
      cv::Mat strip_eig;
      cv::cornerMinEigenVal(gray.rowRange(padded), strip_eig, params.block_size, 3);
      strip_eig.rowRange(rows.start - padded.start, rows.end - padded.start).copyTo(eig.rowRange(rows));
      const int my0 = std::max(rows.start, border), my1 = std::min(rows.end, h - border);
      double m = 0;
      if (my0 < my1) cv::minMaxLoc(eig(cv::Range(my0, my1), cv::Range(border, w - border)), nullptr, &m);
      strip_max[static_cast<size_t>(s)] = m;
    }
  }, strips);
  const double max_eig = *std::max_element(strip_max.begin(), strip_max.end());

  // Candidates: above the quality threshold and the maximum of their 3x3 neighbourhood
  // after thresholding (cv::threshold TOZERO then a 3x3 cv::dilate, without the images).
  const float threshold = static_cast<float>(max_eig * params.quality_level);
  auto kept = [threshold](float v) { return v > threshold ? v : 0.f; };
  std::vector<std::vector<const float*>> strip_candidates(static_cast<size_t>(strips));
  cv::parallel_for_(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      auto& out = strip_candidates[static_cast<size_t>(s)];
      const cv::Range rows = evenPart(s, strips, h);
      for (int y = std::max(rows.start, y0); y < std::min(rows.end, y1); ++y) {
        const float* above = eig.ptr<float>(y - 1);
        const float* row = eig.ptr<float>(y);
        const float* below = eig.ptr<float>(y + 1);
        for (int x = x0; x < x1; ++x) {
          const float v = kept(row[x]);
          if (v == 0.f) continue;
          if (v >= kept(row[x - 1]) && v >= kept(row[x + 1]) && v >= kept(above[x - 1]) && v >= kept(above[x]) &&
              v >= kept(above[x + 1]) && v >= kept(below[x - 1]) && v >= kept(below[x]) && v >= kept(below[x + 1]))
            out.push_back(row + x);
        }
      }
    }
  }, strips);
  std::vector<const float*> candidates;
  size_t total = 0;
  for (const auto& c : strip_candidates) total += c.size();
  candidates.reserve(total);
  for (const auto& c : strip_candidates) candidates.insert(candidates.end(), c.begin(), c.end());
  return keepSpaced(candidates, eig, params);
}

void refineCornersSubPixel(const cv::Mat& gray, std::vector<cv::Point2f>& corners, int half_window, int chunks) {
  if (corners.empty()) return;
  const cv::TermCriteria stop(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 10, 0.01);
  const cv::Size window(half_window, half_window);
  chunks = std::max(1, std::min(chunks > 0 ? chunks : 4 * cv::getNumThreads(), static_cast<int>(corners.size() / 32)));
  cv::parallel_for_(cv::Range(0, chunks), [&](const cv::Range& range) {
    for (int c = range.start; c < range.end; ++c) {
      const cv::Range part = evenPart(c, chunks, static_cast<int>(corners.size()));
      cv::Mat chunk(part.size(), 1, CV_32FC2, corners.data() + part.start);  // refined in place
      cv::cornerSubPix(gray, chunk, window, cv::Size(-1, -1), stop);
    }
  }, chunks);
}

}  // namespace gmc::features
