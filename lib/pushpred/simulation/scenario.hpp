#pragma once
// What to simulate: object, surface, push (speed or acceleration, contact side and position, angle, length),
// seed, sensor realism, and hidden physical effects. Read from a small JSON file (data/paper/case*.json are
// the paper's six cases, compiled into the library) or built in code; docs/simulator.md lists every field.
//
// Effects are physics the toolkit is meant to discover; they change the simulated recording but are never
// written into it (the file name carries only the push parameters, as a real file's does). Names and units:
//   time_offset        [s]      the force stream lags the pose streams: the force stamped t is the one at t - amount
//   force_offset       [N]      sensor bias added to every fx and fy reading (visible while not touching)
//   viscous_friction   [1/s]    extra drag -amount m v and -amount I omega (N s/m per kg of object)
//   stribeck_friction  [-]      mu(v) = mu (1 + amount exp(-(v / 0.01 m/s)^2)) for each footprint element
//   position_friction  [-]      mu (1 + amount) inside a disk on the push line (friction_patch_radius_m, 2 cm by
//                               default), centred friction_patch_ahead_m (2.5 cm) beyond the object's leading point
//                               at the start (the object runs onto it)
//   com_offset         [m]      the mass centre sits `amount` along the body x axis from its nominal place
//                               (pressure shifts with it); inertia about the mass centre unchanged
//   inertia_mismatch   [-]      true mass and inertia are `amount` times the shape table's (weight too)
//   support_tilt       [deg]    the support is tilted by `amount` downhill along support_tilt_direction_rad (world):
//                               a constant force m g sin(alpha) on the mass centre, the normal load m g cos(alpha)
//   anisotropic_friction [-]    the support's mu along the body x axis is `amount` times that along body y, their
//                               mean kept at mu (elliptic Coulomb friction, maximum dissipation)
//   compliant_pusher   [m/N]    the tip is a spring of compliance `amount` behind the recorded (commanded) path:
//                               the contact lags the recorded tip by f x amount
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/reading/recording.hpp"
#include "pushpred/simulation/pusher_path.hpp"

namespace pushpred {

/// The position_friction patch's default place: a disk of this radius on the push line, its centre this far beyond
/// the object's leading point at the start [m] (PushScenario::friction_patch_radius_m, friction_patch_ahead_m).
inline constexpr double kFrictionPatchRadius_m = 0.02;
inline constexpr double kFrictionPatchAhead_m = 0.025;

/// How a scenario's fields are named in its errors, by JSON key ("contact_friction", "sensors.noise_scale",
/// "effects"): a command line names them by the flags that set them.
using ScenarioFieldNames = std::map<std::string, std::string>;

/// The largest sensor bias of the effect force_offset and of a push's own sensor zero error [N]: 200 times the
/// rig's push-to-push spread of the zero (0.1 N).
inline constexpr double kMaxForceOffset_N = 20;
/// The largest viscous drag of the effect viscous_friction [1/s]: 10 N per kg at 1 mm/s, the Coulomb friction of a
/// friction coefficient of 1 on an object crawling at a tenth of the dataset's slowest push (10 mm/s).
inline constexpr double kMaxViscousFriction_1_s = 1e4;
/// The largest scale on the rig's measured sensor noise: a hundred times (0.1 mm of pose noise becomes 1 cm).
inline constexpr double kMaxSensorNoiseScale = 100;

/// A random seed from its decimal text: a whole number from 0 to 2^64 - 1; InputError "must be a whole number from
/// 0 to 18446744073709551615, got '-1'" otherwise (no sign, no wrap-around, no exponent).
std::uint64_t parse_seed(const std::string& text);

struct EffectInfo {
  std::string name;
  std::string unit;
  double neutral = 0;  ///< the amount that means "no effect"
  std::string meaning;
};
/// Every effect the simulator knows, in a fixed order.
const std::vector<EffectInfo>& effect_catalogue();
/// The effect called `name`; throws InputError "unknown effect 'x' (known: ...)".
const EffectInfo& effect_info(const std::string& name);
/// Parses "NAME=AMOUNT"; throws InputError naming the text when malformed, unknown or not a number.
std::pair<std::string, double> parse_effect_assignment(const std::string& text);

struct Effects {
  double time_offset_s = 0;
  double force_offset_N = 0;
  double viscous_per_kg = 0;  ///< [1/s]
  double stribeck_excess = 0;
  double position_friction_excess = 0;
  double com_offset_m = 0;
  double inertia_factor = 1;
  double support_tilt_deg = 0;       ///< [deg] (only reports use degrees; the physics takes radians)
  double friction_anisotropy = 1;    ///< mu_x / mu_y in the body frame
  double pusher_compliance_m_N = 0;  ///< [m/N]; 0: the tip follows its path rigidly

  /// Sets the effect `name` to `amount`; throws InputError for an unknown name or an amount out of range.
  void set(const std::string& name, double amount);
  double get(const std::string& name) const;
  /// The effects with a non-neutral amount, by name.
  std::vector<std::pair<std::string, double>> active() const;
};

/// How realistic the sensors are: scales on the measured noise and on the measured clock jitter (0 = ideal).
struct SensorRealism {
  double noise_scale = 1.0;
  double jitter_scale = 1.0;
  /// The force sensor's own zero error on this push, added to fx and fy [N] (robot frame). The real sensor is not
  /// zeroed between pushes: its reading with nothing touching differs from push to push (docs/simulator.md).
  Eigen::Vector2d push_offset_N = Eigen::Vector2d::Zero();
};

struct PushScenario {
  std::string name;  ///< a label, e.g. "paper case 1"
  std::string shape = "rect2";
  std::string surface = "abs";  ///< only goes into the file name
  /// Coulomb mu, object on surface. 0.47 is the abs value at which clean simulations of the real pushes match
  /// their measured force level (docs/simulator.md); the paper quotes 0.13-0.15 for abs.
  double surface_friction = 0.47;
  double contact_friction = 0.25;  ///< Coulomb mu, rod on object
  /// Stiffness of the rod contact (arm, sensor and contact together) [N/m]; docs/simulator.md.
  double contact_stiffness_N_m = 1e4;
  /// Shape of the support pressure: 0 uniform (then tilted under the mass centre); w > 0 loads the rim more (a
  /// slightly concave base), w < 0 the middle (a convex one): p ~ 1 + w (|r - c|^2 / <|r - c|^2> - 1). Range
  /// [-0.5, 1]. It changes the friction torque for a given force, which real objects show.
  double pressure_rim_weight = 0;
  PusherMotion motion;  ///< speed or acceleration, length, ramp
  int contact_side = 0;
  double contact_position = 0.5;  ///< 0..1 along the side
  double push_angle_rad = 0;      ///< push direction = inward normal rotated counter-clockwise by this
  /// Rod surface to outline at the start; negative: the rod starts pressed into the object by that much, a
  /// preload of stiffness x |gap| (1e4 N/m: 0.0002 m is 2 N), as in many real files.
  double approach_gap_m = 0.001;
  /// The downhill direction of a tilted support (effect support_tilt), as an angle from the robot's x axis [rad].
  double support_tilt_direction_rad = 0;
  /// The patch of the effect position_friction: a disk of this radius [m] on the push line, its centre this far
  /// beyond the object's leading point at the start [m]. A larger patch carries more of the footprint.
  double friction_patch_radius_m = kFrictionPatchRadius_m;
  double friction_patch_ahead_m = kFrictionPatchAhead_m;
  double initial_x_m = 0.35, initial_y_m = 0.0, initial_yaw_rad = 0.0;  ///< tracked centre, robot frame
  double rest_before_s = 0.18;                                          ///< recording before the rod moves
  double rest_after_s = 0.27;                                           ///< recording after the rod stops
  double start_unix_s = 1.6e9;  ///< Unix time of the force stream's first sample
  std::uint64_t seed = 1;
  Effects effects;
  SensorRealism sensors;

  /// The dataset's push parameters (speed -0.001 m/s for an acceleration push, as in the dataset).
  PushParameters push_parameters() const;
  /// Throws InputError naming the first field out of range (shape unknown or without outline, side, ...): by its
  /// JSON key ("contact_friction: must be a finite number in [0, 10], got inf"), or by what `names` says set it
  /// (simulate's flags: {"contact_friction", "--contact-mu"}).
  void validate(const ScenarioFieldNames& names = {}) const;
};

/// A scenario from JSON; unknown keys, wrong types and bad values are InputError prefixed by `source`.
PushScenario scenario_from_json(const nlohmann::json& json, const std::string& source);
PushScenario read_scenario_file(const std::filesystem::path& path);
nlohmann::json scenario_to_json(const PushScenario& scenario);

/// The paper's case n (1..6) of Table I: rect2 on abs, compiled in from data/paper/case<n>.json. Throws
/// InputError for another n.
PushScenario paper_case_scenario(int n);

}  // namespace pushpred
