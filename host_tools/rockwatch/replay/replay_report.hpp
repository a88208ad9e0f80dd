// What `rockwatch replay` prints when it is done: a few lines for people, or one JSON object (--json).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/records_in/input_motion.hpp"
#include "common/replay_out/replay_publisher.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "replay/replay_request.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

// The plant of --wall-file as run: the engine's verdict and the sensor samples it made (the history is not kept).
struct PlantRun {
  sim::AnalysisResult result;
  std::vector<core::WallSensorSample> sensor_samples;
};

struct ReplayReport {
  const ReplayRequest& request;
  const InputMotion& input;
  const ReplayStream& stream;
  const ReplayOutcome& outcome;
  const PlantRun* plant = nullptr;  // with --wall-file
};

std::string replay_summary_text(const ReplayReport& r);

// Keys: record {path, format, dt_s, samples, duration_s}, vertical (path or "third column" or null), the selection
// keys of simulate (suite, component, channel, ...), scale_factor, pga_mps2, rate_hz, resampled, samples,
// samples_done, samples_sent, samples_dropped, messages, message_type, channel, lcm_url (null when only logging),
// batch (null without --batch), speed, paced, start_utime, elapsed_s, sensor {noise_sd_mps2, seed, bias_mps2,
// quantum_mps2, dropout}, log (null or {path, events}), samples_out (null or path), lateness (null unless paced:
// count, p50_us, p99_us, max_us, mean_us, histogram [{from_us, to_us, count}]), publish_failures, interrupted;
// with --wall-sensors wall_sensors {file, channel, samples_sent}; with --wall-file plant {wall_file, wall_options,
// r, model, kappa, collapsed, collapse_after_end, t_collapse_s, t_exceed_s, max_abs_x_m, t_max_abs_x_s, x_inst_m,
// n_impacts, t_final_s, sensor {x_noise_m, x_bias_m, x_quantum_m, rate_hz, a_noise_mps2, dropouts, seed},
// sensor_samples, sensor_samples_sent, channel}: the engine's numbers, as `simulate --json` gives them.
nlohmann::ordered_json replay_summary_json(const ReplayReport& r);

// "ground_accel_t" or "ground_accel_batch_t".
const char* message_type_name(int batch);

}  // namespace rockwatch::cli
