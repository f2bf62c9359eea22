// The push simulator: a scenario (the paper's cases, a dict in the scenario-file format, hidden effects) in, a
// recording that reads like a real one out, with the truth beside it.
#include <optional>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred::python {
namespace {

PushScenario scenario_from(std::optional<int> paper_case, const py::object& scenario, const py::dict& effects,
                           std::optional<std::uint64_t> seed) {
  if (paper_case && !scenario.is_none()) throw InputError("give either paper_case or scenario, not both");
  PushScenario s;
  if (paper_case) s = paper_case_scenario(*paper_case);
  if (!scenario.is_none()) s = scenario_from_json(to_json(scenario, "scenario"), "scenario");
  for (const auto& [name, amount] : effects) s.effects.set(py::str(name), amount.cast<double>());
  if (seed) s.seed = *seed;
  s.validate();
  return s;
}

}  // namespace

void bind_simulation(py::module_& m) {
  m.def(
      "paper_case_scenario", [](int n) { return from_json(scenario_to_json(paper_case_scenario(n))); },
      py::arg("n"), "The paper's case n (1..6) of Table I as a scenario dict (the format of data/paper/case*.json).");

  m.def("effect_catalogue", [] {
    py::list out;
    for (const auto& e : effect_catalogue()) {
      py::dict d;
      d["name"] = e.name;
      d["unit"] = e.unit;
      d["neutral"] = e.neutral;
      d["meaning"] = e.meaning;
      out.append(d);
    }
    return out;
  }, "The hidden physical effects the simulator knows: name, unit, neutral amount, meaning.");

  m.def(
      "simulate",
      [](std::optional<int> paper_case, const py::object& scenario, const py::dict& effects,
         std::optional<std::uint64_t> seed, std::optional<std::filesystem::path> out) {
        const PushScenario s = scenario_from(paper_case, scenario, effects, seed);
        struct Output {
          SimulatedPush sim;
          SynchronisedPush push;
          std::string path;
        };
        const Output o = without_gil([&] {
          Output r{simulate_push(s), {}, ""};
          if (out) {
            const auto path = simulated_output_path(s, *out);
            write_recording_hdf5(r.sim.recording, path);
            r.path = path.string();
          }
          const Recording read = as_read(r.sim.recording);
          r.push = synchronise(read, shape_for(read, s.shape));
          if (!r.path.empty()) r.push.source = r.path;
          return r;
        });
        py::dict d;
        d["scenario"] = from_json(scenario_to_json(o.sim.scenario));
        d["push"] = o.push;
        d["path"] = o.path.empty() ? py::object(py::none()) : py::object(py::str(o.path));
        py::dict truth;
        truth["t_s"] = array(o.sim.t_s);
        truth["tracked_pose"] = array(o.sim.tracked_pose);
        truth["mass_centre_velocity"] = array(o.sim.mass_centre_velocity);
        truth["force_on_object_N"] = array(o.sim.force_on_object_N);
        truth["touching"] = bool_array(o.sim.touching);
        truth["push_start_s"] = o.sim.push_start_s;
        truth["push_end_s"] = o.sim.push_end_s;
        truth["rod_peak_speed_m_s"] = o.sim.rod_peak_speed_m_s;
        d["truth"] = truth;
        return d;
      },
      py::arg("paper_case") = py::none(), py::arg("scenario") = py::none(), py::arg("effects") = py::dict(),
      py::arg("seed") = py::none(), py::arg("out") = py::none(), R"doc(
Simulates one push as `pushpred simulate` does: the paper's case `paper_case` (1..6) or `scenario` (a dict in
the scenario-file format, docs/simulator.md; neither: the default scenario), with hidden `effects`
({name: amount}, effect_catalogue()) and `seed`. With `out` (a file, or a folder ending in '/'), the recording is
also written in the dataset's HDF5 layout.

Returns a dict: scenario (as run), push (a Push, read and synchronised as a real file would be), path (the file
written, or None) and truth on the simulation clock (t_s [s]; tracked_pose x [m], y [m], yaw [rad];
mass_centre_velocity [m/s, m/s, rad/s]; force_on_object_N, n x 2; touching; push_start_s, push_end_s;
rod_peak_speed_m_s). The simulation clock starts at the recording's start; the push's t_s starts where the
three streams overlap.)doc");
}

}  // namespace pushpred::python
