// wetdem command line:
//   wetdem run CASE.toml [--set key=value ...] [--out DIR] [--device NAME] [--resume DIR] [--quiet]
//   wetdem check CASE.toml [--set key=value ...]    validate and print the resolved case; no run
//   wetdem devices                                   list Vulkan devices
//   wetdem study plan|run|run-one|slurm|collect ...  studies (host/study/, docs/studies.md)
//   wetdem calibrate DIR [--refine K]                fit a study to its observation table
//   wetdem diagnose D.toml --out DIR                 sim-to-real diagnosis (host/diagnose/,
//   docs/diagnosis.md) wetdem twin T.toml --out DIR                     observations from a model with a
//   withheld effect wetdem                                           (no arguments) what wetdem is and the
//   tour's first command
// Every command's --help ends with a one-line example (README "A 10-minute tour").
// Exit codes: 0 done; 2 bad input (one line naming the key, nothing written); 1 the run or the device failed.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app/case/case.h"
#include "app/drum/psd.h"
#include "app/run/resources.h"
#include "app/run/run.h"
#include "app/run/stop_signals.h"
#include "vk/context.h"
#ifdef WETDEM_HAVE_STUDY
#include "study/commands.h"
#endif
#ifdef WETDEM_HAVE_DIAGNOSE
#include "diagnose/commands.h"
#include "wetdem/version.h"
#endif

namespace {

constexpr double kPi = 3.14159265358979323846;

// The tour's first command (README "A 10-minute tour"), printed by `wetdem` with no arguments.
constexpr const char* kFirstCommand = "wetdem run assets/quick_drum.toml --out runs/quick";

void print_welcome() {
  std::printf(
      "wetdem: DEM of wet granular materials in a rotating drum (Vulkan compute, GPU or lavapipe)\n"
      "\n"
      "Start here (a wet drum to a quotable angle of repose, a few minutes on a CPU):\n"
      "  %s\n"
      "\n"
      "Then: wetdem check, study, calibrate, twin, diagnose (the tour in README.md); wetdem --help lists\n"
      "every command, wetdem COMMAND --help its options and an example.\n",
      kFirstCommand);
}

int check(const std::string& path, const std::vector<std::string>& sets) {
  using namespace wetdem;
  const app::Case c = app::parse_case_file(path, sets);
  for (const std::string& n : c.notes) std::printf("# note: %s\n", n.c_str());
  // What the run will derive, estimated from the PSD model (the run uses the particles it draws).
  const Psd psd(c.psd);
  const app::ResourceEstimate e = app::estimate_resources(c);
  std::printf("# psd: %s\n", psd.describe().c_str());
  std::printf(
      "# about %.0f particles; r_min = %.4g m, Rayleigh time %.4g s, dt = %.4g s (%s), %.0f steps (%.3g "
      "particle-steps)\n",
      e.particles, e.r_min, e.t_rayleigh, e.dt, e.dt_reason.c_str(), e.steps, e.particle_steps);
  try {
    app::check_reach(c);
  } catch (const app::CaseError& err) {
    std::printf("# ERROR: a run would fail: %s\n", err.what());
  }
  {  // Issue 12: the resource estimate (host/app/run/resources.h) and whether this host could hold it.
    std::printf("%s", app::describe_resources(e, app::lavapipe_throughput(e.particles),
                                              app::kLavapipeThroughputSource)
                          .c_str());
    try {
      app::check_resources(e, {std::nullopt, "", app::host_available_bytes()});
    } catch (const app::CaseError& err) {
      std::printf("# WARNING: a run would be refused: %s\n", err.what());
    }
  }
  std::printf("%s", app::case_to_toml(c).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc <= 1) {  // no command: say what this is and how to start, not a parse error
    print_welcome();
    return 0;
  }
  CLI::App cli{"wetdem: DEM of wet granular materials in a rotating drum (Vulkan compute)"};
  cli.require_subcommand(1);
  cli.set_version_flag("--version", wetdem::code_version());
  cli.footer(std::string("Example: ") + kFirstCommand + "   (the tour: README.md)");

  wetdem::app::RunOptions ro;
  auto* run = cli.add_subcommand("run", "run a case; results in the run folder (summary.json written last)");
  run->add_option("case", ro.case_path, "case file (TOML); optional with --resume");
  run->add_option("--set", ro.overrides, "override a case key: dotted.key=value (value in TOML; repeatable)")
      ->allow_extra_args(false);  // one value per --set, so `--set a=1 case.toml` keeps the case
  run->add_option("--out", ro.out_dir, "run folder (default runs/<name>-<time>)");
  run->add_option("--device", ro.device,
                  "device: index, name substring, \"gpu\" or \"cpu\" (default $WETDEM_DEVICE)");
  run->add_option("--resume", ro.resume_dir, "continue the run in this folder from its last checkpoint");
  run->add_flag("--quiet", ro.quiet, "no progress or log on stdout (run.log is still written)");
  bool no_figures = false;
  run->add_flag("--no-figures", no_figures,
                "draw no figures (default: figures/aor.png and figures/bed.png, scripts/plot_run.py)");
  run->footer(std::string("Example: ") + kFirstCommand);
  run->add_option("--stop-after-steps", ro.stop_after_steps,
                  "stop as if killed after N steps (testing resume)")
      ->group("");

  std::string check_path;
  std::vector<std::string> check_sets;
  auto* chk =
      cli.add_subcommand("check", "validate a case and print it resolved in SI; nothing is run or written");
  chk->add_option("case", check_path, "case file (TOML)")->required();
  chk->add_option("--set", check_sets, "override a case key: dotted.key=value")
      ->allow_extra_args(false);  // one value per --set, so `--set a=1 case.toml` keeps the case
  chk->footer("Example: wetdem check assets/pp2_l5.toml --set liquid.content=10%");

  auto* dev = cli.add_subcommand("devices", "list the Vulkan devices");
  dev->footer("Example: wetdem devices   (then --device INDEX, or WETDEM_DEVICE=INDEX)");

#ifdef WETDEM_HAVE_STUDY
  // Studies and calibration: registered and run by host/study/commands.cpp.
  const auto study_cmds = wetdem::study::add_commands(cli);
#endif
#ifdef WETDEM_HAVE_DIAGNOSE
  // The sim-to-real diagnosis and twins: registered and run by host/diagnose/commands.cpp.
  const auto diagnose_cmds = wetdem::diagnose::add_commands(cli);
#endif

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }

  try {
    if (*dev) {
      for (const std::string& d : wetdem::vk::Context::list_devices()) std::printf("%s\n", d.c_str());
      return 0;
    }
    if (*chk) return check(check_path, check_sets);
#ifdef WETDEM_HAVE_STUDY
    if (study_cmds->selected()) return study_cmds->execute();
#endif
#ifdef WETDEM_HAVE_DIAGNOSE
    if (diagnose_cmds->selected()) return diagnose_cmds->execute();
#endif
    if (ro.case_path.empty() && ro.resume_dir.empty()) {
      std::fprintf(stderr, "wetdem run: give a case file (or --resume DIR)\n");
      return 2;
    }
    // Stop at the next step boundary (FAILED.txt says so, the checkpoint stays); a second Ctrl-C ends at
    // once.
    wetdem::app::install_stop_signals(wetdem::app::request_interrupt);
    ro.figures = !no_figures;
    const wetdem::app::RunResult r = wetdem::app::run_case(ro);
    return r.completed || ro.stop_after_steps ? 0 : 1;
  } catch (const wetdem::app::CaseError& e) {
    std::fprintf(stderr, "wetdem: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wetdem: error: %s\n", e.what());
    return 1;
  }
}
