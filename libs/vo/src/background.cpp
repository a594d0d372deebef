#include "gmc/vo/background.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace gmc::vo {

namespace {

/// Matches known to lie on moving objects are dynamic whatever GMC makes of them.
void labelKnownDynamic(const MatchTrust& trust, GmcResult& result) {
  for (size_t i = 0; i < trust.known_dynamic.size(); ++i) {
    if (!trust.known_dynamic[i] || result.labels[i] == MotionLabel::Dynamic) continue;
    (result.labels[i] == MotionLabel::Static ? result.num_static : result.num_undecided) -= 1;
    ++result.num_dynamic;
    result.labels[i] = MotionLabel::Dynamic;
  }
}

template <class Points>
bool fitRigidPoints(const Points& src, const Points& dst, Isometry& T) {
  if (src.cols() < 3) return false;
  const Eigen::Matrix4d M = Eigen::umeyama(src, dst, false);
  if (!M.allFinite()) return false;
  T.matrix() = M;
  return true;
}

}  // namespace

bool fitRigid(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, Isometry& T) {
  return fitRigidPoints(src, dst, T);
}

bool fitRigid(const Eigen::Matrix3d& src, const Eigen::Matrix3d& dst, Isometry& T) {
  return fitRigidPoints(src, dst, T);
}

std::uint64_t Xorshift64::next() {
  state_ ^= state_ >> 12;
  state_ ^= state_ << 25;
  state_ ^= state_ >> 27;
  return state_ * 2685821657736338717ull;
}

std::uint64_t Xorshift64::seedFor(std::uint64_t built_in, std::uint64_t run_seed) {
  if (run_seed == 0) return built_in;
  std::uint64_t z = built_in + run_seed * 0x9E3779B97F4A7C15ull;  // a splitmix64 step
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return z != 0 ? z : built_in;
}

Isometry ransacRigid(const std::vector<int>& pool, int iterations, Xorshift64& rng,
                     const std::function<Eigen::Vector3d(int)>& src, const std::function<Eigen::Vector3d(int)>& dst,
                     const RigidScore& score, const Isometry& fallback,
                     const std::function<Isometry(const Isometry&)>& refine) {
  Isometry best_T = fallback;
  double best = -1;
  Eigen::Matrix3Xd a(3, 3), b(3, 3);
  if (pool.size() < 3) iterations = 0;
  for (int it = 0; it < iterations; ++it) {
    int idx[3];
    for (int& k : idx) k = pool[rng.next() % pool.size()];
    if (idx[0] == idx[1] || idx[0] == idx[2] || idx[1] == idx[2]) continue;
    for (int k = 0; k < 3; ++k) a.col(k) = src(idx[k]), b.col(k) = dst(idx[k]);
    if ((a.col(1) - a.col(0)).cross(a.col(2) - a.col(0)).norm() < 1e-3) continue;
    Isometry T;
    if (!fitRigid(a, b, T)) continue;
    const double s = score(T, best);
    if (s <= best) continue;
    best = s, best_T = T;
    if (!refine) continue;
    // Local optimisation (Chum et al. 2003): a new best is refitted on its inliers, so
    // the winner is the optimum of its basin, not whichever noisy sample hit it first.
    const Isometry refined = refine(T);
    const double r = score(refined, best);
    if (r >= best) best = r, best_T = refined;  // a tie goes to the least-squares fit
  }
  return best_T;
}

namespace {

bool similar(const Isometry& a, const Isometry& b) {
  const Isometry d = a.inverse() * b;
  return d.translation().norm() < 1e-3 && Eigen::AngleAxisd(d.linear()).angle() < 1e-3;
}

}  // namespace

BackgroundSelector::BackgroundSelector(const BackgroundOptions& options, const GmcParams& gmc)
    : options_(options), gmc_(gmc) {}

bool BackgroundSelector::inlier(const MotionMatch& m, const Isometry& T, double scale) const {
  const double thr = scale * options_.inPlace().at(m.point_cur.z());
  return (m.point_ref - T * m.point_cur).squaredNorm() < thr * thr;
}

void BackgroundSelector::gatherWeighted(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                                        const std::vector<int>& weighted) {
  const InPlaceThreshold threshold = options_.inPlace();
  const auto n = static_cast<Eigen::Index>(weighted.size());
  weighted_.cur.resize(3, n);
  weighted_.ref.resize(3, n);
  weighted_.threshold_sq.resize(weighted.size());
  weighted_.weight.resize(weighted.size());
  weighted_.rest.resize(weighted.size() + 1);
  for (size_t k = 0; k < weighted.size(); ++k) {
    const auto i = static_cast<size_t>(weighted[k]);
    const double thr = threshold.at(matches[i].point_cur.z());
    weighted_.cur.col(static_cast<Eigen::Index>(k)) = matches[i].point_cur;
    weighted_.ref.col(static_cast<Eigen::Index>(k)) = matches[i].point_ref;
    weighted_.threshold_sq[k] = thr * thr;
    weighted_.weight[k] = weight[i];
  }
  weighted_.rest.back() = 0;
  for (size_t k = weighted.size(); k-- > 0;) weighted_.rest[k] = weighted_.rest[k + 1] + weighted_.weight[k];
}

double BackgroundSelector::support(const Isometry& T_ref_cur, double bar) const {
  const Eigen::Matrix3d R = T_ref_cur.linear();
  const Eigen::Vector3d t = T_ref_cur.translation();
  // Most samples are hopeless: counted in blocks, a sample stops once the weight left
  // cannot lift it to the bar (with a margin for the sums' rounding, so that the best
  // sample and ties come out as a full count would give them).
  constexpr Eigen::Index kBlock = 32;
  const Eigen::Index n = weighted_.cur.cols();
  const double margin = 1e-9 * (1.0 + std::abs(bar));
  double s = 0;
  for (Eigen::Index k0 = 0; k0 < n; k0 += kBlock) {
    if (s + weighted_.rest[static_cast<size_t>(k0)] < bar - margin) return s;
    for (Eigen::Index k = k0; k < std::min(n, k0 + kBlock); ++k) {
      const Eigen::Vector3d d = weighted_.ref.col(k) - (R * weighted_.cur.col(k) + t);
      if (d.squaredNorm() < weighted_.threshold_sq[static_cast<size_t>(k)]) s += weighted_.weight[static_cast<size_t>(k)];
    }
  }
  return s;
}

Isometry BackgroundSelector::ransac(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                                   const std::vector<int>& pool, const Isometry& fallback) {
  return ransacRigid(
      pool, options_.ransac_iterations, rng_, [&](int i) { return matches[static_cast<size_t>(i)].point_cur; },
      [&](int i) { return matches[static_cast<size_t>(i)].point_ref; },
      [&](const Isometry& T, double bar) { return support(T, bar); }, fallback,
      options_.ransac_local_optimisation ? [&](const Isometry& T) { return polish(matches, weight, T); }
                                         : std::function<Isometry(const Isometry&)>{});
}

Isometry BackgroundSelector::polish(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                                    Isometry T) const {
  // Least squares on the hypothesis' inliers under the tight threshold: GMC measures
  // residuals against it, and a centimetre of error would shift the whole background
  // off the zero-motion pattern.
  std::vector<int> last;
  for (int round = 0; round < 3; ++round) {
    std::vector<int> in;
    for (size_t i = 0; i < matches.size(); ++i)
      if (weight[i] > 0 && inlier(matches[i], T)) in.push_back(static_cast<int>(i));
    if (in.size() < 6 || in == last) break;  // the same inliers give the same fit
    Eigen::Matrix3Xd src(3, in.size()), dst(3, in.size());
    for (size_t k = 0; k < in.size(); ++k) {
      src.col(static_cast<Eigen::Index>(k)) = matches[static_cast<size_t>(in[k])].point_cur;
      dst.col(static_cast<Eigen::Index>(k)) = matches[static_cast<size_t>(in[k])].point_ref;
    }
    fitRigid(src, dst, T);
    last = std::move(in);
  }
  return T;
}

double BackgroundSelector::priorFactor(const Isometry& T, double frame_gap, bool velocity_known) const {
  const double frames = std::max(1.0, frame_gap * 30.0);
  double sigma_t = options_.prior_translation * frames, sigma_r = options_.prior_rotation * frames;
  if (!velocity_known) {
    sigma_t = std::max(sigma_t, options_.start_translation * frames);
    sigma_r = std::max(sigma_r, options_.start_rotation * frames);
  }
  // The matches are in the predicted camera frame: T itself is the departure from the prediction.
  const double t = T.translation().norm() / sigma_t;
  const double r = Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI / sigma_r;
  return std::exp(-0.5 * (t * t + r * r));
}

void BackgroundSelector::occlusionVotes(const std::vector<MotionMatch>& matches,
                                        const std::vector<MotionLabel>& labels, double& front,
                                        double& behind) const {
  // Walkers pass in front of the room, never behind it: a background that stands in
  // front of what it calls moving is the wrong way round. Image neighbours of opposite
  // labels whose depths differ by more than the margin vote.
  front = behind = 0;
  const double r2 = options_.occlusion_radius * options_.occlusion_radius;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (labels[i] != MotionLabel::Static) continue;
    for (size_t j = 0; j < matches.size(); ++j) {
      if (labels[j] != MotionLabel::Dynamic) continue;
      if (static_cast<double>((matches[i].pixel - matches[j].pixel).squaredNorm()) > r2) continue;
      const double dz = matches[j].point_cur.z() - matches[i].point_cur.z();
      if (dz > options_.occlusion_margin) front += 1;
      else if (dz < -options_.occlusion_margin) behind += 1;
    }
  }
}

void BackgroundSelector::select(const std::vector<MotionMatch>& matches, const MatchTrust& trust,
                                const SelectionContext& context, BackgroundChoice& out) {
  const Isometry predicted = Isometry::Identity();  // point_ref is in the predicted frame
  std::vector<int> static_pool, trusted_pool;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (trust.weight[i] > 0) trusted_pool.push_back(static_cast<int>(i));
    if (trust.established[i]) static_pool.push_back(static_cast<int>(i));
  }
  gatherWeighted(matches, trust.weight, trusted_pool);
  struct Candidate {
    Isometry T;
    const char* source;
  };
  std::vector<Candidate> candidates{{polish(matches, trust.weight, predicted), "prediction"}};
  if (static_pool.size() >= 6)
    candidates.push_back({polish(matches, trust.weight, ransac(matches, trust.weight, static_pool, predicted)),
                          "ransac_static"});
  const Isometry T_all = polish(matches, trust.weight, ransac(matches, trust.weight, trusted_pool, predicted));
  candidates.push_back({T_all, "ransac_all"});
  const bool young = context.young_map && static_cast<int>(static_pool.size()) < options_.min_static_landmarks;
  if (young && options_.young_second_motion) {
    std::vector<int> rest;
    for (int i : trusted_pool)
      if (!inlier(matches[static_cast<size_t>(i)], T_all, 2.0)) rest.push_back(i);
    if (rest.size() >= 6)
      candidates.push_back({polish(matches, trust.weight, ransac(matches, trust.weight, rest, predicted)),
                            "ransac_rest"});
  }

  out.score = -1;
  for (size_t c = 0; c < candidates.size(); ++c) {
    bool seen = false;
    for (size_t k = 0; k < c; ++k) seen = seen || similar(candidates[k].T, candidates[c].T);
    if (seen) continue;
    gmc_.classify(matches, candidates[c].T, context.image_width, context.image_height, scratch_);
    labelKnownDynamic(trust, scratch_);
    // Evidence counts the static matches the hypothesis explains: when no cluster sits at
    // zero motion GMC falls back to the largest one, which the hypothesis does not explain.
    double evidence = 0;
    for (size_t i = 0; i < matches.size(); ++i)
      if (scratch_.labels[i] == MotionLabel::Static && inlier(matches[i], candidates[c].T, 2.0))
        evidence += trust.weight[i];
    double score = evidence * priorFactor(candidates[c].T, context.frame_gap, context.velocity_known);
    if (young && options_.occlusion_radius > 0) {
      // Laplace-smoothed share of votes that put the hypothesis' background behind.
      double front = 0, behind = 0;
      occlusionVotes(matches, scratch_.labels, front, behind);
      score *= (behind + 1) / (behind + front + 2);
    }
    if (score > out.score) {
      out.score = score;
      out.T_ref_cur = candidates[c].T;
      out.source = candidates[c].source;
      std::swap(out.gmc, scratch_);
    }
  }
  out.young = young;
  out.inlier.clear();
  if (young && options_.young_refine_inliers)
    for (const auto& m : matches) out.inlier.push_back(inlier(m, out.T_ref_cur) ? 1 : 0);
  out.established_matched = static_cast<int>(static_pool.size());
  out.established_agreeing = 0;
  for (int i : static_pool)
    if (out.gmc.labels[static_cast<size_t>(i)] == MotionLabel::Static) ++out.established_agreeing;
  out.trustworthy = out.established_matched < options_.min_static_landmarks ||
                    out.established_agreeing >= options_.min_static_agreement * out.established_matched;
}

}  // namespace gmc::vo
