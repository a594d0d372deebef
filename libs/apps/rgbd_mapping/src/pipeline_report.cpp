#include "gmc/apps/pipeline_report.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

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

void PipelineReport::addFrame(const vo::FrameTracking& t, double pipeline_ms) {
  ++frames;
  if (t.tracked()) ++tracked;
  if (t.state == vo::TrackingState::Lost) ++lost;
  if (t.state == vo::TrackingState::Reanchored) ++reanchored, ++lost;
  if (t.pose_undetermined) ++lost_pose_undetermined;
  if (t.background_untrusted) ++lost_background_untrusted;
  if (t.new_keyframe) ++keyframes;
  if (t.window_discarded) ++windows_discarded;
  if (t.rejoined) ++rejoined;
  if (t.start_consensus) ++start_consensus;
  static_matches += static_cast<size_t>(t.num_static);
  dynamic_matches += static_cast<size_t>(t.num_dynamic);
  frontend_ms.push_back(t.times.frontend);
  guess_ms.push_back(t.times.guess);
  gmc_ms.push_back(t.times.gmc);
  refine_ms.push_back(t.times.refine);
  odometry_ms.push_back(t.times.total);
  mask_ms.push_back(t.times.mask);
  total_ms.push_back(pipeline_ms);
}

void PipelineReport::setMapTimes(std::vector<double> insert_ms) {
  map_inserts = insert_ms.size();
  map_ms = std::move(insert_ms);
}

namespace {
using Json = nlohmann::ordered_json;

Json percentiles(const std::vector<double>& v) {
  const auto p = Percentiles::of(v);
  return {{"median", p.median}, {"p95", p.p95}};
}

Json score(const datasets::BinaryScore& s) {
  return {{"precision", s.precision()}, {"recall", s.recall()}, {"tp", s.tp}, {"fp", s.fp}, {"fn", s.fn}};
}

/// Per stage: items, busy seconds, items per busy second (what the stage can sustain)
/// and per wall second (what it did).
Json stagesJson(const std::vector<PipelineReport::Stage>& stages, double wall_seconds) {
  Json out = Json::object();
  for (const auto& s : stages)
    out[s.name] = {{"items", s.items},
                   {"busy_s", s.busy_s},
                   {"per_busy_s", s.busy_s > 0 ? s.items / s.busy_s : 0.0},
                   {"per_wall_s", wall_seconds > 0 ? s.items / wall_seconds : 0.0}};
  return out;
}
}  // namespace

std::string PipelineReport::toJson() const {
  Json j = {{"frames", frames},          {"tracked", tracked},
            {"lost", lost},              {"lost_pose_undetermined", lost_pose_undetermined},
            {"lost_background_untrusted", lost_background_untrusted},
            {"reanchored", reanchored},  {"dropped", dropped},
            {"skipped", skipped},        {"keyframes", keyframes},
            {"windows_discarded", windows_discarded}, {"rejoined", rejoined},
            {"start_consensus", start_consensus},
            {"map_inserts", map_inserts}, {"map_skipped", map_skipped},
            {"interrupted", interrupted}, {"wall_seconds", wall_seconds},
            {"peak_rss_mb", peak_rss_mb}, {"fps", wall_seconds > 0 ? frames / wall_seconds : 0.0},
            {"static_matches", static_matches}, {"dynamic_matches", dynamic_matches}};
  j["ms"] = {{"frontend", percentiles(frontend_ms)}, {"guess", percentiles(guess_ms)},
             {"gmc", percentiles(gmc_ms)},           {"refinement", percentiles(refine_ms)},
             {"odometry", percentiles(odometry_ms)}, {"dynamic_mask", percentiles(mask_ms)},
             {"mapping", percentiles(map_ms)},       {"total", percentiles(total_ms)}};
  j["stages"] = stagesJson(stages, wall_seconds);
  j["queues"] = Json::object();
  for (const auto& q : queues) j["queues"][q.name] = {{"capacity", q.capacity}, {"high_water", q.high_water}};
  if (!lag_s.empty()) {
    j["realtime_lag_s"] = percentiles(lag_s);
    j["realtime_lag_s"]["max"] = *std::max_element(lag_s.begin(), lag_s.end());
  }
  if (has_map) j["map"] = Json::parse(mapping::toJson(map));
  if (has_map_quality) j["map_quality"] = Json::parse(mapping::toJson(map_quality));
  if (has_mask_score) {
    j["dynamic_matches_vs_masks"] = score(mask_score);
    j["dynamic_pixels_vs_masks"] = score(pixel_mask_score);
    j["pose_points_vs_masks"] = {{"points", pose_points.points},
                                 {"on_people", pose_points.on_people},
                                 {"share_on_people", pose_points.share()}};
  }
  return j.dump(2) + "\n";
}

std::string PipelineReport::toText() const {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2);
  os << "frames " << frames << "  tracked " << tracked << "  lost " << lost << "  dropped "
     << dropped << "  skipped " << skipped << "  keyframes " << keyframes << "  re-anchored " << reanchored
     << "  rejoined " << rejoined << "  start consensus " << start_consensus << "  map skipped " << map_skipped << (interrupted ? "  (interrupted)" : "") << "\n";
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
  if (!lag_s.empty()) {
    const auto lag = Percentiles::of(lag_s);
    os << "  realtime lag " << lag.median << " s median, " << lag.p95 << " s p95, "
       << *std::max_element(lag_s.begin(), lag_s.end()) << " s max\n";
  }
  if (has_map) os << "  map: " << mapping::toText(map) << "\n";
  if (has_map_quality)
    os << "  map vs ground truth: " << map_quality.ghost_voxels << " ghost voxels (of "
       << map_quality.dynamic_only_voxels << " where only people were), static coverage "
       << map_quality.static_coverage() << "\n";
  if (has_mask_score)
    os << "  dynamic matches vs ground-truth masks: precision " << mask_score.precision()
       << "  recall " << mask_score.recall() << "\n"
       << "  dynamic mask pixels vs ground-truth masks: precision " << pixel_mask_score.precision()
       << "  recall " << pixel_mask_score.recall() << "\n"
       << "  pose points on people (ground-truth masks): " << pose_points.on_people << " of "
       << pose_points.points << " (" << std::fixed << std::setprecision(1) << 100.0 * pose_points.share()
       << " %)\n" << std::defaultfloat << std::setprecision(6);
  return os.str();
}

}  // namespace gmc::apps
