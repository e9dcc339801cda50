#include "app/observe/slabs.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "app/drum/aor.h"

namespace wetdem::observe {

double SlabAor::plate_deg() const {
  if (!present || lo_flagged || hi_flagged) return std::nan("");
  return std::fabs(0.5 * (plate_lo_deg + plate_hi_deg));
}

double SlabAor::centre_abs_deg() const {
  if (!present || centre_flagged) return std::nan("");
  return std::fabs(centre_deg);
}

SlabAor slab_aor(const SystemState& s, const DrumParams& drum, double thickness) {
  SlabAor r;
  const size_t n = s.p.size();
  if (drum.periodic_z || n == 0) return r;
  r.present = true;
  double dsum = 0;
  for (double rad : s.p.radius) dsum += 2.0 * rad;
  const double L = drum.length;
  const double t = std::min(thickness * dsum / static_cast<double>(n), L / 3.0);
  r.thickness_m = t;
  std::vector<glm::dvec3> x[3];
  std::vector<double> m[3];
  for (size_t k = 0; k < n; ++k) {
    const double z = s.p.x[k].z;
    const int slab = z < -0.5 * L + t ? 0 : z > 0.5 * L - t ? 1 : std::fabs(z) < 0.5 * t ? 2 : -1;
    if (slab < 0) continue;
    x[slab].push_back(s.p.x[k]);
    m[slab].push_back(s.p.mass[k]);
  }
  const AorSample lo = dynamic_aor(x[0], m[0], drum.radius), hi = dynamic_aor(x[1], m[1], drum.radius),
                  c = dynamic_aor(x[2], m[2], drum.radius);
  r.plate_lo_deg = lo.signed_deg, r.lo_flagged = lo.flagged;
  r.plate_hi_deg = hi.signed_deg, r.hi_flagged = hi.flagged;
  r.centre_deg = c.signed_deg, r.centre_flagged = c.flagged;
  return r;
}

}  // namespace wetdem::observe
