#pragma once
// Short simulated pushes for the diagnosis tests: cases drawn at random by a seeded generator within realistic
// ranges (rect2 on abs, 2 to 4 cm, sides, contact positions and angles like the real files), simulated in memory
// with the measured sensor noise and clock jitter, and synchronised like a real recording.
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred::testing {

struct DrawRanges {
  double speed_min_m_s = 0.03, speed_max_m_s = 0.08;
  double length_min_m = 0.025, length_max_m = 0.04;
  double acceleration_m_s2 = 0;  ///< > 0: constant-acceleration pushes drawn in [0.5, 1] x this
};

/// `count` scenarios with the hidden `effects`, drawn by `rng`.
inline std::vector<PushScenario> draw_scenarios(std::mt19937_64& rng, int count,
                                                const std::vector<std::pair<std::string, double>>& effects,
                                                const DrawRanges& ranges = {}) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto between = [&](double a, double b) { return a + (b - a) * unit(rng); };
  std::vector<PushScenario> out;
  for (int k = 0; k < count; ++k) {
    PushScenario s;
    s.name = "simulated push " + std::to_string(10 + k);  // sorted by name: alternate fit and test pushes
    s.shape = "rect2";
    if (ranges.acceleration_m_s2 > 0) {
      s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
      s.motion.acceleration_m_s2 = between(0.5, 1.0) * ranges.acceleration_m_s2;
    } else {
      s.motion.speed_m_s = between(ranges.speed_min_m_s, ranges.speed_max_m_s);
    }
    s.motion.length_m = between(ranges.length_min_m, ranges.length_max_m);
    s.contact_side = static_cast<int>(std::floor(between(0, 4 - 1e-9)));
    s.contact_position = between(0.3, 0.7);
    s.push_angle_rad = between(-0.25, 0.25);
    s.initial_yaw_rad = between(-0.5, 0.5);
    s.seed = rng();
    for (const auto& [name, amount] : effects) s.effects.set(name, amount);
    out.push_back(s);
  }
  return out;
}

/// The scenario simulated and synchronised as `load_push` would do it from a file.
inline SynchronisedPush simulate_and_synchronise(const PushScenario& s) {
  const SimulatedPush sim = simulate_push(s);
  return synchronise(as_read(sim.recording), ShapeTable::published().find(s.shape));
}

inline std::vector<SynchronisedPush> simulate_all(const std::vector<PushScenario>& scenarios) {
  std::vector<SynchronisedPush> out;
  for (const auto& s : scenarios) out.push_back(simulate_and_synchronise(s));
  return out;
}

}  // namespace pushpred::testing
