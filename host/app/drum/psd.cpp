#include "psd.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace wetdem {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt1_2 = 0.70710678118654752440;

// Standard normal CDF Φ(z) and upper tail Q(z) = 1 - Φ(z) = Φ(-z), both through erfc so that neither loses
// precision in its own tail.
double norm_cdf(double z) {
  return 0.5 * std::erfc(-z * kSqrt1_2);
}
double norm_sf(double z) {
  return 0.5 * std::erfc(z * kSqrt1_2);
}

// Φ(b) - Φ(a) for a ≤ b, computed on the side of zero where the two terms are small (no cancellation of two
// numbers near 1).
double norm_mass(double a, double b) {
  if (a > 0.0) return norm_sf(a) - norm_sf(b);
  return norm_cdf(b) - norm_cdf(a);
}

// Standard normal quantile Φ⁻¹(p): Acklam's rational approximation (relative error 1.15e-9) refined by one
// Halley step on Φ(z) - p, which brings it to about machine precision.
double norm_quantile(double p) {
  if (p <= 0.0) return -INFINITY;
  if (p >= 1.0) return INFINITY;
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double plow = 0.02425;
  double z;
  if (p < plow) {
    const double q = std::sqrt(-2.0 * std::log(p));
    z = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p > 1.0 - plow) {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    z = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else {
    const double q = p - 0.5;
    const double r = q * q;
    z = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // Halley: e = Φ(z) - p, u = e √(2π) e^{z²/2}, z -= u / (1 + z u / 2). Use the upper tail for z > 0.
  const double e = z > 0.0 ? (1.0 - p) - norm_sf(z) : norm_cdf(z) - p;
  const double u = (z > 0.0 ? -e : e) * std::sqrt(2.0 * kPi) * std::exp(0.5 * z * z);
  return z - u / (1.0 + 0.5 * z * u);
}

// g(t) = (1 - e^{-t}) / t, g(0) = 1: the mean of e^{-kx} over a unit uniform interval, without cancellation.
double g_exp(double t) {
  return std::fabs(t) < 1e-12 ? 1.0 - 0.5 * t : -std::expm1(-t) / t;
}

}  // namespace

PsdBasis parse_psd_basis(const std::string& s) {
  if (s == "volume") return PsdBasis::kVolume;
  if (s == "number") return PsdBasis::kNumber;
  throw std::invalid_argument("psd basis must be \"volume\" or \"number\", got \"" + s + "\"");
}

PsdTails parse_psd_tails(const std::string& s) {
  if (s == "truncate") return PsdTails::kTruncate;
  if (s == "lognormal") return PsdTails::kLogNormal;
  throw std::invalid_argument("psd tails must be \"truncate\" or \"lognormal\", got \"" + s + "\"");
}

PsdSampling parse_psd_sampling(const std::string& s) {
  if (s == "random") return PsdSampling::kRandom;
  if (s == "stratified") return PsdSampling::kStratified;
  throw std::invalid_argument("psd sampling must be \"random\" or \"stratified\", got \"" + s + "\"");
}

const char* to_string(PsdBasis b) {
  return b == PsdBasis::kVolume ? "volume" : "number";
}
const char* to_string(PsdTails t) {
  return t == PsdTails::kTruncate ? "truncate" : "lognormal";
}
const char* to_string(PsdSampling s) {
  return s == PsdSampling::kRandom ? "random" : "stratified";
}

static PsdSpec table_spec(const double (&d_um)[5], double scale, PsdTails tails) {
  PsdSpec s;
  s.kind = PsdSpec::Kind::kTable;
  s.basis = PsdBasis::kVolume;
  for (int i = 0; i < 5; ++i) s.table.push_back({PsdQuantiles::kFractions[i], d_um[i] * 1e-6});
  s.tails = tails;
  s.scale = scale;
  return s;
}

// drum.md "Powders": laser diffraction, volume basis, µm.
PsdSpec psd_pp1(double scale, PsdTails tails) {
  static const double d[5] = {304.0, 555.5, 736.7, 891.6, 1033.0};
  return table_spec(d, scale, tails);
}
PsdSpec psd_pp2(double scale, PsdTails tails) {
  static const double d[5] = {506.0, 712.7, 904.6, 1123.0, 1345.0};
  return table_spec(d, scale, tails);
}

double PsdQuantiles::operator[](int i) const {
  switch (i) {
    case 0:
      return d10;
    case 1:
      return d25;
    case 2:
      return d50;
    case 3:
      return d75;
    case 4:
      return d90;
    default:
      throw std::out_of_range("PsdQuantiles index");
  }
}

Psd::Psd(const PsdSpec& spec) : spec_(spec) {
  if (!(spec.scale > 0.0) || !std::isfinite(spec.scale)) throw std::invalid_argument("psd scale must be > 0");
  const bool lognormal_tails = spec.tails == PsdTails::kLogNormal;
  if (lognormal_tails && !(spec.tail_lo > 0.0 && spec.tail_hi < 1.0 && spec.tail_lo < spec.tail_hi))
    throw std::invalid_argument("psd tail_lo/tail_hi must satisfy 0 < tail_lo < tail_hi < 1");
  const double ls = std::log(spec.scale);

  if (spec.kind == PsdSpec::Kind::kTable) {
    const auto& t = spec.table;
    if (t.size() < 3) throw std::invalid_argument("psd table needs at least 3 points (D10, D50, D90)");
    for (size_t i = 0; i < t.size(); ++i) {
      if (!(t[i].fraction > 0.0 && t[i].fraction < 1.0))
        throw std::invalid_argument(fmt::format("psd table fraction {} not in (0, 1)", t[i].fraction));
      if (!(t[i].diameter > 0.0) || !std::isfinite(t[i].diameter))
        throw std::invalid_argument(fmt::format("psd table diameter {} must be > 0", t[i].diameter));
      if (i > 0 && !(t[i].fraction > t[i - 1].fraction && t[i].diameter > t[i - 1].diameter))
        throw std::invalid_argument("psd table fractions and diameters must both increase strictly");
    }
    // Reference: the table point nearest the median, so e^{-3x} stays O(1) over the support.
    size_t mid = 0;
    for (size_t i = 1; i < t.size(); ++i)
      if (std::fabs(t[i].fraction - 0.5) < std::fabs(t[mid].fraction - 0.5)) mid = i;
    x_ref_ = std::log(t[mid].diameter) + ls;
    std::vector<double> xs(t.size());
    for (size_t i = 0; i < t.size(); ++i) xs[i] = std::log(t[i].diameter) + ls - x_ref_;
    const size_t m = t.size();
    const double F0 = t[0].fraction, Fl = t[m - 1].fraction;

    // Lower tail.
    if (!lognormal_tails) {
      pieces_.push_back({Piece::kAtom, xs[0], xs[0], 0.0, 0.0, F0});
    } else {
      if (!(spec.tail_lo < F0))
        throw std::invalid_argument("psd tail_lo must be below the first table fraction");
      // Log-normal through the first two points: x = mu + sigma z(F).
      const double sigma = (xs[1] - xs[0]) / (norm_quantile(t[1].fraction) - norm_quantile(F0));
      const double mu = xs[0] - sigma * norm_quantile(F0);
      const double lo = mu + sigma * norm_quantile(spec.tail_lo);
      pieces_.push_back({Piece::kNormal, lo, xs[0], mu, sigma, F0});
    }
    // Table segments: cumulative fraction linear in ln d.
    for (size_t i = 0; i + 1 < m; ++i)
      pieces_.push_back({Piece::kUniform, xs[i], xs[i + 1], 0.0, 0.0, t[i + 1].fraction - t[i].fraction});
    // Upper tail.
    if (!lognormal_tails) {
      pieces_.push_back({Piece::kAtom, xs[m - 1], xs[m - 1], 0.0, 0.0, 1.0 - Fl});
    } else {
      if (!(spec.tail_hi > Fl))
        throw std::invalid_argument("psd tail_hi must be above the last table fraction");
      const double sigma = (xs[m - 1] - xs[m - 2]) / (norm_quantile(Fl) - norm_quantile(t[m - 2].fraction));
      const double mu = xs[m - 1] - sigma * norm_quantile(Fl);
      const double hi = mu + sigma * norm_quantile(spec.tail_hi);
      pieces_.push_back({Piece::kNormal, xs[m - 1], hi, mu, sigma, 1.0 - Fl});
    }
  } else {
    if (!(spec.median > 0.0) || !std::isfinite(spec.median))
      throw std::invalid_argument("psd log-normal median must be > 0");
    if (!(spec.sigma > 0.0) || !std::isfinite(spec.sigma))
      throw std::invalid_argument("psd log-normal sigma must be > 0");
    x_ref_ = std::log(spec.median) + ls;
    const double mu = 0.0, s = spec.sigma;
    if (!lognormal_tails) {
      const double lo = mu + s * norm_quantile(0.10), hi = mu + s * norm_quantile(0.90);
      pieces_.push_back({Piece::kAtom, lo, lo, 0.0, 0.0, 0.10});
      pieces_.push_back({Piece::kNormal, lo, hi, mu, s, 0.80});
      pieces_.push_back({Piece::kAtom, hi, hi, 0.0, 0.0, 0.10});
    } else {
      pieces_.push_back({Piece::kNormal, mu + s * norm_quantile(spec.tail_lo),
                         mu + s * norm_quantile(spec.tail_hi), mu, s, 1.0});
    }
  }

  // Cumulative number-basis masses, normalised, for sampling.
  const double k = weight_k(PsdBasis::kNumber);
  number_cum_.resize(pieces_.size());
  double acc = 0.0;
  for (size_t i = 0; i < pieces_.size(); ++i) number_cum_[i] = (acc += piece_mass(pieces_[i], k));
  for (double& c : number_cum_) c /= acc;
  number_cum_.back() = 1.0;
}

double Psd::weight_k(PsdBasis target) const {
  if (spec_.basis == target) return 0.0;
  // Volume density q3 -> number density q0 ∝ q3 / d³ = q3 e^{-3x}; number -> volume: q3 ∝ q0 e^{+3x}.
  return target == PsdBasis::kNumber ? 3.0 : -3.0;
}

// ∫ over the piece of (its density on the spec basis) × e^{-k x} dx.
double Psd::piece_mass(const Piece& p, double k) const {
  switch (p.type) {
    case Piece::kAtom:
      return p.mass * std::exp(-k * p.a);
    case Piece::kUniform:
      return p.mass * std::exp(-k * p.a) * g_exp(k * (p.b - p.a));
    case Piece::kNormal: {
      // Density m φ((x-mu)/σ)/σ / (Φ(β) - Φ(α)) on [a, b]. Completing the square,
      // φ((x-mu)/σ) e^{-kx} = e^{-k mu + k²σ²/2} φ((x - mu_k)/σ) with mu_k = mu - kσ².
      const double al = (p.a - p.mu) / p.sigma, be = (p.b - p.mu) / p.sigma;
      const double ks = k * p.sigma;
      return p.mass / norm_mass(al, be) * std::exp(-k * p.mu + 0.5 * ks * ks) * norm_mass(al + ks, be + ks);
    }
  }
  return 0.0;
}

double Psd::piece_cdf(const Piece& p, double k, double x) const {
  if (x < p.a) return 0.0;
  if (x >= p.b) return piece_mass(p, k);
  Piece q = p;
  q.b = x;
  if (p.type == Piece::kUniform) {
    q.mass = p.mass * (x - p.a) / (p.b - p.a);
    return piece_mass(q, k);
  }
  // Normal: same normalisation as the full piece, integral up to x.
  const double al = (p.a - p.mu) / p.sigma, be = (p.b - p.mu) / p.sigma, bx = (x - p.mu) / p.sigma;
  const double ks = k * p.sigma;
  return p.mass / norm_mass(al, be) * std::exp(-k * p.mu + 0.5 * ks * ks) * norm_mass(al + ks, bx + ks);
}

// The x where the piece's weighted CDF reaches the fraction u ∈ [0, 1] of its weighted mass.
double Psd::piece_inverse(const Piece& p, double k, double u) const {
  u = std::clamp(u, 0.0, 1.0);
  double x = p.a;
  switch (p.type) {
    case Piece::kAtom:
      return p.a;
    case Piece::kUniform: {
      const double w = p.b - p.a;
      // ∫_a^x e^{-k(t-a)} dt / ∫_a^b ... = u  =>  e^{-k(x-a)} = 1 + u expm1(-k w).
      x = k == 0.0 ? p.a + u * w : p.a - std::log1p(u * std::expm1(-k * w)) / k;
      break;
    }
    case Piece::kNormal: {
      const double mu_k = p.mu - k * p.sigma * p.sigma;
      const double al = (p.a - mu_k) / p.sigma, be = (p.b - mu_k) / p.sigma;
      if (al > 0.0) {  // upper tail: work with Q to keep precision
        const double q = norm_sf(al) - u * (norm_sf(al) - norm_sf(be));
        x = mu_k - p.sigma * norm_quantile(q);
      } else {
        const double pp = norm_cdf(al) + u * (norm_cdf(be) - norm_cdf(al));
        x = mu_k + p.sigma * norm_quantile(pp);
      }
      break;
    }
  }
  return std::clamp(x, p.a, p.b);
}

double Psd::quantile(double F, PsdBasis basis) const {
  const double k = weight_k(basis);
  std::vector<double> m(pieces_.size());
  double total = 0.0;
  for (size_t i = 0; i < pieces_.size(); ++i) total += (m[i] = piece_mass(pieces_[i], k));
  const double target = std::clamp(F, 0.0, 1.0) * total;
  double acc = 0.0;
  for (size_t i = 0; i < pieces_.size(); ++i) {
    if (m[i] <= 0.0) continue;
    if (acc + m[i] >= target || i + 1 == pieces_.size())
      return std::exp(x_ref_ + piece_inverse(pieces_[i], k, (target - acc) / m[i]));
    acc += m[i];
  }
  return d_max();
}

double Psd::cdf(double d, PsdBasis basis) const {
  if (!(d > 0.0)) return 0.0;
  const double k = weight_k(basis), x = std::log(d) - x_ref_;
  double below = 0.0, total = 0.0;
  for (const Piece& p : pieces_) {
    total += piece_mass(p, k);
    below += piece_cdf(p, k, x);
  }
  return std::clamp(below / total, 0.0, 1.0);
}

double Psd::sample(std::mt19937_64& rng) const {
  return number_at(uniform01(rng));
}

double Psd::number_at(double u) const {
  const size_t i =
      static_cast<size_t>(std::upper_bound(number_cum_.begin(), number_cum_.end(), u) - number_cum_.begin());
  const size_t j = std::min(i, pieces_.size() - 1);
  const double lo = j == 0 ? 0.0 : number_cum_[j - 1];
  const double w = number_cum_[j] - lo;
  const double v = w > 0.0 ? (u - lo) / w : 0.0;
  return std::exp(x_ref_ + piece_inverse(pieces_[j], weight_k(PsdBasis::kNumber), v));
}

std::vector<double> Psd::sample_stratified(size_t n, std::mt19937_64& rng) const {
  std::vector<double> d(n);
  for (size_t i = 0; i < n; ++i) d[i] = number_at((double(i) + uniform01(rng)) / double(n));
  // Fisher-Yates: the strata in a random order, so that the insertion order carries no size trend.
  for (size_t i = n; i > 1; --i) {
    const size_t j = std::min(i - 1, static_cast<size_t>(uniform01(rng) * double(i)));
    std::swap(d[i - 1], d[j]);
  }
  return d;
}

std::vector<double> Psd::sample(size_t n, uint64_t seed) const {
  std::mt19937_64 rng(seed);
  std::vector<double> d(n);
  for (double& di : d) di = sample(rng);
  return d;
}

PsdQuantiles Psd::quantiles(PsdBasis basis) const {
  PsdQuantiles q;
  q.d10 = quantile(0.10, basis);
  q.d25 = quantile(0.25, basis);
  q.d50 = quantile(0.50, basis);
  q.d75 = quantile(0.75, basis);
  q.d90 = quantile(0.90, basis);
  return q;
}

double Psd::mean_volume() const {
  // E_n[d³] = e^{3 x_ref} E_n[e^{3x}] and E_n[e^{3x}] = M(k_n - 3) / M(k_n), M(k) = Σ pieces ∫ density
  // e^{-kx}.
  const double kn = weight_k(PsdBasis::kNumber);
  double num = 0.0, den = 0.0;
  for (const Piece& p : pieces_) {
    num += piece_mass(p, kn - 3.0);
    den += piece_mass(p, kn);
  }
  return kPi / 6.0 * std::exp(3.0 * x_ref_) * num / den;
}

double Psd::d_min() const {
  return std::exp(x_ref_ + pieces_.front().a);
}
double Psd::d_max() const {
  return std::exp(x_ref_ + pieces_.back().b);
}

std::string Psd::describe() const {
  const PsdQuantiles q = quantiles(PsdBasis::kVolume);
  return fmt::format(
      "psd {} ({} basis), tails {}, scale l = {}: d = {:.1f}..{:.1f} µm, V̄_S = {:.4g} m³; model volume-basis "
      "D10/D25/D50/D75/D90 = {:.1f}/{:.1f}/{:.1f}/{:.1f}/{:.1f} µm",
      spec_.kind == PsdSpec::Kind::kTable ? "table" : "log-normal", to_string(spec_.basis),
      to_string(spec_.tails), spec_.scale, d_min() * 1e6, d_max() * 1e6, mean_volume(), q.d10 * 1e6,
      q.d25 * 1e6, q.d50 * 1e6, q.d75 * 1e6, q.d90 * 1e6);
}

double sample_quantile(const std::vector<double>& diameters, double fraction, PsdBasis basis) {
  if (diameters.empty()) throw std::invalid_argument("sample_quantile of an empty sample");
  std::vector<double> d = diameters;
  std::sort(d.begin(), d.end());
  const size_t n = d.size();
  std::vector<double> c(n);  // Hazen position of each particle: weight below it plus half its own
  double acc = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = basis == PsdBasis::kVolume ? d[i] * d[i] * d[i] : 1.0;
    c[i] = acc + 0.5 * w;
    acc += w;
  }
  const double target = std::clamp(fraction, 0.0, 1.0) * acc;
  if (target <= c.front()) return d.front();
  if (target >= c.back()) return d.back();
  const size_t j =
      static_cast<size_t>(std::upper_bound(c.begin(), c.end(), target) - c.begin());  // c[j-1] ≤ t < c[j]
  const double s = (target - c[j - 1]) / (c[j] - c[j - 1]);
  return std::exp(std::log(d[j - 1]) + s * (std::log(d[j]) - std::log(d[j - 1])));
}

PsdQuantiles sample_quantiles(const std::vector<double>& diameters, PsdBasis basis) {
  PsdQuantiles q;
  q.d10 = sample_quantile(diameters, 0.10, basis);
  q.d25 = sample_quantile(diameters, 0.25, basis);
  q.d50 = sample_quantile(diameters, 0.50, basis);
  q.d75 = sample_quantile(diameters, 0.75, basis);
  q.d90 = sample_quantile(diameters, 0.90, basis);
  return q;
}

double sample_mean_volume(const std::vector<double>& diameters) {
  if (diameters.empty()) return 0.0;
  double s = 0.0;
  for (double d : diameters) s += d * d * d;
  return kPi / 6.0 * s / static_cast<double>(diameters.size());
}

}  // namespace wetdem
