#include "pushpred/reports/prediction_batch.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/batch_runner.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

constexpr const char* kCommand = "predict";

// --- Exact numbers: nlohmann writes a finite double with the digits that read back to the same bits.

nlohmann::json num(double x) { return exact_number_json(x); }
double num_from(const nlohmann::json& j) { return exact_number(j); }

template <class Vector>
nlohmann::json vec(const Vector& v) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(num(v(i)));
  return out;
}

Eigen::Vector3d vec3_from(const nlohmann::json& j) {
  if (j.size() != 3) throw InputError("a 3-vector has " + std::to_string(j.size()) + " entries");
  return {num_from(j[0]), num_from(j[1]), num_from(j[2])};
}

nlohmann::json relation_exact(const RelationParameters& p) {
  nlohmann::json cov = nlohmann::json::array();
  for (const auto& c : p.covariance) cov.push_back({num(c(0, 0)), num(c(0, 1)), num(c(1, 0)), num(c(1, 1))});
  return {{"estimator", p.estimator},         {"beta", vec(p.beta)},
          {"eps", vec(p.eps)},                {"covariance", cov},
          {"residual_std", vec(p.residual_std)}, {"samples", p.samples},
          {"effective_samples", num(p.effective_samples)}, {"intervals", p.intervals},
          {"loss_scale", vec(p.loss_scale)}};
}

RelationParameters relation_from(const nlohmann::json& j) {
  RelationParameters p;
  p.estimator = j.at("estimator").get<std::string>();
  p.beta = vec3_from(j.at("beta"));
  p.eps = vec3_from(j.at("eps"));
  const auto& cov = j.at("covariance");
  if (cov.size() != 3) throw InputError("a relation's covariance has " + std::to_string(cov.size()) + " channels");
  for (int c = 0; c < 3; ++c) {
    const auto& m = cov[static_cast<std::size_t>(c)];
    p.covariance[static_cast<std::size_t>(c)] << num_from(m.at(0)), num_from(m.at(1)), num_from(m.at(2)),
        num_from(m.at(3));
  }
  p.residual_std = vec3_from(j.at("residual_std"));
  p.samples = j.at("samples").get<long>();
  p.effective_samples = num_from(j.at("effective_samples"));
  p.intervals = j.at("intervals").get<long>();
  p.loss_scale = vec3_from(j.at("loss_scale"));
  return p;
}

nlohmann::json errors_exact(const PredictionErrors& e) {
  return {num(e.pos_mm_mean),    num(e.x_mm_mean),     num(e.x_mm_std),
          num(e.y_mm_mean),      num(e.y_mm_std),      num(e.theta_deg_mean),
          num(e.theta_deg_std),  num(e.final_pos_mm),  num(e.final_theta_deg)};
}

PredictionErrors errors_from(const nlohmann::json& j) {
  if (j.size() != 9) throw InputError("prediction errors hold " + std::to_string(j.size()) + " numbers, not 9");
  PredictionErrors e;
  double* fields[] = {&e.pos_mm_mean,    &e.x_mm_mean,     &e.x_mm_std,     &e.y_mm_mean,       &e.y_mm_std,
                      &e.theta_deg_mean, &e.theta_deg_std, &e.final_pos_mm, &e.final_theta_deg};
  for (std::size_t k = 0; k < 9; ++k) *fields[k] = num_from(j[k]);
  return e;
}

nlohmann::json interval_exact(const TimeInterval& t) { return {num(t.t0_s), num(t.t1_s)}; }
TimeInterval interval_from(const nlohmann::json& j) { return {num_from(j.at(0)), num_from(j.at(1))}; }

// --- The outputs of one whole run, from its studies (a whole run's, or the merged parts').

/// Where a push's predictions wait, by its position among the inputs, until the batch knows what it studied.
constexpr const char* kPendingFolder = "by-input";
std::string pending_predictions_file(std::size_t position) {
  return std::string(kPendingFolder) + "/" + std::to_string(position) + ".csv";
}

/// Throws InputError naming `path` when a write to `stream` (its file) failed.
void require_written(const std::ostream& stream, const fs::path& path) {
  if (!stream) throw InputError(about(path.string(), "cannot be written (is the disk full?)"));
}

/// summary.json and tables.md of a whole run, given one studied push (or failure) at a time in input order. Nothing
/// of a study is kept but its file's stem (to name its predictions): its entry of summary.json goes to a file in the
/// staging folder as it comes, and its errors into the tables' sums, so that a run holds a few hundred bytes per
/// push rather than its study (docs/performance.md, memory).
class PredictionOutputs {
 public:
  PredictionOutputs(StagedOutput& out, nlohmann::json options)
      : out_(out), options_(std::move(options)), tables_("quasi_static", {"hold", "const_velocity"}),
        entries_path_(out.path(".summary-files")) {}
  ~PredictionOutputs() {
    std::error_code ec;
    std::filesystem::remove(entries_path_, ec);
  }
  PredictionOutputs(const PredictionOutputs&) = delete;
  PredictionOutputs& operator=(const PredictionOutputs&) = delete;

  void add(const PushStudy& study) {
    if (!entries_.is_open()) {
      entries_.open(entries_path_, std::ios::binary | std::ios::trunc);
      if (!entries_) throw InputError(about(entries_path_.string(), "cannot be written"));
    }
    entries_ << summary_file_entry(study, stems_.empty());
    require_written(entries_, entries_path_);
    tables_.add(study);
    stems_.push_back(fs::path(study.source).stem().string());
  }
  void add_failure(BatchFailure failure) { failures_.push_back(std::move(failure)); }

  /// The stems of the pushes' files studied, in input order.
  const std::vector<std::string>& stems() const { return stems_; }

  /// Writes summary.json and tables.md and commits the output, unless no input gave a result (then nothing is
  /// written); the report printed to the user.
  BatchRunOutcome finish() {
    BatchRunOutcome outcome;
    outcome.failures = failures_;
    outcome.used = stems_.size();
    if (stems_.empty()) return outcome;  // nothing written
    entries_.close();
    require_written(entries_, entries_path_);
    const std::map<std::string, PredictionErrors> aggregate = tables_.aggregate();
    write_file_atomically(out_.path("summary.json"), [&](std::ostream& file) {
      write_prediction_summary(file, aggregate, failures_, options_, stems_.size(), [&](std::ostream& files) {
        std::ifstream in(entries_path_, std::ios::binary);
        if (!in || !(files << in.rdbuf()))
          throw InputError(about(entries_path_.string(), "cannot be read back"));
      });
    });
    std::filesystem::remove(entries_path_);
    write_text_atomically(out_.path("tables.md"),
                          "Mean over phases of each phase's mean position error [mm] / yaw error [deg]\n\n" +
                              tables_.grouped_errors_markdown() + "\n" + tables_.losing_phases_markdown());
    out_.commit();

    std::ostringstream report;
    report << "predicted " << stems_.size() << " pushes (" << options_.at("intervals").get<int>()
           << " intervals over the " << options_.at("span").get<std::string>() << " span); summary in "
           << out_.destination().string() << "/summary.json\n";
    for (const auto& method : options_.at("methods")) {
      const std::string name = method.get<std::string>();
      const auto e = aggregate.find(name);
      if (e == aggregate.end()) continue;
      char line[256];
      std::snprintf(line, sizeof line, "  %-15s position %6.2f mm (x %6.2f, y %6.2f)  theta %6.2f deg\n", name.c_str(),
                    e->second.pos_mm_mean, e->second.x_mm_mean, e->second.y_mm_mean, e->second.theta_deg_mean);
      report << line;
    }
    outcome.report = report.str();
    return outcome;
  }

 private:
  StagedOutput& out_;
  nlohmann::json options_;
  PredictionTables tables_;
  std::vector<BatchFailure> failures_;
  std::vector<std::string> stems_;
  fs::path entries_path_;
  std::ofstream entries_;  ///< summary.json's "files" entries, as they come
};

/// predictions/NAME.csv for each studied push, in order: its file's stem, made distinct among the studied pushes
/// (distinct_names), so that an input that failed takes no name from one that was studied, and bounded in length
/// (bounded_file_name) so that a stem near the 255-byte limit still makes a file name.
std::vector<std::string> studied_file_names(const std::vector<std::string>& stems) {
  std::vector<std::string> names;
  for (const auto& stem : distinct_names(stems)) names.push_back("predictions/" + bounded_file_name(stem) + ".csv");
  return names;
}

/// What a push leaves for the outputs once studied: its study without samples. Its predictions file is written by
/// the item under its input's position (pending_predictions_file).
struct StudiedPush {
  PushStudy study;
};

/// The outputs of a whole run from its pushes in input order, as they finish or as a merge reads them back: each
/// push's summary entry and errors as it comes, its predictions file named at the end, among the pushes studied.
class PredictionRenderer final : public BatchRenderer<StudiedPush> {
 public:
  PredictionRenderer(StagedOutput& out, nlohmann::json summary_options)
      : out_(out), outputs_(out, std::move(summary_options)) {}
  void add(std::size_t index, StudiedPush&& push) override {
    pending_.push_back(pending_predictions_file(index));
    outputs_.add(push.study);
  }
  void add_failure(std::size_t, BatchFailure&& failure) override { outputs_.add_failure(std::move(failure)); }
  BatchRunOutcome finish() override {
    const std::vector<std::string> names = studied_file_names(outputs_.stems());
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::error_code ec;
      fs::rename(out_.path(pending_[k]), out_.path(names[k]), ec);
      if (ec) throw InputError(about(names[k], "cannot be written: " + ec.message()));
    }
    std::error_code ec;
    fs::remove(out_.staging_folder() / kPendingFolder, ec);  // empty now; absent when nothing was studied
    return outputs_.finish();
  }

 private:
  StagedOutput& out_;
  PredictionOutputs outputs_;
  std::vector<std::string> pending_;
};

/// The renderer from a run's options (predict_options_json): what the summary and the printed report read of them,
/// checked before anything is written.
std::unique_ptr<BatchRenderer<StudiedPush>> prediction_renderer(StagedOutput& out, const nlohmann::json& run_options,
                                                                RenderFor) {
  const nlohmann::json& options = run_options.contains("summary") ? run_options["summary"] : run_options;
  const auto is_names = [](const nlohmann::json& list) {
    if (!list.is_array()) return false;
    for (const auto& n : list)
      if (!n.is_string()) return false;
    return true;
  };
  if (!options.is_object() || !options.contains("intervals") || !options["intervals"].is_number_integer() ||
      !options.contains("span") || !options["span"].is_string() || !options.contains("methods") ||
      !is_names(options["methods"]))
    throw InputError("its partial.json's options are not those of `predict`");
  return std::make_unique<PredictionRenderer>(out, options);
}

PartialCodec<StudiedPush> prediction_codec() {
  PartialCodec<StudiedPush> codec;
  codec.encode = [](const StudiedPush& p) { return push_study_exact_json(p.study); };
  codec.decode = [](const nlohmann::json& j) { return StudiedPush{push_study_from_exact_json(j)}; };
  codec.files = [](std::size_t index, const StudiedPush&) {
    return std::vector<std::string>{pending_predictions_file(index)};
  };
  codec.name = [](std::size_t index) { return "the result of input " + std::to_string(index + 1); };
  return codec;
}

nlohmann::json predict_options_json(const PredictRun& run) {
  // "summary": what summary.json says; "settings": the rest that changes a result, so that a merge refuses parts
  // run with other values.
  return {{"summary", prediction_options_json(run.study)},
          {"settings",
           {{"mu", num(run.study.friction_coefficient)},
            {"shape", run.shape},
            {"rate_hz", num(run.preprocess.rate_hz)}}}};
}

}  // namespace

BatchRunOutcome write_merged_predictions(const MergedParts& merged, StagedOutput& out) {
  if (merged.command != kCommand)
    throw InputError("merge: the parts are partial outputs of `" + merged.command + "`, which cannot be merged");
  return merge_batch<StudiedPush>(merged, out, prediction_codec(), prediction_renderer);
}

nlohmann::json push_study_exact_json(const PushStudy& s) {
  nlohmann::json intervals = nlohmann::json::array();
  for (const auto& t : s.intervals) intervals.push_back(interval_exact(t));
  nlohmann::json phases = nlohmann::json::array();
  for (const auto& r : s.phases) {
    nlohmann::json errors = nlohmann::json::object(), parameters = nlohmann::json::object();
    for (const auto& [name, e] : r.errors) errors[name] = errors_exact(e);
    for (const auto& [name, list] : r.method_parameters) {
      nlohmann::json l = nlohmann::json::array();
      for (const auto& q : list)
        l.push_back({{"name", q.name}, {"value", num(q.value)}, {"std", num(q.std)}, {"unit", q.unit},
                     {"source", q.source}});
      parameters[name] = l;
    }
    nlohmann::json predicted = nlohmann::json::array();
    for (const auto& [name, poses] : r.predicted) predicted.push_back(name);
    phases.push_back({{"phase", r.phase},
                      {"interval", interval_exact(r.interval)},
                      {"relation", relation_exact(r.relation)},
                      {"note", r.note},
                      {"predicted", predicted},
                      {"errors", errors},
                      {"method_notes", r.method_notes},
                      {"method_parameters", parameters},
                      {"initial_velocity", vec(r.initial_velocity)},
                      {"corrected_relation", relation_exact(r.corrected_relation)}});
  }
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& [name, t] : s.method_seconds) seconds[name] = num(t);
  return {{"source", s.source},
          {"span", s.span},
          {"methods", s.methods},
          {"intervals", intervals},
          {"phases", phases},
          {"estimator_seconds", num(s.estimator_seconds)},
          {"observer_seconds", num(s.observer_seconds)},
          {"method_seconds", seconds}};
}

PushStudy push_study_from_exact_json(const nlohmann::json& j) {
  try {
    PushStudy s;
    s.source = j.at("source").get<std::string>();
    s.span = j.at("span").get<std::string>();
    s.methods = j.at("methods").get<std::vector<std::string>>();
    for (const auto& t : j.at("intervals")) s.intervals.push_back(interval_from(t));
    for (const auto& p : j.at("phases")) {
      PhaseResult r;
      r.phase = p.at("phase").get<int>();
      r.interval = interval_from(p.at("interval"));
      r.relation = relation_from(p.at("relation"));
      r.note = p.at("note").get<std::string>();
      for (const auto& name : p.at("predicted")) r.predicted[name.get<std::string>()].resize(0, 3);
      for (const auto& [name, e] : p.at("errors").items()) r.errors[name] = errors_from(e);
      r.method_notes = p.at("method_notes").get<std::map<std::string, std::string>>();
      for (const auto& [name, list] : p.at("method_parameters").items())
        for (const auto& q : list)
          r.method_parameters[name].push_back({q.at("name").get<std::string>(), num_from(q.at("value")),
                                               num_from(q.at("std")), q.at("unit").get<std::string>(),
                                               q.at("source").get<std::string>()});
      r.initial_velocity = vec3_from(p.at("initial_velocity"));
      r.corrected_relation = relation_from(p.at("corrected_relation"));
      r.measured.resize(0, 3);
      s.phases.push_back(std::move(r));
    }
    s.estimator_seconds = num_from(j.at("estimator_seconds"));
    s.observer_seconds = num_from(j.at("observer_seconds"));
    for (const auto& [name, t] : j.at("method_seconds").items()) s.method_seconds[name] = num_from(t);
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a study written by pushpred: ") + e.what());
  }
}

BatchRunOutcome run_predict(const PredictRun& run) {
  const std::vector<fs::path> inputs = expand_inputs(run.inputs);
  const BatchSplit split{run.shard, run.mpi};
  split.refuse_shard_under_mpi("inputs");
  BatchJob<StudiedPush> job;
  job.command = job.label = kCommand;
  job.unit = "pushes";
  job.units = inputs;
  job.options = predict_options_json(run);
  job.jobs = run.jobs;
  // Each push's predictions are written under its input's position while the batch runs (threads, shards and ranks
  // finish in any order) and named at the end, once it is known which inputs were studied (studied_file_names).
  job.item = [&](std::size_t index, FileSink& files) {
    StudiedPush p{run_prediction_study(load_push(inputs[index], run.shape, run.preprocess), run.study)};
    files.write(pending_predictions_file(index), predictions_csv(p.study));
    drop_samples(p.study);  // the summary and tables need only errors and parameters
    return p;
  };
  job.codec = prediction_codec();
  job.shard_outcome = [](const ShardDone& done) {
    BatchRunOutcome outcome;
    outcome.partial = true;
    outcome.failures = done.failures;
    outcome.used = done.counted;
    outcome.report = "predicted " + std::to_string(done.counted) + " of the " + std::to_string(done.here) +
                     " pushes of shard " + done.shard.text() + " (" + std::to_string(done.all) +
                     " inputs in all); partial output in " + done.destination +
                     "; when every shard is done: pushpred merge --out DIR PART...\n";
    return outcome;
  };
  return run_batch_job<StudiedPush>(job, split, run.out, prediction_renderer);
}

}  // namespace pushpred
