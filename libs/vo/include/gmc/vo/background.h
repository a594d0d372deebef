#pragma once
// Which matches are the static background: camera-motion hypotheses (the motion
// prediction, and 3-point RANSAC restricted to landmarks with static evidence, then to
// every landmark not seen moving), each labelled by GMC, each judged by the static
// evidence its background cluster carries and by its agreement with the motion prior.
// When walkers give more matches than the background, the hypothesis that follows a
// walker makes the walker's young landmarks "static" and the long-lived ones "dynamic",
// and loses. No I/O.
#include <cstdint>
#include <functional>
#include <vector>

#include "gmc/gmc/gmc.h"
#include "gmc/vo/in_place_threshold.h"

namespace gmc::vo {

/// INI section [Background].
struct BackgroundOptions {
  int ransac_iterations = 150;        ///< 3-point hypotheses per pool
  bool ransac_local_optimisation = false;  ///< refit each new best on its inliers (LO-RANSAC)
  double inlier_base = 0.005;         ///< m, 3-D inlier threshold at 0 m ...
  double inlier_per_m2 = 0.002;       ///< ... plus this times depth^2 (Kinect noise)
  double prior_translation = 0.01;    ///< m, std dev of the motion prior per 1/30 s: a
                                      ///< hand-held camera changes its velocity by
                                      ///< < 0.3 m/s in 1/30 s (10 m/s^2); walkers' own
                                      ///< motion is 3-5 cm per frame
  double prior_rotation = 1.0;        ///< deg, the same for rotation (30 deg/s change)
  double start_translation = 0.01;    ///< m per 1/30 s, the prior's std dev while the velocity is
                                      ///< unknown (a map's first frame); 0.05 = walking, 1.5 m/s
  double start_rotation = 1.0;        ///< deg, the same for rotation (3 = 90 deg/s)
  int min_static_landmarks = 20;      ///< judge agreement once this many static landmarks match ...
  double min_static_agreement = 0.3;  ///< ... and call the frame lost when fewer agree
  // A young map (its first second, before static evidence can exist) has only one
  // frame's geometry to tell the room from walkers that outnumber it:
  double young_map_seconds = 0;       ///< s after a map starts (or re-anchors) during which it is
                                      ///< young; 0 = off (twelfth round: 1 s fixes synchronous
                                      ///< starts, follows walkers at Bonn's crowded ones)
  bool young_second_motion = true;    ///< young map: also the best motion of what the first leaves
                                      ///< (a group walking in step is the first, the room the second)
  double occlusion_radius = 40;       ///< px, young map: neighbours that vote on occlusion (0 = off)
  double occlusion_margin = 0.3;      ///< m, depth step that counts as occlusion
  bool young_refine_inliers = true;   ///< young map: refine only on the hypothesis' inliers (GMC's
                                      ///< one-frame labels cannot split 3 cm at 3 m; a mix would)

  /// The 3-D inlier threshold these options define: what "in place" means everywhere.
  InPlaceThreshold inPlace() const { return {inlier_base, inlier_per_m2}; }

  template <class V>
  void visit(V& v) {
    v("ransac_iterations", ransac_iterations, 0, 100000, "3-point hypotheses per sampling pool");
    v("ransac_local_optimisation", ransac_local_optimisation,
      "refit each new best hypothesis on its inliers and keep the refit when it scores at least as high (LO-RANSAC)");
    v("inlier_base", inlier_base, 1e-4, 10.0, "m, 3-D inlier threshold at zero depth");
    v("inlier_per_m2", inlier_per_m2, 0.0, 10.0, "inlier threshold growth per depth^2");
    v("prior_translation", prior_translation, 1e-4, 100.0,
      "m, std dev of the constant-velocity prior's translation per 1/30 s");
    v("prior_rotation", prior_rotation, 1e-3, 180.0, "deg, the same for rotation");
    v("start_translation", start_translation, 1e-4, 100.0,
      "m, std dev of the prior's translation per 1/30 s while the velocity is unknown (a map's first frame)");
    v("start_rotation", start_rotation, 1e-3, 180.0, "deg, the same for rotation");
    v("min_static_landmarks", min_static_landmarks, 1, 100000,
      "matched static-evidence landmarks needed before their agreement is judged");
    v("min_static_agreement", min_static_agreement, 0.0, 1.0,
      "lost when fewer of the matched static-evidence landmarks are labelled static");
    v("young_map_seconds", young_map_seconds, 0.0, 1000.0,
      "s after a map starts (or re-anchors) during which it is young, while fewer than min_static_landmarks match");
    v("young_second_motion", young_second_motion,
      "young map: also try the best motion of the matches the first motion leaves out");
    v("young_refine_inliers", young_refine_inliers, "young map: refine on the chosen motion's 3-D inliers only");
    v("occlusion_radius", occlusion_radius, 0.0, 1000.0,
      "px, young map: image neighbours of opposite labels vote on which is in front (0 = off)");
    v("occlusion_margin", occlusion_margin, 0.0, 10.0, "m, depth difference that counts as one in front of the other");
  }
};

/// Rigid transform mapping src onto dst (least squares, no scale); false below 3 points.
bool fitRigid(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, Isometry& T);
/// The same for exactly three points, without allocating (sampling loops).
bool fitRigid(const Eigen::Matrix3d& src, const Eigen::Matrix3d& dst, Isometry& T);

/// xorshift64*: deterministic, cheap random numbers for RANSAC sampling.
class Xorshift64 {
 public:
  explicit Xorshift64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// A stream's built-in seed, or (run_seed != 0) another stream derived from both
  /// ([Odometry] random_seed): equally valid samples, for measuring how much a result
  /// owes to chance. Never 0 (xorshift's fixed point).
  static std::uint64_t seedFor(std::uint64_t built_in, std::uint64_t run_seed);

 private:
  std::uint64_t state_;
};

/// 3-point RANSAC for dst(i) ~ T * src(i) over the correspondences `pool`: `iterations`
/// samples (skipped when an index repeats or the three source points are nearly
/// collinear, which gives unstable rotations), each fitted by fitRigid and scored by
/// `score`. The first best-scoring T, or `fallback` when no sample was usable (or the
/// pool has fewer than three). With `refine`, each new best is also refined and the
/// refined T scored (LO-RANSAC). `score(T, bar)` may stop counting once T's score is sure
/// to stay below `bar` (the best so far) and return anything below it.
using RigidScore = std::function<double(const Isometry&, double bar)>;
Isometry ransacRigid(const std::vector<int>& pool, int iterations, Xorshift64& rng,
                     const std::function<Eigen::Vector3d(int)>& src, const std::function<Eigen::Vector3d(int)>& dst,
                     const RigidScore& score, const Isometry& fallback,
                     const std::function<Isometry(const Isometry&)>& refine = {});

/// Per match: how far its landmark is trusted (0 suspect .. 1 static evidence), whether
/// it has static evidence, and whether it is known to be on a moving object (given from
/// outside, e.g. a person segmenter's pixel labels: labelled dynamic under every
/// hypothesis; empty = none known).
struct MatchTrust {
  std::vector<double> weight;
  std::vector<std::uint8_t> established;
  std::vector<std::uint8_t> known_dynamic;
};

struct BackgroundChoice {
  Isometry T_ref_cur = Isometry::Identity();  ///< chosen motion (current -> reference frame)
  GmcResult gmc;                              ///< GMC's labels under it
  const char* source = "prediction";          ///< prediction | ransac_static | ransac_all
  double score = 0;                           ///< evidence-weighted static support x prior
  int established_matched = 0;                ///< matches on static-evidence landmarks ...
  int established_agreeing = 0;               ///< ... of which labelled static
  bool trustworthy = true;                    ///< false: the static landmarks disagree
  bool young = false;                         ///< fewer than min_static_landmarks static landmarks matched
  std::vector<std::uint8_t> inlier;           ///< young map with young_refine_inliers only (else
                                              ///< empty): per match, within the 3-D threshold of
                                              ///< T_ref_cur; the refinement takes only these
};

/// What the odometry knows about the frame beyond its matches.
struct SelectionContext {
  double frame_gap = 1 / 30.0;  ///< s since the last tracked frame (scales the prior)
  bool velocity_known = true;   ///< false on a map's first frame: the prediction is a guess
  bool young_map = false;       ///< the map is younger than young_map_seconds
  int image_width = 640, image_height = 480;
};

class BackgroundSelector {
 public:
  explicit BackgroundSelector(const BackgroundOptions& options, const GmcParams& gmc);
  const BackgroundOptions& options() const { return options_; }
  /// Another sampling stream (Xorshift64::seedFor); 0 = the built-in one.
  void reseed(std::uint64_t run_seed) { rng_ = Xorshift64(Xorshift64::seedFor(kSeed, run_seed)); }

  /// matches: point_ref in the predicted camera frame, so the prediction is the identity
  /// motion (the motion prior is centred there).
  void select(const std::vector<MotionMatch>& matches, const MatchTrust& trust, const SelectionContext& context,
              BackgroundChoice& out);

 private:
  /// The matches with weight, laid out for scoring hypotheses: RANSAC scores every
  /// sample against all of them, the selection's largest cost.
  struct WeightedPoints {
    Eigen::Matrix3Xd cur, ref;
    std::vector<double> threshold_sq;  ///< squared 3-D inlier threshold at the match's depth
    std::vector<double> weight;
    std::vector<double> rest;  ///< weight from this match to the last: what a score can still gain
  };
  /// Packs matches[weighted] (the matches with weight > 0) into weighted_.
  void gatherWeighted(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                      const std::vector<int>& weighted);
  /// Weighted number of matches within the 3-D inlier threshold under T_ref_cur; stops
  /// counting (and returns less than `bar`) once it cannot reach `bar`.
  double support(const Isometry& T_ref_cur, double bar) const;
  /// Samples from `pool`, scored on weighted_ (gatherWeighted first); with LO-RANSAC each
  /// new best is polished on the weighted matches, the set support() counts.
  Isometry ransac(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                  const std::vector<int>& pool, const Isometry& fallback);
  Isometry polish(const std::vector<MotionMatch>& matches, const std::vector<double>& weight,
                  Isometry T) const;
  /// Neighbour pairs (static, dynamic) where the static one is in front / behind.
  void occlusionVotes(const std::vector<MotionMatch>& matches, const std::vector<MotionLabel>& labels,
                      double& front, double& behind) const;
  /// The motion prior's weight of T (a departure from the prediction, which is the identity).
  double priorFactor(const Isometry& T, double frame_gap, bool velocity_known) const;
  bool inlier(const MotionMatch& m, const Isometry& T, double scale = 1.0) const;

  BackgroundOptions options_;
  GmcClassifier gmc_;
  GmcResult scratch_;
  WeightedPoints weighted_;
  static constexpr std::uint64_t kSeed = 0x9E3779B97F4A7C15ull;
  Xorshift64 rng_{kSeed};
};

}  // namespace gmc::vo
