// Time-step checks of physics.md §6.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

// Largest stable step for a capillary bridge: 0.1 pi sqrt(m* / k_c), k_c = 1.05 f0 sqrt(R_h / V_b) (§6), the
// stiffness of the Willett law at contact (d f / d S at S = 0).
double capillary_dt_limit(double m_star, double R_h, double f0, double volume_m3);

// The smallest bridge (units) the §5 formation rule can make from these films: a bridge forms only when
// V_f,i + V_f,j > V_min and takes min(V_f,i + V_f,j, V_max); a partner whose film an earlier bridge has
// spent gives nothing, so the smallest is min(max(f_min, V_min + 1), V_max) with f_min the smallest positive
// film, one formation per particle per step. 0 when no pair of films exceeds V_min (no bridge can form).
// Smaller bridges can appear later (a film split over k simultaneous first touches, division remainders, a
// film refilled by a rupture); the run checks the bridges present for those.
int64_t smallest_formable_bridge(const LiquidParams& l, const std::vector<int64_t>& films);

// At the start of a run: warning text when dt exceeds the limit of the stiffest bridge present in `s` or of
// the smallest bridge its films can form (smallest_formable_bridge, between the two smallest particles).
// The text names the bridge, the ratio dt / limit and what to do (a smaller run.dt_rayleigh_fraction).
// Empty when dt is fine or liquid is off.
std::optional<std::string> capillary_timestep_warning(const SimParams& prm, const SystemState& s);

// During a run: the same check on the bridges present only.
std::optional<std::string> capillary_timestep_warning_present(const SimParams& prm, const SystemState& s);

// Candidate effect `viscous`: the damping coefficient c = dF_v/dv_n of the Pitois lubrication force at
// S = S_min, 6 pi eta R*^2 / S_min (1 - 1/sqrt(1 + V/(pi R* S_min^2)))^2, and the explicit stability limit of
// that damper, dt <= 2 m*/(Z c) with Z = 4: one damper on m* needs c dt/m* < 2 (v <- v (1 - c dt/m*) must not
// flip beyond -v); a particle in a packing is damped by up to 12 bridged neighbours at once, but only those
// squeezed to S_min damp that hard, and the micro drum ran stably at 8x the Z = 12 step (timestep.cpp).
double viscous_damping_coefficient(double eta, double s_min, double R_star, double volume_m3);
double viscous_dt_limit(double m_star, double R_star, double eta, double s_min, double volume_m3);

// Warning text when dt exceeds viscous_dt_limit for the stiffest lubricated contact the parameters allow: the
// smallest particle, a bridge of V_max, against its twin (m* = m/2, R* = r/2) or a wall with bridges (m* = m,
// R* = r). Empty when viscosity is off or dt is fine.
std::optional<std::string> viscous_timestep_warning(const SimParams& prm, const SystemState& s);

}  // namespace wetdem
