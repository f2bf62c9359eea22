#include "pushpred/diagnosis/residual_regression.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"

namespace pushpred {

bool RegressionFit::uses_cluster_covariance() const {
  return clusters >= 3 && cluster_covariance.size() == covariance.size();
}

Eigen::VectorXd RegressionFit::standard_error() const {
  Eigen::VectorXd v = covariance.diagonal().cwiseMax(0.0);
  if (uses_cluster_covariance()) v = v.cwiseMax(cluster_covariance.diagonal());
  return v.cwiseSqrt();
}

std::vector<Eigen::MatrixXd> RegressionFit::covariance_blocks(Eigen::Index first, Eigen::Index count) const {
  std::vector<Eigen::MatrixXd> out;
  if (first < 0 || count < 0 || first + count > covariance.rows()) return out;
  out.push_back(covariance.block(first, first, count, count));
  if (uses_cluster_covariance()) out.push_back(cluster_covariance.block(first, first, count, count));
  return out;
}

namespace {

double wald_with(const Eigen::VectorXd& t, const Eigen::MatrixXd& V) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(V);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return 0.0;
  return t.dot(ldlt.solve(t));
}

}  // namespace

double RegressionFit::wald(Eigen::Index first, Eigen::Index count) const {
  if (!identifiable) return 0.0;
  const Eigen::VectorXd t = theta.segment(first, count);
  double w = wald_with(t, covariance.block(first, first, count, count));
  return w;
}

double lag1_autocorrelation(const Eigen::Ref<const Eigen::VectorXd>& r) {
  const Eigen::Index n = r.size();
  if (n < 3) return 0.0;
  const double denominator = r.squaredNorm();
  if (!(denominator > 0)) return 0.0;
  const double rho = r.head(n - 1).dot(r.tail(n - 1)) / denominator;
  return std::clamp(rho, 0.0, 0.999);
}

double effective_sample_count(const Eigen::Ref<const Eigen::VectorXd>& r) {
  const double rho = lag1_autocorrelation(r);
  return static_cast<double>(r.size()) * (1 - rho) / (1 + rho);
}

double log_f2_tail(double f, double d) { return -0.5 * d * std::log1p(2 * f / d); }

double long_run_variance(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Index lag) {
  const Eigen::Index n = r.size();
  if (n == 0) return 0.0;
  const Eigen::VectorXd c = r.array() - r.mean();
  double s = c.squaredNorm();
  for (Eigen::Index l = 1; l <= std::min(lag, n - 1); ++l)
    s += 2 * (1 - static_cast<double>(l) / static_cast<double>(lag + 1)) * c.head(n - l).dot(c.tail(n - l));
  return std::max(s, 0.0) / static_cast<double>(n);
}

std::vector<char> friction_law_samples(const DiagnosisPush& d) {
  const Eigen::Index n = d.rows();
  std::vector<char> used(n, 1);
  const double rate_hz = d.push.rate_hz > 0 ? d.push.rate_hz : 250.0;
  const auto guard = static_cast<Eigen::Index>(std::lround(kTransitionGuard_s * rate_hz));
  for (Eigen::Index k = 1; k < n; ++k)
    if (d.stuck[k] != d.stuck[k - 1])
      for (Eigen::Index j = std::max<Eigen::Index>(0, k - guard); j < std::min(n, k + guard); ++j) used[j] = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (d.unresolved[k]) used[k] = 0;
  return used;
}

ResidualRegression::ResidualRegression(const std::vector<DiagnosisPush>& pushes, Relation relation,
                                       SensorZeros zeros)
    : relation_(relation) {
  if (pushes.empty()) throw InputError("diagnosis regression: no pushes to fit");
  blocks_.resize(pushes.size());
  Eigen::Vector3d sum2 = Eigen::Vector3d::Zero();
  double dof = 0;
  std::vector<Eigen::MatrixX3d> linear_residual(pushes.size());
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    const DiagnosisPush& d = pushes[p];
    const Eigen::Index n = d.rows();
    if (n < 3) throw InputError(about(d.push.source, "diagnosis regression: fewer than 3 samples to fit"));
    Block& b = blocks_[p];
    b.rate_hz = d.push.rate_hz > 0 ? d.push.rate_hz : 250.0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::VectorXd qu = d.filtered_input.col(c);
      b.centred_input[c] = qu.array() - qu.mean();
      b.input_norm2[c] = b.centred_input[c].squaredNorm();
      // An input that does not vary leaves only eps to fit.
      if (!(b.input_norm2[c] > 1e-12 * std::max(1.0, qu.squaredNorm()))) {
        b.centred_input[c].setZero();
        b.input_norm2[c] = 0;
      }
    }
    b.stuck = d.stuck;
    b.used = relation_ == Relation::Friction ? friction_law_samples(d) : std::vector<char>(n, 1);
    // The Linear base's residual sets the channel weights and N_eff for both bases.
    Eigen::MatrixX3d lin = d.estimate.d_hat;
    const Relation keep = relation_;
    relation_ = Relation::Linear;
    for (int c = 0; c < 3; ++c) to_base(p, c, lin.col(c));
    relation_ = keep;
    sum2 += lin.colwise().squaredNorm().transpose();
    dof += static_cast<double>(n) - 2;
    samples_ += 3 * n;
    linear_residual[p] = lin;
    if (relation_ == Relation::Linear) {
      b.residual = lin;
    } else {
      // Static balance where stuck: d = -u there, which the observer sees as -Q (stuck u).
      Eigen::MatrixX3d stuck_input = Eigen::MatrixX3d::Zero(n, 3);
      for (Eigen::Index k = 0; k < n; ++k)
        if (b.stuck[k]) stuck_input.row(k) = d.estimate.u.row(k);
      b.residual = d.estimate.d_hat + q_filter(d.estimate.t_s, stuck_input, d.q_zeta, d.q_wn_rad_s, nullptr,
                                               FilterOutput::IntervalMean);
      for (Eigen::Index k = 0; k < n; ++k)
        if (!b.used[k]) b.residual.row(k).setZero();
    }
  }
  for (int c = 0; c < 3; ++c) scale_(c) = sum2(c) > 0 ? std::sqrt(sum2(c) / dof) : 1.0;
  for (const auto& r : linear_residual)
    for (int c = 0; c < 3; ++c) effective_samples_ += effective_sample_count(r.col(c));
  effective_samples_ = std::max(effective_samples_, 2.0);
  if (zeros == SensorZeros::PerPush) take_out_sensor_zeros(pushes);
}

double zero_spread_N(const std::vector<std::optional<Eigen::Vector2d>>& zeros) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  int m = 0;
  for (const auto& z : zeros)
    if (z) {
      mean += *z;
      ++m;
    }
  if (m < 2) return std::numeric_limits<double>::quiet_NaN();
  mean /= m;
  double sum2 = 0;
  for (const auto& z : zeros)
    if (z) sum2 += (*z - mean).squaredNorm();
  return std::sqrt(sum2 / (2.0 * (m - 1)));
}

void ResidualRegression::take_out_sensor_zeros(const std::vector<DiagnosisPush>& pushes) {
  std::vector<std::optional<Eigen::Vector2d>> measured;
  double noise_variance = 0;  // the rest samples' variance per axis, averaged over the measured pushes [N^2]
  for (const auto& d : pushes) {
    const std::optional<MeasuredZero> z = measured_sensor_zero(d);
    measured.push_back(z ? std::optional<Eigen::Vector2d>(z->zero_N) : std::nullopt);
    if (z) noise_variance += z->variance_N2;
  }
  const auto m = std::count_if(measured.begin(), measured.end(), [](const auto& z) { return z.has_value(); });
  // The friction law's constant part is known only where a zero is: with no measured push, projecting every push's
  // zero would leave the law to the little that varies within a push (a straight slide: nothing), so the zeros then
  // stay in the data.
  if (m == 0) return;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& z : measured)
    if (z) mean += *z / static_cast<double>(m);
  noise_variance /= static_cast<double>(m);
  // One measured push is the friction law's anchor as recorded: alone it cannot tell its zero from a shared force.
  const double measured_spread = m >= 2 ? zero_spread_N(measured) : 0.0;
  const double shrink = measured_spread > 0
                            ? std::max(0.0, 1 - kZeroNoiseFactor * noise_variance / (measured_spread * measured_spread))
                            : 0.0;
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    Block& b = blocks_[p];
    const Eigen::Index n = b.residual.rows();
    std::array<Eigen::MatrixX3d, 2> zero = push_sensor_zero_columns(pushes[p]);
    for (auto& z : zero)
      for (int c = 0; c < 3; ++c) to_base(p, c, z.col(c));
    if (measured[p]) {
      if (!(shrink > 0)) continue;
      const Eigen::Vector2d deviation = shrink * (*measured[p] - mean);
      b.residual -= deviation.x() * zero[0] + deviation.y() * zero[1];
      ++zeros_measured_;
      continue;
    }
    Eigen::MatrixXd stacked(3 * n, 2);
    for (int j = 0; j < 2; ++j)
      for (int c = 0; c < 3; ++c) stacked.col(j).segment(c * n, n) = zero[j].col(c) / scale_(c);
    // The rig's known spread s bounds the zero: a random effect of prior N(0, s^2) per axis, not a free constant. Its
    // ridge lambda = sigma^2 / (r s^2) (the weighted residual's variance per sample, at most 1 as the weights are the
    // Linear residual's RMS, over the share r = N_eff / N its autocorrelation leaves) turns the projection off the
    // zero's direction i (singular value d_i of the weighted columns) into a partial one, 1 - sqrt(lambda / (d_i^2 +
    // lambda)) of it: where the data pin the zero down (d_i^2 >> lambda) it goes as before, where a zero of about s
    // would hardly show (the torque l x z beside an offset's, a constant beside a drag at one speed) it stays.
    // Where the measured zeros spread more than the rig's known spread says (a sensor worse than the rig's), theirs.
    if (const double prior = pushes[p].sensor_zero_spread_N; prior > 0) {
      const double spread = std::max(prior, measured_spread);
      // The weighted columns' singular directions from their 2 x 2 Gram matrix (a fixed-size eigenproblem: a dynamic
      // Eigen SVD here would share its template instantiation with the one Ceres's covariance uses, which Ceres's own
      // build lays out differently).
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> gram(stacked.transpose() * stacked);
      const Eigen::Vector2d d2 = gram.eigenvalues().reverse();  // squared singular values, largest first
      const Eigen::Matrix2d v = gram.eigenvectors().rowwise().reverse();
      const double lambda =
          kZeroPriorResidualVariance * static_cast<double>(samples_) / (effective_samples_ * spread * spread);
      Eigen::Index kept = 0;
      while (kept < 2 && d2(kept) > 1e-12 * std::max(1.0, d2(0))) ++kept;
      if (kept == 0) continue;  // stuck or outside the law's samples throughout: nothing to take out
      b.zero_basis = stacked * v.leftCols(kept) * d2.head(kept).cwiseSqrt().cwiseInverse().asDiagonal();
      b.zero_share = (1 - (lambda / (d2.head(kept).array() + lambda)).sqrt()).matrix();
      ++zeros_projected_;
      continue;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(stacked);
    if (qr.rank() == 0) continue;  // stuck or outside the law's samples throughout: nothing to project
    b.zero_basis = qr.householderQ() * Eigen::MatrixXd::Identity(3 * n, qr.rank());
    ++zeros_projected_;
  }
}

void ResidualRegression::project_zero(std::size_t p, Eigen::Ref<Eigen::MatrixXd> rows) const {
  const Eigen::MatrixXd& q = blocks_[p].zero_basis;
  if (q.cols() == 0) return;
  if (blocks_[p].zero_share.size() > 0) {
    rows -= q * (blocks_[p].zero_share.asDiagonal() * (q.transpose() * rows));
    return;
  }
  rows -= q * (q.transpose() * rows);
}

int ResidualRegression::nuisance_parameters() const {
  int zero_columns = 0;
  for (const auto& b : blocks_) zero_columns += static_cast<int>(b.zero_basis.cols());
  return (relation_ == Relation::Linear ? 6 * static_cast<int>(blocks_.size()) : 0) + zero_columns;
}

double ResidualRegression::sliding_share() const {
  double sliding = 0, all = 0;
  for (const auto& b : blocks_)
    for (char s : b.stuck) {
      sliding += s ? 0 : 1;
      all += 1;
    }
  return all > 0 ? sliding / all : 0.0;
}

void ResidualRegression::to_base(std::size_t p, int c, Eigen::Ref<Eigen::VectorXd> x) const {
  const Block& b = blocks_[p];
  if (relation_ == Relation::Linear) {
    x.array() -= x.mean();
    if (b.input_norm2[c] > 0) x -= (b.centred_input[c].dot(x) / b.input_norm2[c]) * b.centred_input[c];
  } else {
    for (Eigen::Index k = 0; k < x.size(); ++k)
      if (!b.used[k]) x(k) = 0;
  }
}

void ResidualRegression::stack(const std::vector<const EffectColumns*>& columns, Eigen::VectorXd& y,
                               Eigen::MatrixXd& X) const {
  int k = 0;
  for (const EffectColumns* e : columns) k += static_cast<int>(e->size());
  y.resize(samples_);
  X.resize(samples_, k);
  Eigen::Index row = 0;
  for (std::size_t p = 0; p < blocks_.size(); ++p) {
    const Eigen::Index n = blocks_[p].residual.rows();
    const Eigen::Index first = row;
    for (int c = 0; c < 3; ++c) {
      y.segment(row, n) = blocks_[p].residual.col(c) / scale_(c);
      int j = 0;
      for (const EffectColumns* e : columns)
        for (const auto& parameter : *e) {
          const Eigen::MatrixX3d& phi = parameter.at(p);
          if (phi.rows() != n) throw InputError("diagnosis regression: an effect column has the wrong number of rows");
          auto x = X.col(j).segment(row, n);
          x = phi.col(c) / scale_(c);
          to_base(p, c, x);
          ++j;
        }
      row += n;
    }
    if (blocks_[p].zero_basis.cols() > 0) {
      auto y_rows = y.segment(first, 3 * n);
      auto x_rows = X.middleRows(first, 3 * n);
      project_zero(p, y_rows);
      project_zero(p, x_rows);
    }
  }
}

std::vector<Eigen::Index> ResidualRegression::push_rows() const {
  std::vector<Eigen::Index> out;
  for (const auto& b : blocks_) out.push_back(b.residual.rows());
  return out;
}

RegressionFit ResidualRegression::fit(const std::vector<const EffectColumns*>& columns, int extra_parameters) const {
  Eigen::VectorXd y;
  Eigen::MatrixXd X;
  stack(columns, y, X);
  const int k = static_cast<int>(X.cols());
  const Eigen::Index N = samples_;
  Eigen::Index row = 0;
  RegressionFit f;
  f.parameters = k + extra_parameters;
  const double log_neff = std::log(effective_samples_);
  const double penalty = (f.parameters + nuisance_parameters()) * log_neff;
  if (k == 0) {
    f.rss = y.squaredNorm();
    f.bic = effective_samples_ * std::log(f.rss / static_cast<double>(N)) + penalty;
    return f;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < k || !X.allFinite()) {
    f.identifiable = false;
    f.theta = Eigen::VectorXd::Zero(k);
    f.covariance = Eigen::MatrixXd::Constant(k, k, std::numeric_limits<double>::infinity());
    f.rss = y.squaredNorm();
    f.bic = std::numeric_limits<double>::infinity();
    return f;
  }
  f.theta = qr.solve(y);
  const Eigen::VectorXd e = y - X * f.theta;
  f.rss = e.squaredNorm();
  f.bic = effective_samples_ * std::log(f.rss / static_cast<double>(N)) + penalty;

  // Newey-West: per push, the score of a sample time sums the three channels; Bartlett weights up to the lag.
  Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(k, k), cluster = Eigen::MatrixXd::Zero(k, k);
  row = 0;
  for (const Block& b : blocks_) {
    const Eigen::Index n = b.residual.rows();
    Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, k);
    for (int c = 0; c < 3; ++c)
      s += (X.middleRows(row + c * n, n).array().colwise() * e.segment(row + c * n, n).array()).matrix();
    const Eigen::VectorXd total = s.colwise().sum().transpose();
    cluster += total * total.transpose();
    const Eigen::Index lag = std::min<Eigen::Index>(n - 1, static_cast<Eigen::Index>(std::lround(kHacLag_s * b.rate_hz)));
    omega += s.transpose() * s;
    for (Eigen::Index l = 1; l <= lag; ++l) {
      const double w = 1 - static_cast<double>(l) / static_cast<double>(lag + 1);
      const Eigen::MatrixXd g = s.topRows(n - l).transpose() * s.bottomRows(n - l);
      omega += w * (g + g.transpose());
    }
    row += 3 * n;
  }
  const Eigen::MatrixXd information = X.transpose() * X;
  const Eigen::MatrixXd inverse = information.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
  f.covariance = inverse * omega * inverse;
  f.clusters = static_cast<int>(blocks_.size());
  const double P = static_cast<double>(blocks_.size());
  f.cluster_covariance = P > 1 ? (inverse * cluster * inverse * (P / (P - 1))).eval() : f.covariance;
  return f;
}

std::vector<Eigen::MatrixX3d> ResidualRegression::residuals(const std::vector<const EffectColumns*>& columns,
                                                            const Eigen::VectorXd& theta) const {
  std::vector<Eigen::MatrixX3d> out;
  for (std::size_t p = 0; p < blocks_.size(); ++p) {
    Eigen::MatrixX3d explained = Eigen::MatrixX3d::Zero(blocks_[p].residual.rows(), 3);
    int j = 0;
    for (const EffectColumns* e : columns)
      for (const auto& parameter : *e) explained += theta(j++) * parameter.at(p);
    for (int c = 0; c < 3; ++c) to_base(p, c, explained.col(c));
    Eigen::MatrixX3d residual = blocks_[p].residual - explained;
    if (blocks_[p].zero_basis.cols() > 0) {
      const Eigen::Index n = residual.rows();
      Eigen::VectorXd stacked(3 * n);
      for (int c = 0; c < 3; ++c) stacked.segment(c * n, n) = residual.col(c) / scale_(c);
      project_zero(p, stacked);
      for (int c = 0; c < 3; ++c) residual.col(c) = scale_(c) * stacked.segment(c * n, n);
    }
    out.push_back(residual);
  }
  return out;
}

std::array<Eigen::MatrixX3d, 2> push_sensor_zero_columns(const DiagnosisPush& d) {
  const Eigen::Index n = d.rows();
  // The recorded f_C is the true force less the zero z, and the input torque uses it at the lever l = r_C - r_O:
  // u errs by -(z, l x z), so d_hat carries +(z, l x z). The torque varies with the lever, so it is part of the
  // same column, not a constant of its own.
  Eigen::MatrixX3d zx(n, 3), zy(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector2d l = d.push.lever_m.row(d.first + k).transpose();
    zx.row(k) << 1, 0, -l.y();
    zy.row(k) << 0, 1, l.x();
  }
  return {d.as_observed(zx), d.as_observed(zy)};
}

EffectColumns sensor_zero_columns(const std::vector<DiagnosisPush>& pushes) {
  EffectColumns out(2 * pushes.size(), std::vector<Eigen::MatrixX3d>(pushes.size()));
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    for (auto& column : out) column[p] = Eigen::MatrixX3d::Zero(pushes[p].rows(), 3);
    auto own = push_sensor_zero_columns(pushes[p]);
    out[2 * p][p] = std::move(own[0]);
    out[2 * p + 1][p] = std::move(own[1]);
  }
  return out;
}

}  // namespace pushpred
