// Time-step checks of physics.md §6.
#pragma once

#include <optional>
#include <string>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

// Largest stable step for a capillary bridge: 0.1 pi sqrt(m* / k_c), k_c = 1.05 f0 sqrt(R_h / V_b) (§6), the
// stiffness of the Willett law at contact (d f / d S at S = 0).
double capillary_dt_limit(double m_star, double R_h, double f0, double volume_m3);

// Warning text when dt exceeds the limit of the stiffest bridge: the bridges present in `s` and, before any
// exist, the stiffest bridge the parameters allow (smallest particles, smallest volume a formation can give:
// V_min + 1 unit when V_min > 0, else the smallest film pair). Empty when dt is fine or liquid is off.
std::optional<std::string> capillary_timestep_warning(const SimParams& prm, const SystemState& s);

}  // namespace wetdem
