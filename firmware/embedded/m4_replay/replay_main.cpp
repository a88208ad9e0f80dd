// The replay on the Cortex-M4: command line "IMAGE INPUT OUTPUT [profile SAMPLE]" (QEMU: -kernel IMAGE -append
// "INPUT OUTPUT ..."); with "profile SAMPLE" the step of that sample is also profiled (profiler.hpp).
// Reads the engine configuration from INPUT (rockwatch/firmware/engine_input_format.hpp), initialises
// firmware::WallEngine with it on the target (init in double: newlib's libm and libgcc's soft double), then replays
// every input sample as the host's `rockwatch simulate --arith fixed` does: sample 0 starts the engine (start()),
// each later sample is one step() through the monitor's seam (double → Q7.56, the chain, the published sample back
// in double). A second engine runs the same samples through process_wall() with the inputs converted beforehand, so
// that the engine's own work is measured apart from the seam's conversions; both must agree on the level.
// With the observer (`simulate --wall-sensors`: the file's observer keys and sensor section), each step is step_at()
// (process_wall_at() for the second engine) at the sample's end time, after pushing the sensor samples due by then
// into both engines, as the analysis does; the push is outside the measured window (the monitor does it on arrival).
//
// OUTPUT is text, one record per line (scripts/m4-replay.sh parses it):
//   rockwatch-m4-replay 1
//   overhead <min> <max>                 ticks of an empty measured call (kOverheadRuns of them)
//   start <ticks> <level>                sample 0: start() (the engine at rest)
//   s <ticks_step> <ticks_engine> <level> <x> <xd>   samples 1 …: step() through the seam, process_wall() alone, the
//                                        level after it, and the published x_m, xd_mps (EngineSample)
//   profile <interval_ticks> <n> <dropped>   with "profile SAMPLE": the profiler's settings and addresses recorded,
//   p <address>                          then one line per recorded address (hexadecimal)
//   end <samples> <stack_bytes>          the number of samples and the deepest stack use [bytes]
// ticks are of the instruction clock (instruction_clock.hpp); level is core::AlarmLevel as a number; x and xd are
// the bits of the doubles in hexadecimal (16 digits), so that the host compares the trajectory exactly.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "instruction_clock.hpp"
#include "profiler.hpp"
#include "replay.hpp"
#include "rockwatch/firmware/engine_input_format.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "semihosting.hpp"

namespace rockwatch::m4 {

namespace {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;

constexpr int kOverheadRuns = 64;
constexpr std::uint32_t kProfileIntervalTicks = 2500;  // 97.66 instructions at -icount shift=10: no loop aliases it

// Buffered reads of the input file.
class InputFile {
 public:
  void attach(std::int32_t handle) { handle_ = handle; }
  // Exactly `size` bytes, or false (end of file or error).
  bool read(void* data, std::size_t size) {
    auto* out = static_cast<unsigned char*>(data);
    while (size > 0) {
      if (pos_ == end_) {
        const std::int32_t n = host_read(handle_, buffer_, sizeof buffer_);
        if (n <= 0) return false;
        pos_ = 0;
        end_ = static_cast<std::size_t>(n);
      }
      const std::size_t take = size < end_ - pos_ ? size : end_ - pos_;
      std::memcpy(out, buffer_ + pos_, take);
      out += take;
      pos_ += take;
      size -= take;
    }
    return true;
  }
  bool read_u64(std::uint64_t& v) { return read(&v, sizeof v); }
  bool read_double(double& v) { return read(&v, sizeof v); }
  // Reads and drops `size` bytes.
  bool skip(std::uint64_t size) {
    unsigned char scratch[64];
    while (size > 0) {
      const std::size_t take = size < sizeof scratch ? static_cast<std::size_t>(size) : sizeof scratch;
      if (!read(scratch, take)) return false;
      size -= take;
    }
    return true;
  }

 private:
  std::int32_t handle_ = -1;
  unsigned char buffer_[4096];
  std::size_t pos_ = 0, end_ = 0;
};

// Buffered text output.
class OutputFile {
 public:
  void attach(std::int32_t handle) { handle_ = handle; }
  void text(const char* s) {
    while (*s != '\0') put(*s++);
  }
  void hex(std::uint64_t v) {
    for (int shift = 60; shift >= 0; shift -= 4) put("0123456789abcdef"[(v >> shift) & 0xFu]);
  }
  void bits(double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    hex(b);
  }
  void number(std::uint64_t v) {
    char digits[20];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    while (n > 0) put(digits[--n]);
  }
  bool flush() {
    const bool ok = ok_ && (used_ == 0 || host_write(handle_, buffer_, used_));
    used_ = 0;
    ok_ = ok;
    return ok;
  }

 private:
  void put(char c) {
    if (used_ == sizeof buffer_) flush();
    buffer_[used_++] = c;
  }
  std::int32_t handle_ = -1;
  char buffer_[4096];
  std::size_t used_ = 0;
  bool ok_ = true;
};

// Static storage: no heap, no large stack frames (the stack measured is the engine's and the replay loop's).
InputFile g_in;
InputFile g_sensors;  // a second reader of the input file, at its sensor section
OutputFile g_out;
firmware::WallEngine g_seam;    // through step(): what the monitor loop calls
firmware::WallEngine g_direct;  // through process_wall(): the engine alone
char g_command_line[512];

// process_wall()'s result of each input sample that step() has not finished yet (carry-over), oldest first.
struct DirectResult {
  core::AlarmLevel level;
  double x_m, xd_mps;
};
struct WaitingResults {
  static constexpr int kCapacity = core::StepperAlarmChain<core::FixedRockingStepper>::kMaxPendingSamples + 2;
  DirectResult ring[kCapacity];
  int head = 0, count = 0;
  bool push(const DirectResult& r) {
    if (count == kCapacity) return false;
    ring[(head + count) % kCapacity] = r;
    ++count;
    return true;
  }
  // The oldest is the finished sample e (level and the bits of x and ẋ), and is removed.
  bool pop_equals(const firmware::EngineSample& e) {
    if (count == 0) return false;
    const DirectResult& r = ring[head];
    head = (head + 1) % kCapacity;
    --count;
    return r.level == e.alarm.level && same_bits(r.x_m, e.x_m) && same_bits(r.xd_mps, e.xd_mps);
  }
  static bool same_bits(double a, double b) { return __builtin_memcmp(&a, &b, sizeof a) == 0; }
};
WaitingResults g_waiting;
std::uint64_t g_first_shed_call = 0;  // the input sample at whose call the engine first shed (0: never)

// The next finished sample against process_wall()'s of the same input sample, at input sample k's call: true when
// they are the same bits, or when the engine has shed since (the trajectories part by design).
bool finished_as_direct(const firmware::EngineSample& e, std::uint64_t k) {
  if (e.work_shed && g_first_shed_call == 0) g_first_shed_call = k;
  const bool same = g_waiting.pop_equals(e);
  return same || g_first_shed_call != 0;
}

// The measured calls, out of line and opaque to the optimiser, so that exactly the call is between the clock reads.
[[gnu::noipa]] void measured_nothing(firmware::WallEngine&, double, double) {}
[[gnu::noipa]] firmware::EngineSample measured_step(firmware::WallEngine& e, double ug, double vg) {
  return e.step(ug, vg);  // into the caller's object (guaranteed copy elision)
}
[[gnu::noipa]] core::AlarmLevel measured_process(firmware::WallEngine& e, core::AccelQ7_56 ug, core::AccelQ7_56 vg) {
  return e.process_wall(ug, vg).alarm.level;
}
[[gnu::noipa]] firmware::EngineSample measured_step_at(firmware::WallEngine& e, double ug, double vg, std::int64_t t_us,
                                                       std::int64_t step_us) {
  return e.step_at(ug, vg, t_us, step_us);
}
[[gnu::noipa]] core::AlarmLevel measured_process_at(firmware::WallEngine& e, core::AccelQ7_56 ug, core::AccelQ7_56 vg,
                                                    std::int64_t t_us, std::int64_t step_us) {
  return e.process_wall_at(ug, vg, t_us, step_us).alarm.level;
}

// The wall-sensor samples of the input file's sensor section, one at a time, in order.
class SensorStream {
 public:
  // Positions `in` (a fresh reader of the whole file) at the sensor section: past the magic, the configuration and
  // the samples. False when the file is shorter than that.
  bool open(InputFile& in, std::uint64_t n_config, std::uint64_t n_samples) {
    in_ = &in;
    std::uint64_t n = 0;
    if (!in.skip(sizeof firmware::kEngineInputMagic + 8 + 16 * n_config) || !in.read_u64(n) || n != n_samples ||
        !in.skip(16 * n_samples) || !in.read_u64(left_)) {
      return false;
    }
    return advance();
  }
  bool has_next() const { return have_; }
  const core::WallSensorSample& next() const { return next_; }
  // Reads the following sample; false only for a truncated section (at the end: true, and has_next() false).
  bool advance() {
    have_ = false;
    if (left_ == 0) return true;
    std::uint64_t utime = 0, valid = 0, status = 0;
    double x = 0.0, a = 0.0;
    if (!in_->read_u64(utime) || !in_->read_double(x) || !in_->read_double(a) || !in_->read_u64(valid) ||
        !in_->read_u64(status)) {
      return false;
    }
    --left_;
    next_ = core::WallSensorSample{};
    next_.utime_us = static_cast<std::int64_t>(utime);
    next_.x_mid_m = x;
    next_.a_mid_mps2 = a;
    next_.x_valid = (valid & firmware::kEngineInputSensorValidX) != 0;
    next_.a_valid = (valid & firmware::kEngineInputSensorValidA) != 0;
    next_.sensor_status = static_cast<std::int32_t>(static_cast<std::int64_t>(status));
    have_ = true;
    return true;
  }

 private:
  InputFile* in_ = nullptr;
  std::uint64_t left_ = 0;
  core::WallSensorSample next_{};
  bool have_ = false;
};
SensorStream g_sensor_stream;

std::uint32_t fail(std::uint32_t status, const char* what) {
  host_print("m4-replay image: ");
  host_print(what);
  host_print("\n");
  return status;
}

// The two file names after the image's own name, and the sample to profile after "profile" (none: UINT64_MAX);
// false unless the words are exactly those.
bool split_command_line(char* line, const char*& input, const char*& output, std::uint64_t& profile_sample) {
  const char* words[6] = {};
  int n = 0;
  for (char* p = line; *p != '\0';) {
    while (*p == ' ') *p++ = '\0';
    if (*p == '\0') break;
    if (n == 6) return false;
    words[n++] = p;
    while (*p != '\0' && *p != ' ') ++p;
  }
  profile_sample = UINT64_MAX;
  if (n == 5) {
    if (std::strcmp(words[3], "profile") != 0 || *words[4] == '\0') return false;
    std::uint64_t v = 0;
    for (const char* c = words[4]; *c != '\0'; ++c) {
      if (*c < '0' || *c > '9' || v > UINT64_MAX / 20) return false;
      v = v * 10 + static_cast<std::uint64_t>(*c - '0');
    }
    profile_sample = v;
  } else if (n != 3) {
    return false;
  }
  input = words[1];
  output = words[2];
  return true;
}

}  // namespace

std::uint32_t run_replay(std::uint32_t (*stack_used_bytes)()) {
  const char* input_path = nullptr;
  const char* output_path = nullptr;
  std::uint64_t profile_sample = UINT64_MAX;
  if (!host_command_line(g_command_line, sizeof g_command_line) ||
      !split_command_line(g_command_line, input_path, output_path, profile_sample)) {
    return fail(replay_status::usage,
                "expected the command line IMAGE INPUT OUTPUT [profile SAMPLE] (qemu -append \"INPUT OUTPUT ...\")");
  }
  const std::int32_t in_handle = host_open(input_path, std::strlen(input_path), kOpenReadBinary);
  if (in_handle < 0) return fail(replay_status::input_open, "cannot open the input file");
  InputFile& in = g_in;
  in.attach(in_handle);

  char magic[sizeof firmware::kEngineInputMagic];
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, firmware::kEngineInputMagic, sizeof magic) != 0) {
    return fail(replay_status::input_format, "the input is not an engine-input file (magic RWENGIN2 expected)");
  }
  std::uint64_t n_config = 0;
  if (!in.read_u64(n_config) || n_config > firmware::kEngineInputMaxConfig) {
    return fail(replay_status::input_format, "the input's configuration count is missing or too large");
  }
  firmware::WallEngineConfig config;
  for (std::uint64_t i = 0; i < n_config; ++i) {
    std::uint64_t key = 0;
    double value = 0.0;
    if (!in.read_u64(key) || !in.read_double(value)) {
      return fail(replay_status::input_format, "the input's configuration is truncated");
    }
    if (!firmware::apply_engine_input_key(config, key, value)) {
      return fail(replay_status::input_format,
                  "the input has a configuration key this image does not know (rebuild the image)");
    }
  }
  std::uint64_t n_samples = 0;
  if (!in.read_u64(n_samples) || n_samples == 0) {
    return fail(replay_status::input_format, "the input's sample count is missing or zero");
  }
  // The sensor section, through a second reader of the same file.
  const std::int32_t sensor_handle = host_open(input_path, std::strlen(input_path), kOpenReadBinary);
  if (sensor_handle < 0) return fail(replay_status::input_open, "cannot open the input file a second time");
  g_sensors.attach(sensor_handle);
  SensorStream& sensors = g_sensor_stream;
  if (!sensors.open(g_sensors, n_config, n_samples)) {
    return fail(replay_status::input_format, "the input's wall-sensor section is missing or truncated");
  }
  if (sensors.has_next() && !config.observer_enabled) {
    return fail(replay_status::input_format, "the input has wall-sensor samples but the observer is off");
  }
  const bool observed = config.observer_enabled;
  const std::int64_t step_us = std::llround(config.dt_s * 1e6);
  const firmware::WallEngineError init_seam = g_seam.init(config);
  const firmware::WallEngineError init_direct = g_direct.init(config);
  if (init_seam != firmware::WallEngineError::ok || init_direct != firmware::WallEngineError::ok) {
    host_print("m4-replay image: WallEngine::init refused the configuration: ");
    return fail(replay_status::engine_init, firmware::wall_engine_error_message(init_seam));
  }

  const std::int32_t out_handle = host_open(output_path, std::strlen(output_path), kOpenWriteBinary);
  if (out_handle < 0) return fail(replay_status::output, "cannot open the output file");
  OutputFile& out = g_out;
  out.attach(out_handle);
  out.text("rockwatch-m4-replay 1\n");

  // The constant cost of a measurement window: an empty call of the same shape between the two reads.
  std::uint32_t overhead_min = UINT32_MAX, overhead_max = 0;
  for (int i = 0; i < kOverheadRuns; ++i) {
    const std::uint32_t t0 = clock_now();
    measured_nothing(g_seam, 0.0, 0.0);
    const std::uint32_t t1 = clock_now();
    const std::uint32_t ticks = ticks_between(t0, t1);
    if (ticks < overhead_min) overhead_min = ticks;
    if (ticks > overhead_max) overhead_max = ticks;
  }
  out.text("overhead ");
  out.number(overhead_min);
  out.text(" ");
  out.number(overhead_max);
  out.text("\n");

  for (std::uint64_t k = 0; k < n_samples; ++k) {
    double ug = 0.0, vg = 0.0;
    if (!in.read_double(ug) || !in.read_double(vg)) {
      return fail(replay_status::input_format, "the input's samples are truncated");
    }
    if (k == 0) {
      const std::uint32_t t0 = clock_now();
      const core::AlarmLevel level = g_seam.start(ug, vg).alarm.level;
      const std::uint32_t t1 = clock_now();
      g_direct.reset_wall(core::AccelQ7_56(ug), core::AccelQ7_56(vg));
      out.text("start ");
      out.number(ticks_between(t0, t1));
      out.text(" ");
      out.number(static_cast<std::uint64_t>(level));
      out.text("\n");
      continue;
    }
    const std::int64_t t_us = core::observed_step_end_us(double(k - 1) * config.dt_s, config.dt_s);
    while (observed && sensors.has_next() && sensors.next().utime_us <= t_us) {
      g_seam.push_sensor(sensors.next());
      g_direct.push_sensor(sensors.next());
      if (!sensors.advance()) {
        return fail(replay_status::input_format, "the input's wall-sensor samples are truncated");
      }
    }
    if (k == profile_sample) profiler_start(kProfileIntervalTicks);
    std::uint32_t t0 = clock_now();
    const firmware::EngineSample sample =
        observed ? measured_step_at(g_seam, ug, vg, t_us, step_us) : measured_step(g_seam, ug, vg);
    std::uint32_t t1 = clock_now();
    if (k == profile_sample) profiler_stop();
    (void)sample;
    const std::uint32_t ticks_step = ticks_between(t0, t1);
    const core::AccelQ7_56 ug_q(ug), vg_q(vg);
    t0 = clock_now();
    const core::AlarmLevel level_direct = observed ? measured_process_at(g_direct, ug_q, vg_q, t_us, step_us)
                                                   : measured_process(g_direct, ug_q, vg_q);
    t1 = clock_now();
    const std::uint32_t ticks_engine = ticks_between(t0, t1);
    // Carry-over (core/work_meter.hpp): step() may finish this sample at a later call, and several at once; each
    // finished sample must be process_wall()'s of the same input sample, in order, bit for bit — until the engine
    // sheds (WorkOverflow::shed at a full queue: its events not located), after which the two trajectories part by
    // design and only the count of finished samples is checked.
    const DirectResult direct{level_direct, g_direct.stepper().x_m().to_double(), g_direct.stepper().xd_mps().to_double()};
    if (!g_waiting.push(direct)) return fail(replay_status::mismatch, "step() left more samples waiting than it queues");
    for (int i = 0; i < g_seam.finished_count(); ++i) {
      if (!finished_as_direct(g_seam.finished_sample(i), k)) {
        out.flush();
        return fail(replay_status::mismatch, "step() and process_wall() disagree on a sample (alarm level, x or xd)");
      }
    }
    out.text("s ");
    out.number(ticks_step);
    out.text(" ");
    out.number(ticks_engine);
    out.text(" ");
    out.number(static_cast<std::uint64_t>(level_direct));
    out.text(" ");
    out.bits(direct.x_m);
    out.text(" ");
    out.bits(direct.xd_mps);
    out.text(" ");
    out.number(static_cast<std::uint64_t>(g_seam.pending_samples()));
    out.text(" ");
    out.number(static_cast<std::uint64_t>(g_seam.last_call_units()));
    out.text("\n");
  }
  // The samples still waiting at the end are finished without a budget (as the monitor does when its input stops).
  while (g_seam.pending_samples() > 0) {
    g_seam.finish_pending();
    for (int i = 0; i < g_seam.finished_count(); ++i) {
      if (!finished_as_direct(g_seam.finished_sample(i), n_samples)) {
        out.flush();
        return fail(replay_status::mismatch, "step() and process_wall() disagree on a sample finished at the end");
      }
    }
  }
  if (g_waiting.count != 0) return fail(replay_status::mismatch, "step() did not finish every sample");
  const firmware::WallEngine::WorkCounters& work = g_seam.work_counters();
  out.text("work ");
  out.number(work.late_samples);
  out.text(" ");
  out.number(work.max_late_calls);
  out.text(" ");
  out.number(work.shed_samples);
  out.text(" ");
  out.number(work.overruns);
  out.text(" ");
  out.number(g_first_shed_call);  // 0: never shed
  out.text("\n");
  // The samples after the last step's end were never due; then the file must end.
  while (sensors.has_next()) {
    if (!sensors.advance()) {
      return fail(replay_status::input_format, "the input's wall-sensor samples are truncated");
    }
  }
  unsigned char extra = 0;
  if (g_sensors.read(&extra, 1)) {
    return fail(replay_status::input_format, "the input has bytes after its last wall-sensor sample");
  }
  if (profile_sample != UINT64_MAX) {
    out.text("profile ");
    out.number(kProfileIntervalTicks);
    out.text(" ");
    out.number(profiler_count());
    out.text(" ");
    out.number(profiler_dropped());
    out.text("\n");
    const std::uint32_t* addresses = profiler_addresses();
    for (std::uint32_t i = 0; i < profiler_count(); ++i) {
      out.text("p ");
      out.hex(addresses[i]);
      out.text("\n");
    }
  }
  out.text("end ");
  out.number(n_samples);
  out.text(" ");
  out.number(stack_used_bytes());
  out.text("\n");
  if (!out.flush()) return fail(replay_status::output, "cannot write the output file");
  host_close(out_handle);
  host_close(sensor_handle);
  host_close(in_handle);
  return replay_status::ok;
}

}  // namespace rockwatch::m4
