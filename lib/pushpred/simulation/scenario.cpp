#include "pushpred/simulation/scenario.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/reading/physical_bounds.hpp"
#include "pushpred/reading/shape_table.hpp"

namespace pushpred {
namespace detail {
extern const char* const kPaperCaseJson[6];
}

namespace {

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

}  // namespace

const std::vector<EffectInfo>& effect_catalogue() {
  static const std::vector<EffectInfo> catalogue = {
      {"time_offset", "s", 0.0, "force stream lags the pose streams: the force stamped t is the force at t - amount"},
      {"force_offset", "N", 0.0, "sensor bias added to every fx and fy reading, visible while not touching"},
      {"viscous_friction", "1/s", 0.0, "extra drag -amount*m*v and -amount*I*omega (N s/m per kg of object)"},
      {"stribeck_friction", "-", 0.0, "mu(v) = mu*(1 + amount*exp(-(v/0.01 m/s)^2)) per footprint element"},
      {"position_friction", "-", 0.0,
       "mu*(1 + amount) inside a disk of radius 0.02 m on the push line, centred 0.025 m beyond the object's "
       "leading point at the start (the object runs onto it)"},
      {"com_offset", "m", 0.0, "mass centre moved by amount along the body x axis; pressure follows it"},
      {"inertia_mismatch", "-", 1.0, "true mass and inertia are amount times the shape table's (weight too)"},
      {"support_tilt", "deg", 0.0,
       "the support is tilted by amount degrees, downhill along support_tilt_direction_rad (robot frame): a constant "
       "force m g sin(alpha) on the mass centre, normal load m g cos(alpha)"},
      {"anisotropic_friction", "-", 1.0,
       "support friction along the body x axis is amount times that along body y, their mean kept at mu (elliptic "
       "Coulomb friction)"},
      {"compliant_pusher", "m/N", 0.0,
       "the tip is a spring of compliance amount behind the recorded (commanded) path: the contact lags it by "
       "f x amount"},
  };
  return catalogue;
}

const EffectInfo& effect_info(const std::string& name) {
  for (const auto& e : effect_catalogue())
    if (e.name == name) return e;
  std::string known;
  for (const auto& e : effect_catalogue()) known += (known.empty() ? "" : ", ") + e.name;
  throw InputError("unknown effect '" + name + "' (known: " + known + ")");
}

std::pair<std::string, double> parse_effect_assignment(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError("effect '" + text + "' is not NAME=AMOUNT");
  const std::string name = text.substr(0, eq), amount_text = text.substr(eq + 1);
  effect_info(name);
  double amount = 0;
  try {
    size_t used = 0;
    amount = std::stod(amount_text, &used);
    if (used != amount_text.size()) throw std::invalid_argument(amount_text);
  } catch (const std::exception&) {
    throw InputError("effect '" + text + "': '" + amount_text + "' is not a number");
  }
  if (!std::isfinite(amount)) throw InputError("effect '" + text + "': amount must be finite");
  return {name, amount};
}

void Effects::set(const std::string& name, double amount) {
  effect_info(name);
  const std::string where = "effect " + name + "=" + number_text(amount) + ": ";
  require(std::isfinite(amount), where + "amount must be finite");
  if (name == "time_offset") {
    require(std::abs(amount) <= 1.0, where + "a time offset beyond 1 s is not a plausible sensor delay");
    time_offset_s = amount;
  } else if (name == "force_offset") {
    require(std::abs(amount) <= kMaxForceOffset_N,
            where + "a sensor bias beyond 20 N is not a force sensor's zero error (the rig's spread: 0.1 N)");
    force_offset_N = amount;
  } else if (name == "viscous_friction") {
    require(amount >= 0 && amount <= kMaxViscousFriction_1_s,
            where +
                "viscous friction must be in [0, 1e4] 1/s (1e4: a drag of 10 N per kg at 1 mm/s, the support "
                "friction of a friction coefficient of 1)");
    viscous_per_kg = amount;
  } else if (name == "stribeck_friction") {
    require(amount >= 0 && amount <= kMaxFrictionCoefficient,
            where +
                "the static excess of Stribeck friction must be in [0, 10] (friction at rest at most 11 times "
                "the sliding friction)");
    stribeck_excess = amount;
  } else if (name == "position_friction") {
    require(amount > -1 && amount <= kMaxFrictionCoefficient,
            where +
                "the patch's friction change must be in (-1, 10] (friction stays positive, at most 11 times the "
                "support's)");
    position_friction_excess = amount;
  } else if (name == "com_offset") {
    require(std::abs(amount) < 0.05, where + "a mass-centre offset of 5 cm or more leaves the object's footprint");
    com_offset_m = amount;
  } else if (name == "inertia_mismatch") {
    require(amount >= 0.1 && amount <= 10,
            where +
                "the mass and inertia factor must be in [0.1, 10] (an object a tenth to ten times as heavy as "
                "its table entry)");
    inertia_factor = amount;
  } else if (name == "support_tilt") {
    require(amount >= 0 && amount <= 20, where +
                                             "the support's tilt must be in [0, 20] degrees (the direction is "
                                             "support_tilt_direction_rad)");
    support_tilt_deg = amount;
  } else if (name == "anisotropic_friction") {
    require(amount >= 0.2 && amount <= 5, where + "the friction ratio along the body axes must be in [0.2, 5]");
    friction_anisotropy = amount;
  } else if (name == "compliant_pusher") {
    require(amount >= 0 && amount <= 0.01,
            where + "the pusher's compliance must be in [0, 0.01] m/N (0.01 m/N: 1 cm of lag per newton)");
    pusher_compliance_m_N = amount;
  }
}

double Effects::get(const std::string& name) const {
  effect_info(name);
  if (name == "time_offset") return time_offset_s;
  if (name == "force_offset") return force_offset_N;
  if (name == "viscous_friction") return viscous_per_kg;
  if (name == "stribeck_friction") return stribeck_excess;
  if (name == "position_friction") return position_friction_excess;
  if (name == "com_offset") return com_offset_m;
  if (name == "support_tilt") return support_tilt_deg;
  if (name == "anisotropic_friction") return friction_anisotropy;
  if (name == "compliant_pusher") return pusher_compliance_m_N;
  return inertia_factor;
}

std::vector<std::pair<std::string, double>> Effects::active() const {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& e : effect_catalogue())
    if (get(e.name) != e.neutral) out.emplace_back(e.name, get(e.name));
  return out;
}

PushParameters PushScenario::push_parameters() const {
  PushParameters p;
  p.surface = surface;
  p.shape = shape;
  if (motion.profile == PusherMotion::Profile::ConstantAcceleration) {
    p.acceleration_m_s2 = motion.acceleration_m_s2;
    p.speed_m_s = -0.001;  // the dataset's marker of an acceleration push
  } else {
    p.acceleration_m_s2 = 0;
    p.speed_m_s = motion.speed_m_s;
  }
  p.contact_side = contact_side;
  p.contact_position = contact_position;
  p.angle_rad = push_angle_rad;
  return p;
}

void PushScenario::validate(const ScenarioFieldNames& names) const {
  // Each problem is named by the field's JSON key, or by what the caller says set it (a flag: "--contact-mu").
  const auto label = [&](const std::string& field) {
    const auto it = names.find(field);
    return it != names.end() ? it->second : field;
  };
  const auto in_range = [&](const std::string& field, double value, bool ok, const std::string& range) {
    if (!ok || !std::isfinite(value))
      throw InputError(label(field) + ": must be " + range + ", got " + number_text(value));
  };
  const ShapeInfo& s = [&]() -> const ShapeInfo& {
    try {
      return ShapeTable::known().find(shape);
    } catch (const InputError& e) {
      throw InputError(label("shape") + ": " + e.what());
    }
  }();
  require(s.has_outline(),
          label("shape") + ": shape '" + shape + "' has no outline in the shape table and cannot be simulated");
  require(
      !surface.empty() && surface.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789") ==
                              std::string::npos,
      label("surface") + ": surface name '" + surface + "' must be letters and digits (it goes into the file name)");
  check_friction_coefficient(surface_friction, label("surface_friction"), false);
  check_friction_coefficient(contact_friction, label("contact_friction"), true);
  in_range("contact_stiffness_N_m", contact_stiffness_N_m, contact_stiffness_N_m >= 1e3 && contact_stiffness_N_m <= 1e6,
           "in [1e3, 1e6] N/m");
  in_range("pressure_rim_weight", pressure_rim_weight, pressure_rim_weight >= -0.5 && pressure_rim_weight <= 1,
           "in [-0.5, 1]");
  if (motion.profile == PusherMotion::Profile::ConstantSpeed)
    in_range("speed_m_s", motion.speed_m_s, motion.speed_m_s > 0 && motion.speed_m_s <= 2.0,
             "a push speed in (0, 2] m/s");
  else
    in_range("acceleration_m_s2", motion.acceleration_m_s2,
             motion.acceleration_m_s2 > 0 && motion.acceleration_m_s2 <= 50.0, "a push acceleration in (0, 50] m/s^2");
  in_range("push_length_m", motion.length_m, motion.length_m > 0 && motion.length_m <= 1.0,
           "a push length in (0, 1] m");
  in_range("ramp_s", motion.ramp_s, motion.ramp_s > 0 && motion.ramp_s <= 2.0, "a speed ramp in (0, 2] s");
  in_range("contact_position", contact_position, contact_position >= 0 && contact_position <= 1,
           "a place along the side in [0, 1]");
  try {
    Outline(s).point_on_side(contact_side, contact_position);  // throws for a side out of range
  } catch (const InputError& e) {
    throw InputError(label("contact_side") + ": " + e.what());
  }
  in_range("push_angle_rad", push_angle_rad, std::abs(push_angle_rad) < M_PI / 2,
           "within (-pi/2, pi/2) rad of the inward normal, or the rod moves away from the object");
  in_range("approach_gap_m", approach_gap_m, approach_gap_m >= -0.001 && approach_gap_m <= 0.05,
           "a gap in [-0.001, 0.05] m (negative: a preload, at most 1 mm deep)");
  require(std::isfinite(initial_x_m) && std::isfinite(initial_y_m) && std::isfinite(initial_yaw_rad),
          label("initial_pose") + ": must be finite");
  in_range("rest_before_s", rest_before_s, rest_before_s >= 0.02 && rest_before_s <= 10, "in [0.02, 10] s");
  in_range("rest_after_s", rest_after_s, rest_after_s >= 0.02 && rest_after_s <= 10, "in [0.02, 10] s");
  in_range("start_unix_s", start_unix_s, start_unix_s >= 0, "a non-negative Unix time");
  in_range("sensors.noise_scale", sensors.noise_scale,
           sensors.noise_scale >= 0 && sensors.noise_scale <= kMaxSensorNoiseScale, "in [0, 100]");
  in_range("sensors.jitter_scale", sensors.jitter_scale, sensors.jitter_scale >= 0 && sensors.jitter_scale <= 10,
           "in [0, 10]");
  require(
      sensors.push_offset_N.allFinite() && sensors.push_offset_N.cwiseAbs().maxCoeff() <= kMaxForceOffset_N,
      label("sensors.push_offset_N") + ": the force sensor's push offset must be finite and within 20 N on each axis");
  in_range("support_tilt_direction_rad", support_tilt_direction_rad, true, "finite");
  in_range("friction_patch_radius_m", friction_patch_radius_m,
           friction_patch_radius_m > 0 && friction_patch_radius_m <= 1.0, "in (0, 1] m");
  in_range("friction_patch_ahead_m", friction_patch_ahead_m, std::abs(friction_patch_ahead_m) <= 1.0, "within 1 m");
  for (const auto& [name, amount] : effects.active()) {  // the range checks
    try {
      Effects().set(name, amount);
    } catch (const InputError& e) {
      throw InputError(label("effects") == "effects" ? std::string(e.what()) : label("effects") + ": " + e.what());
    }
  }
}

std::uint64_t parse_seed(const std::string& text) {
  static const std::string kRange = "must be a whole number from 0 to 18446744073709551615";
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits) throw InputError(kRange + ", got '" + plain_text(text) + "'");
  errno = 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (errno == ERANGE || end != text.c_str() + text.size())
    throw InputError(kRange + ", got '" + plain_text(text) + "'");
  return static_cast<std::uint64_t>(value);
}

PushScenario scenario_from_json(const nlohmann::json& j, const std::string& source) {
  static const std::set<std::string> known = {"name",
                                              "comment",
                                              "shape",
                                              "surface",
                                              "surface_friction",
                                              "contact_friction",
                                              "contact_stiffness_N_m",
                                              "pressure_rim_weight",
                                              "speed_m_s",
                                              "acceleration_m_s2",
                                              "push_length_m",
                                              "ramp_s",
                                              "contact_side",
                                              "contact_position",
                                              "push_angle_rad",
                                              "approach_gap_m",
                                              "support_tilt_direction_rad",
                                              "friction_patch_radius_m",
                                              "friction_patch_ahead_m",
                                              "initial_pose",
                                              "rest_before_s",
                                              "rest_after_s",
                                              "start_unix_s",
                                              "seed",
                                              "effects",
                                              "sensors"};
  try {
    require(j.is_object(), "a scenario must be a JSON object");
    for (const auto& [key, value] : j.items()) {
      (void)value;
      require(known.count(key) > 0, "unknown field '" + key + "'");
    }
    auto number = [&](const char* key, double fallback) {
      if (!j.contains(key)) return fallback;
      require(j[key].is_number(), std::string("field '") + key + "' must be a number");
      const double v = j[key].get<double>();
      require(std::isfinite(v), std::string("field '") + key + "' must be finite");
      return v;
    };
    auto text = [&](const char* key, const std::string& fallback) {
      if (!j.contains(key)) return fallback;
      require(j[key].is_string(), std::string("field '") + key + "' must be a string");
      return j[key].get<std::string>();
    };
    PushScenario s;
    s.name = text("name", "");
    s.shape = text("shape", s.shape);
    s.surface = text("surface", s.surface);
    s.surface_friction = number("surface_friction", s.surface_friction);
    s.contact_friction = number("contact_friction", s.contact_friction);
    s.contact_stiffness_N_m = number("contact_stiffness_N_m", s.contact_stiffness_N_m);
    s.pressure_rim_weight = number("pressure_rim_weight", s.pressure_rim_weight);
    const bool has_speed = j.contains("speed_m_s"), has_accel = j.contains("acceleration_m_s2");
    const double speed = number("speed_m_s", 0.0), accel = number("acceleration_m_s2", 0.0);
    require(!(has_speed && has_accel && speed > 0 && accel > 0),
            "give either a speed (speed_m_s) or an acceleration (acceleration_m_s2), not both");
    if (accel > 0) {
      s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
      s.motion.acceleration_m_s2 = accel;
    } else {
      require(has_speed || !has_accel, "an acceleration push needs acceleration_m_s2 > 0");
      if (has_speed) s.motion.speed_m_s = speed;
    }
    s.motion.length_m = number("push_length_m", s.motion.length_m);
    s.motion.ramp_s = number("ramp_s", s.motion.ramp_s);
    const double side = number("contact_side", s.contact_side);
    require(side == std::floor(side) && std::abs(side) < 1000, "field 'contact_side' must be a whole number");
    s.contact_side = static_cast<int>(side);
    s.contact_position = number("contact_position", s.contact_position);
    s.push_angle_rad = number("push_angle_rad", s.push_angle_rad);
    s.approach_gap_m = number("approach_gap_m", s.approach_gap_m);
    s.support_tilt_direction_rad = number("support_tilt_direction_rad", s.support_tilt_direction_rad);
    s.friction_patch_radius_m = number("friction_patch_radius_m", s.friction_patch_radius_m);
    s.friction_patch_ahead_m = number("friction_patch_ahead_m", s.friction_patch_ahead_m);
    if (j.contains("initial_pose")) {
      const auto& p = j["initial_pose"];
      require(p.is_array() && p.size() == 3 && p[0].is_number() && p[1].is_number() && p[2].is_number(),
              "field 'initial_pose' must be [x_m, y_m, yaw_rad]");
      s.initial_x_m = p[0].get<double>();
      s.initial_y_m = p[1].get<double>();
      s.initial_yaw_rad = p[2].get<double>();
    }
    s.rest_before_s = number("rest_before_s", s.rest_before_s);
    s.rest_after_s = number("rest_after_s", s.rest_after_s);
    s.start_unix_s = number("start_unix_s", s.start_unix_s);
    if (j.contains("seed")) {
      require(j["seed"].is_number_unsigned() || (j["seed"].is_number_integer() && j["seed"].get<long long>() >= 0),
              "field 'seed' must be a non-negative whole number");
      s.seed = j["seed"].get<std::uint64_t>();
    }
    if (j.contains("effects")) {
      require(j["effects"].is_object(), "field 'effects' must be an object of NAME: AMOUNT");
      for (const auto& [name, amount] : j["effects"].items()) {
        require(amount.is_number(), "effect '" + name + "' must be a number");
        s.effects.set(name, amount.get<double>());
      }
    }
    if (j.contains("sensors")) {
      const auto& q = j["sensors"];
      require(q.is_object(), "field 'sensors' must be an object");
      for (const auto& [key, value] : q.items()) {
        require(key == "noise_scale" || key == "jitter_scale" || key == "push_offset_N",
                "unknown field 'sensors." + key + "'");
        if (key == "push_offset_N") {
          require(value.is_array() && value.size() == 2 && value[0].is_number() && value[1].is_number(),
                  "field 'sensors.push_offset_N' must be [fx, fy] in newtons");
          s.sensors.push_offset_N = Eigen::Vector2d(value[0].get<double>(), value[1].get<double>());
          continue;
        }
        require(value.is_number(), "field 'sensors." + key + "' must be a number");
        (key == "noise_scale" ? s.sensors.noise_scale : s.sensors.jitter_scale) = value.get<double>();
      }
    }
    s.validate();
    return s;
  } catch (const InputError& e) {
    throw InputError(about(source, e.what()));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(source, e.what()));
  }
}

PushScenario read_scenario_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(about(path.string(), "is a folder, not a scenario file"));
  std::ifstream in(path);
  if (!in) throw InputError(about(path.string(), "cannot open scenario file"));
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(path.string(), std::string("not valid JSON: ") + e.what()));
  }
  return scenario_from_json(j, path.string());
}

nlohmann::json scenario_to_json(const PushScenario& s) {
  nlohmann::json j;
  if (!s.name.empty()) j["name"] = s.name;
  j["shape"] = s.shape;
  j["surface"] = s.surface;
  j["surface_friction"] = s.surface_friction;
  j["contact_friction"] = s.contact_friction;
  j["contact_stiffness_N_m"] = s.contact_stiffness_N_m;
  j["pressure_rim_weight"] = s.pressure_rim_weight;
  if (s.motion.profile == PusherMotion::Profile::ConstantAcceleration)
    j["acceleration_m_s2"] = s.motion.acceleration_m_s2;
  else
    j["speed_m_s"] = s.motion.speed_m_s;
  j["push_length_m"] = s.motion.length_m;
  j["ramp_s"] = s.motion.ramp_s;
  j["contact_side"] = s.contact_side;
  j["contact_position"] = s.contact_position;
  j["push_angle_rad"] = s.push_angle_rad;
  j["approach_gap_m"] = s.approach_gap_m;
  if (s.effects.support_tilt_deg != 0 || s.support_tilt_direction_rad != 0)
    j["support_tilt_direction_rad"] = s.support_tilt_direction_rad;
  if (s.friction_patch_radius_m != kFrictionPatchRadius_m || s.friction_patch_ahead_m != kFrictionPatchAhead_m) {
    j["friction_patch_radius_m"] = s.friction_patch_radius_m;
    j["friction_patch_ahead_m"] = s.friction_patch_ahead_m;
  }
  j["initial_pose"] = {s.initial_x_m, s.initial_y_m, s.initial_yaw_rad};
  j["rest_before_s"] = s.rest_before_s;
  j["rest_after_s"] = s.rest_after_s;
  j["start_unix_s"] = s.start_unix_s;
  j["seed"] = s.seed;
  nlohmann::json effects = nlohmann::json::object();
  for (const auto& [name, amount] : s.effects.active()) effects[name] = amount;
  j["effects"] = effects;
  j["sensors"] = {{"noise_scale", s.sensors.noise_scale}, {"jitter_scale", s.sensors.jitter_scale}};
  if (!s.sensors.push_offset_N.isZero())
    j["sensors"]["push_offset_N"] = {s.sensors.push_offset_N.x(), s.sensors.push_offset_N.y()};
  return j;
}

PushScenario paper_case_scenario(int n) {
  if (n < 1 || n > 6) throw InputError("paper case " + std::to_string(n) + " does not exist (cases 1 to 6)");
  const std::string source = "data/paper/case" + std::to_string(n) + ".json";
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(detail::kPaperCaseJson[n - 1]);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(source, std::string("not valid JSON: ") + e.what()));
  }
  return scenario_from_json(j, source);
}

}  // namespace pushpred
