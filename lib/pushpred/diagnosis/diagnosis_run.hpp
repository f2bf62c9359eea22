#pragma once
// The first two steps of the diagnosis pipeline (diagnosis_pipeline.hpp) behind the interface of the class that ran
// the steps before it: for callers that want the floors the diagnosis would measure on their pushes
// (validation.cpp's measured_floor_context). New code calls split_pushes, paper_method and friction_base.
#include <optional>
#include <vector>

#include "pushpred/diagnosis/diagnosis_pipeline.hpp"

namespace pushpred {

class DiagnosisRun {
 public:
  DiagnosisRun(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
               const DiagnosisOptions& options)
      : input_(split_pushes(pushes, library, options)) {}
  void paper_method() { paper_.emplace(pushpred::paper_method(input_)); }
  /// Fills result().floor_context. Needs paper_method() first.
  void friction_base() {
    result_.floor_context = pushpred::friction_base(paper_.value().context, paper_->model).floors;
  }
  DiagnosisResult& result() { return result_; }

 private:
  DiagnosisInput input_;
  std::optional<PaperMethodOutcome> paper_;
  DiagnosisResult result_;
};

}  // namespace pushpred
