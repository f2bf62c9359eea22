#pragma once
// Shared by the diagnosis step files only (not installed for users): formatting for the selection log.
#include <string>

#include "pushpred/diagnosis/diagnosis.hpp"

namespace pushpred {

/// printf-style formatting of up to three numbers, for log lines and notes.
std::string diagnosis_format(const char* fmt, double a, double b = 0, double c = 0);

/// The note of an effect that passed its test below its floor: "significant, negligible<when>: amount ... is below
/// its floor ... (basis)".
std::string negligible_note(const EffectReport& r, const std::string& when = "");

}  // namespace pushpred
