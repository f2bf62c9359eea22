#include <cmath>
#include <cstdio>
#include <regex>

#include "pushpred/reading/recording.hpp"

namespace pushpred {

std::optional<PushParameters> parse_push_filename(std::string_view filename) {
  const std::string name = std::filesystem::path(std::string(filename)).filename().string();
  static const std::regex pattern(
      R"(^motion_surface=([A-Za-z0-9]+)_shape=([A-Za-z0-9]+)_a=(-?[0-9.]+)_v=(-?[0-9.]+)_i=(-?[0-9.]+)_s=(-?[0-9.]+)_t=(-?[0-9.]+)\.(h5|json)$)");
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

std::string push_filename(const PushParameters& p, const std::string& extension) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "motion_surface=%s_shape=%s_a=%g_v=%g_i=%.3f_s=%.3f_t=%.3f%s", p.surface.c_str(),
                p.shape.c_str(), p.acceleration_m_s2 * 1e3, std::round(p.speed_m_s * 1e3 * 1e6) / 1e6,
                p.contact_side, p.contact_position, p.angle_rad, extension.c_str());
  return buf;
}

}  // namespace pushpred
