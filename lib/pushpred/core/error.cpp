#include "pushpred/core/error.hpp"

#include <cstdio>
#include <limits>
#include <sstream>

namespace pushpred {
namespace {

/// Length of the valid UTF-8 sequence starting at s[i] (2 to 4 bytes), or 0 when it is not one.
std::size_t utf8_sequence_length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // allowed range of the second byte (excludes overlongs and surrogates)
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c == 0xE0) n = 3, lo = 0xA0;
  else if (c >= 0xE1 && c <= 0xEC) n = 3;
  else if (c == 0xED) n = 3, hi = 0x9F;
  else if (c >= 0xEE && c <= 0xEF) n = 3;
  else if (c == 0xF0) n = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) n = 4;
  else if (c == 0xF4) n = 4, hi = 0x8F;
  else return 0;
  if (i + n > s.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

}  // namespace

std::string plain_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n' || c == '\r' || c == '\t') {
      out += ' ';
      ++i;
    } else if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? utf8_sequence_length(text, i) : 0; n > 0) {
      out.append(text, i, n);
      i += n;
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      out += hex;
      ++i;
    }
  }
  return out;
}

namespace {

[[noreturn]] void throw_out_of_range(double value, const std::string& what, const char* range) {
  char got[48];
  std::snprintf(got, sizeof got, "%g", value);
  throw InputError(what + " must be " + range + ", got " + got);
}

}  // namespace

std::string three_significant_digits(double value) {
  std::ostringstream s;
  s.precision(3);
  s << value;
  return s.str();
}

void require_positive_finite(double value, const std::string& what) {
  if (value > 0 && value < std::numeric_limits<double>::infinity()) return;
  throw_out_of_range(value, what, "positive and finite");
}

void require_not_negative_finite(double value, const std::string& what) {
  if (value >= 0 && value < std::numeric_limits<double>::infinity()) return;
  throw_out_of_range(value, what, "finite and not negative");
}

}  // namespace pushpred
