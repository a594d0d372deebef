#include "gmc/datasets/evaluation.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gmc::datasets {

ErrorStats ErrorStats::of(const std::vector<double>& e) {
  ErrorStats s;
  if (e.empty()) return s;
  double sq = 0, sum = 0;
  for (double v : e) sq += v * v, sum += v, s.max = std::max(s.max, v);
  s.rmse = std::sqrt(sq / e.size());
  s.mean = sum / e.size();
  std::vector<double> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();
  s.median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  return s;
}

namespace {
std::vector<double> stampsOf(const std::vector<StampedPose>& t) {
  std::vector<double> s(t.size());
  for (size_t i = 0; i < t.size(); ++i) s[i] = t[i].stamp;
  return s;
}

size_t closestIndex(const std::vector<double>& sorted, double v) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), v);
  if (it == sorted.end()) return sorted.size() - 1;
  if (it == sorted.begin()) return 0;
  return (v - *(it - 1) <= *it - v) ? static_cast<size_t>(it - sorted.begin() - 1)
                                    : static_cast<size_t>(it - sorted.begin());
}
}  // namespace

AteResult computeAte(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est,
                     double max_dt) {
  AteResult r;
  const auto pairs = associate(stampsOf(gt), stampsOf(est), max_dt);
  r.pairs = pairs.size();
  if (pairs.size() < 3) return r;
  Eigen::Matrix3Xd model(3, pairs.size()), data(3, pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    data.col(static_cast<Eigen::Index>(k)) = gt[pairs[k].first].pose.translation();
    model.col(static_cast<Eigen::Index>(k)) = est[pairs[k].second].pose.translation();
  }
  r.alignment.matrix() = Eigen::umeyama(model, data, false);
  for (size_t k = 0; k < pairs.size(); ++k) {
    const Eigen::Vector3d aligned = r.alignment * model.col(static_cast<Eigen::Index>(k));
    r.stamps.push_back(est[pairs[k].second].stamp);
    r.gt_positions.push_back(data.col(static_cast<Eigen::Index>(k)));
    r.aligned_positions.push_back(aligned);
    r.errors.push_back((aligned - data.col(static_cast<Eigen::Index>(k))).norm());
  }
  r.error = ErrorStats::of(r.errors);
  const Eigen::Matrix4d similarity = Eigen::umeyama(model, data, true);
  r.scale = similarity.block<3, 1>(0, 0).norm();
  std::vector<double> scaled_errors;
  for (Eigen::Index k = 0; k < model.cols(); ++k)
    scaled_errors.push_back(((similarity * model.col(k).homogeneous()).head<3>() - data.col(k)).norm());
  r.scaled_error = ErrorStats::of(scaled_errors);
  return r;
}

namespace {
double angleDeg(const Isometry& T) {
  return std::acos(std::clamp((T.linear().trace() - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
}
}  // namespace

RpeResult computeRpe(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est,
                     double delta) {
  RpeResult r;
  r.delta_s = delta;
  if (gt.size() < 2 || est.size() < 2) return r;
  const auto gs = stampsOf(gt), es = stampsOf(est);
  // Ground-truth stamps further than twice the median ground-truth period are unmatched.
  std::vector<double> periods;
  for (size_t i = 1; i < gs.size(); ++i) periods.push_back(gs[i] - gs[i - 1]);
  std::nth_element(periods.begin(), periods.begin() + periods.size() / 2, periods.end());
  const double max_gt_dt = 2 * periods[periods.size() / 2];
  std::vector<double> trans, rot;
  double gain_num = 0, gain_den = 0;
  for (size_t i = 0; i < es.size(); ++i) {
    const size_t j = closestIndex(es, es[i] + delta);
    if (j <= i || std::abs(es[j] - es[i] - delta) > delta / 2) continue;
    const size_t g0 = closestIndex(gs, es[i]), g1 = closestIndex(gs, es[j]);
    if (std::abs(gs[g0] - es[i]) > max_gt_dt || std::abs(gs[g1] - es[j]) > max_gt_dt) continue;
    const Isometry d_est = est[i].pose.inverse() * est[j].pose;
    const Isometry d_gt = gt[g0].pose.inverse() * gt[g1].pose;
    const Isometry err = d_gt.inverse() * d_est;
    trans.push_back(err.translation().norm());
    rot.push_back(angleDeg(err));
    const double a_est = angleDeg(d_est), a_gt = angleDeg(d_gt);
    gain_num += a_est * a_gt, gain_den += a_gt * a_gt;
  }
  r.rotation_gain = gain_den > 0 ? gain_num / gain_den : std::nan("");
  r.pairs = trans.size();
  r.translation = ErrorStats::of(trans);
  r.rotation = ErrorStats::of(rot);
  return r;
}

namespace {
/// NaN and infinity have no JSON spelling: null (doc/evaluation.md).
nlohmann::ordered_json number(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }
}  // namespace

std::string evaluationJson(const AteResult& ate, const RpeResult& rpe) {
  nlohmann::ordered_json j;
  j["ate"] = {{"rmse", number(ate.error.rmse)},
              {"mean", number(ate.error.mean)},
              {"median", number(ate.error.median)},
              {"max", number(ate.error.max)},
              {"pairs", ate.pairs},
              {"scale", number(ate.scale)},
              {"scaled_rmse", number(ate.scaled_error.rmse)}};
  // Per pose, so a user can see where along the run the error lives.
  auto& per_pose = j["ate"]["per_pose"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < ate.errors.size(); ++i) per_pose.push_back({number(ate.stamps[i]), number(ate.errors[i])});
  j["rpe"] = {{"trans_rmse", number(rpe.translation.rmse)},
              {"trans_median", number(rpe.translation.median)},
              {"rot_rmse", number(rpe.rotation.rmse)},
              {"rot_median", number(rpe.rotation.median)},
              {"rotation_gain", number(rpe.rotation_gain)},
              {"pairs", rpe.pairs},
              {"delta_s", number(rpe.delta_s)}};
  return j.dump(2) + "\n";
}

namespace {
void label(cv::Mat& img, const std::string& text, cv::Point at, double size = 0.45) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, size, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}
std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
/// A drawing coordinate as int: NaN or a value beyond int (a NaN or infinite error, stamps
/// far apart) would be undefined behaviour; cv drawing clips anything far off the image.
int pixel(double v) { return std::isnan(v) ? 0 : static_cast<int>(std::clamp(v, -1e6, 1e6)); }
}  // namespace

cv::Mat plotTrajectory(const AteResult& ate, const std::string& title) {
  const int W = 900, top_h = 640, bottom_h = 260, margin = 70;
  cv::Mat img(top_h + bottom_h, W, CV_8UC3, cv::Scalar(255, 255, 255));
  if (ate.gt_positions.empty()) return img;
  const cv::Scalar gt_colour(40, 40, 40), est_colour(30, 30, 220);
  // Plane with the largest extent: the two axes of largest spread.
  Eigen::Vector3d lo = ate.gt_positions[0], hi = lo;
  for (const auto& p : ate.gt_positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const auto& p : ate.aligned_positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d ext = hi - lo;
  int a0 = 0, a1 = 1;
  if (ext[2] > std::min(ext[0], ext[1])) (ext[0] < ext[1] ? a0 : a1) = 2;
  if (a0 > a1) std::swap(a0, a1);
  // Same scale on both axes, drawing centred in the panel.
  const cv::Rect panel(margin, 50, W - 2 * margin, top_h - 50 - margin);
  const double scale = std::min(panel.width / std::max(ext[a0], 1e-3), panel.height / std::max(ext[a1], 1e-3));
  const double off0 = panel.x + (panel.width - ext[a0] * scale) / 2;
  const double off1 = panel.y + panel.height - (panel.height - ext[a1] * scale) / 2;
  auto toPx = [&](const Eigen::Vector3d& p) {
    return cv::Point(pixel(off0 + (p[a0] - lo[a0]) * scale), pixel(off1 - (p[a1] - lo[a1]) * scale));
  };
  cv::rectangle(img, panel, cv::Scalar(200, 200, 200));
  for (size_t k = 1; k < ate.gt_positions.size(); ++k) {
    cv::line(img, toPx(ate.gt_positions[k - 1]), toPx(ate.gt_positions[k]), gt_colour, 2, cv::LINE_AA);
    cv::line(img, toPx(ate.aligned_positions[k - 1]), toPx(ate.aligned_positions[k]), est_colour, 1, cv::LINE_AA);
  }
  const char names[] = "xyz";
  char text[256];
  std::snprintf(text, sizeof text, "%s   ATE RMSE %.4f m over %zu pairs", title.c_str(), ate.error.rmse, ate.pairs);
  label(img, text, {margin, 30}, 0.6);
  // Axis extents in metres at the ends of the drawn data.
  const cv::Point p_lo = toPx(lo), p_hi = toPx(hi);
  label(img, fmt("%.2f", lo[a0]), {p_lo.x - 15, panel.br().y + 18});
  label(img, fmt("%.2f m", hi[a0]), {p_hi.x - 25, panel.br().y + 18});
  label(img, fmt("%.2f", lo[a1]), {5, p_lo.y});
  label(img, fmt("%.2f", hi[a1]), {5, p_hi.y + 10});
  std::snprintf(text, sizeof text,
                "top view, plane of largest extent: %c (right) vs %c (up);  black: ground truth, red: aligned estimate",
                names[a0], names[a1]);
  label(img, text, {margin, top_h - 20}, 0.42);
  // Error over time.
  const double t0 = ate.stamps.front(), t1 = std::max(ate.stamps.back(), t0 + 1e-6);
  const double emax = std::max(ate.error.max, 1e-4);
  const int x0 = margin, x1 = W - margin, y0 = top_h + bottom_h - 45, h = bottom_h - 90;
  cv::line(img, {x0, y0}, {x1, y0}, cv::Scalar(0, 0, 0));
  cv::line(img, {x0, y0}, {x0, y0 - h}, cv::Scalar(0, 0, 0));
  auto errPx = [&](size_t i) {
    return cv::Point(pixel(x0 + (ate.stamps[i] - t0) / (t1 - t0) * (x1 - x0)),
                     pixel(y0 - ate.errors[i] / emax * h));
  };
  for (size_t k = 1; k < ate.errors.size(); ++k) cv::line(img, errPx(k - 1), errPx(k), est_colour, 1, cv::LINE_AA);
  const int rmse_y = pixel(y0 - ate.error.rmse / emax * h);
  cv::line(img, {x0, rmse_y}, {x1, rmse_y}, cv::Scalar(160, 160, 160), 1, cv::LINE_AA);
  label(img, "position error (m) over time; grey: RMSE", {margin, top_h + 25}, 0.5);
  label(img, fmt("%.3f", emax), {5, y0 - h + 5});
  label(img, "0", {x0 - 15, y0 + 5});
  label(img, "0 s", {x0 - 5, y0 + 20});
  label(img, fmt("%.1f s", t1 - t0), {x1 - 30, y0 + 20});
  return img;
}

}  // namespace gmc::datasets
