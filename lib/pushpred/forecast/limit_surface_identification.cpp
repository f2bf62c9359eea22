#include "pushpred/forecast/limit_surface_identification.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

TorqueRatioIdentification identify_torque_ratio(const SynchronisedPush& push, const RecordedForecastCase& c) {
  constexpr double kMinForce_N = 0.5, kHalfWindow_s = 0.01;
  TorqueRatioIdentification out;
  const Eigen::Index n = c.times_s.size(), i0 = push.size() - n;
  if (n < 3 || i0 < 0 || !c.forecast_object.outline || push.size() < 3) return out;
  RodContactSamples samples(push, c);
  const double dt_grid = (push.t_s(push.size() - 1) - push.t_s(0)) / static_cast<double>(push.size() - 1);
  const Eigen::Index h = std::max<Eigen::Index>(1, std::lround(kHalfWindow_s / std::max(dt_grid, 1e-6)));
  const Eigen::Vector2d cof_body = c.forecast_object.centre_of_friction_m;
  double sum_km = 0, sum_omega = 0;
  double half_km[2] = {0, 0}, half_omega[2] = {0, 0};
  int half_samples[2] = {0, 0};
  for (Eigen::Index k = h; k + h < n; ++k) {
    const Eigen::Index j = i0 + k;
    const std::optional<RodContactSamples::Sample> s = samples.at(j);
    if (!s) continue;
    const Eigen::Matrix2d& R = s->R;
    const Outline::Closest& cl = s->closest;
    const Eigen::Vector2d force = push.force_N.row(j).transpose();  // on the object, world frame
    if (!(force.norm() >= kMinForce_N)) continue;
    const double dt = push.t_s(j + h) - push.t_s(j - h);
    if (!(dt > 0)) continue;
    const double step = 0.5 * (push.t_s(j + 1) - push.t_s(j - 1));
    const Eigen::Vector2d velocity = (push.pose.row(j + h).head<2>() - push.pose.row(j - h).head<2>()).transpose() / dt;
    const double omega = (push.pose(j + h, 2) - push.pose(j - h, 2)) / dt;
    const Eigen::Vector2d cof = R * cof_body;  // from the body origin, world frame
    const Eigen::Vector2d v_cof = velocity + omega * Eigen::Vector2d(-cof.y(), cof.x());
    const Eigen::Vector2d arm = R * (cl.point_m - cof_body);
    const double moment = arm.x() * force.y() - arm.y() * force.x();
    const double k_gain = v_cof.dot(force) / force.squaredNorm();
    sum_km += k_gain * moment * step;
    sum_omega += omega * step;
    ++out.samples;
    const int half = s->progress < 0.5 * (RodContactSamples::kFrom + RodContactSamples::kTo) ? 0 : 1;
    half_km[half] += k_gain * moment * step;
    half_omega[half] += omega * step;
    ++half_samples[half];
  }
  auto ratio = [](double km, double om, int samples) {
    if (samples < TorqueRatioIdentification::kMinSamples || std::abs(om) < TorqueRatioIdentification::kMinTurn_rad ||
        !(km / om > 0))
      return std::numeric_limits<double>::quiet_NaN();
    return std::sqrt(km / om);
  };
  out.first_half_torque_ratio_m = ratio(half_km[0], half_omega[0], half_samples[0]);
  out.second_half_torque_ratio_m = ratio(half_km[1], half_omega[1], half_samples[1]);
  out.turn_rad = sum_omega;
  out.moment_term = sum_km;
  out.torque_ratio_m = ratio(sum_km, sum_omega, out.samples);
  return out;
}

double plan_lever_m(const ForecastObject& object, const PushDescriptor& d) {
  const Eigen::Vector2d r = d.contact_body_m - object.centre_of_friction_m;
  // The push direction in the body frame: the inward normal at the contact turned by the angle. The outline's normal
  // there is recovered from the outline itself.
  int hint = -1;
  const Outline::Closest cl = object.outline->closest(d.contact_body_m, hint);
  const Eigen::Vector2d inward = -cl.normal;
  const Eigen::Vector2d u = Eigen::Rotation2Dd(d.angle_rad) * inward;
  return r.x() * u.y() - r.y() * u.x();
}

namespace {

constexpr double kLeverScale_m = 0.015, kAngleScale_rad = 20 * M_PI / 180, kRidge = 1.0;

/// Ridge regression of y on the rows of X (centred), lambda kRidge: the prediction at x.
template <int P>
double ridge_predict(const std::vector<Eigen::Matrix<double, P, 1>>& X, const std::vector<double>& y,
                     const Eigen::Matrix<double, P, 1>& x) {
  const double n = static_cast<double>(y.size());
  Eigen::Matrix<double, P, 1> mx = Eigen::Matrix<double, P, 1>::Zero();
  double my = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    mx += X[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  Eigen::Matrix<double, P, P> A = kRidge * Eigen::Matrix<double, P, P>::Identity();
  Eigen::Matrix<double, P, 1> b = Eigen::Matrix<double, P, 1>::Zero();
  for (std::size_t i = 0; i < y.size(); ++i) {
    const Eigen::Matrix<double, P, 1> d = X[i] - mx;
    A += d * d.transpose() / n;
    b += d * (y[i] - my) / n;
  }
  const Eigen::Matrix<double, P, 1> slope = A.ldlt().solve(b);
  return my + slope.dot(x - mx);
}

Eigen::Matrix<double, 2, 1> lever_features(const LimitSurfaceStudyPush& p) {
  return {std::abs(p.lever_m) / kLeverScale_m, std::abs(p.descriptor.angle_rad) / kAngleScale_rad};
}

/// The averaged similarity weighting (ObjectModel::similarity_averaged): the mean over the bandwidths 0, 2, 1 and 0.5
/// of the weights under each, normalised.
std::vector<double> averaged_weights(const std::vector<PushDescriptor>& others, const PushDescriptor& d) {
  std::vector<double> w(others.size(), 0.0);
  for (const double h : {0.0, 2.0, 1.0, 0.5}) {
    std::vector<double> part(others.size(), 1.0);
    if (h > 0) {
      double best = 0;
      for (std::size_t i = 0; i < others.size(); ++i) {
        part[i] = std::exp(-0.5 * descriptor_distance2(others[i], d) / (h * h));
        best = std::max(best, part[i]);
      }
      if (!(best > 1e-6)) part.assign(others.size(), 1.0);
    }
    double total = 0;
    for (const double x : part) total += x;
    for (std::size_t i = 0; i < others.size(); ++i) w[i] += part[i] / total / 4.0;
  }
  return w;
}

}  // namespace

std::vector<LimitSurfaceStudyPush> run_limit_surface_study(const std::vector<RecordedForecastCase>& cases,
                                                           const std::vector<PushFit>& fits,
                                                           const std::vector<TorqueRatioIdentification>& identified) {
  std::vector<LimitSurfaceStudyPush> out;
  std::map<std::pair<std::string, std::string>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < cases.size(); ++i) groups[{cases[i].object, cases[i].surface}].push_back(i);
  const ForecastSettings settings;
  for (const auto& [key, members] : groups) {
    std::vector<LimitSurfaceStudyPush> rows;
    for (const std::size_t i : members) {
      LimitSurfaceStudyPush p;
      const RecordedForecastCase& c = cases[i];
      p.name = c.name;
      p.object = c.object;
      p.surface = c.surface;
      p.descriptor = describe_push(c.forecast_object, c.plan, c.start_pose);
      p.lever_m = plan_lever_m(c.forecast_object, p.descriptor);
      p.measured_pusher_friction = c.measured_pusher_friction;
      p.identified = identified[i];
      p.own_fit_torque_ratio_m = fits[i].parameters.torque_ratio_m;
      rows.push_back(p);
    }
    for (std::size_t a = 0; a < members.size(); ++a) {
      LimitSurfaceStudyPush& p = rows[a];
      const RecordedForecastCase& c = cases[members[a]];
      std::vector<double> y, mu_p_measured, mu_p_fitted, mu_s;
      std::vector<PushDescriptor> d;
      std::vector<Eigen::Matrix<double, 4, 1>> xt;
      std::vector<Eigen::Matrix<double, 2, 1>> xl;
      for (std::size_t b = 0; b < members.size(); ++b) {
        if (b == a) continue;
        const LimitSurfaceStudyPush& q = rows[b];
        const PushFit& f = fits[members[b]];
        mu_p_fitted.push_back(f.parameters.pusher_friction);
        mu_s.push_back(f.parameters.support_friction);
        if (std::isfinite(q.measured_pusher_friction)) mu_p_measured.push_back(q.measured_pusher_friction);
        if (!std::isfinite(q.identified.torque_ratio_m)) continue;
        y.push_back(std::log(q.identified.torque_ratio_m));
        d.push_back(q.descriptor);
        xt.push_back(trend_features(q.descriptor));
        xl.push_back(lever_features(q));
      }
      p.predicted_log_c.assign(kPlanModelNames.size(), std::numeric_limits<double>::quiet_NaN());
      if (y.size() >= 3) {
        p.predicted_log_c[0] = median(y);
        p.predicted_log_c[1] = ridge_predict<4>(xt, y, trend_features(p.descriptor));
        const std::vector<double> w = averaged_weights(d, p.descriptor);
        double s = 0;
        for (std::size_t k = 0; k < y.size(); ++k) s += w[k] * y[k];
        p.predicted_log_c[2] = s;
        p.predicted_log_c[3] = ridge_predict<2>(xl, y, lever_features(p));
      }
      p.held_pusher_friction = mu_p_measured.empty() ? median(mu_p_fitted) : median(mu_p_measured);
      p.support_friction = median(mu_s);
      const double c_uniform =
          c.forecast_object.outline->uniform_pressure_torque_ratio_m(c.forecast_object.centre_of_friction_m);
      auto forecast_with = [&](double log_c) {
        ForecastParameters q;
        q.pusher_friction = p.held_pusher_friction;
        q.support_friction = p.support_friction;
        // The fits' bounds on c (fit_push_parameters): 0.15-2.5 times the uniform pressure's.
        q.torque_ratio_m = std::clamp(std::exp(log_c), 0.15 * c_uniform, 2.5 * c_uniform);
        const Eigen::MatrixX3d poses = forecast_poses(c.forecast_object, q, c.plan, c.start_pose, c.times_s, settings);
        return forecast_errors(c, poses);
      };
      const double fallback = std::isfinite(p.predicted_log_c[0]) ? p.predicted_log_c[0] : std::log(c_uniform);
      for (const double lc : p.predicted_log_c) p.errors.push_back(forecast_with(std::isfinite(lc) ? lc : fallback));
      const double own = p.identified.torque_ratio_m;
      p.errors.push_back(forecast_with(std::isfinite(own) ? std::log(own) : fallback));
      // The ensembles: the others' trajectories averaged under the averaged similarity weighting, each with its own
      // fitted (mu_p, c, mu_s) ("ensemble_fitted"), or with the held mu_p, its identified c and its fitted mu_s
      // ("ensemble_identified"; only the others whose c is identified).
      for (const bool identified_c : {false, true}) {
        std::vector<PushDescriptor> dm;
        std::vector<ForecastParameters> pm;
        for (std::size_t b = 0; b < members.size(); ++b) {
          if (b == a) continue;
          const PushFit& f = fits[members[b]];
          ForecastParameters q = f.parameters;
          if (identified_c) {
            if (!std::isfinite(rows[b].identified.torque_ratio_m)) continue;
            q.pusher_friction = p.held_pusher_friction;
            q.torque_ratio_m = std::clamp(rows[b].identified.torque_ratio_m, 0.15 * c_uniform, 2.5 * c_uniform);
          }
          dm.push_back(rows[b].descriptor);
          pm.push_back(q);
        }
        Eigen::MatrixX3d mean = Eigen::MatrixX3d::Zero(c.times_s.size(), 3);
        const std::vector<double> w = averaged_weights(dm, p.descriptor);
        for (std::size_t k = 0; k < pm.size(); ++k)
          mean += w[k] * forecast_poses(c.forecast_object, pm[k], c.plan, c.start_pose, c.times_s, settings);
        p.errors.push_back(pm.empty() ? p.errors[0] : forecast_errors(c, mean));
      }
    }
    for (auto& r : rows) out.push_back(std::move(r));
  }
  return out;
}

std::vector<double> plan_model_r2(const std::vector<LimitSurfaceStudyPush>& pushes, int* used) {
  std::vector<double> se(kPlanModelNames.size(), 0.0);
  int n = 0;
  for (const auto& p : pushes) {
    if (!std::isfinite(p.identified.torque_ratio_m) || p.predicted_log_c.empty() ||
        !std::isfinite(p.predicted_log_c[0]))
      continue;
    const double y = std::log(p.identified.torque_ratio_m);
    for (std::size_t m = 0; m < se.size(); ++m) se[m] += std::pow(p.predicted_log_c[m] - y, 2);
    ++n;
  }
  if (used) *used = n;
  std::vector<double> r2(se.size(), std::numeric_limits<double>::quiet_NaN());
  if (n < 2 || !(se[0] > 0)) return r2;
  for (std::size_t m = 0; m < se.size(); ++m) r2[m] = 1 - se[m] / se[0];
  return r2;
}

std::string limit_surface_study_csv(const std::vector<LimitSurfaceStudyPush>& pushes) {
  std::ostringstream o;
  o << "push,object,surface,contact_x_mm,contact_y_mm,angle_deg,speed_mm_s,lever_mm,measured_pusher_friction,"
       "identified_c_mm,identified_turn_deg,identified_samples,identified_c_first_half_mm,identified_c_second_half_mm,"
       "own_fit_c_mm,held_pusher_friction,support_friction";
  for (const auto& m : kPlanModelNames) o << ",predicted_c_mm_" << m;
  for (const auto& m : kPlanModelNames) o << ",final_yaw_error_deg_" << m;
  o << ",final_yaw_error_deg_own_identified,final_yaw_error_deg_ensemble_fitted,"
       "final_yaw_error_deg_ensemble_identified";
  for (const auto& m : kPlanModelNames) o << ",trajectory_yaw_deg_" << m;
  o << ",trajectory_yaw_deg_own_identified,trajectory_yaw_deg_ensemble_fitted,"
       "trajectory_yaw_deg_ensemble_identified\n";
  auto num = [&](double x) {
    if (std::isfinite(x)) o << x;
  };
  for (const auto& p : pushes) {
    o << p.name << ',' << p.object << ',' << p.surface << ',' << 1e3 * p.descriptor.contact_body_m.x() << ','
      << 1e3 * p.descriptor.contact_body_m.y() << ',' << p.descriptor.angle_rad * 180 / M_PI << ','
      << 1e3 * std::exp(p.descriptor.log_speed) << ',' << 1e3 * p.lever_m << ',';
    num(p.measured_pusher_friction);
    o << ',';
    num(1e3 * p.identified.torque_ratio_m);
    o << ',' << p.identified.turn_rad * 180 / M_PI << ',' << p.identified.samples << ',';
    num(1e3 * p.identified.first_half_torque_ratio_m);
    o << ',';
    num(1e3 * p.identified.second_half_torque_ratio_m);
    o << ',' << 1e3 * p.own_fit_torque_ratio_m << ',' << p.held_pusher_friction << ',' << p.support_friction;
    for (const double lc : p.predicted_log_c) {
      o << ',';
      num(1e3 * std::exp(lc));
    }
    for (const auto& e : p.errors) o << ',' << e.final_yaw_rad * 180 / M_PI;
    for (const auto& e : p.errors) o << ',' << e.trajectory_yaw_rad * 180 / M_PI;
    o << '\n';
  }
  return o.str();
}

std::string limit_surface_study_tables(const std::vector<LimitSurfaceStudyPush>& pushes) {
  std::map<std::string, std::vector<const LimitSurfaceStudyPush*>> by_object;
  for (const auto& p : pushes) {
    by_object[p.object].push_back(&p);
    by_object["all"].push_back(&p);
  }
  std::ostringstream o;
  char buf[512];
  o << "How well the plan predicts each push's identified ln c, leaving the push out (pushes whose c is identified "
       "and predicted): the spread of ln c (sd), and the root mean square of each model's leave-one-out error "
       "(R^2 = 1 - its mean square over others_median's)\n\n";
  o << "| object | pushes | identified | sd ln c | others_median rms | linear_trend rms (R^2) | similarity rms (R^2) | "
       "lever rms (R^2) | corr(ln c identified, ln c own fit) | halves identified | corr(ln c first half, second "
       "half) | rms (ln c second half - first) / 2 |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | "
       "--- | "
       "--- |\n";
  for (const auto& [object, ps] : by_object) {
    std::vector<double> se(kPlanModelNames.size(), 0.0), lc, lf;
    int used = 0;
    for (const auto* p : ps) {
      if (!std::isfinite(p->identified.torque_ratio_m) || !std::isfinite(p->predicted_log_c[0])) continue;
      const double y = std::log(p->identified.torque_ratio_m);
      for (std::size_t m = 0; m < se.size(); ++m) se[m] += std::pow(p->predicted_log_c[m] - y, 2);
      lc.push_back(y);
      lf.push_back(std::log(p->own_fit_torque_ratio_m));
      ++used;
    }
    if (used < 2) continue;
    double mean = 0, meanf = 0;
    for (std::size_t k = 0; k < lc.size(); ++k) {
      mean += lc[k] / used;
      meanf += lf[k] / used;
    }
    double var = 0, varf = 0, cov = 0;
    for (std::size_t k = 0; k < lc.size(); ++k) {
      var += std::pow(lc[k] - mean, 2) / (used - 1);
      varf += std::pow(lf[k] - meanf, 2) / (used - 1);
      cov += (lc[k] - mean) * (lf[k] - meanf) / (used - 1);
    }
    std::vector<double> h1, h2;
    for (const auto* p : ps)
      if (std::isfinite(p->identified.first_half_torque_ratio_m) &&
          std::isfinite(p->identified.second_half_torque_ratio_m)) {
        h1.push_back(std::log(p->identified.first_half_torque_ratio_m));
        h2.push_back(std::log(p->identified.second_half_torque_ratio_m));
      }
    double m1 = 0, m2 = 0, v1 = 0, v2 = 0, c12 = 0, dd = 0;
    for (std::size_t k = 0; k < h1.size(); ++k) {
      m1 += h1[k] / h1.size();
      m2 += h2[k] / h1.size();
    }
    for (std::size_t k = 0; k < h1.size(); ++k) {
      v1 += std::pow(h1[k] - m1, 2);
      v2 += std::pow(h2[k] - m2, 2);
      c12 += (h1[k] - m1) * (h2[k] - m2);
      dd += std::pow(0.5 * (h2[k] - h1[k]), 2) / h1.size();
    }
    auto rms = [&](std::size_t m) { return std::sqrt(se[m] / used); };
    auto r2 = [&](std::size_t m) { return 1 - se[m] / se[0]; };
    std::snprintf(
        buf, sizeof buf,
        "| %s | %zu | %d | %.2f | %.2f | %.2f (%+.2f) | %.2f (%+.2f) | %.2f (%+.2f) | %.2f | %zu | %.2f | %.2f |\n",
        object.c_str(), ps.size(), used, std::sqrt(var), rms(0), rms(1), r2(1), rms(2), r2(2), rms(3), r2(3),
        cov / std::sqrt(var * varf), h1.size(), c12 / std::sqrt(v1 * v2), std::sqrt(dd));
    o << buf;
  }
  o << "\nThe final and trajectory-mean yaw error [deg] of a single forecast of each push with the rod's friction "
       "held at the other pushes' measured median, the support's friction their fitted median, and c predicted by "
       "each model (own_identified: the push's own identified c, where identified); and the mean trajectory of the "
       "other "
       "pushes' forecasts under the averaged similarity weighting with their own fitted (mu_p, c, mu_s) "
       "(ensemble_fitted) or with the held rod friction, their identified c and fitted mu_s (ensemble_identified)\n\n";
  o << "| object | pushes |";
  for (const auto& m : kPlanModelNames) o << ' ' << m << " |";
  o << " own_identified | ensemble_fitted | ensemble_identified |\n| --- | --- |";
  for (std::size_t m = 0; m < kPlanModelNames.size() + 3; ++m) o << " --- |";
  o << '\n';
  for (const auto& [object, ps] : by_object) {
    const std::size_t k = kPlanModelNames.size() + 3;
    std::vector<double> fin(k, 0.0), traj(k, 0.0);
    for (const auto* p : ps)
      for (std::size_t m = 0; m < k; ++m) {
        fin[m] += p->errors[m].final_yaw_rad * 180 / M_PI / ps.size();
        traj[m] += p->errors[m].trajectory_yaw_rad * 180 / M_PI / ps.size();
      }
    o << "| " << object << " | " << ps.size() << " |";
    for (std::size_t m = 0; m < k; ++m) {
      std::snprintf(buf, sizeof buf, " %.2f / %.2f |", fin[m], traj[m]);
      o << buf;
    }
    o << '\n';
  }
  return o.str();
}

}  // namespace pushpred
