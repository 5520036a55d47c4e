// The loader's files: the shipped machine loads and matches the thesis's
// table 9.1; bad URDFs, meshes and parameters are reported with file, line
// and element, never a crash.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/physical_constants.h"
#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/loader_files.h"
#include "vehicle/cylinder_geometry.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;
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
  // Bucket width chosen to fit the track (docs/loader.md, "The machine"): 1.70 m.
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

TEST_F(BrokenLoader, CuttingEdgeThicknessOutOfRangeIsRejected) {
  replace("skidsteer.params.xml", "cutting_edge_thickness_m=\"0.02\"", "cutting_edge_thickness_m=\"0.5\"");
  expect_error({"skidsteer.params.xml:", "<interior>", "cutting_edge_thickness_m", "out of range"});
}

TEST_F(BrokenLoader, UnknownBucketChildAndBadFillingAreRejected) {
  replace("skidsteer.params.xml", "<filling heaped_volume_m3", "<filing heaped_volume_m3");
  expect_error({"skidsteer.params.xml:", "<filing>", "unknown element"});
}

TEST_F(BrokenLoader, FillingParameterOutOfRangeIsRejected) {
  replace("skidsteer.params.xml", "spreading_eps=\"0.4\"", "spreading_eps=\"0.7\"");
  expect_error({"skidsteer.params.xml:", "<filling>", "spreading_eps", "out of range"});
}

// Cylinder geometry that cannot move its joint is refused with the file,
// the line and the element, instead of passing `check` with a 0 s lift.
TEST_F(BrokenLoader, CylinderPinsOnTheAxisOrCoincidentAreRefused) {
  // The same coordinates for both pins: the child pin sits on the joint's
  // axis, so the length never changes.
  replace("skidsteer.params.xml", "parent_pin=\"-0.70 0 -0.20\" child_pin=\"0.1197 0 -0.4563\"",
          "parent_pin=\"0 0 0\" child_pin=\"0 0 0\"");
  expect_error({"skidsteer.params.xml:27:", "<cylinder>", "'lift'", "child_pin", "axis of joint 'lift_arm_joint'"});
}

TEST_F(BrokenLoader, CylinderPinsThatMeetAreRefused) {
  // The parent pin where the child pin is with the arm lowered: 0 m apart.
  replace("skidsteer.params.xml", "parent_pin=\"-0.70 0 -0.20\"", "parent_pin=\"-0.1583 0 0.5887\"");
  expect_error({"skidsteer.params.xml:27:", "<cylinder>", "'lift'", "coincide"});
}

TEST_F(BrokenLoader, CylinderWithoutAMomentArmIsRefused) {
  // A child pin 1.5 cm off the axis: past the axis check, but its moment
  // arm (at most 1.5 cm) falls under a centimetre or turns over.
  replace("skidsteer.params.xml", "child_pin=\"0.1197 0 -0.4563\"", "child_pin=\"0.015 0 0\"");
  try {
    load_loader(path("skidsteer.params.xml"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("skidsteer.params.xml:27: <cylinder>"), std::string::npos) << msg;
    EXPECT_TRUE(msg.find("moment arm") != std::string::npos || msg.find("dead centre") != std::string::npos ||
                msg.find("moves only") != std::string::npos)
        << msg;
  }
}

// Every number of the URDF, checked in its text before urdfdom reads it
// (urdfdom hands back what it cannot parse as 0): the message names the
// URDF, the line, the link or joint, the element and the attribute.
TEST_F(BrokenLoader, UrdfNumbersAreCheckedWhereTheyEnter) {
  struct Case {
    const char* from;
    const char* to;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"<mass value=\"450\"/>", "<mass value=\"nan\"/>", {"link 'lift_arm'", "<mass>", "'value'", "\"nan\""}},
      {"<mass value=\"450\"/>", "<mass value=\"1e308\"/>", {"link 'lift_arm'", "<mass>", "out of range"}},
      {"<mass value=\"1900\"/>", "<mass value=\"-1e308\"/>", {"link 'chassis'", "<mass>", "out of range"}},
      {"<mass value=\"450\"/>", "<mass value=\"450 \"/>", {"link 'lift_arm'", "<mass>", "'value'"}},
      {"<mass value=\"450\"/>", "<mass value=\"0x1c2\"/>", {"link 'lift_arm'", "<mass>", "decimal"}},
      {"ixx=\"716\"", "ixx=\"inf\"", {"link 'chassis'", "<inertia>", "'ixx'"}},
      {"iyy=\"115\"", "iyy=\"1e308\"", {"link 'lift_arm'", "<inertia>", "'iyy'", "out of range"}},
      {"<origin xyz=\"-0.58 0 0.15\" rpy=\"0 0 0\"/>", "<origin xyz=\"-0.58 0 1e308\" rpy=\"0 0 0\"/>",
       {"link 'chassis'", "<inertial><origin>", "'xyz'"}},
      {"<origin xyz=\"0.624 0 -0.588\" rpy=\"0 0.7557 0\"/>", "<origin xyz=\"0.624 0 -0.588\" rpy=\"0 NaN 0\"/>",
       {"link 'lift_arm'", "'rpy'", "NaN"}},
      {"<limit lower=\"0\" upper=\"1.6581\"", "<limit lower=\"0\" upper=\"1e308\"",
       {"joint 'lift_arm_joint'", "<limit>", "'upper'"}},
      {"<axis xyz=\"0 -1 0\"/>", "<axis xyz=\"0 -nan 0\"/>", {"joint 'lift_arm_joint'", "<axis>", "'xyz'"}},
      {"<origin xyz=\"1.248 0 -1.175\" rpy=\"0 0 0\"/>", "<origin xyz=\"1.248 0 -1e400\" rpy=\"0 0 0\"/>",
       {"joint 'bucket_joint'", "<origin>", "'xyz'"}},
      {"<box size=\"0.87 1.70 0.50\"/>", "<box size=\"0.87 1e308 0.50\"/>",
       {"link 'bucket'", "<collision><geometry><box>", "'size'"}},
      {"<cylinder radius=\"0.41\" length=\"0.26\"/>", "<cylinder radius=\"nan\" length=\"0.26\"/>",
       {"link 'wheel_fl'", "<cylinder>", "'radius'"}},
      {"<limit lower=\"0\" upper=\"1.6581\" effort=\"40000\"", "<limit lower=\"0\" upper=\"1.6581\" effort=\"-1\"",
       {"joint 'lift_arm_joint'", "'effort'"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.to);
    fs::remove_all(dir_);
    SetUp();
    replace("skidsteer.urdf", c.from, c.to);
    std::vector<std::string> says = c.says;
    says.push_back("skidsteer.urdf:");
    expect_error(says);
  }
}

// A huge mass on a wheel is blamed on the wheel's link, not on the tyres.
TEST_F(BrokenLoader, WheelMassIsNamedOnItsLink) {
  replace("skidsteer.urdf", "<link name=\"wheel_rr\">",
          "<link name=\"wheel_rr\">\n    <inertial><mass value=\"1e308\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" "
          "iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>");
  try {
    load_loader(path("skidsteer.params.xml"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("link 'wheel_rr' <inertial><mass>"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("tyre"), std::string::npos) << msg;
  }
}

// Meshes are checked as files before assimp reads them, and their vertices
// after: finite and within the loader's extent.
TEST_F(BrokenLoader, MeshesAreCheckedAsFilesAndByExtent) {
  fs::remove(path("meshes/bucket.obj"));
  fs::create_directories(path("meshes/bucket.obj"));
  expect_error({"skidsteer.urdf:", "link 'bucket'", "bucket.obj", "directory"});
  fs::remove_all(path("meshes/bucket.obj"));
  {  // a sparse file past the mesh cap: refused by its size, unread
    std::ofstream(path("meshes/bucket.obj")) << "v 0 0 0\n";
    fs::resize_file(path("meshes/bucket.obj"), kMaxMeshBytes + 1);
    expect_error({"skidsteer.urdf:", "link 'bucket'", "bucket.obj", "more than"});
  }
  std::ofstream(path("meshes/bucket.obj"), std::ios::trunc) << "v 0 0 0\nv 1 0 0\nv 0 1e6 0\nf 1 2 3\n";
  expect_error({"skidsteer.urdf:", "link 'bucket'", "bucket.obj", "beyond"});
  std::ofstream(path("meshes/bucket.obj"), std::ios::trunc) << "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n";
  expect_error({"skidsteer.urdf:", "link 'bucket'", "bucket.obj"});
}

TEST_F(BrokenLoader, MissingUrdfAndMissingParametersAreReported) {
  fs::remove(path("skidsteer.urdf"));
  expect_error({"skidsteer.params.xml:", "skidsteer.urdf", "no such file"});
  EXPECT_THROW(load_loader(path("nope.params.xml")), InputError);
}

}  // namespace
}  // namespace skidsim::io
