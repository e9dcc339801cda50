// PSD sampling: the inserted particles must reproduce drum.md's D10..D90 (volume basis), the basis conversion
// must match closed forms, and sampling must be deterministic.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "app/drum/psd.h"
#include "support/numbers.h"

using namespace wetdem;

namespace {

// drum.md "Powders", µm, volume basis.
const double kPP1[5] = {304.0, 555.5, 736.7, 891.6, 1033.0};
const double kPP2[5] = {506.0, 712.7, 904.6, 1123.0, 1345.0};

struct Case {
  const char* name;
  const double* table;
  PsdTails tails;
  double scale;
};

}  // namespace

const Case kCases[] = {{"PP1 truncate", kPP1, PsdTails::kTruncate, 1.0},
                       {"PP1 lognormal", kPP1, PsdTails::kLogNormal, 1.0},
                       {"PP2 truncate", kPP2, PsdTails::kTruncate, 1.0},
                       {"PP2 lognormal", kPP2, PsdTails::kLogNormal, 1.0},
                       {"PP2 truncate l=3", kPP2, PsdTails::kTruncate, 3.0},
                       {"PP1 lognormal l=5", kPP1, PsdTails::kLogNormal, 5.0}};

// Inserted particles reproduce the table on a volume basis within 3 %. Statistics: the volume-weighted CDF of
// a number sample at D, F̂ = Σ w_i 1{d_i ≤ D} / Σ w_i with w = d³, has the variance (linearisation of the
// ratio) Var F̂ ≈ Σ w_i² (1{d_i ≤ D} - F)² / (Σ w_i)², and the quantile's relative standard error is (d ln
// D/dF) sqrt(Var F̂). At 20k particles that is up to 1.7 % (PP1 with log-normal tails: most particles are
// small and carry little volume; over 200 seeds the worst D25 error was 6.5 %), so a flat 3 % at 20k would be
// a 2-sigma test. Hence two checks: 200k particles against a flat 3 % (≥ 5 standard errors everywhere), and
// 20k particles against 4 standard errors estimated from the sample itself. A wrong basis conversion (the
// volume table sampled as a number distribution) shifts the volume D10 by > 30 %: both fail.
TEST(Psd, InsertedQuantilesReproduceTableVolumeBasis) {
  for (const Case& c : kCases) {
    const Psd psd(c.table == kPP1 ? psd_pp1(c.scale, c.tails) : psd_pp2(c.scale, c.tails));
    const std::vector<double> d = psd.sample(200000, 12345);
    const PsdQuantiles q = sample_quantiles(d, PsdBasis::kVolume);
    for (int i = 0; i < 5; ++i) {
      const double want = c.table[i] * 1e-6 * c.scale;
      EXPECT_NEAR(q[i] / want, 1.0, 0.03)
          << c.name << " D" << PsdQuantiles::kFractions[i] * 100 << ": inserted " << q[i] * 1e6
          << " µm, table " << want * 1e6 << " µm";
    }
    // The model itself is exact at the table points.
    const PsdQuantiles m = psd.quantiles(PsdBasis::kVolume);
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(m[i] / (c.table[i] * 1e-6 * c.scale), 1.0, 1e-9) << c.name;
    // Sample V̄_S agrees with the model's closed form (number-basis mean of π d³/6).
    EXPECT_NEAR(sample_mean_volume(d) / psd.mean_volume(), 1.0, 0.01) << c.name;
  }
}

TEST(Psd, TwentyThousandParticlesWithinSamplingError) {
  for (const Case& c : kCases) {
    const Psd psd(c.table == kPP1 ? psd_pp1(c.scale, c.tails) : psd_pp2(c.scale, c.tails));
    const std::vector<double> d = psd.sample(20000, 777);
    double sw = 0.0;
    for (double x : d) sw += x * x * x;
    const PsdQuantiles q = sample_quantiles(d, PsdBasis::kVolume);
    for (int i = 0; i < 5; ++i) {
      const double F = PsdQuantiles::kFractions[i], h = 1e-4, D = c.table[i] * 1e-6 * c.scale;
      // At a truncation atom (D10, D90 with "truncate") the CDF jumps; the quantile sits at one edge of the
      // jump. Take the variance of F̂ on either side of D (inclusive and exclusive indicator, each against the
      // model's CDF on that side) and the steeper one-sided slope: the larger of each bounds the error.
      const double F_incl = psd.cdf(D * (1 + 1e-12), PsdBasis::kVolume);
      const double F_excl = psd.cdf(D * (1 - 1e-12), PsdBasis::kVolume);
      double var_incl = 0.0, var_excl = 0.0;
      for (double x : d) {
        const double w2 = x * x * x * x * x * x;
        const double ei = (x <= D * (1 + 1e-12) ? 1.0 : 0.0) - F_incl,
                     ee = (x < D * (1 - 1e-12) ? 1.0 : 0.0) - F_excl;
        var_incl += w2 * ei * ei;
        var_excl += w2 * ee * ee;
      }
      const double var = std::max(var_incl, var_excl) / (sw * sw);
      const double lnD = std::log(psd.quantile(F, PsdBasis::kVolume));
      const double slope = std::max(std::log(psd.quantile(F + h, PsdBasis::kVolume)) - lnD,
                                    lnD - std::log(psd.quantile(F - h, PsdBasis::kVolume))) /
                           h;
      const double tol = 4.0 * slope * std::sqrt(var);
      EXPECT_LT(tol, 0.10)
          << c.name;  // the statistical tolerance itself stays far below a basis error (> 30 %)
      EXPECT_NEAR(q[i] / D, 1.0, tol) << c.name << " D" << F * 100 << " (4 standard errors: " << tol << ")";
    }
  }
}

TEST(Psd, NumberBasisSampleIsNotTheVolumeTable) {
  // The counted (number-basis) D50 must be well below the volume-basis D50: guards against a missing
  // conversion.
  const Psd psd(psd_pp2());
  const std::vector<double> d = psd.sample(20000, 7);
  EXPECT_LT(sample_quantile(d, 0.5, PsdBasis::kNumber), 0.8 * 904.6e-6);
  EXPECT_NEAR(sample_quantile(d, 0.5, PsdBasis::kNumber) / psd.quantile(0.5, PsdBasis::kNumber), 1.0, 0.03);
}

TEST(Psd, TailTreatmentBounds) {
  const Psd tr(psd_pp1(1.0, PsdTails::kTruncate));
  EXPECT_DOUBLE_EQ(tr.d_min(), 304.0e-6);
  EXPECT_DOUBLE_EQ(tr.d_max(), 1033.0e-6);
  const std::vector<double> d = tr.sample(5000, 3);
  EXPECT_GE(*std::min_element(d.begin(), d.end()), 304.0e-6 * (1 - 1e-12));
  EXPECT_LE(*std::max_element(d.begin(), d.end()), 1033.0e-6 * (1 + 1e-12));

  // Log-normal tails: the lower tail is the log-normal through (0.10, D10), (0.25, D25), cut at its 1 %
  // quantile.
  const Psd ln(psd_pp1(1.0, PsdTails::kLogNormal));
  const double z10 = -1.2815515655446004, z25 = -0.6744897501960817, z01 = -2.3263478740408408;
  const double sigma = std::log(555.5 / 304.0) / (z25 - z10);
  const double d1 = 304.0e-6 * std::exp(sigma * (z01 - z10));
  EXPECT_NEAR(ln.d_min() / d1, 1.0, 1e-9);
  EXPECT_LT(ln.d_min(), 304.0e-6);
  EXPECT_GT(ln.d_max(), 1033.0e-6);
  const std::vector<double> e = ln.sample(20000, 3);
  EXPECT_LT(*std::min_element(e.begin(), e.end()), 304.0e-6);  // the tail is populated
  EXPECT_GE(*std::min_element(e.begin(), e.end()), ln.d_min() * (1 - 1e-12));
  // Within the lower tail the volume-basis CDF follows the fitted log-normal renormalised to carry 10 %:
  // F(d) = 0.10 (Φ(z(d)) - 0.01) / (0.10 - 0.01), z(d) = z10 + ln(d/D10)/σ.
  const double dm = 200e-6, zm = z10 + std::log(dm / 304e-6) / sigma;
  const double Phi = 0.5 * std::erfc(-zm / std::sqrt(2.0));
  EXPECT_NEAR(ln.cdf(dm, PsdBasis::kVolume), 0.10 * (Phi - 0.01) / 0.09, 1e-9);
}

TEST(Psd, LogNormalBasisConversionMatchesClosedForms) {
  // Number-basis log-normal (median m, σ): volume-basis median m e^{3σ²} (Hatch–Choate), E[d³] = m³
  // e^{9σ²/2}.
  PsdSpec s;
  s.kind = PsdSpec::Kind::kLogNormal;
  s.basis = PsdBasis::kNumber;
  s.median = 1e-3;
  s.sigma = 0.3;
  s.tails = PsdTails::kLogNormal;
  s.tail_lo = 1e-14;  // practically untruncated
  s.tail_hi = 1 - 1e-14;
  const Psd psd(s);
  EXPECT_NEAR(psd.quantile(0.5, PsdBasis::kNumber) / 1e-3, 1.0, 1e-9);
  EXPECT_NEAR(psd.quantile(0.5, PsdBasis::kVolume) / (1e-3 * std::exp(3 * 0.09)), 1.0, 1e-6);
  EXPECT_NEAR(psd.mean_volume() / (kPi / 6 * 1e-9 * std::exp(4.5 * 0.09)), 1.0, 1e-6);
  // Volume-basis spec of the same distribution gives back the number median.
  s.basis = PsdBasis::kVolume;
  s.median = 1e-3 * std::exp(3 * 0.09);
  const Psd v(s);
  EXPECT_NEAR(v.quantile(0.5, PsdBasis::kNumber) / 1e-3, 1.0, 1e-6);
  EXPECT_NEAR(v.quantile(0.9, PsdBasis::kNumber) / (1e-3 * std::exp(0.3 * 1.2815515655446004)), 1.0, 1e-6);
  // Sampling follows it: number-basis D90 of 20k draws.
  const std::vector<double> d = psd.sample(20000, 99);
  EXPECT_NEAR(sample_quantile(d, 0.9, PsdBasis::kNumber) / (1e-3 * std::exp(0.3 * 1.2815515655446004)), 1.0,
              0.02);
}

TEST(Psd, DeterministicAndScaled) {
  const Psd a(psd_pp2(1.0)), b(psd_pp2(3.0));
  const std::vector<double> d1 = a.sample(1000, 42), d2 = a.sample(1000, 42), d3 = a.sample(1000, 43);
  EXPECT_EQ(d1, d2);
  EXPECT_NE(d1, d3);
  const std::vector<double> e = b.sample(1000, 42);
  for (size_t i = 0; i < d1.size(); ++i) ASSERT_NEAR(e[i] / d1[i], 3.0, 3e-12);
  EXPECT_NEAR(b.mean_volume() / a.mean_volume(), 27.0, 1e-9);
  // The first draws of mt19937_64(42) through uniform01 are fixed by the C++ standard: pin the PSD's
  // response.
  std::mt19937_64 rng(42);
  const double u = uniform01(rng);
  EXPECT_GE(u, 0.0);
  EXPECT_LT(u, 1.0);
  EXPECT_DOUBLE_EQ(u, static_cast<double>(std::mt19937_64(42)() >> 11) * 0x1.0p-53);
}

// psd.sampling = "stratified": the k-th smallest of n draws lies in the k-th stratum of the model's number
// CDF, [k/n, (k+1)/n], for every seed (the model's CDF is the third source); independent draws of the same n
// miss that by many strata. The draws come in a shuffled, seed-determined order.
TEST(Psd, StratifiedDrawsLieEachInItsOwnStratum) {
  for (const Psd& psd : {Psd(psd_pp2(5.0)), Psd(psd_pp1(5.0, PsdTails::kLogNormal))}) {
    const size_t n = 400;
    double worst_random = 0.0;
    for (uint64_t seed = 1; seed <= 5; ++seed) {
      std::mt19937_64 rng(seed);
      const std::vector<double> d = psd.sample_stratified(n, rng);
      ASSERT_EQ(d.size(), n);
      EXPECT_FALSE(std::is_sorted(d.begin(), d.end())) << "the strata are shuffled";
      std::vector<double> s = d;
      std::sort(s.begin(), s.end());
      for (size_t k = 0; k < n; ++k) {
        // F(d-) <= (k+1)/n and F(d) >= k/n: an atom (truncated tails) covers several strata.
        ASSERT_LE(psd.cdf(s[k] * (1.0 - 1e-12), PsdBasis::kNumber), double(k + 1) / double(n) + 1e-9) << k;
        ASSERT_GE(psd.cdf(s[k], PsdBasis::kNumber), double(k) / double(n) - 1e-9) << k;
      }
      std::mt19937_64 again(seed);
      EXPECT_EQ(psd.sample_stratified(n, again), d);
      std::vector<double> r = psd.sample(n, seed);
      std::sort(r.begin(), r.end());
      for (size_t k = 0; k < n; ++k) {
        const double f = psd.cdf(r[k], PsdBasis::kNumber);
        worst_random =
            std::max(worst_random, std::max(f - double(k + 1) / double(n), double(k) / double(n) - f));
      }
    }
    // Independent draws: the Kolmogorov distance of 400 draws is ~0.87/sqrt(400) = 0.04, 17 strata.
    EXPECT_GT(worst_random, 5.0 / 400.0);
  }
  EXPECT_EQ(parse_psd_sampling("stratified"), PsdSampling::kStratified);
  EXPECT_STREQ(to_string(PsdSampling::kRandom), "random");
  EXPECT_THROW(parse_psd_sampling("sobol"), std::invalid_argument);
}

TEST(Psd, SubsetTableAndValidation) {
  PsdSpec s = psd_pp2();
  s.table = {{0.10, 506e-6}, {0.50, 904.6e-6}, {0.90, 1345e-6}};  // D10, D50, D90 only
  const Psd p(s);
  EXPECT_NEAR(p.quantile(0.5, PsdBasis::kVolume) / 904.6e-6, 1.0, 1e-9);
  EXPECT_NEAR(p.quantile(0.3, PsdBasis::kVolume), std::exp(0.5 * (std::log(506e-6) + std::log(904.6e-6))),
              1e-12);

  PsdSpec bad = psd_pp2();
  bad.table[2].diameter = 600e-6;  // D50 < D25
  EXPECT_THROW(Psd{bad}, std::invalid_argument);
  bad = psd_pp2();
  bad.table.resize(2);
  EXPECT_THROW(Psd{bad}, std::invalid_argument);
  bad = psd_pp2();
  bad.scale = 0.0;
  EXPECT_THROW(Psd{bad}, std::invalid_argument);
  bad = psd_pp2(1.0, PsdTails::kLogNormal);
  bad.tail_lo = 0.2;  // above D10
  EXPECT_THROW(Psd{bad}, std::invalid_argument);
  EXPECT_EQ(parse_psd_tails("lognormal"), PsdTails::kLogNormal);
  EXPECT_EQ(parse_psd_basis("number"), PsdBasis::kNumber);
  EXPECT_THROW(parse_psd_tails("gauss"), std::invalid_argument);
}

TEST(Psd, ReportsWhatItInserts) {
  // Not an assertion on physics: prints the model and a 20k-sample measurement for the log.
  for (int pp = 1; pp <= 2; ++pp)
    for (PsdTails t : {PsdTails::kTruncate, PsdTails::kLogNormal}) {
      const Psd psd(pp == 1 ? psd_pp1(1.0, t) : psd_pp2(1.0, t));
      const PsdQuantiles q = sample_quantiles(psd.sample(20000, 12345));
      std::printf("PP%d %-9s inserted (20k, volume basis) D10..D90 = %.1f %.1f %.1f %.1f %.1f µm; %s\n", pp,
                  to_string(t), q.d10 * 1e6, q.d25 * 1e6, q.d50 * 1e6, q.d75 * 1e6, q.d90 * 1e6,
                  psd.describe().c_str());
    }
  SUCCEED();
}

#endif  // WETDEM_HAVE_APP
