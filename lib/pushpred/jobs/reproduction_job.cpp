#include "pushpred/jobs/reproduction_job.hpp"

#include <algorithm>
#include <ostream>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred {
namespace {

SynchronisedPush load_case(int n, const ReproductionOptions& o, const StagedOutput& out, std::ostream& log) {
  const std::string name = "cases/case" + std::to_string(n) + ".h5";
  if (!o.case_files.empty()) {
    SynchronisedPush p = load_push(o.case_files.at(static_cast<size_t>(n - 1)));
    log << "case " << n << ": " << p.source << "\n";
    return p;
  }
  const PushScenario scenario = paper_case_scenario(n);
  const SimulatedPush sim = simulate_push(scenario);
  write_recording_hdf5(sim.recording, out.path(name));
  SynchronisedPush p = load_push(out.path(name), scenario.shape);
  p.source = name;
  // The file is named caseN.h5, not like a dataset file, so its name carries no push parameters: they are the
  // scenario's (as the dataset's file name would give them: speed -0.001 m/s marks an acceleration push).
  p.push = scenario.push_parameters();
  log << "case " << n << ": simulated " << scenario.name << " (" << p.duration_s() << " s)\n";
  return p;
}

/// The study options of the reproduction: the user's, with the paper's two methods (its proposed `dob` and its
/// `simple` baseline, which Table II and figures 7-9 compare) always run, before the methods chosen
/// (StudyOptions::methods, default every built-in one).
StudyOptions paper_study_options(const ReproductionOptions& o) {
  StudyOptions study_options = o.study;
  if (study_options.methods.empty()) study_options.methods = prediction_method_names();
  for (const char* paper_method : {"simple", "dob"})
    if (std::find(study_options.methods.begin(), study_options.methods.end(), paper_method) ==
        study_options.methods.end())
      study_options.methods.insert(study_options.methods.begin(), paper_method);
  return study_options;
}

/// The prediction study of each of the six cases, on abs's friction coefficient unless the options give one.
std::vector<PushStudy> study_cases(const std::vector<SynchronisedPush>& pushes, const StudyOptions& study_options) {
  std::vector<PushStudy> cases;
  for (int n = 1; n <= 6; ++n) {
    StudyOptions so = study_options;
    if (so.friction_coefficient < 0) so.friction_coefficient = surface_friction_coefficient("abs");
    cases.push_back(run_prediction_study(pushes[n - 1], so));
    cases.back().source = pushes[n - 1].source;
  }
  return cases;
}

/// The disturbance estimate of each case by the study's observer, and the least-squares line over all their
/// samples (figure 5).
void estimate_disturbances(PaperReproduction& r) {
  Eigen::Index rows = 0;
  for (const SynchronisedPush& p : r.case_pushes) {
    r.case_disturbances.push_back(make_disturbance_estimator(r.study.observer)->estimate(p));
    rows += r.case_disturbances.back().u.rows();
  }
  Eigen::MatrixX3d U(rows, 3), D(rows, 3);
  Eigen::Index row = 0;
  for (const DisturbanceEstimate& e : r.case_disturbances) {
    U.middleRows(row, e.u.rows()) = e.u;
    D.middleRows(row, e.d_hat.rows()) = e.d_hat;
    row += e.u.rows();
  }
  r.all_cases_relation = least_squares_relation(U, D);
}

/// The same study over every real ABS push of `data_folder`, and the recording of the push figures 10 and 11 show.
void study_real_pushes(PaperReproduction& r, const std::filesystem::path& data_folder, std::ostream& log) {
  const auto files = list_recordings(data_folder, "abs");
  log << "real data: " << files.size() << " ABS pushes from " << data_folder.string() << "\n";
  r.real_studied = true;
  r.real_files = files.size();
  r.real = run_batch(files,
                     [&](const std::filesystem::path& path) { return run_prediction_study(load_push(path), r.study); });
  if (const TypicalRealPush typical = typical_real_push(r.real); typical.study)
    r.typical_real_push = load_push(typical.study->source);
}

}  // namespace

PaperReproduction run_paper_reproduction(const ReproductionOptions& o, const StagedOutput& out, std::ostream& log) {
  if (!o.case_files.empty() && o.case_files.size() != 6)
    throw InputError("reproduce: give six rect2 recordings for cases 1-6, or none to simulate them");
  PaperReproduction r;
  r.simulated_cases = o.case_files.empty();
  for (int n = 1; n <= 6; ++n) r.case_pushes.push_back(load_case(n, o, out, log));
  r.study = paper_study_options(o);
  r.cases = study_cases(r.case_pushes, r.study);
  r.case1_observation = observe_push(r.case_pushes[0]);
  estimate_disturbances(r);
  for (const auto& ph : r.cases[0].phases)
    r.case1_plans.push_back(
        plan_from_measurement(r.case_pushes[0], ph.interval.t0_s, ph.interval.t1_s, r.study.plan_rate_hz));
  if (!o.data_folder.empty()) study_real_pushes(r, o.data_folder, log);
  return r;
}

ReproductionResult reproduce_paper(const ReproductionOptions& options, const StagedOutput& out, std::ostream& log) {
  ReproductionResult result;
  result.reproduction = run_paper_reproduction(options, out, log);
  result.plot_notes = write_reproduction_report(result.reproduction, out);
  return result;
}

}  // namespace pushpred
