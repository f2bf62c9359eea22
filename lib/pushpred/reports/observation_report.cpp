#include "pushpred/reports/observation_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "pushpred/reports/plotting.hpp"

namespace pushpred {
namespace {

constexpr double kDeg = 180.0 / M_PI;

std::string csv(const std::vector<std::string>& header, const std::vector<const Eigen::MatrixXd*>& blocks) {
  std::ostringstream out;
  out.precision(10);
  for (std::size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  const Eigen::Index rows = blocks.front()->rows();
  for (Eigen::Index k = 0; k < rows; ++k) {
    bool first = true;
    for (const auto* b : blocks)
      for (Eigen::Index c = 0; c < b->cols(); ++c) {
        out << (first ? "" : ",") << (*b)(k, c);
        first = false;
      }
    out << "\n";
  }
  return out.str();
}

std::string forces_script(const Observation& o) {
  const std::string title = std::filesystem::path(o.source).filename().string();
  std::ostringstream gp;
  gp << "# DOB against PID estimate of the unknown force and torque (the paper's figure 4). Data: observer.csv.\n"
     << png_terminal("forces.png", 1000, 900) << "set datafile separator ','\n"
     << "set multiplot layout 3,1 title " << gnuplot_quoted("Unknown force and torque: " + title) << " noenhanced\n"
     << "set grid\nset key outside right top\n";
  const char* labels[3] = {"f_{frt,x} [N]", "f_{frt,y} [N]", "T_{frt} [N m]"};
  for (int c = 0; c < 3; ++c) {
    gp << "set ylabel '" << labels[c] << "'\n" << (c == 2 ? "set xlabel 't [s]'\n" : "unset xlabel\n")
       << "plot 'observer.csv' every ::1 using 1:" << 5 + c << " with lines lw 1.5 title 'DOB', "
       << "'' every ::1 using 1:" << 8 + c << " with lines lw 1.5 dt 2 title 'PID'\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

std::string trajectory_script(const Observation& o) {
  const std::string title = std::filesystem::path(o.source).filename().string();
  std::ostringstream gp;
  gp << "# Pose re-simulated from each estimate's total force against the measured pose (the paper's figure 2).\n"
     << "# Data: resimulation.csv (SI); drawn in mm and degrees.\n"
     << png_terminal("trajectory.png", 1000, 900) << "set datafile separator ','\n"
     << "set multiplot layout 3,1 title " << gnuplot_quoted("Re-simulated against measured pose: " + title) << " noenhanced\n"
     << "set grid\nset key outside right top\n";
  const char* labels[3] = {"x [mm]", "y [mm]", "theta [deg]"};
  const char* scale[3] = {"1000", "1000", "180/pi"};
  for (int c = 0; c < 3; ++c) {
    gp << "set ylabel '" << labels[c] << "'\n" << (c == 2 ? "set xlabel 't [s]'\n" : "unset xlabel\n")
       << "plot 'resimulation.csv' every ::1 using 1:($" << 2 + c << "*" << scale[c]
       << ") with lines lw 2 title 'measured', '' every ::1 using 1:($" << 8 + c << "*" << scale[c]
       << ") with lines lw 1.5 dt 2 title 'PID', '' every ::1 using 1:($" << 5 + c << "*" << scale[c]
       << ") with lines lw 1.5 dt 3 title 'DOB'\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

nlohmann::json triple(const Eigen::RowVector3d& v, double scale_xy, double scale_theta, const char* unit_xy,
                      const char* unit_theta) {
  return {{std::string("x_") + unit_xy, v(0) * scale_xy},
          {std::string("y_") + unit_xy, v(1) * scale_xy},
          {std::string("theta_") + unit_theta, v(2) * scale_theta}};
}

}  // namespace

std::vector<OutputFile> observation_files(const Observation& o) {
  const Eigen::MatrixXd t = o.dob.t_s, u = o.dob.u, dd = o.dob.d_hat, pd = o.pid.d_hat, dv = o.dob.velocity,
                        pv = o.pid.velocity, m = o.measured_pose, rd = o.resimulated_dob, rp = o.resimulated_pid;
  std::vector<OutputFile> files;
  files.push_back({"observer.csv",
                   csv({"t_s", "u_x_N", "u_y_N", "u_theta_Nm", "dob_d_x_N", "dob_d_y_N", "dob_d_theta_Nm", "pid_d_x_N",
                        "pid_d_y_N", "pid_d_theta_Nm", "dob_v_x_m_s", "dob_v_y_m_s", "dob_v_theta_rad_s",
                        "pid_v_x_m_s", "pid_v_y_m_s", "pid_v_theta_rad_s"},
                       {&t, &u, &dd, &pd, &dv, &pv})});
  files.push_back({"resimulation.csv",
                   csv({"t_s", "measured_x_m", "measured_y_m", "measured_theta_rad", "dob_x_m", "dob_y_m",
                        "dob_theta_rad", "pid_x_m", "pid_y_m", "pid_theta_rad"},
                       {&t, &m, &rd, &rp})});
  files.push_back({"observation.json", observation_json(o).dump(2) + "\n"});
  files.push_back({"forces.gp", forces_script(o)});
  files.push_back({"trajectory.gp", trajectory_script(o)});
  return files;
}

std::vector<std::string> observation_plot_scripts() { return {"forces.gp", "trajectory.gp"}; }

nlohmann::json observation_json(const Observation& o) {
  const Eigen::Index n = o.dob.t_s.size();
  return {{"source", o.source},
          {"t_start_s", o.dob.t_s(0)},
          {"t_end_s", o.dob.t_s(n - 1)},
          {"samples", n},
          {"nominal_mass_kg", o.dob.nominal_inertia(0)},
          {"nominal_inertia_kgm2", o.dob.nominal_inertia(2)},
          {"rms_dob", triple(o.rms_dob, 1, 1, "N", "Nm")},
          {"rms_dob_minus_pid", triple(o.rms_dob_minus_pid, 1, 1, "N", "Nm")},
          {"rms_resimulated_minus_measured",
           {{"dob", triple(o.rms_resimulation_dob, 1e3, kDeg, "mm", "deg")},
            {"pid", triple(o.rms_resimulation_pid, 1e3, kDeg, "mm", "deg")}}}};
}

std::string observation_summary(const Observation& o) {
  char buf[768];
  std::snprintf(buf, sizeof buf,
                "%s: %.3f-%.3f s, %ld samples\n"
                "  RMS d_hat(DOB):                         x %.3f N, y %.3f N, rotation %.4f N m\n"
                "  RMS d_hat(DOB) - d_hat(PID):            x %.3f N, y %.3f N, rotation %.4f N m\n"
                "  RMS re-simulated - measured pose, DOB:  x %.2f mm, y %.2f mm, theta %.2f deg\n"
                "  RMS re-simulated - measured pose, PID:  x %.2f mm, y %.2f mm, theta %.2f deg\n",
                std::filesystem::path(o.source).filename().c_str(), o.dob.t_s(0), o.dob.t_s(o.dob.t_s.size() - 1),
                static_cast<long>(o.dob.t_s.size()), o.rms_dob(0), o.rms_dob(1), o.rms_dob(2), o.rms_dob_minus_pid(0), o.rms_dob_minus_pid(1),
                o.rms_dob_minus_pid(2), 1e3 * o.rms_resimulation_dob(0), 1e3 * o.rms_resimulation_dob(1),
                kDeg * o.rms_resimulation_dob(2), 1e3 * o.rms_resimulation_pid(0), 1e3 * o.rms_resimulation_pid(1),
                kDeg * o.rms_resimulation_pid(2));
  return buf;
}

}  // namespace pushpred
