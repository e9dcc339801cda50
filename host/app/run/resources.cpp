#include "app/run/resources.h"

#include <fmt/format.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "app/drum/psd.h"
#include "vk/context.h"
#include "wetdem/params.h"

namespace wetdem::app {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kUsable = 0.9;  // refuse above 90 % of what is available

}  // namespace

std::string bytes_text(double b) {
  const char* unit[] = {"B", "KB", "MB", "GB", "TB", "PB"};
  int k = 0;
  while (b >= 1000.0 && k < 5) b /= 1000.0, ++k;
  return fmt::format("{:.3g} {}", b, unit[k]);
}

void check_reach(const Case& c) {
  if (!c.drum.periodic_slice) return;
  const Psd psd(c.psd);
  const double vbar = psd.mean_volume();
  const double theta = std::max(c.liquid.theta, c.liquid.theta_receding.value_or(c.liquid.theta));
  const double s_cmax = c.liquid.on() ? rupture_distance(theta, c.liquid.v_max * vbar) : 0.0;
  const double skin = c.run.skin ? *c.run.skin : 0.3 * 0.5 * psd.d_min();
  const double reach = psd.d_max() + s_cmax + skin;
  if (!(reach < 0.5 * c.drum.slice_thickness))
    throw CaseError(
        "drum.slice_thickness",
        fmt::format("must exceed twice the neighbour reach, 2 (2 r_max + S_c,max + skin) = 2 x "
                    "{:.4g} m = {:.4g} m (largest particle of the PSD, bridge of V_max), got {:.4g} m "
                    "(a thicker slice, a PSD cut lower or a smaller V_max)",
                    reach, 2.0 * reach, c.drum.slice_thickness));
}

ResourceEstimate estimate_resources(const Case& c) {
  ResourceEstimate e;
  const Psd psd(c.psd);
  const double v_drum = kPi * 0.25 * c.drum.diameter * c.drum.diameter * c.drum.sim_length();
  const double vbar = psd.mean_volume();
  e.particles = c.drum.fill * v_drum * c.drum.bed_solid_fraction / vbar;
  // Neighbour entries: centres within 2 r̄ + S_c,max + skin (physics.md §4 interaction range).
  const double r_bar = std::cbrt(3.0 * vbar / (4.0 * kPi));
  const double s_cmax = c.liquid.on() ? (1.0 + 0.5 * c.liquid.theta) * std::cbrt(c.liquid.v_max * vbar) : 0.0;
  const double skin = c.run.skin ? *c.run.skin : 0.3 * 0.5 * psd.d_min();
  const double reach = (2.0 * r_bar + s_cmax + skin) / r_bar;
  e.entries_in_list = c.drum.bed_solid_fraction * reach * reach * reach;
  // Allocated: the initial capacity (16 per particle), or 1.5 × the need once a rebuild overflows it.
  e.entries_per_particle = std::max(kInitialEntriesPerParticle, 1.5 * e.entries_in_list);
  e.device_bytes = e.particles * (device_bytes_per_particle(c.drum.periodic_slice) +
                                  e.entries_per_particle * kDeviceBytesPerEntry);
  e.host_bytes = e.particles * kHostBytesPerParticle;
  e.r_min = 0.5 * psd.d_min();
  e.t_rayleigh = rayleigh_time(e.r_min, c.material.density, c.material.G / c.material.stiffness_reduction,
                               c.material.nu);
  e.dt = c.run.dt ? *c.run.dt : c.run.dt_rayleigh_fraction * e.t_rayleigh;
  e.dt_reason = c.run.dt ? "run.dt" : fmt::format("{} x Rayleigh time of r_min", c.run.dt_rayleigh_fraction);
  // The lubrication damper lowers a default dt to its stability limit (make_sim_params).
  if (const double lim = case_viscous_dt_limit(c, e.r_min, vbar); !c.run.dt && lim > 0 && e.dt >= lim)
    e.dt = lim, e.dt_reason = "viscous limit 2 m*/(4 c) of the lubrication damping";
  e.steps = std::round((c.run.settle + c.run.duration) / e.dt);
  e.particle_steps = e.particles * e.steps;
  // n ∝ fill × D² × L / l³: the particle size factor is the strongest lever; name the drum key instead when
  // the drum, not the particles, is what makes n large (a drum much longer or wider than the paper's 140 ×
  // 280 mm).
  e.driver_key = "scaling";
  if (c.drum.sim_length() > 1.0)
    e.driver_key = c.drum.periodic_slice ? "drum.slice_thickness" : "drum.length";
  if (c.drum.diameter > 1.0) e.driver_key = "drum.diameter";
  return e;
}

std::optional<double> host_available_bytes() {
  std::ifstream f("/proc/meminfo");
  std::string line;
  while (std::getline(f, line)) {
    std::istringstream is(line);
    std::string key;
    double kb = 0;
    if (is >> key >> kb && key == "MemAvailable:") return kb * 1024.0;
  }
  return std::nullopt;
}

double device_heap_bytes(const vk::Context& ctx) {
  VkPhysicalDeviceMemoryProperties mp{};
  vkGetPhysicalDeviceMemoryProperties(ctx.physical(), &mp);
  double best = 0;
  for (uint32_t h = 0; h < mp.memoryHeapCount; ++h)
    if (mp.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      best = std::max(best, double(mp.memoryHeaps[h].size));
  return best;
}

void check_resources(const ResourceEstimate& e, const Available& a) {
  auto refuse = [&](const std::string& what, double need, double have) {
    throw CaseError(
        e.driver_key,
        fmt::format("the case needs about {:.3g} particles ({:.3g} neighbour entries each): {} of {} memory, "
                    "but {} is available ({:.0f} % usable); a larger scaling (fewer, larger particles) or a "
                    "smaller drum.fill / drum length reduces it",
                    e.particles, e.entries_per_particle, bytes_text(need), what, bytes_text(have),
                    kUsable * 100.0));
  };
  if (a.device_bytes && e.device_bytes > kUsable * *a.device_bytes)
    refuse("device (" + a.device + ")", e.device_bytes, *a.device_bytes);
  if (a.host_bytes && e.host_bytes > kUsable * *a.host_bytes) refuse("host", e.host_bytes, *a.host_bytes);
  // The particle index is uint32 on the device.
  if (e.particles > 4.0e9) refuse("device index range (uint32 particles)", e.particles, 4.0e9);
}

double lavapipe_throughput(double particles) {
  const double n0 = 410, r0 = 2.1e5, n1 = 1834, r1 = 6.3e5;
  const double x = std::clamp(
      (std::log(std::max(particles, 1.0)) - std::log(n0)) / (std::log(n1) - std::log(n0)), 0.0, 1.0);
  return std::exp(std::log(r0) + x * (std::log(r1) - std::log(r0)));
}

std::string describe_resources(const ResourceEstimate& e, double throughput, const std::string& source) {
  const double secs = e.particle_steps / throughput;
  std::string t = secs < 60.0      ? fmt::format("{:.3g} s", secs)
                  : secs < 3600.0  ? fmt::format("{:.3g} min", secs / 60.0)
                  : secs < 86400.0 ? fmt::format("{:.3g} h", secs / 3600.0)
                                   : fmt::format("{:.3g} days", secs / 86400.0);
  return fmt::format(
      "# resources: about {:.3g} particles, {:.3g} neighbour entries each (with regrow headroom): device "
      "memory {}, host memory {}; {:.3g} steps, {:.3g} particle-steps: {} at {:.3g} particle-steps/s ({})\n",
      e.particles, e.entries_per_particle, bytes_text(e.device_bytes), bytes_text(e.host_bytes), e.steps,
      e.particle_steps, t, throughput, source);
}

}  // namespace wetdem::app
