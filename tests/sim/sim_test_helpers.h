#pragma once
// Helpers shared by the test_sim sources.
#include <string>

#include "gmc/config/ini.h"
#include "gmc/sim/sim_config.h"
#include "gmc/sim/simulator.h"

/// Quarter-resolution camera keeps the tests fast; geometry is the same.
inline gmc::sim::SimOptions small(gmc::sim::SimOptions o) {
  o.camera.width = 160, o.camera.height = 120;
  o.camera.fx /= 4, o.camera.fy /= 4, o.camera.cx = (o.camera.cx + 0.5) / 4 - 0.5, o.camera.cy = (o.camera.cy + 0.5) / 4 - 0.5;
  return o;
}

/// A shipped scenario, config/sim/<name>.ini.
inline gmc::sim::SimOptions scenario(const std::string& name) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/" + name + ".ini";
  return gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
}

/// Static pixels of frame i, back-projected with their depth and ground-truth pose and
/// projected into frame j, land where frame j sees the same surface (for noise-free
/// options; test_simulator.cpp).
void expectStaticPixelsReprojectExactly(const gmc::sim::SimOptions& o, const std::string& name, int i = 3,
                                        int j = 17);
