#include <cmath>
#include <cstdio>
#include <regex>
#include <string>

#include "pushpred/reading/recording.hpp"

namespace pushpred {

std::optional<PushParameters> parse_push_filename(std::string_view filename) {
  const std::string name = std::filesystem::path(std::string(filename)).filename().string();
  // No file system allows longer names (NAME_MAX), and std::regex recurses per character.
  if (name.size() > 255) return std::nullopt;
  static const std::regex pattern(
      R"(^motion_surface=([A-Za-z0-9]+)_shape=([A-Za-z0-9]+)_a=(-?[0-9.]+)_v=(-?[0-9.]+)_i=(-?[0-9.]+)_s=(-?[0-9.]+)_t=(-?[0-9.]+)\.([hH]5|[jJ][sS][oO][nN])$)");
  std::smatch m;
  if (!std::regex_match(name, m, pattern)) return std::nullopt;
  try {
    PushParameters p;
    p.surface = m[1];
    p.shape = m[2];
    p.acceleration_m_s2 = std::stod(m[3]) * 1e-3;
    p.speed_m_s = std::stod(m[4]) * 1e-3;
    p.contact_side = std::stod(m[5]);
    p.contact_position = std::stod(m[6]);
    p.angle_rad = std::stod(m[7]);
    return p;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

namespace {

/// %g, but never with an exponent (the name pattern has none): "10", "0.5", "0.000012".
std::string plain_number(double v) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%g", v);
  if (std::string(buf).find_first_of("eE") == std::string::npos) return buf;
  std::snprintf(buf, sizeof buf, "%.9f", v);
  std::string s = buf;
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::string push_filename(const PushParameters& p, const std::string& extension) {
  char buf[1536];
  std::snprintf(buf, sizeof buf, "motion_surface=%s_shape=%s_a=%s_v=%s_i=%.3f_s=%.3f_t=%.3f%s", p.surface.c_str(),
                p.shape.c_str(), plain_number(p.acceleration_m_s2 * 1e3).c_str(),
                plain_number(std::round(p.speed_m_s * 1e3 * 1e6) / 1e6).c_str(), p.contact_side, p.contact_position,
                p.angle_rad, extension.c_str());
  return buf;
}

}  // namespace pushpred
