#pragma once
// The schedule and method options every study-running subcommand shares (predict, compare, reproduce, diagnose):
// one place for their flags, defaults, checks and help text.
#include <CLI/CLI.hpp>
#include <string>

#include "pushpred/prediction/prediction_study.hpp"

namespace pushpred::app {

struct StudyArguments {
  int intervals = 4;
  std::string span = "whole";
  double plan_rate_hz = 10.0;
  std::string observer = "dob";
  std::string estimator = "rls";
  std::string observer_run = "per-interval";
  std::string observer_start = "steady";
  std::string observer_output = "interval-mean";
  double mu = -1.0;  ///< < 0: from the surface table
  std::string methods;  ///< comma-separated prediction method names; empty: the built-ins (a subcommand may preset it)
  std::string methods_note;  ///< what a subcommand adds to the --methods help (e.g. the methods it always runs)

  /// Which of the optional flags a subcommand offers.
  struct Flags {
    int min_intervals = 2;
    bool observer = true, estimator = true, mu = true;
    bool methods = false;  ///< --methods (the prediction methods to run, by name)
  };
  void add_to(CLI::App& sub, Flags flags);
  void add_to(CLI::App& sub) { add_to(sub, Flags{}); }
  /// The options, with estimator and method names checked, so a bad name fails before any file is read.
  StudyOptions options() const;
};

}  // namespace pushpred::app
