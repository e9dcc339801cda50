#include "app/observe/surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "app/drum/aor.h"

namespace wetdem::observe {

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

struct Frame {
  glm::dvec2 t, n;
  explicit Frame(double a) : t(std::cos(a), std::sin(a)), n(-std::sin(a), std::cos(a)) {}
  double u(const glm::dvec3& x) const { return x.x * t.x + x.y * t.y; }
  double h(const glm::dvec3& x) const { return x.x * n.x + x.y * n.y; }
};

struct Columns {
  std::vector<double> u, h;                 // fitted surface points
  std::vector<std::vector<size_t>> layers;  // their surface layers
};

// Surface points of the columns in the central part of the chord, in frame f (header).
Columns surface_points(const SystemState& s, const Frame& f, double w, size_t n_mono, double central) {
  const size_t n = s.p.size();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t k = 0; k < n; ++k) {
    const double u = f.u(s.p.x[k]);
    lo = std::min(lo, u - s.p.radius[k]);
    hi = std::max(hi, u + s.p.radius[k]);
  }
  Columns c;
  if (!(hi > lo)) return c;
  const size_t ncol = std::max<size_t>(1, static_cast<size_t>(std::ceil((hi - lo) / w)));
  const double mid = 0.5 * (lo + hi), half = 0.5 * central * (hi - lo);
  std::vector<std::vector<std::pair<double, size_t>>> col(ncol);
  for (size_t k = 0; k < n; ++k) {
    const size_t j = std::min(ncol - 1, static_cast<size_t>((f.u(s.p.x[k]) - lo) / w));
    const double uc = lo + (static_cast<double>(j) + 0.5) * w;
    if (std::fabs(uc - mid) <= half) col[j].push_back({f.h(s.p.x[k]), k});
  }
  for (size_t j = 0; j < ncol; ++j) {
    auto& v = col[j];
    if (v.empty()) continue;
    const size_t m = std::min(n_mono, v.size());
    // The m highest, in descending h (ties by index: deterministic).
    std::partial_sort(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end(),
                      [](const auto& a, const auto& b) {
                        return a.first > b.first || (a.first == b.first && a.second < b.second);
                      });
    const double med = m % 2 ? v[m / 2].first : 0.5 * (v[m / 2 - 1].first + v[m / 2].first);
    c.u.push_back(lo + (static_cast<double>(j) + 0.5) * w);
    c.h.push_back(med);
    std::vector<size_t> layer(m);
    for (size_t i = 0; i < m; ++i) layer[i] = v[i].second;
    c.layers.push_back(std::move(layer));
  }
  return c;
}

struct Line {
  double a = 0, b = 0, se_b = 0;
};

// Ordinary least squares h = a + b u and the standard error of b, s_e / sqrt(Σ (u - ū)²).
Line ols(const std::vector<double>& u, const std::vector<double>& h) {
  const double n = static_cast<double>(u.size());
  double mu = 0, mh = 0;
  for (size_t i = 0; i < u.size(); ++i) mu += u[i], mh += h[i];
  mu /= n, mh /= n;
  double suu = 0, suh = 0;
  for (size_t i = 0; i < u.size(); ++i) suu += (u[i] - mu) * (u[i] - mu), suh += (u[i] - mu) * (h[i] - mh);
  Line l;
  l.b = suu > 0 ? suh / suu : 0.0;
  l.a = mh - l.b * mu;
  double sse = 0;
  for (size_t i = 0; i < u.size(); ++i) sse += std::pow(h[i] - l.a - l.b * u[i], 2);
  l.se_b = (u.size() > 2 && suu > 0) ? std::sqrt(sse / (n - 2.0) / suu) : 0.0;
  return l;
}

}  // namespace

SurfaceResult fit_surface(const SystemState& s, double drum_radius, double bed_length,
                          const SurfaceOptions& opt) {
  SurfaceResult r;
  const size_t n = s.p.size();
  if (n == 0) return r;
  double dsum = 0;
  for (double rad : s.p.radius) dsum += 2.0 * rad;
  const double d = dsum / static_cast<double>(n);
  r.mean_diameter_m = d;
  const AorSample com = dynamic_aor(s, drum_radius, opt.flag_fraction);
  r.com_angle_deg = com.signed_deg;
  if (com.flagged || !(d > 0)) return r;

  const double w = opt.column_width * d;
  const size_t n_mono = std::max<size_t>(1, static_cast<size_t>(std::llround(w * bed_length / (d * d))));
  double angle = com.signed_deg / kDeg;
  Columns c;
  Line line;
  for (int pass = 0; pass < 2; ++pass) {
    c = surface_points(s, Frame(angle), w, n_mono, opt.central_fraction);
    if (c.u.size() < 3) return r;
    line = ols(c.u, c.h);
    angle += std::atan(line.b);
  }
  r.valid = true;
  r.angle_deg = angle * kDeg;
  r.angle_se_deg = line.se_b / (1.0 + line.b * line.b) * kDeg;  // d atan(b) = db / (1 + b²)
  r.columns = c.u.size();
  // The last pass's line h = a + b u, expressed in the frame α: distance from the axis a / sqrt(1 + b²).
  r.height_m = line.a / std::sqrt(1.0 + line.b * line.b);
  for (const auto& l : c.layers) r.layer.insert(r.layer.end(), l.begin(), l.end());

  const Frame fa(angle);
  const double sgn = angle >= 0 ? 1.0 : -1.0;
  auto downhill = [&](size_t k) { return -sgn * (s.p.v[k].x * fa.t.x + s.p.v[k].y * fa.t.y); };
  double vs = 0;
  for (size_t k : r.layer) vs += downhill(k);
  r.downhill_speed_mps = vs / static_cast<double>(r.layer.size());

  // Velocity profile along the normal through the axis (header).
  const double bin = opt.depth_bin * d;
  std::vector<double> vsum, dsum_b;
  std::vector<size_t> cnt;
  for (size_t k = 0; k < n; ++k) {
    if (std::fabs(fa.u(s.p.x[k])) >= 0.5 * w) continue;
    const double depth = r.height_m - fa.h(s.p.x[k]);
    const size_t b = depth < bin ? 0 : static_cast<size_t>(depth / bin);
    if (b >= cnt.size()) vsum.resize(b + 1, 0.0), dsum_b.resize(b + 1, 0.0), cnt.resize(b + 1, 0);
    vsum[b] += downhill(k);
    dsum_b[b] += depth;
    ++cnt[b];
  }
  r.flowing_layer_depth_m = std::nan("");
  bool have_prev = false;
  double pv = 0, pd = 0;
  for (size_t b = 0; b < cnt.size(); ++b) {
    if (cnt[b] == 0) continue;
    const double v = vsum[b] / static_cast<double>(cnt[b]), dep = dsum_b[b] / static_cast<double>(cnt[b]);
    if (v <= 0) {
      r.flowing_layer_depth_m = have_prev ? std::max(0.0, pd + pv * (dep - pd) / (pv - v)) : 0.0;
      break;
    }
    have_prev = true, pv = v, pd = dep;
  }
  return r;
}

}  // namespace wetdem::observe
