// rockwatch-monitor's configuration file: monitor::parse_monitor_arguments({"rockwatch-monitor", "--config", FILE})
// with the input as FILE (JSON parsing, duplicate keys, key and type checks, merging, validation). The documented
// outcome for a bad file is options::UsageError; anything else escaping is a defect.
// Seeds: tests/fuzz/corpus/monitor_config.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "monitor_config.hpp"
#include "rockwatch/options/usage_error.hpp"

using namespace rockwatch;

namespace {

// Settings the parser accepted: the ranges it promises (monitor_config.hpp, monitor_loop.hpp's MonitorError).
void check_config(const monitor::MonitorConfig& c) {
  const firmware::MonitorSettings& s = c.settings;
  ROCKWATCH_FUZZ_CHECK(s.sample_rate_hz > 0.0 && s.sample_rate_hz <= 10000.0);
  ROCKWATCH_FUZZ_CHECK(s.max_bridge_samples >= 0 && s.max_bridge_samples <= 1000);
  ROCKWATCH_FUZZ_CHECK(s.sensor_range_mps2 > 0.0 && s.sensor_range_mps2 <= 80.0);
  ROCKWATCH_FUZZ_CHECK(s.late_limit_s > 0.0 && s.late_limit_s <= 60.0);
  ROCKWATCH_FUZZ_CHECK(s.engine.kappa >= 1.0 && s.engine.kappa < 100.0);
  ROCKWATCH_FUZZ_CHECK(s.clock_tolerance_us >= 1 && s.clock_tolerance_us <= firmware::kMaxClockTolerance_us);
  ROCKWATCH_FUZZ_CHECK(c.timing.priority >= 0 && c.timing.priority <= 99);
  ROCKWATCH_FUZZ_CHECK(c.timing.cpu >= -1 && c.timing.busy_poll_us >= 0 && c.timing.busy_poll_us <= 100000);
  ROCKWATCH_FUZZ_CHECK(!c.lcm_url.empty());
  ROCKWATCH_FUZZ_CHECK(c.normalised.is_object());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // The parser reads $LCM_DEFAULT_URL; the fuzz runs must not depend on the caller's environment.
  unsetenv("LCM_DEFAULT_URL");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_monitor_config");
  const std::string& path = file.write(data, size);
  const char* const argv[] = {"rockwatch-monitor", "--config", path.c_str()};
  try {
    const monitor::MonitorParse parse = monitor::parse_monitor_arguments(3, argv);
    ROCKWATCH_FUZZ_CHECK(parse.config.has_value());
    check_config(*parse.config);
  } catch (const options::UsageError& error) {
    ROCKWATCH_FUZZ_CHECK(error.what()[0] != '\0');
  }
  return 0;
}
