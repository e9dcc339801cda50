// Case files: unit parsing, validation (every bad input rejected naming its key), --set overrides, the
// resolved echo, and the shipped assets.
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/case/case.h"
#include "app/case/units.h"
#include "app/run/run.h"
#include "support/numbers.h"

namespace wetdem::app {
namespace {

namespace fs = std::filesystem;

// A complete, valid case (PP2-like, small): every test starts from it.
const char* kValid = R"(
name = "t"
scaling = 5
[material]
E = "1325 MPa"
G = "400 MPa"
restitution = 0.5
density = "900 kg/m3"
[friction]
mu_s = 0.8
mu_r = 0.3
[walls.cylinder]
mu_s = 0.5
[psd]
basis = "volume"
d10 = "506.0 um"
d25 = "712.7 um"
d50 = "904.6 um"
d75 = "1123 um"
d90 = "1345 um"
[liquid]
gamma = "21.7 mN/m"
theta = "30 deg"
content = "5 %"
v_min = "10 %"
v_max = "1 %"
[drum]
diameter = "140 mm"
length = "180 mm"
rpm = 5
fill = 0.36
[run]
settle = "0.5 s"
duration = "3 s"
steady_state_start = "1 s"
sample_interval = "0.05 s"
[output]
formats = ["vtk"]
)";

TEST(Units, ParsesSuffixedStrings) {
  EXPECT_DOUBLE_EQ(parse_quantity("140 mm", Dim::Length), 0.14);
  EXPECT_DOUBLE_EQ(parse_quantity("506.0um", Dim::Length), 506.0e-6);
  EXPECT_DOUBLE_EQ(parse_quantity("506 µm", Dim::Length), 506.0e-6);
  EXPECT_DOUBLE_EQ(parse_quantity("21.7 mN/m", Dim::SurfaceTension), 0.0217);
  EXPECT_DOUBLE_EQ(parse_quantity("30 deg", Dim::Angle), kPi / 6.0);
  EXPECT_DOUBLE_EQ(parse_quantity("1325 MPa", Dim::Pressure), 1.325e9);
  EXPECT_DOUBLE_EQ(parse_quantity("1.5e-2 GPa", Dim::Pressure), 1.5e7);
  EXPECT_DOUBLE_EQ(parse_quantity("5 rpm", Dim::AngularRate), 5.0 * 2.0 * kPi / 60.0);
  EXPECT_DOUBLE_EQ(parse_quantity("900 kg/m^3", Dim::Density), 900.0);
  EXPECT_DOUBLE_EQ(parse_quantity("0.9 g/cm3", Dim::Density), 900.0);
  EXPECT_DOUBLE_EQ(parse_quantity("5 %", Dim::Fraction), 0.05);
  EXPECT_DOUBLE_EQ(parse_quantity("0.05", Dim::Fraction), 0.05);
  EXPECT_DOUBLE_EQ(parse_quantity("250 ms", Dim::Time), 0.25);
}

TEST(Units, RejectsMissingWrongAndUnknownUnits) {
  EXPECT_THROW(parse_quantity("140", Dim::Length), std::invalid_argument);     // no unit
  EXPECT_THROW(parse_quantity("140 kg", Dim::Length), std::invalid_argument);  // wrong dimension
  EXPECT_THROW(parse_quantity("21.7 mN", Dim::SurfaceTension), std::invalid_argument);
  EXPECT_THROW(parse_quantity("mm", Dim::Length), std::invalid_argument);  // no number
  EXPECT_THROW(parse_quantity("5 %", Dim::Dimensionless), std::invalid_argument);
}

TEST(Case, ValidCaseResolvesToSi) {
  const Case c = parse_case_string(kValid);
  EXPECT_DOUBLE_EQ(c.drum.diameter, 0.14);
  EXPECT_DOUBLE_EQ(c.drum.omega, 5.0 * 2.0 * kPi / 60.0);
  EXPECT_DOUBLE_EQ(c.liquid.theta, kPi / 6.0);
  EXPECT_DOUBLE_EQ(c.liquid.gamma, 0.0217);
  EXPECT_DOUBLE_EQ(c.liquid.v_min, 0.10);
  EXPECT_DOUBLE_EQ(c.material.nu, 1325.0 / 800.0 - 1.0);
  EXPECT_DOUBLE_EQ(c.material.E_star, 1.325e9 / (2.0 * (1.0 - c.material.nu * c.material.nu)));
  EXPECT_DOUBLE_EQ(c.material.stiffness_reduction, 1000.0);
  EXPECT_DOUBLE_EQ(c.cylinder.mu_s, 0.5);  // override
  EXPECT_DOUBLE_EQ(c.cylinder.mu_r, 0.3);  // default: the particle value
  EXPECT_DOUBLE_EQ(c.plates.mu_s, 0.8);
  EXPECT_EQ(c.psd.table.size(), 5u);
  EXPECT_DOUBLE_EQ(c.psd.scale, 5.0);
  EXPECT_EQ(c.psd.tails, PsdTails::kTruncate);
  EXPECT_EQ(c.liquid.films, FilmMode::PerParticleVolume);
  EXPECT_FALSE(c.notes.empty());  // nu = 0.656 outside [-1, 0.5] is noted
  EXPECT_NE(c.notes.front().find("nu = 0.6562"), std::string::npos) << c.notes.front();
}

TEST(Case, KeysWithUnitsEqualSuffixedStrings) {
  const Case a = parse_case_string(kValid);
  const Case b =
      parse_case_string(kValid, {"drum.diameter_mm=140", "liquid.theta_deg=30", "liquid.gamma_N_per_m=0.0217",
                                 "material.E_MPa=1325", "drum.rotation_rpm=5", "liquid.v_max_pct=1"});
  EXPECT_EQ(case_to_json(a), case_to_json(b));
}

// Every malformed input: (overrides, expected key, expected words in the message).
struct Bad {
  std::vector<std::string> set;
  std::string key, words;
};

void PrintTo(const Bad& b, std::ostream* os) {
  *os << ::testing::PrintToString(b.set);
}

class Malformed : public ::testing::TestWithParam<Bad> {};

TEST_P(Malformed, RejectedNamingTheKey) {
  const Bad& b = GetParam();
  try {
    parse_case_string(kValid, b.set);
    FAIL() << "accepted: " << ::testing::PrintToString(b.set);
  } catch (const CaseError& e) {
    EXPECT_EQ(e.key(), b.key) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(b.key + ": ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(b.words), std::string::npos) << e.what();
  }
}

// The run driver rejects the same inputs before it creates the run folder or opens a device.
TEST_P(Malformed, RunWritesNothing) {
  const fs::path tmp = fs::temp_directory_path() / ("wetdem_malformed_" + std::to_string(::getpid()));
  const fs::path out = tmp / "run";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::ofstream(tmp / "case.toml") << kValid;
  RunOptions o;
  o.case_path = (tmp / "case.toml").string();
  o.overrides = GetParam().set;
  o.out_dir = out.string();
  o.quiet = true;
  try {
    run_case(o);
    FAIL() << "accepted";
  } catch (const CaseError& e) {
    EXPECT_EQ(e.key(), GetParam().key) << e.what();
  }
  EXPECT_FALSE(fs::exists(out)) << out;
  fs::remove_all(tmp);
}

INSTANTIATE_TEST_SUITE_P(
    Case, Malformed,
    ::testing::Values(
        Bad{{"drum.fill=1.3"}, "drum.fill", "must be in (0, 1], got 1.3"},
        Bad{{"drum.fill=0"}, "drum.fill", "(0, 1]"},
        Bad{{"drum.fill=\"lots\""}, "drum.fill", "expected a number"},
        Bad{{"drum.diameter=\"-140 mm\""}, "drum.diameter", "must be > 0"},
        Bad{{"drum.diameter=0.14"}, "drum.diameter", "no unit"},
        Bad{{"drum.diamter_m=0.14"}, "drum.diamter_m", "unknown key"},
        Bad{{"drum.rpm=-5"}, "drum.rpm", "must be >= 0"},
        Bad{{"drum.periodic_slice=1"}, "drum.periodic_slice", "true or false"},
        Bad{{"drum.periodic_slice=true"}, "drum.slice_thickness", "required"},
        Bad{{"drum.end_plates=\"open\""}, "drum.end_plates", "must be one of"},
        Bad{{"psd.d90=\"400 um\""}, "psd.d90", "must be larger than psd.d75"},
        Bad{{"psd.d25=\"1000 um\""}, "psd.d50", "must be larger than psd.d25"},
        Bad{{"psd.d10=\"-5 um\""}, "psd.d10", "must be > 0"},
        Bad{{"psd.basis=\"mass\""}, "psd.basis", "must be one of"},
        Bad{{"psd.tails=\"gaussian\""}, "psd.tails", "must be one of"},
        Bad{{"psd.sampling=\"sobol\""}, "psd.sampling", "must be one of"},
        Bad{{"psd.lognormal.sigma=0.3"}, "psd.d10", "not both"},
        Bad{{"liquid.theta=\"90 deg\""}, "liquid.theta", "[0, 90) deg"},
        Bad{{"liquid.theta_deg=120"}, "liquid.theta_deg", "[0, 90) deg"},
        Bad{{"liquid.gamma=\"21.7 mN\""}, "liquid.gamma", "unknown unit"},
        Bad{{"liquid.v_min=-0.1"}, "liquid.v_min", "must be >= 0"},
        Bad{{"liquid.v_max=0"}, "liquid.v_max", "must be > 0"},
        Bad{{"liquid.d_c=1.5"}, "liquid.d_c", "[0, 1]"},
        Bad{{"liquid.content=\"150 %\""}, "liquid.content", "[0, 1]"},
        Bad{{"liquid.films=\"thick\""}, "liquid.films", "per_particle_volume"},
        Bad{{"material.restitution=0"}, "material.restitution", "(0, 1]"},
        Bad{{"material.restitution=1.5"}, "material.restitution", "(0, 1]"},
        Bad{{"material.nu=0.3"}, "material.nu", "one modulus too many"},
        Bad{{"material.G=\"300 MPa\""}, "material.G", "nu = 1.208"},
        Bad{{"material.density=\"-900 kg/m3\""}, "material.density", "must be > 0"},
        Bad{{"material.stiffness_reduction=0.5"}, "material.stiffness_reduction", ">= 1"},
        Bad{{"friction.mu_s=-0.1"}, "friction.mu_s", "must be >= 0"},
        Bad{{"walls.cylinder.mu_r=-1"}, "walls.cylinder.mu_r", "must be >= 0"},
        Bad{{"walls.lid.mu_s=0.1"}, "walls.lid", "unknown key"}, Bad{{"scaling=0"}, "scaling", "must be > 0"},
        Bad{{"scaling=60"}, "scaling", "does not fit the drum"},
        Bad{{"run.duration=\"1 s\""}, "run.steady_state_start", "must be < run.duration"},
        Bad{{"run.sample_interval=0"}, "run.sample_interval", "must be > 0"},
        Bad{{"run.settle=\"-1 s\""}, "run.settle", "must be >= 0"},
        Bad{{"run.seed=-3"}, "run.seed", "must be >= 0"},
        Bad{{"run.seed=1.5"}, "run.seed", "must be an integer"},
        Bad{{"run.dt=\"0 s\""}, "run.dt", "must be > 0"},
        Bad{{"run.perturb=\"-1 nm\""}, "run.perturb", "must be >= 0"},
        Bad{{"run.perturb=\"0.1 mm\""}, "run.perturb", "must be <= 1 um"},
        Bad{{"run.perturb_seed=-1"}, "run.perturb_seed", "must be >= 0"},
        Bad{{"output.formats=[\"obj\"]"}, "output.formats", "\"gltf\" or \"vtk\""},
        Bad{{"output.checkpoint_interval=-1"}, "output.checkpoint_interval", "must be >= 0"},
        Bad{{"foo=1"}, "foo", "unknown key"}, Bad{{"drum=5"}, "drum", "must be a table"},
        Bad{{"drum.periodic_slice=true", "drum.slice_thickness=\"5 mm\""},
            "drum.slice_thickness",
            "twice the largest"},
        Bad{{"drum.periodic_slice=true", "drum.slice_thickness=\"20 mm\"", "drum.end_plates=\"fixed\""},
            "drum.end_plates",
            "no end plates"},
        Bad{{"drum.periodic_slice=true", "drum.slice_thickness=\"20 mm\"", "walls.plates.mu_s=0.1"},
            "walls.plates",
            "no end plates"},
        Bad{{"material.E_star=\"500 MPa\""}, "material.E_star", "one modulus too many"},
        Bad{{"liquid.v_max_pct=0"}, "liquid.v_max_pct", "must be > 0"}));

TEST(Case, GivenTwiceIsRejected) {
  std::string text = kValid;
  text.replace(text.find("diameter = "), 0, "diameter_m = 0.14\n");
  try {
    parse_case_string(text);
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
  }
}

TEST(Case, MissingTableAndSyntaxErrors) {
  std::string text = kValid;
  const size_t at = text.find("[drum]");
  text = text.substr(0, at) + text.substr(text.find("[run]"));
  try {
    parse_case_string(text);
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_EQ(e.key(), "drum");
  }
  try {
    parse_case_string("[drum\ndiameter = 1", {}, "bad.toml");
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.toml:1:", 0), 0u) << e.what();
  }
  EXPECT_THROW(parse_case_file("/nonexistent/case.toml"), CaseError);
}

TEST(Case, SetOverridesReplaceOtherSpellingsAndTakePlainStrings) {
  const Case c = parse_case_string(
      kValid, {"drum.diameter_m=0.2", "drum.rpm=10", "liquid.films=mean_volume", "run.seed=42",
               "output.formats=[\"gltf\", \"vtk\"]", "drum.length=200mm", "liquid.v_min_pct=2.5"});
  EXPECT_DOUBLE_EQ(c.drum.diameter, 0.2);
  EXPECT_DOUBLE_EQ(c.drum.omega, 10.0 * 2.0 * kPi / 60.0);
  EXPECT_EQ(c.liquid.films, FilmMode::MeanVolume);
  EXPECT_EQ(c.run.seed, 42u);
  EXPECT_EQ(c.output.formats.size(), 2u);
  EXPECT_DOUBLE_EQ(c.drum.length, 0.2);
  EXPECT_DOUBLE_EQ(c.liquid.v_min, 0.025);
  EXPECT_THROW(parse_case_string(kValid, {"no_equals_sign"}), CaseError);
  // --set can create a table that the file does not have.
  const Case p = parse_case_string(kValid, {"walls.plates.mu_s=0.1"});
  EXPECT_DOUBLE_EQ(p.plates.mu_s, 0.1);
  EXPECT_DOUBLE_EQ(p.plates.mu_r, 0.3);
}

TEST(Case, EchoParsesBackToTheSameCase) {
  const std::vector<std::vector<std::string>> variants = {
      {},
      {"psd.tails=lognormal", "liquid.films=mean_volume", "run.dt=\"20 us\""},
      {"psd.sampling=stratified"},
      {"drum.periodic_slice=true", "drum.slice_thickness=\"20 mm\"", "run.skin=\"0.1 mm\""},
      {"run.perturb=\"1 nm\"", "run.perturb_seed=11"}};
  for (size_t i = 0; i < variants.size(); ++i) {
    const Case a = parse_case_string(kValid, variants[i]);
    const Case b = parse_case_string(case_to_toml(a), {}, "echo");
    EXPECT_EQ(case_to_json(a), case_to_json(b)) << case_to_toml(a);
    EXPECT_EQ(b.psd.sampling, a.psd.sampling);
  }
  // The default sampling is not echoed: a case without the key resolves (and hashes) as before it existed.
  EXPECT_EQ(case_to_toml(parse_case_string(kValid)).find("sampling"), std::string::npos);
  EXPECT_NE(
      case_to_toml(parse_case_string(kValid, {"psd.sampling=stratified"})).find("sampling = 'stratified'"),
      std::string::npos);
  // E*, G* given directly: nu = (4 - r)/(2 - r) with r = E*/G* = 5 -> nu = 1/3.
  std::string text = kValid;
  text.replace(text.find("E = \"1325 MPa\""), 14, "E_star = \"500 MPa\"");
  text.replace(text.find("G = \"400 MPa\""), 13, "G_star = \"100 MPa\"");
  const Case s = parse_case_string(text);
  EXPECT_NEAR(s.material.nu, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(s.material.E / (2.0 * (1.0 - s.material.nu * s.material.nu)), 5e8, 1e-3);
  EXPECT_EQ(case_to_json(s), case_to_json(parse_case_string(case_to_toml(s))));
}

// run.perturb moves every start by at most p along each axis (uniform, seeded): the same seed the same
// starts, another seed other starts, radii and films untouched (the checkpoint's radii hash still matches).
TEST(Case, PerturbMovesTheStartsWithinTheBoundReproducibly) {
  const std::string path = std::string(WETDEM_SOURCE_DIR) + "/tests/cases/closed_slice_wet.toml";
  const Prepared base = prepare_run(parse_case_file(path));
  const double p = 1e-9;
  const Prepared a = prepare_run(parse_case_file(path, {"run.perturb=\"1 nm\"", "run.perturb_seed=11"}));
  const Prepared b = prepare_run(parse_case_file(path, {"run.perturb=\"1 nm\"", "run.perturb_seed=11"}));
  const Prepared c = prepare_run(parse_case_file(path, {"run.perturb=\"1 nm\"", "run.perturb_seed=12"}));
  ASSERT_EQ(a.state.p.size(), base.state.p.size());
  double largest = 0;
  for (size_t k = 0; k < a.state.p.size(); ++k) {
    const glm::dvec3 d = a.state.p.x[k] - base.state.p.x[k];
    for (int i = 0; i < 3; ++i) {
      EXPECT_LE(std::fabs(d[i]), p * (1 + 1e-6)) << "particle " << k;
      largest = std::max(largest, std::fabs(d[i]));
    }
    EXPECT_EQ(a.state.p.x[k], b.state.p.x[k]) << "same seed, same starts";
  }
  EXPECT_GT(largest, 0.9 * p) << "uniform in [-p, p]: the largest of ~5,500 draws is near p";
  EXPECT_NE(a.state.p.x, c.state.p.x) << "another seed, other starts";
  EXPECT_EQ(a.state.p.radius, base.state.p.radius);
  EXPECT_EQ(a.state.p.film, base.state.p.film);
  EXPECT_EQ(a.radii_hash, base.radii_hash);
}

}  // namespace
}  // namespace wetdem::app

#endif  // WETDEM_HAVE_APP
