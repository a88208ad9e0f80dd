// `rockwatch replay`: a record (as `rockwatch simulate` reads it), resampled to --rate, through the sensor model,
// sent as LCM messages paced on absolute deadlines (or written to an LCM log), with the lateness measured; with
// --wall-file also the sensors of the wall simulated under the record (the plant). This file wires the parts together
// and maps every failure to a message and an exit status.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/replay_out/lcm_multicast.hpp"
#include "common/process/progress_line.hpp"
#include "common/replay_out/replay_publisher.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "common/process/signal_interrupt.hpp"
#include "replay/replay_report.hpp"
#include "replay/replay_request.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch replay: error: ", "out of memory (a very long record at a high --rate?)"};

// An output file created before the run (so a wrong directory is reported at once) and removed again unless the
// run kept it.
class RunOutput {
 public:
  RunOutput(const char* option, const std::optional<std::string>& path) : option_(option) {
    if (!path) return;
    path_ = *path;
  }
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;
  ~RunOutput() {
    if (!path_.empty() && !keep_) std::remove(path_.c_str());
  }
  const std::string& path() const { return path_; }
  std::string name() const { return std::string(option_) + " " + path_; }
  void keep() { keep_ = true; }

 private:
  const char* option_;
  std::string path_;
  bool keep_ = false;
};

InputMotion read_input(const ReplayRequest& q) {
  return prepare_input(InputRequest{q.record, q.scale_pga_g, q.g_mps2});
}

// Bounds on the plant's work, those of `rockwatch simulate --sensors-out` (which keeps the history too): a typo such
// as --max-step 1e-9 should be an error message, not hours of computing or an exhausted machine.
constexpr double kMaxPlantHistoryRows = 2e7;

void check_plant_work(const ReplayPlant& plant, const sim::GroundMotion& motion) {
  const double dt_s = motion.dt_s;
  const int substeps = core::substeps_per_sample(dt_s, plant.analysis.max_step_s);
  if (substeps == 0) {
    throw UsageError("--max-step " + number_text(plant.analysis.max_step_s) + " s would need more than " +
                     std::to_string(core::kMaxSubsteps) + " sub-steps per record sample (the record's dt is " +
                     number_text(dt_s) + " s): give --max-step >= dt / " + std::to_string(core::kMaxSubsteps));
  }
  const double span_s = motion.duration_s() + plant.analysis.free_motion_limit_s;
  const double worst_steps = span_s / (dt_s / std::fmax(1.0, double(substeps)));
  if (worst_steps > kMaxPlantHistoryRows) {
    throw UsageError("the plant's integration step over the record (plus up to " +
                     number_text(plant.analysis.free_motion_limit_s) + " s of free rocking) means up to " +
                     number_text(std::round(worst_steps)) + " steps, more than the " +
                     number_text(kMaxPlantHistoryRows) + " a run with --wall-file may take: raise --max-step");
  }
  const double rate_hz = plant.sensor_model.rate_hz > 0.0 ? plant.sensor_model.rate_hz : 1.0 / dt_s;
  if (rate_hz * span_s > kMaxPlantHistoryRows) {
    throw UsageError("--sensor-rate-hz " + number_text(rate_hz) + " over the record (plus up to " +
                     number_text(plant.analysis.free_motion_limit_s) + " s of free rocking) means up to " +
                     number_text(std::round(rate_hz * span_s)) + " sensor samples, more than the " +
                     number_text(kMaxPlantHistoryRows) + " a run with --wall-file may make: lower the rate");
  }
}

// The plant: the wall of --wall-file under the record as read and scaled (input.motion, the true ground, before the
// resampling and the ground sensor's model), through sim::analyse and sim::synthesize_wall_sensors exactly as
// `rockwatch simulate --wall-file --sensors-out` runs them, so the samples equal that file's, bit for bit.
PlantRun run_plant(const ReplayPlant& plant, const InputMotion& input) {
  check_plant_work(plant, input.motion);
  PlantRun run;
  run.result = sim::analyse(plant.wall, input.motion, plant.analysis);
  run.sensor_samples = sim::synthesize_wall_sensors(plant.wall, run.result, input.motion.dt_s, plant.sensor_model);
  run.result.history.clear();  // only the samples were needed from it
  run.result.history.shrink_to_fit();
  return run;
}

void check_writable(const RunOutput& out) {
  if (out.path().empty()) return;
  errno = 0;
  std::ofstream file(out.path(), std::ios::out | std::ios::trunc | std::ios::binary);
  if (!file) throw UsageError(out.name() + ": cannot open the file for writing" + system_reason());
}

void write_samples(const RunOutput& out, const ReplayStream& stream, std::size_t count) {
  errno = 0;
  std::ofstream file(out.path(), std::ios::out | std::ios::trunc | std::ios::binary);
  if (file) write_samples_csv(file, stream, count);
  file.close();
  if (file.fail()) throw UsageError(out.name() + ": writing the samples failed" + system_reason());
}

int run(const ReplayRequest& q) {
  const InputMotion input = read_input(q);
  for (const std::string& note : input.notes) std::cerr << "note: " << note << '\n';
  const ReplayStream stream = make_replay_stream(input.motion, q.rate_hz, q.sensor);
  if (stream.resampled) {
    std::cerr << "note: the record (dt " << number_text(stream.source_dt_s) << " s) is resampled to "
              << number_text(q.rate_hz) << " Hz by linear interpolation"
              << (1.0 / stream.source_dt_s > q.rate_hz ? ", without an anti-alias filter" : "") << '\n';
  }

  // The wall's sensors, read (and checked: exit 2 naming file and line) or simulated before anything is opened or
  // sent.
  std::vector<core::WallSensorSample> wall_sensors;
  if (q.wall_sensors_path) wall_sensors = read_wall_sensor_samples(*q.wall_sensors_path);
  std::optional<PlantRun> plant;
  if (q.plant) {
    plant = run_plant(*q.plant, input);
    if (plant->result.free_motion_undecided) {
      std::cerr << "note: the plant's free rocking after the record neither settled nor collapsed within "
                << number_text(q.plant->analysis.free_motion_limit_s)
                << " s; collapse_after_end is false but undecided\n";
    }
  }

  RunOutput samples_out("--samples-out", q.samples_out_path);
  RunOutput log_out("--log", q.log_path);
  check_writable(samples_out);
  std::unique_ptr<lcm::LogFile> log;
  if (q.log_path) {
    errno = 0;
    log = std::make_unique<lcm::LogFile>(*q.log_path, "w");
    if (!log->good()) throw UsageError(log_out.name() + ": cannot create the LCM log" + system_reason());
  }
  std::unique_ptr<lcm::LCM> lcm;
  if (q.publish) {
    MulticastProbe failed;
    lcm = open_lcm(q.lcm_url, failed.problem);
    if (!lcm) {
      if (q.lcm_url.rfind("udpm://", 0) != 0) throw UsageError("--lcm-url: " + failed.problem);
      std::cerr << kErrors.prefix << "--lcm-url: " << multicast_help(q.lcm_url, failed);
      return kExitUsageError;
    }
  }

  PublishPlan plan;
  plan.channel = q.channel;
  plan.batch = q.batch;
  plan.speed = q.speed;
  plan.log_name = log_out.name();
  if (q.wall_sensors_path) {
    plan.wall_sensors = &wall_sensors;
    plan.wall_sensor_channel = q.wall_sensor_channel;
  } else if (plant) {
    plan.wall_sensors = &plant->sensor_samples;
    plan.wall_sensor_channel = q.wall_sensor_channel;
  }
  ReplayOutcome outcome;
  {
    const SignalInterrupt interrupt;  // Ctrl-C: stop between messages, report what was sent
    ProgressLine progress(std::cerr, stderr_is_terminal() && !q.json);
    const std::size_t total = stream.size();
    outcome = publish_stream(stream, plan, lcm.get(), log.get(), interrupt.flag(),
                             [&progress, total](std::size_t done, double elapsed_s) {
                               progress.update("replay " + progress_bar_text(done, total, elapsed_s));
                             });
    progress.clear();
  }
  log.reset();  // closes the log file
  if (outcome.aborted) {
    MulticastProbe probe;
    probe.problem = "the first message could not be sent on " + q.lcm_url + " (" + outcome.first_failure + ")";
    std::cerr << kErrors.prefix << multicast_help(q.lcm_url, probe);
    return kExitUsageError;
  }
  log_out.keep();
  if (q.samples_out_path) {
    write_samples(samples_out, stream, outcome.samples_done);
    samples_out.keep();
  }

  const ReplayReport report{q, input, stream, outcome, plant ? &*plant : nullptr};
  if (q.json) {
    std::cout << replay_summary_json(report).dump(2) << '\n';
  } else {
    std::cout << replay_summary_text(report);
  }
  const int status = finish_stdout(kErrors);
  if (status != kExitOk) return status;
  if (outcome.interrupted) return kExitInterrupted;
  if (outcome.publish_failures > 0) {
    return fail(kErrors,
                std::to_string(outcome.publish_failures) + " of " + std::to_string(outcome.messages + outcome.wall_sensor_samples_sent) +
                    " messages could not be published (" + outcome.first_failure + ")",
                kExitInternalError);
  }
  return kExitOk;
}

}  // namespace

int replay_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const ReplayParse parsed = parse_replay_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
