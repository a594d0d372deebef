// TUM trajectories (groundtruth.txt, trajectory_tum.txt) and what gmc-eval does with them:
// interpolation, ATE, RPE, the plot. Input: the file's bytes.
// Documented failure: gmc::datasets::InputError. Anything else is a finding.
#include <cmath>

#include "fuzz_util.h"
#include "gmc/datasets/evaluation.h"
#include "gmc/datasets/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace ds = gmc::datasets;
  static const std::string path = gmc::fuzz::scratchPath("groundtruth.txt");
  gmc::fuzz::writeFile(path, reinterpret_cast<const char*>(data), size);
  try {
    const auto traj = ds::readTumTrajectory(path);
    for (size_t i = 0; i < traj.size(); ++i) {
      GMC_FUZZ_CHECK(std::isfinite(traj[i].stamp));
      GMC_FUZZ_CHECK(traj[i].pose.matrix().allFinite());
      GMC_FUZZ_CHECK(i == 0 || traj[i].stamp >= traj[i - 1].stamp);
    }
    if (traj.empty()) return 0;
    for (double f : {-0.5, 0.0, 0.37, 1.0, 1.5}) {
      const double t = traj.front().stamp + f * (traj.back().stamp - traj.front().stamp);
      ds::interpolatePose(traj, t);
    }
    const auto ate = ds::computeAte(traj, traj);
    GMC_FUZZ_CHECK(ate.pairs <= traj.size());
    ds::computeRpe(traj, traj);
    if (ate.pairs >= 2 && traj.size() <= 200) ds::plotTrajectory(ate, "fuzz");
  } catch (const ds::InputError&) {
  }
  return 0;
}
