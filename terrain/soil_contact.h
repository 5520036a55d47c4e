// Terrain-body interaction (thesis ch. 5, docs/soil_contact.md): each step,
// for each body near the soil, build its contact map, let the soil carry and
// resist the body, and change the terrain under it:
//   - vertical load: Bekker pressure-sinkage (3.19) with an elastic/plastic
//     split; the plastic part stays in the terrain (ruts, imprints) and later
//     loads follow Wong's stiffer reload line. A compressible soil (5.4)
//     keeps it as compacted material; an incompressible one (5.3) pushes
//     that volume out from under the load to the contour of the pressed
//     zone, where it rises;
//   - tangential: the Mohr-Coulomb bound on the shear the contact carries
//     (5.4.2);
//   - horizontal push: the fracture wedge limit (5.6) of every vertical
//     interface, a bounded reaction applied at a third of its height, and the
//     material an advancing interface displaces (5.7, 5.8), moved into the
//     wedge in front of it;
//   - the hard base under the soil as a very stiff contact.
// Forces come back as a wrench plus the linearisation and bounds a multibody
// engine needs to apply them stably at 2 ms (see BodyReaction).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "terrain/body_geometry.h"
#include "terrain/contact_map.h"
#include "terrain/granular_grid.h"
#include "terrain/earthmoving.h"
#include "terrain/soil_mechanics.h"

namespace skidsim::terrain {

// The fracture wedge in front of the interfaces that face one direction.
struct WedgeReaction {
  // Largest horizontal force (N) the soil resists with before it fails and
  // the body advances, pushing soil (5.5.2). Zero: no interface that way.
  double bound_N = 0.0;
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  // at a third of the interface height
  double depth_m = 0.0;   // H, width-weighted over the interfaces
  double width_m = 0.0;   // B, the interfaces' total width
  double weight_N = 0.0;  // W, the soil in the wedge
  double rho_rad = 0.0;   // angle of the fracture plane from the horizontal (beta)
  double rake_rad = 0.0;  // the tool face's angle from the horizontal (90 deg: vertical)
  double surcharge_Pa = 0.0;  // soil heaped on the wedge beyond flat ground (earthmoving q)
  // The earthmoving equation's vertical force on the face at the bound
  // (positive down: the face pulled into the soil when alpha + delta < 90
  // deg, pushed up past it); the soil's force is inclined at delta to the
  // face's normal, so its vertical part follows the horizontal reaction.
  // 0 for the thesis's wedge (a smooth face).
  double vertical_down_N = 0.0;
};

// What the soil does to one body in one step.
//
// How an engine applies it at 2 ms: `force_N` / `torque_Nm` are the soil's
// pressure at the current state (explicit). Its change with the body's
// vertical motion is `normal_stiffness_N_per_m` (per metre of further
// sinkage) and `normal_damping_N_s_per_m`; applying these implicitly (for
// example, with F taken at the current velocity v,
// v' = (m v + dt (F + C v + F_other)) / (m + dt (dt K + C)) along z) keeps
// the stiff soil and hard-base contacts stable for any body mass.
// Shear and wedge forces are bounded reactions, like static friction: the
// engine lets them take whatever value keeps the body still, up to the
// bound, in the direction that resists motion (a velocity constraint with
// an impulse limit of bound * dt).
struct BodyReaction {
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_Nm = Eigen::Vector3d::Zero();  // about BodyMotion::reference_point_m
  double normal_stiffness_N_per_m = 0.0;
  double normal_damping_N_s_per_m = 0.0;
  // Mohr-Coulomb (5.4.2): bound on the horizontal shear force over the
  // cells that carry load, acting at `shear_point_m` (its parts' centre).
  double shear_bound_N = 0.0;
  Eigen::Vector3d shear_point_m = Eigen::Vector3d::Zero();
  // Per direction of motion +x, -x, +y, -y: the wedge that resists it.
  std::array<WedgeReaction, kFaceCount> wedge{};
  // The hard base's part of force_N and torque_Nm: an engine that makes the
  // base a rigid contact of its own (as skidsim's does) takes it out.
  Eigen::Vector3d base_force_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d base_torque_Nm = Eigen::Vector3d::Zero();
  // Diagnostics.
  double contact_area_m2 = 0.0;
  double base_penetration_m = 0.0;  // deepest point of the body below the hard base
  double displaced_m3 = 0.0;        // material pushed this step
  double compacted_m3 = 0.0;        // material compacted this step
  int contact_cells = 0;
};

// One per terrain grid; any number of bodies. Per-cell state (the peak and
// plastic sinkage and the area they were pressed over, 12 bytes; the count
// of bodies covering the cell, 1; the soil region, 1) is allocated at the
// first contact or the first region set: a scene no body touches pays
// nothing. Everything else is sized by the contact areas.
class SoilContactModel {
 public:
  // `soil` is soil 0, which every cell has until set_soil_region says
  // otherwise.
  SoilContactModel(GranularGrid& grid, const SoilMechanics& soil);

  // Soil regions: the mechanics of the soil under each cell (a sand pile on
  // a clay yard). Returns the new soil's index (at most 256 soils). The
  // avalanche law stays the grid's own (one per automaton).
  int add_soil(const SoilMechanics& soil);
  void set_soil_region(int i, int j, int soil_index);

  // One body, one step (step 3 of the 2 ms step, docs/architecture.md): builds the
  // body's contact map, updates the terrain under it and returns the soil's
  // reaction. `body_id` in [0, 65535] names the body across steps (its
  // previous map tells how far its interfaces advanced). Allocates only
  // while a body's contact grows beyond its largest size so far.
  // `wedge_bounds` false skips the wedge limits (BodyReaction::wedge) for a
  // caller that does not apply them (the soil is still pushed into the
  // wedge in front of an advancing interface).
  BodyReaction interact(int body_id, const BodyGeometry& body, const BodyMotion& motion, bool wedge_bounds = true);
  // Places a body in the soil as if it had got there by itself: the soil
  // under its covered parts is taken to be at its underside, so nothing is
  // pressed or pushed by the placement (a blade started in its slot, a
  // machine loaded with a saved terrain). The soil its volume overlaps is
  // the caller's to remove.
  void embed(int body_id, const BodyGeometry& body, const BodyMotion& motion);
  // Sizes a body's lists for its largest footprint (`diagonal_m`, its
  // longest dimension) so that its steps never allocate for them; otherwise
  // they are sized at its first contact from its bounds then.
  void reserve_body(int body_id, double diagonal_m);
  // Forgets a body: it no longer covers its cells (they stay covered while
  // another body covers them).
  void release(int body_id);

  // A cutting edge (thesis 6.4): a slicing body does not push a fracture
  // wedge. The soil its interfaces sweep (5.7) as they advance along the
  // edge's horizontal `forward` direction (within 72 deg of it) leaves the
  // grid (exported, exact) and is listed per cell for the caller, who puts
  // it on the body (terrain/material_exchange.h); moving any other way the
  // body pushes soil like any other (a bucket backing up drags its heel).
  // The list is refilled by each interact().
  struct SlicedCell {
    std::uint32_t cell;
    std::int64_t quanta;
  };
  void set_slicing(int body_id, bool on, const Eigen::Vector2d& forward = Eigen::Vector2d::UnitX());

  // The face a body pushes soil with (a blade's front, the bucket's back
  // plate): its outward unit normal in the world frame, set again as the body
  // turns. The earthmoving equation takes the face's rake against each
  // direction it pushes from it (the angle from the horizontal, 10-90 deg; a
  // face turned away or overhanging counts as vertical). A body without one
  // pushes with the vertical interfaces of its contact map (5.2.3).
  void set_tool_face(int body_id, const Eigen::Vector3d& outward_normal_world);

  // A rolling wheel (terrain/wheel_contact.h) presses the soil it newly
  // covers into its rut, as the Wong-Reece theory has it (compaction, or
  // the incompressible soil's push to the contour), and sweeps none ahead.
  void set_press_only(int body_id, bool on);
  const std::vector<SlicedCell>& sliced(int body_id) const { return bodies_.at(body_id).sliced; }

  const ContactMap& contact_map(int body_id) const { return bodies_.at(body_id).map; }
  // The cells a body pressed at its last step (none for a body not in contact).
  bool in_contact_map(int body_id, std::uint32_t cell) const;
  const SoilMechanics& soil(int index = 0) const { return regions_.at(index).soil; }
  // The soil under a cell (its region's).
  const SoilMechanics& soil_at_cell(int cell) const { return regions_[region_index(cell)].soil; }
  // The earthmoving equation's soil under a cell (its region's, set once).
  const CuttingSoil& cutting_soil_at_cell(int cell) const { return regions_[region_index(cell)].cutting; }
  // The largest sinkage (from the undisturbed surface) a load reached at a
  // cell: the start of its reload line.
  double peak_sinkage_m(int cell) const { return peak_.empty() ? 0.0 : peak_[cell]; }
  // How far loads have lowered a cell's soil for good (the plastic sinkage
  // over the whole cell: what its surface shows).
  double plastic_lowering_m(int cell) const { return plastic_.empty() ? 0.0 : plastic_[cell]; }

 private:
  struct BodyState {
    ContactMap map;    // this step's (after interact) or last step's
    ContactMap next;   // being built
    std::vector<std::uint32_t> covered;       // cells this body covers completely
    std::vector<std::uint32_t> covered_next;  // being built (each body keeps its own: no regrowth)
    std::vector<SlicedCell> sliced;           // this step's, for a slicing body
    bool in_contact = false;
    bool slicing = false;
    Eigen::Vector2d slicing_forward = Eigen::Vector2d::UnitX();
    bool press_only = false;
    bool has_tool_face = false;
    Eigen::Vector3d tool_face_normal = Eigen::Vector3d::UnitX();
  };
  struct Push {
    std::uint32_t cell;
    int direction;
    double height_m;  // material to move, as a height over the cell
    bool plastic;     // the plastic sinkage of an incompressible soil (else swept by an advancing interface)
  };

  // A vertical interface of a contact cell on one side (5.2.3).
  struct Interface {
    double s_m = 0.0;      // covered length behind it, from the cell edge
    double w_m = 0.0;      // width
    double depth_m = 0.0;  // soil standing against it: H = d_0 at the interface
  };

  BodyState& body_state(int body_id);  // throws for an id out of [0, 65535]
  // Level of the soil under the part of a cell a body newly covers.
  double untouched_level_m(int cell, double covered_fraction) const;
  void update_covered(BodyState& state);
  void cover(std::uint32_t cell, bool on);
  // Plastic sinkage already realised under the covered part of a cell.
  double plastic_sinkage_under(int cell, double covered_fraction) const;
  // Records `quanta` taken plastically from under contact c (compacted or
  // pushed aside): the cell's plastic record and its covered part's level.
  void record_plastic(CellContact& c, std::int64_t quanta);
  struct SoilRegion {
    SoilMechanics soil;
    double phi_rad = 0.0;
    double tan_tool_friction = 0.0;
    WedgeAngleTable rho_table;
    CuttingSoil cutting;  // the earthmoving equation's soil
    double modulus_Pa = 0.0;  // Bekker's k_c / b + k_phi for this step's footprint
  };
  int region_index(int cell) const { return region_of_cell_.empty() ? 0 : region_of_cell_[cell]; }
  const SoilRegion& region_at(int cell) const { return regions_[region_index(cell)]; }
  // The soil of the cell in front of contact c in direction f (its own
  // where the grid ends).
  int region_in_front(const CellContact& c, int f) const;

  void press(CellContact& c, const BodyMotion& motion, BodyReaction& out);
  void push_material(const Push& push, const CellContact& c);
  void wedge_reactions(const BodyState& state, const ContactMap& map, BodyReaction& out);
  // The rake of the body's tool face against direction f (set_tool_face).
  double tool_rake_rad(const BodyState& state, int f) const;
  bool interface_at(const CellContact& c, int direction, Interface* out) const;
  // Highest level the free part of a partly covered cell can hold, next to
  // the cell in front of it in `direction`.
  double free_level_cap(int cell, double covered_fraction, int direction) const;
  // Level (m) of the free part of a partly covered cell (5.2.2: h2), given
  // the level of its covered part: the cell's material is f h1 + (1 - f) h2.
  double free_surface_m(int cell, double covered_fraction, double covered_level_m) const;
  // Walks the fracture wedge in front of an interface: the soil above the
  // plane rising at rho from the interface's foot, cell by cell, until the
  // plane emerges or the wedge is twice its flat-ground length. Returns the
  // wedge's section (m^2) and fills wedge_cells_ / wedge_area_ with the
  // cells in front and their part of it.
  // With `beyond_body`, the walk starts past the body's own cells (where
  // pushed material goes); without, it stops at them.
  double walk_wedge(const CellContact& c, int direction, const Interface& face, double rho_rad, bool beyond_body);

  GranularGrid& grid_;
  std::vector<SoilRegion> regions_;
  std::vector<std::uint8_t> region_of_cell_;  // empty: every cell is soil 0
  std::vector<double> region_width_;          // wedge scratch
  // Per cell, allocated at the first contact: the largest sinkage reached
  // (start of the reload line) and the plastic sinkage realised, as a height
  // over the cell (compacted, or pushed aside by an incompressible soil),
  // with the fraction of the cell it was taken from.
  std::vector<float> peak_;
  std::vector<float> plastic_;
  std::vector<float> pressed_;  // largest covered fraction plastic_ was taken from
  std::vector<std::uint8_t> cover_count_;  // bodies covering each cell completely
  Eigen::Vector2d current_footprint_centre_ = Eigen::Vector2d::Zero();
  std::vector<BodyState> bodies_;
  ContactMapper mapper_;
  // Where each cell of the map being worked on sits in it (index_map).
  void index_map(const ContactMap& map);
  int map_slot(int i, int j) const;  // -1: the body does not touch cell (i, j)
  std::vector<int> slots_;
  int slot_i0_ = 0, slot_j0_ = 0, slot_ni_ = 0, slot_nj_ = 0;
  struct FaceRef {
    int contact;    // index in the map
    int direction;  // +x, -x, +y, -y
    Interface face;
  };
  std::vector<FaceRef> interfaces_;
  std::vector<Push> pushes_;
  double wedge_end_surface_m_ = 0.0;  // walk_wedge: the ground where the plane came out
  std::vector<int> wedge_cells_;
  std::vector<double> wedge_area_;
};

}  // namespace skidsim::terrain
