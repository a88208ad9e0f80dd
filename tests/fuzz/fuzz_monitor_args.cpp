// rockwatch-monitor's command line: monitor::parse_monitor_arguments on argv = {"rockwatch-monitor", the input split
// at NUL bytes...}. Parsing only: the function never starts a monitor. --config is given a fixed small file instead
// of a fuzzed path (a path such as /dev/zero would only test the operating system). options::UsageError is the documented
// outcome for bad arguments; anything else escaping is a defect. Seeds: tests/fuzz/corpus/monitor_args.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "monitor_config.hpp"
#include "rockwatch/options/usage_error.hpp"

using namespace rockwatch;

namespace {

constexpr std::size_t kMaxArguments = 64;

bool is_config_option(const std::string& arg) { return arg == "--config" || arg.rfind("--config=", 0) == 0; }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  unsetenv("LCM_DEFAULT_URL");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile config("fuzz_monitor_args_config");
  static const bool written = [] {
    const char text[] = "{\"kappa\": 1.5, \"alarm\": {\"lambda_w\": 0.5}, \"sample_rate_hz\": 100}";
    config.write(reinterpret_cast<const std::uint8_t*>(text), sizeof text - 1);
    return true;
  }();
  (void)written;

  std::vector<std::string> args{"rockwatch-monitor"};
  const char* const begin = reinterpret_cast<const char*>(data);
  std::size_t start = 0;
  while (start <= size && args.size() < kMaxArguments) {
    const void* nul = std::memchr(begin + start, '\0', size - start);
    const std::size_t end = nul == nullptr ? size : static_cast<std::size_t>(static_cast<const char*>(nul) - begin);
    std::string arg(begin + start, end - start);
    if (is_config_option(arg)) {
      // --config FILE / --config=FILE: always our file; the fuzzed value after --config is skipped.
      args.emplace_back("--config=" + config.path());
      if (arg == "--config") {
        const void* next = end < size ? std::memchr(begin + end + 1, '\0', size - end - 1) : nullptr;
        start = next == nullptr ? size + 1 : static_cast<std::size_t>(static_cast<const char*>(next) - begin) + 1;
        continue;
      }
    } else {
      args.push_back(std::move(arg));
    }
    start = end + 1;
  }
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    const monitor::MonitorParse parse = monitor::parse_monitor_arguments(static_cast<int>(argv.size()), argv.data());
    ROCKWATCH_FUZZ_CHECK(parse.config.has_value() || !parse.text.empty());
  } catch (const options::UsageError& error) {
    ROCKWATCH_FUZZ_CHECK(error.what()[0] != '\0');
  }
  return 0;
}
