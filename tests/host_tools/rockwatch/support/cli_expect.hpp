// Shared assertion for the tool's rejections: exit status 2, nothing on stdout, and a message on stderr that
// starts with "rockwatch COMMAND: error: " and names what was wrong.
#pragma once

#include <string>
#include <vector>

#include "cli_process.hpp"
#include "cli_test_files.hpp"

#include <CppUTest/TestHarness.h>

namespace rockwatch::test {

inline void expect_command_rejected(const std::string& command, const std::vector<std::string>& args,
                                    const std::vector<std::string>& mentions) {
  std::vector<std::string> full{command};
  full.insert(full.end(), args.begin(), args.end());
  const ProcessResult r = run_rockwatch(full);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(2, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.empty(), what.c_str());
  CHECK_TEXT(r.err.rfind("rockwatch " + command + ": error: ", 0) == 0, what.c_str());
  for (const std::string& m : mentions) CHECK_TEXT(r.err.find(m) != std::string::npos, (m + " in\n" + what).c_str());
}

}  // namespace rockwatch::test
