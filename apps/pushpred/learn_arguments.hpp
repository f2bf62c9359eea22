#pragma once
// The learning choices `learn` and `forecast-study` share (what the object model learns, and how a forecast uses it):
// one place for their flags, defaults, checks and help text.
#include <CLI/CLI.hpp>
#include <string>

#include "pushpred/forecast/object_model.hpp"

namespace pushpred::app {

struct LearnArguments {
  std::string central = kCentralForecastDefaultChoice;
  std::string residual_correction = kResidualCorrectionDefaultChoice;
  std::string pusher_friction = kPusherFrictionDefaultChoice;
  std::string centre_of_friction = "chosen";
  std::string trend = kTrendDefaultChoice;
  std::string similarity = kSimilarityDefaultChoice;
  std::string limit_surface = "ellipsoid";  ///< read with the pushes (load_forecast_inputs), not by apply_to
  std::string pressure_shape = kPressureShapeDefaultChoice;

  void add_to(CLI::App& sub);
  /// Every choice but the limit surface, into `options`.
  void apply_to(LearnOptions& options) const;
};

}  // namespace pushpred::app
