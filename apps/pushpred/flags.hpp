#pragma once
// The flags several subcommands share, declared once each: the same name, check and (unless a subcommand says what
// is special about it there) help text everywhere.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/simulation/scenario.hpp"

namespace pushpred::app {

/// A number check that says plainly what is wrong ("--plan-rate: must be a positive finite number, got 'inf'") and
/// refuses nan and inf, which CLI11's PositiveNumber lets through or answers with its range written out in 300 digits.
inline CLI::Validator finite_number_above(double lowest, bool inclusive, const std::string& what) {
  return CLI::Validator(
      [lowest, inclusive, what](std::string& text) -> std::string {
        double value = 0;
        const bool ok = CLI::detail::lexical_cast(text, value) && std::isfinite(value) &&
                        (inclusive ? value >= lowest : value > lowest);
        return ok ? std::string() : "must be " + what + ", got '" + text + "'";
      },
      inclusive ? "NONNEGATIVE" : "POSITIVE");
}
inline const CLI::Validator kPositiveNumber = finite_number_above(0, false, "a positive finite number");
/// A rate [Hz] above 0 and at most `highest` ("--rate: must be a positive finite number up to 2500, got '1e9'").
inline CLI::Validator rate_up_to(double highest) {
  return CLI::Validator(
      [highest](std::string& text) -> std::string {
        double value = 0;
        const bool ok = CLI::detail::lexical_cast(text, value) && std::isfinite(value) && value > 0 && value <= highest;
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", highest);
        return ok ? std::string()
                  : "must be a positive finite number up to " + std::string(limit) + ", got '" + text + "'";
      },
      "POSITIVE");
}
/// A number above 0 and at most `highest` ("--zeta: must be a positive finite number up to 10, got '1e300'").
inline CLI::Validator positive_number_up_to(double highest) { return rate_up_to(highest); }
/// The highest grid rate [Hz]: the fastest a recording's stream may run (PlausibilityLimits::max_rate_hz); a finer
/// grid only interpolates, and `--rate 1e9` would ask for billions of samples.
inline const double kMaxGridRate_Hz = PlausibilityLimits{}.max_rate_hz;
inline const CLI::Validator kNonNegativeNumber = finite_number_above(0, true, "a finite number >= 0");
/// A number within [lowest, highest] ("--direction: must be a finite number in [-360, 360], got '1e300'").
inline CLI::Validator finite_number_in(double lowest, double highest) {
  char range[80];
  std::snprintf(range, sizeof range, "a finite number in [%g, %g]", lowest, highest);
  const std::string what = range;
  return CLI::Validator(
      [lowest, highest, what](std::string& text) -> std::string {
        double value = 0;
        const bool ok =
            CLI::detail::lexical_cast(text, value) && std::isfinite(value) && value >= lowest && value <= highest;
        return ok ? std::string() : "must be " + what + ", got '" + text + "'";
      },
      lowest == 0 ? "NONNEGATIVE" : "NUMBER");
}
/// A whole number within [lowest, highest] ("--side: must be a whole number from 0 to 1000, got 'nan'"), where CLI11
/// alone says "Could not convert".
inline CLI::Validator whole_number_in(long long lowest, long long highest) {
  const std::string what = "a whole number from " + std::to_string(lowest) + " to " + std::to_string(highest);
  return CLI::Validator(
      [lowest, highest, what](std::string& text) -> std::string {
        long long value = 0;
        const bool ok = CLI::detail::lexical_cast(text, value) && value >= lowest && value <= highest;
        return ok ? std::string() : "must be " + what + ", got '" + text + "'";
      },
      "INT");
}
/// A random seed: a whole number from 0 to 2^64 - 1 (parse_seed); CLI11 alone let "-1" wrap around to 2^64 - 1 and
/// an overlong one saturate.
inline const CLI::Validator kSeed(
    [](std::string& text) -> std::string {
      try {
        parse_seed(text);
        return {};
      } catch (const std::exception& e) {
        return e.what();
      }
    },
    "UINT");

/// The recordings a batch subcommand reads (required): files, or folders of them.
inline CLI::Option* add_recordings(CLI::App& sub, std::vector<std::string>& files,
                                   const std::string& help = "Recordings (.h5 or .json), or folders of them") {
  return sub.add_option("files", files, help)->required()->default_str("");  // no "=[]" in --help
}

/// `--out DIR` (required); `help` says what is written there.
inline CLI::Option* add_out_folder(CLI::App& sub, std::string& out, const std::string& help = "Output folder") {
  return sub.add_option("--out", out, help)->required();
}

/// `--shapes FILE`: a user's own objects (CSV or JSON, docs/own-objects.md), added to the dataset's shapes and
/// replacing those of the same name. run_selected reads the file before the subcommand runs, so that a bad one stops
/// the run with exit 2 before any input is read.
inline CLI::Option* add_shapes(CLI::App& sub) {
  return sub
      .add_option("--shapes",
                  "Own objects: a shape file (CSV or JSON, docs/own-objects.md) whose shapes add to "
                  "and override the dataset's")
      ->type_name("FILE");
}

/// `--shape NAME`, for files whose name does not carry the shape, with `--shapes FILE` for own objects.
inline CLI::Option* add_shape(CLI::App& sub, std::string& shape) {
  add_shapes(sub);
  return sub.add_option("--shape", shape,
                        "Object shape, for files whose name does not carry it: the dataset's or one of --shapes");
}

/// `--rate HZ` (positive): the rate the streams are resampled to.
inline CLI::Option* add_rate(CLI::App& sub, double& rate_hz) {
  return sub.add_option("--rate", rate_hz, "Resampling rate [Hz], at most 2500")->check(rate_up_to(kMaxGridRate_Hz));
}

/// `--jobs N` (positive); `help` says what runs in parallel. More jobs than cores only add threads that wait for
/// each other (2000 threads ran 26 times slower than 2 on a 2-core machine): N above the core count is capped to it,
/// and the program says so once, on stderr.
inline CLI::Option* add_jobs(CLI::App& sub, int& jobs, const std::string& help) {
  return sub
      .add_option_function<int>(
          "--jobs",
          [&jobs](int requested) {
            const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
            jobs = std::min(requested, cores);
            if (requested > cores)
              std::cerr << "note: --jobs " << requested << " is more than the " << cores << " cores; " << cores
                        << " jobs run\n";
          },
          help)
      ->check(kPositiveNumber);
}

/// `--floor-margin K` (>= 0): how many standard errors an effect's amount must exceed its floor by to be found.
inline CLI::Option* add_floor_margin(CLI::App& sub, double& margin_std) {
  return sub
      .add_option("--floor-margin", margin_std,
                  "Standard errors by which an effect's amount must exceed its floor to be found (default 1; 0: the "
                  "estimate alone)")
      ->check(kNonNegativeNumber);
}

/// `--sensor-zero-spread N`: the rig's known push-to-push spread of the force sensor's zero
/// (DiagnosisOptions::sensor_zero_spread_N).
inline CLI::Option* add_sensor_zero_spread(CLI::App& sub, double& spread_N) {
  return sub
      .add_option("--sensor-zero-spread", spread_N,
                  "The rig's push-to-push spread of the force sensor's zero, sd per axis in N (default 0.1, the "
                  "MCube rig's as `pushpred inspect` measures it; 0: the pushes' own spread alone; at most 20): a "
                  "bias the pushes' rests share is judged against it")
      ->check(kNonNegativeNumber)
      ->check(finite_number_in(0, kMaxForceOffset_N));
}

/// `--measured-contact-compliance`: the base model's rod gives way as the fit pushes' contact does
/// (DiagnosisOptions::measured_contact_compliance).
inline CLI::Option* add_measured_contact_compliance(CLI::App& sub, bool& on) {
  return sub.add_flag("--measured-contact-compliance", on,
                      "The base model's pushing model sinks its rod by the fit pushes' measured contact compliance "
                      "times the normal force (default: a rigid rod)");
}

/// `--shard I/N` where a subcommand can split its work; `help` says what is shared out. The spec is parsed when the
/// subcommand runs (parse_shard_spec), so that a bad one is refused like the subcommand's other input errors.
inline CLI::Option* add_shard(CLI::App& sub, std::string& spec, const std::string& help) {
  return sub.add_option("--shard", spec, help)->type_name("I/N");
}

}  // namespace pushpred::app
