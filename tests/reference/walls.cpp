#include "reference/walls.h"

#include <cmath>

namespace wetdem::ref {

bool wall_present(const DrumParams& drum, uint32_t w) {
  if (w == kWallCylinder) return true;
  if (drum.periodic_z) return false;
  return w == kWallPlateLo ? drum.plate_lo.present : drum.plate_hi.present;
}

bool wall_geometry(const DrumParams& drum, uint32_t w, const glm::dvec3& x, double r, glm::dvec3& n,
                   double& delta) {
  if (w == kWallCylinder) {
    const double rho = std::sqrt(x.x * x.x + x.y * x.y);
    if (rho == 0.0) return false;
    n = glm::dvec3(-x.x / rho, -x.y / rho, 0.0);  // from the cylinder surface towards the axis
    delta = r - (drum.radius - rho);
    return true;
  }
  const double half = 0.5 * drum.length;
  if (w == kWallPlateLo) {
    n = glm::dvec3(0.0, 0.0, 1.0);
    delta = r - (x.z + half);
  } else {
    n = glm::dvec3(0.0, 0.0, -1.0);
    delta = r - (half - x.z);
  }
  return true;
}

ContactKinematics wall_kinematics(const DrumParams& drum, uint32_t w, const glm::dvec3& x, double r, double m,
                                  const glm::dvec3& v, const glm::dvec3& omega, const glm::dvec3& n,
                                  double delta) {
  bool rotates = true;
  if (w == kWallPlateLo) rotates = drum.plate_lo.rotates;
  if (w == kWallPlateHi) rotates = drum.plate_hi.rotates;
  const glm::dvec3 wall_w = rotates ? glm::dvec3(0.0, 0.0, drum.omega) : glm::dvec3(0.0);

  ContactKinematics k;
  k.n = n;
  k.delta = delta;
  k.r_ci = -(r - 0.5 * delta) * n;  // §0
  const glm::dvec3 c = x + k.r_ci;
  k.r_cj = glm::dvec3(0.0);
  k.v_rel = v + glm::cross(omega, k.r_ci) - glm::cross(wall_w, c);  // wall: rigid rotation about the z axis
  k.w_rel = omega - wall_w;
  k.R_star = r;  // §0: flat or cylindrical wall
  k.m_star = m;
  k.R_h = 2.0 * r;  // §4
  return k;
}

}  // namespace wetdem::ref
