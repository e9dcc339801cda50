// Phases "prepare" and "fill": everything that depends only on the input, before any file or device. A case
// that cannot be run fails here with a CaseError naming the key.
#include <fmt/format.h>

#include <filesystem>
#include <random>

#include "app/drum/fill.h"
#include "app/drum/psd.h"
#include "app/output/checkpoint.h"
#include "app/run/run.h"

namespace fs = std::filesystem;

namespace wetdem::app {

Case resolve_case(const RunOptions& opt) {
  if (opt.resume_dir.empty()) {
    if (opt.case_path.empty()) throw CaseError("", "no case file given");
    return parse_case_file(opt.case_path, opt.overrides);
  }
  const fs::path own = fs::path(opt.resume_dir) / "case.toml";
  if (!fs::exists(own))
    throw CaseError("", "--resume " + opt.resume_dir + ": no case.toml there (not a run folder)");
  Case c = parse_case_file(own.string());
  if (!opt.case_path.empty()) {
    const Case given = parse_case_file(opt.case_path, opt.overrides);
    if (case_to_json(given) != case_to_json(c))
      throw CaseError(
          "", "--resume: " + opt.case_path + " (with --set) differs from the case of " + opt.resume_dir);
  } else if (!opt.overrides.empty()) {
    throw CaseError("", "--resume continues the run's own case; --set is not allowed");
  }
  return c;
}

Prepared prepare_run(const Case& c) {
  Prepared p;
  p.c = c;
  const Psd psd(c.psd);
  p.psd_description = psd.describe();
  FillSpec fs_;
  fs_.drum_radius = 0.5 * c.drum.diameter;
  fs_.drum_length = c.drum.sim_length();
  fs_.periodic_z = c.drum.periodic_slice;
  fs_.bed_fraction = c.drum.fill;
  fs_.solid_fraction = c.drum.bed_solid_fraction;
  fs_.seed = c.run.seed;
  FillResult fill;
  try {
    fill = fill_drum(fs_, psd);
  } catch (const std::exception& e) {
    throw CaseError("drum.fill", std::string("cannot place the particles: ") + e.what());
  }
  p.prm = make_sim_params(c, fill.radius, &p.derived);
  // A periodic slice needs every interaction range below half the period (minimum image).
  if (c.drum.periodic_slice) {
    const double reach = 2.0 * p.derived.r_max + p.prm.bridge_range_pp() + p.derived.skin;
    if (!(reach < 0.5 * c.drum.slice_thickness))
      throw CaseError("drum.slice_thickness",
                      fmt::format("must exceed twice the neighbour reach, 2 (2 r_max + S_c,max + skin) = 2 x "
                                  "{:.4g} m = {:.4g} m, got {:.4g} m (a thicker slice, a PSD cut lower or a "
                                  "smaller V_max)",
                                  reach, 2.0 * reach, c.drum.slice_thickness));
  }
  const size_t n = fill.radius.size();
  SystemState& s = p.state;
  s.p.resize(n);
  for (size_t k = 0; k < n; ++k) set_sphere(s.p, k, fill.x[k], fill.radius[k], c.material.density);
  if (c.run.perturb > 0) {
    // run.perturb: every start moved by a uniform offset in [-p, p]^3, particle by particle in id order, x
    // then y then z (as the MercuryDPM driver in ../shared/peer/mercurydpm/ does).
    std::mt19937_64 rng(c.run.perturb_seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (size_t k = 0; k < n; ++k) {
      const double dx = u(rng), dy = u(rng), dz = u(rng);
      s.p.x[k] += c.run.perturb * glm::dvec3(dx, dy, dz);
    }
  }
  s.p.film = initial_films(c, fill.radius, p.prm.liquid_unit_m3);
  for (double r : fill.radius) p.diameters.push_back(2.0 * r);
  p.radii_hash = bytes_hash(fill.radius.data(), fill.radius.size() * sizeof(double));
  return p;
}

}  // namespace wetdem::app
