// What `rockwatch replay` prints when it is done: a few lines for people, or one JSON object (--json).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "common/records_in/input_motion.hpp"
#include "common/replay_out/replay_publisher.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "replay/replay_request.hpp"

namespace rockwatch::cli {

struct ReplayReport {
  const ReplayRequest& request;
  const InputMotion& input;
  const ReplayStream& stream;
  const ReplayOutcome& outcome;
};

std::string replay_summary_text(const ReplayReport& r);

// Keys: record {path, format, dt_s, samples, duration_s}, vertical (path or "third column" or null), the selection
// keys of simulate (suite, component, channel, ...), scale_factor, pga_mps2, rate_hz, resampled, samples,
// samples_done, samples_sent, samples_dropped, messages, message_type, channel, lcm_url (null when only logging),
// batch (null without --batch), speed, paced, start_utime, elapsed_s, sensor {noise_sd_mps2, seed, bias_mps2,
// quantum_mps2, dropout}, log (null or {path, events}), samples_out (null or path), lateness (null unless paced:
// count, p50_us, p99_us, max_us, mean_us, histogram [{from_us, to_us, count}]), publish_failures, interrupted.
nlohmann::ordered_json replay_summary_json(const ReplayReport& r);

// "ground_accel_t" or "ground_accel_batch_t".
const char* message_type_name(int batch);

}  // namespace rockwatch::cli
