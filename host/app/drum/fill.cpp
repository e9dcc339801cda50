#include "fill.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace wetdem {

namespace {

constexpr double kPi = 3.14159265358979323846;

// splitmix64 (Steele, Lea, Flood 2014): derives independent seeds for the size and position streams.
uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform cell grid over a box; each particle is registered in every cell its bounding box [c - r, c + r]
// touches, so two spheres that overlap (|dx| < r_i + r_j on every axis) always share a cell whatever their
// sizes. z may be periodic (cells wrap).
class Grid {
 public:
  Grid(glm::dvec3 lo, glm::dvec3 hi, double cell, bool periodic_z, size_t max_cells)
      : lo_(lo), per_z_(periodic_z) {
    const glm::dvec3 ext = hi - lo;
    for (;;) {
      for (int a = 0; a < 3; ++a) n_[a] = std::max(1, static_cast<int>(std::floor(ext[a] / cell)));
      if (static_cast<double>(n_.x) * n_.y * n_.z <= static_cast<double>(max_cells)) break;
      cell *= 1.25;
    }
    for (int a = 0; a < 3; ++a) h_[a] = ext[a] / n_[a];
    head_.assign(static_cast<size_t>(n_.x) * n_.y * n_.z, -1);
  }

  void insert(uint32_t p, glm::dvec3 c, double r) {
    for_cells(c, r, [&](size_t cell) {
      nodes_.push_back({p, head_[cell]});
      head_[cell] = static_cast<int32_t>(nodes_.size() - 1);
    });
  }

  // Calls f(p) for every particle registered in a cell the box [c - r, c + r] touches (a particle may come
  // more than once); stops early when f returns false. Returns false if stopped.
  template <class F>
  bool query(glm::dvec3 c, double r, F&& f) const {
    bool go = true;
    for_cells(c, r, [&](size_t cell) {
      for (int32_t k = go ? head_[cell] : -1; k >= 0; k = nodes_[static_cast<size_t>(k)].second)
        if (!f(nodes_[static_cast<size_t>(k)].first)) {
          go = false;
          break;
        }
    });
    return go;
  }

 private:
  template <class F>
  void for_cells(glm::dvec3 c, double r, F&& f) const {
    int a0[3], a1[3];
    for (int a = 0; a < 3; ++a) {
      a0[a] = static_cast<int>(std::floor((c[a] - r - lo_[a]) / h_[a]));
      a1[a] = static_cast<int>(std::floor((c[a] + r - lo_[a]) / h_[a]));
      if (a == 2 && per_z_) {
        if (a1[a] - a0[a] + 1 >= n_[a]) {  // the box covers the whole period: every z cell once
          a0[a] = 0;
          a1[a] = n_[a] - 1;
        }
      } else {
        a0[a] = std::clamp(a0[a], 0, n_[a] - 1);
        a1[a] = std::clamp(a1[a], 0, n_[a] - 1);
      }
    }
    for (int iz = a0[2]; iz <= a1[2]; ++iz) {
      const int z = ((iz % n_.z) + n_.z) % n_.z;
      for (int iy = a0[1]; iy <= a1[1]; ++iy)
        for (int ix = a0[0]; ix <= a1[0]; ++ix)
          f((static_cast<size_t>(z) * n_.y + static_cast<size_t>(iy)) * n_.x + static_cast<size_t>(ix));
    }
  }

  glm::dvec3 lo_, h_{1.0};
  glm::ivec3 n_{1};
  bool per_z_ = false;
  std::vector<int32_t> head_;
  std::vector<std::pair<uint32_t, int32_t>> nodes_;
};

// Minimum-image separation.
glm::dvec3 separation(glm::dvec3 a, glm::dvec3 b, double length, bool periodic_z) {
  glm::dvec3 d = a - b;
  if (periodic_z) d.z -= length * std::nearbyint(d.z / length);
  return d;
}

double median_radius(std::vector<double> r) {
  const size_t m = r.size() / 2;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(m), r.end());
  return r[m];
}

// Area of the disc of radius R below the line y = h (h ∈ [-R, R]): π R² minus the cap above it,
// cap = R² acos(h/R) - h sqrt(R² - h²).
double disc_area_below(double R, double h) {
  h = std::clamp(h, -R, R);
  return kPi * R * R - (R * R * std::acos(h / R) - h * std::sqrt(R * R - h * h));
}

// Height whose region below holds `volume` in a drum of radius R and length L (bisection; R when it is more
// than the drum).
double height_for_volume(double R, double L, double volume) {
  if (volume >= kPi * R * R * L) return R;
  double lo = -R, hi = R;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (disc_area_below(R, mid) * L < volume ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

double drum_volume(double radius, double length) {
  return kPi * radius * radius * length;
}

size_t particles_for_fill(const Psd& psd, double drum_radius, double drum_length, double bed_fraction,
                          double solid_fraction) {
  return static_cast<size_t>(std::llround(bed_fraction * drum_volume(drum_radius, drum_length) *
                                          solid_fraction / psd.mean_volume()));
}

double fill_for_particles(const Psd& psd, double drum_radius, double drum_length, size_t count,
                          double solid_fraction) {
  return static_cast<double>(count) * psd.mean_volume() /
         (drum_volume(drum_radius, drum_length) * solid_fraction);
}

FillResult fill_drum(const FillSpec& spec, const std::vector<double>& radii) {
  const double R = spec.drum_radius, L = spec.drum_length, gap = spec.wall_gap;
  if (!(R > 0.0) || !(L > 0.0)) throw std::invalid_argument("fill: drum radius and length must be > 0");
  if (!(spec.loose_fraction > 0.0 && spec.loose_fraction <= 0.45))
    throw std::invalid_argument("fill: loose_fraction must be in (0, 0.45] (random addition jams near 0.38)");
  if (gap < 0.0) throw std::invalid_argument("fill: wall_gap must be ≥ 0");
  if (spec.max_attempts == 0) throw std::invalid_argument("fill: max_attempts must be > 0");
  const size_t n = radii.size();
  FillResult res;
  res.radius = radii;
  res.x.assign(n, glm::dvec3(0.0));
  if (n == 0) return res;
  if (n > 0x7fffffffu) throw std::invalid_argument("fill: too many particles");
  double r_max = 0.0;
  for (double r : radii) {
    if (!(r > 0.0) || !std::isfinite(r)) throw std::invalid_argument("fill: radii must be > 0");
    r_max = std::max(r_max, r);
    res.solid_volume += 4.0 / 3.0 * kPi * r * r * r;
  }
  if (r_max + gap >= R)
    throw std::invalid_argument(fmt::format("fill: particle radius {} does not fit the drum", r_max));
  if (!spec.periodic_z && 2.0 * (r_max + gap) > L)
    throw std::invalid_argument(fmt::format("fill: particle diameter {} exceeds the drum length", 2 * r_max));
  if (spec.periodic_z && 2.0 * r_max + gap >= 0.5 * L)
    throw std::invalid_argument("fill: periodic length must exceed twice the largest interaction distance");

  // Largest first; ties by index so the order (and thus the result) is fully determined.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return radii[a] > radii[b]; });

  Grid grid(glm::dvec3(-R, -R, -0.5 * L), glm::dvec3(R, R, 0.5 * L), 2.0 * median_radius(radii) + gap,
            spec.periodic_z, 16 * n + 4096);
  std::mt19937_64 rng(splitmix64(spec.seed ^ 0x66696c6c2d706f73ull));  // "fill-pos"

  double region_volume = spec.lower_part ? res.solid_volume / spec.loose_fraction : drum_volume(R, L);
  double y_top = height_for_volume(R, L, region_volume);

  for (uint32_t p : order) {
    const double r = radii[p];
    const double Rp = R - r - gap;  // centre must stay within this radius
    const double z_lo = spec.periodic_z ? -0.5 * L : -0.5 * L + r + gap;
    const double z_hi = spec.periodic_z ? 0.5 * L : 0.5 * L - r - gap;
    for (;;) {
      const double y_hi = std::min(y_top, Rp);
      bool placed = false;
      if (y_hi > -Rp) {
        for (uint32_t attempt = 0; attempt < spec.max_attempts && !placed; ++attempt) {
          glm::dvec3 c;
          do {  // uniform in the disc section below y_hi (rejection from its bounding rectangle)
            c.x = -Rp + 2.0 * Rp * uniform01(rng);
            c.y = -Rp + (y_hi + Rp) * uniform01(rng);
          } while (c.x * c.x + c.y * c.y > Rp * Rp);
          c.z = z_lo + (z_hi - z_lo) * uniform01(rng);
          const bool free = grid.query(c, r + gap, [&](uint32_t q) {
            const glm::dvec3 d = separation(c, res.x[q], L, spec.periodic_z);
            const double s = r + radii[q] + gap;
            return glm::dot(d, d) >= s * s;
          });
          if (free) {
            res.x[p] = c;
            grid.insert(p, c, r);
            placed = true;
          }
        }
      }
      if (placed) break;
      if (y_top >= R)
        throw std::runtime_error(
            fmt::format("fill: the drum is too full for random addition ({} particles, solid volume {:.3g} "
                        "of the drum's {:.3g})",
                        n, res.solid_volume, drum_volume(R, L)));
      region_volume *= 1.05;
      y_top = height_for_volume(R, L, region_volume);
      ++res.region_growths;
    }
  }
  res.y_top = y_top;
  return res;
}

FillResult fill_drum(const FillSpec& spec, const Psd& psd) {
  std::mt19937_64 rng(splitmix64(spec.seed ^ 0x66696c6c2d73697aull));  // "fill-siz"
  std::vector<double> radii;
  const bool stratified = psd.spec().sampling == PsdSampling::kStratified;
  if (spec.count > 0) {
    if (stratified) {
      radii = psd.sample_stratified(spec.count, rng);
      for (double& r : radii) r *= 0.5;
    } else {
      radii.resize(spec.count);
      for (double& r : radii) r = 0.5 * psd.sample(rng);
    }
  } else {
    if (!(spec.bed_fraction > 0.0 && spec.bed_fraction <= 1.0) ||
        !(spec.solid_fraction > 0.0 && spec.solid_fraction < 1.0))
      throw std::invalid_argument("fill: bed_fraction must be in (0, 1] and solid_fraction in (0, 1)");
    // Draw until the solid volume reaches the target: the last particle crosses it.
    const double target =
        spec.bed_fraction * drum_volume(spec.drum_radius, spec.drum_length) * spec.solid_fraction;
    double vol = 0.0;
    if (stratified) {
      // As many stratified draws as the target holds at the model's mean particle volume (their volume is
      // then within about one particle of n V̄), then independent draws until the target is crossed.
      radii = psd.sample_stratified(static_cast<size_t>(std::floor(target / psd.mean_volume())), rng);
      for (double& r : radii) r *= 0.5, vol += 4.0 / 3.0 * kPi * r * r * r;
    }
    while (vol < target) {
      const double r = 0.5 * psd.sample(rng);
      radii.push_back(r);
      vol += 4.0 / 3.0 * kPi * r * r * r;
    }
  }
  return fill_drum(spec, radii);
}

double max_pair_overlap(const std::vector<glm::dvec3>& x, const std::vector<double>& radius,
                        double drum_length, bool periodic_z) {
  const size_t n = x.size();
  if (radius.size() != n) throw std::invalid_argument("max_pair_overlap: sizes differ");
  if (n < 2) return -INFINITY;
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (size_t i = 0; i < n; ++i) {
    lo = glm::min(lo, x[i] - radius[i]);
    hi = glm::max(hi, x[i] + radius[i]);
  }
  std::vector<glm::dvec3> xw = x;
  if (periodic_z) {
    for (glm::dvec3& c : xw) c.z -= drum_length * std::floor(c.z / drum_length + 0.5);  // into [-L/2, L/2)
    lo.z = -0.5 * drum_length;
    hi.z = 0.5 * drum_length;
  }
  Grid grid(lo, hi, 2.0 * median_radius(radius), periodic_z, 16 * n + 4096);
  double worst = -INFINITY;
  for (size_t i = 0; i < n; ++i) {
    grid.query(xw[i], radius[i], [&](uint32_t q) {
      const glm::dvec3 d = separation(xw[i], xw[q], drum_length, periodic_z);
      worst = std::max(worst, radius[i] + radius[q] - glm::length(d));
      return true;
    });
    grid.insert(static_cast<uint32_t>(i), xw[i], radius[i]);
  }
  return worst;
}

double max_wall_overlap(const std::vector<glm::dvec3>& x, const std::vector<double>& radius,
                        double drum_radius, double drum_length, bool periodic_z) {
  if (radius.size() != x.size()) throw std::invalid_argument("max_wall_overlap: sizes differ");
  double worst = -INFINITY;
  for (size_t i = 0; i < x.size(); ++i) {
    worst = std::max(worst, std::hypot(x[i].x, x[i].y) + radius[i] - drum_radius);
    if (!periodic_z) worst = std::max(worst, std::fabs(x[i].z) + radius[i] - 0.5 * drum_length);
  }
  return worst;
}

}  // namespace wetdem
