#include "gmc/apps/eval_app.h"

#include <cstdio>
#include <filesystem>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/evaluation.h"

namespace gmc::apps {
namespace {
const char* kUsage = "usage: gmc-eval --gt FILE --est FILE [--json OUT.json] [--plot OUT.png]";
}

void EvalApp::initialize(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string* target = a == "--gt" ? &gt_ : a == "--est" ? &est_ : a == "--json" ? &json_
                        : a == "--plot" ? &plot_ : nullptr;
    if (!target) throw AppError("unknown argument '" + a + "'\n" + kUsage, 2);
    if (i + 1 >= args.size()) throw AppError(a + " needs a value\n" + kUsage, 2);
    *target = args[++i];
  }
  if (gt_.empty() || est_.empty()) throw AppError(kUsage, 2);
}

int EvalApp::run() {
  const auto gt = datasets::readTumTrajectory(gt_);
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
  if (!json_.empty()) datasets::writeTextAtomic(json_, datasets::evaluationJson(ate, rpe));
  if (!plot_.empty())
    datasets::writeImageAtomic(plot_, datasets::plotTrajectory(ate, std::filesystem::path(est_).filename().string()));
  return 0;
}

}  // namespace gmc::apps
