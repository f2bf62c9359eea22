#pragma once
// Online identification of the quasi-static pushing model (quasi_static_pushing.hpp) from a push's measured tip
// and object motion and force, and the model's prediction of one phase: the API a study, the diagnosis or a
// user's program calls.
//
// Identification, on the intervals measured so far (fed one by one, like a RelationEstimator), on the grid samples
// where the force sensor reports contact and the tip moves faster than `min_tip_speed_m_s`:
// - measured: the object's twist and the tip's velocity by central differences over +-`difference_half_window_s`
//   (SI, {R}), the force f_C and its torque about the CoF (synchronised_push.hpp);
// - contact geometry: the outline (see contact_outline_for) at the measured poses;
// - Ceres fits (mu_p, c, mu_s) over all samples at once, bounded to physical ranges, with a Huber loss:
//     kinematics, per sample: (v_meas - v_qs, c0 (omega_meas - omega_qs)) / sigma_v, with v_qs, omega_qs the
//       quasi-static motion (quasi_static_motion) under the measured tip velocity, c0 the default c;
//     force, per sample where the object moves: (sqrt(|f|^2 + (m / c)^2) - mu_s m g) / sigma_f, the wrench on the
//       ellipsoidal limit surface (a quasi-statically sliding object is pushed by the support's friction wrench).
//     prior, per parameter: (theta - theta_default) / sigma_prior (QuasiStaticIdentificationOptions::use_prior).
//   Optionally (prior_centre_offset_std_m > 0) the fit also estimates delta, the CoF's offset from the shape table's
//   centroid (body frame): the pressure under a real object need not centre on its tracked centre.
// - Covariance: Ceres' covariance of (mu_p, c, mu_s) (QuasiStaticIdentification::fit_covariance). With the prior,
//   a parameter whose posterior standard deviation stays near its prior's is reported as "default: ..." (the data
//   add little; e.g. every contact sample stuck, so mu_p is only bounded below) with the posterior's value and std.
//   Without the prior, a parameter is determined when its Jacobian column is not negligible and its standard deviation
//   is below half its value; otherwise it is fixed at its default, std 0, and `sources` says why.
// - The contact offset: the rod-outline distance measured at the phase's start when the sensor reports contact
//   there; else the median over the identified contact samples (zero without any), lowered if need be so that the
//   rod does not start inside the outline: the model starts the phase in contact exactly when the data do.
// - Samples within `contact_settling_s` of a contact's onset are left out (the object accelerates from rest).
// QuasiStaticEstimator is an OnlineParameterEstimator (estimators/online_parameter_estimator.hpp), the interface it
// shares with the relation estimators: its estimate() holds pusher_friction [-], torque_ratio_m [m],
// support_friction [-] and contact_offset_m [m], with fit_covariance and the contact offset's variance (the offset
// is measured apart from the fit, so uncorrelated with it).
//
// Physical defaults (not fitted to any data set): mu_p 0.25 (steel on steel), mu_s 0.3 (steel on ABS), c the
// uniform-pressure value of the footprint (uniform_pressure_torque_ratio), or 0.94 sqrt(I / m) where the outline is
// not known (the ratio of c to the radius of gyration is 0.94 for a uniform disk and 0.94 for a square).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/estimators/online_parameter_estimator.hpp"
#include "pushpred/prediction/quasi_static_contact.hpp"
#include "pushpred/prediction/quasi_static_pushing.hpp"
#include "pushpred/prediction/schedule.hpp"

namespace pushpred {

struct QuasiStaticIdentificationOptions {
  double difference_half_window_s = 0.02;
  double min_tip_speed_m_s = 5e-3;     ///< samples slower than this carry no kinematic information
  double min_object_speed_m_s = 5e-3;  ///< force samples: the object must slide for its wrench to be on the limit surface
  double velocity_noise_m_s = 3e-3;    ///< sigma_v, also the Huber scale (in sigmas: 1)
  /// Samples within this time after a contact's onset are left out: the object accelerates from rest there, which
  /// the quasi-static model leaves out (the pusher's own speed ramp takes about 0.05 s, docs/simulator.md).
  double contact_settling_s = 0.05;
  double force_noise_N = 0.3;          ///< sigma_f
  int min_samples = 3;                 ///< fewer samples: defaults
  QuasiStaticParameters defaults;      ///< torque_ratio_m <= 0: from the shape (see above)
  /// A Gaussian prior about the defaults (a maximum a posteriori fit), so that a few samples inform without
  /// overturning physics: standard deviations of mu_p, c as a fraction of its default, and mu_s. A parameter whose
  /// posterior standard deviation stays above `prior_dominated_fraction` of its prior's is reported as a default.
  /// use_prior false: a plain fit, where undetermined parameters are fixed at their defaults.
  bool use_prior = true;
  double prior_pusher_friction_std = 0.1, prior_torque_ratio_fraction = 0.3, prior_support_friction_std = 0.15;
  double prior_dominated_fraction = 0.7;
  /// Prior std of the CoF's offset from the shape table's centroid, per axis [m]; 0 (default): no offset
  /// identified. Tried at 2 mm (docs/prediction.md): the real pushes' position error drops a little, but on simulated
  /// pushes the offset trades off against mu_p and biases it.
  double prior_centre_offset_std_m = 0;
};

/// The identified model of one push after some intervals, with standard deviations and where each value came from.
struct QuasiStaticIdentification {
  QuasiStaticParameters parameters;
  /// Standard deviations of mu_p, c [m], mu_s, contact offset [m] (0 for a default).
  Eigen::Vector4d std = Eigen::Vector4d::Zero();
  /// Covariance of (mu_p, c [m], mu_s) from the fit: its diagonal is std(0..2)^2, the correlations are Ceres' (zero
  /// where the covariance could not be computed, and for a parameter held at its default by the plain fit).
  Eigen::Matrix3d fit_covariance = Eigen::Matrix3d::Zero();
  /// Per parameter (mu_p, c, mu_s, contact offset): "identified" or "default: REASON".
  std::array<std::string, 4> sources;
  /// The CoF's identified offset from the shape table's centroid, body frame [m] (zero unless identified).
  Eigen::Vector2d centre_offset_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d centre_offset_std_m = Eigen::Vector2d::Zero();
  std::string centre_offset_source = "default: not identified";
  long kinematic_samples = 0, force_samples = 0, sliding_samples = 0;
  long intervals = 0;
  static const std::array<const char*, 4>& names();  ///< "pusher_friction", "torque_ratio_m", "support_friction", "contact_offset_m"
};

/// Identifies the model online: feed the measured intervals one after another, ask for the parameters at any time.
class QuasiStaticEstimator final : public OnlineParameterEstimator {
 public:
  explicit QuasiStaticEstimator(QuasiStaticIdentificationOptions options = {});
  std::string name() const override { return "quasi_static"; }
  /// Starts over on a new push (the outline and defaults come from it).
  void reset(const SynchronisedPush& push);
  /// Adds the samples of `interval` of the push given to reset (InputError for an interval outside it).
  void add_interval(const TimeInterval& interval);
  /// The fit over every interval so far; the contact offset is the median rod-outline distance of the contact
  /// samples (predict_quasi_static_phase replaces it by the one measured at the phase's start). Never throws for
  /// lack of data: parameters without information keep their defaults, and say so.
  QuasiStaticIdentification identify() const;

  // The common interface (online_parameter_estimator.hpp).
  /// Forgets the push and its intervals; the next interval's push is the one identified.
  void reset() override;
  /// The first interval after reset() starts on its push (as reset(push)); an interval of another push before the
  /// next reset() is an InputError. Only the push is read, not the observer's output.
  void add_interval(const IdentificationInterval& interval) override;
  /// Ready once it has a push: from then on every parameter has a value (its default until the data inform it).
  std::string not_ready_reason() const override;

 protected:
  ParameterEstimate current_estimate() const override;

 private:
  struct Sample {
    Eigen::Vector2d contact_from_cof_m, inward_normal, tip_velocity_m_s, object_velocity_m_s;
    double omega_rad_s = 0;
    bool moving = false;
    Eigen::Vector2d point_from_centre_m, centre_velocity_m_s, force_vector_N;
    double yaw_rad = 0, torque_about_centre_Nm = 0;
  };
  QuasiStaticIdentificationOptions options_;
  const SynchronisedPush* push_ = nullptr;
  std::shared_ptr<const ContactOutline> outline_;
  QuasiStaticParameters defaults_;
  std::vector<Sample> samples_;
  std::vector<double> gaps_m_;
  long intervals_ = 0;
};

/// One phase predicted by the quasi-static model, with what it was predicted with.
struct QuasiStaticPhase {
  Eigen::MatrixX3d poses;  ///< at the output times
  QuasiStaticIdentification identification;
  std::string note;        ///< e.g. which outline was used
};

/// Predicts `phase` of `push`: identifies the model on `identified` (the intervals measured before the phase), plans
/// the tip path at `plan_rate_hz` (plan_tip_velocity_from_measurement) from the tip's measured position at the
/// phase's start, and integrates from the measured pose there with tracked-centre velocity `velocity0` (x, y [m/s],
/// yaw rate; e.g. the observer's estimate) to `output_times_s`. This is what the `quasi_static` predictor does; a
/// caller that already holds a QuasiStaticEstimator fed with those intervals passes it to skip the refeeding.
/// `free_slide_terms`: QuasiStaticObject::free_slide_terms (empty: the identified Coulomb friction of mu_s).
/// `contact_compliance_m_N`: QuasiStaticParameters::contact_compliance_m_N; where the rod touches at the phase's start,
/// the contact offset then adds the compliance times the normal force measured there, so that the model's rod starts
/// as deep as that force presses it.
QuasiStaticPhase predict_quasi_static_phase(
    const SynchronisedPush& push, const std::vector<TimeInterval>& identified, const TimeInterval& phase,
    double plan_rate_hz, const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times_s,
    const IntegratorOptions& integrator = quasi_static_integrator_options(),
    const QuasiStaticEstimator* fed_estimator = nullptr,
    std::vector<std::shared_ptr<const GeneralizedForceTerm>> free_slide_terms = {}, double contact_compliance_m_N = 0);

}  // namespace pushpred
