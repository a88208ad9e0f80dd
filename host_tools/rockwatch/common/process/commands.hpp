// The subcommands of `rockwatch` and the exit statuses they share. main.cpp dispatches on the first argument; each
// command parses the rest itself, so commands can be added without touching the others.
#pragma once

namespace rockwatch::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternalError = 1;  // a bug or an exhausted machine, never a user mistake
inline constexpr int kExitUsageError = 2;     // bad options, unreadable or invalid input, unwritable output

// argv[0] is the command name ("simulate"), the rest are its arguments. Returns the process exit status.
using CommandMain = int (*)(int argc, const char* const* argv);

struct Command {
  const char* name;
  const char* summary;  // one line for `rockwatch --help`
  CommandMain run;
};

int simulate_main(int argc, const char* const* argv);
int static_main(int argc, const char* const* argv);
int spectrum_main(int argc, const char* const* argv);
int generate_main(int argc, const char* const* argv);
int study_main(int argc, const char* const* argv);
int replay_main(int argc, const char* const* argv);
int demo_main(int argc, const char* const* argv);
int dashboard_main(int argc, const char* const* argv);
int identify_main(int argc, const char* const* argv);

}  // namespace rockwatch::cli
