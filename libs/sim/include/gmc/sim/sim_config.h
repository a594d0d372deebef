#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include "gmc/sim/simulator.h"

namespace gmc::sim {

/// Loads [Simulator], [Camera], [Trajectory], [People], [Sensor] (strict: unknown keys
/// and unknown sections are errors naming them). Throws gmc::cfg::ConfigError.
SimOptions loadSimOptions(const mrpt::config::CConfigFileBase& ini, const std::string& source);

}  // namespace gmc::sim
