// CLI11 plumbing the commands share: parsing with the tool's own messages for the common mistakes, and whether
// an option was given.
#pragma once

#include <optional>
#include <string>

#include "rockwatch/options/cli11_fwd.hpp"

namespace rockwatch::options {

// Parses argv into `app`. Returns the help text when --help was asked for, nothing otherwise; throws UsageError
// for a parse error, ending in " (see rockwatch COMMAND --help)". `command` is "simulate", "static", ...
std::optional<std::string> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                              const std::string& command);

bool given(const CLI::App& app, const char* option);

}  // namespace rockwatch::options
