// `pushpred simulate`: a simulated push in the MCube HDF5 format, from one of the paper's cases, a scenario
// file or flags, with optional hidden physical effects. Also `--compare-real FILE...` (a clean simulation of
// each real push beside it) and `--measure-real [FILE|FOLDER...]` (the rig's clocks and noise, as used).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/jobs/real_comparison_job.hpp"
#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/reading/physical_bounds.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred::app {
namespace {

struct SimulateArgs {
  std::optional<int> paper_case;
  std::string config, out;
  std::optional<std::string> shape, surface;
  std::optional<double> mu, contact_mu, speed, acceleration, position, angle, length, gap, noise_scale, jitter_scale;
  std::optional<int> side;
  std::optional<std::string> seed;  ///< checked by parse_seed (a negative seed would wrap around)
  std::vector<std::string> effects;
  bool print_config = false, compare_real = false, measure_real = false;
  std::vector<std::string> files;
};

PushScenario scenario_from_args(const SimulateArgs& a) {
  PushScenario s;
  if (a.paper_case && !a.config.empty()) throw InputError("give either --case or --config, not both");
  if (a.paper_case) {
    try {
      s = paper_case_scenario(*a.paper_case);
    } catch (const InputError& e) {
      throw InputError(std::string("--case: ") + e.what());
    }
  } else if (!a.config.empty()) {
    s = read_scenario_file(a.config);
  }
  // A field out of range is named by the flag that set it, else by its key in the scenario file.
  ScenarioFieldNames names;
  const auto named = [&](bool given, const char* field, const char* flag) {
    if (given) names[field] = flag;
  };
  named(a.shape.has_value(), "shape", "--shape");
  named(a.surface.has_value(), "surface", "--surface");
  named(a.mu.has_value(), "surface_friction", "--mu");
  named(a.contact_mu.has_value(), "contact_friction", "--contact-mu");
  named(a.speed.has_value(), "speed_m_s", "--speed");
  named(a.acceleration.has_value(), "acceleration_m_s2", "--acceleration");
  named(a.side.has_value(), "contact_side", "--side");
  named(a.position.has_value(), "contact_position", "--position");
  named(a.angle.has_value(), "push_angle_rad", "--angle");
  named(a.length.has_value(), "push_length_m", "--length");
  named(a.gap.has_value(), "approach_gap_m", "--gap");
  named(a.noise_scale.has_value(), "sensors.noise_scale", "--noise-scale");
  named(a.jitter_scale.has_value(), "sensors.jitter_scale", "--jitter-scale");
  if (a.shape) s.shape = *a.shape;
  if (a.surface) s.surface = *a.surface;
  if (a.mu) s.surface_friction = *a.mu;
  if (a.contact_mu) s.contact_friction = *a.contact_mu;
  if (a.speed && a.acceleration) throw InputError("give either --speed or --acceleration, not both");
  if (a.speed) {
    s.motion.profile = PusherMotion::Profile::ConstantSpeed;
    s.motion.speed_m_s = *a.speed;
  }
  if (a.acceleration) {
    s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
    s.motion.acceleration_m_s2 = *a.acceleration;
  }
  if (a.side) s.contact_side = *a.side;
  if (a.position) s.contact_position = *a.position;
  if (a.angle) s.push_angle_rad = *a.angle;
  if (a.length) s.motion.length_m = *a.length;
  if (a.gap) s.approach_gap_m = *a.gap;
  if (a.seed) s.seed = parse_seed(*a.seed);
  if (a.noise_scale) s.sensors.noise_scale = *a.noise_scale;
  if (a.jitter_scale) s.sensors.jitter_scale = *a.jitter_scale;
  for (const auto& text : a.effects) {
    try {
      const auto [name, amount] = parse_effect_assignment(text);
      s.effects.set(name, amount);
    } catch (const InputError& e) {
      throw InputError(std::string("--effect: ") + e.what());
    }
  }
  s.validate(names);
  return s;
}

int run_measure(const SimulateArgs& a) {
  std::vector<std::string> inputs = a.files;
  if (inputs.empty()) inputs.push_back(resolve_data_folder().string());
  std::vector<std::string> skipped;
  RecordingStatistics stats;
  try {
    stats = measure_recordings(inputs, &skipped);
  } catch (const InputError&) {
    if (skipped.empty()) throw;  // not about the files
    stats.files = 0;             // none could be read: each is listed below
  }
  if (stats.files > 0) std::cout << stats.text();
  for (const auto& s : skipped) std::cerr << "FAILED " << plain_text(s) << "\n";
  if (skipped.empty()) return 0;
  std::cerr << skipped.size() << " of " << skipped.size() + static_cast<std::size_t>(stats.files) << " inputs failed"
            << (stats.files == 0 ? "; nothing measured" : "") << "\n";
  return stats.files == 0 ? kExitNothingDone : kExitSomeFailed;
}

int run_compare(const SimulateArgs& a) {
  if (a.files.empty()) throw InputError("--compare-real needs real recordings (files or folders)");
  const double mu = a.mu ? *a.mu : PushScenario().surface_friction;
  const double contact_mu = a.contact_mu ? *a.contact_mu : PushScenario().contact_friction;
  check_friction_coefficient(mu, "--mu", false);
  check_friction_coefficient(contact_mu, "--contact-mu", true);
  const Batch<RealComparison> batch = compare_with_real(a.files, mu, contact_mu);
  if (batch.results.empty()) return report_failures(batch.failures, 0);  // no input usable: no table, exit 2
  std::printf(
      "clean simulations (surface friction %.3f, rod friction %.3f) of the real pushes, with their parameters, "
      "pose, gap and timing\n",
      mu, contact_mu);
  std::cout << comparison_table(batch, mu);
  return report_failures(batch.failures, batch.results.size());
}

int run_simulate(const SimulateArgs& a) {
  if (a.measure_real) return run_measure(a);
  if (a.compare_real) return run_compare(a);
  if (!a.files.empty())
    throw InputError("unexpected arguments (recordings are only read with --compare-real or --measure-real)");
  const PushScenario s = scenario_from_args(a);
  if (a.print_config) std::cout << scenario_to_json(s).dump(2) << "\n";
  if (a.out.empty()) {
    if (a.print_config) return 0;
    throw InputError("--out FILE.h5 (or a folder) is required");
  }
  const std::filesystem::path path = simulated_output_path(s, a.out);
  const SimulatedPush sim = simulate_push(s);
  // A scenario far outside the physics (a force offset of 1e300 N, a start a million km away) gives a recording every
  // command would refuse: it is refused here, before it is written.
  try {
    check_plausible(sim.recording);
  } catch (const InputError& e) {
    std::string reason = e.what();
    if (reason.rfind(sim.recording.source + ": ", 0) == 0) reason = reason.substr(sim.recording.source.size() + 2);
    throw InputError("the simulated push is not one pushpred reads (" + reason + "); nothing written");
  }
  write_recording_hdf5(sim.recording, path);
  const Eigen::Index n = sim.t_s.size();
  const Eigen::Vector3d moved = sim.tracked_pose.row(n - 1) - sim.tracked_pose.row(0);
  std::printf("wrote %s\n  %s: %s on %s, %.2f s, object moved %.1f mm and turned %.1f deg\n", path.string().c_str(),
              s.name.empty() ? "push" : s.name.c_str(), s.shape.c_str(), s.surface.c_str(),
              sim.recording.ft_wrench.end_s() - sim.recording.ft_wrench.start_s(), 1e3 * moved.head<2>().norm(),
              moved(2) * 180 / M_PI);
  std::string effects;
  for (const auto& [name, amount] : s.effects.active()) effects += " " + name + "=" + std::to_string(amount);
  if (!effects.empty()) std::printf("  hidden effects (not in the file):%s\n", effects.c_str());
  return 0;
}

std::string effects_help() {
  std::string h = "Effects (--effect NAME=AMOUNT, repeatable; never written into the file):\n";
  for (const auto& e : effect_catalogue()) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-18s [%s] %s (neutral %g)\n", e.name.c_str(), e.unit.c_str(),
                  e.meaning.c_str(), e.neutral);
    h += line;
  }
  h += "Paper cases (--case N): rect2 on abs; 1-3 at 10 mm/s, 4 at 50 mm/s, 5 at 0.2 m/s^2, 6 at 2.5 m/s^2.\n"
       "Model, conventions and measured sensor noise: docs/simulator.md.";
  return h;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<SimulateArgs>();
  auto* sub = app.add_subcommand("simulate", "Simulate a push and write it as an MCube HDF5 recording");
  sub->footer(effects_help());
  sub->add_option("--case", a->paper_case, "One of the paper's cases, 1 to 6")->check(whole_number_in(1, 6));
  sub->add_option("--config", a->config, "Scenario file (JSON, see data/paper/case1.json)");
  sub->add_option("--out", a->out, "Output .h5 file, or a folder (then the dataset's file name is used)");
  sub->add_option("--shape", a->shape, "Object: the dataset's (rect1..3, tri1..3, ellip1..3, hex) or one of --shapes");
  add_shapes(*sub);
  sub->add_option("--surface", a->surface, "Surface name for the file name");
  sub->add_option("--mu", a->mu, "Surface friction coefficient, in (0, 10]");
  sub->add_option("--contact-mu", a->contact_mu, "Rod-object friction coefficient, in [0, 10]");
  sub->add_option("--speed", a->speed, "Constant push speed [m/s]");
  sub->add_option("--acceleration", a->acceleration, "Constant push acceleration from rest [m/s^2]");
  sub->add_option("--side", a->side, "Contact side index (the file names' i), from 0")
      ->check(whole_number_in(0, 999));
  sub->add_option("--position", a->position, "Contact position along the side, 0..1 (the file names' s)");
  sub->add_option("--angle", a->angle, "Push angle from the inward normal [rad] (the file names' t)");
  sub->add_option("--length", a->length, "Push length [m]");
  sub->add_option("--gap", a->gap, "Rod-to-object gap at the start [m]");
  sub->add_option("--seed", a->seed, "Random seed for clocks and noise, 0 to 2^64 - 1")
      ->type_name("UINT")
      ->check(kSeed);
  sub->add_option("--effect", a->effects, "Hidden effect NAME=AMOUNT (repeatable; list below)");
  sub->add_option("--noise-scale", a->noise_scale, "Scale on the measured sensor noise, 0 (none) to 100");
  sub->add_option("--jitter-scale", a->jitter_scale, "Scale on the measured clock jitter, 0 (ideal clocks) to 10");
  sub->add_flag("--print-config", a->print_config, "Print the resolved scenario as JSON");
  sub->add_flag("--compare-real", a->compare_real,
                "Simulate a clean copy of each real recording given and compare (with --mu, --contact-mu)");
  sub->add_flag("--measure-real", a->measure_real,
                "Measure clocks, noise and timing of real recordings (default: the data folder)");
  sub->add_option("files", a->files, "Real recordings for --compare-real / --measure-real");
  sub->callback([a, &run] { run = [a] { return run_simulate(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
