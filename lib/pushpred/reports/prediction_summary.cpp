#include "pushpred/reports/prediction_summary.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "pushpred/core/version.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

nlohmann::json errors_json(const PredictionErrors& e) {
  return {{"pos_mm_mean", e.pos_mm_mean},
          {"x_mm_mean", e.x_mm_mean},           {"x_mm_std", e.x_mm_std},
          {"y_mm_mean", e.y_mm_mean},           {"y_mm_std", e.y_mm_std},
          {"theta_deg_mean", e.theta_deg_mean}, {"theta_deg_std", e.theta_deg_std},
          {"final_pos_mm", e.final_pos_mm},     {"final_theta_deg", e.final_theta_deg}};
}

nlohmann::json relation_json(const RelationParameters& p) {
  nlohmann::json channels = nlohmann::json::object();
  for (int c = 0; c < 3; ++c)
    channels[relation_channel_name(c)] = {{"beta", p.beta(c)},
                                          {"beta_std", std::sqrt(p.covariance[c](0, 0))},
                                          {"eps", p.eps(c)},
                                          {"eps_std", std::sqrt(p.covariance[c](1, 1))},
                                          {"residual_std", p.residual_std(c)}};
  return {{"estimator", p.estimator}, {"samples", p.samples}, {"intervals", p.intervals}, {"channels", channels}};
}

nlohmann::json study_json(const PushStudy& s) {
  nlohmann::json phases = nlohmann::json::array();
  for (const auto& r : s.phases) {
    nlohmann::json methods = nlohmann::json::object();
    for (const auto& name : s.methods) methods[name] = errors_json(r.errors.at(name));
    // Moved, not copied, into place: an initializer list copies, and the summary is built once per run on one
    // thread after every push is done (keys are sorted, so the order of insertion does not change the file).
    nlohmann::json phase = {{"phase", r.phase}, {"t0_s", r.interval.t0_s}, {"t1_s", r.interval.t1_s}};
    phase["methods"] = std::move(methods);
    if (!r.method_notes.empty()) phase["method_notes"] = r.method_notes;
    for (const auto& [method, parameters] : r.method_parameters)
      for (const auto& q : parameters)
        phase["method_parameters"][method][q.name] = {
            {"value", q.value}, {"std", q.std}, {"unit", q.unit}, {"source", q.source}};
    if (r.relation.samples > 0) phase["relation"] = relation_json(r.relation);
    if (!r.note.empty()) phase["note"] = r.note;
    phases.push_back(std::move(phase));
  }
  nlohmann::json study = {{"source", s.source}, {"span", s.span}};
  study["phases"] = std::move(phases);
  return study;
}

std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<PushStudy>& studies) {
  std::vector<const PushStudy*> all;
  all.reserve(studies.size());
  for (const auto& s : studies) all.push_back(&s);
  return aggregate_errors(all);
}

namespace {

/// Adds `e` to `sum`, key by key.
void add_errors(PredictionErrors& sum, const PredictionErrors& e) {
  sum.pos_mm_mean += e.pos_mm_mean;
  sum.x_mm_mean += e.x_mm_mean;
  sum.x_mm_std += e.x_mm_std;
  sum.y_mm_mean += e.y_mm_mean;
  sum.y_mm_std += e.y_mm_std;
  sum.theta_deg_mean += e.theta_deg_mean;
  sum.theta_deg_std += e.theta_deg_std;
  sum.final_pos_mm += e.final_pos_mm;
  sum.final_theta_deg += e.final_theta_deg;
}

/// Each key of each method's sum divided by that method's phase count (a method skipped on some pushes, for want of
/// a coefficient, is averaged over the phases it predicted).
void divide_errors(std::map<std::string, PredictionErrors>& sums, const std::map<std::string, int>& counts) {
  for (auto& [name, a] : sums)
    for (double* v : {&a.pos_mm_mean, &a.x_mm_mean, &a.x_mm_std, &a.y_mm_mean, &a.y_mm_std, &a.theta_deg_mean,
                      &a.theta_deg_std, &a.final_pos_mm, &a.final_theta_deg})
      *v /= counts.at(name);
}

}  // namespace

std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<const PushStudy*>& studies) {
  std::map<std::string, PredictionErrors> sum;
  std::map<std::string, int> count;
  for (const PushStudy* s : studies)
    for (const auto& r : s->phases)
      for (const auto& [name, e] : r.errors) {
        add_errors(sum[name], e);
        ++count[name];
      }
  divide_errors(sum, count);
  return sum;
}

nlohmann::json prediction_options_json(const StudyOptions& o) {
  return {{"intervals", o.schedule.intervals},
          {"span", schedule_span_name(o.schedule.span)},
          {"plan_rate_hz", o.plan_rate_hz},
          {"observer", o.observer},
          {"observer_run", observer_run_name(o.observer_run)},
          {"observer_start", observer_start_name(o.observer_options.start)},
          {"observer_output", observer_output_name(o.observer_options.output)},
          {"methods", o.methods.empty() ? prediction_method_names() : o.methods},
          {"estimator", o.estimator}};
}

namespace {

/// The summary without its "files".
nlohmann::json summary_head(const std::map<std::string, PredictionErrors>& aggregate_errors,
                            const std::vector<BatchFailure>& batch_failures, const nlohmann::json& options) {
  nlohmann::json aggregate = nlohmann::json::object();
  for (const auto& [name, e] : aggregate_errors) aggregate[name] = errors_json(e);
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : batch_failures) {
    failures.push_back({{"source", f.source}, {"reason", f.reason}});
    if (f.skipped) failures.back()["skipped"] = true;
  }
  nlohmann::json summary = {{"pushpred_version", kVersion}, {"options", options}};
  summary["aggregate"] = std::move(aggregate);
  summary["failures"] = std::move(failures);
  return summary;
}

}  // namespace

nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const nlohmann::json& options) {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& s : batch.results) files.push_back(study_json(s));
  nlohmann::json summary = summary_head(aggregate_errors(batch.results), batch.failures, options);
  summary["files"] = std::move(files);
  return summary;
}

std::string summary_file_entry(const PushStudy& study, bool first) {
  const std::string item = study_json(study).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out = first ? "\n    " : ",\n    ";
  out.reserve(out.size() + item.size() + item.size() / 8);
  for (std::size_t from = 0; from < item.size();) {
    const std::size_t line_end = std::min(item.find('\n', from), item.size());
    out.append(item, from, line_end - from);
    if (line_end < item.size()) out += "\n    ";
    from = line_end + 1;
  }
  return out;
}

void write_prediction_summary(std::ostream& out, const std::map<std::string, PredictionErrors>& aggregate,
                              const std::vector<BatchFailure>& failures, const nlohmann::json& options,
                              std::size_t files, const std::function<void(std::ostream&)>& write_files) {
  // The files are written in their place, each indented as the whole document's dump would indent it (two levels:
  // 4 spaces). Whole, the document took about 0.1 MB per push (its tree and its text) on top of the studies.
  const JsonTextAround text = json_file_text_around(summary_head(aggregate, failures, options), "files");
  out << text.before << '[';
  write_files(out);
  out << (files == 0 ? "]" : "\n  ]") << text.after;
}

void write_prediction_summary(std::ostream& out, const Batch<PushStudy>& batch, const nlohmann::json& options) {
  write_prediction_summary(out, aggregate_errors(batch.results), batch.failures, options, batch.results.size(),
                           [&](std::ostream& files) {
                             for (const auto& s : batch.results)
                               files << summary_file_entry(s, &s == &batch.results.front());
                           });
}

nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const StudyOptions& o) {
  return prediction_summary_json(batch, prediction_options_json(o));
}

PredictionTables::PredictionTables(std::string losing_method, std::vector<std::string> references, int worst)
    : losing_method_(std::move(losing_method)), references_(std::move(references)), worst_(worst) {}

void PredictionTables::Group::add(const PushStudy& study) {
  ++pushes;
  for (const auto& r : study.phases) {
    ++phases;
    for (const auto& [name, e] : r.errors) {
      add_errors(sums[name], e);
      ++counts[name];
    }
  }
}

std::map<std::string, PredictionErrors> PredictionTables::Group::mean() const {
  std::map<std::string, PredictionErrors> out = sums;
  divide_errors(out, counts);  // as aggregate_errors divides
  return out;
}

double PredictionTables::Loss::excess() const {
  return std::max(0.0, pos - best_pos) + std::max(0.0, yaw - best_yaw);
}

void PredictionTables::keep_worst(std::vector<Loss>& losses, std::size_t count) {
  // Worst first; among equal excesses, the earlier push first (a stable sort of pushes in input order), so that
  // trimming as they come keeps what sorting them all at the end would.
  std::stable_sort(losses.begin(), losses.end(), [](const Loss& a, const Loss& b) { return a.excess() > b.excess(); });
  if (losses.size() > count) losses.resize(count);
}

void PredictionTables::add(const PushStudy& study) {
  if (!started_) {
    started_ = true;
    methods_ = study.methods;
    const auto has = [&](const std::string& m) { return std::find(methods_.begin(), methods_.end(), m) != methods_.end(); };
    losing_table_ = !losing_method_.empty() && has(losing_method_) && std::all_of(references_.begin(), references_.end(), has);
  }
  const auto p = parse_push_filename(study.source);
  const std::string object = p ? p->shape : std::string("unknown");
  std::string pusher = "unknown";
  if (p) {
    char label[64];
    if (p->speed_m_s > 0) std::snprintf(label, sizeof label, "v = %3.0f mm/s", 1e3 * p->speed_m_s);
    else std::snprintf(label, sizeof label, "a = %4.0f mm/s^2", 1e3 * p->acceleration_m_s2);
    pusher = label;
  }
  all_.add(study);
  by_object_[object].add(study);
  by_pusher_[pusher].add(study);
  if (!losing_table_) return;

  const std::size_t keep = static_cast<std::size_t>(std::max(worst_, 0));
  for (const auto& r : study.phases) {
    ++lost_per_object_[object].second;
    const auto& e = r.errors.at(losing_method_);
    double best_pos = 1e300, best_yaw = 1e300;
    for (const auto& ref : references_) {
      best_pos = std::min(best_pos, r.errors.at(ref).pos_mm_mean);
      best_yaw = std::min(best_yaw, r.errors.at(ref).theta_deg_mean);
    }
    const bool lost = (e.pos_mm_mean > 1.02 * best_pos && e.pos_mm_mean > best_pos + 0.05) ||
                      (e.theta_deg_mean > 1.02 * best_yaw && e.theta_deg_mean > best_yaw + 0.05);
    if (!lost) continue;
    ++lost_per_object_[object].first;
    losses_.push_back({std::filesystem::path(study.source).filename().string(), r.phase, e.pos_mm_mean,
                       e.theta_deg_mean, best_pos, best_yaw});
    if (losses_.size() >= 4 * keep + 64) keep_worst(losses_, keep);
  }
}

std::string PredictionTables::grouped_errors_markdown() const {
  if (!started_) return "";
  auto table = [&](const std::string& title, const std::map<std::string, Group>& groups) {
    std::ostringstream md;
    std::vector<std::string> header = {title, "pushes", "phases"};
    header.insert(header.end(), methods_.begin(), methods_.end());
    md << markdown_header(header);
    for (const auto& [group, sums] : groups) {
      const auto agg = sums.mean();
      std::vector<std::string> cells = {group, std::to_string(sums.pushes), std::to_string(sums.phases)};
      for (const auto& m : methods_) {
        const auto e = agg.find(m);
        cells.push_back(e == agg.end() ? std::string("-")
                                       : table_number("%.2f", e->second.pos_mm_mean) + " / " +
                                             table_number("%.2f", e->second.theta_deg_mean));
      }
      md << markdown_row(cells);
    }
    return md.str();
  };
  std::ostringstream out;
  out << table("object", by_object_) << "\n";
  out << table("pusher", by_pusher_) << "\n";
  out << table("all", {{"all", all_}});
  return out.str();
}

std::string PredictionTables::losing_phases_markdown() const {
  if (!started_ || !losing_table_) return "";
  std::ostringstream md;
  md << "Phases where `" << losing_method_ << "` loses to the better of";
  for (const auto& r : references_) md << " `" << r << "`";
  md << " (position or yaw more than 2 % and 0.05 mm / 0.05 deg worse):";
  for (const auto& [object, counts] : lost_per_object_)
    md << " " << object << " " << counts.first << " of " << counts.second << ";";
  md << "\n\n" << markdown_header({"push", "phase", losing_method_ + " [mm / deg]", "better reference [mm / deg]"});
  std::vector<Loss> worst = losses_;
  keep_worst(worst, static_cast<std::size_t>(std::max(worst_, 0)));
  for (const Loss& l : worst)
    md << markdown_row({"`" + l.push + "`", std::to_string(l.phase),
                        table_number("%.2f", l.pos) + " / " + table_number("%.2f", l.yaw),
                        table_number("%.2f", l.best_pos) + " / " + table_number("%.2f", l.best_yaw)});
  return md.str();
}

std::string grouped_errors_markdown(const std::vector<PushStudy>& studies) {
  PredictionTables tables;
  for (const auto& s : studies) tables.add(s);
  return tables.grouped_errors_markdown();
}

std::string losing_phases_markdown(const std::vector<PushStudy>& studies, const std::string& method,
                                   const std::vector<std::string>& references, int worst) {
  PredictionTables tables(method, references, worst);
  for (const auto& s : studies) tables.add(s);
  return tables.losing_phases_markdown();
}

namespace {

/// Appends `v` as printf's "%.9g" writes it (what an ostream at precision 9 writes), without the stream: the CSVs
/// hold millions of numbers, and the stream's formatting was a tenth of `predict`'s time (perf, the 77 ABS pushes).
void append_number(std::string& out, double v) {
  char buffer[32];
  const auto written = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 9);
  out.append(buffer, written.ptr);
}

}  // namespace

std::string predictions_csv(const PushStudy& s) {
  std::string out = "phase,t_s,measured_x_mm,measured_y_mm,measured_theta_deg";
  for (const auto& m : s.methods) out += "," + m + "_x_mm," + m + "_y_mm," + m + "_theta_deg";
  out += "\n";
  constexpr double deg = 180.0 / M_PI;
  std::vector<const Eigen::MatrixX3d*> predicted(s.methods.size());
  for (const auto& r : s.phases) {
    for (std::size_t k = 0; k < s.methods.size(); ++k) predicted[k] = &r.predicted.at(s.methods[k]);
    const std::string phase = std::to_string(r.phase);
    for (Eigen::Index j = 0; j < r.t_s.size(); ++j) {
      out += phase;
      out += ',';
      append_number(out, r.t_s(j));
      for (int c = 0; c < 3; ++c) {
        out += ',';
        append_number(out, (c < 2 ? 1e3 : deg) * r.measured(j, c));
      }
      for (const Eigen::MatrixX3d* p : predicted)
        for (int c = 0; c < 3; ++c) {
          out += ',';
          append_number(out, (c < 2 ? 1e3 : deg) * (*p)(j, c));
        }
      out += '\n';
    }
  }
  return out;
}

std::string markdown_method_list(const std::vector<std::string>& methods) {
  std::string out;
  for (const auto& m : methods) out += (out.empty() ? "`" : ", `") + m + "`";
  return out;
}

}  // namespace pushpred
