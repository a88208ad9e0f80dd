// The monitor image for QEMU's mps2-an386 (scripts/m4-monitor.sh): firmware::MonitorLoop with firmware::WallEngine
// (fixed point; the wall observer when configured) on the emulated Cortex-M4, fed by real LCM datagrams through the
// board's LAN9118 (lan9118.hpp) and the image's own IPv4/UDP path (udp_ipv4.hpp), publishing what rockwatch-monitor
// publishes (wall_state_t, alarm_event_t, monitor_status_t once per second, wall_estimate_t with the observer) as LCM
// datagrams (LC02) to the same group and port.
//
// Command line (QEMU -append): "OUTPUT CONFIG". CONFIG (written by scripts/m4-monitor-run.py from
// `rockwatch-monitor --print-config`, so that the image runs exactly the host monitor's settings), little-endian:
//   magic "RWMONCF1", uint64 n, n pairs {uint64 key, 8-byte value}, then 7 channel names of 64 bytes each (accel,
//   accel_batch, wall_state, alarm, status, wall_sensor, wall_estimate; NUL-terminated).
//   Keys below 1000 are EngineInputKey (rockwatch/firmware/engine_input_format.hpp, double values); the monitor's:
//   ConfigKey below (double values, except config_digest: the int64's bits).
// The receive path mirrors the host's (host_tools/monitor/datagram_input.cpp, udp_receiver.cpp): datagram →
// firmware::LcmDatagramReassembler → the input channels (accel, accel_batch, and wall_sensor with the observer) to
// MonitorLoop::on_message; messages on other channels are counted, not handed to the loop; the reassembler's rejected
// count goes to note_datagram_counts() after every datagram, as the host does.
//
// Time: receive_utime is the host's CLOCK_REALTIME in µs, read through semihosting: at start-up the image waits for
// SYS_TIME (whole seconds) to change and takes SYS_ELAPSED (QEMU's CLOCK_MONOTONIC, ns) at that edge; then every
// receive time is that second plus the elapsed time since (within ~20 µs of the host's clock). The board's own clocks
// cannot serve: under -icount (needed to count instructions exactly) virtual time runs at 2^shift ns per
// instruction, not at the wall clock's pace. The samples carry their publisher's utime; the loop compares the two
// (late, time_untrusted) exactly as on the host.
//
// Instructions are counted as in the replay image (../m4_replay/instruction_clock.hpp: TIMER0 under -icount): per
// received frame, from before the driver takes it to after on_message() returns (NIC FIFO, Ethernet/IPv4/UDP, LCM
// reassembly, the loop, the engine, encoding and sending every output frame), and the receive part alone (up to the
// reassembler's answer).
//
// OUTPUT is text, one record per line (scripts/m4-monitor-run.py parses it):
//   rockwatch-m4-monitor 1
//   overhead <ticks>                      an empty measured window
//   call_overhead <per call> <per sample> kImageCallOverheadUnits, kImageUnitsPerSample (declared to the engine)
//   ready <utime>                         listening (after the clock calibration and the NIC's start)
//   d <kind> <ticks> <ticks_receive> <samples> <ticks_engine> <states>   one frame: kind g (ground message to the loop), s
//                                         (wall sensor to the loop), o (message on another channel), f (fragment
//                                         stored), r (rejected by the LCM layer), n (dropped by the NIC/IPv4/UDP
//                                         path); samples: ground samples the loop received from it; ticks_engine: in
//                                         the engine's calls (the rest is the image's own part); states: samples
//                                         finished and published (the own part within kImageCallOverheadUnits +
//                                         states · kImageUnitsPerSample)
//   k <ticks> <states>                    between frames: the samples a budgeted call left waiting, finished and
//                                         published (states: how many)
//   a <input_seq> <level>                 an alarm transition (alarm_event_t as published)
//   c <name> <value> ...                  the counters (written whenever the loop is idle and something changed)
// Exit status (QEMU's, through semihosting): 3 usage, 4 config unreadable, 5 config invalid, 6 init refused, 7 NIC
// missing, 8 output, 9 fault.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "../m4_replay/instruction_clock.hpp"
#include "lan9118.hpp"
#include "rockwatch/firmware/engine_input_format.hpp"
#include "rockwatch/firmware/lcm_datagram.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "../m4_replay/semihosting.hpp"
#include "udp_ipv4.hpp"

extern "C" {
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
[[noreturn]] void m4_monitor_start();
[[noreturn]] void m4_monitor_fault(std::uint32_t exception_number);
}

namespace rockwatch::m4 {
namespace {

namespace firmware = rockwatch::firmware;
namespace core = rockwatch::core;

namespace status {
constexpr std::uint32_t usage = 3, config_open = 4, config_invalid = 5, init = 6, nic = 7, output = 8, fault = 9;
}

enum class ConfigKey : std::uint64_t {
  sample_rate_hz = 1001,
  max_bridge_samples = 1002,
  sensor_range_mps2 = 1003,
  late_limit_s = 1004,
  restart_window = 1005,
  clock_tolerance_us = 1006,
  config_digest = 1007,
  work_budget_units = 1008,
  group_ipv4 = 1009,
  port = 1010,
  image_ipv4 = 1011,
};
constexpr char kConfigMagic[8] = {'R', 'W', 'M', 'O', 'N', 'C', 'F', '1'};
constexpr std::uint64_t kMaxConfigPairs = 128;

// --- semihosting clocks ---
constexpr std::uint32_t kSysTime = 0x11, kSysElapsed = 0x30;
std::int64_t host_elapsed_ns() {
  std::uint32_t block[2] = {0, 0};
  semihost(kSysElapsed, block);
  return static_cast<std::int64_t>(std::uint64_t{block[1]} << 32 | block[0]);
}
std::int64_t g_epoch_utime = 0, g_epoch_elapsed_ns = 0;
void calibrate_clock() {
  const std::int32_t first = semihost(kSysTime, nullptr);
  std::int32_t now = first;
  std::int64_t elapsed = host_elapsed_ns();
  const std::int64_t start = elapsed;
  while (now == first && elapsed - start < 2000000000) {
    now = semihost(kSysTime, nullptr);
    elapsed = host_elapsed_ns();
  }
  g_epoch_utime = static_cast<std::int64_t>(now) * 1000000;
  g_epoch_elapsed_ns = elapsed;
}
std::int64_t realtime_utime() { return g_epoch_utime + (host_elapsed_ns() - g_epoch_elapsed_ns) / 1000; }

// --- buffered text output through semihosting ---
class OutputFile {
 public:
  void attach(std::int32_t handle) { handle_ = handle; }
  void text(const char* s) {
    while (*s != '\0') put(*s++);
  }
  void number(std::int64_t v) {
    if (v < 0) {
      put('-');
      v = -v;
    }
    char digits[20];
    int n = 0;
    auto u = static_cast<std::uint64_t>(v);
    do {
      digits[n++] = static_cast<char>('0' + u % 10);
      u /= 10;
    } while (u != 0);
    while (n > 0) put(digits[--n]);
  }
  void field(const char* name, std::int64_t v) {
    put(' ');
    text(name);
    put(' ');
    number(v);
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

// What the image's call does around the engine's, at most [Cortex-M4 instructions], declared to the engine
// (WallEngineConfig::caller_overhead_units, caller_units_per_sample) so that with the observer the whole call, not
// only the engine's, fits the estimator's share: 32 000 instructions at 1 kHz (issue 43).
// - once a call: the receive (NIC FIFO, Ethernet/IPv4/UDP with both checksums, the LC02 header: 2 017), MonitorLoop's
//   decoding, sequence rules and step clock, the engine's seam (TimedEngine);
// - once for every sample the call finishes: MonitorLoop encoding and sending its outputs (wall_state_t and
//   wall_estimate_t, an alarm_event_t at a transition), paid from the engine's budget with the sample's end.
// The numbers: the image's own part of a call (its instructions less those in the engine's calls: the "d" lines'
// ticks_engine; scripts/m4-monitor.sh's image_overhead_insn_by_samples_published), at most rounded up.
// Measured: docs/BENCHMARKS.md, "The monitor on the wire".
// m4_monitor_wire fails when a call's own part exceeds 4 000 + 12 500 per sample published.
constexpr std::int32_t kImageCallOverheadUnits = 4000;
constexpr std::int32_t kImageUnitsPerSample = 12500;

// The engine behind a clock: the instructions spent in its calls during the current frame (handle_frame() takes
// them off the frame's to give the image's own part, checked against kImageCallOverheadUnits), and MonitorLoop's
// step clock (worst_step_ns) from the same counter.
std::uint32_t g_engine_ticks = 0;  // TIMER0 ticks in engine calls since the frame began
class TimedEngine final : public core::SampleEngine {
 public:
  explicit TimedEngine(firmware::WallEngine& engine) : e_(engine) {}
  core::MonitorArithmetic arithmetic() const override { return e_.arithmetic(); }
  core::WallEngineError init(const core::WallEngineConfig& config) override { return e_.init(config); }
  core::EngineSample start(double ug, double vg) override {
    const Timed t;
    return e_.start(ug, vg);
  }
  core::EngineSample restart(double ug, double vg) override {
    const Timed t;
    return e_.restart(ug, vg);
  }
  core::EngineSample step(double ug, double vg) override {
    const Timed t;
    return e_.step(ug, vg);
  }
  core::EngineSample step_at(double ug, double vg, std::int64_t t_us, std::int64_t step_us) override {
    const Timed t;
    return e_.step_at(ug, vg, t_us, step_us);
  }
  std::uint32_t push_sensor(const core::WallSensorSample& sample) override {
    const Timed t;
    return e_.push_sensor(sample);
  }
  const core::ObserverCounters& observer_counters() const override { return e_.observer_counters(); }
  int finished_count() const override { return e_.finished_count(); }
  const core::EngineSample& finished_sample(int i) const override { return e_.finished_sample(i); }
  int pending_samples() const override { return e_.pending_samples(); }
  void finish_pending() override {
    const Timed t;
    e_.finish_pending();
  }

 private:
  struct Timed {
    std::uint32_t t0 = clock_now();
    ~Timed() { g_engine_ticks += ticks_between(t0, clock_now()); }
  };
  firmware::WallEngine& e_;
};

// MonitorLoop's step clock (worst_step_ns): the engine call's instructions (TIMER0 under -icount shift=10: 25.6 ticks
// of 40 ns an instruction) as time on the Cortex-M4 the budgets assume (168 MHz, 128 million instructions a second:
// core::kM4InstructionsPerSecond; 7.8125 ns an instruction): ns = ticks · 40 / 1024 · 7.8125 = ticks · 625 / 2048.
// Not wall-clock time: the emulator's own speed never enters. Extended to 64 bits (one wrap between reads at most).
constexpr int kIcountShift = 10;  // scripts/m4-monitor-run.py: SHIFT
static_assert(kIcountShift == 10, "step_clock_ns assumes 1024 ns of virtual time per instruction");
std::uint32_t g_step_clock_last = 0;
std::uint64_t g_step_clock_ticks = 0;
std::int64_t step_clock_ns() {
  const std::uint32_t now = clock_now();
  g_step_clock_ticks += ticks_between(g_step_clock_last, now);
  g_step_clock_last = now;
  return static_cast<std::int64_t>(g_step_clock_ticks * 625u / 2048u);
}

// --- the image's state: static, nothing allocated ---
OutputFile g_out;
Lan9118 g_nic;
UdpPath g_udp;
firmware::LcmDatagramReassembler g_lcm;
firmware::WallEngine g_engine;
TimedEngine g_timed_engine(g_engine);
firmware::MonitorLoop g_loop;
firmware::MonitorSettings g_settings;
std::uint8_t g_rx_frame[Lan9118::kMaxFrame];
std::uint8_t g_tx_frame[Lan9118::kMaxFrame];
std::uint8_t g_tx_payload[UdpPath::kMaxPayload];
char g_command_line[512];
std::int64_t g_input_messages = 0, g_other_channels = 0;

// MonitorLoop's transport: one LC02 datagram per message (LCM's short message: "LC02", sequence number, channel,
// NUL, payload), in one frame to the group.
class WireTransport final : public firmware::Transport {
 public:
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override {
    const std::size_t name = std::strlen(channel);
    const std::size_t total = 8 + name + 1 + size;
    if (total > sizeof g_tx_payload) return false;
    std::uint8_t* p = g_tx_payload;
    const std::uint32_t magic = firmware::LcmDatagramReassembler::kMagicShort;
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(magic >> (24 - 8 * i));
    for (int i = 0; i < 4; ++i) p[4 + i] = static_cast<std::uint8_t>(sequence_ >> (24 - 8 * i));
    ++sequence_;
    std::memcpy(p + 8, channel, name + 1);
    std::memcpy(p + 8 + name + 1, data, size);
    const std::size_t length = g_udp.build_frame(g_tx_payload, total, g_tx_frame, sizeof g_tx_frame);
    const bool ok = length != 0 && g_nic.send(g_tx_frame, length);
    ++(ok ? g_udp.counters().sent : g_udp.counters().send_failures);
    return ok;
  }

 private:
  std::uint32_t sequence_ = 0;
};
WireTransport g_transport;

class TransitionLog final : public firmware::MonitorListener {
 public:
  void on_alarm(const rockwatch::alarm_event_t& event) override {
    g_out.text("a");
    g_out.field("", event.input_seq);
    g_out.field("", event.level);
    g_out.text("\n");
  }
};
TransitionLog g_transitions;

// --- configuration ---
class ConfigFile {
 public:
  explicit ConfigFile(std::int32_t handle) : handle_(handle) {}
  bool read(void* data, std::size_t size) { return host_read(handle_, data, size) == static_cast<std::int32_t>(size); }

 private:
  std::int32_t handle_;
};

bool whole(double v, double lo, double hi) { return v >= lo && v <= hi && static_cast<double>(static_cast<std::int64_t>(v)) == v; }

std::uint32_t g_group = 0, g_image_ip = 0;
std::uint16_t g_port = 0;

std::uint32_t read_config(const char* path) {
  const std::int32_t handle = host_open(path, std::strlen(path), kOpenReadBinary);
  if (handle < 0) return status::config_open;
  ConfigFile in(handle);
  char magic[8];
  std::uint64_t n = 0;
  std::uint32_t result = 0;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kConfigMagic, sizeof magic) != 0 || !in.read(&n, 8) ||
      n > kMaxConfigPairs) {
    result = status::config_invalid;
  }
  firmware::MonitorSettings& s = g_settings;
  for (std::uint64_t i = 0; result == 0 && i < n; ++i) {
    std::uint64_t key = 0;
    double v = 0.0;
    std::int64_t bits = 0;
    if (!in.read(&key, 8) || !in.read(&v, 8)) {
      result = status::config_invalid;
      break;
    }
    std::memcpy(&bits, &v, 8);
    bool ok = true;
    switch (static_cast<ConfigKey>(key)) {
      case ConfigKey::sample_rate_hz: s.sample_rate_hz = v; break;
      case ConfigKey::max_bridge_samples: ok = whole(v, 0, 1000); s.max_bridge_samples = static_cast<std::int32_t>(v); break;
      case ConfigKey::sensor_range_mps2: s.sensor_range_mps2 = v; break;
      case ConfigKey::late_limit_s: s.late_limit_s = v; break;
      case ConfigKey::restart_window: ok = whole(v, 1, 1e9); s.restart_window = static_cast<std::int64_t>(v); break;
      case ConfigKey::clock_tolerance_us: ok = whole(v, 1, 1e14); s.clock_tolerance_us = static_cast<std::int64_t>(v); break;
      case ConfigKey::config_digest: s.config_digest = bits; break;
      case ConfigKey::work_budget_units:
        ok = whole(v, 0, 1e9);
        s.engine.work_budget_units = static_cast<std::int32_t>(v);
        break;
      case ConfigKey::group_ipv4: ok = whole(v, 0, 4294967295.0); g_group = static_cast<std::uint32_t>(v); break;
      case ConfigKey::port: ok = whole(v, 1, 65535); g_port = static_cast<std::uint16_t>(v); break;
      case ConfigKey::image_ipv4: ok = whole(v, 0, 4294967295.0); g_image_ip = static_cast<std::uint32_t>(v); break;
      default: ok = key < 1000 && firmware::apply_engine_input_key(s.engine, key, v); break;
    }
    if (!ok) result = status::config_invalid;
  }
  char (*channels[7])[firmware::kChannelNameMax] = {&s.channels.accel,  &s.channels.accel_batch, &s.channels.wall_state,
                                                    &s.channels.alarm,  &s.channels.status,      &s.channels.wall_sensor,
                                                    &s.channels.wall_estimate};
  for (int i = 0; result == 0 && i < 7; ++i) {
    if (!in.read(*channels[i], firmware::kChannelNameMax) || (*channels[i])[firmware::kChannelNameMax - 1] != '\0') {
      result = status::config_invalid;
    }
  }
  host_close(handle);
  if (result == 0 && (g_group >> 28) != 0xEu) result = status::config_invalid;  // 224.0.0.0/4
  return result;
}

// --- counters ---
std::int64_t g_last_written_frames = -1;
void write_counters() {
  const NetCounters& net = g_udp.counters();
  if (net.frames == g_last_written_frames) return;
  g_last_written_frames = net.frames;
  const firmware::MonitorCounters& c = g_loop.counters();
  const firmware::DatagramCounters& d = g_lcm.counters();
  g_out.text("c");
  g_out.field("frames", net.frames);
  g_out.field("nic_dropped", g_nic.frames_dropped());
  g_out.field("not_ipv4", net.not_ipv4);
  g_out.field("ip_malformed", net.ip_malformed);
  g_out.field("ip_fragments", net.ip_fragments);
  g_out.field("not_udp", net.not_udp);
  g_out.field("not_for_us", net.not_for_us);
  g_out.field("udp_malformed", net.udp_malformed);
  g_out.field("datagrams", net.datagrams);
  g_out.field("frames_sent", net.sent);
  g_out.field("send_failures", net.send_failures);
  g_out.field("lcm_rejected", d.rejected);
  g_out.field("lcm_fragments", d.fragments);
  g_out.field("lcm_skipped_too_large", d.skipped_too_large);
  g_out.field("input_messages", g_input_messages);
  g_out.field("other_channels", g_other_channels);
  g_out.field("samples_received", c.samples_received);
  g_out.field("samples_processed", c.samples_processed);
  g_out.field("samples_bridged", c.samples_bridged);
  g_out.field("gaps", c.gaps);
  g_out.field("state_resets", c.state_resets);
  g_out.field("duplicates", c.duplicates);
  g_out.field("out_of_order", c.out_of_order);
  g_out.field("late", c.late);
  g_out.field("rejected_not_finite", c.rejected_not_finite);
  g_out.field("rejected_out_of_range", c.rejected_out_of_range);
  g_out.field("lift_off", c.lift_off);
  g_out.field("publisher_restarts", c.publisher_restarts);
  g_out.field("decode_errors", c.decode_errors);
  g_out.field("time_untrusted", c.time_untrusted);
  g_out.field("alarm_events", c.alarm_events);
  g_out.field("states_published", c.states_published);
  g_out.field("publish_failures", c.publish_failures);
  g_out.field("sensor_samples_received", c.sensor_samples_received);
  g_out.field("sensor_duplicates", c.sensor_duplicates);
  g_out.field("estimates_published", c.estimates_published);
  g_out.field("samples_late", c.samples_late);
  g_out.field("samples_work_shed", c.samples_work_shed);
  g_out.field("alarm_level", static_cast<std::int64_t>(g_loop.alarm_level()));
  g_out.text("\n");
}

// --- one received frame, measured ---
[[gnu::noinline]] void handle_frame() {
  g_engine_ticks = 0;
  const std::uint32_t t0 = clock_now();
  const int size = g_nic.receive(g_rx_frame, sizeof g_rx_frame);
  if (size < 0) return;
  const std::int64_t now = realtime_utime();
  char kind = 'n';
  std::int64_t samples = g_loop.counters().samples_received;
  const std::int64_t states = g_loop.counters().states_published + g_loop.counters().publish_failures;
  UdpDatagram datagram;
  firmware::LcmMessageView message;
  firmware::DatagramOutcome outcome = firmware::DatagramOutcome::rejected;
  bool have_message = false;
  if (size > 0 && g_udp.accept_frame(g_rx_frame, static_cast<std::size_t>(size), &datagram)) {
    outcome = g_lcm.accept(datagram.payload, datagram.size, {datagram.source_ipv4, datagram.source_port}, now,
                           &message, nullptr);
    have_message = outcome == firmware::DatagramOutcome::message;
    kind = have_message ? 'o' : outcome == firmware::DatagramOutcome::rejected ? 'r' : 'f';
  }
  const std::uint32_t t_receive = clock_now();
  if (have_message) {
    const firmware::MonitorChannels& ch = g_settings.channels;
    const bool sensor = g_settings.engine.observer_enabled && std::strcmp(message.channel, ch.wall_sensor) == 0;
    if (sensor || std::strcmp(message.channel, ch.accel) == 0 || std::strcmp(message.channel, ch.accel_batch) == 0) {
      ++g_input_messages;
      kind = sensor ? 's' : 'g';
      g_loop.on_message(message.channel, message.payload, message.size, now);
    } else {
      ++g_other_channels;
    }
  }
  if (size > 0 && kind != 'n') g_loop.note_datagram_counts(g_lcm.counters().rejected, 0);
  const std::uint32_t t1 = clock_now();
  samples = g_loop.counters().samples_received - samples;
  const char text[3] = {kind, ' ', '\0'};
  g_out.text("d ");
  g_out.text(text);
  g_out.number(ticks_between(t0, t1));
  g_out.field("", ticks_between(t0, t_receive));
  g_out.field("", samples);
  g_out.field("", g_engine_ticks);
  g_out.field("", g_loop.counters().states_published + g_loop.counters().publish_failures - states);
  g_out.text("\n");
}

// Between frames: the samples the engine still works on, finished and published (MonitorLoop::finish_pending).
[[gnu::noinline]] void catch_up() {
  const std::int64_t states = g_loop.counters().states_published + g_loop.counters().publish_failures;
  const std::uint32_t t0 = clock_now();
  g_loop.finish_pending();
  const std::uint32_t t1 = clock_now();
  g_out.text("k");
  g_out.field("", ticks_between(t0, t1));
  g_out.field("", g_loop.counters().states_published + g_loop.counters().publish_failures - states);
  g_out.text("\n");
}

[[gnu::noinline]] void measured_nothing() {}

volatile std::uint32_t& syst(std::uint32_t offset) {
  return *reinterpret_cast<volatile std::uint32_t*>(std::uintptr_t{0xE000E010} + offset);
}

std::uint32_t run() {
  if (!host_command_line(g_command_line, sizeof g_command_line)) return status::usage;
  // "IMAGE OUTPUT CONFIG": split on spaces.
  char* words[4] = {};
  int n = 0;
  for (char* p = g_command_line; *p != '\0' && n < 4;) {
    while (*p == ' ') *p++ = '\0';
    if (*p == '\0') break;
    words[n++] = p;
    while (*p != '\0' && *p != ' ') ++p;
  }
  if (n != 3) return status::usage;
  const std::int32_t out = host_open(words[1], std::strlen(words[1]), kOpenWriteBinary);
  if (out < 0) return status::output;
  g_out.attach(out);
  g_out.text("rockwatch-m4-monitor 1\n");
  if (const std::uint32_t r = read_config(words[2]); r != 0) return r;
  g_settings.engine.caller_overhead_units = kImageCallOverheadUnits;
  g_settings.engine.caller_units_per_sample = kImageUnitsPerSample;
  if (g_loop.init(g_settings, g_timed_engine, g_transport, &g_transitions) != firmware::MonitorError::ok) {
    host_print("m4-monitor image: MonitorLoop::init refused the settings\n");
    return status::init;
  }
  const std::uint8_t mac[6] = {0x02, 0x52, 0x57, 0x00, 0x00, 0x02};
  if (!g_nic.init(mac)) return status::nic;
  g_udp.init({{0x02, 0x52, 0x57, 0x00, 0x00, 0x02}, g_image_ip, 7667}, g_group, g_port);
  {
    const std::uint32_t a = clock_now();
    measured_nothing();
    const std::uint32_t b = clock_now();
    g_out.text("overhead");
    g_out.field("", ticks_between(a, b));
    g_out.text("\ncall_overhead");
    g_out.field("", kImageCallOverheadUnits);
    g_out.field("", kImageUnitsPerSample);
    g_out.text("\n");
  }
  calibrate_clock();
  g_step_clock_last = clock_now();
  g_loop.set_step_clock(step_clock_ns);
  // SysTick: a wake-up every 2^20 cycles of the 25 MHz clock (virtual time), so that the status goes out once a second
  // also when no frame arrives.
  syst(4) = 0x00FFFFFFu;
  syst(8) = 0;
  syst(0) = 0x7u;  // enable, interrupt, processor clock
  asm volatile("cpsid i" ::: "memory");  // interrupts only wake WFI
  std::int64_t next_status = realtime_utime();
  g_out.text("ready");
  g_out.field("", next_status);
  g_out.text("\n");
  if (!g_out.flush()) return status::output;
  for (;;) {
    while (g_nic.rx_pending()) handle_frame();
    // Samples a budgeted call left waiting (carry-over) are finished and published in the time between frames, not
    // in the next frame's call: a call that caught up on a waiting sample would publish two, more than 32 000
    // instructions at 1 kHz with the observer (docs/BENCHMARKS.md, "The monitor on the wire"). The values are the
    // same whichever call finishes a sample (core/work_meter.hpp); measured apart (k lines).
    if (!g_nic.rx_pending() && g_engine.pending_samples() > 0) catch_up();
    g_nic.clear_rx_interrupt();
    const std::int64_t now = realtime_utime();
    if (now >= next_status) {
      g_loop.publish_status(now);
      next_status = now + 1000000;
    }
    write_counters();
    if (!g_out.flush()) return status::output;
    if (!g_nic.rx_pending()) {
      *reinterpret_cast<volatile std::uint32_t*>(std::uintptr_t{0xE000ED04}) = 1u << 25;  // ICSR.PENDSTCLR
      asm volatile("wfi" ::: "memory");
    }
  }
}

}  // namespace
}  // namespace rockwatch::m4

extern "C" [[noreturn]] void m4_monitor_start() {
  for (void (**f)() = __init_array_start; f < __init_array_end; ++f) (*f)();
  rockwatch::m4::start_instruction_clock();
  rockwatch::m4::host_exit(rockwatch::m4::run());
}

extern "C" [[noreturn]] void m4_monitor_fault(std::uint32_t exception_number) {
  char text[] = "m4-monitor image: fault, exception number 00\n";
  text[sizeof text - 4] = static_cast<char>('0' + (exception_number / 10) % 10);
  text[sizeof text - 3] = static_cast<char>('0' + exception_number % 10);
  rockwatch::m4::host_print(text);
  rockwatch::m4::host_exit(rockwatch::m4::status::fault);
}

extern "C" [[noreturn]] void __assert_func(const char* file, int, const char*, const char* expression) {
  rockwatch::m4::host_print("m4-monitor image: assertion failed: ");
  rockwatch::m4::host_print(expression != nullptr ? expression : "?");
  rockwatch::m4::host_print(" in ");
  rockwatch::m4::host_print(file != nullptr ? file : "?");
  rockwatch::m4::host_print("\n");
  rockwatch::m4::host_exit(rockwatch::m4::status::fault);
}

void operator delete(void*) noexcept {
  rockwatch::m4::host_print("m4-monitor image: operator delete called\n");
  rockwatch::m4::host_exit(rockwatch::m4::status::fault);
}
void operator delete(void*, std::size_t) noexcept {
  rockwatch::m4::host_print("m4-monitor image: operator delete called\n");
  rockwatch::m4::host_exit(rockwatch::m4::status::fault);
}

// Static objects with destructors (the loop's Transport and MonitorListener, the engine) register them at start-up;
// the image never returns, so they never run: the registration is a no-op (and newlib's atexit table is not linked).
extern "C" {
void* __dso_handle = nullptr;
int __cxa_atexit(void (*)(void*), void*, void*) { return 0; }
}
