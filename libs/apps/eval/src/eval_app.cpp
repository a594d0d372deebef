#include "gmc/apps/eval_app.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gmc/apps/command_line.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/evaluation.h"

namespace gmc::apps {
namespace {
const char* kUsage =
    "usage: gmc-eval --gt FILE --est FILE [--gt-frame camera|bonn] [--json OUT.json] [--plot OUT.png] "
    "[--gt-out OUT.txt]";
}

void EvalApp::initialize(const std::vector<std::string>& args) {
  CommandLine line("gmc-eval", kUsage);
  TCLAP::ValueArg<std::string> gt("", "gt", "ground-truth trajectory (TUM format)", false, "", "FILE", line.cmd());
  TCLAP::ValueArg<std::string> est("", "est", "estimated trajectory (TUM format)", false, "", "FILE", line.cmd());
  std::vector<std::string> frames = datasets::kGroundTruthFrames;
  TCLAP::ValuesConstraint<std::string> frame_names(frames);
  TCLAP::ValueArg<std::string> gt_frame("", "gt-frame", "what the ground truth gives poses of", false, "camera",
                                        &frame_names, line.cmd());
  TCLAP::ValueArg<std::string> json("", "json", "write the figures as JSON", false, "", "OUT.json", line.cmd());
  TCLAP::ValueArg<std::string> plot("", "plot", "write a trajectory plot", false, "", "OUT.png", line.cmd());
  TCLAP::ValueArg<std::string> gt_out("", "gt-out", "write the ground truth as compared (camera poses, TUM format)",
                                      false, "", "OUT.txt", line.cmd());
  line.parse(args);
  if (gt.getValue().empty() || est.getValue().empty()) line.fail("--gt and --est are required");
  gt_ = gt.getValue(), est_ = est.getValue(), gt_frame_ = gt_frame.getValue();
  json_ = json.getValue(), plot_ = plot.getValue(), gt_out_ = gt_out.getValue();
}

int EvalApp::run() {
  const auto gt = datasets::readGroundTruth(gt_, gt_frame_);
  const auto est = datasets::readTumTrajectory(est_);
  if (gt.empty()) throw AppError(gt_ + ": no poses");
  if (est.empty()) throw AppError(est_ + ": no poses");
  const auto ate = datasets::computeAte(gt, est);
  if (ate.pairs < 3)
    throw AppError(est_ + ": only " + std::to_string(ate.pairs) +
                   " poses have a ground-truth stamp within 0.02 s (need 3)");
  const auto rpe = datasets::computeRpe(gt, est, 1.0);
  std::printf("ATE  rmse %.6f m  mean %.6f  median %.6f  max %.6f  (%zu pairs)\n", ate.error.rmse,
              ate.error.mean, ate.error.median, ate.error.max, ate.pairs);
  std::printf("RPE  1 s: trans rmse %.6f m  median %.6f  |  rot rmse %.4f deg  median %.4f  (%zu pairs)\n",
              rpe.translation.rmse, rpe.translation.median, rpe.rotation.rmse, rpe.rotation.median,
              rpe.pairs);
  // Diagnostics, not benchmark figures (doc/evaluation.md).
  std::printf("diag  ATE with scale %.6f m (scale %.4f)  |  ", ate.scaled_error.rmse, ate.scale);
  if (std::isnan(rpe.rotation_gain))
    std::printf("rotation gain n/a (the ground truth does not turn over %.0f s)\n", rpe.delta_s);
  else
    std::printf("rotation gain %.4f\n", rpe.rotation_gain);
  if (!gt_out_.empty()) datasets::writeTumTrajectory(gt_out_, gt);
  if (!json_.empty()) datasets::writeTextAtomic(json_, datasets::evaluationJson(ate, rpe));
  if (!plot_.empty())
    datasets::writeImageAtomic(plot_, datasets::plotTrajectory(ate, std::filesystem::path(est_).filename().string()));
  return 0;
}

}  // namespace gmc::apps
