// Particle-size distributions (PSD): a D10/D25/D50/D75/D90 table or a log-normal, on a volume basis (laser
// diffraction) or a number basis, and deterministic sampling of the diameters of the particles to insert.
//
// Representation. Let x = ln d. The distribution is given on its own basis ("spec basis": volume or number)
// as a mixture of pieces in x:
//   - table segment [x_i, x_{i+1}] between two table points (F_i, d_i), (F_{i+1}, d_{i+1}): the cumulative
//     fraction is linear in ln d, i.e. the density in x is uniform with mass F_{i+1} - F_i;
//   - log-normal piece: a normal density in x (mean mu, sd sigma) restricted to [lo, hi] and renormalised;
//   - atom: a point mass at one diameter (the "truncate" tails).
// Conversion between bases (drum.md: the table is on a volume basis, the inserted particles are counted):
// the number density is the volume density divided by the particle volume, n(x) ∝ q3(x) e^{-3x}, so every
// piece is re-weighted by e^{-k x} with k = 3 (volume -> number) or k = -3 (number -> volume). Each piece's
// weighted mass and inverse CDF are closed forms (below), so sampling is exact: no grids, no rejection.
//
// Tails beyond the first and last table points (D10 and D90 for the drum powders), `tails`:
//   - "truncate" (default): no particle smaller than D_first or larger than D_last. The volume the table puts
//     below D_first (10 %) is carried by particles of exactly D_first, and the volume above D_last by
//     particles of exactly D_last (atoms). This keeps every table quantile exact on a volume basis (the
//     inserted D10 is the table's D10) and bounds the smallest particle, hence the time step (drum.md: Δt
//     from the smallest particle). Cost: a spike of D_first particles in the number distribution.
//   - "lognormal": below D_first a log-normal fitted to the first table segment (its sigma and mu are those
//   of
//     the log-normal through the two points (F_0, d_0), (F_1, d_1): sigma = (x_1 - x_0)/(z(F_1) - z(F_0)),
//     mu = x_0 - sigma z(F_0), z = standard-normal quantile), likewise above D_last from the last segment.
//     Each tail is cut at the fitted log-normal's quantile `tail_lo` (default 0.01: the D1-equivalent) or
//     `tail_hi` (default 0.99: D99) and renormalised to carry the table's full tail mass (F_0 below, 1 -
//     F_last above), so the table quantiles stay exact. Smaller particles: smaller Δt.
// A log-normal spec (median, sigma on its basis) with "lognormal" tails is cut at its tail_lo/tail_hi
// quantiles and renormalised; with "truncate" its mass below D10 / above D90 goes to atoms at D10 / D90 as
// for a table.
//
// Sampling: std::mt19937_64 and our own 53-bit uniform (uniform01), then the inverse number-basis CDF; std
// distributions are not used because their algorithms differ between standard libraries. A given seed gives
// the same diameters on every platform up to libm's last-bit differences in exp/log/erfc.
//
// `sampling` (psd.sampling): "random" draws every diameter independently; "stratified" draws one diameter in
// each of n equal-probability strata of the number-basis CDF, u_i = (i + U_i) / n, and shuffles them
// (stratified sampling: the sample's CDF is within 1/n of the model's at every diameter, for every seed).
// With a few hundred particles independent draws make the inserted powder differ from seed to seed: on the
// 410-particle flowing drum the counts spread 362-422 and D50 ±5 %; stratified, 397-398 and ±0.3 %. The
// lab observables of that drum did not become less noisy from seed to seed (docs/validation.md, "Is the
// inserted powder the seed luck?"): their noise is the bed's own stick-slip, so the default stays random.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace wetdem {

enum class PsdBasis { kVolume, kNumber };
enum class PsdTails { kTruncate, kLogNormal };
enum class PsdSampling { kRandom, kStratified };

// "volume" | "number"; "truncate" | "lognormal". Throw std::invalid_argument on anything else.
PsdBasis parse_psd_basis(const std::string& s);
PsdTails parse_psd_tails(const std::string& s);
PsdSampling parse_psd_sampling(const std::string& s);  // "random" | "stratified"
const char* to_string(PsdBasis b);
const char* to_string(PsdTails t);
const char* to_string(PsdSampling s);

// One table point: cumulative fraction F in (0, 1) (0.10 for D10) and the diameter D_F (m).
struct PsdPoint {
  double fraction = 0.0;
  double diameter = 0.0;
};

struct PsdSpec {
  enum class Kind { kTable, kLogNormal };
  Kind kind = Kind::kTable;
  PsdBasis basis = PsdBasis::kVolume;
  // Table: at least 3 points, fractions strictly increasing in (0, 1), diameters strictly increasing (m).
  // The drum powders give D10, D25, D50, D75, D90; any subset that keeps D10, D50, D90 is fine.
  std::vector<PsdPoint> table;
  // Log-normal: ln d ~ N(ln median, sigma^2) on `basis`. median in m, sigma dimensionless (> 0).
  double median = 0.0;
  double sigma = 0.0;
  PsdTails tails = PsdTails::kTruncate;
  double tail_lo = 0.01;  // "lognormal" tails: lower cut at this quantile of the fitted log-normal (D1)
  double tail_hi = 0.99;  // upper cut (D99)
  double scale = 1.0;     // scaling factor l: every diameter is multiplied by it (drum.md)
  PsdSampling sampling = PsdSampling::kRandom;  // how the inserted diameters are drawn (above)
};

// drum.md Tables 1-3, laser diffraction, volume basis, in metres, multiplied by `scale` (l).
PsdSpec psd_pp1(double scale = 1.0, PsdTails tails = PsdTails::kTruncate);
PsdSpec psd_pp2(double scale = 1.0, PsdTails tails = PsdTails::kTruncate);

// The five reported quantiles (m).
struct PsdQuantiles {
  double d10 = 0.0, d25 = 0.0, d50 = 0.0, d75 = 0.0, d90 = 0.0;
  static constexpr double kFractions[5] = {0.10, 0.25, 0.50, 0.75, 0.90};
  double operator[](int i) const;
};

class Psd {
 public:
  // Validates (throws std::invalid_argument with the reason) and builds the pieces.
  explicit Psd(const PsdSpec& spec);

  const PsdSpec& spec() const { return spec_; }

  // One diameter (m) drawn from the number-basis distribution (what is inserted).
  double sample(std::mt19937_64& rng) const;
  // The number-basis diameter (m) at cumulative fraction u in [0, 1) (sample() at a given uniform).
  double number_at(double u) const;
  // n diameters, one in each of n equal strata of the number-basis CDF, in a random order (psd.sampling =
  // "stratified"; the shuffle is our own Fisher-Yates on uniform01, as std::shuffle differs between
  // libraries).
  std::vector<double> sample_stratified(size_t n, std::mt19937_64& rng) const;
  // n diameters from a fresh std::mt19937_64(seed).
  std::vector<double> sample(size_t n, uint64_t seed) const;
  // Diameter at cumulative fraction F in [0, 1] of the given basis (the exact model, not a sample).
  double quantile(double F, PsdBasis basis) const;
  // Cumulative fraction of the given basis at diameter d (atoms at d included).
  double cdf(double d, PsdBasis basis) const;
  PsdQuantiles quantiles(PsdBasis basis) const;
  // Number-mean particle volume V̄_S = (π/6) E_n[d^3] (m^3): total solid volume / particle count.
  double mean_volume() const;
  double d_min() const;  // smallest diameter with non-zero probability (m)
  double d_max() const;  // largest (m)
  // One line: kind, basis, tails, scale, d_min, d_max, V̄_S, and the model's volume-basis D10..D90.
  std::string describe() const;

 private:
  struct Piece {
    enum Type { kUniform, kNormal, kAtom } type;
    double a, b;       // support in x = ln(d / d_ref): [a, b]; atoms: a == b
    double mu, sigma;  // kNormal only
    double mass;       // mass on the spec basis
  };
  double piece_mass(const Piece& p, double k) const;               // ∫ density e^{-k x} over the piece
  double piece_inverse(const Piece& p, double k, double u) const;  // x where the weighted CDF reaches u
  double piece_cdf(const Piece& p, double k, double x) const;      // weighted mass of the piece below x
  double weight_k(PsdBasis target) const;                          // k turning the spec basis into `target`

  PsdSpec spec_;
  double x_ref_ = 0.0;  // ln of a reference diameter (m): keeps e^{-kx} near 1
  std::vector<Piece> pieces_;
  std::vector<double> number_cum_;  // cumulative normalised number-basis masses of the pieces
};

// Quantile of a sample on the given basis (volume: each particle weighted by d^3). The sorted sample's
// cumulative weight is taken at the middle of each particle's weight ("Hazen" plotting position) and
// interpolated linearly in ln d.
double sample_quantile(const std::vector<double>& diameters, double fraction, PsdBasis basis);
PsdQuantiles sample_quantiles(const std::vector<double>& diameters, PsdBasis basis = PsdBasis::kVolume);
// (π/6) mean d^3 of a sample (m^3).
double sample_mean_volume(const std::vector<double>& diameters);

// The deterministic uniform in [0, 1) used everywhere in wetdem's set-up: the top 53 bits of one draw.
inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace wetdem
