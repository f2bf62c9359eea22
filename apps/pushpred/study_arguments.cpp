#include "study_arguments.hpp"

#include "flags.hpp"
#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/prediction/predictor.hpp"
#include "pushpred/reading/physical_bounds.hpp"

namespace pushpred::app {

void StudyArguments::add_to(CLI::App& sub, Flags flags) {
  sub.add_option("--intervals", intervals, "Number of equal intervals (identify on the first)")
      ->check(CLI::Range(flags.min_intervals, 100));
  sub.add_option("--span", span, "Split the whole recording or only the contact span")
      ->check(CLI::IsMember({"whole", "contact"}));
  sub.add_option("--plan-rate", plan_rate_hz, "Planned-force sampling rate [Hz], at most the grid's (--rate)")
      ->check(rate_up_to(kMaxGridRate_Hz));
  if (flags.observer) {
    sub.add_option("--observer", observer, "Disturbance estimator: dob or pid")->capture_default_str();
    sub.add_option("--observer-run", observer_run,
                   "One observer run per identification interval, or one over the whole schedule "
                   "(docs/reproduction.md)")
        ->check(CLI::IsMember({"per-interval", "continuous"}))
        ->capture_default_str();
    sub.add_option("--observer-start", observer_start, "The dob observer's initial state: steady or rest")
        ->check(CLI::IsMember({"steady", "rest"}))
        ->capture_default_str();
    sub.add_option("--observer-output", observer_output,
                   "What the dob observer reports per sample: interval-mean or point")
        ->check(CLI::IsMember({"interval-mean", "point"}))
        ->capture_default_str();
  }
  if (flags.estimator) {
    std::string names;
    for (const auto& n : relation_estimator_names()) names += (names.empty() ? "" : ", ") + n;
    sub.add_option("--estimator", estimator, "Relation estimator: " + names);
  }
  if (flags.methods) {
    std::string names;
    for (const auto& n : predictor_names()) names += (names.empty() ? "" : ", ") + n;
    // A subcommand whose tables are about some methods only (compare) presets `methods` before calling add_to.
    sub.add_option("--methods", methods,
                   "Prediction methods, comma-separated (default: " + (methods.empty() ? "all built-in" : methods) +
                       ")" + methods_note + ": " + names);
  }
  if (flags.mu)
    sub.add_option("--mu", mu,
                   "Friction coefficient of the paper's simple baseline, 0 to 10 (default: from the surface)")
        ->check(finite_number_in(0, kMaxFrictionCoefficient))
        ->default_str("");  // its stored default (-1) only means "from the surface"
}

StudyOptions StudyArguments::options() const {
  StudyOptions o;
  o.schedule.intervals = intervals;
  o.schedule.span = parse_schedule_span(span);
  o.plan_rate_hz = plan_rate_hz;
  o.observer = observer;
  o.observer_run = parse_observer_run(observer_run);
  o.observer_options.start = parse_observer_start(observer_start);
  o.observer_options.output = parse_observer_output(observer_output);
  o.estimator = estimator;
  o.friction_coefficient = mu;
  o.methods = parse_predictor_list(methods);
  make_disturbance_estimator(o.observer);
  make_relation_estimator(o.estimator);
  return o;
}

}  // namespace pushpred::app
