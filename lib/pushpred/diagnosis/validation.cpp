#include "pushpred/diagnosis/validation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis_pipeline.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Samples where the object moves slower than this are left out of the patch's truth (the friction's direction is
/// the velocity's, undefined at rest) [m/s].
constexpr double kSlidingSpeed_m_s = 5e-3;
const std::vector<std::string> kShapes{"rect1", "rect2", "rect3", "ellip1", "ellip2", "ellip3", "hex"};
const std::vector<double> kSpeeds_m_s{0.01, 0.02, 0.05, 0.075, 0.1, 0.15};
const std::vector<double> kAccelerations_m_s2{0.2, 0.5, 1.0, 2.5};

template <class T>
const T& pick(std::mt19937_64& rng, const std::vector<T>& v) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}

double uniform(std::mt19937_64& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

/// The peak acceleration of the pusher on a push: the raised-cosine ramp's pi v / (2 ramp), or the constant one.
double push_acceleration(const PusherMotion& m) {
  if (m.profile == PusherMotion::Profile::ConstantAcceleration) return m.acceleration_m_s2;
  return M_PI * m.speed_m_s / (2 * m.ramp_s);
}

/// The typical speed while sliding: the cruise speed, or for an acceleration push the mean speed sqrt(a L / 2).
double push_speed(const PusherMotion& m) {
  if (m.profile == PusherMotion::Profile::ConstantAcceleration) return std::sqrt(m.acceleration_m_s2 * m.length_m / 2);
  return m.speed_m_s;
}

}  // namespace

void ValidationOptions::validate() const {
  if (trials_per_kind < 1) throw InputError("validation: at least one trial per kind");
  if (min_pushes < 2)
    throw InputError("validation: --min-pushes must be at least 2 (got " + std::to_string(min_pushes) + ")");
  if (max_pushes < min_pushes)
    throw InputError("validation: --max-pushes must not be below --min-pushes (got " + std::to_string(max_pushes) +
                     " and " + std::to_string(min_pushes) + ")");
  if (max_pushes > kMaxValidationPushes)
    throw InputError("validation: --max-pushes must be at most " + std::to_string(kMaxValidationPushes) +
                     " (got " + std::to_string(max_pushes) + ")");
  if (!(min_floor_multiple > 0) || !(max_floor_multiple >= min_floor_multiple))
    throw InputError("validation: floor multiples must be positive, the maximum not below the minimum");
  if (jobs < 1) throw InputError("validation: --jobs must be at least 1");
  if (!(sensor_offset_spread_N >= 0) || !std::isfinite(sensor_offset_spread_N))
    throw InputError("validation: --sensor-offset-spread must be a finite number of newtons, at least 0");
  if (sensor_offset_spread_N > kMaxSensorOffsetSpread_N) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "validation: --sensor-offset-spread must be at most %g N (got %g): the sensor zeros drawn must stay "
                  "within the simulator's %g N bound on a zero error",
                  kMaxSensorOffsetSpread_N, sensor_offset_spread_N, kMaxForceOffset_N);
    throw InputError(text);
  }
  for (const auto& k : kinds)
    if (k != "none") effect_info(k);  // throws for an unknown kind, naming the known ones
  for (const auto& k : hide) {
    if (k == "none") throw InputError("validation: --hide takes simulator effects, not 'none'");
    effect_info(k);
  }
  diagnosis.validate();
}

std::vector<std::string> default_validation_kinds() {
  const EffectLibrary library = EffectLibrary::standard();
  std::vector<std::string> out{"none"};
  for (const auto& e : effect_catalogue())
    if (library.find(e.name)) out.push_back(e.name);
  return out;
}

std::vector<std::string> validation_kinds(const ValidationOptions& options) {
  if (!options.kinds.empty()) return options.kinds;
  if (options.hide.empty()) return default_validation_kinds();
  std::vector<std::string> out{"none"};
  for (const auto& k : options.hide)
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  return out;
}

EffectLibrary validation_library(const ValidationOptions& options) {
  EffectLibrary library = EffectLibrary::standard();
  for (const auto& k : options.hide)
    if (library.find(k)) library.remove(k);
  return library;
}

FloorContext scenario_floor_context(const std::vector<PushScenario>& scenarios, double relevance_fraction) {
  if (scenarios.empty()) throw InputError("validation: no scenario");
  const ShapeInfo& shape = ShapeTable::published().find(scenarios.front().shape);
  FloorContext c;
  c.mass_kg = shape.mass_kg;
  c.inertia_kgm2 = shape.inertia_kgm2;
  c.radius_of_gyration_m = std::sqrt(shape.inertia_kgm2 / shape.mass_kg);
  c.friction_coefficient = scenarios.front().surface_friction;
  c.relevance_fraction = relevance_fraction;
  c.sample_period_s = 0.004;  // the rig's force stream, 250 Hz (docs/data.md)
  double v2 = 0, travel = 0, accel = 0;
  for (const auto& s : scenarios) {
    // The pusher's speed over the push, sampled like the rig: the object's while it is pushed.
    const PusherPath path(Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX(), 0.0, s.motion);
    for (double t = 0; t < path.end_time_s(); t += c.sample_period_s) {
      const double v = path.speed_m_s(t);
      if (v > 1.5e-3) c.sliding_speeds_m_s.push_back(v);
    }
    v2 += push_speed(s.motion) * push_speed(s.motion);
    travel += s.motion.length_m;
    accel = std::max(accel, push_acceleration(s.motion));
  }
  const double n = static_cast<double>(scenarios.size());
  c.sliding_speed_m_s = std::sqrt(v2 / n);
  c.travel_m = travel / n;
  c.acceleration_m_s2 = accel;
  return c;
}

/// The largest Stribeck excess drawn (relative to mu): static friction twice the sliding friction.
constexpr double kMaxStribeckExcess = 1.0;
/// The friction patch's largest relative excess: four times the support's friction on it (rubber on a plastic
/// table, mu about 1, against the validation's 0.2-0.6).
constexpr double kMaxPatchExcess = 3.0;
/// Rounds of the floor's fixed point for friction laws (draw_validation_trial).
constexpr int kFloorRounds = 4;

/// The largest drawn support tilt, as a share of the friction angle: the object must rest on the tilted support.
constexpr double kMaxTiltShareOfFrictionAngle = 0.5;
/// The largest drawn anisotropy |A - 1| = |r - 1| / (r + 1): 0.6 is a ratio of 4 along the body axes.
constexpr double kMaxAnisotropy = 0.6;
/// The largest drawn pusher compliance [m/N] (the simulator's range).
constexpr double kMaxCompliance_m_N = 0.01;

/// The floor of a simulator effect the standard catalogue has no candidate for, on the diagnosis's yardstick
/// (validation.hpp), in the simulator's units.
double yardstick_floor(const std::string& kind, const FloorContext& c, const std::string& shape_name) {
  const double kappa = c.relevance_fraction, mu = c.friction_coefficient;
  if (kind == "support_tilt") return std::asin(std::min(1.0, kappa * mu)) * 180 / M_PI;  // [deg]
  if (kind == "anisotropic_friction") return kappa;  // |A - 1|; the ratio is (1 + a) / (1 - a) or its inverse
  if (kind == "compliant_pusher") {
    const double mass = c.mass_kg > 0 ? c.mass_kg : ShapeTable::published().find(shape_name).mass_kg;
    const double travel = c.travel_m > 0 ? c.travel_m : 0.04;
    return kappa * travel / (mu * mass * kGravity_m_s2);  // [m/N]
  }
  throw InputError("validation: no floor for the simulator's '" + kind + "'");
}

double simulator_floor(const std::string& kind, const FloorContext& c, const std::string& shape_name) {
  const auto effect = EffectLibrary::standard().find(kind);
  if (!effect) return yardstick_floor(kind, c, shape_name);
  const double floor = effect->floor(c).amount;
  if (kind == "force_offset") return floor / std::sqrt(2.0);             // the sim's amount is per axis
  if (kind == "stribeck_friction") return floor / c.friction_coefficient;  // the sim's is relative to mu
  if (kind == "support_tilt") {  // the candidate's |f| [N] as the tilt whose downhill force it is [deg]
    const double weight = ShapeTable::published().find(shape_name).mass_kg * kGravity_m_s2;
    return std::asin(std::min(1.0, floor / weight)) * 180 / M_PI;
  }
  if (kind == "anisotropic_friction") return floor / c.friction_coefficient;  // k / mu = |A - 1|
  if (kind == "position_friction") {
    // The patch (a disk of radius kFrictionPatchRadius_m) carries at most its share of the footprint's load: its relative
    // excess must be kappa over that share to change the friction force by kappa.
    const ShapeInfo& shape = ShapeTable::published().find(shape_name);
    const double area = make_footprint(Outline(shape)).total_area_m2;
    const double share = std::min(1.0, M_PI * kFrictionPatchRadius_m * kFrictionPatchRadius_m / area);
    return c.relevance_fraction / share;
  }
  return floor;  // time_offset [s], viscous_friction [1/s], com_offset [m], inertia_mismatch |factor - 1|
}

FloorContext measured_floor_context(const std::vector<SynchronisedPush>& pushes, const DiagnosisOptions& options) {
  const PaperMethodOutcome paper = paper_method(split_pushes(pushes, EffectLibrary::standard(), options));
  return friction_base(paper.context, paper.model).floors;
}

double patch_gradient_per_excess(const std::vector<SimulatedPush>& sims, double onset_m) {
  // Least squares of the patch's force per unit excess on the candidate's two friction columns, the Coulomb law
  // (mu, which takes the mean) and the travel times it (g) less its mean over the push's sliding samples, as the
  // candidate's regressor is (builtin_effects.cpp), over the samples where the object slides.
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d right = Eigen::Vector2d::Zero();
  for (const SimulatedPush& sim : sims) {
    const ShapeInfo& shape = ShapeTable::published().find(sim.scenario.shape);
    const FrictionFootprint footprint = FrictionFootprint::of(shape);
    const Eigen::MatrixX3d patch = patch_wrench_per_excess(sim);
    std::vector<Eigen::Index> rows;
    Eigen::MatrixX2d coulomb(sim.t_s.size(), 2), ramp(sim.t_s.size(), 2);
    Eigen::RowVector2d ramp_sum = Eigen::RowVector2d::Zero();
    for (Eigen::Index k = 0; k < sim.t_s.size(); ++k) {
      const Eigen::Vector3d pose = sim.tracked_pose.row(k).transpose();
      const Eigen::Vector3d velocity = sim.mass_centre_velocity.row(k).transpose();
      if (sliding_speed(velocity, shape) < kSlidingSpeed_m_s) continue;
      const double travelled = position_friction_travel(pose, sim.tracked_pose.row(0).transpose(), onset_m);
      coulomb.row(k) = coulomb_friction_wrench(pose, velocity, shape, footprint).head<2>().transpose();
      ramp.row(k) = travelled * coulomb.row(k);
      ramp_sum += ramp.row(k);
      rows.push_back(k);
    }
    if (rows.empty()) continue;
    const Eigen::RowVector2d ramp_mean = ramp_sum / static_cast<double>(rows.size());
    for (Eigen::Index k : rows) {
      Eigen::Matrix2d columns;
      columns << coulomb.row(k).transpose(), (ramp.row(k) - ramp_mean).transpose();
      normal += columns.transpose() * columns;
      right += columns.transpose() * patch.row(k).head<2>().transpose();
    }
  }
  if (!(normal.determinant() > 1e-12 * normal.squaredNorm())) return 0;
  return normal.ldlt().solve(right)(1);
}

namespace {

/// The pushes of `scenarios` simulated (the truth) and as the diagnosis reads them.
struct SimulatedTrial {
  std::vector<SimulatedPush> sims;
  std::vector<SynchronisedPush> pushes;
};
SimulatedTrial simulate_with_truth(const std::vector<PushScenario>& scenarios) {
  SimulatedTrial t;
  for (const auto& s : scenarios) {
    t.sims.push_back(simulate_push(s));
    t.pushes.push_back(synchronise(as_read(t.sims.back().recording), ShapeTable::published().find(s.shape)));
  }
  return t;
}

}  // namespace

double measured_simulator_floor(const std::string& kind, const std::vector<PushScenario>& clean,
                                const DiagnosisOptions& options, const std::string& shape) {
  double floor = kNaN;
  try {
    const SimulatedTrial simulated = simulate_with_truth(clean);
    const FloorContext context = measured_floor_context(simulated.pushes, options);
    if (kind == "position_friction") {
      // The patch's excess at which the candidate's own measure, the gradient g along the travel (in mu's unit per
      // metre), is at its floor.
      const double per_excess = patch_gradient_per_excess(simulated.sims, 0.0);  // the floor's onset
      const auto effect = EffectLibrary::standard().find(kind);
      if (per_excess > 1e-6) floor = effect->floor(context).amount / per_excess;
    } else {
      floor = simulator_floor(kind, context, shape);
    }
  } catch (const std::exception&) {
    // no measured floor (e.g. the friction law not identifiable): the scenario's, below
  }
  // Infinite for Stribeck friction: the diagnosis itself says no amount matters on these pushes (the object never
  // slides slowly); kept, so that such a trial is never counted at twice its floor. Other kinds' infinite floors
  // mean "unknown" (unknown_floor): the scenario's, below.
  if (floor > 0 && (std::isfinite(floor) || kind == "stribeck_friction")) return floor;
  return simulator_floor(kind, scenario_floor_context(clean, options.relevance_fraction), shape);
}

std::vector<PushScenario> draw_validation_trial(const ValidationOptions& o, int index, const std::string& kind,
                                                ValidationTrial& trial) {
  const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(index);
  std::mt19937_64 rng(seed);
  trial.index = index;
  trial.seed = seed;
  trial.true_kind = kind;
  trial.shape = pick(rng, kShapes);
  trial.surface_friction = uniform(rng, 0.2, 0.6);
  trial.contact_friction = uniform(rng, 0.1, 0.4);
  trial.contact_stiffness_N_m = std::exp(uniform(rng, std::log(5e3), std::log(3e4)));
  trial.pressure_rim_weight = uniform(rng, -0.3, 0.6);
  trial.pushes = std::uniform_int_distribution<int>(o.min_pushes, o.max_pushes)(rng);
  // The start of each push, the sensor's offsets and the support's tilt direction come from a generator of their
  // own, so that the rest of a trial is drawn as without them.
  std::mt19937_64 start_rng(seed ^ 0x9E3779B97F4A7C15ULL);
  // One support for the trial: the downhill direction of a tilt (used only when the kind is support_tilt).
  const double downhill_rad = uniform(start_rng, -M_PI, M_PI);
  trial.preloaded_pushes = 0;
  const ShapeInfo& shape_info = ShapeTable::published().find(trial.shape);
  const double friction_force_N = trial.surface_friction * shape_info.mass_kg * kGravity_m_s2;
  const int sides = Outline(ShapeTable::published().find(trial.shape)).side_count();
  std::vector<PushScenario> out;
  for (int k = 0; k < trial.pushes; ++k) {
    PushScenario s;
    s.name = "validation trial " + std::to_string(index) + " push " + std::to_string(10 + k);
    s.shape = trial.shape;
    s.surface_friction = trial.surface_friction;
    s.contact_friction = trial.contact_friction;
    s.contact_stiffness_N_m = trial.contact_stiffness_N_m;
    s.pressure_rim_weight = trial.pressure_rim_weight;
    if (uniform(rng, 0, 1) < 0.3) {
      s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
      s.motion.acceleration_m_s2 = pick(rng, kAccelerations_m_s2);
    } else {
      s.motion.speed_m_s = pick(rng, kSpeeds_m_s);
    }
    s.motion.length_m = uniform(rng, 0.025, 0.05);
    s.contact_side = std::uniform_int_distribution<int>(0, sides - 1)(rng);
    s.contact_position = uniform(rng, 0.25, 0.75);
    s.push_angle_rad = uniform(rng, -0.35, 0.35);
    s.initial_yaw_rad = uniform(rng, -M_PI, M_PI);
    s.seed = rng();
    s.support_tilt_direction_rad = downhill_rad;
    // The real pushes start pressed with up to 3.7 N, or a gap away; a sensor may not be zeroed between pushes. Both
    // are drawn every time, whether used or not, so that switching one off leaves the other's draws as they were.
    const bool pressed = uniform(start_rng, 0, 1) < 0.5;
    const double preload_N = uniform(start_rng, 0.3, std::max(0.3, std::min(3.7, 0.7 * friction_force_N)));
    const double gap_m = uniform(start_rng, 0.0005, 0.002);
    std::normal_distribution<double> offset(0.0, o.sensor_offset_spread_N);
    const Eigen::Vector2d offset_N(offset(start_rng), offset(start_rng));
    if (o.draw_preloads) {
      s.approach_gap_m = pressed ? std::max(-0.001, -preload_N / s.contact_stiffness_N_m) : gap_m;
      trial.preloaded_pushes += pressed;
    }
    if (o.draw_sensor_offsets) s.sensors.push_offset_N = offset_N;
    out.push_back(s);
  }
  if (kind != "none") {
    // The floor the diagnosis itself would state on these pushes: measured on the clean pushes (same scenarios and
    // noise seeds, no effect) by the diagnosis's own first steps. The scenario's nominal physics (the pusher's peak
    // ramp acceleration, its cruise speed) can differ from what the object does by several times, and then an
    // amount "at twice the floor" would be below the floor the diagnosis measures.
    trial.floor = measured_simulator_floor(kind, out, o.diagnosis, trial.shape);
    trial.floor_multiple = uniform(rng, o.min_floor_multiple, o.max_floor_multiple);
    const double sign =
        kind == "force_offset" || kind == "com_offset" || kind == "inertia_mismatch" || kind == "anisotropic_friction"
            ? (uniform(rng, 0, 1) < 0.5 ? -1.0 : 1.0)
            : 1.0;
    // The simulator's amount for a size in the diagnosis's measure (|factor - 1| for the mass, |A - 1| for the
    // friction's anisotropy: the ratio (1 + a) / (1 - a) along the body axes or its inverse).
    const auto simulator_amount = [&](double size) {
      if (kind == "inertia_mismatch") return 1 + sign * size;
      if (kind == "anisotropic_friction") return sign > 0 ? (1 + size) / (1 - size) : (1 - size) / (1 + size);
      return sign * size;
    };
    // A mass factor of 0.5 at the least and 4 at the most: inside the diagnosis's plausible range (0.2-5), where the
    // floor is large (an object that hardly accelerates) the drawn multiple of the floor is then smaller. Friction at
    // rest at most twice the sliding friction (a Stribeck excess of 1): where the pushes spend too little time at low
    // speed for the term to matter below that, the drawn multiple is smaller, below 2 floors or below 1, and the
    // trial is not one the detection target counts. Likewise a drag at most the support's friction at the pushes'
    // typical speed (c <= mu g / v), and a patch with at most four times the support's friction.
    const double typical_speed_m_s = scenario_floor_context(out, o.diagnosis.relevance_fraction).sliding_speed_m_s;
    const double max_drag_1_s = typical_speed_m_s > 0
                                    ? trial.surface_friction * kGravity_m_s2 / typical_speed_m_s
                                    : std::numeric_limits<double>::infinity();
    const auto capped = [&](double size) {
      if (kind == "inertia_mismatch") return std::min(size, sign < 0 ? 0.5 : 3.0);
      if (kind == "stribeck_friction") return std::min(size, kMaxStribeckExcess);
      if (kind == "viscous_friction") return std::min(size, max_drag_1_s);
      if (kind == "position_friction") return std::min(size, kMaxPatchExcess);
      if (kind == "support_tilt")
        return std::min(size, kMaxTiltShareOfFrictionAngle * std::atan(trial.surface_friction) * 180 / M_PI);
      if (kind == "anisotropic_friction") return std::min(size, kMaxAnisotropy);
      if (kind == "compliant_pusher") return std::min(size, kMaxCompliance_m_N);
      return size;
    };
    double size = capped(std::isfinite(trial.floor) ? trial.floor_multiple * trial.floor : kMaxStribeckExcess);
    // A friction law or a wrong mass changes how the object moves, and with it the speeds, accelerations and travel
    // its floor is measured on: Stribeck friction turns slow sliding into stick-slip, so the pushes that carry it
    // spend less time sliding slowly than the clean ones; a heavier object accelerates less. The floor the diagnosis
    // states is the one on the data it is given, so the amount is set to the drawn multiple of the floor measured
    // on the pushes with the effect (a fixed point, a few rounds; the trial's floor is the one at the final amount).
    if (kind == "viscous_friction" || kind == "stribeck_friction" || kind == "position_friction" ||
        kind == "inertia_mismatch") {
      double measured_at = std::numeric_limits<double>::quiet_NaN();  // the amount trial.floor was measured at
      const auto measure_at = [&](double amount) {
        std::vector<PushScenario> with = out;
        for (auto& s : with) s.effects.set(kind, simulator_amount(amount));
        trial.floor = measured_simulator_floor(kind, with, o.diagnosis, trial.shape);
        measured_at = amount;
      };
      for (int round = 0; round < kFloorRounds; ++round) {
        measure_at(size);
        if (!std::isfinite(trial.floor)) break;
        const double next = capped(trial.floor_multiple * trial.floor);
        const bool settled = std::abs(next - size) <= 0.05 * size;
        size = next;
        if (settled) break;
      }
      if (size != measured_at) measure_at(size);
    }
    trial.amount = simulator_amount(size);
    trial.floor_multiple = size / trial.floor;
    for (auto& s : out) s.effects.set(kind, trial.amount);
  }
  return out;
}

namespace {

/// The diagnosis's amount of `kind` in the simulator's unit.
double fitted_in_simulator_units(const EffectReport& e, const ValidationTrial& trial) {
  const std::string& kind = trial.true_kind;
  const double mu = trial.surface_friction;
  if (e.theta.size() == 0) return kNaN;
  if (kind == "force_offset") return e.theta.size() >= 2 ? 0.5 * (e.theta(0) + e.theta(1)) : kNaN;
  if (kind == "stribeck_friction") return e.theta(0) / mu;
  if (kind == "position_friction") return kNaN;  // needs the simulated states: fitted_patch_excess
  if (kind == "inertia_mismatch") return 1 + e.theta(0);
  if (kind == "support_tilt") return kNaN;  // a force [N] against a tilt [deg]: compared through the floor only
  if (kind == "anisotropic_friction") {     // k = mu (r - 1) / (r + 1): the ratio r = (mu + k) / (mu - k)
    return mu > std::abs(e.theta(0)) ? (mu + e.theta(0)) / (mu - e.theta(0)) : kNaN;
  }
  return e.theta(0);  // time_offset, viscous_friction, com_offset (delta_x)
}

/// The patch's excess whose friction gradient along the travel of `sims`, from the onset the diagnosis chose, is
/// the one it found (NaN when position_friction was not found): the fit in the simulator's unit.
double fitted_patch_excess(const DiagnosisResult& r, const std::vector<SimulatedPush>& sims) {
  for (const auto& e : r.effects) {
    if (e.kind != "position_friction" || !e.selected || e.theta.size() == 0) continue;
    const double per_excess = patch_gradient_per_excess(sims, e.setting);
    return per_excess > 1e-9 ? e.theta(0) / per_excess : kNaN;
  }
  return kNaN;
}

/// The diagnosis's model-adequacy verdict (DiagnosisResult::adequacy).
void read_adequacy(const DiagnosisResult& r, ValidationTrial& trial) {
  trial.adequacy_tested = r.adequacy.tested;
  trial.explained = r.adequacy.explained;
}

void run_trial(const ValidationOptions& o, ValidationTrial& trial, const std::string& kind) {
  try {
    const std::vector<PushScenario> scenarios = draw_validation_trial(o, trial.index, kind, trial);
    const EffectLibrary library = validation_library(o);
    trial.hidden = kind != "none" && !library.find(kind);
    const SimulatedTrial simulated = simulate_with_truth(scenarios);
    const DiagnosisResult result = diagnose(simulated.pushes, library, o.diagnosis);
    score_trial(result, trial);
    if (kind == "position_friction") trial.fitted_amount = fitted_patch_excess(result, simulated.sims);
  } catch (const std::exception& e) {
    trial.failure = e.what();
  }
}

}  // namespace

std::vector<SynchronisedPush> simulate_trial(const std::vector<PushScenario>& scenarios) {
  std::vector<SynchronisedPush> pushes;
  for (const auto& s : scenarios)
    pushes.push_back(synchronise(as_read(simulate_push(s).recording), ShapeTable::published().find(s.shape)));
  return pushes;
}

void score_trial(const DiagnosisResult& r, ValidationTrial& trial) {
  const std::string& kind = trial.true_kind;
  trial.named.clear();
  trial.negligible.clear();
  trial.fitted_amount = kNaN;
  trial.true_score = trial.true_amount = trial.true_floor = kNaN;
  trial.true_passed = trial.true_negligible = false;
  trial.true_note.clear();
  for (const auto& e : r.effects) {
    if (e.structural) continue;
    if (e.selected) trial.named.push_back(e.kind);
    if (e.negligible) trial.negligible.push_back(e.kind);
    if (e.kind == kind && e.selected) trial.fitted_amount = fitted_in_simulator_units(e, trial);
    if (e.kind == kind) {
      trial.true_score = e.score;
      trial.true_passed = e.passed_test;
      trial.true_negligible = e.negligible;
      trial.true_amount = e.amount;
      trial.true_floor = e.floor.amount;
      trial.true_note = e.note;
    }
  }
  trial.true_named = kind == "none" ? trial.named.empty()
                                    : std::find(trial.named.begin(), trial.named.end(), kind) != trial.named.end();
  read_adequacy(r, trial);
  trial.before = r.error_before;
  trial.base = r.error_base;
  trial.after = r.error_after;
  trial.hold = r.hold;
  trial.const_velocity = r.const_velocity;
  trial.quasi_static = r.quasi_static;
}

int validation_trial_count(const ValidationOptions& options) {
  const std::size_t kinds = validation_kinds(options).size();
  return options.trials_per_kind * static_cast<int>(kinds);
}

ValidationResult validate_diagnosis(const ValidationOptions& options, const std::function<void(int, int)>& progress) {
  std::vector<int> all(static_cast<std::size_t>(std::max(0, validation_trial_count(options))));
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  return validate_diagnosis_trials(options, all, progress);
}

ValidationResult validate_diagnosis_trials(const ValidationOptions& options, const std::vector<int>& indices,
                                           const std::function<void(int, int)>& progress) {
  options.validate();
  ValidationResult result;
  result.options = options;
  result.options.kinds = validation_kinds(options);
  const auto& kinds = result.options.kinds;
  const int count = validation_trial_count(result.options);
  for (int k : indices)
    if (k < 0 || k >= count)
      throw InputError("validation: trial " + std::to_string(k) + " is not one of the run's " + std::to_string(count));
  const int total = static_cast<int>(indices.size());
  result.trials.resize(indices.size());
  // Trials interleave the kinds (index k draws kinds[k % K]), so a run cut short still covers every kind.
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  parallel_for_index(indices.size(), options.jobs, [&](std::size_t j) {
    ValidationTrial& t = result.trials[j];
    const int k = indices[j];
    t.index = k;
    run_trial(result.options, t, kinds[static_cast<std::size_t>(k) % kinds.size()]);
    const int d = ++done;
    if (progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress(d, total);
    }
  });
  return result;
}

ValidationSummary summarise_validation(const ValidationResult& r) {
  ValidationSummary s;
  for (const auto& t : r.trials) {
    ++s.trials;
    if (!t.failure.empty()) {
      ++s.failed;
      continue;
    }
    if (t.true_kind == "none") {
      ++s.clean_trials;
      s.clean_nothing_named += t.named.empty();
      s.clean_adequacy_tested += t.adequacy_tested;
      s.clean_explained += t.adequacy_tested && t.explained;
    } else if (t.floor_multiple >= 2 && t.hidden) {
      ++s.hidden_trials_at_twice_floor;
      s.hidden_adequacy_tested += t.adequacy_tested;
      s.hidden_unexplained += t.adequacy_tested && !t.explained;
      s.hidden_none_named += t.named.empty();
    } else if (t.floor_multiple >= 2) {
      ++s.effect_trials_at_twice_floor;
      s.named_at_twice_floor += t.true_named;
    }
    ++s.compared;
    s.after_below_paper += t.after.pos_mm_mean < t.before.pos_mm_mean;
    s.after_below_const_velocity += t.after.pos_mm_mean < t.const_velocity.pos_mm_mean;
  }
  return s;
}

}  // namespace pushpred
