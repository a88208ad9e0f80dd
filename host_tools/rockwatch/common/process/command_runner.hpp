// What every `rockwatch` command shares around its own work: the mapping of failures to one-line messages
// ("rockwatch COMMAND: error: MESSAGE") and exit statuses, the checked flush of standard output, and errno text.
#pragma once

#include <functional>
#include <string>

namespace rockwatch::cli {

struct CommandErrors {
  const char* prefix;         // "rockwatch simulate: error: "
  const char* out_of_memory;  // the message for std::bad_alloc, which may hint at what was too large
};

// Runs `body` and returns its status. UsageError, records::RecordError, sim::AnalysisError and sim::MeasureError
// become usage errors (kExitUsageError); std::bad_alloc and any other exception are internal (kExitInternalError).
int run_command(const CommandErrors& errors, const std::function<int()>& body);

// Prints "PREFIXmessage" and a newline to standard error and returns `status`.
int fail(const CommandErrors& errors, const std::string& message, int status);

// Prints help text to standard output; returns kExitOk.
int print_help(const std::string& help_text);

// Flushes standard output; kExitOk, or a message and kExitUsageError when the result could not be written.
int finish_stdout(const CommandErrors& errors);

// ": " and strerror(errno), or nothing when errno is 0.
std::string system_reason();

}  // namespace rockwatch::cli
