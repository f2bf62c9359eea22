// `pushpred fit-pid FILE... --out DIR [--per-push] [--shape NAME] [--lambda L] [--cvode]`: the PID gains of the paper's
// force reconstruction fitted by Ceres over the pushes (and per push), compared with the paper's trial-and-error
// gains; DIR/pid_gains.json, DIR/pid_fit.md and DIR/forces/<push>.csv (u and d_hat of the observer and of the PID
// with the paper's and the jointly fitted gains). The objective is stated in docs/pid_gains.md.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/calibration/pid_gain_fit.hpp"
#include "pushpred/core/batch.hpp"
#include "pushpred/reports/pid_fit_report.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred::app {
namespace {

struct FitPidArgs {
  std::vector<std::string> files;
  std::string out, shape;
  bool per_push = false, cvode = false;
  double lambda = 1.0, rate_hz = 250.0;
  int max_iterations = 50;
  int jobs = default_jobs();
};

int run_fit_pid(const FitPidArgs& a) {
  PidFitStudyOptions o;
  o.per_push = a.per_push;
  o.fit.roughness_weight = a.lambda;
  o.fit.solver.max_num_iterations = a.max_iterations;
  o.fit.exact_discretisation = !a.cvode;
  o.fit.validate();  // a bad option fails before any file is read
  PreprocessOptions pre;
  pre.rate_hz = a.rate_hz;

  // A prepared push, or why the fit cannot use it (a skip, not a failure).
  struct Prepared {
    std::optional<PidFitPush> push;
    BatchFailure skip;
  };
  const auto inputs = expand_inputs(a.files);
  BatchProgress progress("fit-pid: reading", "files", inputs.size());
  const Batch<Prepared> batch = run_batch(inputs, [&](const std::filesystem::path& path) {
    SynchronisedPush push = load_push(path, a.shape, pre);
    Prepared p;
    const std::string reason = pid_fit_unsuitable_reason(push);
    if (!reason.empty()) p.skip = {path.string(), reason};
    else p.push = make_pid_fit_push(std::move(push));
    return p;
  }, a.jobs, &progress);
  std::vector<PidFitPush> pushes;
  std::vector<BatchFailure> skipped;
  for (const auto& p : batch.results) {
    if (p.push) pushes.push_back(*p.push);
    else skipped.push_back(p.skip);
  }
  for (const auto& f : skipped) std::cerr << "SKIPPED " << f.source << ": " << f.reason << "\n";
  for (const auto& f : batch.failures) std::cerr << "FAILED " << f.source << ": " << f.reason << "\n";
  if (pushes.empty()) {
    std::cerr << "fit-pid: none of the " << batch.results.size() + batch.failures.size()
              << " input file(s) can be fitted; nothing written\n";
    return 2;
  }

  PidFitStudy study = run_pid_fit_study(pushes, o);
  study.skipped = skipped;
  study.failed.insert(study.failed.begin(), batch.failures.begin(), batch.failures.end());
  StagedOutput out(a.out);
  write_text_atomically(out.path("pid_gains.json"), json_text(pid_fit_json(study)));
  write_text_atomically(out.path("pid_fit.md"), pid_fit_markdown(study));
  // One file per fitted push, named among the fitted pushes (as predict names its predictions).
  std::vector<std::filesystem::path> sources;
  for (const PidFitPush& p : pushes) sources.emplace_back(p.push.source);
  const std::vector<std::string> stems = distinct_stems(sources);
  for (std::size_t k = 0; k < pushes.size(); ++k)
    write_text_atomically(out.path("forces/" + stems[k] + ".csv"),
                          pid_fit_forces_csv(pid_fit_forces(pushes[k], study.joint.gains, o.fit)));
  out.commit();

  const PidGains paper, &g = study.joint.gains;
  std::printf("fitted PID gains over %zu push(es), lambda %g; report in %s/pid_fit.md\n", pushes.size(), a.lambda,
              a.out.c_str());
  std::printf("  %-8s kp %8.4g  ki %8.4g  kd %8.4g  lp %8.4g  li %8.4g  ld %8.4g\n", "paper", paper.kp, paper.ki,
              paper.kd, paper.lp, paper.li, paper.ld);
  std::printf("  %-8s kp %8.4g  ki %8.4g  kd %8.4g  lp %8.4g  li %8.4g  ld %8.4g\n", "fitted", g.kp, g.ki, g.kd,
              g.lp, g.li, g.ld);
  for (const auto& f : study.failed)
    if (f.reason.rfind("per-push fit", 0) == 0) std::cerr << "FAILED " << f.source << ": " << f.reason << "\n";
  if (!study.failed.empty())
    std::cerr << study.failed.size() << " of " << pushes.size() + skipped.size() + batch.failures.size()
              << " files failed\n";
  return study.failed.empty() ? 0 : 1;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<FitPidArgs>();
  auto* sub = app.add_subcommand("fit-pid",
                                 "Fit the PID force reconstruction's gains by Ceres (tracking vs force roughness); "
                                 "write pid_gains.json and pid_fit.md");
  add_recordings(*sub, a->files);
  add_out_folder(*sub, a->out);
  sub->add_flag("--per-push", a->per_push, "Also fit one gain set per push (the joint fit is always made)");
  add_shape(*sub, a->shape);
  sub->add_option("--lambda", a->lambda, "Weight of the force-roughness term (> 0)")->check(kPositiveNumber);
  sub->add_option("--max-iterations", a->max_iterations, "Ceres iterations per problem")->check(CLI::Range(1, 1000));
  add_rate(*sub, a->rate_hz);
  add_jobs(*sub, a->jobs, "Files read in parallel (default: all cores); the output does not depend on it");
  sub->add_flag("--cvode", a->cvode,
                "Run the reconstruction by CVODE instead of its exact discretisation (a hundred times slower)");
  sub->callback([a, &run] { run = [a] { return run_fit_pid(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
