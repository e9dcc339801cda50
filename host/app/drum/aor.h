// Dynamic angle of repose (drum.md): the angle between the vertical and the line from the drum centre to the
// bed's centre of mass, in the plane normal to the drum axis (z), gravity along -y. And the time statistics
// of a series of such angles (mean, standard deviation, blocked standard error, stationarity of the window).
//
// Sign convention. With the mass-weighted centre of mass c = (c_x, c_y) in the xy plane,
//     signed angle θ = atan2(c_x, -c_y)  (degrees, in (-180, 180]),
// i.e. measured from the downward vertical (0, -1), positive when the bed is displaced towards +x. A drum
// turning with ω > 0 about +z moves its bottom towards +x (ω ẑ × (0, -R, 0) = (ωR, 0, 0)), so it drags the
// bed up on the +x side: θ > 0 for ω > 0 and θ < 0 for ω < 0. |θ| is the reported angle of repose,
// independent of the sense of rotation. For a bed with a flat free surface the centre of mass of the circular
// segment lies on the perpendicular from the drum centre to the surface, so θ equals the surface's
// inclination exactly. Beds with |c| < flag_fraction × R (0.2 R, drum.md: empty or nearly centred beds whose
// angle is meaningless) are flagged and must not be reported.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <limits>
#include <string>
#include <vector>

#include "wetdem/state.h"

namespace wetdem {

struct AorSample {
  double signed_deg = 0.0;  // θ = atan2(c_x, -c_y), degrees; > 0 for a bed displaced towards +x
  double abs_deg = 0.0;     // |θ|
  glm::dvec2 com{0.0};      // mass-weighted centre of mass in the xy plane (m)
  double com_radius = 0.0;  // |com| (m)
  double mass = 0.0;        // Σ m (kg)
  bool flagged = true;      // |com| < flag_fraction × R, or no mass: do not report θ
};

// Mass-weighted COM of the particles (x, y of each position) and its angle. mass may be empty: equal masses.
AorSample dynamic_aor(const std::vector<glm::dvec3>& x, const std::vector<double>& mass, double drum_radius,
                      double flag_fraction = 0.2);
AorSample dynamic_aor(const SystemState& s, double drum_radius, double flag_fraction = 0.2);

// Statistics of a time series v(t) over the window t ≥ t_from.
struct SeriesStats {
  size_t n = 0;  // samples in the window
  double t_begin = 0.0, t_end = 0.0;
  double mean = 0.0;
  double stddev = 0.0;     // sample standard deviation (n - 1)
  double sem_naive = 0.0;  // stddev / sqrt(n): valid for uncorrelated samples only
  // Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989): the series is halved by averaging neighbours, level
  // by level; the variance of the mean estimated at level j, s_j² / (n_j - 1), grows with j until the blocks
  // are longer than the correlation time and then stays flat. The level is chosen by Jonsson's test
  // (Phys. Rev. E 98, 043304 (2018)): the first level j where M_j = Σ_{i≥j} n_i (γ_i / s_i²)² (γ = lag-1
  // autocovariance) is below the 99 % χ² quantile with (levels - j) degrees of freedom.
  double sem = 0.0;           // blocked standard error of the mean
  int block_level = 0;        // chosen level (block length 2^level samples)
  bool sem_reliable = false;  // false: no level passed the test (window too short for the correlation time);
                              // sem is then the largest estimate over levels with ≥ 4 blocks
  // Stationarity: means of the first and second halves of the window, each with its blocked SEM;
  // z = (mean_2 - mean_1) / sqrt(sem_1² + sem_2²), stationary when |z| < 3.
  double mean_first = 0.0, mean_second = 0.0;
  double sem_first = 0.0, sem_second = 0.0;
  double drift_z = 0.0;
  bool stationary = false;
};

// Statistics of v over samples with t ≥ t_from (t ascending). Throws std::invalid_argument when the sizes
// differ.
SeriesStats series_stats(const std::vector<double>& t, const std::vector<double>& v,
                         double t_from = -std::numeric_limits<double>::infinity());
// The blocked SEM alone (Flyvbjerg–Petersen levels, Jonsson's choice), for samples equally spaced in time.
double blocked_sem(const std::vector<double>& v, int* level = nullptr, bool* reliable = nullptr);

// AoR over a run: statistics of the signed and absolute angles of the unflagged samples with t ≥ t_from.
struct AorSummary {
  SeriesStats signed_deg, abs_deg;
  size_t samples = 0;            // samples in the window
  size_t flagged = 0;            // of which flagged (excluded)
  std::string describe() const;  // one line: mean ± sd, SEM, window, flags
};
AorSummary summarize_aor(const std::vector<double>& t, const std::vector<AorSample>& samples,
                         double t_from = -std::numeric_limits<double>::infinity());

}  // namespace wetdem
