#include "io/loader_files.h"
#include "common/physical_constants.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <sys/stat.h>
#include <filesystem>
#include <map>
#include <sstream>
#include <vector>

#include "io/input_file.h"
#include "io/soil_table.h"
#include "io/urdf_checks.h"
#include "io/xml_reader.h"
#include "vehicle/cylinder_geometry.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;
using vehicle::LoaderDescription;


// Cylinder geometry that can move its joint. A pin closer than 1 cm to the
// joint's axis, or pins closer than 1 cm to each other, leave the length
// (nearly) fixed; a moment arm under 1 cm (the shipped tilt cylinder's
// least is 2.6 cm, at full dump) is a dead centre in all but name; a
// cylinder that moves under 1 cm over the joint's whole range would give a
// cycle time of ~0 s.
constexpr double kMinPinOffAxis_m = 0.01;
constexpr double kMinMomentArm_m = 0.01;
constexpr double kMinStrokeUsed_m = 0.01;

// Vectors in messages as "x y z", without Eigen's column padding.
const Eigen::IOFormat kPlain(Eigen::StreamPrecision, Eigen::DontAlignCols, " ", " ");

[[noreturn]] void fail_line(const std::string& path, int line, const std::string& what) {
  std::ostringstream msg;
  msg << path << ":" << line << ": " << what;
  throw InputError(msg.str());
}

// What urdfdom hands back is checked again where it enters (the text was
// checked before it read it, io/urdf_checks.h): a pose must be finite and
// within the loader's extent.
vehicle::Pose to_pose(const urdf::Pose& p, const std::string& urdf_path, int line, const std::string& what) {
  vehicle::Pose out;
  out.position_m = {p.position.x, p.position.y, p.position.z};
  const Eigen::Vector4d q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  if (!(out.position_m.cwiseAbs().maxCoeff() <= kMaxUrdfExtent_m) || !q.allFinite() || !(q.norm() > 0.5)) {
    std::ostringstream m;
    m << what << " <origin>: xyz (" << out.position_m.transpose() << ") must be finite and within +-"
      << kMaxUrdfExtent_m << " m, rpy finite";
    fail_line(urdf_path, line, m.str());
  }
  out.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  return out;
}

// Every file assimp opens (the mesh, and whatever it names: an OBJ's
// material library, a glTF's buffers) goes through the checked opener: a
// FIFO or a device named inside a mesh would otherwise hang the read.
class CheckedIOSystem : public Assimp::DefaultIOSystem {
 public:
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::string(mode).find_first_of("wa+") != std::string::npos) return nullptr;  // read only
    try {
      check_input_file(file, kMaxMeshBytes, "mesh file");
    } catch (const InputError& e) {
      refused = e.what();
      return nullptr;
    }
    return DefaultIOSystem::Open(file, mode);
  }
  // DefaultIOSystem's Exists() opens the file: on a FIFO that waits forever.
  bool Exists(const char* file) const override {
    struct stat st {};
    return ::stat(file, &st) == 0 && S_ISREG(st.st_mode);
  }
  std::string refused;  // the last file refused, for the message
};

// A polygon of this many corners is no part of a machine; triangulating a
// million-corner face (assimp's ear clipping) would take hours.
constexpr unsigned kMaxFaceCorners = 1024;

void load_mesh(vehicle::VisualMesh& mesh, const Eigen::Vector3d& scale, const std::string& urdf_path, int line,
               const std::string& link) {
  // A regular file of a sane size before assimp is given it (a folder, a
  // device or a 10 GB file would fail late or never end).
  try {
    check_input_file(mesh.path, kMaxMeshBytes, "mesh");
  } catch (const InputError& e) {
    fail_line(urdf_path, line, "link '" + link + "' visual mesh '" + mesh.path + "': " + e.what());
  }
  Assimp::Importer importer;
  auto* io = new CheckedIOSystem;  // the importer owns it
  importer.SetIOHandler(io);
  const std::string where = "link '" + link + "' visual mesh '" + mesh.path + "'";
  // Read first, check the polygons' sizes, then post-process.
  const aiScene* scene = importer.ReadFile(mesh.path, 0);
  if (!scene || !scene->mRootNode || scene->mNumMeshes == 0)
    fail_line(urdf_path, line, where + ": cannot read it (" + (io->refused.empty() ? importer.GetErrorString() : io->refused) + ")");
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    for (unsigned f = 0; f < scene->mMeshes[m]->mNumFaces; ++f)
      if (scene->mMeshes[m]->mFaces[f].mNumIndices > kMaxFaceCorners)
        fail_line(urdf_path, line, where + ": face " + std::to_string(f) + " of mesh " + std::to_string(m) + " has " +
                                       std::to_string(scene->mMeshes[m]->mFaces[f].mNumIndices) + " corners (at most " +
                                       std::to_string(kMaxFaceCorners) + ")");
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (!scene || !scene->mRootNode || scene->mNumMeshes == 0)
    fail_line(urdf_path, line, where + ": cannot read it (" + importer.GetErrorString() + ")");
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const unsigned base = static_cast<unsigned>(mesh.vertices_m.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      const Eigen::Vector3d scaled = Eigen::Vector3d(p.x, p.y, p.z).cwiseProduct(scale);
      if (!scaled.allFinite())
        fail_line(urdf_path, line, "link '" + link + "' visual mesh '" + mesh.path + "': non-finite vertex " +
                                       std::to_string(v) + " of mesh " + std::to_string(m));
      // A loader's part lies within metres of its link's frame: a mesh
      // that reaches past the URDF's extent (a file in millimetres read
      // as metres, a corrupt vertex) is refused, not drawn.
      if (!(scaled.cwiseAbs().maxCoeff() <= kMaxUrdfExtent_m)) {
        std::ostringstream msg;
        msg << "link '" << link << "' visual mesh '" << mesh.path << "': vertex " << v << " of mesh " << m << " at ("
            << scaled.transpose().format(kPlain) << ") m (after <mesh scale>) lies beyond +-" << kMaxUrdfExtent_m
            << " m of the link's frame (a mesh in millimetres needs scale=\"0.001 0.001 0.001\")";
        fail_line(urdf_path, line, msg.str());
      }
      mesh.vertices_m.emplace_back(scaled.cast<float>());
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  if (mesh.triangles.empty())
    fail_line(urdf_path, line, "link '" + link + "' visual mesh '" + mesh.path + "': no triangles");
}

// One link: inertia, collision boxes, visual meshes. Wheels may be massless.
vehicle::RigidLink read_link(const urdf::Link& link, const std::string& urdf_path, int line, bool massless_ok) {
  vehicle::RigidLink out;
  out.name = link.name;
  out.urdf_line = line;
  const std::string where = "link '" + link.name + "'";
  if (link.inertial) {
    const urdf::Inertial& in = *link.inertial;
    if (!(in.mass > 0.0 && in.mass <= kMaxUrdfMass_kg)) {
      std::ostringstream m;
      m << where << " <inertial><mass value=" << in.mass << ">: the mass must be positive and at most "
        << kMaxUrdfMass_kg << " kg";
      fail_line(urdf_path, line, m.str());
    }
    const double off = std::abs(in.ixy) + std::abs(in.ixz) + std::abs(in.iyz);
    const Eigen::Vector3d I(in.ixx, in.iyy, in.izz);
    if (!std::isfinite(off) || !(I.cwiseAbs().maxCoeff() <= kMaxUrdfInertia_kg_m2))
      fail_line(urdf_path, line, where + " <inertia>: the moments must be finite and at most " +
                                     std::to_string(kMaxUrdfInertia_kg_m2) + " kg m^2");
    if (off > 1e-9 * I.cwiseAbs().maxCoeff())
      fail_line(urdf_path, line, where + " <inertia>: give principal moments (ixy = ixz = iyz = 0) and turn the "
                                         "<inertial><origin rpy> to the principal axes");
    if (!(I.minCoeff() > 0.0) || I.x() > I.y() + I.z() || I.y() > I.x() + I.z() || I.z() > I.x() + I.y()) {
      std::ostringstream m;
      m << where << " <inertia> (" << I.transpose().format(kPlain) << "): the moments must be positive and satisfy the triangle "
        << "inequality";
      fail_line(urdf_path, line, m.str());
    }
    out.mass_kg = in.mass;
    out.com = to_pose(in.origin, urdf_path, line, where + " <inertial>");
    out.principal_inertia_kg_m2 = I;
  } else if (!massless_ok) {
    fail_line(urdf_path, line, where + ": missing <inertial> (only wheels may be massless)");
  }
  for (const auto& c : link.collision_array) {
    if (!c->geometry || c->geometry->type != urdf::Geometry::BOX) continue;
    const auto& box = static_cast<const urdf::Box&>(*c->geometry);
    vehicle::CollisionBox b;
    b.pose = to_pose(c->origin, urdf_path, line, where + " <collision>");
    b.half_extents_m = 0.5 * Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
    if (!(b.half_extents_m.minCoeff() > 0.0) || !(b.half_extents_m.maxCoeff() <= kMaxUrdfExtent_m))
      fail_line(urdf_path, line, where + " <collision><box>: sizes must be positive and finite");
    out.collision.push_back(b);
  }
  const fs::path dir = fs::path(urdf_path).parent_path();
  for (const auto& v : link.visual_array) {
    if (!v->geometry || v->geometry->type != urdf::Geometry::MESH) continue;
    const auto& mesh = static_cast<const urdf::Mesh&>(*v->geometry);
    if (mesh.filename.rfind("package://", 0) == 0)
      fail_line(urdf_path, line, where + " visual mesh '" + mesh.filename + "': package:// paths are not supported; "
                                          "give a path relative to the URDF");
    if (!(mesh.scale.x > 0.0 && mesh.scale.y > 0.0 && mesh.scale.z > 0.0) || !std::isfinite(mesh.scale.x) ||
        !std::isfinite(mesh.scale.y) || !std::isfinite(mesh.scale.z))
      fail_line(urdf_path, line, where + " visual mesh '" + mesh.filename + "': scale must be positive");
    vehicle::VisualMesh vm;
    vm.path = fs::absolute(dir / mesh.filename).lexically_normal().string();
    vm.pose = to_pose(v->origin, urdf_path, line, where + " <visual>");
    load_mesh(vm, {mesh.scale.x, mesh.scale.y, mesh.scale.z}, urdf_path, line, link.name);
    out.visuals.push_back(std::move(vm));
  }
  return out;
}

void read_urdf(LoaderDescription& d) {
  const std::string& path = d.urdf_path;
  // Read once, its numbers checked before urdfdom parses it (io/urdf_checks.h).
  const CheckedUrdf checked = read_checked_urdf(path);
  const UrdfLines& lines = checked.lines;
  const urdf::ModelInterfaceSharedPtr& model = checked.model;
  const urdf::LinkConstSharedPtr root = model->getRoot();
  auto link_line = [&](const std::string& n) { return lines.link.count(n) ? lines.link.at(n) : 0; };
  auto joint_line = [&](const std::string& n) { return lines.joint.count(n) ? lines.joint.at(n) : 0; };
  d.links.push_back(read_link(*root, path, link_line(root->name), false));

  // Walk the tree: continuous joints on the chassis are wheels; revolute
  // joints form the implement chain (lift arm, bucket).
  std::vector<urdf::LinkConstSharedPtr> stack{root};
  std::map<std::string, int> index{{root->name, 0}};
  while (!stack.empty()) {
    const urdf::LinkConstSharedPtr parent = stack.back();
    stack.pop_back();
    for (const auto& child : parent->child_links) {
      const urdf::JointConstSharedPtr j = child->parent_joint;
      const int jl = joint_line(j->name);
      if (j->type == urdf::Joint::CONTINUOUS) {
        if (parent != root) fail_line(path, jl, "joint '" + j->name + "': a wheel (continuous joint) must hang on the chassis");
        if (!child->child_links.empty()) fail_line(path, jl, "joint '" + j->name + "': a wheel link must have no children");
        const urdf::Cylinder* cyl = nullptr;
        for (const auto& c : child->collision_array)
          if (c->geometry && c->geometry->type == urdf::Geometry::CYLINDER)
            cyl = static_cast<const urdf::Cylinder*>(c->geometry.get());
        if (!cyl) fail_line(path, link_line(child->name), "link '" + child->name + "': a wheel needs a <collision><cylinder>");
        if (!(cyl->radius >= kMinUrdfSize_m && cyl->radius <= kMaxUrdfExtent_m && cyl->length >= kMinUrdfSize_m &&
              cyl->length <= kMaxUrdfExtent_m))
          fail_line(path, link_line(child->name), "link '" + child->name + "' <cylinder>: radius and length must be positive and finite");
        // The tyre model takes the axle along the chassis's y.
        const vehicle::Pose hub = to_pose(j->parent_to_joint_origin_transform, path, jl, "joint '" + j->name + "'");
        if (std::abs(std::abs(j->axis.y) - 1.0) > 1e-6 || hub.rotation.angularDistance(Eigen::Quaterniond::Identity()) > 1e-6)
          fail_line(path, jl, "joint '" + j->name + "': a wheel's axle must be the chassis's y (axis 0 1 0, rpy 0 0 0)");
        vehicle::Wheel w;
        w.name = child->name;
        w.hub_m = hub.position_m;
        d.wheels.push_back(w);
        if (d.tyre.radius_m == 0.0) {
          d.tyre.radius_m = cyl->radius;
          d.tyre.width_m = cyl->length;
        } else if (std::abs(d.tyre.radius_m - cyl->radius) > 1e-6 || std::abs(d.tyre.width_m - cyl->length) > 1e-6) {
          fail_line(path, link_line(child->name), "link '" + child->name + "': every wheel must have the same cylinder");
        }
        // Thesis: massless discs; any mass given is ignored only if zero.
        if (child->inertial && child->inertial->mass != 0.0)
          fail_line(path, link_line(child->name), "link '" + child->name + "': wheels are massless discs (lump their "
                                                  "mass into the chassis) - remove the <inertial>");
        continue;
      }
      if (j->type != urdf::Joint::REVOLUTE)
        fail_line(path, jl, "joint '" + j->name + "': only revolute (implement) and continuous (wheel) joints are supported");
      if (!j->limits || !(j->limits->upper > j->limits->lower) || !(std::abs(j->limits->lower) <= kMaxUrdfAngle_rad) ||
          !(std::abs(j->limits->upper) <= kMaxUrdfAngle_rad))
        fail_line(path, jl, "joint '" + j->name + "' <limit>: lower and upper must be finite angles, upper above lower");
      vehicle::ImplementJoint ij;
      ij.name = j->name;
      ij.origin = to_pose(j->parent_to_joint_origin_transform, path, jl, "joint '" + j->name + "'");
      ij.axis = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z);
      if (!ij.axis.allFinite() || !(ij.axis.norm() > 0.5))
        fail_line(path, jl, "joint '" + j->name + "' <axis>: must be a unit vector");
      ij.axis.normalize();
      ij.lower_rad = j->limits->lower;
      ij.upper_rad = j->limits->upper;
      ij.urdf_line = jl;
      d.joints.push_back(ij);
      d.joint_parent_link.push_back(index.at(parent->name));
      index[child->name] = static_cast<int>(d.links.size());
      d.links.push_back(read_link(*child, path, link_line(child->name), false));
      stack.push_back(child);
    }
  }
  // The wheels' visual meshes, for the renderer.
  for (auto& w : d.wheels)
    w.visuals = read_link(*model->getLink(w.name), path, link_line(w.name), true).visuals;
  if (d.joints.size() != 2)
    fail_line(path, link_line(root->name), "expected two revolute joints (lift arm and bucket), found " +
                                               std::to_string(d.joints.size()));
}

int joint_index(const LoaderDescription& d, const std::string& name) {
  for (size_t i = 0; i < d.joints.size(); ++i)
    if (d.joints[i].name == name) return static_cast<int>(i);
  return -1;
}

void read_cylinder(LoaderDescription& d, const std::string& path, const tinyxml2::XMLElement* e) {
  AttributeReader a(path, e);
  vehicle::Cylinder c;
  c.name = a.text("name", true);
  const std::string joint = a.text("joint", true);
  c.joint = joint_index(d, joint);
  if (c.joint < 0) a.fail("attribute 'joint' = \"" + joint + "\": no revolute joint of that name in the URDF");
  c.bore_m = a.number_in("bore_mm", 1.0, 1000.0) * 1e-3;
  c.rod_m = a.number_in("rod_mm", 1.0, 1000.0) * 1e-3;
  if (!(c.rod_m < c.bore_m)) a.fail("the rod must be thinner than the bore");
  c.min_length_m = a.number_in("min_length_m", 0.01, 20.0);
  c.max_length_m = a.number_in("max_length_m", 0.01, 20.0);
  if (!(c.max_length_m > c.min_length_m)) a.fail("max_length_m must exceed min_length_m");
  c.relief_pressure_Pa = a.number_in("relief_MPa", 0.1, 100.0) * 1e6;
  c.parent_pin_m = a.vector3_in("parent_pin", -50.0, 50.0);
  c.child_pin_m = a.vector3_in("child_pin", -50.0, 50.0);
  c.line = e->GetLineNum();
  a.reject_unknown();
  a.reject_content();
  const vehicle::ImplementJoint& j = d.joints[c.joint];
  // A pin on the joint's axis keeps the cylinder's length whatever the
  // angle: it cannot turn the joint (and its speed would be infinite). In
  // the child frame the axis runs through the origin along j.axis; in the
  // parent frame through the joint's origin.
  {
    const double child_off_axis_m = j.axis.cross(c.child_pin_m).norm();
    const double parent_off_axis_m =
        (j.origin.rotation * j.axis).cross(c.parent_pin_m - j.origin.position_m).norm();
    for (const auto& [pin, off_m] : {std::pair{"child_pin", child_off_axis_m}, std::pair{"parent_pin", parent_off_axis_m}})
      if (!(off_m >= kMinPinOffAxis_m)) {
        std::ostringstream m;
        m << "cylinder '" << c.name << "': attribute '" << pin << "' lies " << off_m << " m from the axis of joint '" << j.name
          << "' (at least " << kMinPinOffAxis_m << " m): the cylinder's length would not change as the "
          << "joint turns, so it could not move it";
        a.fail(m.str());
      }
  }
  // The stroke must carry the joint through its whole range, one way (the
  // length must grow or shrink monotonically: no dead centre inside), with
  // a moment arm everywhere (tau = F dl/dq, dq/dt = v / (dl/dq)).
  constexpr int kSamples = 400;
  double previous = 0.0;
  int sign = 0;
  for (int k = 0; k <= kSamples; ++k) {
    const double q = j.lower_rad + (j.upper_rad - j.lower_rad) * k / kSamples;
    const vehicle::CylinderKinematics ck = vehicle::cylinder_kinematics(c, j, q);
    if (!(ck.length_m >= kMinPinOffAxis_m)) {
      std::ostringstream m;
      m << "cylinder '" << c.name << "': parent_pin and child_pin coincide at " << q * 180.0 / kPi << " deg of joint '"
        << j.name << "' (" << ck.length_m << " m apart)";
      a.fail(m.str());
    }
    if (ck.length_m < c.min_length_m - 1e-6 || ck.length_m > c.max_length_m + 1e-6) {
      std::ostringstream m;
      m << "cylinder '" << c.name << "' cannot reach joint '" << j.name << "' at " << q * 180.0 / kPi
        << " deg: it would need " << ck.length_m << " m pin to pin, its stroke spans [" << c.min_length_m << ", "
        << c.max_length_m << "] m";
      a.fail(m.str());
    }
    if (!(std::abs(ck.moment_arm_m) >= kMinMomentArm_m)) {
      std::ostringstream m;
      m << "cylinder '" << c.name << "': its moment arm about joint '" << j.name << "' is " << std::abs(ck.moment_arm_m)
        << " m at " << q * 180.0 / kPi << " deg (at least " << kMinMomentArm_m
        << " m): it is in line with the joint's pin there and cannot turn it";
      a.fail(m.str());
    }
    if (k > 0) {
      const int s = ck.length_m > previous ? 1 : -1;
      if (sign != 0 && s != sign) a.fail("cylinder '" + c.name + "' passes a dead centre inside the joint's range");
      sign = s;
    }
    previous = ck.length_m;
  }
  const double used_m = std::abs(vehicle::cylinder_kinematics(c, j, j.upper_rad).length_m -
                                 vehicle::cylinder_kinematics(c, j, j.lower_rad).length_m);
  if (!(used_m >= kMinStrokeUsed_m)) {
    std::ostringstream m;
    m << "cylinder '" << c.name << "' moves only " << used_m << " m over the range of joint '" << j.name << "' (at least "
      << kMinStrokeUsed_m << " m)";
    a.fail(m.str());
  }
  d.cylinders.push_back(c);
}

// <bucket> children: <interior> (the container the load rides in) and
// <filling> (cutting edge and load spreading), both optional together.
void read_bucket_interior(LoaderDescription& d, const std::string& path, const tinyxml2::XMLElement* bucket) {
  vehicle::BucketInterior& in = d.bucket_interior;
  bool have_interior = false, have_filling = false;
  for (const tinyxml2::XMLElement* c = bucket->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = c->Name();
    AttributeReader a(path, c);
    if (name == "interior") {
      if (have_interior) a.fail("appears twice");
      have_interior = true;
      in.origin_m = a.vector3_in("origin", -50.0, 50.0);
      // At least three cells of the coarsest site (10 cm) each way.
      in.length_m = a.number_in("length_m", 0.3, 10.0);
      in.width_m = a.number_in("width_m", 0.3, 10.0);
      in.back_height_m = a.number_in("back_height_m", 0.0, 5.0);
      in.side_height_front_m = a.number_in("side_height_front_m", 0.0, 5.0);
      in.heel_radius_m = a.number_in("heel_radius_m", 0.0, 5.0);
      in.plate_thickness_m = a.number_in("plate_thickness_m", 0.005, 0.5);
      in.cutting_edge_length_m = a.number_in("cutting_edge_length_m", 0.01, 10.0);
      in.bottom_clearance_rad = deg_to_rad(a.number_in("bottom_clearance_deg", 0.0, 45.0));
      in.cutting_edge_thickness_m =
          a.number_in_or("cutting_edge_thickness_m", 0.001, 0.2, in.cutting_edge_thickness_m);
      a.reject_unknown();
      a.reject_content();
      if (in.heel_radius_m > in.back_height_m) a.fail("heel_radius_m must not exceed back_height_m");
    } else if (name == "filling") {
      if (have_filling) a.fail("appears twice");
      have_filling = true;
      in.heaped_volume_m3 = a.number_in("heaped_volume_m3", 0.001, 50.0);
      in.edge_resistance = a.number_in("edge_resistance", 0.0, 1.0);
      in.filling_angle_drop_deg = a.number_in("angle_drop_deg", 0.0, 30.0);
      in.spreading_eps = a.number_in("spreading_eps", 0.0, 0.5);
      in.spreading_block_cells = a.number_in("block_height_cells", 0.25, 8.0);
      a.reject_unknown();
      a.reject_content();
    } else {
      a.fail("unknown element (expected <interior> or <filling>)");
    }
  }
  if (have_filling && !have_interior) fail_at(path, bucket, "<filling> needs an <interior>");
  in.present = have_interior;
}

// <engine idle_rpm rated_rpm ...> and its <power rpm kW> table.
void read_engine(vehicle::EngineParameters& en, const std::string& parameters_path, const tinyxml2::XMLElement* e) {
  AttributeReader a(parameters_path, e);
  en.idle_rpm = a.number_in("idle_rpm", 100.0, 10000.0);
  en.rated_rpm = a.number_in("rated_rpm", 100.0, 10000.0);
  en.inertia_kg_m2 = a.number_in("inertia_kg_m2", 1e-3, 1e3);
  en.governor_droop = a.number_in("governor_droop", 0.005, 0.5);
  en.friction_torque_N_m = a.number_in("friction_torque_N_m", 0.0, 1e5);
  a.reject_unknown();
  if (!(en.rated_rpm > en.idle_rpm)) a.fail("rated_rpm must exceed idle_rpm");
  for (const tinyxml2::XMLElement* p = e->FirstChildElement(); p; p = p->NextSiblingElement()) {
    AttributeReader pa(parameters_path, p);
    if (std::string(p->Name()) != "power") pa.fail("unknown element (expected <power>)");
    const double rpm = pa.number_in("rpm", 1.0, 10000.0);
    const double kw = pa.number_in("kW", 0.0, 10000.0);
    pa.reject_unknown();
    pa.reject_content();
    if (!en.speed_rpm.empty() && !(rpm > en.speed_rpm.back())) pa.fail("rpm must increase down the table");
    en.speed_rpm.push_back(rpm);
    en.full_load_power_W.push_back(kw * 1e3);
  }
  if (en.speed_rpm.size() < 2) a.fail("needs at least two <power rpm kW> points");
  if (en.speed_rpm.front() > en.idle_rpm || en.speed_rpm.back() < en.rated_rpm)
    a.fail("the power table must span idle_rpm to rated_rpm");
}

// <drive>: the hydrostatic drive.
void read_drive(vehicle::DriveParameters& dr, const std::string& parameters_path, const tinyxml2::XMLElement* e) {
  AttributeReader a(parameters_path, e);
  dr.top_speed_m_per_s = a.number_in("top_speed_km_h", 0.1, 100.0) / 3.6;
  dr.relief_pressure_Pa = a.number_in("relief_MPa", 0.1, 100.0) * 1e6;
  dr.motor_displacement_m3_per_rad = a.number_in("motor_displacement_cc_per_rev", 1.0, 1e5) * 1e-6 / (2.0 * kPi);
  dr.final_drive_ratio = a.number_in("final_drive_ratio", 0.1, 100.0);
  dr.efficiency = a.number_in("efficiency", 0.1, 1.0);
  dr.side_inertia_kg_m2 = a.number_in("side_inertia_kg_m2", 0.01, 1e4);
  dr.servo_gain_N_m_s = a.number_in("servo_gain_N_m_s", 1.0, 1e7);
  dr.brake_torque_N_m = a.number_in("brake_torque_N_m", 0.0, 1e6);
  dr.pump_stroke_time_s = a.number_in("pump_stroke_time_s", 0.0, 10.0);
  a.reject_unknown();
  a.reject_content();
}

// <tyre>: the Magic Formula's coefficients, the carcass and rolling resistance.
void read_tyre(vehicle::TyreParameters& t, const std::string& parameters_path, const tinyxml2::XMLElement* e) {
  AttributeReader a(parameters_path, e);
  t.radial_stiffness_N_per_m = a.number_in("radial_stiffness_kN_per_m", 1.0, 1e5) * 1e3;
  t.radial_damping_N_s_per_m = a.number_in("radial_damping_kN_s_per_m", 0.0, 1e4) * 1e3;
  t.relaxation_x_m = a.number_in("relaxation_x_m", 0.005, 5.0);
  t.relaxation_y_m = a.number_in("relaxation_y_m", 0.005, 5.0);
  t.low_speed_damping_N_s_per_m = a.number_in("low_speed_damping_kN_s_per_m", 0.0, 1e4) * 1e3;
  t.low_speed_m_per_s = a.number_in("low_speed_m_per_s", 0.01, 10.0);
  t.Bx = a.number_in("Bx", 0.1, 100.0);
  t.Cx = a.number_in("Cx", 0.1, 3.0);
  t.Ex = a.number_in("Ex", -10.0, 1.0);
  t.mu_x = a.number_in("mu_x", 0.01, 3.0);
  t.By = a.number_in("By", 0.1, 100.0);
  t.Cy = a.number_in("Cy", 0.1, 3.0);
  t.Ey = a.number_in("Ey", -10.0, 1.0);
  t.mu_y = a.number_in("mu_y", 0.01, 3.0);
  t.rBx1 = a.number_in("rBx1", 0.0, 100.0);
  t.rBx2 = a.number_in("rBx2", 0.0, 100.0);
  t.Cxa = a.number_in("Cxa", 0.1, 3.0);
  t.rBy1 = a.number_in("rBy1", 0.0, 100.0);
  t.rBy2 = a.number_in("rBy2", 0.0, 100.0);
  t.Cyk = a.number_in("Cyk", 0.1, 3.0);
  t.rolling_resistance = a.number_in("rolling_resistance", 0.0, 0.5);
  // Optional: without them the tyre is a rigid wheel on soft soil.
  t.inflation_pressure_Pa = a.number_in_or("inflation_pressure_kPa", 20.0, 1000.0, 0.0) * 1e3;
  t.carcass_pressure_Pa = a.number_in_or("carcass_pressure_kPa", 0.0, 500.0, 0.0) * 1e3;
  a.reject_unknown();
  a.reject_content();
}

}  // namespace

LoaderDescription load_loader(const std::string& parameters_path) {
  LoaderDescription d;
  d.parameters_path = parameters_path;
  tinyxml2::XMLDocument doc;
  load_xml(doc, parameters_path);
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "loader_parameters")
    fail_at(parameters_path, root, "expected the root element <loader_parameters>");
  {
    AttributeReader a(parameters_path, root);
    const std::string urdf = a.text("urdf", true);
    a.reject_unknown();
    d.urdf_path = (fs::path(parameters_path).parent_path() / urdf).lexically_normal().string();
    try {
      check_input_file(d.urdf_path, kMaxXmlBytes, "URDF");
    } catch (const InputError& e) {
      a.fail("attribute 'urdf' = \"" + urdf + "\": " + e.what());
    }
  }
  read_urdf(d);

  bool have_engine = false, have_pump = false, have_drive = false, have_tyre = false, have_bucket = false;
  std::vector<std::string> wheel_links;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string name = e->Name();
    AttributeReader a(parameters_path, e);
    auto once = [&](bool& have) {
      if (have) a.fail("appears twice");
      have = true;
    };
    if (name == "engine") {
      once(have_engine);
      read_engine(d.engine, parameters_path, e);
    } else if (name == "implement_pump") {
      once(have_pump);
      d.implement_pump.flow_at_rated_m3_per_s = a.number_in("flow_l_per_min", 1.0, 2000.0) / 60000.0;
      d.implement_pump.efficiency = a.number_in("efficiency", 0.1, 1.0);
      d.implement_pump.spool_time_s = a.number_in("spool_time_s", 0.0, 10.0);
      a.reject_unknown();
      a.reject_content();
    } else if (name == "cylinder") {
      read_cylinder(d, parameters_path, e);
    } else if (name == "drive") {
      once(have_drive);
      read_drive(d.drive, parameters_path, e);
    } else if (name == "tyre") {
      once(have_tyre);
      read_tyre(d.tyre, parameters_path, e);
    } else if (name == "wheel") {
      const std::string link = a.text("link", true);
      const std::string side = a.text("side", true);
      a.reject_unknown();
      a.reject_content();
      vehicle::Wheel* w = nullptr;
      for (auto& cand : d.wheels)
        if (cand.name == link) w = &cand;
      if (!w) a.fail("attribute 'link' = \"" + link + "\": not a wheel (continuous joint on the chassis) in the URDF");
      for (const std::string& listed : wheel_links)
        if (listed == link) a.fail("wheel '" + link + "' is listed twice");
      if (side != "left" && side != "right") a.fail("attribute 'side' = \"" + side + "\": expected left or right");
      w->side = side == "left" ? 0 : 1;
      wheel_links.push_back(link);
    } else if (name == "bucket") {
      once(have_bucket);
      const std::string link = a.text("link", true);
      if (d.link_index(link) != static_cast<int>(d.links.size()) - 1)
        a.fail("attribute 'link' = \"" + link + "\": the bucket must be the last link of the implement chain");
      d.bucket_load_centre_m = a.vector3_in("load_centre", -50.0, 50.0);
      d.bucket_volume_m3 = a.number_in("volume_m3", 0.01, 20.0);
      a.reject_unknown();
      read_bucket_interior(d, parameters_path, e);
    } else {
      a.fail("unknown element");
    }
  }
  auto need = [&](bool have, const char* what) {
    if (!have) fail_at(parameters_path, root, std::string("missing <") + what + ">");
  };
  need(have_engine, "engine");
  need(have_pump, "implement_pump");
  need(have_drive, "drive");
  need(have_tyre, "tyre");
  need(have_bucket, "bucket");
  if (d.wheels.empty()) fail_at(parameters_path, root, "the URDF has no wheels (continuous joints on the chassis)");
  {
    // The tyres must carry the machine: static deflection under a quarter of
    // the radius (the drive's rolling radius would turn negative, and the
    // chassis would sit on its belly, long before).
    const double deflection = kGravity_m_s2 * d.total_mass_kg() / (d.wheels.size() * d.tyre.radial_stiffness_N_per_m);
    if (deflection > 0.25 * d.tyre.radius_m) {
      std::ostringstream m;
      m << "<tyre> radial_stiffness_kN_per_m: the machine would squash its tyres by " << deflection
        << " m standing (more than a quarter of the radius)";
      fail_at(parameters_path, root, m.str());
    }
  }
  for (size_t j = 0; j < d.joints.size(); ++j) {
    int n = 0;
    for (const auto& c : d.cylinders) n += c.joint == static_cast<int>(j);
    if (n != 1) fail_at(parameters_path, root, "joint '" + d.joints[j].name + "' needs exactly one <cylinder>");
  }
  // What the cylinders imply, checked here so that no figure built on them
  // (vehicle/loader_figures.h: lift, lower, dump and curl times) is 0 or
  // not finite: the seconds to run each joint's range on the full pump flow.
  for (const auto& c : d.cylinders) {
    const vehicle::ImplementJoint& j = d.joints[c.joint];
    const double used_m = std::abs(vehicle::cylinder_kinematics(c, j, j.upper_rad).length_m -
                                   vehicle::cylinder_kinematics(c, j, j.lower_rad).length_m);
    for (const double area_m2 : {c.piston_area_m2(), c.annulus_area_m2()}) {
      const double time_s = used_m * area_m2 / d.implement_pump.flow_at_rated_m3_per_s;
      if (!(std::isfinite(time_s) && time_s > 0.0)) {
        std::ostringstream m;
        m << "<cylinder> cylinder '" << c.name << "' would run the range of joint '" << j.name << "' in " << time_s
          << " s on the <implement_pump>'s flow (must be finite and positive)";
        fail_line(parameters_path, c.line, m.str());
      }
    }
  }
  if (d.wheels.size() > 8) fail_at(parameters_path, root, "at most 8 wheels are supported");
  if (wheel_links.size() != d.wheels.size())
    fail_at(parameters_path, root, "every URDF wheel needs a <wheel link side> entry");
  int left = 0;
  for (const auto& w : d.wheels) left += w.side == 0;
  if (left == 0 || left == static_cast<int>(d.wheels.size()))
    fail_at(parameters_path, root, "a skid steer needs wheels on both sides");
  return d;
}

std::string default_loader_path() { return default_assets_dir() + "/loader/skidsteer.params.xml"; }

}  // namespace skidsim::io
