#include "pushpred/prediction/predictor.hpp"

#include <map>
#include <mutex>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/prediction/quasi_static_identification.hpp"

namespace pushpred {
namespace {

/// dob and dob_velinit: the paper's relation model under the planned force.
class RelationPredictor final : public Predictor {
 public:
  explicit RelationPredictor(bool velocity_from_observer) : velocity_from_observer_(velocity_from_observer) {}
  std::string name() const override { return velocity_from_observer_ ? "dob_velinit" : "dob"; }
  PhasePrediction predict(const PhaseContext& c) override {
    const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
    const PredictionModel model = relation_prediction_model(c.push.shape, c.relation_ready ? c.relation.beta : zero,
                                                            c.relation_ready ? c.relation.eps : zero);
    const PlannedForce plan = plan_from_measurement(c.push, c.phase.t0_s, c.phase.t1_s, c.plan_rate_hz);
    // The double integrator's exact discretisation, not CVODE (predict_poses_exactly says why).
    return {predict_poses_exactly(model, plan, c.pose0,
                                  velocity_from_observer_ ? c.velocity0 : Eigen::Vector3d::Zero().eval(), c.t_s),
            {},
            {}};
  }

 private:
  bool velocity_from_observer_;
};

/// The paper's simple baseline: Coulomb friction mu m g against the velocity, from rest.
class SimplePredictor final : public Predictor {
 public:
  std::string name() const override { return "simple"; }
  void start_push(const SynchronisedPush& push, const StudyOptions& o) override {
    mu_ = simple_friction_coefficient(push, o);
  }
  PhasePrediction predict(const PhaseContext& c) override {
    const PredictionModel model = simple_prediction_model(c.push.shape, mu_);
    const PlannedForce plan = plan_from_measurement(c.push, c.phase.t0_s, c.phase.t1_s, c.plan_rate_hz);
    // Coulomb friction solved in closed form, not CVODE on its regularisation (predict_poses_exactly says why).
    return {predict_poses_exactly(model, plan, c.pose0, Eigen::Vector3d::Zero(), c.t_s), {}, {}};
  }

 private:
  double mu_ = 0;
};

class HoldPredictor final : public Predictor {
 public:
  std::string name() const override { return "hold"; }
  PhasePrediction predict(const PhaseContext& c) override {
    return {c.pose0.transpose().replicate(c.t_s.size(), 1), {}, {}};
  }
};

class ConstantVelocityPredictor final : public Predictor {
 public:
  std::string name() const override { return "const_velocity"; }
  PhasePrediction predict(const PhaseContext& c) override {
    Eigen::MatrixX3d poses(c.t_s.size(), 3);
    for (Eigen::Index j = 0; j < c.t_s.size(); ++j)
      poses.row(j) = (c.pose0 + (c.t_s(j) - c.phase.t0_s) * c.velocity0).transpose();
    return {poses, {}, {}};
  }
};

}  // namespace

PhasePrediction as_phase_prediction(const QuasiStaticPhase& phase) {
  std::string note = phase.note;
  for (size_t k = 0; k < 3; ++k)
    if (phase.identification.sources[k].rfind("default", 0) == 0)
      note += std::string(note.empty() ? "" : "; ") + QuasiStaticIdentification::names()[k] + " " +
              phase.identification.sources[k];
  PhasePrediction out{phase.poses, note, {}};
  const auto& id = phase.identification;
  const double values[4] = {id.parameters.pusher_friction, id.parameters.torque_ratio_m, id.parameters.support_friction,
                            id.parameters.contact_offset_m};
  const char* units[4] = {"", "m", "", "m"};
  for (size_t k = 0; k < 4; ++k)
    out.parameters.push_back({QuasiStaticIdentification::names()[k], values[k], id.std(static_cast<Eigen::Index>(k)),
                              units[k], id.sources[k]});
  out.parameters.push_back({"centre_offset_x_m", id.centre_offset_m.x(), id.centre_offset_std_m.x(), "m",
                            id.centre_offset_source});
  out.parameters.push_back({"centre_offset_y_m", id.centre_offset_m.y(), id.centre_offset_std_m.y(), "m",
                            id.centre_offset_source});
  return out;
}

namespace {

class QuasiStaticPredictor final : public Predictor {
 public:
  std::string name() const override { return "quasi_static"; }
  void start_push(const SynchronisedPush& push, const StudyOptions&) override { estimator_.reset(push); }
  void add_interval(const SynchronisedPush&, const TimeInterval& interval, const DisturbanceEstimate&) override {
    estimator_.add_interval(interval);
  }
  PhasePrediction predict(const PhaseContext& c) override {
    return as_phase_prediction(predict_quasi_static_phase(c.push, c.identified, c.phase, c.plan_rate_hz, c.velocity0,
                                                          c.t_s, c.options.pushing_model_integrator, &estimator_));
  }

 private:
  QuasiStaticEstimator estimator_;
};

struct Entry {
  std::string name, description;
  PredictorFactory factory;
};

std::vector<Entry>& registry() {
  static std::vector<Entry> entries{
      {"dob", "the paper's relation model m r'' = u + beta u + eps under the planned force, from rest",
       [] { return std::make_unique<RelationPredictor>(false); }},
      {"dob_velinit", "the paper's relation model, from the observer's velocity",
       [] { return std::make_unique<RelationPredictor>(true); }},
      {"simple", "the paper's baseline: Coulomb friction mu m g against the velocity, from rest",
       [] { return std::make_unique<SimplePredictor>(); }},
      {"hold", "the object stays where it was", [] { return std::make_unique<HoldPredictor>(); }},
      {"const_velocity", "the object keeps the observer's velocity",
       [] { return std::make_unique<ConstantVelocityPredictor>(); }},
      {"quasi_static",
       "quasi-static pushing (motion cone, ellipsoidal limit surface) under the planned tip path, then the slide to "
       "rest; identified online",
       [] { return std::make_unique<QuasiStaticPredictor>(); }},
  };
  return entries;
}

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

const Entry& find_entry(const std::string& name) {
  for (const auto& e : registry())
    if (e.name == name) return e;
  std::string known;
  for (const auto& e : registry()) known += (known.empty() ? "" : ", ") + e.name;
  throw InputError("unknown prediction method '" + name + "' (known: " + known + ")");
}

}  // namespace

void register_predictor(const std::string& name, const std::string& description, PredictorFactory factory) {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  if (name.empty() || name.find(',') != std::string::npos)
    throw InputError("a prediction method needs a name without commas");
  if (name == kCorrectedMethod) throw InputError("'corrected' is reserved for the study's PredictionCorrection");
  for (const auto& e : registry())
    if (e.name == name) throw InputError("prediction method '" + name + "' is registered twice");
  if (!factory) throw InputError("prediction method '" + name + "' has no factory");
  registry().push_back({name, description, std::move(factory)});
}

std::vector<std::string> predictor_names() {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  std::vector<std::string> out;
  for (const auto& e : registry()) out.push_back(e.name);
  return out;
}

std::string predictor_description(const std::string& name) {
  const std::lock_guard<std::mutex> lock(registry_mutex());
  return find_entry(name).description;
}

std::unique_ptr<Predictor> make_predictor(const std::string& name) {
  PredictorFactory factory;
  {
    const std::lock_guard<std::mutex> lock(registry_mutex());
    factory = find_entry(name).factory;
  }
  auto p = factory();
  if (!p || p->name() != name)
    throw InputError("prediction method '" + name + "': its factory made a predictor of another name");
  return p;
}

std::vector<std::string> parse_predictor_list(const std::string& text) {
  if (text.empty()) return prediction_method_names();
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string name = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name.empty()) throw InputError("empty name in the method list '" + text + "'");
    {
      const std::lock_guard<std::mutex> lock(registry_mutex());
      find_entry(name);
    }
    for (const auto& n : out)
      if (n == name) throw InputError("method '" + name + "' listed twice");
    out.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace pushpred
