#pragma once
// The output of `pushpred observe` (and of the reproduction's figures 2 and 4) for one Observation
// (observers/observation.hpp): CSV tables in SI units, observation.json, gnuplot scripts and a few lines for the
// terminal in N, N m, mm and degrees. The app writes the files through StagedOutput.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/observers/observation.hpp"

namespace pushpred {

/// An output file: its name inside the output folder and its text.
struct OutputFile {
  std::string name, text;
};

/// observer.csv, resimulation.csv, observation.json and the gnuplot scripts (forces.gp: DOB against PID, as the
/// paper's figure 4; trajectory.gp: re-simulated against measured pose, as its figure 2). Each script reads its
/// CSV and writes its PNG by relative name.
std::vector<OutputFile> observation_files(const Observation& observation);
/// Names of the gnuplot scripts among observation_files(), for the app to run.
std::vector<std::string> observation_plot_scripts();

nlohmann::json observation_json(const Observation& observation);
/// A few lines for the terminal: RMS differences in N, N m, mm and degrees.
std::string observation_summary(const Observation& observation);

}  // namespace pushpred
