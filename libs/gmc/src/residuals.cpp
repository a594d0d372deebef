// Eq. (3): depth-normalised 3-D residuals and their patterns in the four shifted tables.
#include "classify_steps.h"

namespace gmc::detail {

ResidualNormaliser::ResidualNormaliser(const GmcParams& p, const Isometry& T_ref_cur)
    : R(T_ref_cur.linear()),
      t(T_ref_cur.translation()),
      alpha(p.alpha),
      z_depth_power(p.z_depth_power),
      squared(p.z_depth_power == 2.0),
      inv_int{static_cast<float>(1.0 / p.e_int_x), p.use_y ? static_cast<float>(1.0 / p.e_int_y) : 0.f,
              static_cast<float>(1.0 / p.e_int_z)} {}

void computeResiduals(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur, int image_width,
                      int image_height, const GmcParams& p, Residuals& out) {
  const size_t n = matches.size();
  out.e.resize(n);
  out.valid.assign(n, 0);
  out.code.resize(n);
  out.num_valid = 0;
  const ResidualNormaliser normalise(p, T_ref_cur);
  for (size_t i = 0; i < n; ++i) {
    if (!isUsable(matches[i], image_width, image_height)) continue;
    out.e[i] = normalise(matches[i]);
    out.code[i] = patternCodes(out.e[i]);
    out.valid[i] = 1;
    ++out.num_valid;
  }
}

}  // namespace gmc::detail
