#include "gmc/sim/sim_config.h"

#include "gmc/config/ini.h"

namespace gmc::sim {

SimOptions loadSimOptions(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  SimOptions o;
  cfg::loadSection(ini, "Simulator", o.simulator, source);
  cfg::loadSection(ini, "Camera", o.camera, source);
  cfg::loadSection(ini, "Trajectory", o.trajectory, source);
  cfg::loadSection(ini, "People", o.people, source);
  cfg::loadSection(ini, "Sensor", o.sensor, source);
  cfg::loadSection(ini, "Room", o.room, source);
  const auto unknown = cfg::unknownSections(ini, {"Simulator", "Camera", "Trajectory", "People", "Sensor", "Room"});
  if (!unknown.empty()) throw cfg::ConfigError(source + ": unknown section [" + unknown.front() + "]");
  if (o.people.speed_min > o.people.speed_max)
    throw cfg::ConfigError(source + ": [People] speed_min is above speed_max");
  if (o.people.pause_min > o.people.pause_max)
    throw cfg::ConfigError(source + ": [People] pause_min is above pause_max");
  if (o.people.distance_min > o.people.distance_max)
    throw cfg::ConfigError(source + ": [People] distance_min is above distance_max");
  if (o.people.group > 0 && o.trajectory.style != "walk")
    throw cfg::ConfigError(source + ": [People] group needs [Trajectory] style = walk");
  if (o.trajectory.style == "follow" && o.people.walkers < 1)
    throw cfg::ConfigError(source + ": [Trajectory] style = follow needs [People] walkers >= 1");
  return o;
}

}  // namespace gmc::sim
