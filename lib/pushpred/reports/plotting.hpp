#pragma once
// Plots for reports, drawn by gnuplot when it is installed. A report writes a gnuplot script and its data file
// into its output folder and asks run_gnuplot() to draw it; the script names its data and PNG by relative
// name, so the folder can be moved and the plot re-drawn or edited by hand. Without gnuplot nothing is drawn
// and the caller gets a note to print instead.
#include <filesystem>
#include <string>

namespace pushpred {

/// The gnuplot executable found on PATH; empty when there is none.
std::filesystem::path find_gnuplot();

struct PlotRun {
  bool drawn = false;
  std::string note;  ///< why nothing was drawn (gnuplot absent, or its error message); empty when drawn
};

/// Runs gnuplot on `script` with the script's folder as working directory. Never throws for a missing or failing
/// gnuplot: plots are secondary to the numbers, so the report goes on and says why a plot is missing.
PlotRun run_gnuplot(const std::filesystem::path& script);

/// Script lines that send the plot to `png_name`: pngcairo where gnuplot has it, the plain png terminal otherwise.
std::string png_terminal(const std::string& png_name, int width_px, int height_px);

/// `text` as a single-quoted gnuplot string.
std::string gnuplot_quoted(const std::string& text);

}  // namespace pushpred
