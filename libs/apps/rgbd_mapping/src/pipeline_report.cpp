#include "gmc/apps/pipeline_report.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace gmc::apps {
namespace {
/// A "VmRSS:" style line of /proc/self/status in MB.
double procStatusMb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) return std::stod(line.substr(prefix.size())) / 1024.0;  // kB
  return 0;
}
}  // namespace

double residentMemoryMb() { return procStatusMb("VmRSS"); }
double peakResidentMemoryMb() { return procStatusMb("VmHWM"); }

double heapInUseMb() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
#else
  return 0;
#endif
}

Percentiles Percentiles::of(std::vector<double> v) {
  Percentiles p;
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const double pos = q * static_cast<double>(v.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(pos));
    const size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
  };
  p.median = at(0.5);
  p.p95 = at(0.95);
  return p;
}

void PipelineReport::addFrame(const vo::FrameTracking& t, double map_insert_ms, double pipeline_ms) {
  ++frames;
  if (t.tracked()) ++tracked;
  if (t.state == vo::TrackingState::Lost) ++lost;
  if (t.state == vo::TrackingState::Reanchored) ++reanchored, ++lost;
  if (t.pose_undetermined) ++lost_pose_undetermined;
  if (t.new_keyframe) ++keyframes;
  static_matches += static_cast<size_t>(t.num_static);
  dynamic_matches += static_cast<size_t>(t.num_dynamic);
  frontend_ms.push_back(t.times.frontend);
  guess_ms.push_back(t.times.guess);
  gmc_ms.push_back(t.times.gmc);
  refine_ms.push_back(t.times.refine);
  odometry_ms.push_back(t.times.total);
  mask_ms.push_back(t.times.mask);
  if (map_insert_ms > 0) {
    map_ms.push_back(map_insert_ms);
    ++map_inserts;
  }
  total_ms.push_back(pipeline_ms);
}

namespace {
void stage(std::ostringstream& os, const char* name, const std::vector<double>& v, bool last = false) {
  const auto p = Percentiles::of(v);
  os << "    \"" << name << "\": {\"median\": " << p.median << ", \"p95\": " << p.p95 << "}"
     << (last ? "\n" : ",\n");
}
}  // namespace

std::string PipelineReport::toJson() const {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "{\n";
  os << "  \"frames\": " << frames << ",\n  \"tracked\": " << tracked << ",\n  \"lost\": " << lost
     << ",\n  \"lost_pose_undetermined\": " << lost_pose_undetermined << ",\n  \"reanchored\": " << reanchored
     << ",\n  \"dropped\": " << dropped
     << ",\n  \"skipped\": " << skipped << ",\n  \"keyframes\": " << keyframes
     << ",\n  \"map_inserts\": " << map_inserts << ",\n  \"interrupted\": "
     << (interrupted ? "true" : "false") << ",\n  \"wall_seconds\": " << wall_seconds
     << ",\n  \"peak_rss_mb\": " << peak_rss_mb << ",\n  \"fps\": " << (wall_seconds > 0 ? frames / wall_seconds : 0.0)
     << ",\n  \"static_matches\": " << static_matches << ",\n  \"dynamic_matches\": "
     << dynamic_matches << ",\n";
  os << "  \"ms\": {\n";
  stage(os, "frontend", frontend_ms);
  stage(os, "guess", guess_ms);
  stage(os, "gmc", gmc_ms);
  stage(os, "refinement", refine_ms);
  stage(os, "odometry", odometry_ms);
  stage(os, "dynamic_mask", mask_ms);
  stage(os, "mapping", map_ms);
  stage(os, "total", total_ms, true);
  os << "  }";
  if (has_map) os << ",\n  \"map\": " << mapping::toJson(map);
  if (has_map_quality) os << ",\n  \"map_quality\": " << mapping::toJson(map_quality);
  if (has_mask_score)
    os << ",\n  \"dynamic_matches_vs_masks\": {\"precision\": " << mask_score.precision()
       << ", \"recall\": " << mask_score.recall() << ", \"tp\": " << mask_score.tp
       << ", \"fp\": " << mask_score.fp << ", \"fn\": " << mask_score.fn << "}"
       << ",\n  \"dynamic_pixels_vs_masks\": {\"precision\": " << pixel_mask_score.precision()
       << ", \"recall\": " << pixel_mask_score.recall() << ", \"tp\": " << pixel_mask_score.tp
       << ", \"fp\": " << pixel_mask_score.fp << ", \"fn\": " << pixel_mask_score.fn << "}";
  os << "\n}\n";
  return os.str();
}

std::string PipelineReport::toText() const {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2);
  os << "frames " << frames << "  tracked " << tracked << "  lost " << lost << "  dropped "
     << dropped << "  skipped " << skipped << "  keyframes " << keyframes
     << (interrupted ? "  (interrupted)" : "") << "\n";
  auto line = [&](const char* name, const std::vector<double>& v) {
    const auto p = Percentiles::of(v);
    os << "  " << std::left << std::setw(11) << name << std::right << std::setw(8) << p.median
       << " ms median " << std::setw(8) << p.p95 << " ms p95\n";
  };
  line("frontend", frontend_ms);
  line("guess", guess_ms);
  line("gmc", gmc_ms);
  line("refinement", refine_ms);
  line("odometry", odometry_ms);
  line("mask", mask_ms);
  line("mapping", map_ms);
  line("total", total_ms);
  os << "  " << (wall_seconds > 0 ? frames / wall_seconds : 0.0) << " frames/s overall, peak resident memory "
     << std::fixed << std::setprecision(0) << peak_rss_mb << " MB\n" << std::defaultfloat << std::setprecision(6);
  if (has_map) os << "  map: " << mapping::toText(map) << "\n";
  if (has_map_quality)
    os << "  map vs ground truth: " << map_quality.ghost_voxels << " ghost voxels (of "
       << map_quality.dynamic_only_voxels << " where only people were), static coverage "
       << map_quality.static_coverage() << "\n";
  if (has_mask_score)
    os << "  dynamic matches vs ground-truth masks: precision " << mask_score.precision()
       << "  recall " << mask_score.recall() << "\n"
       << "  dynamic mask pixels vs ground-truth masks: precision " << pixel_mask_score.precision()
       << "  recall " << pixel_mask_score.recall() << "\n";
  return os.str();
}

}  // namespace gmc::apps
