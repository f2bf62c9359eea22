#pragma once
// The results of the batch commands as a partial output carries them (runtime/shard.hpp): JSON that reads back to
// the same result, every double written so that it reads back to the same bits (exact_number_json: non-finite ones
// by name), so that a merge of shards writes what one run writes, byte for byte. Each result keeps what the outputs
// (reports/) read of it, no more: a study without its samples, an object's overview entry. Each reader throws
// InputError on a malformed document.
#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/reports/diagnosis_overview.hpp"

namespace pushpred {

/// A study (`predict`'s result): every field drop_samples keeps.
nlohmann::json push_study_exact_json(const PushStudy& study);
/// The study push_study_exact_json wrote (without samples, as drop_samples leaves it).
PushStudy push_study_from_exact_json(const nlohmann::json& doc);

/// An ErrorSummary: [phases, the six values].
nlohmann::json error_summary_exact_json(const ErrorSummary& e);
ErrorSummary error_summary_from_exact_json(const nlohmann::json& j);

/// The six held-out error summaries of one diagnosis, in the order a partial output keeps them: the paper's method,
/// the base model, the corrected model, hold, const_velocity, quasi_static (the fields of a DiagnosisResult or a
/// ValidationTrial).
using HeldOutErrorFields = std::array<ErrorSummary*, 6>;
nlohmann::json held_out_errors_exact_json(const std::array<const ErrorSummary*, 6>& errors);
/// Reads held_out_errors_exact_json's list into `fields`; the error names `holder` ("an object", "a trial") when it
/// is not six summaries.
void held_out_errors_from_exact_json(const nlohmann::json& list, const HeldOutErrorFields& fields,
                                     const std::string& holder);

/// A trial of `validate-diagnosis`.
nlohmann::json validation_trial_exact_json(const ValidationTrial& trial);
ValidationTrial validation_trial_from_exact_json(const nlohmann::json& doc);

/// An object's diagnosis of `diagnose --per-object`: what the overview and the printed report read of it (the
/// object's shape and surface, its selected effects, its adequacy verdict and six error summaries), exactly.
nlohmann::json diagnosed_object_exact_json(const DiagnosedObject& object);
DiagnosedObject diagnosed_object_from_exact_json(const nlohmann::json& doc);

}  // namespace pushpred
