#include "texture.h"

namespace gmc::sim::detail {
namespace {

/// Integer cell of a coordinate, as a hash input (negative cells hash fine).
inline std::uint64_t cell(double x) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x))); }

Eigen::Vector3d hsvToRgb(double h, double s, double v) {
  h = (h - std::floor(h)) * 6;
  s = std::clamp(s, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
  const int i = std::min(5, static_cast<int>(h));
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), r = v * (1 - s * (1 - f));
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  switch (i) {
    case 0: c = {v, r, p}; break;
    case 1: c = {q, v, p}; break;
    case 2: c = {p, v, r}; break;
    case 3: c = {p, q, v}; break;
    case 4: c = {r, p, v}; break;
    default: c = {v, p, q}; break;
  }
  return 255 * c;
}

/// A colour of the material's palette, chosen by hash `h`.
Eigen::Vector3d paletteColour(const Material& m, std::uint64_t h) {
  const double hue = m.hue + m.hue_spread * (unit(h) - 0.5);
  const double sat = m.saturation * (0.5 + 0.9 * unit(mix(h + 1)));
  const double val = m.value * (0.45 + 0.75 * unit(mix(h + 2)));
  return hsvToRgb(hue, sat, val);
}

/// Smooth value noise in [0, 1] (bilinear between hashed lattice values, smoothstep).
double valueNoise(std::uint64_t seed, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  const double sx = ax * ax * (3 - 2 * ax), sy = ay * ay * (3 - 2 * ay);
  auto at = [&](double i, double j) { return unit(hash(seed, cell(i), cell(j), 77)); };
  const double top = at(fx, fy) * (1 - sx) + at(fx + 1, fy) * sx;
  const double bottom = at(fx, fy + 1) * (1 - sx) + at(fx + 1, fy + 1) * sx;
  return top * (1 - sy) + bottom * sy;
}

Eigen::Vector3d tiles(const Material& m, double s, double t) {
  const double gs = s / m.scale, gt = t / m.scale;
  const double fi = std::floor(gs), fj = std::floor(gt);
  const std::uint64_t h = hash(m.seed, cell(gs), cell(gt));
  const double split_u = 0.25 + 0.5 * unit(mix(h + 1)), split_v = 0.25 + 0.5 * unit(mix(h + 2));
  const int quadrant = (gs - fi > split_u ? 1 : 0) + (gt - fj > split_v ? 2 : 0);
  Eigen::Vector3d c = paletteColour(m, mix(h + 3 + static_cast<std::uint64_t>(quadrant)));
  // A darker disc in some tiles: curved edges and corners at a smaller scale.
  if (unit(mix(h + 9)) < 0.35) {
    const double du = gs - fi - 0.5, dv = gt - fj - 0.5;
    if (du * du + dv * dv < 0.06) c *= 0.35;
  }
  return c;
}

Eigen::Vector3d poster(const Material& m, double s, double t, double width, double height) {
  const double margin = 0.03, down = height - t;  // content laid out from the top
  const Eigen::Vector3d paper = hsvToRgb(m.hue, 0.05, 0.95);
  if (s < margin || s > width - margin || down < margin || t < margin) return paper;
  const double picture_bottom = 0.55 * height;
  if (t > picture_bottom) {  // picture: a background and overlapping rectangles / discs
    Eigen::Vector3d c = paletteColour(m, hash(m.seed, 1));
    for (std::uint64_t k = 0; k < 5; ++k) {
      const std::uint64_t h = hash(m.seed, 2, k);
      const double cs = margin + (width - 2 * margin) * unit(h);
      const double ct = picture_bottom + (height - margin - picture_bottom) * unit(mix(h + 1));
      const double size = (0.06 + 0.12 * unit(mix(h + 2))) * width;
      const double ds = s - cs, dt = t - ct;
      const bool inside = unit(mix(h + 3)) < 0.5 ? std::abs(ds) < size && std::abs(dt) < 0.7 * size
                                                 : ds * ds + dt * dt < size * size;
      if (inside) c = paletteColour(m, mix(h + 4));
    }
    return c;
  }
  // Lines of glyphs, each a 3 x 3 block pattern (strokes large enough to survive 5 m).
  const double stroke = 0.035, pitch_s = 4 * stroke, pitch_t = 4.5 * stroke;
  const double line = std::floor((down - 0.45 * height) / pitch_t), col = std::floor((s - margin) / pitch_s);
  const double ls = (s - margin) / stroke - 4 * col, lt = (down - 0.45 * height) / stroke - 4.5 * line;
  if (line < 0 || ls >= 3 || lt >= 3) return paper;
  const std::uint64_t g = hash(m.seed, 3, cell(line), cell(col));
  if (unit(g) < 0.2) return paper;  // a space between words
  const int bit = static_cast<int>(lt) * 3 + static_cast<int>(ls);
  const bool ink = ((mix(g) >> bit) & 1u) || bit == 4;  // the centre stroke is always inked
  return ink ? hsvToRgb(m.hue + 0.5, 0.6, 0.25) : paper;
}

Eigen::Vector3d cloth(const Material& m, double s, double t) {
  // A checker of two palette colours (X-junctions: strong corners on people too), every
  // patch with its own brightness so that no two patches are alike.
  const double i = std::floor(s / m.scale), j = std::floor(t / m.scale);
  const std::uint64_t parity = static_cast<std::uint64_t>(static_cast<std::int64_t>(i + j) & 1);
  return paletteColour(m, hash(m.seed, 12, parity)) * (0.7 + 0.5 * unit(hash(m.seed, cell(i), cell(j), 13)));
}

Eigen::Vector3d skin(const Material& m, double s, double t) {
  // t: height above the head's centre; the cap above it is hair, with a parting line.
  if (t > 0.02 + 0.03 * std::sin(s * 25)) return hsvToRgb(m.hue + 0.02, 0.5, 0.22 + 0.2 * unit(m.seed));
  return hsvToRgb(m.hue, m.saturation, m.value);
}

Eigen::Vector3d paint(const Material& m, double s, double t) {
  // Broad shading (light falling off over metres), no detail a corner detector could use.
  return hsvToRgb(m.hue, m.saturation, m.value * (0.94 + 0.06 * valueNoise(m.seed, s / 1.5, t / 1.5)));
}

Eigen::Vector3d speckle(const Material& m, double s, double t) {
  // Flecks of m.scale in 10 % of the cells: visible at 1-2 m, blurred to grey farther away.
  const std::uint64_t h = hash(m.seed, cell(s / m.scale), cell(t / m.scale), 21);
  const double fleck = unit(h) < 0.10 ? 0.65 + 0.25 * unit(mix(h)) : 1.0;
  return hsvToRgb(m.hue, m.saturation, m.value * fleck);
}

Eigen::Vector3d plainCloth(const Material& m, double s, double t) {
  // One colour per garment; darker seams along it every ~30 cm and a hem or two across,
  // and on some garments a print (a block of a second colour).
  const Eigen::Vector3d base = paletteColour(m, hash(m.seed, 30));
  const double seam_s = std::abs(std::remainder(s, 0.3)), seam_t = std::abs(std::remainder(t - 0.1, 0.4));
  // Folds (12 x 20 cm) and a knit / weave grain (2.5 cm) that only a near camera resolves.
  double shade = (0.75 + 0.45 * valueNoise(m.seed + 1, s / 0.12, t / 0.2)) *
                 (0.8 + 0.4 * valueNoise(m.seed + 2, s / 0.025, t / 0.025));
  if (seam_s < 0.006 || seam_t < 0.006) shade *= 0.6;
  const std::uint64_t h = hash(m.seed, 31);
  if (unit(h) < 0.4 && std::abs(s - 0.05) < 0.07 && std::abs(t - 0.3) < 0.06) return paletteColour(m, mix(h)) * 1.2;
  return base * shade;
}

}  // namespace

Material randomMaterial(Rng& rng, Pattern pattern, double scale, double hue_lo, double hue_hi,
                        double saturation, double value, double hue_spread) {
  Material m;
  m.pattern = pattern;
  m.seed = rng.next();
  m.scale = scale;
  m.hue = rng.uniform(hue_lo, hue_hi);
  m.saturation = saturation;
  m.value = value;
  m.hue_spread = hue_spread;
  return m;
}

Eigen::Vector3d textureColour(const Material& m, double s, double t, double width, double height) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  switch (m.pattern) {
    case Pattern::Tiles: c = tiles(m, s, t); break;
    case Pattern::Poster: c = poster(m, s, t, width, height); break;
    case Pattern::Cloth: c = cloth(m, s, t); break;
    case Pattern::Skin: c = skin(m, s, t); break;
    case Pattern::Paint: return paint(m, s, t);
    case Pattern::Speckle: return speckle(m, s, t);
    case Pattern::PlainCloth: c = plainCloth(m, s, t); break;
  }
  // Fine smooth noise everywhere: no flat patch, so gradients exist for dense methods too.
  return c * (0.82 + 0.36 * valueNoise(m.seed, s / 0.08, t / 0.08));
}

}  // namespace gmc::sim::detail
