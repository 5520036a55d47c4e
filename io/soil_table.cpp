#include "io/soil_table.h"

#include <tinyxml2.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "io/atomic_file.h"
#include "io/xml_reader.h"

namespace skidsim::io {
namespace {

using tinyxml2::XMLElement;

[[noreturn]] void fail(const std::string& path, const XMLElement* e, const std::string& what) {
  fail_at(path, e, what);
}

}  // namespace

SoilTable load_soil_table(const std::string& path) {
  tinyxml2::XMLDocument doc;
  load_xml(doc, path);
  const XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "soils") fail(path, root, "expected the root element <soils>");
  AttributeReader(path, root).reject_unknown();  // <soils> takes no attributes

  SoilTable table;
  for (const XMLElement* s = root->FirstChildElement(); s; s = s->NextSiblingElement()) {
    if (std::string(s->Name()) != "soil") fail(path, s, "unknown element (expected <soil>)");
    AttributeReader soil_attrs(path, s);
    SoilRecord rec;
    rec.line = s->GetLineNum();
    rec.flow.name = soil_attrs.text("id", true);
    rec.description = soil_attrs.text("description", false);
    soil_attrs.reject_unknown();
    if (table.count(rec.flow.name)) fail(path, s, "duplicate soil id '" + rec.flow.name + "'");

    const XMLElement* flow = s->FirstChildElement("flow");
    const XMLElement* tm = s->FirstChildElement("terramechanics");
    if (!flow) fail(path, s, "missing child <flow>");
    if (!tm) fail(path, s, "missing child <terramechanics>");
    for (const XMLElement* c = s->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string name = c->Name();
      if (name != "flow" && name != "terramechanics") fail(path, c, "unknown element (expected <flow> or <terramechanics>)");
    }

    AttributeReader f(path, flow);
    rec.flow.bulk_density_kg_m3 = f.number_in("bulk_density_kg_m3", 100.0, 5000.0);
    rec.flow.repose_angle_deg = f.number_in("repose_angle_deg", 1.0, 89.0);
    rec.flow.stop_angle_deg = f.number_in("stop_angle_deg", 1.0, 89.0);
    rec.flow.rolling_speed_m_per_s = f.number_in("rolling_speed_m_per_s", 1e-4, 100.0);
    rec.flow.rolling_layer_m = f.number_in("rolling_layer_m", 1e-5, 10.0);
    rec.flow.min_flow_layer_m = f.number_in("min_flow_layer_m", 0.0, 10.0);
    // Li & Moshell's slippage model (a site that selects it): the strength of
    // the soil as it lies; the automaton ignores both.
    rec.flow.slip_cohesion_Pa = 1000.0 * f.number_in_or("slip_cohesion_kPa", 0.0, 1e4, 0.0);
    rec.flow.slip_friction_angle_deg = f.number_in_or("slip_friction_angle_deg", 0.0, 89.0, 0.0);
    // Fast flows (a site that turns them on): a flowing layer's bed friction.
    rec.flow.flowing_friction_angle_deg = f.number_in_or("flowing_friction_angle_deg", 0.0, 89.0, 0.0);
    rec.flow.grain_diameter_m = f.number_in_or("grain_diameter_m", 0.0, 1.0, 0.0);
    rec.flow.thin_layer_friction_angle_deg = f.number_in_or("thin_layer_friction_angle_deg", 0.0, 89.0, 0.0);
    rec.flow.thin_layer_decay_grains = f.number_in_or("thin_layer_decay_grains", 0.0, 1000.0, 0.0);
    rec.flow.rate_friction_angle_deg = f.number_in_or("rate_friction_angle_deg", 0.0, 89.0, 0.0);
    rec.flow.rate_friction_i0 = f.number_in_or("rate_friction_i0", 0.0, 10.0, 0.0);
    rec.flow.bed_start_angle_deg = f.number_in_or("bed_start_angle_deg", 0.0, 89.0, 0.0);
    rec.flow.impact_sheet_speed_ratio = f.number_in_or("impact_sheet_speed_ratio", 0.0, 1.0, 0.0);
    f.reject_unknown();
    f.reject_content();
    try {
      terrain::validate(rec.flow);
    } catch (const std::invalid_argument& e) {
      fail(path, flow, e.what());
    }

    AttributeReader t(path, tm);
    auto& m = rec.terramechanics;
    m.n = t.number_in("n", 0.0, 3.0);
    m.k_c_kN_per_m_n1 = t.number_in("k_c", 0.0, 1e7);
    m.k_phi_kN_per_m_n2 = t.number_in("k_phi", 0.0, 1e8);
    m.cohesion_kPa = t.number_in("cohesion_kPa", 0.0, 1e4);
    m.friction_angle_deg = t.number_in("friction_angle_deg", 0.0, 60.0);
    m.shear_modulus_K_m = t.number_in("K_m", 1e-6, 10.0);
    // The reload line, damping, soil-tool contact and load model have
    // defaults (terrain/soil_mechanics.h) a soil may override.
    m.unload_k0_kPa_per_m = t.number_in_or("unload_k0_kPa_per_m", 0.0, 1e9, m.unload_k0_kPa_per_m);
    m.unload_Au_kPa_per_m2 = t.number_in_or("unload_Au_kPa_per_m2", 0.0, 1e10, m.unload_Au_kPa_per_m2);
    m.damping_kPa_s_per_m = t.number_in_or("damping_kPa_s_per_m", 0.0, 1e7, m.damping_kPa_s_per_m);
    m.tool_adhesion_kPa = t.number_in_or("tool_adhesion_kPa", 0.0, 1e4, m.tool_adhesion_kPa);
    m.tool_friction_angle_deg = t.number_in_or("tool_friction_angle_deg", 0.0, 60.0, m.tool_friction_angle_deg);
    m.base_stiffness_kPa_per_m = t.number_in_or("base_stiffness_kPa_per_m", 0.0, 1e10, m.base_stiffness_kPa_per_m);
    const std::string model = t.text("model", false);
    if (model == "incompressible") m.model = terrain::VerticalLoadModel::kIncompressible;
    else if (model.empty() || model == "bekker") m.model = terrain::VerticalLoadModel::kBekker;
    else fail(path, tm, "attribute 'model' = \"" + model + "\": expected \"bekker\" or \"incompressible\"");
    const std::string cutting = t.text("cutting_model", false);
    if (cutting.empty()) m.cutting = terrain::CuttingModel::kThesisWedge;
    else if (!terrain::cutting_model_from_name(cutting, &m.cutting))
      fail(path, tm, "attribute 'cutting_model' = \"" + cutting + "\": expected \"earthmoving\" or \"thesis_wedge\"");
    // Wheels (terrain/wheel_soil.h): Wong and Reece's theta_m coefficients
    // and the slip sinkage model.
    m.wheel_theta_max_c1 = t.number_in_or("wheel_theta_max_c1", 0.0, 1.0, m.wheel_theta_max_c1);
    m.wheel_theta_max_c2 = t.number_in_or("wheel_theta_max_c2", 0.0, 1.0, m.wheel_theta_max_c2);
    const std::string slip_sinkage = t.text("wheel_slip_sinkage", false);
    if (slip_sinkage == "none") m.wheel_slip_sinkage = false;
    else if (slip_sinkage.empty() || slip_sinkage == "lyasko") m.wheel_slip_sinkage = true;
    else fail(path, tm, "attribute 'wheel_slip_sinkage' = \"" + slip_sinkage + "\": expected \"lyasko\" or \"none\"");
    t.reject_unknown();
    t.reject_content();
    try {
      terrain::validate(m);
    } catch (const std::invalid_argument& e) {
      fail(path, tm, e.what());
    }

    table.emplace(rec.flow.name, rec);
  }
  if (table.empty()) fail(path, root, "no <soil> entries");
  return table;
}

std::string default_assets_dir() {
  if (const char* env = std::getenv("SKIDSIM_ASSETS")) return env;
  return SKIDSIM_ASSETS_DIR;
}

std::string default_soil_table_path() { return default_assets_dir() + "/soils.xml"; }

}  // namespace skidsim::io
