// Makes an input log for the monitor's golden replay test (tests/data/monitor/README.md): the ground motion
// `rockwatch simulate` would run for the given simulate options (read and scaled by the same code), as ground_accel_t
// events on ROCKWATCH_ACCEL, one per sample, cut after SECONDS of record time.
//
//   make_monitor_log OUT.lcmlog SECONDS SIMULATE-OPTIONS...
//   make_monitor_log set01_X_0.40g_200Hz.lcmlog 8 --suite sim/suites/npr9998-2015 --set 1 --component X --scale-pga 0.40
//
// Deterministic: sample i has utime = 1 700 000 000 000 000 µs + i·dt, seq = 1 + i, and the log event is stamped
// 1 ms after the sample time (the receive time the offline monitor uses).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/records_in/input_motion.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "simulate/simulate_request.hpp"

namespace {

constexpr std::int64_t kStartUtime = 1700000000000000;  // 2023-11-14T22:13:20Z
constexpr std::int64_t kLatencyUs = 1000;
constexpr const char* kChannel = "ROCKWATCH_ACCEL";

int make_log(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: make_monitor_log OUT.lcmlog SECONDS SIMULATE-OPTIONS...\n";
    return 2;
  }
  const std::string out_path = argv[1];
  char* end = nullptr;
  const double seconds = std::strtod(argv[2], &end);
  if (end == argv[2] || *end != '\0' || !(seconds > 0.0)) {
    std::cerr << "make_monitor_log: SECONDS must be a number > 0 (got " << argv[2] << ")\n";
    return 2;
  }
  std::vector<const char*> simulate_argv{"simulate"};
  for (int i = 3; i < argc; ++i) simulate_argv.push_back(argv[i]);
  const rockwatch::cli::SimulateParse parse =
      rockwatch::cli::parse_simulate_arguments(static_cast<int>(simulate_argv.size()), simulate_argv.data());
  if (!parse.request) {
    std::cerr << parse.help_text;
    return 2;
  }
  const rockwatch::cli::InputMotion input = rockwatch::cli::prepare_input(
      rockwatch::cli::InputRequest{parse.request->record, parse.request->scale_pga_g, parse.request->wall.g_mps2});
  const rockwatch::sim::GroundMotion& motion = input.motion;
  const auto period_us = static_cast<std::int64_t>(std::llround(motion.dt_s * 1e6));
  if (std::fabs(static_cast<double>(period_us) - motion.dt_s * 1e6) > 1e-6) {
    std::cerr << "make_monitor_log: dt " << motion.dt_s << " s is not a whole number of microseconds\n";
    return 2;
  }

  lcm::LogFile log(out_path, "w");
  if (!log.good()) {
    std::cerr << "make_monitor_log: cannot create " << out_path << '\n';
    return 1;
  }
  const auto n = static_cast<std::size_t>(std::llround(seconds / motion.dt_s)) + 1;
  std::size_t written = 0;
  std::vector<std::uint8_t> buffer;
  for (std::size_t i = 0; i < n && i < motion.ug_mps2.size(); ++i) {
    rockwatch::ground_accel_t m;
    m.utime = kStartUtime + static_cast<std::int64_t>(i) * period_us;
    m.seq = 1 + static_cast<std::int64_t>(i);
    m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
    m.ug_mps2 = motion.ug_mps2[i];
    m.vg_mps2 = motion.vg_mps2.empty() ? 0.0 : motion.vg_mps2[i];
    m.sensor_status = 0;
    buffer.resize(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
    lcm::LogEvent event{};
    event.timestamp = m.utime + kLatencyUs;
    event.channel = kChannel;
    event.datalen = static_cast<std::int32_t>(buffer.size());
    event.data = buffer.data();
    if (log.writeEvent(&event) != 0) {
      std::cerr << "make_monitor_log: cannot write " << out_path << '\n';
      return 1;
    }
    ++written;
  }
  std::cerr << "make_monitor_log: " << written << " samples at " << motion.dt_s << " s ("
            << input.horizontal.source << ", scale factor " << input.scale_factor << ") -> " << out_path << '\n';
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return make_log(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "make_monitor_log: error: " << e.what() << '\n';
    return 2;
  }
}
