#include "colormap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "app/observe/clusters.h"

namespace wetdem {

ParticleFrame frame_from_state(const SystemState& s, const std::vector<double>& liquid_m3) {
  if (!liquid_m3.empty() && liquid_m3.size() != s.p.size())
    throw std::invalid_argument("frame_from_state: liquid_m3 must be empty or one per particle");
  ParticleFrame f;
  f.time = s.time;
  f.step = s.step;
  f.x = s.p.x;
  f.v = s.p.v;
  f.radius = s.p.radius;
  f.liquid_m3 = liquid_m3;
  f.id.resize(s.p.size());
  for (size_t i = 0; i < f.id.size(); ++i) f.id[i] = static_cast<uint32_t>(i);  // state is in stable-id order
  observe::Clusters c = observe::bridge_clusters(s);
  f.cluster = std::move(c.id);
  f.cluster_size = std::move(c.size);
  return f;
}

double srgb_to_linear(double c) {
  // IEC 61966-2-1 transfer function, inverted.
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

glm::dvec3 liquid_color_srgb(double value, double vmax) {
  // ColorBrewer "Blues" 9-class end points and quartiles, sRGB 0..255.
  static const double stops[5][3] = {
      {255, 255, 255}, {198, 219, 239}, {107, 174, 214}, {33, 113, 181}, {8, 48, 107}};
  double t = (vmax > 0.0 && value > 0.0) ? value / vmax : 0.0;  // NaN and negatives: dry
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double s = t - i;
  glm::dvec3 c;
  for (int k = 0; k < 3; ++k) c[k] = ((1.0 - s) * stops[i][k] + s * stops[i + 1][k]) / 255.0;
  return c;
}

glm::dvec3 liquid_color_linear(double value, double vmax) {
  const glm::dvec3 c = liquid_color_srgb(value, vmax);
  return {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
}

}  // namespace wetdem
