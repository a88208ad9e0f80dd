// `rockwatch simulate --forecast-members N --forecast-horizon-s H`: the ensemble forecast of collapse (SPEC §10) from
// the simulated (or fused) state every --forecast-every-s seconds while the wall is not at rest, the ground model
// fitted to the record up to each forecast time.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"
#include "simulate/simulate_request.hpp"

namespace rockwatch::cli {

struct ForecastEntry {
  double t_s = 0.0;
  sim::ForecastResult result;
  std::optional<core::AlarmLevel> alarm;  // the alarm's level at t_s (with --alarms; none past the listed transitions)
  double energy_ratio_max = 0.0;          // max E/E_barrier over [t − 2 s, t] (the recalibration's feature)
  double x_over_x_inst = 0.0;             // |x|/x_inst at t
  std::optional<double> p_calibrated;     // the recalibrated P (none when the calibration is not applied)
  // With --wall-sensors: the observer's estimates the members started from (its σ_x, σ_ẋ, √r̂, κc, κk at the end of
  // the sample the state belongs to; SPEC §10 "State uncertainty"). None: the open loop's spread and the nominal wall.
  std::optional<sim::ObserverHistoryRow> observer;
  // Started from the fused state with its σ_x, σ_ẋ (a displacement reading fused within the dropout time): the
  // fused state's coefficients. Otherwise the members start at the state itself (σ = 0, the wall as estimated) and
  // the open loop's coefficients apply (SPEC §10 "From the fused state").
  bool fused = false;
};

struct ForecastSeries {
  sim::ForecastSettings settings;
  double every_s = 0.1;
  std::vector<ForecastEntry> entries;
  std::size_t at_rest = 0;  // forecast times skipped because the wall was at rest
  sim::ForecastCalibration calibration;        // the open loop's (an entry not fused), or the given one
  sim::ForecastCalibration calibration_fused;  // a fused entry's: the fused state's own, or the given one
  bool calibration_applied = false;  // given, or the default at its own horizon
  bool fused = false;                // the analysis ran the wall observer (its estimates in the entries)
};

// Needs request.forecast and result.history (keep_history).
ForecastSeries run_forecasts(const SimulateRequest& request, const sim::GroundMotion& motion,
                             const sim::AnalysisResult& result);

nlohmann::ordered_json forecast_json(const ForecastSeries& series, bool with_alarm);
std::string forecast_text(const ForecastSeries& series);

}  // namespace rockwatch::cli
