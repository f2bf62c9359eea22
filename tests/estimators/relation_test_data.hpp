#pragma once
// Data for the relation-estimator tests: synthetic inputs with a known relation d = beta u + eps + noise, and
// identification intervals cut from a real push.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred::test {

using Interval = std::pair<Eigen::MatrixX3d, Eigen::MatrixX3d>;  ///< (u, d_hat)

/// A relation with a known answer; noise_std in N, N, N m.
struct KnownRelation {
  Eigen::Vector3d beta{-0.85, -0.92, -0.7};
  Eigen::Vector3d eps{-0.3, 0.12, 0.004};
  Eigen::Vector3d noise_std{0.2, 0.15, 0.003};
};

/// A push-like input over n samples at 250 Hz starting at t0_s: an offset, a slow swing and sensor noise, in
/// N, N and N m.
inline Eigen::MatrixX3d synthetic_input(Eigen::Index n, double t0_s, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  Eigen::MatrixX3d u(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = t0_s + static_cast<double>(k) / 250.0;
    u(k, 0) = 3.0 + 1.2 * std::sin(2.0 * M_PI * 0.7 * t) + 0.3 * noise(rng);
    u(k, 1) = 1.5 + 0.8 * std::cos(2.0 * M_PI * 0.4 * t) + 0.3 * noise(rng);
    u(k, 2) = 0.01 * std::sin(2.0 * M_PI * 0.9 * t) + 0.004 * noise(rng);
  }
  return u;
}

/// d = beta u + eps + Gaussian noise.
inline Eigen::MatrixX3d synthetic_disturbance(const Eigen::MatrixX3d& u, const KnownRelation& r, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  Eigen::MatrixX3d d(u.rows(), 3);
  for (Eigen::Index k = 0; k < u.rows(); ++k)
    for (int c = 0; c < 3; ++c) d(k, c) = r.beta(c) * u(k, c) + r.eps(c) + r.noise_std(c) * noise(rng);
  return d;
}

/// `count` synthetic intervals of n samples each, one after the other in time.
inline std::vector<Interval> synthetic_intervals(int count, Eigen::Index n, const KnownRelation& r, std::mt19937& rng) {
  std::vector<Interval> out;
  for (int i = 0; i < count; ++i) {
    Eigen::MatrixX3d u = synthetic_input(n, static_cast<double>(i * n) / 250.0, rng);
    Eigen::MatrixX3d d = synthetic_disturbance(u, r, rng);
    out.emplace_back(std::move(u), std::move(d));
  }
  return out;
}

/// All intervals stacked.
inline Interval stack(const std::vector<Interval>& intervals) {
  Eigen::Index n = 0;
  for (const auto& i : intervals) n += i.first.rows();
  Interval all{Eigen::MatrixX3d(n, 3), Eigen::MatrixX3d(n, 3)};
  Eigen::Index at = 0;
  for (const auto& i : intervals) {
    all.first.middleRows(at, i.first.rows()) = i.first;
    all.second.middleRows(at, i.first.rows()) = i.second;
    at += i.first.rows();
  }
  return all;
}

/// A push of the abs surface, by the part of its file name after "motion_surface=abs_shape=".
inline SynchronisedPush real_push(const std::string& name) {
  return load_push(resolve_data_folder() / "abs" / ("motion_surface=abs_shape=" + name + ".h5"));
}

/// The push's contact span cut into `count` equal intervals of (u, d_hat). The observer is not part of these
/// tests, so d_hat is a stand-in with the real data's texture: the finite-difference estimate m a - u
/// (I theta'' - u for rotation) from the recorded pose, central second differences on the 250 Hz grid.
inline std::vector<Interval> real_intervals(const SynchronisedPush& p, int count) {
  const Eigen::MatrixX3d u = p.applied_input();
  const double dt = 1.0 / p.rate_hz;
  const Eigen::Index first = std::max<Eigen::Index>(p.index_at(p.contact_start_s), 1);
  const Eigen::Index last = std::min<Eigen::Index>(p.index_at(p.contact_end_s), p.size() - 2);
  const Eigen::Index n = last - first + 1;
  const Eigen::Vector3d inertia(p.shape.mass_kg, p.shape.mass_kg, p.shape.inertia_kgm2);
  Eigen::MatrixX3d d(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = first + k;
    const Eigen::RowVector3d acc = (p.pose.row(i + 1) - 2.0 * p.pose.row(i) + p.pose.row(i - 1)) / (dt * dt);
    d.row(k) = acc.cwiseProduct(inertia.transpose()) - u.row(i);
  }
  std::vector<Interval> out;
  for (int q = 0; q < count; ++q) {
    const Eigen::Index a = q * n / count, b = (q + 1) * n / count;
    out.emplace_back(u.middleRows(first + a, b - a), d.middleRows(a, b - a));
  }
  return out;
}

/// Largest difference between the disturbances two fits predict over the data, relative to the largest
/// |d_hat| per channel: a scale-free "same fit" measure that does not blow up where eps is near zero.
inline double fit_difference(const Eigen::Vector3d& beta_a, const Eigen::Vector3d& eps_a,
                             const Eigen::Vector3d& beta_b, const Eigen::Vector3d& eps_b, const Interval& data) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    const double scale = data.second.col(c).cwiseAbs().maxCoeff();
    const double diff =
        ((beta_a(c) - beta_b(c)) * data.first.col(c).array() + (eps_a(c) - eps_b(c))).abs().maxCoeff();
    worst = std::max(worst, diff / scale);
  }
  return worst;
}

/// Eigenvalues of C_ref^-1/2 C C_ref^-1/2: all 1 when C equals C_ref.
inline Eigen::Vector2d covariance_ratio(const Eigen::Matrix2d& c, const Eigen::Matrix2d& c_ref) {
  const Eigen::LLT<Eigen::Matrix2d> llt(c_ref);
  const Eigen::Matrix2d l_inv = llt.matrixL().solve(Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d w = l_inv * c * l_inv.transpose();
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(w).eigenvalues();
}

}  // namespace pushpred::test
