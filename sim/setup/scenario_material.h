#pragma once
/// \file
/// The material section of a scenario's organ: contact, friction, friction map, force shading
/// and surface texture. Internal to lap_sim.

#include <string>

#include "sim/setup/scenario.h"
#include "sim/setup/scenario_files.h"
#include "sim/setup/yaml_fields.h"

namespace lap::sim {

/// Reads the material at `n` (field path `field`) into `material`, reporting to `fields`.
void parse_material(YamlFields& fields, ScenarioFiles& files, const YAML::Node& n,
                    const std::string& field, MaterialSpec& material);

}  // namespace lap::sim
