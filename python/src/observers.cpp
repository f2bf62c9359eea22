// Disturbance estimators: the Q-filter observer and the PID force reconstruction, and the PID gain fit.
// Channels everywhere: 0 = x force [N], 1 = y force [N], 2 = torque about the object centre [N m], {R}.
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/calibration/pid_gain_fit.hpp"
#include "pushpred/observers/observation.hpp"

namespace pushpred::python {
namespace {

constexpr const char* kEstimateDoc = R"doc(
Estimates the unknown force over the grid samples with t in [t_start_s, t_end_s] (t_end_s None: the end of the
push), initialised from the data at t_start_s. Returns a dict: t_s [s]; u, the applied input (f_Cx [N], f_Cy [N],
T_C + r_m x f_C [N m]); d_hat, the estimated unknown force per channel [N, N, N m]; velocity (x', y' [m/s],
theta' [rad/s]); total, the estimated total force M r'' [N, N, N m]; nominal_inertia (m [kg], m [kg],
I [kg m^2]). Forces are means over the grid interval that ends at each sample; all arrays n x 3.)doc";

double end_of(const SynchronisedPush& push, std::optional<double> t_end_s) {
  return t_end_s ? *t_end_s : push.duration_s();
}

Hold parse_hold(const std::string& name) {
  if (name == "first") return Hold::First;
  if (name == "zero") return Hold::Zero;
  throw InputError("hold must be 'first' or 'zero', not '" + name + "'");
}

py::dict gains_dict(const PidGains& g) {
  py::dict d;
  d["kp"] = g.kp;
  d["ki"] = g.ki;
  d["kd"] = g.kd;
  d["lp"] = g.lp;
  d["li"] = g.li;
  d["ld"] = g.ld;
  return d;
}

PidGains gains_from(double kp, double ki, double kd, double lp, double li, double ld) {
  PidGains g;
  g.kp = kp;
  g.ki = ki;
  g.kd = kd;
  g.lp = lp;
  g.li = li;
  g.ld = ld;
  g.validate();
  return g;
}

py::dict solve_dict(const PidFitSolve& s) {
  py::dict d;
  d["fitted"] = s.fitted;
  d["given_cost"] = s.given_cost;
  d["start"] = s.start;
  d["start_cost"] = s.start_cost;
  d["final_cost"] = s.final_cost;
  d["iterations"] = s.iterations;
  d["termination"] = s.termination;
  return d;
}

}  // namespace

void bind_observers(py::module_& m) {
  m.def("disturbance_estimator_names", &disturbance_estimator_names, "names for estimate_disturbance: dob, pid");

  m.def(
      "estimate_disturbance",
      [](const SynchronisedPush& push, const std::string& name, double t_start_s, std::optional<double> t_end_s) {
        auto estimator = make_disturbance_estimator(name);
        return estimate_dict(without_gil([&] { return estimator->estimate(push, t_start_s, end_of(push, t_end_s)); }));
      },
      py::arg("push"), py::arg("estimator") = "dob", py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(),
      (std::string("The estimator called `estimator` (\"dob\" or \"pid\") with its default options.\n") + kEstimateDoc)
          .c_str());

  py::class_<QFilterObserver>(m, "QFilterObserver", R"doc(
The paper's Q-filter disturbance observer (section III-A), integrated with CVODE:
d_hat = -Q u + Q P_n^-1 y, P_n = 1/(M s^2), Q = wn^2 / (s^2 + 2 zeta wn s + wn^2), per channel.
mass_kg / inertia_kgm2 0: the nominal values of the push's shape. hold: how y and u are held between samples
("first" or "zero"); start: "steady" (no start-up transient) or "at_rest".)doc")
      .def(py::init([](double wn_rad_s, double zeta, double mass_kg, double inertia_kgm2, const std::string& hold,
                       const std::string& start, double velocity_window_s) {
             QFilterObserverOptions o;
             o.wn_rad_s = wn_rad_s;
             o.zeta = zeta;
             o.mass_kg = mass_kg;
             o.inertia_kgm2 = inertia_kgm2;
             o.hold = parse_hold(hold);
             if (start == "steady")
               o.start = QFilterObserverOptions::Start::Steady;
             else if (start == "at_rest")
               o.start = QFilterObserverOptions::Start::AtRest;
             else
               throw InputError("start must be 'steady' or 'at_rest', not '" + start + "'");
             o.velocity_window_s = velocity_window_s;
             o.validate();
             return QFilterObserver(o);
           }),
           py::arg("wn_rad_s") = 300.0, py::arg("zeta") = 1.0 / std::sqrt(2.0), py::arg("mass_kg") = 0.0,
           py::arg("inertia_kgm2") = 0.0, py::arg("hold") = "first", py::arg("start") = "steady",
           py::arg("velocity_window_s") = 0.03)
      .def_property_readonly("name", &QFilterObserver::name)
      .def("__repr__",
           [](const QFilterObserver& o) {
             const QFilterObserverOptions& q = o.options();
             return "QFilterObserver(wn_rad_s=" + repr_number(q.wn_rad_s) + ", zeta=" + repr_number(q.zeta) +
                    ", mass_kg=" + repr_number(q.mass_kg) + ", inertia_kgm2=" + repr_number(q.inertia_kgm2) +
                    ", hold='" + (q.hold == Hold::Zero ? "zero" : "first") + "', start='" +
                    (q.start == QFilterObserverOptions::Start::AtRest ? "at_rest" : "steady") +
                    "', velocity_window_s=" + repr_number(q.velocity_window_s) + ")";
           })
      .def(
          "estimate",
          [](const QFilterObserver& o, const SynchronisedPush& push, double t_start_s, std::optional<double> t_end_s) {
            return estimate_dict(without_gil([&] { return o.estimate(push, t_start_s, end_of(push, t_end_s)); }));
          },
          py::arg("push"), py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(), kEstimateDoc)
      .def(
          "estimate_exactly",
          [](const QFilterObserver& o, const SynchronisedPush& push, double t_start_s, std::optional<double> t_end_s) {
            return estimate_dict(
                without_gil([&] { return o.estimate_exactly(push, t_start_s, end_of(push, t_end_s)); }));
          },
          py::arg("push"), py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(),
          "The same estimate from the exact discretisation (matrix exponentials) instead of CVODE.");

  py::class_<PidForceReconstruction>(m, "PidForceReconstruction", R"doc(
The paper's PID force reconstruction (section II-B): a simulated object tracks the measured pose under a PID
controller whose output is the total force; d_hat = f_hat - u. Gains default to the paper's: kp [N/m],
ki [N/(m s)], kd [N s/m] for translation, lp [N m/rad], li [N m/(rad s)], ld [N m s/rad] for rotation.)doc")
      .def(py::init([](double kp, double ki, double kd, double lp, double li, double ld, double mass_kg,
                       double inertia_kgm2) {
             PidReconstructionOptions o;
             o.mass_kg = mass_kg;
             o.inertia_kgm2 = inertia_kgm2;
             o.validate();
             return PidForceReconstruction(gains_from(kp, ki, kd, lp, li, ld), o);
           }),
           py::arg("kp") = PidGains{}.kp, py::arg("ki") = PidGains{}.ki, py::arg("kd") = PidGains{}.kd,
           py::arg("lp") = PidGains{}.lp, py::arg("li") = PidGains{}.li, py::arg("ld") = PidGains{}.ld,
           py::arg("mass_kg") = 0.0, py::arg("inertia_kgm2") = 0.0)
      .def_property_readonly("name", &PidForceReconstruction::name)
      .def("__repr__",
           [](const PidForceReconstruction& p) {
             const PidGains& g = p.gains();
             return "PidForceReconstruction(kp=" + repr_number(g.kp) + ", ki=" + repr_number(g.ki) +
                    ", kd=" + repr_number(g.kd) + ", lp=" + repr_number(g.lp) + ", li=" + repr_number(g.li) +
                    ", ld=" + repr_number(g.ld) + ")";
           })
      .def_property_readonly(
          "gains", [](const PidForceReconstruction& p) { return gains_dict(p.gains()); },
          "kp, ki, kd (translation) and lp, li, ld (rotation), units as in the class docstring")
      .def(
          "estimate",
          [](const PidForceReconstruction& p, const SynchronisedPush& push, double t_start_s,
             std::optional<double> t_end_s) {
            return estimate_dict(without_gil([&] { return p.estimate(push, t_start_s, end_of(push, t_end_s)); }));
          },
          py::arg("push"), py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(), kEstimateDoc)
      .def(
          "track",
          [](const PidForceReconstruction& p, const SynchronisedPush& push, double t_start_s,
             std::optional<double> t_end_s) {
            const auto tracking = without_gil([&] { return p.track(push, t_start_s, end_of(push, t_end_s)); });
            py::dict d = estimate_dict(tracking.estimate);
            d["simulated_pose"] = array(tracking.simulated_pose);
            return d;
          },
          py::arg("push"), py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(),
          "estimate() plus simulated_pose, the pose r_sim that tracked the measurement (x [m], y [m], yaw [rad]).");

  m.def(
      "observe",
      [](const SynchronisedPush& push, double t_start_s, std::optional<double> t_end_s) {
        ObservationOptions o;
        o.t_start_s = t_start_s;
        o.t_end_s = t_end_s ? *t_end_s : -1.0;
        const Observation obs = without_gil([&] { return observe_push(push, o); });
        py::dict d;
        d["source"] = obs.source;
        d["dob"] = estimate_dict(obs.dob);
        d["pid"] = estimate_dict(obs.pid);
        d["measured_pose"] = array(obs.measured_pose);
        d["resimulated_dob"] = array(obs.resimulated_dob);
        d["resimulated_pid"] = array(obs.resimulated_pid);
        d["rms_dob"] = array(obs.rms_dob);
        d["rms_dob_minus_pid"] = array(obs.rms_dob_minus_pid);
        d["rms_resimulation_dob"] = array(obs.rms_resimulation_dob);
        d["rms_resimulation_pid"] = array(obs.rms_resimulation_pid);
        return d;
      },
      py::arg("push"), py::arg("t_start_s") = 0.0, py::arg("t_end_s") = py::none(), R"doc(
What `pushpred observe` computes: the observer (dob) and the PID reconstruction (pid) as estimate dicts, the
measured pose and the poses re-simulated from each estimate's total force (x [m], y [m], yaw [rad]), and RMS
differences: rms_dob and rms_dob_minus_pid [N, N, N m], rms_resimulation_* [m, m, rad].)doc");

  m.def(
      "fit_pid_gains",
      [](const std::vector<SynchronisedPush>& pushes, double roughness_weight) {
        PidGainFitOptions o;
        o.roughness_weight = roughness_weight;
        o.validate();
        const PidGainFit fit = without_gil([&] {
          std::vector<PidFitPush> fit_pushes;
          for (const auto& p : pushes) fit_pushes.push_back(make_pid_fit_push(p));
          return fit_pid_gains(fit_pushes, o, PidGains{});
        });
        py::dict d;
        d["gains"] = gains_dict(fit.gains);
        d["translation"] = solve_dict(fit.translation);
        d["rotation"] = solve_dict(fit.rotation);
        d["pushes"] = fit.pushes;
        return d;
      },
      py::arg("pushes"), py::arg("roughness_weight") = 1.0, R"doc(
PID gains fitted by Ceres over `pushes` (one gain set for all), starting from the paper's, as `pushpred fit-pid`
does: gains (kp, ki, kd, lp, li, ld) and how each of the two problems was solved.)doc");
}

}  // namespace pushpred::python
