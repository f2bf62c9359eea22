#include "pushpred/jobs/real_comparison_job.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "pushpred/jobs/inspection_job.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/physical_bounds.hpp"
#include "pushpred/simulation/sensor_model.hpp"

namespace pushpred {
namespace {

/// Median |f_C| over the last 0.1 s of a push: what the sensor reads once everything has stopped.
double final_force(const SynchronisedPush& p) {
  std::vector<double> f;
  for (Eigen::Index k = 0; k < p.size(); ++k)
    if (p.t_s(k) >= p.duration_s() - 0.1) f.push_back(p.force_N.row(k).norm());
  if (f.empty()) return NAN;
  std::nth_element(f.begin(), f.begin() + f.size() / 2, f.end());
  return f[f.size() / 2];
}

}  // namespace

Batch<RealComparison> compare_with_real(const std::vector<std::string>& inputs, double surface_friction,
                                        double contact_friction) {
  // Checked once, before any file is read: a coefficient out of range would fail every push alike.
  check_friction_coefficient(surface_friction, "surface_friction", false);
  check_friction_coefficient(contact_friction, "contact_friction", true);
  return run_batch(expand_inputs(inputs), [&](const std::filesystem::path& path) {
    RealComparison c;
    c.source = path.string();
    const SynchronisedPush real = load_push(path);
    c.real = inspect(real);
    c.real_force_trusted = !real.flags.frozen_force_sensor;
    c.real_force_per_weight = mid_push_force_per_weight(real);
    c.real_force_spread_N = mid_push_force_spread(real);
    c.real_final_force_N = final_force(real);
    const SimulatedPush sim = simulate_push(scenario_like_recording(path, surface_friction, contact_friction));
    const SynchronisedPush simulated = synchronise(as_read(sim.recording), real.shape);
    c.simulated = inspect(simulated);
    c.simulated.source = sim.recording.source;
    c.simulated_force_per_weight = mid_push_force_per_weight(simulated);
    c.simulated_force_spread_N = mid_push_force_spread(simulated);
    c.simulated_final_force_N = final_force(simulated);
    return c;
  });
}

}  // namespace pushpred
