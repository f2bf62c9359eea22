#include "pushpred/diagnosis/model_adequacy.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>

#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"

namespace pushpred {

namespace {

std::string printed(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

/// The (1 - alpha) quantile of `values` (sorted in place).
double upper_quantile(std::vector<double>& values, double alpha) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto at = static_cast<std::size_t>(std::clamp(std::ceil((1 - alpha) * static_cast<double>(values.size())) - 1,
                                                      0.0, static_cast<double>(values.size() - 1)));
  return values[at];
}

/// Orthonormal basis of the column space of `X` (columns the data cannot tell apart dropped).
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& X) {
  if (X.cols() == 0) return Eigen::MatrixXd(X.rows(), 0);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  qr.setThreshold(1e-9);
  const Eigen::Index rank = qr.rank();
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(X.rows(), rank);
  Q = qr.householderQ() * Q;
  return Q;
}

/// `v` with its projection on the orthonormal `Q` removed.
Eigen::VectorXd off(const Eigen::MatrixXd& Q, const Eigen::VectorXd& v) {
  return Q.cols() ? (v - Q * (Q.transpose() * v)).eval() : v;
}

double share_of(const Eigen::MatrixXd& Q, const Eigen::VectorXd& e) {
  const double total = e.squaredNorm();
  if (!(total > 0) || Q.cols() == 0) return 0.0;
  return (Q.transpose() * e).squaredNorm() / total;
}

}  // namespace

std::string ModelAdequacy::verdict() const {
  if (!tested) return "not tested";
  if (explained) return "explained";
  std::string s = "unexplained residual:";
  // The signatures' structure, unless only the shared force is what is unexplained.
  const bool structure = structure_unexplained || (force_unexplained && !shared_force_unexplained);
  if (structure)
    s += printed(" %.3g N and %.3g N m of structured force (floors %.3g N, %.3g N m)", force_N, torque_Nm,
                 force_floor_N, torque_floor_Nm);
  if (shared_force_unexplained)
    s += std::string(structure ? ";" : "") +
         printed(" a force of %.3g N that the %.0f pushes whose sensor zero is measured share (floor %.3g N)",
                 shared_force_N, zero_measured_pushes, force_floor_N);
  if (rest_unexplained)
    s += std::string(force_unexplained ? ";" : "") +
         printed(" the sensor reads %.3g N at rest, where nothing touches, on %.0f pushes (floor %.3g N)", rest_force_N,
                 rest_pushes, force_floor_N);
  if (contact_unexplained)
    s += std::string(force_unexplained || rest_unexplained ? ";" : "") +
         printed(
             " the recorded rod sits %.3g mm/N deeper in the outline the harder it pushes: a contact lag of "
             "%.2f mm under the friction force, which a rigid pusher does not have (floor %.2f mm)",
             1e3 * contact_compliance_m_N, contact_lag_mm, contact_floor_mm);
  if (motion_unexplained)
    s += std::string(force_unexplained || rest_unexplained || contact_unexplained ? ";" : "") +
         printed(" a prediction bias of %.2f mm and %.2f deg on the fit phases (floors %.2f mm, %.2f deg)",
                 position_bias_mm, yaw_bias_deg, position_floor_mm, yaw_floor_deg);
  return s;
}

void test_rest_force(const std::vector<SynchronisedPush>& pushes, const Eigen::Vector2d& shared_rest_force_N,
                     const FloorContext& context, double bic_threshold, const AdequacyOptions& options,
                     ModelAdequacy& adequacy) {
  std::vector<const SynchronisedPush*> recorded;
  for (const auto& push : pushes) recorded.push_back(&push);
  const DirectFit fit = rest_force_fit(recorded, shared_rest_force_N, options.sensor_zero_spread_N);
  adequacy.rest_pushes = fit.pushes;
  adequacy.rest_tested = std::isfinite(fit.score);
  adequacy.rest_threshold = bic_threshold;
  if (!adequacy.rest_tested) {
    adequacy.rest_unexplained = false;
    return;
  }
  const Eigen::Vector2d b = fit.theta.head<2>();
  adequacy.rest_bias_N = b;
  adequacy.rest_force_N = b.norm();
  // The magnitude's standard error along the bias (delta method).
  adequacy.rest_force_N_std = adequacy.rest_force_N > 0
                                  ? std::sqrt(b.dot(fit.covariance.topLeftCorner<2, 2>() * b)) / adequacy.rest_force_N
                                  : std::sqrt(fit.covariance.trace() / 2);
  adequacy.rest_score = fit.score;
  const double floor = context.relevance_fraction * context.friction_force_N();
  adequacy.force_floor_N = floor;
  adequacy.rest_unexplained =
      fit.score > bic_threshold && adequacy.rest_force_N - options.floor_margin_std * adequacy.rest_force_N_std > floor;
}

std::optional<double> contact_compliance_m_N(const SynchronisedPush& push) {
  if (!push.shape.has_outline()) return std::nullopt;
  const Outline outline(push.shape);
  // Sums for the least-squares line penetration = a + b f_n.
  double n = 0, sf = 0, sp = 0, sff = 0, sfp = 0;
  for (Eigen::Index i = 0; i < push.size(); ++i) {
    if (!push.in_contact[static_cast<std::size_t>(i)]) continue;
    const double c = std::cos(push.pose(i, 2)), s = std::sin(push.pose(i, 2));
    const Eigen::Vector2d force = push.force_N.row(i).transpose();
    const Eigen::Vector2d force_body(c * force.x() + s * force.y(), -s * force.x() + c * force.y());
    const Outline::Closest closest = rod_closest(push, outline, i);
    const double penetration = kPusherRadius_m - closest.signed_distance_m;
    const double into = -force_body.dot(closest.normal);
    n += 1;
    sf += into;
    sp += penetration;
    sff += into * into;
    sfp += into * penetration;
  }
  if (n < kMinContactSamples) return std::nullopt;
  const double force_variance = sff / n - (sf / n) * (sf / n);
  if (!(force_variance >= kMinContactForceSpread_N * kMinContactForceSpread_N)) return std::nullopt;
  const double slope = (sfp / n - (sf / n) * (sp / n)) / force_variance;
  if (!std::isfinite(slope)) return std::nullopt;
  return slope;
}

std::vector<double> contact_compliance_slopes_m_N(const std::vector<SynchronisedPush>& pushes) {
  std::vector<double> slopes;
  for (const auto& push : pushes)
    if (const auto slope = contact_compliance_m_N(push)) slopes.push_back(*slope);
  return slopes;
}

void test_contact_compliance(const std::vector<SynchronisedPush>& pushes, const FloorContext& context,
                             const AdequacyOptions& options, ModelAdequacy& adequacy) {
  const std::vector<double> slopes = contact_compliance_slopes_m_N(pushes);
  adequacy.contact_pushes = static_cast<int>(slopes.size());
  adequacy.contact_floor_mm = 1e3 * context.relevance_fraction * context.travel_m;
  adequacy.contact_tested = adequacy.contact_pushes >= kMinContactPushes;
  adequacy.contact_unexplained = false;
  if (!adequacy.contact_tested) {
    adequacy.note += std::string(adequacy.note.empty() ? "" : "; ") +
                     printed(
                         "the contact was not tested: %.0f pushes resolve their rod's penetration against the "
                         "force (%.0f needed)",
                         adequacy.contact_pushes, kMinContactPushes);
    return;
  }
  const double compliance = median(slopes);
  // The median's standard error: 1.2533 sigma / sqrt(n) for normal slopes, sigma from the MAD.
  const double compliance_std = 1.2533 * robust_spread(slopes) / std::sqrt(static_cast<double>(slopes.size()));
  adequacy.contact_compliance_m_N = compliance;
  adequacy.contact_compliance_m_N_std = compliance_std;
  adequacy.contact_lag_mm = 1e3 * compliance * context.friction_force_N();
  adequacy.contact_lag_mm_std = 1e3 * compliance_std * context.friction_force_N();
  adequacy.contact_unexplained =
      adequacy.contact_lag_mm - options.floor_margin_std * adequacy.contact_lag_mm_std > adequacy.contact_floor_mm;
}

std::vector<ResidualSignature> residual_signatures(const std::vector<DiagnosisPush>& pushes,
                                                   double friction_coefficient) {
  std::vector<ResidualSignature> out = {
      {"world_force", "a constant force in the world frame (a support that is not level, a cable, a draught)", {}},
      {"body_direction_friction", "friction that depends on the sliding direction in the body frame", {}},
      {"speed", "a force that grows with speed (drag, friction rising with speed)", {}},
      {"travel", "friction that changes along the travel (a patch, a gradient)", {}},
      {"time_since_contact", "friction that changes with the time since contact (creep, wear, warming)", {}},
      {"tip_motion", "the tip moving relative to the object (a compliant pusher's lag, penetration)", {}},
      {"force_rate", "the force's rate (a delay between the force and the pose)", {}},
      {"lever_arm", "the push force's moment about a point shifted in the body frame (a lever-arm error)", {}},
  };
  const std::size_t columns[] = {2, 2, 2, 2, 2, 4, 3, 2};
  for (std::size_t g = 0; g < out.size(); ++g)
    out[g].columns.assign(columns[g], std::vector<Eigen::MatrixX3d>(pushes.size()));
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    const DiagnosisPush& d = pushes[p];
    const Eigen::Index n = d.rows();
    const ShapeInfo& shape = d.push.shape;
    const double weight = shape.mass_kg * kGravity_m_s2;
    const FrictionFootprint footprint = FrictionFootprint::of(shape);
    const double contact_s = d.push.has_contact ? d.push.contact_start_s : d.push.t_s(d.first);
    // The lever r_C - r_O in the body frame, smoothed without lag, and its rate: the tip's motion relative to the
    // object (zero for a rigid pusher that neither slides nor penetrates).
    Eigen::MatrixXd lever_body(n, 2);
    Eigen::VectorXd t(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const Eigen::Index i = d.first + k;
      t(k) = d.push.t_s(i);
      const double c = std::cos(d.smooth_pose(k, 2)), s = std::sin(d.smooth_pose(k, 2));
      const Eigen::Vector2d l = d.push.lever_m.row(i).transpose();
      lever_body.row(k) << c * l.x() + s * l.y(), -s * l.x() + c * l.y();
    }
    Eigen::MatrixXd lever_rate;
    const Eigen::MatrixXd lever_smooth = zero_phase_smooth(t, lever_body, kSmoothingBandwidth_rad_s, &lever_rate);
    Eigen::Index at_contact = 0;
    while (at_contact + 1 < n && t(at_contact) < contact_s) ++at_contact;

    std::vector<Eigen::MatrixX3d> raw;
    for (std::size_t g = 0; g < out.size(); ++g)
      for (std::size_t j = 0; j < columns[g]; ++j) raw.emplace_back(Eigen::MatrixX3d::Zero(n, 3));
    for (Eigen::Index k = 0; k < n; ++k) {
      const EffectState st = d.state(k);
      const double c = std::cos(st.pose(2)), s = std::sin(st.pose(2));
      const Eigen::Vector2d ex(c, s), ey(-s, c);
      const Eigen::Vector3d coulomb = coulomb_friction_wrench(st.pose, st.velocity, shape, footprint);
      const double speed = st.velocity.head<2>().norm();
      const double regularised = std::hypot(speed, kFrictionRegularisation_m_s);
      const Eigen::Vector2d v_body(ex.dot(st.velocity.head<2>()), ey.dot(st.velocity.head<2>()));
      const double travel = (st.pose.head<2>() - st.start_pose.head<2>()).norm();
      const double since = std::max(0.0, t(k) - contact_s);
      const Eigen::Vector2d penetration = lever_smooth.row(k).transpose() - lever_smooth.row(at_contact).transpose();
      const Eigen::Vector2d rate(lever_rate(k, 0), lever_rate(k, 1));
      std::size_t j = 0;
      // world_force
      raw[j++].row(k) << weight, 0, 0;
      raw[j++].row(k) << 0, weight, 0;
      // body_direction_friction: -W e_i (v_i / |v|) along each body axis
      for (const Eigen::Vector2d& e : {ex, ey}) {
        const double share = (e == ex ? v_body.x() : v_body.y()) / regularised;
        raw[j++].row(k) << -weight * share * e.x(), -weight * share * e.y(), 0;
      }
      // speed: drag -(m v, I omega) and the Coulomb law growing with speed (per 10 cm/s)
      raw[j++].row(k) << -shape.mass_kg * st.velocity(0), -shape.mass_kg * st.velocity(1),
          -shape.inertia_kgm2 * st.velocity(2);
      raw[j++].row(k) = (speed / 0.1) * coulomb.transpose();
      // travel: the Coulomb law times the distance travelled (per cm) and its square
      raw[j++].row(k) = (travel / 0.01) * coulomb.transpose();
      raw[j++].row(k) = std::pow(travel / 0.01, 2) * coulomb.transpose();
      // time since contact: the Coulomb law times the time (per s), and a decay over 0.3 s
      raw[j++].row(k) = since * coulomb.transpose();
      raw[j++].row(k) = std::exp(-since / 0.3) * coulomb.transpose();
      // tip_motion: penetration (per mm) and its rate (per 10 mm/s), body axes, as forces in the world frame
      for (int a = 0; a < 2; ++a) {
        const Eigen::Vector2d e = a == 0 ? ex : ey;
        raw[j++].row(k) << weight * (penetration(a) / 1e-3) * e.x(), weight * (penetration(a) / 1e-3) * e.y(), 0;
      }
      for (int a = 0; a < 2; ++a) {
        const Eigen::Vector2d e = a == 0 ? ex : ey;
        raw[j++].row(k) << weight * (rate(a) / 0.01) * e.x(), weight * (rate(a) / 0.01) * e.y(), 0;
      }
      // force_rate: filled below (already as observed)
      j += 3;
      // lever_arm: -(R e_i) x f_C in the torque channel, with f_C the force the motion implies, m a less the
      // support's friction: the measured force's own noise, times the lever it enters the torque with, would
      // correlate with its noise in the residual and pass as a lever-arm error on clean pushes.
      const Eigen::Vector2d implied =
          shape.mass_kg * d.smooth_acceleration.row(k).head<2>().transpose() - friction_coefficient * coulomb.head<2>();
      raw[j++].row(k) << 0, 0, -(ex.x() * implied.y() - ex.y() * implied.x());
      raw[j++].row(k) << 0, 0, -(ey.x() * implied.y() - ey.y() * implied.x());
    }
    std::size_t j = 0;
    for (std::size_t g = 0; g < out.size(); ++g)
      for (std::size_t q = 0; q < columns[g]; ++q, ++j) {
        if (out[g].name == "force_rate") {
          Eigen::MatrixX3d r = Eigen::MatrixX3d::Zero(n, 3);
          r.col(static_cast<Eigen::Index>(q)) = 0.01 * d.filtered_input_rate.col(static_cast<Eigen::Index>(q));
          out[g].columns[q][p] = std::move(r);
        } else {
          out[g].columns[q][p] = d.as_observed(raw[j]);
        }
      }
  }
  return out;
}

std::vector<ResidualHint> test_residual_structure(const std::vector<DiagnosisPush>& pushes,
                                                  const std::vector<const EffectColumns*>& model,
                                                  const FloorContext& context, const AdequacyOptions& options,
                                                  ModelAdequacy& adequacy) {
  adequacy.alpha = options.alpha;
  adequacy.replicates = options.replicates;
  const ResidualRegression regression(pushes, Relation::Friction);
  const std::vector<ResidualSignature> signatures = residual_signatures(pushes, context.friction_coefficient);
  std::vector<const EffectColumns*> all;
  for (const auto& s : signatures) all.push_back(&s.columns);
  Eigen::VectorXd y;
  Eigen::MatrixXd Xm, Xs;
  regression.stack(model, y, Xm);
  {
    Eigen::VectorXd unused;
    regression.stack(all, unused, Xs);
  }
  // Only sliding samples the friction base uses: where stuck, static friction balances whatever acts.
  const std::vector<Eigen::Index> rows = regression.push_rows();
  Eigen::VectorXd mask(y.size());
  {
    Eigen::Index row = 0;
    for (std::size_t p = 0; p < pushes.size(); ++p) {
      const std::vector<char> used = friction_law_samples(pushes[p]);
      for (int c = 0; c < 3; ++c)
        for (Eigen::Index i = 0; i < rows[p]; ++i) mask(row++) = used[i] && !pushes[p].stuck[i] ? 1.0 : 0.0;
    }
  }
  const double sliding_rows = mask.sum() / 3;
  if (sliding_rows < 50) {
    adequacy.note = "the force residual was not tested: fewer than 50 sliding samples";
    return {};
  }
  y = y.cwiseProduct(mask);
  Xm = mask.asDiagonal() * Xm;
  Xs = mask.asDiagonal() * Xs;
  // Each push's own sensor zero (sensor_zero_columns) is a constant the friction fit cannot tell from Coulomb
  // friction on a straight push, so it is kept out of that fit and taken out here, where it can reach:
  // - where it is not measured (the rod starts pressed), the push's zero columns join the model's columns: projected
  //   out of the residual, of every signature and of every replicate (fixed effects);
  // - where it is measured at rest, on two pushes or more, its deviation from the measured pushes' mean is taken out
  //   of the residual; the mean is a force the pushes share (a bias, a tilt), which the zeros' own chance mean hides.
  //   Its columns are projected too, and the shared part tested on its own (below), against the zeros' spread.
  // With the zero's torque l x z in the same columns: on clean tuning trials with zeros drawn the structure the
  // zeros leave is mostly in the torque channel (lever_arm the first hint), so the force channels alone would not do.
  Eigen::MatrixXd zero_shared;                              // the measured pushes' zero columns, summed (y.size() x 2)
  Eigen::Vector2d zero_mean_std = Eigen::Vector2d::Zero();  // the standard error of the measured zeros' mean [N]
  int measured = 0;
  adequacy.pushes_zero_projected = 0;
  std::vector<std::optional<Eigen::Vector2d>> zeros;
  for (const auto& d : pushes) zeros.push_back(measured_sensor_zero_N(d));
  measured = static_cast<int>(std::count_if(zeros.begin(), zeros.end(), [](const auto& z) { return z.has_value(); }));
  // Measured zeros (two pushes or more) that spread by less than the force floor cannot leave structure the floor
  // counts: those pushes keep their zeros as recorded (a sensor zeroed on every push is then tested as before).
  adequacy.zero_spread_N = zero_spread_N(zeros);  // NaN below two measured zeros
  const bool measured_as_recorded = adequacy.zero_spread_N <= context.relevance_fraction * context.friction_force_N();
  if (options.sensor_zeros) {
    const EffectColumns zero_columns = sensor_zero_columns(pushes);
    Eigen::VectorXd unused;
    Eigen::MatrixXd Xz;
    regression.stack({&zero_columns}, unused, Xz);
    Xz = mask.asDiagonal() * Xz;
    // One measured push cannot tell its own zero from a shared force: its zero is then projected like a pressed one.
    const bool take_out_measured = measured >= 2 && !measured_as_recorded;
    if (!take_out_measured) measured = 0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& z : zeros)
      if (z && take_out_measured) mean += *z / measured;
    std::vector<Eigen::Index> projected;
    zero_shared = Eigen::MatrixXd::Zero(y.size(), 2);
    for (std::size_t p = 0; p < pushes.size(); ++p) {
      const auto c = static_cast<Eigen::Index>(2 * p);
      if (zeros[p] && measured_as_recorded) continue;
      if (!zeros[p] || !take_out_measured) {
        projected.push_back(c);
        projected.push_back(c + 1);
        ++adequacy.pushes_zero_projected;
        continue;
      }
      y -= Xz.middleCols(c, 2) * (*zeros[p] - mean);
      zero_shared += Xz.middleCols(c, 2);
    }
    // One spread for both axes (the zeros' scatter is taken as the same in x and y), on 2 (m - 1) degrees of freedom:
    // with three or four measured pushes a spread per axis would rest on two or three.
    if (take_out_measured)
      zero_mean_std.setConstant(std::sqrt(adequacy.zero_spread_N * adequacy.zero_spread_N / measured));
    Eigen::MatrixXd augmented(Xm.rows(), Xm.cols() + static_cast<Eigen::Index>(projected.size()));
    augmented << Xm, Xz(Eigen::all, projected);
    Xm = std::move(augmented);
  }
  if (!options.sensor_zeros) measured = 0;
  adequacy.zero_measured_pushes = measured;
  // The model's columns and the unmeasured zeros: what the shared part is tested against.
  const Eigen::MatrixXd Qa = orthonormal_basis(Xm);
  Eigen::MatrixXd shared_off;
  if (measured >= 2) {
    shared_off = zero_shared;
    for (Eigen::Index j = 0; j < 2; ++j) shared_off.col(j) = off(Qa, zero_shared.col(j));
    Eigen::MatrixXd augmented(Xm.rows(), Xm.cols() + 2);
    augmented << Xm, zero_shared;
    Xm = std::move(augmented);
  }
  const Eigen::MatrixXd Qm = orthonormal_basis(Xm);
  const Eigen::VectorXd e0 = off(Qm, y);
  Eigen::MatrixXd Xs_off = Xs;
  for (Eigen::Index j = 0; j < Xs.cols(); ++j) Xs_off.col(j) = off(Qm, Xs.col(j));
  const Eigen::MatrixXd Qs = orthonormal_basis(Xs_off);
  adequacy.force_share = share_of(Qs, e0);
  // Each signature's own basis, off the model's columns: the statistic is the largest standardised share.
  std::vector<Eigen::MatrixXd> group_bases;
  {
    Eigen::Index column = 0;
    for (const auto& s : signatures) {
      const auto k = static_cast<Eigen::Index>(s.columns.size());
      group_bases.push_back(orthonormal_basis(Xs_off.middleCols(column, k)));
      column += k;
    }
  }
  const auto group_shares = [&](const Eigen::VectorXd& e) {
    Eigen::VectorXd out(static_cast<Eigen::Index>(group_bases.size()));
    for (std::size_t g = 0; g < group_bases.size(); ++g)
      out(static_cast<Eigen::Index>(g)) = share_of(group_bases[g], e);
    return out;
  };
  const Eigen::VectorXd observed_shares = group_shares(e0);

  const Eigen::Vector3d& scale = regression.channel_scale();
  // The structured part's mean square in physical units over the sliding samples: force (x, y) [N^2], torque
  // [(N m)^2].
  const auto mean_squares = [&](const Eigen::VectorXd& residual) {
    const Eigen::VectorXd structured =
        Qs.cols() ? (Qs * (Qs.transpose() * residual)).eval() : Eigen::VectorXd::Zero(residual.size());
    double force2 = 0, torque2 = 0;
    Eigen::Index row = 0;
    for (std::size_t p = 0; p < pushes.size(); ++p) {
      const Eigen::Index n = rows[p];
      for (Eigen::Index i = 0; i < n; ++i) {
        force2 += std::pow(scale(0) * structured(row + i), 2) + std::pow(scale(1) * structured(row + n + i), 2);
        torque2 += std::pow(scale(2) * structured(row + 2 * n + i), 2);
      }
      row += 3 * n;
    }
    return Eigen::Vector2d(force2 / sliding_rows, torque2 / sliding_rows);
  };

  // Block bootstrap of the model's residual (see the header).
  std::mt19937_64 rng(options.seed);
  // What is resampled is the residual of the model with the signatures (unrestricted): under the null it is the same
  // noise, and where a signature holds structure the replicates do not carry it into the null.
  const Eigen::VectorXd noise = off(Qs, e0);
  Eigen::MatrixXd null_shares(options.replicates, static_cast<Eigen::Index>(group_bases.size()));
  Eigen::MatrixX2d chance_rms(options.replicates, 2);  // the structured part's RMS the replicates show [N, N m]
  Eigen::Vector2d null_mean_squares = Eigen::Vector2d::Zero();
  Eigen::VectorXd resampled(e0.size());
  // Blocks are drawn from any push (the same sensor and observer everywhere), which breaks a block's tie to its own
  // push's states better than resampling within a push of a second or two.
  std::vector<std::pair<std::size_t, Eigen::Index>> origins;  // (push, first stacked row of its x channel)
  {
    Eigen::Index row = 0;
    for (std::size_t p = 0; p < pushes.size(); ++p) {
      origins.emplace_back(p, row);
      row += 3 * rows[p];
    }
  }
  std::uniform_int_distribution<std::size_t> any_push(0, pushes.size() - 1);
  // The shared force's fit on the measured pushes (least squares on the shared columns off the model's), and what
  // noise alone gives it in each replicate [N].
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> shared_fit;
  if (measured >= 2) shared_fit.compute(shared_off);
  Eigen::MatrixX2d shared_noise(options.replicates, 2);
  for (int b = 0; b < options.replicates; ++b) {
    for (std::size_t p = 0; p < pushes.size(); ++p) {
      const Eigen::Index n = rows[p], row = origins[p].second;
      const double rate = pushes[p].push.rate_hz > 0 ? pushes[p].push.rate_hz : 250.0;
      const Eigen::Index block = std::max<Eigen::Index>(1, std::lround(options.block_s * rate));
      for (Eigen::Index filled = 0; filled < n;) {
        const std::size_t q = any_push(rng);
        const Eigen::Index m = rows[q], from_row = origins[q].second;
        const Eigen::Index from = std::uniform_int_distribution<Eigen::Index>(0, m - 1)(rng);
        for (Eigen::Index i = 0; i < block && filled < n; ++i, ++filled)
          for (int c = 0; c < 3; ++c) resampled(row + c * n + filled) = noise(from_row + c * m + (from + i) % m);
      }
    }
    resampled = resampled.cwiseProduct(mask);
    if (measured >= 2) shared_noise.row(b) = shared_fit.solve(off(Qa, resampled)).transpose();
    resampled = off(Qm, resampled);
    null_shares.row(b) = group_shares(resampled).transpose();
    const Eigen::Vector2d chance = mean_squares(resampled);
    null_mean_squares += chance / static_cast<double>(options.replicates);
    chance_rms.row(b) = chance.cwiseSqrt().transpose();
  }
  // Standardised by the replicates' own mean and spread per signature; the largest over the signatures, in the data and
  // in every replicate, so that testing eight signatures is paid for in the null.
  const Eigen::VectorXd mean = null_shares.colwise().mean().transpose();
  Eigen::VectorXd spread(mean.size());
  for (Eigen::Index g = 0; g < mean.size(); ++g)
    spread(g) = std::max(1e-12, std::sqrt((null_shares.col(g).array() - mean(g)).square().sum() /
                                          std::max(1.0, static_cast<double>(options.replicates - 1))));
  const auto largest_z = [&](const Eigen::VectorXd& shares) {
    return ((shares - mean).cwiseQuotient(spread)).maxCoeff();
  };
  adequacy.force_statistic = largest_z(observed_shares);
  std::vector<double> null;
  int exceed = 0;
  for (Eigen::Index b = 0; b < null_shares.rows(); ++b) {
    null.push_back(largest_z(null_shares.row(b).transpose()));
    if (null.back() >= adequacy.force_statistic) ++exceed;
  }
  adequacy.force_p_value = (1.0 + exceed) / (1.0 + options.replicates);
  adequacy.force_threshold = upper_quantile(null, options.alpha);
  // Size: the structured part's RMS beyond what the signatures pick out of noise alone (the replicates' mean square),
  // so that chance fits of slow noise do not count as structure.
  const Eigen::Vector2d observed = mean_squares(e0);
  adequacy.force_N = std::sqrt(std::max(0.0, observed(0) - null_mean_squares(0)));
  adequacy.torque_Nm = std::sqrt(std::max(0.0, observed(1) - null_mean_squares(1)));
  adequacy.force_floor_N = context.relevance_fraction * context.friction_force_N();
  adequacy.torque_floor_Nm = adequacy.force_floor_N * context.radius_of_gyration_m;
  // The sizes' standard errors: how far noise alone moves the structured part's RMS (the replicates' spread).
  for (int c = 0; c < 2; ++c) {
    const double m = chance_rms.col(c).mean();
    const double sd = std::sqrt((chance_rms.col(c).array() - m).square().sum() /
                                std::max(1.0, static_cast<double>(options.replicates - 1)));
    (c == 0 ? adequacy.force_N_std : adequacy.torque_Nm_std) = sd;
  }
  adequacy.force_tested = adequacy.force_floor_N > 0;
  const double margin = options.structure_margin_std;
  adequacy.structure_unexplained =
      adequacy.force_tested && adequacy.force_p_value <= options.alpha &&
      (adequacy.force_N - margin * adequacy.force_N_std > adequacy.force_floor_N ||
       adequacy.torque_Nm - margin * adequacy.torque_Nm_std > adequacy.torque_floor_Nm);

  // The force the measured pushes share, beyond their zeros' chance mean: F = (t_x^2 + t_y^2) / 2, t = c / se per
  // axis, se^2 the zeros' mean's variance (their spread over the pushes / m) plus what noise gives the fit (the
  // replicates' variance), against F(2, 2 (m - 1)) (the spread's degrees of freedom). Unexplained when significant at
  // alpha and |c| exceeds the force floor by floor_margin_std of its standard errors.
  std::vector<ResidualHint> hints;
  adequacy.force_unexplained = adequacy.structure_unexplained;
  if (measured >= 2) {
    const Eigen::VectorXd e_a = off(Qa, y);
    const Eigen::Vector2d c = shared_fit.solve(e_a);
    Eigen::Vector2d se;
    for (int a = 0; a < 2; ++a) {
      const double m = shared_noise.col(a).mean();
      const double noise_var =
          (shared_noise.col(a).array() - m).square().sum() / std::max(1.0, static_cast<double>(options.replicates - 1));
      se(a) = std::sqrt(zero_mean_std(a) * zero_mean_std(a) + noise_var);
    }
    const double F = se.minCoeff() > 0 ? 0.5 * c.cwiseQuotient(se).squaredNorm() : 0.0;
    const double p = std::exp(log_f2_tail(F, 2.0 * (measured - 1)));
    adequacy.shared_force_N = c.norm();
    adequacy.shared_force_N_std = c.norm() > 0 ? std::sqrt(c.cwiseAbs2().dot(se.cwiseAbs2())) / c.norm() : se.norm();
    adequacy.shared_force_p_value = p;
    adequacy.shared_force_unexplained =
        adequacy.force_tested && p <= options.alpha &&
        adequacy.shared_force_N - options.floor_margin_std * adequacy.shared_force_N_std > adequacy.force_floor_N;

    adequacy.force_unexplained = adequacy.force_unexplained || adequacy.shared_force_unexplained;
    const double share = share_of(orthonormal_basis(shared_off), e_a);
    hints.push_back({"shared_force",
                     "a force the pushes whose sensor zero is measured share (a sensor bias, a support that is not "
                     "level)",
                     share, adequacy.force_share > 0 ? share / adequacy.force_share : 0.0});
  }
  for (const auto& s : signatures) {
    Eigen::VectorXd unused;
    Eigen::MatrixXd X;
    regression.stack({&s.columns}, unused, X);
    X = mask.asDiagonal() * X;
    for (Eigen::Index j = 0; j < X.cols(); ++j) X.col(j) = off(Qm, X.col(j));
    const double share = share_of(orthonormal_basis(X), e0);
    hints.push_back({s.name, s.description, share, adequacy.force_share > 0 ? share / adequacy.force_share : 0.0});
  }
  std::stable_sort(hints.begin(), hints.end(), [](const auto& a, const auto& b) { return a.share > b.share; });
  return hints;
}

void test_motion_bias(const std::vector<PhaseBias>& phases, double hold_position_mm, double hold_yaw_deg, double kappa,
                      double radius_of_gyration_m, const AdequacyOptions& options, ModelAdequacy& adequacy) {
  adequacy.phases = static_cast<int>(phases.size());
  adequacy.position_floor_mm = kappa * hold_position_mm;
  // Pushes that hardly turn the object make kappa of the rotation tiny: a yaw bias counts only when it also moves the
  // outline (at the radius of gyration) by the position floor.
  adequacy.yaw_floor_deg = kappa * hold_yaw_deg;
  if (radius_of_gyration_m > 0)
    adequacy.yaw_floor_deg =
        std::max(adequacy.yaw_floor_deg, 1e-3 * adequacy.position_floor_mm / radius_of_gyration_m * 180.0 / M_PI);
  if (phases.size() < 4) {
    adequacy.note +=
        std::string(adequacy.note.empty() ? "" : "; ") + "the motion was not tested: fewer than 4 fit phases";
    return;
  }
  // Per phase: world x, y [mm], along and across its travel [mm], yaw [deg].
  const Eigen::Index K = static_cast<Eigen::Index>(phases.size());
  Eigen::MatrixXd v(K, 5);
  for (Eigen::Index k = 0; k < K; ++k) {
    const PhaseBias& b = phases[static_cast<std::size_t>(k)];
    const Eigen::Vector2d d = b.travel_direction;
    v.row(k) << 1e3 * b.position_m.x(), 1e3 * b.position_m.y(), 1e3 * d.dot(b.position_m),
        1e3 * (d.x() * b.position_m.y() - d.y() * b.position_m.x()), b.yaw_rad * 180.0 / M_PI;
  }
  const auto largest_t = [&](const Eigen::VectorXd& signs) {
    double t = 0;
    for (int c = 0; c < 5; ++c) {
      const Eigen::VectorXd x = v.col(c).cwiseProduct(signs);
      const double mean = x.mean();
      const double sd = std::sqrt((x.array() - mean).square().sum() / static_cast<double>(K - 1));
      if (sd > 0) t = std::max(t, std::abs(mean) / (sd / std::sqrt(static_cast<double>(K))));
    }
    return t;
  };
  adequacy.motion_t = largest_t(Eigen::VectorXd::Ones(K));
  std::mt19937_64 rng(options.seed + 1);
  std::bernoulli_distribution flip(0.5);
  std::vector<double> null;
  int exceed = 0;
  const int draws = std::max(options.replicates, 199);
  for (int b = 0; b < draws; ++b) {
    Eigen::VectorXd signs(K);
    for (Eigen::Index k = 0; k < K; ++k) signs(k) = flip(rng) ? 1.0 : -1.0;
    const double t = largest_t(signs);
    null.push_back(t);
    if (t >= adequacy.motion_t) ++exceed;
  }
  adequacy.motion_p_value = (1.0 + exceed) / (1.0 + draws);
  adequacy.motion_t_threshold = upper_quantile(null, options.alpha);
  const Eigen::VectorXd mean = v.colwise().mean().transpose();
  adequacy.position_bias_mm = std::max(mean.head<2>().norm(), mean.segment<2>(2).norm());
  adequacy.yaw_bias_deg = std::abs(mean(4));
  adequacy.motion_tested = hold_position_mm > 0;
  adequacy.motion_unexplained =
      adequacy.motion_tested && adequacy.motion_p_value <= options.alpha &&
      (adequacy.position_bias_mm > adequacy.position_floor_mm || adequacy.yaw_bias_deg > adequacy.yaw_floor_deg);
}

}  // namespace pushpred
