#include "replay/replay_request.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/replay_out/lcm_multicast.hpp"
#include "common/process/output_file.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/sensor_model_options.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace replay_request {

constexpr double kMinReplayRateHz = 1.0;  // below: no ground-acceleration sensor samples that slowly
constexpr double kMinReplaySpeed = 0.01;  // --speed other than 0: 100 times slower than real time

struct RawOptions {
  RecordOptionTexts record;
  std::string scale_pga, rate, speed, lcm_url, channel, batch;
  std::string noise, seed, bias, quantum, dropout, log, samples_out;
  std::string wall_sensors, wall_sensor_channel;
  // The plant (--wall-file): simulate's wall, engine and sensor-model options.
  WallOptionTexts wall;
  std::string r = "exp", model = "linear", kappa, max_step;
  SensorModelOptionTexts plant_sensors;
  bool json = false;
};

// The options that set the plant besides --wall-file and the --sensor-* ones: they need --wall-file.
const char* const kPlantOptionNames[] = {"--b",     "--h1", "--h2", "--rho",   "--fp",    "--a",
                                         "--a-prime", "--g", "--r", "--model", "--kappa", "--max-step"};

const char* const kFooter =
    "The record is read as `rockwatch simulate` reads it (same options, same messages), scaled by --scale-pga, then\n"
    "resampled to --rate by linear interpolation between the record's samples: sample i is the record at\n"
    "t = i/rate (i = 0 .. floor(duration * rate)); where 1/rate is the record's own step the samples are copied bit\n"
    "for bit. There is no anti-alias filter: to go below the record's rate, low-pass filter the record first.\n"
    "\n"
    "Messages (firmware/lcmtypes): ground_accel_t per sample on ROCKWATCH_ACCEL, or with --batch N\n"
    "ground_accel_batch_t of up to N consecutive samples on ROCKWATCH_ACCEL_BATCH (--lcm-channel renames either).\n"
    "seq counts samples from 0; utime = start + i/rate [us], start being the host clock (CLOCK_REALTIME) when the\n"
    "replay begins; u'' and v'' in m/s2 (v'' = 0 without a vertical record).\n"
    "\n"
    "Pacing: sample i is due at start + (i/rate)/speed on CLOCK_MONOTONIC, waited for with clock_nanosleep\n"
    "(TIMER_ABSTIME), so delays never accumulate; a batch is due with its last sample. --speed 0 sends as fast as\n"
    "possible. Lateness = the time the publish call returned - the deadline; the summary gives p50, p99, max and a\n"
    "histogram.\n"
    "\n"
    "Sensor model, in this order: bias, Gaussian noise (--seed), quantisation to multiples of --quantum-mps2, then\n"
    "--dropout: the sample is not sent, but seq still advances, so the monitor sees a gap. u'' always; v'' only when\n"
    "there is a vertical record.\n"
    "\n"
    "--log FILE writes a standard LCM log (lcm-logplayer plays it) with the messages, each event stamped with its\n"
    "sample time (a batch: its last sample's). --log alone writes the log instead of publishing, at once, without\n"
    "pacing; with --lcm-url too, the replay publishes in real time and writes the log.\n"
    "--samples-out FILE writes the samples as sent (t_s, ug_mps2, vg_mps2; one row per seq; a dropped sample's row\n"
    "holds the previous values, as the monitor bridges a short gap, and ends in '# dropped'), a plain record that\n"
    "`rockwatch simulate --arith fixed --record FILE` reads with dt = 1/rate.\n"
    "\n"
    "The wall as a plant (--wall-file W.json), for a hardware-in-the-loop rig: the wall under test is simulated\n"
    "under the record as read and scaled (--scale-pga, --vertical; the true ground: not the accelerometer messages,\n"
    "whose --noise-mps2, --bias-mps2, --quantum-mps2 and --dropout model the ground sensor, nor the --rate\n"
    "resampling), exactly as `rockwatch simulate --wall-file W.json` with the same record options runs it (the double\n"
    "engine; --b ... --g, --r, --model, --kappa, --max-step as in simulate; g is the wall's, also for records in g\n"
    "and --scale-pga). Its sensors (--sensor-* options: the names and defaults of simulate's) are sent as\n"
    "wall_sensor_t beside the ground messages, exactly as `simulate --wall-file W.json --sensors-out S.csv` followed\n"
    "by `replay --wall-sensors S.csv` sends them: each sample just before the ground message that reaches its time;\n"
    "none after the record's last sample (the free rocking after it and its verdict are in the summary only).\n"
    "The plant does not react to anything sent, so it is computed before the first message.\n"
    "\n"
    "Exit status: 0 the record was sent, 2 invalid options or input or LCM unusable (multicast not routed: the\n"
    "message says what to do), 1 some messages could not be sent or an internal error, 130 interrupted (Ctrl-C).\n"
    "\n"
    "Examples:\n"
    "  rockwatch replay --suite sim/suites/npr9998-2015 --set 3 --component Y --scale-pga 0.25\n"
    "  rockwatch replay --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2 --rate 1000 --batch 10 --noise-mps2 0.02\n"
    "  rockwatch replay --record motion.csv --units g --log motion.lcmlog --samples-out sent.csv\n";

void add_options(CLI::App& app, RawOptions& raw) {
  add_record_options(app, raw.record, VerticalOptions::allowed);
  app.add_option("--scale-pga", raw.scale_pga,
                 "Scale the horizontal record to peak |u''| = G*g (g = 9.81 m/s2); the vertical by the same factor")
      ->type_name("G");
  app.add_option("--rate", raw.rate, "Samples per second sent, resampled by linear interpolation (default 200)")
      ->type_name("HZ");
  app.add_option("--speed", raw.speed, "Pacing: 1 real time (default), 2 twice as fast, 0 as fast as possible")
      ->type_name("X");
  app.add_option("--lcm-url", raw.lcm_url, std::string("LCM URL (default ") + kDefaultLcmUrl + ")")->type_name("URL");
  app.add_option("--lcm-channel", raw.channel, "Channel (default ROCKWATCH_ACCEL, with --batch ROCKWATCH_ACCEL_BATCH)")
      ->type_name("NAME");
  app.add_option("--batch", raw.batch, "Send ground_accel_batch_t messages of up to N samples (1-50), for high rates")
      ->type_name("N");
  app.add_option("--noise-mps2", raw.noise, "Sensor noise: Gaussian, standard deviation SD >= 0 [m/s2]")
      ->type_name("SD");
  app.add_option("--seed", raw.seed, "Seed of the noise and dropout draws, 0 to 2^64-1 (default 1)")->type_name("S");
  app.add_option("--bias-mps2", raw.bias, "Sensor bias added to every sample [m/s2]")->type_name("B");
  app.add_option("--quantum-mps2", raw.quantum, "Sensor resolution: values rounded to multiples of Q > 0 [m/s2]")
      ->type_name("Q");
  app.add_option("--dropout", raw.dropout, "Probability in [0, 1) that a sample is not sent (seq still advances)")
      ->type_name("P");
  app.add_option("--log", raw.log, "Write the messages to a standard LCM log (alone: instead of publishing)")
      ->type_name("FILE");
  app.add_option("--samples-out", raw.samples_out, "Write the samples as sent: CSV t_s, ug_mps2, vg_mps2")
      ->type_name("FILE.csv");
  app.add_option("--wall-sensors", raw.wall_sensors,
                 "Also send the wall's sensors (wall_sensor_t): CSV t_s,x_mid_m[,a_mid_mps2] on the record's clock, "
                 "as `rockwatch simulate --sensors-out` writes it")
      ->type_name("FILE");
  app.add_option("--wall-sensor-channel", raw.wall_sensor_channel,
                 "Channel of the wall's sensors (default ROCKWATCH_WALL_SENSOR)")
      ->type_name("NAME");
  // The plant: simulate's wall and engine options, whose help says they need --wall-file.
  add_wall_options(app, raw.wall);
  add_restitution_option(app, raw.r);
  add_model_option(app, raw.model);
  add_kappa_option(app, raw.kappa);
  add_max_step_option(app, raw.max_step);
  app.get_option("--wall-file")
      ->description(
          "Simulate the wall of a wall file (JSON; rockwatch identify --wall-out) under the record, with its r unless "
          "--r, and send its sensors as wall_sensor_t: the wall under test as a plant");
  for (const char* name : kPlantOptionNames) {
    CLI::Option* option = app.get_option(name);
    option->description("With --wall-file: " + option->get_description());
  }
  // The plant is a wall file's wall: --wall (paper, the only built-in one) is refused with a message, not listed.
  app.get_option("--wall")->group("");
  add_sensor_model_options(app, raw.plant_sensors, "With --wall-file, as simulate --sensors-out: ");
  app.add_flag("--json", raw.json, "Print the summary as one JSON object on stdout");
  app.footer(kFooter);
}

std::string file_option(const char* option, const std::string& text) {
  if (text.empty()) throw UsageError(std::string(option) + " needs a file name");
  check_output_file(option, text);
  return text;
}

bool same_file(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

void check_output_paths(const ReplayRequest& q) {
  const std::pair<const char*, const std::optional<std::string>*> outputs[] = {{"--log", &q.log_path},
                                                                               {"--samples-out", &q.samples_out_path}};
  for (const auto& [option, path] : outputs) {
    if (!*path) continue;
    if (same_file(**path, q.record.record_path) ||
        (q.record.vertical_path && same_file(**path, *q.record.vertical_path))) {
      throw UsageError(std::string(option) + " " + **path + " is an input record: choose another file name");
    }
  }
  if (q.log_path && q.samples_out_path && same_file(*q.log_path, *q.samples_out_path)) {
    throw UsageError("--log and --samples-out name the same file " + *q.log_path + ": give two file names");
  }
}

void parse_sensor(const CLI::App& app, const RawOptions& raw, SensorModel& s) {
  if (given(app, "--noise-mps2")) {
    s.noise_sd_mps2 = parse_finite_number("--noise-mps2", raw.noise);
    if (!(s.noise_sd_mps2 >= 0.0)) {
      throw UsageError("--noise-mps2 must be >= 0 m/s2, a standard deviation (got " + number_text(s.noise_sd_mps2) +
                       ")");
    }
  }
  if (given(app, "--seed")) {
    const std::optional<std::uint64_t> seed = whole_number(raw.seed, 0, UINT64_MAX);
    if (!seed) throw UsageError("--seed must be a whole number from 0 to 2^64-1 (got " + options::quoted(raw.seed) + ")");
    s.seed = *seed;
  }
  if (given(app, "--bias-mps2")) s.bias_mps2 = parse_finite_number("--bias-mps2", raw.bias);
  if (given(app, "--quantum-mps2")) s.quantum_mps2 = parse_positive_number("--quantum-mps2", raw.quantum, " m/s2");
  if (given(app, "--dropout")) {
    s.dropout = parse_finite_number("--dropout", raw.dropout);
    if (!(s.dropout >= 0.0 && s.dropout < 1.0)) {
      throw UsageError("--dropout must be a probability in [0, 1) (got " + number_text(s.dropout) + ")");
    }
  }
}

// --wall-file and the options that shape the plant, checked as `rockwatch simulate` checks them; nothing without
// --wall-file (where any of them is refused: it would be silently ignored).
std::optional<ReplayPlant> parse_plant(const CLI::App& app, const RawOptions& raw) {
  if (!given(app, "--wall-file")) {
    if (given(app, "--wall")) throw UsageError("--wall sets the wall simulated as a plant: give --wall-file too");
    for (const char* name : kPlantOptionNames) {
      if (given(app, name)) {
        throw UsageError(std::string(name) + " sets the wall simulated as a plant: give --wall-file too");
      }
    }
    if (const char* name = first_sensor_model_option_given(app)) {
      throw UsageError(std::string(name) + " sets the sensors of the wall simulated as a plant: give --wall-file too");
    }
    return std::nullopt;
  }
  if (given(app, "--wall-sensors")) {
    throw UsageError(
        "--wall-file and --wall-sensors both give the wall's sensors (the simulated plant's, or a file's): give one");
  }
  const WallChoice wall = parse_wall_options(app, raw.wall);  // names the file and field of a bad wall file
  ReplayPlant plant;
  plant.wall_file_path = *wall.wall_file_path;
  plant.wall = wall.wall;
  plant.wall_options_given = wall.options_given;
  plant.analysis.restitution = restitution_of(app, wall, raw.r);
  plant.analysis.model = parse_model("--model", raw.model);
  check_computable(plant.wall, plant.analysis);
  if (given(app, "--kappa")) plant.analysis.kappa = parse_kappa("--kappa", raw.kappa);
  if (given(app, "--max-step")) plant.analysis.max_step_s = parse_positive_number("--max-step", raw.max_step, " s");
  plant.analysis.keep_history = true;  // the sensor samples are taken from the history
  plant.sensor_model = parse_sensor_model_options(app, raw.plant_sensors);
  return plant;
}

}  // namespace replay_request
}  // namespace

ReplayParse parse_replay_arguments(int argc, const char* const* argv) {
  using namespace replay_request;
  CLI::App app{
      "Replays a ground-motion record as the monitor's sensor would send it: LCM messages paced in real time "
      "(or faster), with an optional sensor model, an LCM log and a CSV of the samples sent.",
      "rockwatch replay"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "replay")) {
    return ReplayParse{std::nullopt, std::move(*help)};
  }

  ReplayRequest q;
  q.plant = parse_plant(app, raw);
  // The plant's g reads the record, as simulate's wall's does, so both routes run the same ground.
  if (q.plant) q.g_mps2 = q.plant->wall.g_mps2;
  q.record = parse_record_selection(app, raw.record, q.g_mps2);
  if (given(app, "--scale-pga"))
    q.scale_pga_g = parse_positive_number("--scale-pga", raw.scale_pga, " (a multiple of g)");
  if (given(app, "--rate")) {
    q.rate_hz = parse_positive_number("--rate", raw.rate, " Hz");
    if (q.rate_hz < kMinReplayRateHz) {
      throw UsageError("--rate must be at least " + number_text(kMinReplayRateHz) +
                       " Hz: a ground-acceleration sensor samples far faster (got " + number_text(q.rate_hz) + ")");
    }
    if (q.rate_hz > kMaxReplayRateHz) {
      throw UsageError("--rate must be at most " + number_text(kMaxReplayRateHz) + " Hz, the monitor's limit (got " +
                       number_text(q.rate_hz) + ")");
    }
  }
  if (given(app, "--speed")) {
    q.speed = parse_finite_number("--speed", raw.speed);
    if (!(q.speed >= 0.0)) {
      throw UsageError("--speed must be >= 0: 1 real time, 2 twice as fast, 0 as fast as possible (got " +
                       number_text(q.speed) + ")");
    }
    // A replay lasts the record's duration / speed: below 1/100 of real time a 40 s record takes over an hour, so a
    // smaller value is taken for a typo rather than left to run for days.
    if (q.speed != 0.0 && q.speed < kMinReplaySpeed) {
      throw UsageError("--speed must be 0 (as fast as possible) or at least " + number_text(kMinReplaySpeed) +
                       " (100 times slower than real time; got " + number_text(q.speed) + ")");
    }
  }
  if (given(app, "--batch")) {
    const std::optional<std::uint64_t> n = whole_number(raw.batch, 1, kMaxBatchSamples);
    if (!n) {
      throw UsageError("--batch must be a whole number of samples from 1 to " + std::to_string(kMaxBatchSamples) +
                       " (ground_accel_batch_t holds at most " + std::to_string(kMaxBatchSamples) + "; got " +
                       options::quoted(raw.batch) + ")");
    }
    q.batch = static_cast<int>(*n);
    if (!whole_period_us(q.rate_hz)) {
      throw UsageError(
          "--batch needs a --rate whose sample period is a whole number of microseconds "
          "(ground_accel_batch_t carries sample_period_us): " +
          number_text(q.rate_hz) + " Hz gives " + number_text(1e6 / q.rate_hz) +
          " us; use e.g. 200, 250, 500, 1000 or 2000 Hz");
    }
  }
  q.channel = q.batch > 0 ? kAccelBatchChannel : kAccelChannel;
  if (given(app, "--lcm-channel")) {
    if (raw.channel.empty()) throw UsageError("--lcm-channel needs a channel name");
    if (raw.channel.size() > 63) {
      throw UsageError("--lcm-channel " + options::quoted(raw.channel) + " is longer than 63 characters, LCM's limit");
    }
    q.channel = raw.channel;
  }
  q.lcm_url = kDefaultLcmUrl;
  if (given(app, "--lcm-url")) {
    if (raw.lcm_url.empty()) throw UsageError("--lcm-url needs a URL, e.g. " + std::string(kDefaultLcmUrl));
    q.lcm_url = raw.lcm_url;
  }
  parse_sensor(app, raw, q.sensor);
  if (given(app, "--wall-sensors")) {
    if (raw.wall_sensors.empty()) throw UsageError("--wall-sensors needs a file name");
    q.wall_sensors_path = raw.wall_sensors;
  }
  if (given(app, "--wall-sensor-channel")) {
    if (!q.wall_sensors_path && !q.plant) {
      throw UsageError("--wall-sensor-channel needs --wall-sensors or --wall-file");
    }
    if (raw.wall_sensor_channel.empty() || raw.wall_sensor_channel.size() > 63) {
      throw UsageError("--wall-sensor-channel needs a channel name of 1 to 63 characters (got " +
                       options::quoted(raw.wall_sensor_channel) + ")");
    }
    if (raw.wall_sensor_channel == q.channel) {
      throw UsageError("--wall-sensor-channel " + options::quoted(raw.wall_sensor_channel) +
                       " is the ground channel: give the wall's sensors their own");
    }
    q.wall_sensor_channel = raw.wall_sensor_channel;
  }
  if (given(app, "--log")) q.log_path = file_option("--log", raw.log);
  if (given(app, "--samples-out")) q.samples_out_path = file_option("--samples-out", raw.samples_out);
  check_output_paths(q);
  // --log alone: the log instead of the network. With --lcm-url as well: both.
  q.publish = !q.log_path || given(app, "--lcm-url");
  if (!q.publish && given(app, "--speed")) {
    throw UsageError(
        "--speed paces publishing, but --log without --lcm-url only writes the log (at once, stamped "
        "with the sample times): drop --speed, or add --lcm-url to publish as well");
  }
  q.json = raw.json;
  return ReplayParse{q, {}};
}

}  // namespace rockwatch::cli
