// `rockwatch simulate`: one record (pair) through sim::analyse, the engine every tool shares. This file only wires
// the parts together and maps every failure to a one-line message and exit status 2; the CLI adds no physics.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/history_csv.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/process/output_file.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"
#include "simulate/engine_input_file.hpp"
#include "simulate/simulate_forecast.hpp"
#include "simulate/simulate_report.hpp"
#include "simulate/simulate_request.hpp"
#include "simulate/simulate_settings.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch simulate: error: ", "out of memory (a very long record or --out history?)"};

void check_out_path(const char* option, const std::optional<std::string>& out, const SimulateRequest& q) {
  if (!out) return;
  const std::string& path = *out;
  std::error_code ec;
  if (std::filesystem::equivalent(path, q.record.record_path, ec) ||
      (q.record.vertical_path && std::filesystem::equivalent(path, *q.record.vertical_path, ec))) {
    throw UsageError(std::string(option) + " " + path + " is an input record: choose another file name");
  }
}

void check_out_paths(const SimulateRequest& q) {
  const std::pair<const char*, const std::optional<std::string>*> outputs[] = {
      {"--out", &q.out_csv_path},
      {"--sensors-out", &q.sensors_out_path},
      {"--observer-out", &q.observer_out_path},
      {"--engine-input-out", &q.engine_input_out_path}};
  std::error_code ec;
  const auto same = [&ec](const std::string& a, const std::string& b) {
    return a == b || std::filesystem::equivalent(a, b, ec);
  };
  for (std::size_t i = 0; i < std::size(outputs); ++i) {
    const auto& [name, path] = outputs[i];
    check_out_path(name, *path, q);
    if (!*path) continue;
    for (std::size_t j = 0; j < i; ++j) {
      const auto& [other_name, other_path] = outputs[j];
      if (*other_path && same(**path, **other_path)) {
        throw UsageError(std::string(other_name) + " and " + name + " name the same file: choose two");
      }
    }
    if (q.wall_sensors_path && same(**path, *q.wall_sensors_path)) {
      throw UsageError(std::string(name) + " " + **path + " is the --wall-sensors input: choose another file name");
    }
  }
}

// --x0 without a record: the ground at rest, on a grid of --dt to --t-end (at least two samples).
InputMotion ground_at_rest(const SimulateRequest& q) {
  InputMotion in;
  const double dt_s = q.ground_at_rest_dt_s;
  const double t_end_s = q.analysis.t_end_s ? *q.analysis.t_end_s : 0.0;
  const auto n = static_cast<std::size_t>(std::max(2.0, std::ceil(t_end_s / dt_s - 1e-9) + 1.0));
  in.motion.dt_s = dt_s;
  in.motion.ug_mps2.assign(n, 0.0);
  in.horizontal.path = "(none: ground at rest)";
  in.horizontal.format = "none";
  in.horizontal.units = "m/s2";
  in.horizontal.dt_s = dt_s;
  in.horizontal.samples = n;
  in.horizontal.description = "release test (--x0) on ground at rest";
  return in;
}

int run(const SimulateRequest& q) {
  const InputMotion input = q.ground_at_rest ? ground_at_rest(q) : prepare_input(InputRequest{q.record, q.scale_pga_g, q.wall.g_mps2});
  for (const std::string& note : input.notes) std::cerr << "note: " << note << '\n';
  check_work_size(q, input.motion);
  check_out_paths(q);
  std::vector<core::WallSensorSample> wall_sensors;
  sim::AnalysisOptions options = q.analysis;
  if (q.wall_sensors_path) {
    wall_sensors = read_wall_sensor_samples(*q.wall_sensors_path);
    options.wall_sensors = &wall_sensors;
  }
  PendingOutputFile csv(q.out_csv_path);  // opened now, so a wrong directory is reported before a long run
  PendingOutputFile sensors_csv(q.sensors_out_path, "--sensors-out");
  PendingOutputFile observer_csv(q.observer_out_path, "--observer-out");
  PendingOutputFile engine_input(q.engine_input_out_path, "--engine-input-out");
  std::vector<std::array<double, 2>> engine_inputs;
  if (q.engine_input_out_path) options.engine_inputs_out = &engine_inputs;

  const sim::AnalysisResult result = sim::analyse(q.wall, input.motion, options);
  engine_input.write("the engine input", [&](std::ostream& out) {
    write_engine_input(out, engine_config_of(q, result), engine_inputs, wall_sensors);
  });
  csv.write("the time history", [&result](std::ostream& out) { write_history_csv(out, result.history); });
  observer_csv.write("the observer's estimates",
                     [&result](std::ostream& out) { write_observer_history_csv(out, result.observer_history); });
  if (q.sensors_out_path) {
    const std::vector<core::WallSensorSample> samples =
        sim::synthesize_wall_sensors(q.wall, result, input.motion.dt_s, q.sensor_model);
    sensors_csv.write("the sensor samples", [&](std::ostream& out) {
      write_wall_sensor_csv(out, samples, q.sensor_model.a_noise_mps2.has_value());
    });
  }

  std::optional<ForecastSeries> forecast;
  if (q.forecast) forecast = run_forecasts(q, input.motion, result);

  if (q.json) {
    if (result.free_motion_undecided) {
      std::cerr << "note: free rocking after the record neither settled nor collapsed within "
                << number_text(q.analysis.free_motion_limit_s) << " s; collapse_after_end is false but undecided\n";
    }
    nlohmann::ordered_json j = result_json(q, result);
    if (forecast) j["forecast"] = forecast_json(*forecast, q.analysis.evaluate_alarm);
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << summary_text(q, input, result);
    if (forecast) std::cout << forecast_text(*forecast);
  }
  return finish_stdout(kErrors);
}

}  // namespace

int simulate_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const SimulateParse parsed = parse_simulate_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
