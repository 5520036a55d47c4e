#include "engine/soil_resistance.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

namespace skidsim::engine {

SoilResistance::SoilResistance(btMultiBody* body, int bullet_link)
    : btMultiBodyConstraint(body, nullptr, bullet_link, -1, kMaxRows, false, MULTIBODY_CONSTRAINT_POINT_TO_POINT) {
  m_data.resize(kMaxRows);  // the solver's applied impulses, one per row
}

int SoilResistance::getIslandIdA() const {
  const btMultiBodyLinkCollider* col = m_linkA < 0 ? m_bodyA->getBaseCollider() : m_bodyA->getLink(m_linkA).m_collider;
  return col ? col->getIslandTag() : -1;
}

void SoilResistance::set(const terrain::BodyReaction& r, double scale, double dt_s) {
  rows_ = 0;
  const auto add = [&](const Eigen::Vector3d& p, int axis, double resist_plus_N, double resist_minus_N) {
    if (resist_plus_N <= 0.0 && resist_minus_N <= 0.0) return;
    Row& row = row_[rows_++];
    row.point = btVector3(p.x(), p.y(), p.z());
    row.direction = btVector3(0, 0, 0);
    row.direction[axis] = 1.0;
    // A negative impulse resists motion towards +axis (the wedge ahead on
    // that side), a positive one motion towards -axis.
    row.lower = -scale * resist_plus_N * dt_s;
    row.upper = scale * resist_minus_N * dt_s;
  };
  for (int axis = 0; axis < 2; ++axis) {
    const terrain::WedgeReaction& plus = r.wedge[static_cast<size_t>(2 * axis)];
    const terrain::WedgeReaction& minus = r.wedge[static_cast<size_t>(2 * axis + 1)];
    // One row per axis, at the point of the stronger wedge.
    add(plus.bound_N >= minus.bound_N ? plus.point_m : minus.point_m, axis, plus.bound_N, minus.bound_N);
  }
  for (int axis = 0; axis < 2; ++axis) add(r.shear_point_m, axis, r.shear_bound_N, r.shear_bound_N);
}

void SoilResistance::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                          const btContactSolverInfo& info) {
  for (int k = 0; k < rows_; ++k) {
    const Row& row = row_[k];
    btMultiBodySolverConstraint& c = rows.expandNonInitializing();
    c.m_orgConstraint = this;
    c.m_orgDofIndex = k;
    c.m_relpos1CrossNormal.setValue(0, 0, 0);
    c.m_contactNormal1.setValue(0, 0, 0);
    c.m_relpos2CrossNormal.setValue(0, 0, 0);
    c.m_contactNormal2.setValue(0, 0, 0);
    c.m_angularComponentA.setValue(0, 0, 0);
    c.m_angularComponentB.setValue(0, 0, 0);
    c.m_solverBodyIdA = data.m_fixedBodyId;
    c.m_solverBodyIdB = data.m_fixedBodyId;
    // Target: no velocity of the point along the row (no position error:
    // the soil does not pull a body back to where it was).
    fillMultiBodyConstraint(c, data, nullptr, nullptr, btVector3(0, 0, 0), row.direction, row.point, row.point, 0.0,
                            info, row.lower, row.upper);
  }
}

}  // namespace skidsim::engine
