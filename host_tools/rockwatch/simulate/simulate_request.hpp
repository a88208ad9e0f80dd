// What `rockwatch simulate` was asked to do, parsed and validated from its command line.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::cli {

// Alarm transitions simulate lists (more are counted, not listed): a wall rocking for minutes can go between QUIET
// and ROCKING thousands of times.
inline constexpr std::size_t kMaxAlarmTransitionsListed = 1000;

struct SimulateRequest {
  RecordSelection record;              // --record or --suite, the vertical, --units, --dt, --gain (g: the wall's)
  std::optional<double> scale_pga_g;   // target peak |ü| in units of g (the --g value)
  std::string wall_name = "paper";     // the base wall the --b … --a-prime options modify
  core::WallParameters wall = core::paper_wall();
  std::vector<std::string> wall_options_given;  // e.g. {"--b", "--h1"}, for the report
  std::optional<std::string> wall_file_path;     // --wall-file: the base wall (and r unless --r) came from it
  sim::AnalysisOptions analysis;       // arithmetic, model, restitution, kappa, max step, t_end, alarm
  bool arith_given = false;            // --arith was given: the JSON says which arithmetic ran
  std::string history_kept_by = "with --out";  // what keeps the history, as the work-size message says it
  std::optional<std::string> out_csv_path;
  bool json = false;
  // --wall-sensors FILE: the wall observer fuses these samples (read when the command runs); its settings are
  // analysis.observer (--observer-*).
  std::optional<std::string> wall_sensors_path;
  // --observer-out FILE: the observer's estimates at the end of every input sample (AnalysisResult::observer_history).
  std::optional<std::string> observer_out_path;
  // --sensors-out FILE: samples of the simulated wall's sensors with this model (--sensor-*).
  std::optional<std::string> sensors_out_path;
  sim::SensorModel sensor_model;
  // --engine-input-out FILE: the engine's configuration and every input it stepped on, for the Cortex-M4 replay
  // (scripts/m4-replay.sh; format: firmware/include/rockwatch/firmware/engine_input_format.hpp).
  std::optional<std::string> engine_input_out_path;
  // --x0 M: a release (snap-back) test: the wall starts at x = x0 with no velocity (analysis.initial_x_m) and is
  // followed until it rests. Without --record/--suite the ground is at rest, sampled every ground_at_rest_dt_s
  // (--dt, default 0.005 s) to --t-end (default 0: free motion only).
  bool ground_at_rest = false;
  double ground_at_rest_dt_s = 0.005;
  // --forecast-members N --forecast-horizon-s H [--forecast-every-s S] [--forecast-seed K]: the ensemble forecast of
  // collapse (SPEC §10) from the simulated state every S seconds while the wall is not at rest (JSON `forecast`).
  std::optional<sim::ForecastSettings> forecast;
  double forecast_every_s = 0.1;
  // --forecast-calibration c0,c1,c2,c3[,c4]: the recalibration's coefficients (SPEC §10 "Calibrated P"); none: the
  // shipped default (sim::default_forecast_calibration), applied when the horizon is the one it was fitted at.
  std::optional<sim::ForecastCalibration> forecast_calibration;
};

// Outcome of reading the command line: either a request to run, or text to print and an exit status
// (--help: the help on stdout, status 0).
struct SimulateParse {
  std::optional<SimulateRequest> request;
  std::string help_text;
};

// Parses `rockwatch simulate` arguments (argv[0] is the command name): the texts converted to SimulateSettings
// (simulate_settings.hpp), which apply_simulate_settings checks, then the command line's own options (record, files,
// sensors, forecast). Throws UsageError with a message that names the option at fault, for CLI11 parse errors as well
// as for invalid values.
SimulateParse parse_simulate_arguments(int argc, const char* const* argv);

}  // namespace rockwatch::cli
