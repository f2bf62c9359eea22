// The PID force reconstruction of section II-B.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/observers/resimulation.hpp"
#include "synthetic_push.hpp"

using namespace pushpred;
using pushpred::testing::SyntheticPushSpec;
using pushpred::testing::synthetic_push;

namespace {

PidGains scaled(PidGains g, double factor) {
  g.kp *= factor, g.ki *= factor, g.kd *= factor, g.lp *= factor, g.li *= factor, g.ld *= factor;
  return g;
}

/// max over t >= t_from of |f_hat - M y''| per channel, relative to the amplitude M A of M y''.
Eigen::Vector3d total_force_error(const PidForceReconstruction& pid, const SyntheticPushSpec& spec, double t_from) {
  const SynchronisedPush push = synthetic_push(spec);
  const DisturbanceEstimate e = pid.estimate(push);
  const Eigen::Vector3d M(push.shape.mass_kg, push.shape.mass_kg, push.shape.inertia_kgm2);
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();
  for (Eigen::Index k = push.index_at(t_from); k < push.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const double truth = M(c) * spec.motion[c].acceleration(push.t_s(k));
      worst(c) = std::max(worst(c), std::abs(e.total(k, c) - truth) / (M(c) * spec.motion[c].A));
    }
  return worst;
}

/// The same measure for an estimate of zero: max over t >= t_from of |M y''| / (M A) = max |sin(w t)| on the grid,
/// close to 1 over a span longer than a period.
Eigen::Vector3d zero_estimate_error(const SyntheticPushSpec& spec, double t_from) {
  const SynchronisedPush push = synthetic_push(spec);
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();
  for (Eigen::Index k = push.index_at(t_from); k < push.size(); ++k)
    for (int c = 0; c < 3; ++c) worst(c) = std::max(worst(c), std::abs(std::sin(spec.motion[c].w * push.t_s(k))));
  return worst;
}

std::filesystem::path first_push_of(const std::string& shape) {
  for (const auto& f : list_recordings(resolve_data_folder(), "abs"))
    if (f.filename().string().find("shape=" + shape + "_") != std::string::npos) return f;
  throw std::runtime_error("no " + shape + " push in the data folder");
}

}  // namespace

BOOST_AUTO_TEST_SUITE(pid_force_reconstruction)

BOOST_AUTO_TEST_CASE(the_reconstructed_total_force_follows_a_known_motion_and_depends_on_the_gains) {
  // The paper's caveat: "the errors in the estimation are strongly dependent on the choice of PID control gains".
  SyntheticPushSpec spec;
  spec.duration_s = 3.0;
  spec.disturbance = [](int c, double t) { return (c == 2 ? 0.01 : 1.0) * (t > 0.5 ? -2.0 : -1.5); };
  const Eigen::Vector3d paper = total_force_error(PidForceReconstruction{}, spec, 0.5);
  const Eigen::Vector3d stiffer = total_force_error(PidForceReconstruction{scaled(PidGains{}, 10.0)}, spec, 0.5);
  BOOST_TEST_MESSAGE("max |f_hat - M y''| / (M A), paper gains: " << paper.transpose()
                                                                    << "; ten times the gains: " << stiffer.transpose());
  // It does follow the motion: its worst error is at most three quarters of the amplitude, which an estimate of
  // zero (error = the whole signal, max |sin| ~ 1 over these 2.5 s) fails. Measured: 0.67, 0.37, 0.025.
  const double bound = 0.75;
  const Eigen::Vector3d zero = zero_estimate_error(spec, 0.5);
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST_INFO("channel " << c);
    BOOST_TEST(zero(c) > bound);  // the bound means something
    BOOST_TEST(paper(c) < bound);
  }
  // Translation: the mass matters against kd, so stiffer gains track better. Rotation: I is so small that the
  // closed loop is already near its limit I -> 0, whose slow poles depend on the gains' ratios only.
  BOOST_TEST(stiffer(0) < paper(0) / 3);
  BOOST_TEST(stiffer(1) < paper(1) / 3);
}

BOOST_AUTO_TEST_CASE(the_estimated_total_force_reproduces_the_measured_trajectory_of_a_slow_push) {
  // The paper's check (figure 2, its case 1: a constant 10 mm/s push): integrate M r'' = f_hat and compare with
  // the measured pose. "Reasonably close" is taken as within 1 mm and 1 degree RMS over the whole push. (At
  // 150 mm/s the paper's gains lag by a few millimetres: docs/observer.md.)
  const SynchronisedPush push = load_push(first_push_of("ellip3_a=0_v=10"));
  const DisturbanceEstimate e = PidForceReconstruction{}.estimate(push);
  const Eigen::RowVector3d rms = rms_difference(resimulate_pose(push, e), push.pose);
  BOOST_TEST_MESSAGE("RMS re-simulated - measured: " << 1e3 * rms(0) << " mm, " << 1e3 * rms(1) << " mm, "
                                                     << rms(2) * 180 / M_PI << " deg");
  BOOST_TEST(rms(0) < 1e-3);
  BOOST_TEST(rms(1) < 1e-3);
  BOOST_TEST(rms(2) < M_PI / 180);
}

BOOST_AUTO_TEST_CASE(cvode_and_the_exact_discretisation_agree_on_a_real_push) {
  const SynchronisedPush push = load_push(first_push_of("ellip3"));
  PidReconstructionOptions o;
  o.integrator.relative_tolerance = 1e-10;
  o.integrator.absolute_tolerance = 1e-12;
  const PidForceReconstruction pid(PidGains{}, o);
  const auto cvode = pid.track(push, 0, push.duration_s()), exact = pid.track_exactly(push, 0, push.duration_s());
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST_INFO("channel " << c);
    const auto close = [&](const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
      return (a.col(c) - b.col(c)).cwiseAbs().maxCoeff() <= 1e-6 * b.col(c).cwiseAbs().maxCoeff();
    };
    BOOST_TEST(close(cvode.estimate.d_hat, exact.estimate.d_hat));
    BOOST_TEST(close(cvode.estimate.velocity, exact.estimate.velocity));
    BOOST_TEST(close(cvode.simulated_pose.rowwise() - push.pose.row(0), exact.simulated_pose.rowwise() - push.pose.row(0)));
  }
}

BOOST_AUTO_TEST_CASE(gains_are_a_plain_value_checked_on_use) {
  PidGains g;
  BOOST_TEST(g.kp == 46.6);
  BOOST_TEST(g.ld == 24.5);
  g.ki = -1;
  BOOST_CHECK_THROW(PidForceReconstruction{g}, InputError);
  try {
    PidForceReconstruction pid(g);
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()) == "PID force reconstruction: gain ki must be finite and not negative, got -1");
  }
  g.ki = 0;  // no integral action is a valid choice
  BOOST_CHECK_NO_THROW(PidForceReconstruction{g});
  g = {};
  g.lp = std::numeric_limits<double>::quiet_NaN();
  BOOST_CHECK_THROW(PidForceReconstruction{g}, InputError);
  PidReconstructionOptions o;
  o.mass_kg = -1;
  BOOST_CHECK_THROW((PidForceReconstruction{PidGains{}, o}), InputError);
  o = {};
  o.integrator.relative_tolerance = 0;
  BOOST_CHECK_THROW((PidForceReconstruction{PidGains{}, o}), InputError);
  BOOST_CHECK_THROW(PidForceReconstruction{}.estimate(SynchronisedPush{}), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
