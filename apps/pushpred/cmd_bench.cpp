// `pushpred bench FILE|DIR...`: the whole prediction pipeline on real pushes, timed per stage (read, preprocess,
// observer, relation estimator, each prediction method, and optionally a diagnosis per push), as samples per
// second and as a multiple of a reference measured in the same run: the exact discretisation of the paper's
// observer over every push (one matrix-vector step per sample). Ratios, not seconds, are what compare across
// machines and runs (docs/performance.md); nothing here is asserted by a test.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct BenchArgs {
  std::vector<std::string> files;
  std::string shape, json;
  StudyArguments study;
  double rate_hz = 250.0;
  int repeat = 1;
  int diagnose_pushes = 0;
  bool cvode_observer = false;
  bool cvode_prediction = false;
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Stage {
  std::string name;
  double seconds = 0;
  double samples = 0;  ///< synchronised samples the stage processed
};

/// The largest differences between the two paths of the prediction model, per model: position [mm], yaw [deg].
struct PathDifference {
  double position_mm = 0, yaw_deg = 0;
};

/// One pass over every input; stage times summed over the pushes.
std::vector<Stage> one_pass(const BenchArgs& a, const std::vector<std::filesystem::path>& inputs, const StudyOptions& o,
                            std::size_t& used, std::vector<BatchFailure>& failures, double& worst_cvode_difference,
                            std::map<std::string, PathDifference>& path_differences) {
  PreprocessOptions pre;
  pre.rate_hz = a.rate_hz;
  std::map<std::string, Stage> by_name;
  const auto add = [&](const std::string& name, double seconds, double samples) {
    Stage& s = by_name[name];
    s.name = name;
    s.seconds += seconds;
    s.samples += samples;
  };
  const QFilterObserver exact_observer;
  std::vector<SynchronisedPush> studied;
  used = 0;
  failures.clear();
  for (const auto& path : inputs) {
    // A file that cannot be read or synchronised is a failure of that file, as in predict: the others are timed.
    const auto fail = [&](const std::exception& e) {
      std::string reason = e.what();
      if (reason.rfind(path.string() + ": ", 0) == 0) reason = reason.substr(path.string().size() + 2);
      failures.push_back({path.string(), plain_text(reason)});
    };
    auto start = Clock::now();
    Recording recording;
    try {
      recording = read_recording(path);
    } catch (const InputError& e) {
      fail(e);
      continue;
    }
    const double read_s = since(start);
    start = Clock::now();
    SynchronisedPush push;
    try {
      push = synchronise(recording, shape_for(recording, a.shape), pre);
    } catch (const InputError& e) {
      fail(e);
      continue;
    }
    const double preprocess_s = since(start);
    if (push.flags.frozen_force_sensor) {  // predict skips these too: not part of the pipeline's work
      failures.push_back({path.string(), "force sensor frozen: its force cannot be trusted for prediction", true});
      continue;
    }
    const auto n = static_cast<double>(push.size());
    start = Clock::now();
    const PushStudy study = run_prediction_study(push, o);
    const double study_s = since(start);
    start = Clock::now();
    const DisturbanceEstimate reference = exact_observer.estimate_exactly(push, 0, push.duration_s());
    const double reference_s = since(start);
    if (!reference.d_hat.allFinite()) throw SolverError("bench: the reference observer gave non-finite output");
    if (a.cvode_observer) {
      // The observer's CVODE path over the same whole push: its cost against the reference is the ratio itself.
      start = Clock::now();
      const DisturbanceEstimate cvode = exact_observer.estimate(push, 0, push.duration_s());
      add("observer, CVODE path (whole push)", since(start), n);
      double worst = 0;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, (cvode.d_hat.col(c) - reference.d_hat.col(c)).cwiseAbs().maxCoeff() /
                                    reference.d_hat.col(c).cwiseAbs().maxCoeff());
      worst_cvode_difference = std::max(worst_cvode_difference, worst);
    }
    if (a.cvode_prediction) {
      // The models of dob and simple on every phase, as the study builds them (dob's relation zero where it was not
      // identifiable yet), by both paths on the same plan, built outside the timing: the closed form the study uses
      // and CVODE (simple's friction regularised over coulomb_speed_scale_m_s there).
      const PredictionModel friction = simple_prediction_model(push.shape, simple_friction_coefficient(push, o));
      for (const PhaseResult& phase : study.phases) {
        const PredictionModel relation =
            relation_prediction_model(push.shape, phase.relation.beta, phase.relation.eps);
        const Eigen::Vector3d pose0 = push.pose.row(push.index_at(phase.interval.t0_s)).transpose();
        const PlannedForce plan = plan_from_measurement(push, phase.interval.t0_s, phase.interval.t1_s, o.plan_rate_hz);
        const auto phase_samples = static_cast<double>(phase.t_s.size());
        for (const auto& [name, model] : {std::pair<std::string, const PredictionModel&>{"dob model", relation},
                                          std::pair<std::string, const PredictionModel&>{"simple model", friction}}) {
          start = Clock::now();
          const Eigen::MatrixX3d closed = predict_poses_exactly(model, plan, pose0, Eigen::Vector3d::Zero(), phase.t_s);
          add(name + ", closed form", since(start), phase_samples);
          start = Clock::now();
          const Eigen::MatrixX3d cvode =
              predict_poses(model, plan, pose0, Eigen::Vector3d::Zero(), phase.t_s, o.integrator);
          add(name + ", CVODE", since(start), phase_samples);
          PathDifference& d = path_differences[name];
          for (Eigen::Index j = 0; j < phase.t_s.size(); ++j) {
            d.position_mm = std::max(d.position_mm, 1e3 * (closed.row(j).head<2>() - cvode.row(j).head<2>()).norm());
            d.yaw_deg = std::max(d.yaw_deg, std::abs(closed(j, 2) - cvode(j, 2)) * 180.0 / M_PI);
          }
        }
      }
    }

    add("read", read_s, n);
    add("preprocess", preprocess_s, n);
    add("observer", study.observer_seconds, n);
    add("estimator", study.estimator_seconds, n);
    double methods_s = 0;
    for (const auto& [method, seconds] : study.method_seconds) {
      add("method " + method, seconds, n);
      methods_s += seconds;
    }
    add("study, other", study_s - study.observer_seconds - study.estimator_seconds - methods_s, n);
    add("total", read_s + preprocess_s + study_s, n);
    add("reference", reference_s, n);
    ++used;
    if (a.diagnose_pushes > 0) studied.push_back(push);
  }
  if (a.diagnose_pushes > 0 && !studied.empty()) {
    // The first object's pushes, at most diagnose_pushes of them: a diagnosis fits one object.
    std::vector<PushGroup> groups = group_by_object(std::move(studied));
    std::vector<SynchronisedPush> pushes = std::move(groups.front().pushes);
    if (pushes.size() > static_cast<std::size_t>(a.diagnose_pushes)) pushes.resize(static_cast<std::size_t>(a.diagnose_pushes));
    double n = 0;
    for (const auto& p : pushes) n += static_cast<double>(p.size());
    DiagnosisOptions d;
    d.study = o;
    d.study.methods = {};
    const auto start = Clock::now();
    const DiagnosisResult result = diagnose(pushes, EffectLibrary::standard(), d);
    add("diagnose (" + std::to_string(pushes.size()) + " pushes of " + groups.front().name() + ")", since(start), n);
  }
  std::vector<Stage> out;
  for (auto& [name, s] : by_name) out.push_back(s);
  return out;
}

int run_bench(const BenchArgs& a) {
  if (!a.json.empty()) {  // the destination checked before any work, as an output folder is
    const std::filesystem::path json(a.json);
    const std::filesystem::path folder = json.has_parent_path() ? json.parent_path() : ".";
    std::error_code ec;
    if (std::filesystem::is_directory(json, ec)) throw InputError(about(a.json, "--json: is a folder, not a file"));
    if (!std::filesystem::is_directory(folder, ec))
      throw InputError(about(a.json, "--json: its folder does not exist"));
  }
  const StudyOptions o = a.study.options();
  const auto inputs = expand_inputs(a.files);
  std::vector<Stage> best;
  std::size_t used = 0;
  std::vector<BatchFailure> failures;
  double worst_cvode_difference = 0;
  std::map<std::string, PathDifference> path_differences;
  // The reference's own time in every pass: it moves with the machine's other work as every stage does, and each
  // ratio moves with it.
  std::vector<double> reference_passes_s;
  for (int r = 0; r < a.repeat; ++r) {
    std::vector<Stage> pass = one_pass(a, inputs, o, used, failures, worst_cvode_difference, path_differences);
    for (const auto& s : pass)
      if (s.name == "reference") reference_passes_s.push_back(s.seconds);
    if (best.empty()) {
      best = std::move(pass);
      continue;
    }
    // The fastest of the repetitions, stage by stage: the least disturbed by other work on the machine.
    for (std::size_t k = 0; k < best.size() && k < pass.size(); ++k)
      best[k].seconds = std::min(best[k].seconds, pass[k].seconds);
  }
  std::size_t skipped = 0;
  for (const auto& f : failures) skipped += f.skipped;
  if (used == 0) {
    report_failures(failures, used);
    throw InputError("bench: no push could be studied");
  }
  // Report order: the pipeline's, then the methods, then the totals.
  const auto rank = [](const std::string& name) {
    static const std::vector<std::string> order{"read", "preprocess", "observer", "estimator"};
    const auto it = std::find(order.begin(), order.end(), name);
    if (it != order.end()) return static_cast<int>(it - order.begin());
    if (name.rfind("method ", 0) == 0) return 10;
    if (name.find(" model, ") != std::string::npos) return 15;
    if (name == "study, other") return 20;
    if (name.rfind("diagnose", 0) == 0) return 30;
    if (name == "total") return 40;
    return 50;
  };
  std::stable_sort(best.begin(), best.end(), [&](const Stage& x, const Stage& y) { return rank(x.name) < rank(y.name); });
  double reference_s = 0;
  for (const auto& s : best)
    if (s.name == "reference") reference_s = s.seconds;

  std::printf("%zu pushes studied (%zu skipped), best of %d; reference: the exact discretisation of the observer "
              "over every push\n",
              used, skipped, a.repeat);
  if (!reference_passes_s.empty()) {
    const auto [fastest, slowest] = std::minmax_element(reference_passes_s.begin(), reference_passes_s.end());
    std::printf(
        "the reference itself varies between runs (on a shared 2-core machine, 6.6 to 34 ms between six "
        "runs of --repeat 1 over the ABS folder; docs/performance.md); here %.4f to %.4f s over %d pass(es): "
        "compare ratios of runs with --repeat 5 or more, which keeps each stage's fastest pass\n",
        *fastest, *slowest, a.repeat);
  }
  std::printf("%-40s %12s %14s %14s\n", "stage", "seconds", "samples/s", "x reference");
  nlohmann::json doc;
  doc["pushes"] = used;
  doc["skipped"] = skipped;
  doc["repeat"] = a.repeat;
  doc["reference"] = "exact discretisation of the observer over every push";
  doc["reference_seconds_per_pass"] = reference_passes_s;
  for (const auto& s : best) {
    const double rate = s.seconds > 0 ? s.samples / s.seconds : 0;
    const double ratio = reference_s > 0 ? s.seconds / reference_s : 0;
    std::printf("%-40s %12.4f %14.0f %14.2f\n", s.name.c_str(), s.seconds, rate, ratio);
    doc["stages"].push_back({{"stage", s.name}, {"seconds", s.seconds}, {"samples", s.samples},
                             {"samples_per_s", rate}, {"ratio_to_reference", ratio}});
  }
  if (a.cvode_observer) {
    std::printf("observer, CVODE path against the reference: largest difference %.2g of a channel's largest d_hat\n",
                worst_cvode_difference);
    doc["cvode_observer_worst_relative_difference"] = worst_cvode_difference;
  }
  for (const auto& [name, d] : path_differences) {
    std::printf("%s, CVODE against the closed form: largest difference %.2g mm, %.2g deg\n", name.c_str(),
                d.position_mm, d.yaw_deg);
    doc["cvode_prediction_largest_difference"][name] = {{"position_mm", d.position_mm}, {"yaw_deg", d.yaw_deg}};
  }
  doc["failed"] = failures.size() - skipped;
  if (!a.json.empty()) write_text_atomically(a.json, json_text(doc));
  return report_failures(failures, used);
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<BenchArgs>();
  auto* sub = app.add_subcommand(
      "bench", "Time the prediction pipeline per stage on real pushes, as ratios to a reference from the same run");
  add_recordings(*sub, a->files);
  add_shape(*sub, a->shape);
  a->study.add_to(*sub, {2, true, true, true, true});
  add_rate(*sub, a->rate_hz);
  sub->add_option("--repeat", a->repeat, "Passes over the inputs; each stage reports its fastest (default 1)")
      ->check(CLI::Range(1, 1000));
  sub->add_option("--diagnose", a->diagnose_pushes,
                  "Also diagnose up to N pushes of the first object, timed per push (default 0: no diagnosis)")
      ->check(kNonNegativeNumber);
  sub->add_option("--json", a->json, "Also write the table as JSON to this file");
  sub->add_flag("--cvode-observer", a->cvode_observer,
                "Also time the observer's CVODE path over every push, and its largest difference from the reference");
  sub->add_flag("--cvode-prediction", a->cvode_prediction,
                "Also time the dob and simple prediction models by their closed form and by CVODE on every phase, and "
                "their largest difference");
  sub->callback([a, &run] { run = [a] { return run_bench(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
