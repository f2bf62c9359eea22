#pragma once
// Closing the loop on the paper's method: find what it leaves unexplained, trace it to a missing physical
// effect, add the effect, and measure the prediction error before and after on phases not used to select or fit.
//
// Roles of the data (pushes of one object on one surface):
// - several pushes: sorted by name, alternate pushes are fit (1st, 3rd, ...) and test (2nd, 4th, ...) pushes.
//   Effect parameters are physical constants fitted on the fit pushes and applied to the test pushes, where the
//   paper's online relation estimator still runs per push as before;
// - one push: the fit data are all intervals but the last; the test phase is the last prediction phase.
// Steps:
// 1. The residuals of the paper's method: the observer's d_hat on the fit data less the relation beta Q u + eps
//    (per push and channel), and the prediction errors of every phase (`dob`).
// 2. Direct effects (force offset) are estimated and scored; if selected, the data are corrected.
// 3. Greedy forward selection over the regression effects: at each step every remaining candidate (at each of
//    its settings) is fitted jointly with those already selected; the one with the largest BIC drop joins if the
//    drop exceeds `bic_threshold` (residual_regression.hpp: BIC with the effective sample count).
// 4. Effects that correct the data (time offset, inertia) are applied and the selected set re-fitted on the
//    corrected data until their residual amounts vanish.
//    Then each selected direct effect that corrects the data is tested again when a friction law is selected: on
//    the data without its correction, the friction law's refinements are searched anew and the effect re-fitted
//    with what they explain set aside; if it no longer passes, those refinements replace it (a lag found against a
//    bare Coulomb law may be a friction effect in disguise).
// 5. Prediction-structure effects (initial velocity, the quasi-static law, its pusher_stop refinement) are scored
//    together, every combination at every setting, on the fit pushes' prediction phases: the best is selected when
//    the mean normalised error drops by more than twice its standard error over phases. A refinement
//    (CandidateEffect::refines) is tried only in combinations that hold the effect it refines.
// 6. Confirmation: an effect selected in 2-4 whose removal does not make the fit phases' prediction error worse
//    is dropped; the rest are re-fitted.
// 7. Test phases: the paper's `dob`, the corrected model, `hold` and `const_velocity`.
// The normalised prediction error of a phase is pos_mm_mean / H_pos + theta_deg_mean / H_theta, H the mean `hold`
// errors over the phases compared (so millimetres and degrees weigh alike).
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/prediction/prediction_study.hpp"

namespace pushpred {

struct DiagnosisOptions {
  StudyOptions study;                ///< the paper's method (schedule, plan rate, relation estimator); no correction
  QFilterObserverOptions observer;   ///< the disturbance observer
  double bic_threshold = 10;         ///< an effect joins when it lowers the BIC by more than this
  int max_refits = 4;                ///< re-fits after applying data corrections
  bool search_structure = true;      ///< step 5 (off: prediction-structure effects are not tried)
  bool confirm_on_prediction = true; ///< step 6
  void validate() const;
};

/// Mean errors over a set of prediction phases.
struct ErrorSummary {
  int phases = 0;
  double pos_mm_mean = 0;    ///< mean over phases of the mean Euclidean position error
  double x_mm_mean = 0, y_mm_mean = 0, theta_deg_mean = 0;
  double final_pos_mm = 0, final_theta_deg = 0;
};

struct EffectReport {
  std::string kind, description;
  EffectTest test = EffectTest::Regression;
  /// A fix of the paper's model structure (a friction law replacing the relation, a prediction-structure effect),
  /// which may be selected on data without any hidden effect; the others are physical effects found in the data.
  bool structural = false;
  bool passed_test = false;  ///< passed its own test (BIC drop above the threshold, or the prediction test)
  bool selected = false;     ///< in the final correction (passed, and not dropped by the confirmation)
  /// Regression and direct effects: the BIC drop when last tried (for a selected effect, when it joined);
  /// prediction effects: the relative drop of the fit phases' normalised error.
  double score = 0;
  std::vector<EffectParameter> parameter_info;
  Eigen::VectorXd theta, theta_std;  ///< last fitted values (final ones when selected)
  bool has_setting = false;
  EffectParameter setting_info;
  double setting = 0;
  std::vector<CandidateEffect::Derived> derived;
  std::string note;  ///< why it was not selected or was dropped
  /// Selected effects: the held-out errors of the final correction without this effect (what it contributes on
  /// the test phases; reported only, never used to select).
  bool has_ablation = false;
  ErrorSummary held_out_without;
};

/// Errors over time of one phase, for plots.
struct PhaseTrace {
  std::string source;
  int phase = 0;
  double t0_s = 0;      ///< the phase start on the push's clock
  Eigen::VectorXd t_s;  ///< since the phase start
  std::map<std::string, Eigen::MatrixX3d> error;  ///< per method, predicted - measured (m, m, rad)
};

/// The disturbance residual of one fit push before and after, for plots.
struct ResidualTrace {
  std::string source;
  Eigen::VectorXd t_s;
  Eigen::MatrixX3d before, after;  ///< d_hat - beta Q u - eps (- effects) [N, N, N m]
  /// Against the selected friction law and its refinements (empty when none; zero near stuck-sliding changes).
  Eigen::MatrixX3d friction;
};

struct DiagnosisResult {
  std::string shape, surface;
  std::string held_out;  ///< how the test phases were chosen
  std::vector<std::string> fit_sources, test_sources;
  std::vector<EffectReport> effects;  ///< every candidate, in library order
  ModelCorrection correction;         ///< the selected effects together
  /// On the test phases: the paper's `dob`, the corrected model, and the references.
  ErrorSummary error_before, error_after, hold, const_velocity, dob_velinit;
  /// The same on the fit pushes' phases (in-sample), for comparison.
  ErrorSummary fit_before, fit_after, fit_hold, fit_const_velocity;
  // The disturbance regression on the fit data.
  long samples = 0;
  double effective_samples = 0;
  Eigen::Vector3d residual_std_before = Eigen::Vector3d::Zero();  ///< [N, N, N m]
  Eigen::Vector3d residual_std_after = Eigen::Vector3d::Zero();  ///< against the linear relation, after the effects
  /// Against the selected friction law and the effects that refine it (NaN when no law was selected).
  Eigen::Vector3d friction_residual_std = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<ResidualTrace> residuals;
  std::vector<PhaseTrace> test_phases;
  std::vector<BatchFailure> failures;  ///< pushes left out, and why
  std::vector<std::string> log;        ///< the selection, step by step
};

/// Diagnoses `pushes` (one object, one surface) with the candidates of `library`. Throws InputError when there
/// is no usable push, the pushes are of different objects or surfaces, or the options are invalid; a push whose
/// study fails is left out and listed in `failures`.
DiagnosisResult diagnose(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
                         const DiagnosisOptions& options = {});

/// Mean errors of `method` over `phases` (all phases of the studies given, or those listed).
struct StudyPhase {
  const PushStudy* study;
  std::size_t phase;  ///< index into study->phases
};
ErrorSummary summarise_errors(const std::vector<StudyPhase>& phases, const std::string& method);

}  // namespace pushpred
