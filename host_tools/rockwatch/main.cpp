// `rockwatch COMMAND [options]`: dispatches to one subcommand. Each command owns its options and help, so the
// table below is the only place that changes when a command is added.
#include <cstddef>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "common/process/commands.hpp"

#ifndef ROCKWATCH_VERSION
#define ROCKWATCH_VERSION "unknown"
#endif

namespace rockwatch::cli {
namespace {

constexpr Command kCommands[] = {
    {"simulate", "response of a wall to a ground-motion record (two-block rocking model, Newmark)", simulate_main},
    {"identify", "a wall's capacity, stiffness and r from a test record (snap-back or forced); writes a wall file",
     identify_main},
    {"static", "allowable PGA by the static kinematic check (NTC 2008, NZSEE 2016); Figure 3 sweep", static_main},
    {"spectrum", "response spectrum and intensity measures of a record, against a design spectrum", spectrum_main},
    {"generate", "spectrum-compatible ground-motion suite (NPR 9998-like): set files, manifest, spectra plots",
     generate_main},
    {"study", "collapse-probability study of the design paper (Table 3): a wall through a suite at many PGA levels",
     study_main},
    {"replay", "send a record as the monitor's sensor would: LCM messages paced in real time, sensor model, LCM log",
     replay_main},
    {"demo", "the live monitor on two suite records over LCM, its alarm timeline beside the offline simulation",
     demo_main},
    {"dashboard", "live web page of the monitor: alarm level, x(t), energy, transitions and status of every wall",
     dashboard_main},
};

void print_usage(std::ostream& out) {
  out << "rockwatch " << ROCKWATCH_VERSION
      << ": out-of-plane rocking of unreinforced masonry walls (two-block model)\n\n"
         "Usage:\n"
         "  rockwatch COMMAND [options]\n"
         "  rockwatch COMMAND --help     options of one command\n"
         "  rockwatch --version\n\n"
         "Commands:\n";
  constexpr std::size_t kNameColumn = 12;
  for (const Command& c : kCommands) {
    const std::size_t length = std::strlen(c.name);
    out << "  " << c.name << std::string(length < kNameColumn ? kNameColumn - length : 1, ' ') << c.summary << '\n';
  }
  out << "\nExit status: 0 done, 2 invalid options or input, 1 internal error.\n";
}

const Command* find_command(const std::string& name) {
  for (const Command& c : kCommands) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

std::string command_names() {
  std::string names;
  for (const Command& c : kCommands) names += (names.empty() ? "" : ", ") + std::string(c.name);
  return names;
}

int dispatch(int argc, const char* const* argv) {
  if (argc < 2) {
    std::cerr << "rockwatch: error: no command given\n\n";
    print_usage(std::cerr);
    return kExitUsageError;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || first == "help") {
    // `rockwatch help simulate` reads like `rockwatch simulate --help`.
    if (first == "help" && argc > 2) {
      if (const Command* c = find_command(argv[2])) {
        const char* const help_argv[] = {c->name, "--help"};
        return c->run(2, help_argv);
      }
      std::cerr << "rockwatch: error: unknown command '" << argv[2] << "' (commands: " << command_names() << ")\n";
      return kExitUsageError;
    }
    print_usage(std::cout);
    return kExitOk;
  }
  if (first == "--version" || first == "-V") {
    std::cout << "rockwatch " << ROCKWATCH_VERSION << '\n';
    return kExitOk;
  }
  if (const Command* c = find_command(first)) return c->run(argc - 1, argv + 1);
  if (!first.empty() && first.front() == '-') {
    std::cerr << "rockwatch: error: unknown option '" << first << "' before the command (commands: " << command_names()
              << "; see rockwatch --help)\n";
  } else {
    std::cerr << "rockwatch: error: unknown command '" << first << "' (commands: " << command_names()
              << "; see rockwatch --help)\n";
  }
  return kExitUsageError;
}

}  // namespace
}  // namespace rockwatch::cli

int main(int argc, char** argv) {
  try {
    return rockwatch::cli::dispatch(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "rockwatch: internal error: " << e.what() << '\n';
  } catch (...) {
    std::cerr << "rockwatch: internal error\n";
  }
  return rockwatch::cli::kExitInternalError;
}
