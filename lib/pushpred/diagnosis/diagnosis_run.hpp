#pragma once
// The diagnosis (diagnosis.hpp) as named steps over one shared state, so that each step can be run and tested
// alone. diagnose() runs them in order:
//   1. paper_method      the paper's method on every push; the disturbance residual of the fit pushes
//   2. friction_base     the base model's friction law (Coulomb, always in) fitted; the effect-size floors measured
//   3. direct_effects    effects with a test of their own (force offset, time offset): found when the test passes
//                        and the amount is above its floor; found data corrections are applied
//   4. force_laws        greedy forward selection of the physical force laws against the base friction law, each
//                        joining only when significant and above its floor; data corrections iterated
//   5. base_structure    the prediction structure of the base model: the quasi-static push's stop fraction fitted on
//                        the fit phases (the structure itself is fixed, never re-selected)
//      motion_confirmation  a found effect that changes how the pushing model moves the object (the mass-centre
//                        offset) stays found only if it predicts the fit pushes' phases better than the model
//                        without it; otherwise it is dropped, the friction laws searched again without it (step 4's
//                        friction part) and step 5 repeated
//   6. held_out          the test phases: the paper's `dob`, the base model, the base model plus what was found, the
//                        references; what each found effect contributes there (the model without it)
//   7. model_adequacy    whether the corrected model leaves structure noise does not explain (model_adequacy.hpp)
// A step that fails reports the failure (DiagnosisResult::step_failures) instead of scoring anything as infinite;
// steps 1 and 6 are essential and their failure ends the diagnosis with an InputError.
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/residual_regression.hpp"

namespace pushpred {

/// One effect in the model being built: a library candidate, its setting and amounts.
struct Selection {
  std::size_t candidate = 0;  ///< index into the library
  double setting = 0;
  int extra_parameters = 0;   ///< 1 when the setting was chosen on a grid
  Eigen::VectorXd total;      ///< amount applied so far (data corrections) or fitted (force laws)
  Eigen::VectorXd std;
  double score = 0;
  /// The fit's covariance blocks of these parameters (Newey-West, and clustered by push where the fit uses it; `std`
  /// is the larger diagonal): the amount's standard error takes the larger of its variances under them, so that
  /// correlated parameters (the mass-centre offset's delta_x, delta_y) count as such. Empty: only `std` is known.
  std::vector<Eigen::MatrixXd> covariances;
};

class DiagnosisRun {
 public:
  /// Validates the options, splits the pushes into fit and test pushes (diagnosis.hpp). Throws InputError as
  /// diagnose() does.
  DiagnosisRun(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
               const DiagnosisOptions& options);

  // The steps, in order (see above). Each may throw; diagnose() reports a throw as a step failure.
  void paper_method();
  void friction_base();
  void direct_effects();
  void force_laws();
  void base_structure();
  void motion_confirmation();
  void held_out();
  void model_adequacy();

  /// Runs every step, reporting failures; returns the result.
  DiagnosisResult run();

  DiagnosisResult& result() { return result_; }
  const std::vector<Selection>& selected() const { return model_terms_; }
  const std::vector<DiagnosisPush>& data() const { return fit_data_; }

 private:
  void rebuild_data(const ModelCorrection& data_correction);
  EffectColumns columns(std::size_t candidate, double setting) const;
  /// The correction of `selected`: data corrections only, or the whole model for the prediction.
  ModelCorrection correction_of(const std::vector<Selection>& selected, bool for_prediction) const;
  /// Studies of `pushes` with `correction` as the `corrected` method. Throws what the study throws.
  std::vector<PushStudy> studies(const std::vector<const SynchronisedPush*>& pushes,
                                 const ModelCorrection& correction) const;
  std::vector<StudyPhase> fit_phases(const std::vector<PushStudy>& s) const;
  std::vector<StudyPhase> test_phases(const std::vector<PushStudy>& s) const;
  std::vector<double> normalised(const std::vector<StudyPhase>& phases, const std::string& method) const;
  /// The support's friction torque coefficient in `fit` (a friction-group fit of `selected`'s regression effects,
  /// then any candidate's): the friction law's mu plus the parameter of every effect that scales_support_torque()
  /// (the base model's friction_torque), all scaling the footprint's Coulomb torque. 1 when no friction law is in
  /// `selected`. At or below zero the friction would drive the rotation instead of damping it.
  double support_torque_coefficient(const std::vector<Selection>& selected, const RegressionFit& fit) const;
  /// The mean normalised error (normalised()) of the corrected prediction with `correction` over the fit pushes'
  /// phases; infinite when there is none. Throws what the study throws.
  double fit_phase_error(const ModelCorrection& correction) const;
  Relation group_of(std::size_t candidate) const;
  RegressionFit fit_selected(const std::vector<Selection>& selected, Relation group,
                             std::vector<EffectColumns>& storage) const;
  void refit(std::vector<Selection>& selected);
  /// After selections were dropped from model_terms_: the rest re-fitted from scratch (the data corrections that are
  /// regression effects restart from zero, as the data are rebuilt without the dropped ones).
  void refit_after_dropping();
  void retest_direct(std::vector<Selection>& selected, double log_neff);
  /// The found effects whose amount no longer clears its floor by the margin after a joint re-fit: reported
  /// negligible and dropped, the rest re-fitted.
  void drop_below_floor();
  /// Greedy forward selection in `group`. A candidate significant but below its floor is not tried again and stays
  /// in every later fit as a nuisance term (the joint test); `nuisance_out` receives those.
  void greedy(std::vector<Selection>& selected, Relation group, double log_neff,
              std::vector<Selection>* nuisance_out = nullptr);
  /// Records effect i's floor, amount (of s.total) and the amount's standard error (amount_standard_error from s's
  /// covariances, or its `std` without them; none when both are empty); true when the amount exceeds the floor by
  /// options.floor_margin_std standard errors.
  bool above_floor(std::size_t i, const Selection& s);
  /// The base model's selections: the friction law and the prediction structure.
  std::vector<Selection> base_selections() const;
  std::vector<const SynchronisedPush*> fit_pointers() const;
  std::vector<const SynchronisedPush*> test_pointers() const;
  void measure_floors(bool add_law);
  // held_out's steps (step_held_out.cpp).
  /// Marks what was found in the reports, with every physical candidate's amount against its floor.
  void report_findings();
  /// The residual of the fit data after the found effects: against the linear relation and the friction law.
  void residual_after_findings();
  /// The corrected model, the paper's method and the references on the test phases; the pushes that could be
  /// predicted. Throws InputError when none could.
  std::vector<const SynchronisedPush*> predict_test_phases();
  /// The base model alone, and the model without each found effect, on the pushes `tested`.
  void base_and_ablations(const std::vector<const SynchronisedPush*>& tested, const std::vector<Selection>& model);
  /// The corrected model and the references on the fit pushes' phases (in-sample).
  void predict_fit_phases();
  void log(const std::string& line) { result_.log.push_back(line); }
  void fail(const std::string& step, const std::string& what);
  bool is_base(std::size_t candidate) const;

  EffectLibrary library_;  // a copy: shared effects, so a temporary library may be passed
  DiagnosisOptions options_;
  DiagnosisResult result_;
  bool single_push_ = false;  ///< one push: fit on all intervals but the last, test on the last
  std::vector<SynchronisedPush> fit_pushes_, test_pushes_;
  std::vector<double> fit_end_s_;            ///< per fit push, the end of its fit span [s]
  std::vector<DiagnosisPush> fit_data_;      ///< the fit pushes as corrected so far, with the observer run over them
  std::vector<PushStudy> base_fit_studies_;  ///< the paper's method on the fit pushes
  std::vector<Eigen::MatrixX3d> residual_before_;   ///< the paper's residual on the fit pushes
  double hold_position_mm_ = 1, hold_yaw_deg_ = 1;  ///< normalisers: mean hold errors on the fit phases
  double log_effective_samples_ = 0;                ///< ln N_eff of the paper's residual: the BIC penalty per parameter
  /// The regression side of the model: the base friction law and its refinements, and the physical effects found so
  /// far (data corrections and force laws).
  std::vector<Selection> model_terms_;
  /// The base model's prediction structure (its parts and their settings).
  std::vector<Selection> prediction_structure_;
  /// The corrected model's signed error on each fit phase (predict_fit_phases), for the adequacy test.
  std::vector<PhaseBias> fit_phase_biases_;
};

}  // namespace pushpred
