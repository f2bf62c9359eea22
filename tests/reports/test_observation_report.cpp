// The files of `pushpred observe` for a hand-made Observation of three samples: names, columns, one row per sample,
// and the JSON's units (m -> mm and rad -> deg converted here by hand).
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "pushpred/reports/observation_report.hpp"

using namespace pushpred;

namespace {

Observation three_samples() {
  Observation o;
  o.source = "/somewhere/motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.500_t=0.000.h5";
  for (DisturbanceEstimate* e : {&o.dob, &o.pid}) {
    e->t_s = Eigen::Vector3d(0.25, 0.5, 0.75);
    e->u = e->d_hat = e->velocity = e->total = Eigen::MatrixX3d::Zero(3, 3);
    e->nominal_inertia = Eigen::Vector3d(0.5, 0.5, 2e-3);
  }
  o.dob.d_hat(1, 0) = 1.5;  // row t = 0.5 s, dob_d_x_N
  o.measured_pose = o.resimulated_dob = o.resimulated_pid = Eigen::MatrixX3d::Zero(3, 3);
  o.rms_dob = Eigen::RowVector3d(1, 2, 3);
  o.rms_dob_minus_pid = Eigen::RowVector3d(0.5, 0.25, 0.125);
  o.rms_resimulation_dob = Eigen::RowVector3d(0.001, 0.002, M_PI / 180);  // 1 mm, 2 mm, 1 deg
  o.rms_resimulation_pid = Eigen::RowVector3d(0.004, 0.0005, M_PI / 90);  // 4 mm, 0.5 mm, 2 deg
  return o;
}

const OutputFile& file_named(const std::vector<OutputFile>& files, const std::string& name) {
  const auto found = std::find_if(files.begin(), files.end(), [&](const OutputFile& f) { return f.name == name; });
  BOOST_TEST_INFO("file " << name);
  BOOST_TEST_REQUIRE((found != files.end()));
  return *found;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(observation_report)

BOOST_AUTO_TEST_CASE(each_table_has_its_columns_and_one_row_per_sample) {
  const Observation o = three_samples();
  const std::vector<OutputFile> files = observation_files(o);
  const std::string& observer = file_named(files, "observer.csv").text;
  BOOST_TEST(observer.substr(0, observer.find('\n')) ==
             "t_s,u_x_N,u_y_N,u_theta_Nm,dob_d_x_N,dob_d_y_N,dob_d_theta_Nm,pid_d_x_N,pid_d_y_N,pid_d_theta_Nm,"
             "dob_v_x_m_s,dob_v_y_m_s,dob_v_theta_rad_s,pid_v_x_m_s,pid_v_y_m_s,pid_v_theta_rad_s");
  BOOST_TEST(std::count(observer.begin(), observer.end(), '\n') == 3 + 1);
  BOOST_TEST(observer.find("\n0.5,0,0,0,1.5,0,0,0,0,0,0,0,0,0,0,0\n") != std::string::npos);
  const std::string& resimulation = file_named(files, "resimulation.csv").text;
  BOOST_TEST(resimulation.substr(0, resimulation.find('\n')) ==
             "t_s,measured_x_m,measured_y_m,measured_theta_rad,dob_x_m,dob_y_m,dob_theta_rad,pid_x_m,pid_y_m,"
             "pid_theta_rad");
  BOOST_TEST(std::count(resimulation.begin(), resimulation.end(), '\n') == 3 + 1);
  for (const std::string& script : observation_plot_scripts()) BOOST_TEST(!file_named(files, script).text.empty());
}

BOOST_AUTO_TEST_CASE(the_json_gives_the_span_and_the_differences_in_mm_and_degrees) {
  const nlohmann::json j = observation_json(three_samples());
  BOOST_TEST(j["t_start_s"].get<double>() == 0.25);
  BOOST_TEST(j["t_end_s"].get<double>() == 0.75);
  BOOST_TEST(j["samples"].get<int>() == 3);
  BOOST_TEST(j["nominal_mass_kg"].get<double>() == 0.5);
  BOOST_TEST(j["nominal_inertia_kgm2"].get<double>() == 2e-3);
  BOOST_TEST(j["rms_dob_minus_pid"]["theta_Nm"].get<double>() == 0.125);
  const auto& dob = j["rms_resimulated_minus_measured"]["dob"];
  const auto& pid = j["rms_resimulated_minus_measured"]["pid"];
  const auto tol = boost::test_tools::tolerance(1e-12);
  BOOST_TEST(dob["x_mm"].get<double>() == 1.0, tol);
  BOOST_TEST(dob["y_mm"].get<double>() == 2.0, tol);
  BOOST_TEST(dob["theta_deg"].get<double>() == 1.0, tol);
  BOOST_TEST(pid["x_mm"].get<double>() == 4.0, tol);
  BOOST_TEST(pid["y_mm"].get<double>() == 0.5, tol);
  BOOST_TEST(pid["theta_deg"].get<double>() == 2.0, tol);
}

BOOST_AUTO_TEST_CASE(the_terminal_summary_names_the_file_not_its_folder) {
  const std::string summary = observation_summary(three_samples());
  BOOST_TEST(summary.rfind("motion_surface=abs_shape=rect1_", 0) == 0u);
  BOOST_TEST(summary.find("0.250-0.750 s, 3 samples") != std::string::npos);
  BOOST_TEST(summary.find("x 4.00 mm, y 0.50 mm, theta 2.00 deg") != std::string::npos);
}

BOOST_AUTO_TEST_SUITE_END()
