#pragma once
// Procedural surface textures. Colours are functions of the surface coordinates only, so a
// surface looks the same from every view (exact for photometric checks), and every cell
// has its own hashed colours, so no two places of the scene look alike (no matching
// ambiguity). Patterns are corner-rich at the scale a detector sees from 1-6 m.
#include <Eigen/Core>

#include <cstdint>

#include "random.h"

namespace gmc::sim::detail {

enum class Pattern : std::uint8_t {
  Tiles,   ///< square tiles split into four quadrants at a random point, some with a disc
  Poster,  ///< paper with a picture of rectangles and discs above lines of glyphs
  Cloth,   ///< checker of two colours, per-patch brightness (people's clothes)
  Skin,    ///< skin tone with a darker hair cap (heads)
  Paint,   ///< bare painted wall: one colour, faint broad shading only
  Speckle, ///< pale floor covering with small dark flecks (corners only up close)
  PlainCloth,  ///< solid cloth with seams, hems, broad folds and a pocket or print
};

struct Material {
  Pattern pattern = Pattern::Tiles;
  std::uint64_t seed = 0;
  double scale = 0.2;     ///< cell size (m): tile or patch side
  double hue = 0;         ///< base colour, HSV in [0, 1]
  double saturation = 0.5;
  double value = 0.7;
  double hue_spread = 0.5;  ///< how far cell hues wander from the base (turns)

  /// The same palette with another seed (the faces of one box look alike, not equal).
  Material reseeded(std::uint64_t salt) const {
    Material m = *this;
    m.seed = mix(seed + salt);
    return m;
  }
};

/// Material with a random seed and palette: base hue in [hue_lo, hue_hi].
Material randomMaterial(Rng& rng, Pattern pattern, double scale, double hue_lo, double hue_hi,
                        double saturation, double value, double hue_spread);

/// RGB colour (0-255) at surface coordinates (s, t) in metres; `width`/`height` is the
/// extent of the face (posters lay out their content in it). t grows upwards on walls.
Eigen::Vector3d textureColour(const Material& m, double s, double t, double width, double height);

}  // namespace gmc::sim::detail
