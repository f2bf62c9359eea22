#include "learn_arguments.hpp"

namespace pushpred::app {

void LearnArguments::add_to(CLI::App& sub) {
  const std::string central_help =
      "The central forecast at each time from the learned pushes' own forecasts: ensemble_mean (their weighted mean), "
      "ensemble_median (their positions' weighted geometric median and their yaws' weighted median) or median (the "
      "forecast of their parameters' median); default " +
      std::string(kCentralForecastDefaultChoice);
  sub.add_option("--central", central, central_help)->check(CLI::IsMember(kCentralForecastNames));
  const std::string residual_help =
      "Shift the central forecast by the learned pushes' leave-one-out final errors (similarity-weighted, shrunk, "
      "growing with the tip's progress): none, loo (always) or chosen (when it forecasts the learned pushes better "
      "leaving one out); default " +
      std::string(kResidualCorrectionDefaultChoice);
  sub.add_option("--residual-correction", residual_correction, residual_help)
      ->check(CLI::IsMember(kResidualCorrectionNames));
  const std::string friction_help =
      "Where the learned pushes' rod friction comes from: fitted (each push's own fit) or measured (the median of "
      "what their force sensors measured where the contact slid, held while c and the support's friction are "
      "fitted); default " +
      std::string(kPusherFrictionDefaultChoice);
  sub.add_option("--pusher-friction", pusher_friction, friction_help)->check(CLI::IsMember(kPusherFrictionNames));
  sub.add_option("--centre-of-friction", centre_of_friction,
                 "chosen (default: learned jointly over the pushes when that forecasts them better in "
                 "cross-validation, else the centroid), learned (always) or centroid (never learned)")
      ->check(CLI::IsMember({"chosen", "learned", "centroid"}));
  sub.add_option("--trend", trend,
                 "none (default) or chosen (the parameters follow the plan along a ridge-regression trend over the "
                 "learned pushes when that forecasts them better leaving each out)")
      ->check(CLI::IsMember({"chosen", "none"}));
  sub.add_option("--similarity", similarity,
                 "How the learned pushes are weighted by how alike they push to the plan: chosen (one bandwidth, "
                 "chosen by their own leave-one-out error) or averaged (the weights under the bandwidths 0, 2, 1 and "
                 "0.5 averaged; none chosen)")
      ->check(CLI::IsMember({"chosen", "averaged"}));
  sub.add_option("--limit-surface", limit_surface,
                 "ellipsoid (default: the ellipsoidal limit surface of a ratio c fitted per push) or outline (the "
                 "limit surface of a planar pressure over the outline centred at the centre of friction; no c)")
      ->check(CLI::IsMember({"ellipsoid", "outline"}));
  sub.add_option("--pressure-shape", pressure_shape,
                 "with --limit-surface outline: chosen (default: the pressure's rim weight learned jointly with the "
                 "centre of friction when that forecasts the pushes better in cross-validation, else uniform), "
                 "learned (always) or uniform (never learned)")
      ->check(CLI::IsMember({"chosen", "learned", "uniform"}));
}

void LearnArguments::apply_to(LearnOptions& options) const {
  options.central = central_forecast_named(central);
  options.residual_correction = residual_correction_named(residual_correction);
  options.pusher_friction = pusher_friction_named(pusher_friction);
  set_centre_of_friction_choice(options, centre_of_friction);
  set_trend_choice(options, trend);
  set_similarity_choice(options, similarity);
  set_pressure_shape_choice(options, pressure_shape);
}

}  // namespace pushpred::app
