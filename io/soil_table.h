// The soil parameter table (assets/soils.xml): one <soil id="..."> per soil,
// with the avalanche (flow) parameters of the granular automaton and the
// terramechanics (Bekker / Mohr-Coulomb) parameters of Wong's table.
#pragma once

#include <map>
#include <string>

#include "terrain/flow_law.h"

namespace skidsim::io {

// Bekker pressure-sinkage and Mohr-Coulomb shear parameters (Wong, Theory of
// Ground Vehicles), read and validated here for the soil-body interaction.
struct TerramechanicsRecord {
  double n = 1.0;
  double k_c_kN_per_m_n1 = 0.0;    // kN/m^(n+1)
  double k_phi_kN_per_m_n2 = 0.0;  // kN/m^(n+2)
  double cohesion_kPa = 0.0;
  double friction_angle_deg = 30.0;
  double shear_modulus_K_m = 0.025;  // Janosi-Hanamoto K
};

struct SoilRecord {
  terrain::SoilFlowParameters flow;
  TerramechanicsRecord terramechanics;
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
