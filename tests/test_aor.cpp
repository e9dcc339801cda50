// Dynamic angle of repose: synthetic static beds with known free-surface angles, both senses of rotation, and
// the time statistics (blocked SEM against AR(1) series whose SEM is known in closed form).
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/drum/aor.h"
#include "app/drum/psd.h"  // uniform01
#include "support/numbers.h"

using namespace wetdem;

namespace {

constexpr double kR = 0.07;

// A bed filling `fraction` of the cross-section below a flat free surface inclined at beta (degrees; > 0
// raises the bed on the +x side, as a drum turning with ω > 0 does). The bed is the circular segment {p : p·u
// ≥ c} with u = (sin β, -cos β) the unit normal of the surface pointing into the bed, sampled on a fine
// square lattice (spacing R/300), several z layers. Unequal masses in z do not move the COM in the xy plane.
struct Bed {
  std::vector<glm::dvec3> x;
  std::vector<double> m;
  double c = 0.0;  // distance of the surface from the drum centre
};

// Segment area fraction for a chord at distance c from the centre: (α - sin α cos α)/π with cos α = c/R.
double segment_fraction(double c) {
  const double a = std::acos(c / kR);
  return (a - std::sin(a) * std::cos(a)) / kPi;
}

Bed make_bed(double beta_deg, double fraction) {
  double lo = -kR, hi = kR;  // bisection on c: fraction decreases with c
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (segment_fraction(mid) > fraction ? lo : hi) = mid;
  }
  Bed b;
  b.c = 0.5 * (lo + hi);
  const double beta = beta_deg * kPi / 180.0;
  const glm::dvec2 u(std::sin(beta), -std::cos(beta));
  const int n = 300;
  const double h = kR / n;
  for (int layer = 0; layer < 3; ++layer)
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) {
        const glm::dvec2 p((i + 0.5) * h, (j + 0.5) * h);
        if (glm::dot(p, p) > kR * kR || glm::dot(p, u) < b.c) continue;
        b.x.emplace_back(p.x, p.y, 0.01 * layer);
        b.m.push_back(1.0 + layer);
      }
  return b;
}

// Standard normal by Box–Muller from our portable uniform.
double gauss(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform01(rng), u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// AR(1): x_t = ρ x_{t-1} + sqrt(1-ρ²) ε, unit variance. Variance of the mean of n samples, exactly:
// (1/n)[1 + 2 Σ_{k=1}^{n-1} (1 - k/n) ρ^k].
std::vector<double> ar1(size_t n, double rho, uint64_t seed, double& sem_exact) {
  std::mt19937_64 rng(seed);
  std::vector<double> x(n);
  double v = gauss(rng);
  for (size_t i = 0; i < n; ++i) x[i] = v = rho * v + std::sqrt(1 - rho * rho) * gauss(rng);
  double s = 1.0, rk = 1.0;
  for (size_t k = 1; k < n; ++k) {
    rk *= rho;
    s += 2.0 * (1.0 - double(k) / double(n)) * rk;
  }
  sem_exact = std::sqrt(s / double(n));
  return x;
}

}  // namespace

TEST(Aor, StaticBedsWithKnownSurfaceAngleBothSenses) {
  for (double beta : {0.0, 20.0, 40.0, -20.0, -40.0}) {
    const Bed b = make_bed(beta, 0.4);
    const AorSample s = dynamic_aor(b.x, b.m, kR);
    // The COM of a circular segment lies on the perpendicular from the centre to its chord: θ = β exactly;
    // the lattice (~2×10^5 points) resolves it to ~0.01°.
    EXPECT_NEAR(s.signed_deg, beta, 0.05) << "beta " << beta;
    EXPECT_NEAR(s.abs_deg, std::fabs(beta), 0.05) << "beta " << beta;
    // |COM| of a segment with half-angle α: 4 R sin³α / (3 (2α - sin 2α)).
    const double a = std::acos(b.c / kR);
    const double d = 4 * kR * std::pow(std::sin(a), 3) / (3 * (2 * a - std::sin(2 * a)));
    EXPECT_NEAR(s.com_radius / d, 1.0, 2e-3);
    EXPECT_FALSE(s.flagged);
    EXPECT_NEAR(s.mass, 2.0 * double(b.x.size()), 1e-6);
  }
  // Mirror symmetry x -> -x (the other sense of rotation) flips the sign only.
  Bed b = make_bed(33.0, 0.3);
  const AorSample s1 = dynamic_aor(b.x, b.m, kR);
  for (auto& p : b.x) p.x = -p.x;
  const AorSample s2 = dynamic_aor(b.x, b.m, kR);
  EXPECT_NEAR(s1.signed_deg, -s2.signed_deg, 1e-9);
  EXPECT_NEAR(s1.abs_deg, s2.abs_deg, 1e-9);
}

TEST(Aor, MassWeightedAndFlags) {
  // Two particles: the heavy one dominates. COM = (3·(0.01,-0.05) + 1·(-0.03,-0.05))/4 = (0, -0.05): θ = 0.
  const std::vector<glm::dvec3> x{{0.01, -0.05, 0.0}, {-0.03, -0.05, 0.0}};
  const AorSample s = dynamic_aor(x, {3.0, 1.0}, kR);
  EXPECT_NEAR(s.signed_deg, 0.0, 1e-12);
  EXPECT_NEAR(s.com.x, 0.0, 1e-15);
  const AorSample eq = dynamic_aor(x, {}, kR);  // equal masses: COM (-0.01, -0.05)
  EXPECT_NEAR(eq.signed_deg, std::atan2(-0.01, 0.05) * 180 / kPi, 1e-12);
  // An empty bed and a full drum (COM at the centre) are flagged.
  EXPECT_TRUE(dynamic_aor({}, {}, kR).flagged);
  EXPECT_TRUE(dynamic_aor(make_bed(0.0, 0.999).x, {}, kR).flagged);
  // |COM| just below / above 0.2 R.
  EXPECT_TRUE(dynamic_aor({{0.0, -0.0139, 0.0}}, {}, kR).flagged);
  EXPECT_FALSE(dynamic_aor({{0.0, -0.0141, 0.0}}, {}, kR).flagged);
  // A bed lifted past the horizontal: the angle keeps growing beyond 90° (atan2, not atan).
  EXPECT_NEAR(dynamic_aor({{0.05, 0.01, 0.0}}, {}, kR).signed_deg, 90.0 + std::atan2(0.01, 0.05) * 180 / kPi,
              1e-9);
}

TEST(Aor, BlockedSemMatchesCorrelatedSeries) {
  // ρ = 0.9: the naive SEM underestimates by sqrt((1+ρ)/(1-ρ)) ≈ 4.4; blocking must recover the exact value.
  double exact = 0.0;
  const std::vector<double> x = ar1(1 << 16, 0.9, 2024, exact);
  std::vector<double> t(x.size());
  for (size_t i = 0; i < t.size(); ++i) t[i] = 0.01 * double(i);
  const SeriesStats s = series_stats(t, x);
  EXPECT_EQ(s.n, x.size());
  EXPECT_NEAR(s.stddev, 1.0, 0.1);
  EXPECT_LT(s.sem_naive, 0.5 * exact);
  EXPECT_NEAR(s.sem / exact, 1.0, 0.25) << "level " << s.block_level;
  EXPECT_TRUE(s.sem_reliable);
  EXPECT_GT(s.block_level, 2);
  EXPECT_TRUE(s.stationary) << s.drift_z;

  // Uncorrelated noise: blocked ≈ naive.
  const std::vector<double> w = ar1(1 << 14, 0.0, 5, exact);
  int level = -1;
  bool reliable = false;
  const double sem = blocked_sem(w, &level, &reliable);
  EXPECT_NEAR(sem / exact, 1.0, 0.2);
  EXPECT_TRUE(reliable);
}

TEST(Aor, StationarityDetectsDrift) {
  double exact = 0.0;
  std::vector<double> x = ar1(4096, 0.5, 11, exact);
  std::vector<double> t(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    t[i] = double(i);
    x[i] += 2.0 * double(i) / double(x.size());  // drift of 2 standard deviations across the window
  }
  const SeriesStats s = series_stats(t, x);
  EXPECT_FALSE(s.stationary);
  EXPECT_GT(s.drift_z, 3.0);
  // The window t >= t_from keeps only the last quarter.
  const SeriesStats tail = series_stats(t, x, 3072.0);
  EXPECT_EQ(tail.n, 1024u);
  EXPECT_DOUBLE_EQ(tail.t_begin, 3072.0);
}

TEST(Aor, SummaryExcludesFlaggedAndEarlySamples) {
  std::vector<double> t;
  std::vector<AorSample> s;
  for (int i = 0; i < 100; ++i) {
    AorSample a;
    a.signed_deg = (i % 2 ? -30.0 : -34.0);  // a drum turning with ω < 0
    a.abs_deg = std::fabs(a.signed_deg);
    a.flagged = (i == 60);
    if (i < 20) a.signed_deg = a.abs_deg = 5.0;  // start-up, outside the window
    t.push_back(0.1 * i);
    s.push_back(a);
  }
  const AorSummary sum = summarize_aor(t, s, 2.0);
  EXPECT_EQ(sum.samples, 80u);
  EXPECT_EQ(sum.flagged, 1u);
  EXPECT_EQ(sum.abs_deg.n, 79u);
  EXPECT_NEAR(sum.abs_deg.mean, 32.0, 0.03);
  EXPECT_NEAR(sum.signed_deg.mean, -32.0, 0.03);
  EXPECT_FALSE(sum.describe().empty());
}

#endif  // WETDEM_HAVE_APP
