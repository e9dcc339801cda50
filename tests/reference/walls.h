// Drum walls of the CPU reference (ARCHITECTURE.md "walls"; physics §0-§4 with j = the wall):
// the cylinder of radius R about +z, and the end plates at z = -L/2 (lo) and z = +L/2 (hi).
#pragma once

#include <glm/glm.hpp>

#include "reference/contact_law.h"
#include "wetdem/params.h"

namespace wetdem::ref {

// Whether wall w exists in this drum: the cylinder always; a plate when present and z is not periodic.
bool wall_present(const DrumParams& drum, uint32_t w);

// Contact geometry of a particle (x, r) with wall w: normal from the wall into the particle and overlap
// delta = r - distance to the wall surface. Returns false when it cannot be defined (particle on the axis).
bool wall_geometry(const DrumParams& drum, uint32_t w, const glm::dvec3& x, double r, glm::dvec3& n,
                   double& delta);

// Kinematics of particle i against wall w (§0): c = x_i - (r_i - delta/2) n; the wall moves as a rigid body
// turning about z with Omega = drum.omega when it rotates (cylinder always, a plate if `rotates`), so its
// velocity at c is Omega z x c and its angular velocity Omega z; R* = r_i, m* = m_i, R_h = 2 r_i.
ContactKinematics wall_kinematics(const DrumParams& drum, uint32_t w, const glm::dvec3& x, double r, double m,
                                  const glm::dvec3& v, const glm::dvec3& omega, const glm::dvec3& n,
                                  double delta);

}  // namespace wetdem::ref
