// Shared assertions of the monitor's test suites. Refusals: no signal, exit status 2, nothing on stdout, and a
// message on stderr that starts with "rockwatch-monitor: error: " and names each of `mentions`.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_files.hpp"  // describe
#include "monitor_test_support.hpp"

#include <CppUTest/TestHarness.h>

namespace rockwatch::test {

inline void expect_monitor_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  const ProcessResult r = run_monitor(args);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(2, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.empty(), what.c_str());
  CHECK_TEXT(r.err.rfind("rockwatch-monitor: error: ", 0) == 0, what.c_str());
  for (const std::string& m : mentions) CHECK_TEXT(r.err.find(m) != std::string::npos, (m + " in\n" + what).c_str());
}

// What `rockwatch-monitor --print-config` prints with a configuration file holding `text` (none when empty) and the
// options `extra`: its one JSON line; the run must succeed.
inline nlohmann::json monitor_printed_config(const std::string& text, const std::vector<std::string>& extra) {
  const TempDir dir;
  std::vector<std::string> args{"--print-config"};
  if (!text.empty()) {
    const std::string path = dir.file("monitor.json");
    write_file(path, text);
    args.insert(args.end(), {"--config", path});
  }
  args.insert(args.end(), extra.begin(), extra.end());
  const ProcessResult r = run_monitor(args);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  const std::vector<nlohmann::json> lines = json_lines(r.out);
  CHECK_EQUAL_TEXT(1u, lines.size(), what.c_str());
  return lines.front();
}

}  // namespace rockwatch::test
