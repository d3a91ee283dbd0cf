#pragma once
/// @file SimulationConfig.h
/// Loading and saving lidarseg::sim::SimulationParams (section [simulation]).

#include <string>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>

#include "lidarseg/sim/Simulation.h"

namespace lidarseg::mrpt_adapter {

inline const std::string kSimulationSection = "simulation";

/// Keys of the [simulation] section (config/simulate.ini documents each).
std::vector<std::string> simulationKeys();

/// Reads the keys present in `section` into `params` (the sensor profile itself is chosen
/// by name elsewhere; its noise and frequency can be overridden here), then validates.
/// @throws std::invalid_argument naming source, line, section and key.
void loadSimulationParams(sim::SimulationParams& params, const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section = kSimulationSection,
                          const std::string& source = "configuration");
void saveSimulationParams(const sim::SimulationParams& params, mrpt::config::CConfigFileBase& cfg,
                          const std::string& section = kSimulationSection);
/// Loads `section` of an INI or YAML file on top of `params`.
void loadSimulationParamsFile(sim::SimulationParams& params, const std::string& path,
                              const std::string& section = kSimulationSection);

}  // namespace lidarseg::mrpt_adapter
