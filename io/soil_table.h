// The soil parameter table (assets/soils.xml): one <soil id="..."> per soil,
// with the avalanche (flow) parameters of the granular automaton and the
// terramechanics (Bekker / Mohr-Coulomb) parameters of Wong's table.
#pragma once

#include <map>
#include <string>

#include "terrain/flow_law.h"
#include "terrain/soil_mechanics.h"

namespace skidsim::io {

struct SoilRecord {
  terrain::SoilFlowParameters flow;
  // Bekker / Mohr-Coulomb (Wong's table), the reload line, the soil-tool
  // contact and the vertical load model (terrain/soil_mechanics.h).
  terrain::SoilMechanics terramechanics;
  std::string description;
  int line = 0;  // line of the <soil> element in its file
};

using SoilTable = std::map<std::string, SoilRecord>;

// Throws InputError naming file, line, element and attribute on any problem.
SoilTable load_soil_table(const std::string& path);

// The table shipped in assets/: SKIDSIM_ASSETS_DIR (set at build time) unless
// the SKIDSIM_ASSETS environment variable names another assets folder.
std::string default_assets_dir();
std::string default_soil_table_path();

}  // namespace skidsim::io
