#include "pushpred/jobs/partial_codecs.hpp"

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {
namespace {

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
  return {{"estimator", p.estimator},
          {"beta", vec(p.beta)},
          {"eps", vec(p.eps)},
          {"covariance", cov},
          {"residual_std", vec(p.residual_std)},
          {"samples", p.samples},
          {"effective_samples", num(p.effective_samples)},
          {"intervals", p.intervals},
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
  p.samples = json_whole_number<long>(j.at("samples"), "samples");
  p.effective_samples = num_from(j.at("effective_samples"));
  p.intervals = json_whole_number<long>(j.at("intervals"), "intervals");
  p.loss_scale = vec3_from(j.at("loss_scale"));
  return p;
}

nlohmann::json errors_exact(const PredictionErrors& e) {
  return {num(e.pos_mm_mean),    num(e.x_mm_mean),     num(e.x_mm_std),     num(e.y_mm_mean),      num(e.y_mm_std),
          num(e.theta_deg_mean), num(e.theta_deg_std), num(e.final_pos_mm), num(e.final_theta_deg)};
}

PredictionErrors errors_from(const nlohmann::json& j) {
  if (j.size() != 9) throw InputError("prediction errors hold " + std::to_string(j.size()) + " numbers, not 9");
  PredictionErrors e;
  double* fields[] = {&e.pos_mm_mean,    &e.x_mm_mean,     &e.x_mm_std,     &e.y_mm_mean,      &e.y_mm_std,
                      &e.theta_deg_mean, &e.theta_deg_std, &e.final_pos_mm, &e.final_theta_deg};
  for (std::size_t k = 0; k < 9; ++k) *fields[k] = num_from(j[k]);
  return e;
}

nlohmann::json interval_exact(const TimeInterval& t) { return {num(t.t0_s), num(t.t1_s)}; }
TimeInterval interval_from(const nlohmann::json& j) { return {num_from(j.at(0)), num_from(j.at(1))}; }

}  // namespace

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
        l.push_back(
            {{"name", q.name}, {"value", num(q.value)}, {"std", num(q.std)}, {"unit", q.unit}, {"source", q.source}});
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
      r.phase = json_whole_number<int>(p.at("phase"), "phase");
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

nlohmann::json error_summary_exact_json(const ErrorSummary& e) {
  return {e.phases,
          exact_number_json(e.pos_mm_mean),
          exact_number_json(e.x_mm_mean),
          exact_number_json(e.y_mm_mean),
          exact_number_json(e.theta_deg_mean),
          exact_number_json(e.final_pos_mm),
          exact_number_json(e.final_theta_deg)};
}

ErrorSummary error_summary_from_exact_json(const nlohmann::json& j) {
  if (!j.is_array()) throw InputError("an error summary is not an array of 7 numbers");
  if (j.size() != 7) throw InputError("an error summary holds " + std::to_string(j.size()) + " numbers, not 7");
  ErrorSummary e;
  e.phases = json_whole_number<int>(j[0], "phases");
  double* fields[] = {&e.pos_mm_mean,    &e.x_mm_mean,    &e.y_mm_mean,
                      &e.theta_deg_mean, &e.final_pos_mm, &e.final_theta_deg};
  for (std::size_t k = 0; k < 6; ++k) *fields[k] = exact_number(j[k + 1]);
  return e;
}

nlohmann::json held_out_errors_exact_json(const std::array<const ErrorSummary*, 6>& errors) {
  nlohmann::json list = nlohmann::json::array();
  for (const ErrorSummary* e : errors) list.push_back(error_summary_exact_json(*e));
  return list;
}

void held_out_errors_from_exact_json(const nlohmann::json& list, const HeldOutErrorFields& fields,
                                     const std::string& holder) {
  if (!list.is_array() || list.size() != 6)
    throw InputError(holder + " holds " + (list.is_array() ? std::to_string(list.size()) : std::string("no list of")) +
                     " error summaries, not 6");
  for (std::size_t k = 0; k < 6; ++k) *fields[k] = error_summary_from_exact_json(list[k]);
}

nlohmann::json validation_trial_exact_json(const ValidationTrial& t) {
  return {{"index", t.index},
          {"seed", t.seed},
          {"true_kind", t.true_kind},
          {"amount", exact_number_json(t.amount)},
          {"floor", exact_number_json(t.floor)},
          {"floor_multiple", exact_number_json(t.floor_multiple)},
          {"shape", t.shape},
          {"surface_friction", exact_number_json(t.surface_friction)},
          {"contact_friction", exact_number_json(t.contact_friction)},
          {"contact_stiffness_N_m", exact_number_json(t.contact_stiffness_N_m)},
          {"pressure_rim_weight", exact_number_json(t.pressure_rim_weight)},
          {"pushes", t.pushes},
          {"named", t.named},
          {"negligible", t.negligible},
          {"true_named", t.true_named},
          {"fitted_amount", exact_number_json(t.fitted_amount)},
          {"true_score", exact_number_json(t.true_score)},
          {"true_passed", t.true_passed},
          {"true_negligible", t.true_negligible},
          {"true_amount", exact_number_json(t.true_amount)},
          {"true_floor", exact_number_json(t.true_floor)},
          {"true_note", t.true_note},
          {"hidden", t.hidden},
          {"preloaded_pushes", t.preloaded_pushes},
          {"adequacy_tested", t.adequacy_tested},
          {"explained", t.explained},
          {"errors",
           held_out_errors_exact_json({&t.before, &t.base, &t.after, &t.hold, &t.const_velocity, &t.quasi_static})},
          {"failure", t.failure}};
}

ValidationTrial validation_trial_from_exact_json(const nlohmann::json& j) {
  try {
    ValidationTrial t;
    t.index = json_whole_number<int>(j.at("index"), "index");
    t.seed = json_whole_number<std::uint64_t>(j.at("seed"), "seed");
    t.true_kind = j.at("true_kind").get<std::string>();
    t.amount = exact_number(j.at("amount"));
    t.floor = exact_number(j.at("floor"));
    t.floor_multiple = exact_number(j.at("floor_multiple"));
    t.shape = j.at("shape").get<std::string>();
    t.surface_friction = exact_number(j.at("surface_friction"));
    t.contact_friction = exact_number(j.at("contact_friction"));
    t.contact_stiffness_N_m = exact_number(j.at("contact_stiffness_N_m"));
    t.pressure_rim_weight = exact_number(j.at("pressure_rim_weight"));
    t.pushes = json_whole_number<int>(j.at("pushes"), "pushes");
    t.named = j.at("named").get<std::vector<std::string>>();
    t.negligible = j.at("negligible").get<std::vector<std::string>>();
    t.true_named = j.at("true_named").get<bool>();
    t.fitted_amount = exact_number(j.at("fitted_amount"));
    t.true_score = exact_number(j.at("true_score"));
    t.true_passed = j.at("true_passed").get<bool>();
    t.true_negligible = j.at("true_negligible").get<bool>();
    t.true_amount = exact_number(j.at("true_amount"));
    t.true_floor = exact_number(j.at("true_floor"));
    t.true_note = j.at("true_note").get<std::string>();
    t.hidden = j.at("hidden").get<bool>();
    t.preloaded_pushes = json_whole_number<int>(j.at("preloaded_pushes"), "preloaded_pushes");
    t.adequacy_tested = j.at("adequacy_tested").get<bool>();
    t.explained = j.at("explained").get<bool>();
    held_out_errors_from_exact_json(
        j.at("errors"), {&t.before, &t.base, &t.after, &t.hold, &t.const_velocity, &t.quasi_static}, "a trial");
    t.failure = j.at("failure").get<std::string>();
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a trial written by pushpred: ") + e.what());
  }
}

// --- An object's outcome in a partial output: what the overview and the printed report read of it, exactly.

nlohmann::json diagnosed_object_exact_json(const DiagnosedObject& d) {
  nlohmann::json j = {{"name", d.outcome.name},     {"pushes", d.outcome.pushes}, {"printed", d.printed},
                      {"complaints", d.complaints}, {"left_out", d.left_out},     {"error", d.outcome.error}};
  if (!d.outcome.result) {
    j["overview"] = nullptr;
    return j;
  }
  // The overview reads the object's shape and surface, its selected effects and six error summaries.
  const DiagnosisResult& r = *d.outcome.result;
  nlohmann::json selected = nlohmann::json::array();
  for (const auto& e : r.effects)
    if (e.selected) selected.push_back({{"kind", e.kind}, {"structural", e.structural}});
  j["overview"] = {{"shape", r.shape},
                   {"surface", r.surface},
                   {"selected", selected},
                   {"adequacy", {{"tested", r.adequacy.tested}, {"explained", r.adequacy.explained}}},
                   {"errors", held_out_errors_exact_json({&r.error_before, &r.error_base, &r.error_after, &r.hold,
                                                          &r.const_velocity, &r.quasi_static})}};
  return j;
}

DiagnosedObject diagnosed_object_from_exact_json(const nlohmann::json& j) {
  try {
    DiagnosedObject d;
    d.outcome.name = j.at("name").get<std::string>();
    d.outcome.pushes = json_whole_number<std::size_t>(j.at("pushes"), "pushes");
    d.outcome.error = j.at("error").get<std::string>();
    d.printed = j.at("printed").get<std::string>();
    d.complaints = j.at("complaints").get<std::string>();
    d.left_out = json_whole_number<std::size_t>(j.at("left_out"), "left_out");
    const auto& o = j.at("overview");
    if (o.is_null()) return d;
    DiagnosisResult r;
    r.shape = o.at("shape").get<std::string>();
    r.surface = o.at("surface").get<std::string>();
    for (const auto& e : o.at("selected")) {
      EffectReport report;
      report.kind = e.at("kind").get<std::string>();
      report.structural = e.at("structural").get<bool>();
      report.selected = true;
      r.effects.push_back(std::move(report));
    }
    r.adequacy.tested = o.at("adequacy").at("tested").get<bool>();
    r.adequacy.explained = o.at("adequacy").at("explained").get<bool>();
    held_out_errors_from_exact_json(
        o.at("errors"), {&r.error_before, &r.error_base, &r.error_after, &r.hold, &r.const_velocity, &r.quasi_static},
        "an object");
    d.outcome.result = std::move(r);
    return d;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not an object's diagnosis written by pushpred: ") + e.what());
  }
}

}  // namespace pushpred
