#pragma once
// Blind validation of the diagnosis over randomized physics (`pushpred validate-diagnosis`). Each trial draws a
// scenario from ranges wider than the simulator's defaults: one of the dataset's objects with an outline, support
// friction 0.2-0.6, pusher-object friction 0.1-0.4, contact stiffness 5e3-3e4 N/m, a support pressure loading the
// rim or the middle (rim weight -0.3 to 0.6), push speeds of the dataset (10-150 mm/s) or accelerations
// (0.2-2.5 m/s^2), sides, contact positions and angles, sensor noise seeds; one effect kind (or none) at an amount
// drawn between `min_floor_multiple` and `max_floor_multiple` times its floor; 4-8 pushes; and, like the real rig,
// on every push a start either pressed (a preload: the rod already in contact, 0.3-3.7 N, at most 70 % of the
// support's friction so that the object stays put) or a gap of 0.5-2 mm (even odds), and the force sensor's own zero
// error on that push (fx, fy each normal, push-to-push spread `sensor_offset_spread_N`, kSimulatedSensorZeroSpread_N
// by default). Then the diagnosis, which is told nothing of the draw.
//
// Honesty (`hide`): a hidden kind is simulated but left out of the diagnosis's catalogue, as are the simulator's
// effects that have no candidate at all (compliant_pusher): the diagnosis should then say "unexplained residual"
// and name no other kind. A kind without a candidate in the standard catalogue has a floor on the same yardstick
// (simulator_floor): the support's tilt whose downhill force m g sin(alpha) is kappa of the friction force mu m g
// (the support_tilt candidate's floor), the anisotropy whose friction along a body axis differs from the mean by
// kappa of it, |A - 1| = |r - 1| / (r + 1) = kappa (anisotropic_friction's), the pusher compliance whose lag under
// the friction force, c mu m g, is kappa of the pushes' mean travel.
//
// The floor of a trial's effect is the candidate's own floor (candidate_effect.hpp) evaluated on the FloorContext
// the diagnosis measures on the trial's pushes simulated without the effect (measured_simulator_floor: the floor
// the diagnosis itself would state there), then put into the simulator's units
// (simulation/scenario.hpp): the force offset's sim amount is per axis (|b| = sqrt 2 x amount), Stribeck's is
// relative to mu, and the friction patch's relative excess is the one whose friction gradient along the pushes'
// travel (patch_gradient_per_excess: the patch's own force at the simulated states, projected on the candidate's
// regressor) is the position_friction candidate's floor. The fitted gradient is put into the patch's excess the same
// way, at the onset the diagnosis chose, so that its amount error is measured against the excess simulated.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/simulation/scenario.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred {

/// A pessimistic bound on the sensor's zero error [N per axis], the size the large real rest forces would have if
/// they were zeros rather than preloads: what the diagnosis must survive, not what the rig does.
inline constexpr double kPessimisticSensorZeroSpread_N = 0.6;

/// The simulated sensor's own zero error, push to push [N, standard deviation per axis]: what the real rig's rest
/// forces spread beyond the sensor's slow noise. The real rig's clear rests read 0.10 N RMS per axis
/// (kSensorZeroSpread_N, `pushpred inspect`), a mean over a rest of about 0.2 s; the simulator's force noise (its slow
/// Gauss-Markov part, fitted to the same rests' spread within a rest, simulation/sensor_model.hpp) already spreads such
/// a mean by about 0.08 N, so a zero drawn at 0.10 N on top would make the simulated rests spread by 0.14 N, and
/// 0.06 N makes them spread as the real ones do (tests/diagnosis/test_preload.cpp compares the two).
inline constexpr double kSimulatedSensorZeroSpread_N = 0.06;

/// The most pushes a validation trial may draw: the dataset's objects have at most 40 recorded pushes, and a trial of
/// 100 already takes minutes; a larger --max-pushes is a typing error, not a study.
inline constexpr int kMaxValidationPushes = 100;

/// The largest push-to-push spread of the drawn sensor zeros [N]: a tenth of the simulator's bound on a sensor's zero
/// error (kMaxForceOffset_N, 20 N), so that a draw beyond that bound is 10 standard deviations out (never, in
/// practice), and 20 times the real rig's spread; 1e300 made every trial fail.
inline constexpr double kMaxSensorOffsetSpread_N = kMaxForceOffset_N / 10;

struct ValidationOptions {
  int trials_per_kind = 20;
  std::uint64_t seed = 1;  ///< trial k of the whole run uses seed + k: any trial can be re-run alone
  /// Kinds to draw, "none" for clean trials; empty: "none" and every simulator effect.
  std::vector<std::string> kinds;
  int min_pushes = 4, max_pushes = 8;  ///< at most kMaxValidationPushes
  double min_floor_multiple = 1, max_floor_multiple = 5;
  DiagnosisOptions diagnosis;
  int jobs = 1;  ///< trials run in parallel (results do not depend on it)
  /// Kinds left out of the diagnosis's catalogue in every trial (still simulated when drawn). When given and
  /// `kinds` is empty, the kinds drawn are "none" and these.
  std::vector<std::string> hide;
  /// Draw on every push a preload or a gap (false: 1 mm, the simulator's default), and the force sensor's own zero
  /// on that push (false: zeroed).
  bool draw_preloads = true, draw_sensor_offsets = true;
  /// The push-to-push spread (standard deviation per axis) of the drawn sensor zeros [N].
  double sensor_offset_spread_N = kSimulatedSensorZeroSpread_N;
  void validate() const;
};

/// The kinds drawn by default: "none" and every effect of the simulator's catalogue that the standard diagnosis
/// has a candidate for.
std::vector<std::string> default_validation_kinds();
/// The kinds drawn by `options`: its kinds; or "none" and the hidden ones; or default_validation_kinds().
std::vector<std::string> validation_kinds(const ValidationOptions& options);
/// The catalogue the diagnosis uses in the trials of `options`: the standard one without the hidden kinds.
EffectLibrary validation_library(const ValidationOptions& options);

struct ValidationTrial {
  int index = 0;
  std::uint64_t seed = 0;
  std::string true_kind;  ///< "none" for a clean trial
  double amount = 0;      ///< drawn, in the simulator's unit (signed)
  double floor = 0;       ///< the effect's floor in the simulator's unit (0 for none)
  double floor_multiple = 0;
  std::string shape;
  double surface_friction = 0, contact_friction = 0, contact_stiffness_N_m = 0, pressure_rim_weight = 0;
  int pushes = 0;
  std::vector<std::string> named;       ///< the physical effects the diagnosis found
  std::vector<std::string> negligible;  ///< significant but below their floor
  bool true_named = false;              ///< the true kind is among `named` (for none: nothing named)
  /// The diagnosis's amount of the true kind in the simulator's unit (NaN when not found or not comparable).
  double fitted_amount = 0;
  /// What the diagnosis said of the true kind, found or not (for tracing misses): its last score (BIC drop),
  /// whether it passed its test, was negligible, and its amount against the floor the diagnosis measured, both in
  /// the candidate's own unit (NaN for none).
  double true_score = 0;
  bool true_passed = false, true_negligible = false;
  double true_amount = 0, true_floor = 0;
  std::string true_note;
  /// The true kind is not in the diagnosis's catalogue (hidden, or the simulator's effect has no candidate).
  bool hidden = false;
  int preloaded_pushes = 0;  ///< pushes that started with the rod pressing
  /// The diagnosis's model-adequacy verdict: whether it was tested, and "explained" (else "unexplained residual").
  bool adequacy_tested = false, explained = false;
  ErrorSummary before, base, after, hold, const_velocity, quasi_static;
  std::string failure;  ///< why the trial could not be diagnosed (empty: it was)
};

struct ValidationResult {
  ValidationOptions options;
  std::vector<ValidationTrial> trials;
};

/// A FloorContext from the physics of `scenarios` (one trial's pushes, sharing object and surface): mass and inertia
/// of the shape table, the scenario's mu, the pushes' speeds, ramp or push accelerations and lengths.
FloorContext scenario_floor_context(const std::vector<PushScenario>& scenarios, double relevance_fraction);

/// The floor of simulator effect `kind` in the simulator's units for `context` and the object `shape`. Throws
/// InputError for an unknown kind.
double simulator_floor(const std::string& kind, const FloorContext& context, const std::string& shape);

/// The friction gradient g [1/m] (in mu's unit per metre) along the travel that the simulator's friction patch of
/// relative excess 1 gives on the simulated pushes `sims`: the patch's force per unit excess at the simulated states
/// (patch_wrench_per_excess) fitted by least squares on position_friction's regressor with onset `onset_m`, the
/// travel from the push's first pose beyond the onset times the unit Coulomb law's force less its mean over the
/// push's sliding samples, beside the Coulomb law itself (mu takes the mean), over the samples where the object
/// slides. The patch's excess e then gives the gradient e times
/// this, in the candidate's own unit.
double patch_gradient_per_excess(const std::vector<SimulatedPush>& sims, double onset_m);

/// The FloorContext the diagnosis measures on `pushes` (its paper_method and friction_base steps with `options`):
/// what its floors are stated on. Throws what those steps throw.
FloorContext measured_floor_context(const std::vector<SynchronisedPush>& pushes, const DiagnosisOptions& options);

/// The floor of simulator effect `kind` in the simulator's units as the diagnosis would measure it on the pushes
/// of `clean` (the trial's scenarios without the effect, simulated); the scenario's physics
/// (scenario_floor_context) where no floor can be measured. For the friction patch, the excess whose gradient
/// (patch_gradient_per_excess) is the candidate's floor.
double measured_simulator_floor(const std::string& kind, const std::vector<PushScenario>& clean,
                                const DiagnosisOptions& options, const std::string& shape);

/// The pushes of trial `index` (kind and amount drawn inside): deterministic in (options.seed + index, kind).
std::vector<PushScenario> draw_validation_trial(const ValidationOptions& options, int index, const std::string& kind,
                                                ValidationTrial& trial);

/// The trial's pushes simulated and synchronised as load_push would read them from files.
std::vector<SynchronisedPush> simulate_trial(const std::vector<PushScenario>& scenarios);
/// Fills trial's outcome (named, negligible, true_named, fitted_amount, errors) from the diagnosis of its pushes.
void score_trial(const DiagnosisResult& result, ValidationTrial& trial);

/// Runs every trial; `progress(done, total)` after each (from the calling thread's view: may be called from
/// worker threads, one at a time).
ValidationResult validate_diagnosis(const ValidationOptions& options,
                                    const std::function<void(int, int)>& progress = {});
/// The number of trials of a whole run: trials_per_kind times the kinds (default_validation_kinds when empty).
int validation_trial_count(const ValidationOptions& options);
/// validate_diagnosis on the trials `indices` only (0-based, each below validation_trial_count; a shard of the
/// run, runtime/shard.hpp): each trial is the whole run's trial of that index; result.trials holds them in the order
/// given, result.options has the kinds filled in as validate_diagnosis's.
ValidationResult validate_diagnosis_trials(const ValidationOptions& options, const std::vector<int>& indices,
                                           const std::function<void(int, int)>& progress = {});

/// Summary numbers of a validation, as the report states them.
struct ValidationSummary {
  int trials = 0, failed = 0;
  int effect_trials_at_twice_floor = 0, named_at_twice_floor = 0;
  int clean_trials = 0, clean_nothing_named = 0;
  int after_below_paper = 0, after_below_const_velocity = 0, compared = 0;
  // Honesty: trials whose kind the catalogue lacks, at twice its floor or more; with the adequacy test's verdict.
  int hidden_trials_at_twice_floor = 0, hidden_adequacy_tested = 0, hidden_unexplained = 0, hidden_none_named = 0;
  int clean_adequacy_tested = 0, clean_explained = 0;
};
ValidationSummary summarise_validation(const ValidationResult& result);

}  // namespace pushpred
