// The soil's bounded reactions on a link as a Bullet constraint (thesis
// 5.4.2 and 5.5.2; terrain/soil_contact.h, BodyReaction): fracture wedges
// ahead of a body's interfaces and Mohr-Coulomb shear under it hold the
// body still up to their bounds, like dry friction. Each is a velocity row
// (the link's point must not move along an axis) whose impulse the solver
// keeps within bound * dt, so the soil resists exactly what the machine
// pushes with, up to the bound, and never pushes back on its own: stable
// at 2 ms for any bound (an explicit saturating force is not).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

#include <Eigen/Core>

#include "terrain/soil_contact.h"

namespace skidsim::engine {

class SoilResistance : public btMultiBodyConstraint {
 public:
  // `bullet_link` is Bullet's link index (-1 for the base).
  SoilResistance(btMultiBody* body, int bullet_link);

  // This step's rows from the soil's reaction; `dt_s` turns the bounds into
  // impulse limits. `wedge_scale[f]` scales the wedge towards face f (+x,
  // -x, +y, -y); `slip` is the horizontal velocity of the body at the
  // shear point (the shear's first row opposes it, the second is across
  // it). No rows: clear().
  void set(const terrain::BodyReaction& r, const double wedge_scale[4], const Eigen::Vector2d& slip, double dt_s);
  void clear() { rows_ = 0; }
  // The vertical part of the soil's force on the faces that pushed in the
  // last solve (terrain::WedgeReaction::vertical_down_N per newton of the
  // bound, times the horizontal reaction the solver gave; only wedges met
  // whole, wedge_scale 1): up to four forces (world frame) and their points.
  // Returns how many; `reaction_N` gets the horizontal reactions they go with.
  int vertical_forces(double dt_s, Eigen::Vector3d force_N[4], Eigen::Vector3d point_m[4], double* reaction_N);

  void finalizeMultiDof() override {}
  int getIslandIdA() const override;
  int getIslandIdB() const override { return -1; }
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void debugDraw(class btIDebugDraw*) override {}

 private:
  struct Row {
    btVector3 point, direction;
    double lower = 0.0, upper = 0.0;  // impulse along `direction`
    double down_per_N = 0.0;          // vertical force down per newton of reaction (wedge rows)
  };
  static constexpr int kMaxRows = 6;  // a wedge each way, shear along and across the slip
  Row row_[kMaxRows];
  int rows_ = 0;
};

}  // namespace skidsim::engine
