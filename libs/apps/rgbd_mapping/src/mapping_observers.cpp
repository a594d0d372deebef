#include "gmc/apps/mapping_observers.h"

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <unistd.h>

#include "gmc/apps/app.h"
#include "gmc/datasets/atomic_file.h"

namespace gmc::apps {

namespace fs = std::filesystem;

namespace {

/// memory.png: resident memory (MB, red, left scale) and map nodes (blue, right scale)
/// against the frame number, both from zero.
cv::Mat plotMemory(const std::vector<MemorySampler::Sample>& samples) {
  const int W = 800, H = 400, left = 70, right = 80, top = 40, bottom = 50;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double max_f = 1, max_mb = 1, max_nodes = 1;
  for (const auto& s : samples) {
    max_f = std::max(max_f, s.frame);
    max_mb = std::max(max_mb, s.resident_mb * 1.1);
    max_nodes = std::max(max_nodes, s.map_nodes * 1.1);
  }
  auto px = [&](double f, double v, double vmax) {
    return cv::Point(left + static_cast<int>((W - left - right) * f / max_f),
                     H - bottom - static_cast<int>((H - top - bottom) * v / vmax));
  };
  cv::rectangle(img, {left, top}, {W - right, H - bottom}, cv::Scalar(0, 0, 0));
  for (size_t i = 1; i < samples.size(); ++i) {
    const auto& a = samples[i - 1];
    const auto& b = samples[i];
    cv::line(img, px(a.frame, a.resident_mb, max_mb), px(b.frame, b.resident_mb, max_mb), {0, 0, 220}, 2);
    cv::line(img, px(a.frame, a.map_nodes, max_nodes), px(b.frame, b.map_nodes, max_nodes), {200, 0, 0}, 2);
    cv::line(img, px(a.frame, a.heap_mb, max_mb), px(b.frame, b.heap_mb, max_mb), {0, 150, 255}, 2);
  }
  auto text = [&](const std::string& t, cv::Point p, cv::Scalar c) {
    cv::putText(img, t, p, cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
  };
  char buf[96];
  std::snprintf(buf, sizeof buf, "resident memory (MB), max %.0f", max_mb / 1.1);
  text(buf, {left, 25}, {0, 0, 220});
  text("orange: heap in use (MB)", {left + 260, 25}, {0, 150, 255});
  std::snprintf(buf, sizeof buf, "map nodes, max %.0f", max_nodes / 1.1);
  text(buf, {W - right - 200, 25}, {200, 0, 0});
  text("0", {left - 15, H - bottom + 5}, {0, 0, 0});
  std::snprintf(buf, sizeof buf, "%.0f", max_mb);
  text(buf, {5, top + 5}, {0, 0, 220});
  std::snprintf(buf, sizeof buf, "%.0f", max_nodes);
  text(buf, {W - right + 5, top + 5}, {200, 0, 0});
  std::snprintf(buf, sizeof buf, "frame %.0f", max_f);
  text(buf, {W - right - 70, H - bottom + 20}, {0, 0, 0});
  text("frame 0", {left, H - bottom + 20}, {0, 0, 0});
  return img;
}

/// Draws keypoints coloured by label and the dynamic GMC cells over the image.
/// `truth_mask` (simulated input, may be empty): outlined in cyan, so what the dynamic
/// mask misses is visible.
cv::Mat drawOverlay(const datasets::RgbdFrame& frame, const vo::FrameTracking& t,
                    const cv::Mat& mask, const cv::Mat& truth_mask) {
  // Grey, dimmed background so the coloured labels stand out on any texture.
  cv::Mat img;
  if (frame.rgb.channels() == 3) cv::cvtColor(frame.rgb, img, cv::COLOR_BGR2GRAY);
  else img = frame.rgb.clone();
  img.convertTo(img, CV_8U, 0.6, 40);
  cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);
  if (!mask.empty()) {
    cv::Mat red(img.size(), CV_8UC3, cv::Scalar(0, 0, 255));
    cv::Mat blended;
    cv::addWeighted(img, 0.6, red, 0.4, 0, blended);
    blended.copyTo(img, mask);
  }
  if (!truth_mask.empty()) {
    std::vector<std::vector<cv::Point>> outlines;
    cv::findContours(truth_mask > 0, outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(img, outlines, -1, cv::Scalar(255, 255, 0), 2);
  }
  for (const auto& cell : t.gmc.cells) {
    if (cell.cluster < 0 || t.gmc.clusters[static_cast<size_t>(cell.cluster)].is_static) continue;
    cv::rectangle(img, cv::Rect(cell.x0, cell.y0, cell.x1 - cell.x0, cell.y1 - cell.y0),
                  cv::Scalar(0, 200, 255), 1);
  }
  for (size_t i = 0; i < t.keypoints.size(); ++i) {
    const auto label = t.keypoint_labels[i];
    const cv::Scalar colour = label == MotionLabel::Static    ? cv::Scalar(0, 220, 0)
                              : label == MotionLabel::Dynamic ? cv::Scalar(0, 0, 255)
                                                              : cv::Scalar(160, 160, 160);
    if (label != MotionLabel::Undecided) cv::circle(img, t.keypoints[i], 5, cv::Scalar(0, 0, 0), cv::FILLED);
    cv::circle(img, t.keypoints[i], label == MotionLabel::Undecided ? 2 : 4, colour,
               label == MotionLabel::Undecided ? 1 : cv::FILLED);
  }
  std::ostringstream text;
  text << std::fixed << std::setprecision(6) << frame.stamp << "  " << vo::toString(t.state)
       << "  static " << t.num_static << "  dynamic " << t.num_dynamic;
  cv::putText(img, text.str(), {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 2);
  cv::putText(img, text.str(), {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1);
  return img;
}

std::string stampName(double stamp, const char* extension) {
  std::ostringstream name;
  name << std::fixed << std::setprecision(6) << stamp << extension;
  return name.str();
}

}  // namespace

const cv::Mat& TruthMasks::of(const SourceFrame& f) {
  if (f.index == index_) return mask_;
  const std::string path = dir_ + "/" + stampName(f.recorded_stamp, ".png");
  mask_ = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mask_.empty()) throw AppError(dir_ + ": no mask for frame " + f.frame.name);
  index_ = f.index;
  return mask_;
}

void ProgressLine::onFrame(const FrameEvent& e) {
  const double elapsed = secondsSince(start_);
  const double fps = static_cast<double>(e.report.frames) / std::max(elapsed, 1e-9);
  const std::size_t done = e.source.index + 1;
  std::fprintf(stderr, "\rframe %zu", done);
  if (total_) std::fprintf(stderr, "/%zu", total_);
  std::fprintf(stderr, "  %.1f fps", fps);
  if (total_ && fps > 0) std::fprintf(stderr, "  ETA %.0f s", (static_cast<double>(total_) - done) / fps);
  if (realtime_) std::fprintf(stderr, "  lag %.3f s", e.lag_s);
  std::fprintf(stderr, "  %s   ", vo::toString(e.tracking.state));
}

void ProgressLine::onEnd(PipelineReport&, const mapping::StaticMapBuilder*) { std::fprintf(stderr, "\n"); }

OverlayWriter::OverlayWriter(std::string out_dir, int every, TruthMasks* truth)
    : dir_((fs::path(out_dir) / "overlays").string()), every_(every), truth_(truth) {
  fs::create_directories(dir_);
}

void OverlayWriter::onFrame(const FrameEvent& e) {
  // report.frames counts this frame: overlays of frames 0, N, 2N, ...
  if ((e.report.frames - 1) % static_cast<std::size_t>(every_) != 0) return;
  const cv::Mat truth = truth_ ? truth_->of(e.source) : cv::Mat();
  datasets::writeImageAtomic(dir_ + "/" + stampName(e.source.frame.stamp, ".png"),
                             drawOverlay(e.source.frame, e.tracking, e.dynamic_mask, truth));
}

PosePoints countPosePoints(const vo::FrameTracking& t, const cv::Mat& mask) {
  PosePoints n;
  if (t.state != vo::TrackingState::Tracking) return n;
  for (std::size_t i = 0; i < t.keypoint_in_pose.size() && i < t.keypoints.size(); ++i) {
    if (!t.keypoint_in_pose[i]) continue;
    const int u = std::clamp(static_cast<int>(t.keypoints[i].x + 0.5f), 0, mask.cols - 1);
    const int v = std::clamp(static_cast<int>(t.keypoints[i].y + 0.5f), 0, mask.rows - 1);
    ++n.points;
    n.on_people += mask.at<std::uint8_t>(v, u) > 0;
  }
  return n;
}

GroundTruthScorer::GroundTruthScorer(TruthMasks& truth, const mapping::StaticMapOptions& map_options,
                                     std::vector<datasets::StampedPose> groundtruth, bool score_map)
    : truth_(truth), max_range_(map_options.max_range), groundtruth_(std::move(groundtruth)) {
  if (score_map) voxels_ = std::make_unique<mapping::GroundTruthVoxels>(map_options);
}

void GroundTruthScorer::onFrame(const FrameEvent& e) {
  if (e.source.pass > 0) return;  // later passes repeat the same frames
  const auto& frame = e.source.frame;
  const cv::Mat& mask = truth_.of(e.source);
  const auto& t = e.tracking;
  for (std::size_t i = 0; i < t.keypoints.size(); ++i) {
    if (t.keypoint_labels[i] == MotionLabel::Undecided) continue;  // unmatched, or no decision
    const auto& kp = t.keypoints[i];
    const bool on_person = mask.at<std::uint8_t>(static_cast<int>(kp.y + 0.5f), static_cast<int>(kp.x + 0.5f)) > 0;
    keypoints_.add(t.keypoint_labels[i] == MotionLabel::Dynamic, on_person);
  }
  pose_points_ += countPosePoints(t, mask);
  // Pixels the map could insert: depth within its range.
  const auto max_raw = static_cast<std::uint16_t>(std::min(65535.0, max_range_ / frame.depth_units));
  for (int v = 0; v < frame.depth.rows; ++v) {
    const auto* depth_row = frame.depth.ptr<std::uint16_t>(v);
    const auto* truth_row = mask.ptr<std::uint8_t>(v);
    const auto* predicted_row = e.dynamic_mask.empty() ? nullptr : e.dynamic_mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < frame.depth.cols; ++u) {
      if (depth_row[u] == 0 || depth_row[u] > max_raw) continue;
      pixels_.add(predicted_row && predicted_row[u] > 0, truth_row[u] > 0);
    }
  }
  if (!voxels_) return;
  if (const auto gt_pose = datasets::interpolatePose(groundtruth_, e.source.recorded_stamp))
    voxels_->addFrame(frame, mask, *gt_pose);
}

void GroundTruthScorer::onEnd(PipelineReport& report, const mapping::StaticMapBuilder* map) {
  report.has_mask_score = true;
  report.mask_score = keypoints_;
  report.pixel_mask_score = pixels_;
  report.pose_points = pose_points_;
  if (!voxels_ || !map) return;
  report.map_quality = voxels_->evaluate(map->tree());
  report.has_map_quality = true;
}

MemorySampler::MemorySampler(std::string out_dir, int every, const MapStage* map)
    : dir_(std::move(out_dir)), every_(static_cast<std::size_t>(every)), map_(map) {}

void MemorySampler::onFrame(const FrameEvent& e) {
  if (e.report.frames % every_ != 0) return;
  samples_.push_back({static_cast<double>(e.report.frames), residentMemoryMb(),
                      static_cast<double>(map_ ? map_->treeNodes() : 0), heapInUseMb()});
}

void MemorySampler::onEnd(PipelineReport&, const mapping::StaticMapBuilder*) {
  std::ostringstream csv;
  csv << "frame,resident_mb,map_nodes,heap_in_use_mb\n";
  for (const auto& s : samples_)
    csv << s.frame << "," << s.resident_mb << "," << s.map_nodes << "," << s.heap_mb << "\n";
  datasets::writeTextAtomic((fs::path(dir_) / "memory.csv").string(), csv.str());
  datasets::writeImageAtomic((fs::path(dir_) / "memory.png").string(), plotMemory(samples_));
}

CsvLog::CsvLog(std::string path, const char* header) : path_(std::move(path)) {
  csv_ << header << "\n" << std::fixed << std::setprecision(6);
}

void CsvLog::onEnd(PipelineReport&, const mapping::StaticMapBuilder*) {
  datasets::writeTextAtomic(path_, csv_.str());
}

TrackingLog::TrackingLog(const std::string& out_dir)
    : CsvLog((fs::path(out_dir) / "tracking.csv").string(),
             "frame,stamp,state,keyframe,window_shift,window_discarded,rejoined,start_consensus,background,matches,"
             "static,dynamic,inliers,static_landmarks_matched,static_landmarks_agreeing,landmarks_to_refind,"
             "landmarks_refound,gmc_clusters,gmc_static_fallback,position_sigma,pixel_error_median,"
             "depth_error_median,x,y,z,qx,qy,qz,qw,lost_reason") {}

void TrackingLog::onFrame(const FrameEvent& e) {
  const auto& t = e.tracking;
  const Eigen::Quaterniond q(t.T_world_camera.linear());
  const auto& p = t.T_world_camera.translation();
  std::string reason = t.lost_reason;
  // One quoted field, also for readers that split lines at commas.
  std::replace(reason.begin(), reason.end(), '"', '\'');
  std::replace(reason.begin(), reason.end(), ',', ';');
  csv_ << e.report.frames << "," << t.stamp << "," << vo::toString(t.state) << "," << t.new_keyframe << ","
       << t.window_shift << "," << t.window_discarded << "," << t.rejoined << "," << t.start_consensus << "," << t.background_source << ","
       << t.num_matches << ","
       << t.num_static << "," << t.num_dynamic << "," << t.num_inliers << "," << t.static_landmarks_matched << ","
       << t.static_landmarks_agreeing << "," << t.landmarks_to_refind << "," << t.landmarks_refound << ","
       << t.gmc.clusters.size() << "," << t.gmc.static_fallback << ","
       << t.position_sigma << "," << t.pixel_error_median << "," << t.depth_error_median << "," << p.x() << ","
       << p.y() << "," << p.z() << "," << q.x() << "," << q.y() << "," << q.z() << "," << q.w() << ",\"" << reason
       << "\"\n";
}

MatchLog::MatchLog(const std::string& out_dir)
    : CsvLog((fs::path(out_dir) / "map_matches.csv").string(),
             "frame,stamp,state,u,v,x,y,z,origin_x,origin_y,origin_z,origin_stamp,label,established,in_pose,"
             "pose_inlier") {}

void MatchLog::onFrame(const FrameEvent& e) {
  const auto& t = e.tracking;
  for (const auto& m : t.map_matches) {
    const auto& kp = t.keypoints[static_cast<size_t>(m.keypoint)];
    const char label = m.label == MotionLabel::Static ? 'S' : m.label == MotionLabel::Dynamic ? 'D' : 'U';
    csv_ << e.report.frames << "," << t.stamp << "," << vo::toString(t.state) << "," << kp.x << "," << kp.y << ","
         << m.point_cur.x() << "," << m.point_cur.y() << "," << m.point_cur.z() << "," << m.landmark_origin.x() << ","
         << m.landmark_origin.y() << "," << m.landmark_origin.z() << "," << m.landmark_origin_stamp << "," << label
         << "," << m.established << "," << m.in_pose << "," << m.pose_inlier << "\n";
  }
}

}  // namespace gmc::apps
