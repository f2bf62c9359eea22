#pragma once
// Shared by the diagnosis step files only (not installed for users): formatting for the selection log.
#include <string>

namespace pushpred {

/// printf-style formatting of up to three numbers, for log lines and notes.
std::string diagnosis_format(const char* fmt, double a, double b = 0, double c = 0);

}  // namespace pushpred
