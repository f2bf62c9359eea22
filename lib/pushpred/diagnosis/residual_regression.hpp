#pragma once
// The disturbance regression of candidate_effect.hpp over a set of pushes, and the statistics that decide
// whether effects explain the residual.
//
// Two bases for what the effects are tested against:
// - Relation::Linear, the paper's: per push and channel, beta (Q u_c) + eps is projected out of d_hat and of
//   every effect column (Frisch-Waugh), so that effect parameters are fitted jointly with a free relation per
//   push, as the paper's online estimator would have it (6 nuisance parameters per push).
// - Relation::Friction: no free relation. Samples where the object is stuck (sliding speed below
//   kStuckSpeed_m_s) are taken as balanced by static friction, d = -u, and explain nothing else (every column is
//   zero there); on sliding samples d_hat is explained by the effect columns alone, among them a friction law that
//   replaces the relation (ForceLawEffect::support_friction() ReplacesRelation: Coulomb friction). In quasi-static
//   pushing the free relation absorbs any friction law (the push force mirrors the friction), so friction effects
//   are only visible against this base.
// Channels are weighted by 1 / sigma_c, sigma_c the Linear base's residual standard deviation pooled over the
// pushes, so that newtons and newton metres add up; parameters stay in physical units.
//
// Statistics:
// - Parameter covariance: heteroscedasticity-and-autocorrelation-consistent (Newey-West, Bartlett weights, lag
//   kHacLag_s within each push, the three channels of a sample together). The observer's output is strongly
//   autocorrelated (its Q filter is a 48 Hz low-pass of a 250 Hz signal, and model errors are slow), so the plain
//   least-squares covariance would be far too small. Beside it, the covariance clustered by push: an effect that
//   differs mostly between pushes (a drag against the pushes' speeds) is only as certain as the pushes agree, which
//   no within-push lag window sees. Tests use Newey-West (with few pushes the clustered one is too noisy to
//   test with); reported standard errors are the larger of the two.
// - Effective sample count N_eff = sum over push-channel blocks of n (1 - rho) / (1 + rho), rho the lag-1
//   autocorrelation of the Linear base's residual (the AR(1) variance-inflation rule).
// - Adding effects to a model (nested): the BIC drop is approximated by the robust Wald statistic of the added
//   parameters minus their BIC penalty, W - k ln(N_eff).
// - Changing the base (not nested): BIC = N_eff ln(RSS / N) + k ln(N_eff), k counting the nuisance.
//
// Each push's own force-sensor zero (a sensor not zeroed between pushes; sensor_zero_columns()) is, on a
// straight push, a constant the friction law cannot tell from Coulomb friction, and its torque l x z is what a
// mass-centre offset or a drag at one speed looks like. With SensorZeros::PerPush the regression is invariant to it
// where it can reach, when two pushes or more rest clear of the object (measured_sensor_zero): each such push's
// zero less their mean is taken out of its residual (the mean, a force the pushes share, stays for the effects that
// describe it), shrunk by max(0, 1 - K sigma^2 / s^2) (the best linear predictor of a random zero seen through
// noise), s the zeros' spread (zero_spread_N), sigma^2 the rest samples' variance and K = kZeroNoiseFactor; on every
// other push (the rod starts pressed) the zero is a random effect about zero with the rig's known push-to-push spread s
// (DiagnosisPush::sensor_zero_spread_N, DiagnosisOptions::sensor_zero_spread_N; the measured zeros' own spread where
// two or more are measured and spread more): the push's two zero columns are
// taken out of the residual and of every column as far as a zero of about s can reach them (a ridge on the zero,
// eliminated: a partial projection, 2 nuisance parameters a push), or projected out wholly as fixed effects when s is
// 0. A free constant on a pressed push would take up, within a straight push, the Coulomb friction's constant and
// what an offset's torque or a drag at one speed puts there, and leave the rest to stand in for effects that are not
// there (a drag and Stribeck friction on clean simulated pushes); bounded by the spread it cannot. One measured push
// stays as recorded; with none the zeros stay in the data: the friction law's constant part rests on the measured
// pushes.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "pushpred/diagnosis/diagnosis_data.hpp"

namespace pushpred {

/// Regressor columns of one effect: [parameter][push], each n_push x 3 (channels).
using EffectColumns = std::vector<std::vector<Eigen::MatrixX3d>>;

/// Lag window of the Newey-West covariance [s].
inline constexpr double kHacLag_s = 0.2;
/// Against the friction law, samples this close to a change between stuck and sliding are left out: there the
/// switch between static balance and the law is only known to within the smoothing's and the observer's time
/// scales, and a sharp friction law misfits for reasons no candidate effect describes [s].
inline constexpr double kTransitionGuard_s = 0.03;

/// Per row of `d`: 1 where the friction law is tested (not within kTransitionGuard_s of a change between stuck and
/// sliding, and the speed resolved: DiagnosisPush::unresolved), 0 elsewhere.
std::vector<char> friction_law_samples(const DiagnosisPush& d);

enum class Relation { Linear, Friction };

/// K above: a rest of a few tenths of a second spans two or three correlation times of the sensor's slow noise
/// (docs/simulator.md), so the variance within it understates the error of its mean; deviations are taken out only
/// where their spread exceeds twice the rest's standard deviation. Chosen between 1 and 4 on tuning seeds
/// 348000-348599 (docs/diagnosis.md) and the sensor-zeroed pushes of tests/diagnosis.
inline constexpr double kZeroNoiseFactor = 4.0;

/// The weighted residual's variance per sample in the pressed pushes' zero prior (above): the weights are the
/// Linear base's residual RMS per channel, so noise alone is at most 1 there; the upper bound makes the prior the
/// stronger one beside the data, so a zero never takes up more than a zero of the rig's spread could.
inline constexpr double kZeroPriorResidualVariance = 1.0;

/// How the regression treats each push's own sensor zero (see above).
enum class SensorZeros { AsRecorded, PerPush };
/// The pooled spread of measured zeros about their mean, sqrt(sum |z - mean|^2 / (2 (m - 1))) [N], one spread for
/// both axes over the m >= 2 measured ones; NaN for fewer.
double zero_spread_N(const std::vector<std::optional<Eigen::Vector2d>>& zeros);

/// What each push's own constant sensor zero z = (z_x, z_y) [N, world frame] puts in d_hat, as EffectColumns with
/// two columns per push (2p: z_x, 2p + 1: z_y), zero on every other push: the force z and its torque l x z about the
/// object centre at the measured lever l = r_C - r_O, through the observer like any regressor.
EffectColumns sensor_zero_columns(const std::vector<DiagnosisPush>& pushes);
/// One push's two columns of sensor_zero_columns() (z_x, z_y), without the other pushes' zero blocks.
std::array<Eigen::MatrixX3d, 2> push_sensor_zero_columns(const DiagnosisPush& push);

struct RegressionFit {
  Eigen::VectorXd theta;       ///< effect parameters, in the order of the columns given
  Eigen::MatrixXd covariance;  ///< Newey-West
  /// Clustered by push (every sample of a push may correlate with every other), times P / (P - 1): the honest
  /// uncertainty of a constant shared by the pushes when each push carries its own model error.
  Eigen::MatrixXd cluster_covariance;
  double rss = 0;              ///< weighted residual sum of squares (dimensionless)
  double bic = 0;              ///< N_eff ln(RSS / N) + k ln(N_eff), k including the base's nuisance
  int parameters = 0;          ///< effect parameters (plus settings) counted in k
  bool identifiable = true;    ///< false when the columns are (numerically) dependent: bic is then +inf
  /// Whether the clustered covariance counts beside Newey-West's: from three pushes (clusters) on.
  bool uses_cluster_covariance() const;
  /// The larger of the two covariances' standard errors.
  Eigen::VectorXd standard_error() const;
  /// The blocks [first, first + count) of the covariances standard_error() reads (Newey-West, and the clustered one
  /// where it is used).
  std::vector<Eigen::MatrixXd> covariance_blocks(Eigen::Index first, Eigen::Index count) const;
  /// Robust Wald statistic of the parameters [first, first + count): theta^T V^-1 theta with Newey-West's V.
  double wald(Eigen::Index first, Eigen::Index count) const;
  int clusters = 0;
};

class ResidualRegression {
 public:
  /// Throws InputError for no pushes or a push with fewer than 3 rows.
  ResidualRegression(const std::vector<DiagnosisPush>& pushes, Relation relation = Relation::Linear,
                     SensorZeros zeros = SensorZeros::AsRecorded);

  /// Fits the effect parameters of `columns` (concatenated: one EffectColumns per effect) jointly with the
  /// base. `extra_parameters` adds to k (settings chosen on a grid).
  RegressionFit fit(const std::vector<const EffectColumns*>& columns, int extra_parameters = 0) const;

  /// Per push, the residual (unweighted, n x 3) after the base and sum Phi theta.
  std::vector<Eigen::MatrixX3d> residuals(const std::vector<const EffectColumns*>& columns,
                                          const Eigen::VectorXd& theta) const;

  /// The weighted base residual `y` and the weighted columns `X` in the base, stacked as fit() fits them: per push,
  /// its x, y and rotation channels one after the other (push_rows() rows each).
  void stack(const std::vector<const EffectColumns*>& columns, Eigen::VectorXd& y, Eigen::MatrixXd& X) const;
  /// Rows (samples) per push.
  std::vector<Eigen::Index> push_rows() const;

  Relation relation() const { return relation_; }
  long samples() const { return samples_; }  ///< N: rows x channels
  double effective_samples() const { return effective_samples_; }
  const Eigen::Vector3d& channel_scale() const { return scale_; }  ///< sigma_c [N, N, N m]
  /// 6 per push for Linear, 0 for Friction; with SensorZeros::PerPush 2 more for each push whose zero is projected.
  int nuisance_parameters() const;
  /// Pushes whose sensor zero is projected out, and pushes whose measured zero's deviation is taken out.
  int zeros_projected() const { return zeros_projected_; }
  int zeros_measured() const { return zeros_measured_; }
  /// Share of the fit samples where the object slides.
  double sliding_share() const;

 private:
  /// The base applied to column `x` of push p, channel c, in place: the nuisance projected out (Linear) or the
  /// stuck samples zeroed (Friction).
  void to_base(std::size_t p, int c, Eigen::Ref<Eigen::VectorXd> x) const;

  struct Block {
    Eigen::VectorXd centred_input[3];  ///< Q u_c minus its mean (zero when it does not vary)
    double input_norm2[3] = {0, 0, 0};
    std::vector<char> stuck;
    std::vector<char> used;  ///< Friction: not near a stuck-sliding change
    Eigen::MatrixX3d residual;  ///< d_hat in the base: nuisance projected out, or d_hat + Q u at stuck samples
    double rate_hz = 250;
    /// SensorZeros::PerPush, a push whose zero is not measured: an orthonormal basis of its weighted zero columns in
    /// the base, over the push's stacked rows (3 n); empty otherwise.
    Eigen::MatrixXd zero_basis;
    /// How much of each zero_basis direction is taken out (the zero's prior, above; 1: all, a fixed effect); empty:
    /// all. zero_basis is then the left singular vectors of the weighted zero columns.
    Eigen::VectorXd zero_share;
  };
  /// SensorZeros::PerPush (see above), after the channel weights are set.
  void take_out_sensor_zeros(const std::vector<DiagnosisPush>& pushes);
  /// Projects push p's stacked rows (3 n, weighted) off its zero basis, in place.
  void project_zero(std::size_t p, Eigen::Ref<Eigen::MatrixXd> rows) const;
  Relation relation_;
  std::vector<Block> blocks_;
  Eigen::Vector3d scale_ = Eigen::Vector3d::Ones();
  long samples_ = 0;
  double effective_samples_ = 0;
  int zeros_projected_ = 0;
  int zeros_measured_ = 0;
};

/// Lag-1 autocorrelation of `r`, clamped to [0, 0.999].
double lag1_autocorrelation(const Eigen::Ref<const Eigen::VectorXd>& r);
/// n (1 - rho) / (1 + rho) with rho = lag1_autocorrelation(r).
double effective_sample_count(const Eigen::Ref<const Eigen::VectorXd>& r);
/// Newey-West long-run variance of the mean of `r` (Bartlett weights up to `lag`): the variance of the
/// sample mean of an autocorrelated series, times n.
double long_run_variance(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Index lag);
/// ln P(X > f) for X ~ F(2, d): -(d / 2) ln(1 + 2 f / d) (chi^2_2 / 2 is exponential; its tail at f times a
/// chi^2_d / d is that variable's moment-generating function at -f). The test of a force shared by pushes whose zeros'
/// spread is estimated from them, on d = 2 (pushes - 1) degrees of freedom.
double log_f2_tail(double f, double d);

}  // namespace pushpred
