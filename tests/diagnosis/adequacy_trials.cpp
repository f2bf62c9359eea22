// The model-adequacy test (diagnosis/model_adequacy.hpp) on randomized simulated trials, one line per trial: the
// numbers docs/diagnosis.md quotes ("Is the corrected model adequate?"). Not a test: a program to rerun them.
//
//   adequacy_trials FIRST_SEED TRIALS KIND AMOUNT [hide|show]
//
// Trial k draws 4 to 8 pushes of rect2 on abs (speeds 2-15 cm/s) from seed FIRST_SEED + k with the simulator effect
// KIND at AMOUNT (KIND none: clean), and diagnoses them with the standard catalogue, or with KIND removed from it
// (hide). Each line: the verdict, both parts' statistics, sizes and floors, the effects found, the first hint.
#include <cstdio>
#include <random>
#include <string>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "simulated_pushes.hpp"

using namespace pushpred;
using namespace pushpred::testing;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: adequacy_trials FIRST_SEED TRIALS KIND AMOUNT [hide|show]\n");
    return 2;
  }
  try {
    const unsigned long first = std::stoul(argv[1]);
    const int count = std::stoi(argv[2]);
    const std::string kind = argv[3];
    const double amount = std::stod(argv[4]);
    const bool hide = argc > 5 && std::string(argv[5]) == "hide";
    int unexplained = 0, with_finding = 0;
    for (int t = 0; t < count; ++t) {
      std::mt19937_64 rng(first + static_cast<unsigned long>(t));
      const int n = 4 + static_cast<int>(rng() % 5);
      DrawRanges ranges;
      ranges.speed_min_m_s = 0.02;
      ranges.speed_max_m_s = 0.15;
      std::vector<std::pair<std::string, double>> effects;
      if (kind != "none") effects.push_back({kind, amount});
      const auto pushes = simulate_all(draw_scenarios(rng, n, effects, ranges));
      EffectLibrary library = EffectLibrary::standard();
      if (hide && kind != "none") library.remove(kind);
      const DiagnosisResult r = diagnose(pushes, library, DiagnosisOptions{});
      const ModelAdequacy& a = r.adequacy;
      std::string found;
      for (const auto& k : effects_found(r)) found += (found.empty() ? "" : ",") + k;
      unexplained += a.tested && !a.explained ? 1 : 0;
      with_finding += found.empty() ? 0 : 1;
      std::printf(
          "%lu %s pushes %d: %s | force z %.2f (threshold %.2f, p %.3f), %.3f +- %.3f N, %.4f +- %.4f N m "
          "(floors %.3f N, %.4f N m) | motion |t| %.2f (threshold %.2f, p %.3f), %.2f mm, %.2f deg (floors "
          "%.2f mm, %.2f deg) | found %s | first hint %s\n",
          first + static_cast<unsigned long>(t), kind.c_str(), n, a.verdict().c_str(), a.force_statistic,
          a.force_threshold, a.force_p_value, a.force_N, a.force_N_std, a.torque_Nm, a.torque_Nm_std, a.force_floor_N,
          a.torque_floor_Nm, a.motion_t, a.motion_t_threshold, a.motion_p_value, a.position_bias_mm, a.yaw_bias_deg,
          a.position_floor_mm, a.yaw_floor_deg, found.empty() ? "-" : found.c_str(),
          r.hints.empty() ? "-" : r.hints.front().signature.c_str());
      std::fflush(stdout);
    }
    std::printf("unexplained residual in %d of %d trials; a kind found in %d\n", unexplained, count, with_finding);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "adequacy_trials: %s\n", e.what());
    return 1;
  }
}
