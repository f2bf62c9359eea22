// libFuzzer target: the file name parser. A name that parses must give finite parameters, and the name written
// back from them must parse again to the same shape and surface
// when it fits a file system's name length.
#include <cmath>
#include <cstdlib>
#include <string>

#include "pushpred/reading/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string name(reinterpret_cast<const char*>(data), size);
  const auto parsed = pushpred::parse_push_filename(name);
  if (!parsed) return 0;
  for (const double v : {parsed->acceleration_m_s2, parsed->speed_m_s, parsed->contact_side, parsed->contact_position,
                         parsed->angle_rad})
    if (!std::isfinite(v)) std::abort();
  const std::string written = pushpred::push_filename(*parsed);
  if (written.size() > 255) return 0;  // longer than any file system allows: not parsed, by design
  const auto again = pushpred::parse_push_filename(written);
  if (!again || again->shape != parsed->shape || again->surface != parsed->surface) std::abort();
  return 0;
}
