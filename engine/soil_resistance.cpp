#include "engine/soil_resistance.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>

namespace skidsim::engine {

SoilResistance::SoilResistance(btMultiBody* body, int bullet_link)
    : btMultiBodyConstraint(body, nullptr, bullet_link, -1, kMaxRows, false, MULTIBODY_CONSTRAINT_POINT_TO_POINT) {
  m_data.resize(kMaxRows);  // the solver's applied impulses, one per row
}

int SoilResistance::getIslandIdA() const {
  const btMultiBodyLinkCollider* col = m_linkA < 0 ? m_bodyA->getBaseCollider() : m_bodyA->getLink(m_linkA).m_collider;
  return col ? col->getIslandTag() : -1;
}

void SoilResistance::set(const terrain::BodyReaction& r, const double wedge_scale[4], const Eigen::Vector2d& slip,
                         double dt_s) {
  rows_ = 0;
  // A row: the point's velocity along `direction` held at zero with an
  // impulse in [lower, upper].
  const auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector2d& direction, double lower_N, double upper_N) {
    if (lower_N >= 0.0 && upper_N <= 0.0) return;
    Row& row = row_[rows_++];
    row.point = btVector3(p.x(), p.y(), p.z());
    row.direction = btVector3(direction.x(), direction.y(), 0.0);
    row.lower = lower_N * dt_s;
    row.upper = upper_N * dt_s;
    row.down_per_N = 0.0;
  };
  // Each wedge on its own side, at its own point, one way only: the wedge
  // ahead of a +x interface resists motion towards +x (a negative impulse
  // along +x), never pulls.
  static const Eigen::Vector2d kAxis[4] = {Eigen::Vector2d::UnitX(), -Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY(),
                                           -Eigen::Vector2d::UnitY()};
  for (int f = 0; f < 4; ++f) {
    const terrain::WedgeReaction& w = r.wedge[static_cast<size_t>(f)];
    if (!(w.bound_N > 0.0)) continue;
    const int before = rows_;
    add(w.point_m, kAxis[f], -wedge_scale[f] * w.bound_N, 0.0);
    if (rows_ > before && wedge_scale[f] == 1.0) row_[before].down_per_N = w.vertical_down_N / w.bound_N;
  }
  // Mohr-Coulomb: against the slip and across it (as Bullet's own friction
  // pairs its rows), each up to the bound.
  if (r.shear_bound_N > 0.0) {
    const double speed = slip.norm();
    const Eigen::Vector2d along = speed > 1e-9 ? Eigen::Vector2d(slip / speed) : Eigen::Vector2d::UnitX();
    const Eigen::Vector2d across(-along.y(), along.x());
    add(r.shear_point_m, along, -r.shear_bound_N, r.shear_bound_N);
    add(r.shear_point_m, across, -r.shear_bound_N, r.shear_bound_N);
  }
}

int SoilResistance::vertical_forces(double dt_s, Eigen::Vector3d force_N[4], Eigen::Vector3d point_m[4],
                                    double* reaction_sum_N) {
  int n = 0;
  *reaction_sum_N = 0.0;
  for (int k = 0; k < rows_ && n < 4; ++k) {
    const Row& row = row_[k];
    if (row.down_per_N == 0.0) continue;
    // The wedge rows' impulses are negative along their axis (they resist).
    const double reaction_N = std::max(0.0, -getAppliedImpulse(k) / dt_s);
    if (!(reaction_N > 0.0)) continue;
    force_N[n] = Eigen::Vector3d(0.0, 0.0, -row.down_per_N * reaction_N);
    point_m[n] = Eigen::Vector3d(row.point.x(), row.point.y(), row.point.z());
    *reaction_sum_N += reaction_N;
    ++n;
  }
  return n;
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
