#pragma once
// Shared by the diagnosis step files only (not installed for users): formatting for the selection log.
#include <string>

#include "pushpred/diagnosis/diagnosis.hpp"

namespace pushpred {

/// printf-style formatting of up to three numbers, for log lines and notes.
std::string diagnosis_format(const char* fmt, double a, double b = 0, double c = 0);

/// The note of an effect that passed its test below its floor: "significant, negligible<when>: amount ... is below
/// its floor ... (basis)", or, above the floor by less than `margin_std` of its standard errors, "... is within
/// ... standard error(s) of its floor ...".
std::string negligible_note(const EffectReport& r, double margin_std, const std::string& when = "");

/// The standard error of effect.amount(theta) through its gradient: the largest of its variances under
/// `covariances` (theta's covariance matrices), or, where none is given, from theta's standard errors `std` taken as
/// uncorrelated (0 when std is empty too).
double amount_standard_error(const CandidateEffect& effect, const Eigen::VectorXd& theta, const Eigen::VectorXd& std,
                             const std::vector<Eigen::MatrixXd>& covariances = {});

}  // namespace pushpred
