// What `rockwatch replay` was asked to do, parsed and validated from its command line: the record (the record options
// of `rockwatch simulate`), the rate it is resampled to, the sensor model, the pacing and where the samples go (LCM,
// an LCM log, a CSV of the samples), and with --wall-file the wall under test simulated as a plant.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::cli {

// --wall-file W.json [wall and engine options] [--sensor-* options]: the wall under test as a plant for a
// hardware-in-the-loop rig. It is simulated exactly as `rockwatch simulate --wall-file W.json --sensors-out S.csv`
// with the same record and options would (the double engine, driven by the record as read and scaled: the true
// ground, not the replay's --noise-mps2 … of the accelerometer messages), and its sensor samples are sent as
// wall_sensor_t exactly as `rockwatch replay --wall-sensors S.csv` would send that file.
struct ReplayPlant {
  std::string wall_file_path;
  core::WallParameters wall;                    // the file's, with --b … --g replacing fields
  std::vector<std::string> wall_options_given;  // e.g. {"--b"}, for the report
  sim::AnalysisOptions analysis;                // --r (else the file's r), --model, --kappa, --max-step; with history
  sim::SensorModel sensor_model;                // --sensor-* (simulate's names and defaults)
};

struct ReplayRequest {
  RecordSelection record;             // --record or --suite, --vertical, --units, --dt, ...
  std::optional<double> scale_pga_g;  // peak |ü| = G·g (g = 9.81 m/s²)
  double g_mps2 = 9.81;               // converts records in g and --scale-pga; with --wall-file the wall's g
  double rate_hz = 200.0;             // --rate: the samples sent per second of record time
  double speed = 1.0;                 // --speed: 1 real time, 2 twice as fast, 0 as fast as possible
  bool publish = true;                // over LCM (false: --log without --lcm-url)
  std::string lcm_url;
  std::string channel;  // --lcm-channel, default by message type
  int batch = 0;        // --batch N: ground_accel_batch_t of up to N samples; 0 = ground_accel_t
  SensorModel sensor;
  std::optional<std::string> log_path;          // --log FILE: a standard LCM log of the messages
  std::optional<std::string> samples_out_path;  // --samples-out FILE: the samples as sent, CSV
  std::optional<std::string> wall_sensors_path;  // --wall-sensors FILE: wall_sensor_t alongside the ground stream
  std::optional<ReplayPlant> plant;              // --wall-file: wall_sensor_t of the simulated wall
  std::string wall_sensor_channel = "ROCKWATCH_WALL_SENSOR";  // --wall-sensor-channel
  bool json = false;
};

struct ReplayParse {
  std::optional<ReplayRequest> request;  // empty for --help
  std::string help_text;
};

// Parses `rockwatch replay` arguments (argv[0] is the command name). Throws UsageError naming the option at fault.
ReplayParse parse_replay_arguments(int argc, const char* const* argv);

}  // namespace rockwatch::cli
