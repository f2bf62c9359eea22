#pragma once
// The validation of the diagnosis (diagnosis/validation.hpp) as validation.json (every trial) and validation.md:
// the confusion matrix (true kind x named kinds, "nothing" included), the detection rate against the amount in
// floors, the amount error, the false findings on clean trials, and the held-out errors of the paper's method, the
// base model, the base model plus what was found, and the references; and the targets, met or not.
#include <nlohmann/json.hpp>
#include <string>

#include "pushpred/diagnosis/validation.hpp"

namespace pushpred {

nlohmann::json validation_json(const ValidationResult& result);
std::string validation_markdown(const ValidationResult& result);

}  // namespace pushpred
