// The loader's files: the shipped machine loads and matches the thesis's
// table 9.1; bad URDFs, meshes and parameters are reported with file, line
// and element, never a crash.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/atomic_file.h"
#include "io/loader_files.h"
#include "vehicle/cylinder_geometry.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

TEST(LoaderFiles, ShippedLoaderIsTheThesisMachine) {
  const vehicle::LoaderDescription d = load_loader(default_loader_path());
  ASSERT_EQ(d.links.size(), 3u);
  EXPECT_EQ(d.links[0].mass_kg, 1900.0);  // chassis (thesis ch. 9)
  EXPECT_EQ(d.links[1].mass_kg, 450.0);   // lift arm
  EXPECT_EQ(d.links[2].mass_kg, 300.0);   // bucket
  ASSERT_EQ(d.wheels.size(), 4u);
  ASSERT_EQ(d.cylinders.size(), 2u);
  for (const auto& l : d.links) EXPECT_FALSE(l.visuals.empty()) << l.name;
  for (const auto& w : d.wheels) EXPECT_FALSE(w.visuals.empty()) << w.name;

  // Table 9.1, with the machine standing on its tyres (axle height = r).
  const double axle = d.tyre.radius_m;
  const vehicle::ImplementJoint& arm = d.joints[0];
  const vehicle::ImplementJoint& tilt = d.joints[1];
  double front = -1e9, back = 1e9;
  for (const auto& w : d.wheels) {
    front = std::max(front, w.hub_m.x());
    back = std::min(back, w.hub_m.x());
  }
  EXPECT_NEAR(front - back, 1.03, 1e-9);                                   // B wheelbase
  EXPECT_NEAR(arm.upper_rad - arm.lower_rad, 95.0 * kDeg, 0.1 * kDeg);     // arm travel
  auto pin_at = [&](double q) { return arm.origin.apply(Eigen::AngleAxisd(q, arm.axis) * tilt.origin.position_m); };
  EXPECT_NEAR(axle + pin_at(arm.upper_rad).z(), 2.80, 0.01);               // G hinge pin, fully raised
  EXPECT_NEAR(-tilt.lower_rad, 30.0 * kDeg, 0.1 * kDeg);                   // L rollback at ground
  EXPECT_NEAR(tilt.upper_rad - arm.upper_rad, 40.0 * kDeg, 0.1 * kDeg);    // M dump angle at full height
  // K digging depth: the bucket's floor (bottom of its collision box) with the arm down, level.
  const vehicle::CollisionBox& bucket_box = d.links[2].collision.at(0);
  const double floor_z = axle + pin_at(0.0).z() + bucket_box.pose.position_m.z() - bucket_box.half_extents_m.z();
  EXPECT_NEAR(floor_z, -0.015, 0.01);
  // A overall length with the bucket on the ground, within 5 %.
  double rear = 0.0;
  for (const auto& b : d.links[0].collision) rear = std::min(rear, b.pose.position_m.x() - b.half_extents_m.x());
  const double edge = pin_at(0.0).x() + bucket_box.pose.position_m.x() + bucket_box.half_extents_m.x();
  EXPECT_NEAR(edge - rear, 3.27, 0.05 * 3.27);
  // Bucket width chosen to fit the track (LOADER.md): 1.70 m.
  EXPECT_NEAR(2.0 * bucket_box.half_extents_m.y(), 1.70, 1e-9);
  // Each cylinder's stroke spans its joint's range.
  for (const auto& c : d.cylinders) {
    const auto& j = d.joints[c.joint];
    EXPECT_GE(vehicle::cylinder_kinematics(c, j, j.lower_rad).length_m, c.min_length_m);
    EXPECT_LE(vehicle::cylinder_kinematics(c, j, j.upper_rad).length_m, c.max_length_m);
  }
}

// A copy of the shipped loader folder in a temporary directory, to break.
class BrokenLoader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skidsim_loader_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::copy(fs::path(default_loader_path()).parent_path(), dir_, fs::copy_options::recursive);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void replace(const std::string& name, const std::string& from, const std::string& to) {
    std::ifstream in(path(name));
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(path(name), std::ios::trunc) << text;
  }
  // Loading must throw InputError whose message has every word.
  void expect_error(const std::vector<std::string>& words) {
    try {
      load_loader(path("skidsteer.params.xml"));
      FAIL() << "no error";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      for (const auto& w : words) EXPECT_NE(msg.find(w), std::string::npos) << "'" << w << "' not in: " << msg;
    }
  }
  fs::path dir_;
};

TEST_F(BrokenLoader, MalformedUrdfNamesFileAndLine) {
  replace("skidsteer.urdf", "</link>\n\n  <link name=\"lift_arm\">", "</lnk>\n\n  <link name=\"lift_arm\">");
  expect_error({"skidsteer.urdf:", "MISMATCHED_ELEMENT", "link"});
}

TEST_F(BrokenLoader, MissingMeshNamesUrdfLinkAndFile) {
  fs::remove(path("meshes/bucket.obj"));
  expect_error({"skidsteer.urdf:", "link 'bucket'", "bucket.obj", "no such file"});
}

TEST_F(BrokenLoader, UnreadableMeshNamesUrdfLinkAndFile) {
  std::ofstream(path("meshes/lift_arm.obj"), std::ios::trunc) << "this is not a mesh\n\x01\x02";
  expect_error({"skidsteer.urdf:", "link 'lift_arm'", "lift_arm.obj"});
}

TEST_F(BrokenLoader, NegativeMassNamesLinkAndLine) {
  replace("skidsteer.urdf", "<mass value=\"450\"/>", "<mass value=\"-450\"/>");
  expect_error({"skidsteer.urdf:", "link 'lift_arm'", "mass", "positive"});
}

TEST_F(BrokenLoader, CylinderThatCannotReachItsJointRangeIsRejected) {
  replace("skidsteer.params.xml", "max_length_m=\"1.66\"", "max_length_m=\"1.40\"");
  expect_error({"skidsteer.params.xml:", "<cylinder>", "'lift'", "cannot reach joint 'lift_arm_joint'"});
}

TEST_F(BrokenLoader, UnknownParameterAndOutOfRangeValueAreRejected) {
  replace("skidsteer.params.xml", "relief_MPa=\"34\"", "relief_MPa=\"34\" relif=\"1\"");
  expect_error({"skidsteer.params.xml:", "<drive>", "unknown attribute 'relif'"});
}

TEST_F(BrokenLoader, OutOfRangeParameterIsRejected) {
  replace("skidsteer.params.xml", "mu_x=\"0.9\"", "mu_x=\"-0.9\"");
  expect_error({"skidsteer.params.xml:", "<tyre>", "mu_x", "out of range"});
}

TEST_F(BrokenLoader, UrdfdomErrorsGetTheLineOfTheElementTheyName) {
  replace("skidsteer.urdf", "<parent link=\"lift_arm\"/>", "<parent link=\"lift_armm\"/>");
  // urdfdom names the joint whose parent it cannot find: its line.
  std::ifstream in(path("skidsteer.urdf"));
  std::string text;
  int line = 0, joint_line = 0;
  while (std::getline(in, text) && joint_line == 0) {
    ++line;
    if (text.find("<joint name=\"bucket_joint\"") != std::string::npos) joint_line = line;
  }
  ASSERT_GT(joint_line, 0);
  expect_error({"skidsteer.urdf:" + std::to_string(joint_line) + ":", "not a valid URDF", "lift_armm"});
}

TEST_F(BrokenLoader, WheelListedTwiceOrTwoEnginesAreRejected) {
  replace("skidsteer.params.xml", "<wheel link=\"wheel_rl\" side=\"left\"/>", "<wheel link=\"wheel_fr\" side=\"left\"/>");
  expect_error({"skidsteer.params.xml:", "<wheel>", "listed twice"});
}

TEST_F(BrokenLoader, SecondEngineIsRejected) {
  replace("skidsteer.params.xml", "<implement_pump", "<engine idle_rpm=\"900\"/>\n  <implement_pump");
  expect_error({"skidsteer.params.xml:", "<engine>", "appears twice"});
}

TEST_F(BrokenLoader, WheelAxleOffTheChassisYIsRejected) {
  replace("skidsteer.urdf", "<origin xyz=\"0.515 0.70 0\" rpy=\"0 0 0\"/><axis xyz=\"0 1 0\"/>",
          "<origin xyz=\"0.515 0.70 0\" rpy=\"0 0 1.57\"/><axis xyz=\"1 0 0\"/>");
  expect_error({"skidsteer.urdf:", "joint 'wheel_fl_joint'", "axle"});
}

TEST_F(BrokenLoader, TyresTooSoftToCarryTheMachineAreRejected) {
  replace("skidsteer.params.xml", "radial_stiffness_kN_per_m=\"350\"", "radial_stiffness_kN_per_m=\"3\"");
  expect_error({"skidsteer.params.xml:", "radial_stiffness_kN_per_m", "squash"});
}

TEST_F(BrokenLoader, MeshScaleMustBePositive) {
  replace("skidsteer.urdf", "<mesh filename=\"meshes/bucket.obj\"/>", "<mesh filename=\"meshes/bucket.obj\" scale=\"0 0 0\"/>");
  expect_error({"skidsteer.urdf:", "link 'bucket'", "scale"});
}

TEST_F(BrokenLoader, BucketInteriorErrorsNameTheElement) {
  replace("skidsteer.params.xml", "heel_radius_m=\"0.30\"", "heel_radius_m=\"0.60\"");
  expect_error({"skidsteer.params.xml:", "<interior>", "heel_radius_m"});
}

TEST_F(BrokenLoader, UnknownBucketChildAndBadFillingAreRejected) {
  replace("skidsteer.params.xml", "<filling heaped_volume_m3", "<filing heaped_volume_m3");
  expect_error({"skidsteer.params.xml:", "<filing>", "unknown element"});
}

TEST_F(BrokenLoader, FillingParameterOutOfRangeIsRejected) {
  replace("skidsteer.params.xml", "spreading_eps=\"0.4\"", "spreading_eps=\"0.7\"");
  expect_error({"skidsteer.params.xml:", "<filling>", "spreading_eps", "out of range"});
}

TEST_F(BrokenLoader, MissingUrdfAndMissingParametersAreReported) {
  fs::remove(path("skidsteer.urdf"));
  expect_error({"skidsteer.params.xml:", "skidsteer.urdf", "no such file"});
  EXPECT_THROW(load_loader(path("nope.params.xml")), InputError);
}

}  // namespace
}  // namespace skidsim::io
