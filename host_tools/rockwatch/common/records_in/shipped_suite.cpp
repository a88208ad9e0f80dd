#include "common/records_in/shipped_suite.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/suite_format.hpp"

#ifndef ROCKWATCH_SOURCE_SUITE_DIR
#define ROCKWATCH_SOURCE_SUITE_DIR ""
#endif

namespace rockwatch::cli {

namespace {

bool holds_suite(const std::string& dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(std::filesystem::path(dir) / records::kSuiteManifestName, ec);
}

// The running binary, not argv[0]: a tool started through PATH or a symlink must still find its installation.
std::string executable_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

}  // namespace

SuiteLocation find_shipped_suite() {
  const char* variable = std::getenv(kSuiteDirVariable);
  if (variable != nullptr && *variable != '\0') {
    if (holds_suite(variable)) return {variable, std::string("$") + kSuiteDirVariable};
    throw UsageError(std::string("$") + kSuiteDirVariable + " is " + quoted(variable) + ", which holds no suite (no " +
                     records::kSuiteManifestName + "): point it at the shipped suite " + kShippedSuiteName +
                     ", unset it, or give --suite DIR");
  }
  std::vector<std::string> tried;
  const std::string bin = executable_dir();
  if (!bin.empty()) {
    const std::filesystem::path share = std::filesystem::path(bin) / ".." / "share" / "rockwatch" / "suites";
    const std::string installed = (share / kShippedSuiteName).lexically_normal().string();
    if (holds_suite(installed)) return {installed, "the installation (<bin>/../share/rockwatch/suites)"};
    tried.push_back(installed);
  }
  const std::string source = ROCKWATCH_SOURCE_SUITE_DIR;
  if (!source.empty()) {
    if (holds_suite(source)) return {source, "the source tree the tool was built from"};
    tried.push_back(source);
  }
  std::string list;
  for (const std::string& t : tried) list += (list.empty() ? "" : ", ") + t;
  throw UsageError(std::string("the shipped suite ") + kShippedSuiteName + " was not found (tried $" +
                   kSuiteDirVariable + " (not set)" + (list.empty() ? "" : ", " + list) +
                   "): give --suite DIR or --records LIST, or set $" + kSuiteDirVariable);
}

}  // namespace rockwatch::cli
