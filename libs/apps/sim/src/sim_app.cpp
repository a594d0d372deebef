#include "gmc/apps/sim_app.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "gmc/apps/command_line.h"
#include "gmc/config/ini.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"
#include "gmc/gmc/options.h"
#include "gmc/sim/sim_config.h"

namespace gmc::apps {
namespace fs = std::filesystem;
namespace {
const char* kUsage = "usage: gmc-sim <config.ini> --out DIR [--seed N] [--frames N] [--preview I]";

int nonNegative(const TCLAP::ValueArg<int>& arg, int unset) {
  if (!arg.isSet()) return unset;
  if (arg.getValue() < 0)
    throw AppError("--" + arg.getName() + ": " + std::to_string(arg.getValue()) + " is negative; " + kUsage, 2);
  return arg.getValue();
}

/// Removes the folder being assembled unless the run completed (no half-written output).
class PartialDir {
 public:
  explicit PartialDir(fs::path path) : path_(std::move(path)) {
    fs::remove_all(path_);
    for (const char* sub : {"rgb", "depth", "masks"}) fs::create_directories(path_ / sub);
  }
  ~PartialDir() {
    std::error_code ignored;
    if (!path_.empty()) fs::remove_all(path_, ignored);
  }
  PartialDir(const PartialDir&) = delete;
  PartialDir& operator=(const PartialDir&) = delete;
  const fs::path& path() const { return path_; }
  /// Renames the folder to `final_dir` (replacing it) and keeps it.
  void commit(const fs::path& final_dir) {
    fs::remove_all(final_dir);
    fs::rename(path_, final_dir);
    path_.clear();
  }

 private:
  fs::path path_;
};

/// scene.xyz: one "x y z" line per static surface sample (world frame, z up, metres).
void writeSceneSamples(const std::string& path, const sim::Simulator& simulator, double spacing) {
  char line[96];
  std::snprintf(line, sizeof line, "# static surface samples every %.3f m, world frame (z up): x y z\n", spacing);
  std::string text = line;
  for (const auto& p : simulator.staticSurfaceSamples(spacing)) {
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", p.x(), p.y(), p.z());
    text += line;
  }
  datasets::writeTextAtomic(path, text);
}

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

void SimApp::initialize(const std::vector<std::string>& args) {
  TCLAP::CmdLine cmd("synthetic dynamic RGB-D sequence with ground truth", ' ', "", false);
  TCLAP::UnlabeledValueArg<std::string> config("config", "scenario INI", true, "", "config.ini", cmd);
  TCLAP::ValueArg<std::string> out("", "out", "output folder", true, "", "DIR", cmd);
  TCLAP::ValueArg<int> seed("", "seed", "random seed (overrides the INI)", false, 0, "N", cmd);
  TCLAP::ValueArg<int> frames("", "frames", "frame count (overrides the INI)", false, 0, "N", cmd);
  TCLAP::ValueArg<int> preview("", "preview", "write preview.png of frame I", false, 0, "I", cmd);
  parseCommandLine(cmd, "gmc-sim", args, kUsage);
  config_ = config.getValue();
  out_ = out.getValue();
  seed_ = nonNegative(seed, -1);
  frames_ = nonNegative(frames, -1);
  preview_ = nonNegative(preview, -1);
  if (frames_ == 0) throw AppError("--frames: must be at least 1", 2);
}

int SimApp::run() {
  const auto ini = cfg::loadIniFile(config_);
  sim::SimOptions options = sim::loadSimOptions(ini, config_);
  if (seed_ >= 0) options.simulator.seed = seed_;
  if (frames_ > 0) options.simulator.frames = frames_;
  if (preview_ >= options.simulator.frames)
    throw AppError("--preview: frame " + std::to_string(preview_) + " is beyond the last frame (" +
                   std::to_string(options.simulator.frames - 1) + ")", 2);
  const std::string override_error = validateOptions(options.simulator, "Simulator");
  if (!override_error.empty()) throw AppError("--seed/--frames: " + override_error);
  // Refuse to overwrite anything but an earlier gmc-sim output.
  if (fs::exists(out_) && !(fs::exists(fs::path(out_) / "sequence.rawlog") || fs::is_empty(out_)))
    throw AppError(out_ + ": exists and is not a gmc-sim output; choose another --out");
  const fs::path final_dir(out_);
  PartialDir partial(final_dir.parent_path() /
                     ("." + final_dir.filename().string() + ".partial" + std::to_string(::getpid())));
  const fs::path& tmp = partial.path();

  const sim::Simulator simulator(options);
  datasets::RawlogWriter rawlog((tmp / "sequence.rawlog").string());
  std::vector<datasets::TumListEntry> rgb_list, depth_list;
  std::vector<datasets::StampedPose> gt;
  const auto t0 = std::chrono::steady_clock::now();
  double render_seconds = 0;
  const bool tty = isatty(fileno(stderr));
  for (int i = 0; i < simulator.frameCount(); ++i) {
    const auto t_render = std::chrono::steady_clock::now();
    const sim::SimFrame f = simulator.renderFrame(i);
    render_seconds += secondsSince(t_render);
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", f.frame.stamp);
    const std::string name = std::string(stamp) + ".png";
    datasets::writeImageAtomic((tmp / "rgb" / name).string(), f.frame.rgb);
    datasets::writeImageAtomic((tmp / "depth" / name).string(), f.frame.depth);
    datasets::writeImageAtomic((tmp / "masks" / name).string(), f.mask);
    rgb_list.push_back({f.frame.stamp, "rgb/" + name});
    depth_list.push_back({f.frame.stamp, "depth/" + name});
    gt.push_back({f.frame.stamp, f.T_world_camera});
    rawlog.write(f.frame);
    if (i == preview_) datasets::writeImageAtomic((tmp / "preview.png").string(), sim::sideBySide(f));
    if (tty) {
      const double fps = (i + 1) / secondsSince(t0);
      std::fprintf(stderr, "\rgmc-sim: frame %d/%d  %.1f fps  ETA %.0f s   ", i + 1,
                   simulator.frameCount(), fps, (simulator.frameCount() - i - 1) / fps);
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  rawlog.close();
  datasets::writeTumList((tmp / "rgb.txt").string(), rgb_list, "color images (gmc-sim)");
  datasets::writeTumList((tmp / "depth.txt").string(), depth_list, "depth images (gmc-sim), value/5000 = m");
  datasets::writeTumTrajectory((tmp / "groundtruth.txt").string(), gt);
  writeSceneSamples((tmp / "scene.xyz").string(), simulator, 0.02);
  partial.commit(final_dir);
  const double seconds = secondsSince(t0);
  std::printf("%s: %d frames (%dx%d) in %.1f s (rendering %.1f s, writing %.1f s)\n", out_.c_str(),
              simulator.frameCount(), options.camera.width, options.camera.height, seconds, render_seconds,
              seconds - render_seconds);
  return 0;
}

}  // namespace gmc::apps
