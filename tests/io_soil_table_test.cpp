// The soil table: the shipped file loads, and bad files are reported with
// file, line, element and attribute.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/atomic_file.h"
#include "io/soil_table.h"

namespace skidsim::io {
namespace {

TEST(SoilTable, ShippedTableLoadsAndIsValid) {
  const SoilTable table = load_soil_table(default_soil_table_path());
  ASSERT_TRUE(table.count("dry_sand"));
  const SoilRecord& sand = table.at("dry_sand");
  EXPECT_GE(sand.flow.repose_angle_deg, 30.0);  // the project's estimate: 30-34 deg
  EXPECT_LE(sand.flow.repose_angle_deg, 34.0);
  EXPECT_DOUBLE_EQ(sand.terramechanics.n, 1.1);
  EXPECT_DOUBLE_EQ(sand.terramechanics.k_phi_kN_per_m_n2, 1528.43);
  EXPECT_EQ(table.size(), 8u);
  for (const auto& [id, rec] : table) {
    EXPECT_NO_THROW(terrain::validate(rec.flow)) << id;
    EXPECT_NO_THROW(terrain::validate(rec.terramechanics)) << id;
  }
  EXPECT_EQ(sand.terramechanics.model, terrain::VerticalLoadModel::kBekker);
  EXPECT_DOUBLE_EQ(sand.terramechanics.tool_friction_angle_deg, 19.0);
  EXPECT_EQ(table.at("gravel").terramechanics.model, terrain::VerticalLoadModel::kIncompressible);
  // The cutting model: the thesis's wedge unless a soil selects the
  // equation, as the DEM reference's material and the clays do.
  EXPECT_EQ(sand.terramechanics.cutting, terrain::CuttingModel::kThesisWedge);
  EXPECT_EQ(table.at("dem_sand").terramechanics.cutting, terrain::CuttingModel::kEarthmoving);
  for (const char* clay : {"clayey_soil_38", "heavy_clay_25"})
    EXPECT_EQ(table.at(clay).terramechanics.cutting, terrain::CuttingModel::kEarthmoving) << clay;
  EXPECT_DOUBLE_EQ(table.at("dem_sand").terramechanics.cohesion_kPa, 0.0);
  // A flowing layer's friction: calibrated for the DEM's material, the
  // stop angle where a soil has none of its own.
  EXPECT_DOUBLE_EQ(table.at("dem_sand").flow.flowing_friction_deg(), 23.74);
  EXPECT_DOUBLE_EQ(sand.flow.flowing_friction_deg(), sand.flow.stop_angle_deg);
}

std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}

void expect_error(const std::string& xml, const std::vector<std::string>& words) {
  const std::string path = write_temp("skidsim_bad_soils.xml", xml);
  try {
    load_soil_table(path);
    FAIL() << "expected an InputError for:\n" << xml;
  } catch (const InputError& e) {
    for (const auto& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

const char* kFlow =
    "<flow bulk_density_kg_m3=\"1600\" repose_angle_deg=\"33\" stop_angle_deg=\"30\" rolling_speed_m_per_s=\"1\" "
    "rolling_layer_m=\"0.3\" min_flow_layer_m=\"0.005\"/>";
const char* kTm = "<terramechanics n=\"1.1\" k_c=\"0.99\" k_phi=\"1528\" cohesion_kPa=\"1\" friction_angle_deg=\"28\" K_m=\"0.025\"/>";

TEST(SoilTable, BadFilesNameFileLineElementAndAttribute) {
  expect_error("<soils>\n<soil id=\"a\">\n" + std::string(kFlow) + "\n</soil>\n</soils>\n",
               {"skidsim_bad_soils.xml:2", "<soil>", "terramechanics"});
  std::string flow = kFlow;
  flow.replace(flow.find("\"33\""), 4, "\"steep\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n",
               {":3:", "<flow>", "repose_angle_deg", "expected a number"});
  flow = kFlow;
  flow.replace(flow.find("\"33\""), 4, "\"33deg\"");  // trailing junk is not a number
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n",
               {":3:", "repose_angle_deg", "33deg"});
  flow = kFlow;
  flow.replace(flow.find("\"30\""), 4, "\"40\"");  // stop angle above repose
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "stop_angle_deg"});
  flow = kFlow;  // a flowing layer's friction above the repose angle
  flow.insert(flow.find("/>"), " flowing_friction_angle_deg=\"36\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "flowing_friction_angle_deg"});
  flow = kFlow;  // a thin layer's friction below the thick one's
  flow.insert(flow.find("/>"), " grain_diameter_m=\"0.001\" thin_layer_friction_angle_deg=\"20\" thin_layer_decay_grains=\"5\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "thin_layer_friction_angle_deg"});
  flow = kFlow;  // a friction's rise with the inertial number with no grain size to read it
  flow.insert(flow.find("/>"), " rate_friction_angle_deg=\"40\" rate_friction_i0=\"0.1\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "rate_friction_angle_deg"});
  flow = kFlow;  // and one whose I_0 is out of range
  flow.insert(flow.find("/>"), " grain_diameter_m=\"0.001\" thin_layer_friction_angle_deg=\"32\" thin_layer_decay_grains=\"5\" "
                               "rate_friction_angle_deg=\"40\" rate_friction_i0=\"0\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "rate_friction_i0"});
  flow = kFlow;  // a bed that starts to flow above the repose angle
  flow.insert(flow.find("/>"), " bed_start_angle_deg=\"40\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "bed_start_angle_deg"});
  flow = kFlow;  // a sheet faster than the fall that sends it
  flow.insert(flow.find("/>"), " impact_sheet_speed_ratio=\"1.2\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + flow + "\n" + kTm + "\n</soil>\n</soils>\n", {":3:", "impact_sheet_speed_ratio"});
  expect_error("<soils>\n<soil id=\"a\" colour=\"red\">\n" + std::string(kFlow) + kTm + "</soil>\n</soils>\n",
               {":2:", "unknown attribute 'colour'"});
  expect_error("<soils>\n<soil id=\"a\">\n" + std::string(kFlow) + kTm + "</soil>\n<soil id=\"a\">\n" + kFlow + kTm +
                   "</soil>\n</soils>\n",
               {":4:", "duplicate soil id 'a'"});
  expect_error("<soils><soil id=\"a\">", {"skidsim_bad_soils.xml"});  // not well-formed
  // Terramechanics: a bad load model, and a value out of range, name the
  // line and the field.
  std::string tm = kTm;
  tm.insert(tm.find("/>"), " model=\"squishy\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + std::string(kFlow) + "\n" + tm + "\n</soil>\n</soils>\n",
               {":4:", "<terramechanics>", "model", "squishy"});
  tm = kTm;
  tm.insert(tm.find("/>"), " cutting_model=\"bulldozer\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + std::string(kFlow) + "\n" + tm + "\n</soil>\n</soils>\n",
               {":4:", "<terramechanics>", "cutting_model", "bulldozer", "earthmoving"});
  tm = kTm;
  tm.insert(tm.find("/>"), " tool_friction_angle_deg=\"75\"");
  expect_error("<soils>\n<soil id=\"a\">\n" + std::string(kFlow) + "\n" + tm + "\n</soil>\n</soils>\n",
               {":4:", "tool_friction_angle_deg"});
}

}  // namespace
}  // namespace skidsim::io
