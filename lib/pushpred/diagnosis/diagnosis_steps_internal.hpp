#pragma once
// Shared by the diagnosis step files only (not installed for users): the search the steps share, and formatting
// for the notes and the log.
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/diagnosis_pipeline.hpp"
#include "pushpred/diagnosis/model_adequacy.hpp"

namespace pushpred {

/// The adequacy test's options from the diagnosis's.
AdequacyOptions adequacy_options(const DiagnosisOptions& options);

/// The adequacy test's force part (test_residual_structure) on `data`, against every regression term of `terms` whose
/// amount the residual still carries (data corrections are applied to the data), with `options`: fills the force
/// fields of `adequacy` and returns the hints. Step 7 runs it on every push.
std::vector<ResidualHint> test_corrected_residual(const DiagnosisContext& context, const std::vector<Selection>& terms,
                                                  const std::vector<DiagnosisPush>& data, const FloorContext& floors,
                                                  const AdequacyOptions& options, ModelAdequacy& adequacy);
/// The same on `model`'s data (the fit pushes) with adequacy_options(): the stand-in check runs it.
std::vector<ResidualHint> test_corrected_residual(const DiagnosisContext& context, const ModelState& model,
                                                  const FloorContext& floors, ModelAdequacy& adequacy);

/// Every push as `model`'s data corrections leave it: the fit pushes of its data, then the held-out pushes corrected
/// the same way (none when one push is fitted and tested). The adequacy test's rest, contact and force parts read them.
std::vector<SynchronisedPush> every_corrected_push(const DiagnosisContext& context, const ModelState& model);

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

/// What a greedy forward selection chose, and the significant candidates it judged negligible (kept as nuisance
/// terms in every later fit: the joint test), with its decisions.
struct SearchOutcome {
  std::vector<Selection> selected;
  std::vector<Selection> nuisance;
  DiagnosisTrace trace;
};

/// Greedy forward selection in `group` on `data`, starting from `selected`: at each round every remaining candidate
/// (at each of its settings) is fitted jointly with those selected and the nuisance terms; the best joins when its
/// score exceeds the BIC threshold and its amount clears its floor (under `floors`) by the margin. A candidate
/// significant but below its floor is not tried again and becomes a nuisance term. Candidates in `ruled_out` are not
/// tried.
SearchOutcome greedy_search(const DiagnosisContext& context, const std::vector<DiagnosisPush>& data,
                            std::vector<Selection> selected, Relation group, const FloorContext& floors,
                            const std::vector<std::size_t>& ruled_out = {});

/// Applies the data corrections of `selected`, re-runs the observer and re-fits the regression terms jointly, until
/// the data corrections' residual amounts are negligible against their standard errors; a term whose re-fit leaves
/// the plausible range, or turns the support's friction torque negative, is dropped (decisions in `trace`).
ModelState refit(const DiagnosisContext& context, std::vector<Selection> selected, DiagnosisTrace& trace);

/// After terms were dropped: the rest re-fitted from scratch (the data corrections that are regression effects
/// restart from zero, as the data are rebuilt without the dropped ones).
ModelState refit_after_dropping(const DiagnosisContext& context, std::vector<Selection> selected,
                                DiagnosisTrace& trace);

/// The found terms whose amount no longer clears its floor by the margin after the joint re-fit: judged negligible
/// and dropped, the rest re-fitted.
ModelState drop_below_floor(const DiagnosisContext& context, ModelState model, const FloorContext& floors,
                            DiagnosisTrace& trace);

/// The base friction law fitted on `model.data` and the floors measured with it; `add_law` also puts the law and
/// its resolved refinements into the model (otherwise only the floors and the law's report are restated).
FrictionBase fit_friction_base(const DiagnosisContext& context, const ModelState& model, bool add_law);

}  // namespace pushpred
