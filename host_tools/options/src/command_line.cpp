#include "rockwatch/options/command_line.hpp"

#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::options {

namespace {

// CLI11's messages already name the option; these make the common ones read like the rest of the tool's.
std::string parse_error_message(const CLI::App& app, const CLI::ParseError& e, const std::string& command) {
  const std::string hint = " (see rockwatch " + command + " --help)";
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    const std::vector<std::string> extras = app.remaining();
    if (!extras.empty()) {
      const std::string& first = extras.front();
      const bool is_option = first.size() > 1 && first.front() == '-';
      return std::string(is_option ? "unknown option " : "unexpected argument ") + quoted(first) + hint;
    }
  }
  return e.what() + hint;
}

}  // namespace

std::optional<std::string> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                              const std::string& command) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.help();  // --help
    throw UsageError(parse_error_message(app, e, command));
  }
  return std::nullopt;
}

bool given(const CLI::App& app, const char* option) { return app.count(option) > 0; }

}  // namespace rockwatch::options
