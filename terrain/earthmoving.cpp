#include "terrain/earthmoving.h"

#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace skidsim::terrain {
namespace {

constexpr double kTinyAngle_rad = 1e-4;  // keeps cot() finite at the ends of beta's range

// P / w and the factors at one beta (McKyes (4.12)); false where the wedge
// does not close.
bool factors(const CuttingSoil& soil, const CuttingTool& tool, double beta, CuttingForce* out) {
  const double alpha = tool.rake_rad, phi = soil.friction_angle_rad, delta = soil.tool_friction_angle_rad;
  const double d = tool.depth_m;
  const double cot_alpha = std::cos(alpha) / std::sin(alpha);
  const double cot_beta = std::cos(beta) / std::sin(beta);
  const double cot_beta_phi = std::cos(beta + phi) / std::sin(beta + phi);
  // D = sin(alpha + delta + beta + phi) / sin(beta + phi): positive while the
  // wedge can be pushed up the failure plane.
  const double denominator = std::cos(alpha + delta) + std::sin(alpha + delta) * cot_beta_phi;
  const double r = d * (cot_alpha + cot_beta);
  if (!(denominator > 0.0) || !(r > 0.0) || !(std::sin(beta + phi) > 0.0)) return false;
  // The crescents span rho' on each side (McKyes and Ali 1977): the arc of
  // radius r about the face's top edge, from straight ahead to the tip's
  // plane; a face at or past vertical gives the full quarter.
  const double cos_rho = std::clamp(cot_alpha / (cot_alpha + cot_beta), 0.0, 1.0);
  const double rho = std::acos(cos_rho);
  const double side = tool.side_crescents ? r * std::sin(rho) / tool.width_m : 0.0;
  out->failure_angle_rad = beta;
  out->rupture_m = r;
  out->crescent_angle_rad = tool.side_crescents ? rho : 0.0;
  out->n_gamma = r / (2.0 * d) * (1.0 + 2.0 * side / 3.0) / denominator;
  out->n_c = (1.0 + cot_beta * cot_beta_phi) * (1.0 + side) / denominator;
  out->n_q = r / d * (1.0 + (tool.surcharge_on_crescents ? side : 0.0)) / denominator;
  out->n_a = (1.0 - cot_alpha * cot_beta_phi) / denominator;
  const double w = tool.width_m;
  const double gamma_part = w * soil.unit_weight_N_per_m3 * d * d * out->n_gamma;
  const double cohesion_part = w * soil.cohesion_Pa * d * out->n_c;
  const double surcharge_part = w * tool.surcharge_Pa * d * out->n_q;
  const double adhesion_part = w * soil.tool_adhesion_Pa * d * out->n_a;
  out->face_force_N = gamma_part + cohesion_part + surcharge_part + adhesion_part;
  // On the tool: P at delta to the face normal, and the adhesion c_a d w /
  // sin(alpha) along the face.
  const double s = std::sin(alpha + delta), c = std::cos(alpha + delta);
  const double face_adhesion = soil.tool_adhesion_Pa * d * w;
  out->weight_term_N = gamma_part * s;
  out->cohesion_term_N = cohesion_part * s;
  out->surcharge_term_N = surcharge_part * s;
  out->adhesion_term_N = adhesion_part * s + face_adhesion * cot_alpha;
  out->horizontal_N = out->face_force_N * s + face_adhesion * cot_alpha;
  out->vertical_down_N = out->face_force_N * c - face_adhesion;
  return true;
}

double face_force_at(const CuttingSoil& soil, const CuttingTool& tool, double beta) {
  CuttingForce f;
  return factors(soil, tool, beta, &f) ? f.face_force_N : HUGE_VAL;
}

}  // namespace

double max_failure_angle_rad(const CuttingSoil& soil, double rake_rad) {
  // beta + phi + alpha + delta < pi (D > 0), beta < pi - alpha (r > 0), and
  // the plane rises ahead of the tip (beta < pi / 2).
  return std::min({0.5 * kPi, kPi - rake_rad - soil.friction_angle_rad - soil.tool_friction_angle_rad,
                   kPi - rake_rad});
}

CuttingForce mckyes_ali_at(const CuttingSoil& soil, const CuttingTool& tool, double beta_rad) {
  CuttingForce f;
  if (!(tool.depth_m > 0.0) || !(tool.width_m > 0.0)) return f;
  if (!(beta_rad > 0.0) || !(beta_rad < max_failure_angle_rad(soil, tool.rake_rad))) return f;
  if (!factors(soil, tool, beta_rad, &f)) return CuttingForce{};
  return f;
}

CuttingForce mckyes_ali(const CuttingSoil& soil, const CuttingTool& tool) {
  if (!(tool.depth_m > 0.0) || !(tool.width_m > 0.0)) return {};
  const double lo = kTinyAngle_rad, hi = max_failure_angle_rad(soil, tool.rake_rad) - kTinyAngle_rad;
  if (!(hi > lo)) return {};
  // A scan brackets the least P (it is one valley over the range), then
  // golden sections narrow it.
  constexpr int kScan = 24;
  int best = 0;
  double best_p = HUGE_VAL;
  for (int k = 0; k <= kScan; ++k) {
    const double p = face_force_at(soil, tool, lo + (hi - lo) * k / kScan);
    if (p < best_p) best_p = p, best = k;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / kScan;
  double b = lo + (hi - lo) * std::min(kScan, best + 1) / kScan;
  constexpr double kInvPhi = 0.6180339887498949;
  double x1 = b - kInvPhi * (b - a), x2 = a + kInvPhi * (b - a);
  double f1 = face_force_at(soil, tool, x1), f2 = face_force_at(soil, tool, x2);
  while (b - a > 1e-6) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1;
      x1 = b - kInvPhi * (b - a);
      f1 = face_force_at(soil, tool, x1);
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = a + kInvPhi * (b - a);
      f2 = face_force_at(soil, tool, x2);
    }
  }
  CuttingForce f;
  if (!factors(soil, tool, 0.5 * (a + b), &f)) return {};
  return f;
}

void validate(const CuttingSoil& soil, const CuttingTool& tool) {
  const auto check = [](bool ok, const char* field, double value, const char* range) {
    if (!ok)
      throw std::invalid_argument(std::string("earthmoving: ") + field + " = " + std::to_string(value) +
                                  " is outside " + range);
  };
  check(soil.unit_weight_N_per_m3 >= 0.0 && std::isfinite(soil.unit_weight_N_per_m3), "unit weight (N/m^3)",
        soil.unit_weight_N_per_m3, "[0, inf)");
  check(soil.cohesion_Pa >= 0.0 && std::isfinite(soil.cohesion_Pa), "cohesion (Pa)", soil.cohesion_Pa, "[0, inf)");
  check(soil.tool_adhesion_Pa >= 0.0 && std::isfinite(soil.tool_adhesion_Pa), "tool adhesion (Pa)",
        soil.tool_adhesion_Pa, "[0, inf)");
  check(soil.friction_angle_rad >= 0.0 && soil.friction_angle_rad < deg_to_rad(60.0), "friction angle (deg)",
        rad_to_deg(soil.friction_angle_rad), "[0, 60)");
  check(soil.tool_friction_angle_rad >= 0.0 && soil.tool_friction_angle_rad < deg_to_rad(60.0),
        "tool friction angle (deg)", rad_to_deg(soil.tool_friction_angle_rad), "[0, 60)");
  check(tool.rake_rad >= deg_to_rad(5.0) && tool.rake_rad <= deg_to_rad(150.0), "rake (deg)",
        rad_to_deg(tool.rake_rad), "[5, 150]");
  check(tool.depth_m >= 0.0 && std::isfinite(tool.depth_m), "depth (m)", tool.depth_m, "[0, inf)");
  check(tool.width_m >= 0.0 && std::isfinite(tool.width_m), "width (m)", tool.width_m, "[0, inf)");
  check(tool.surcharge_Pa >= 0.0 && std::isfinite(tool.surcharge_Pa), "surcharge (Pa)", tool.surcharge_Pa,
        "[0, inf)");
}

}  // namespace skidsim::terrain
