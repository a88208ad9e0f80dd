// Strict conversion of option texts to values. Every message names the option and quotes what was given, so a
// user running a batch of analyses can see which argument of which line is wrong.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/work_meter.hpp"

namespace rockwatch::options {

// The whole text must be one finite decimal number; "1.5x", "nan" and "inf" are rejected. Throws UsageError.
double parse_finite_number(const std::string& option, const std::string& text);

// A number given as a number (a program's field rather than a command line's text) must be finite too: the same
// message as parse_finite_number's.
double check_finite_number(const std::string& option, double value);

// A finite number > 0; the message says "OPTION must be > 0UNIT (got VALUE)", e.g. unit " s".
double parse_positive_number(const std::string& option, const std::string& text, const char* unit);
// The same check of a value given as a number (a program's field rather than a command line's text): finite, > 0.
double check_positive_number(const std::string& option, double value, const char* unit);

// A finite number in [low, high]; the message says "OPTION must be in [LOW, HIGH]UNIT (got VALUE)", e.g. unit " m".
double parse_number_in(const std::string& option, const std::string& text, double low, double high, const char* unit);

// A plain decimal whole number in [min, max], so "1.5", "1e2" and "+3" are refused rather than read as something
// else; nullopt otherwise (the caller's message says what the option takes).
std::optional<std::uint64_t> whole_number(const std::string& text, std::uint64_t min, std::uint64_t max);

// The fields of "A,B,C" split at `separator`: empty fields kept, so "ana,,exp" is an error rather than two cases.
std::vector<std::string> split_fields(const std::string& text, char separator);

// ana | exp | impulse | a number in [0, 1]. Throws UsageError naming `option` and what is accepted.
core::Restitution parse_restitution(const std::string& option, const std::string& text);
// An energy ratio given as a number: in [0, 1], with parse_restitution's message.
core::Restitution restitution_value(const std::string& option, double value);

// The collapse factor kappa: a finite number >= 1 (collapse cannot come before x_inst).
double parse_kappa(const std::string& option, const std::string& text);
double check_kappa(const std::string& option, double kappa);

// linear | full.
core::ModelKind parse_model(const std::string& option, const std::string& text);
const char* model_name(core::ModelKind kind);

// shed | finish (core::WorkOverflow: what the budgeted fixed-point engine does when its queue is full).
core::WorkOverflow parse_work_overflow(const std::string& option, const std::string& text);
const char* work_overflow_name(core::WorkOverflow overflow);

// Quotes user text for a message: printable and bounded, so a stray binary argument cannot garble the terminal.
std::string quoted(const std::string& text);

// Input paths, checked before anything is opened: a FIFO with no writer would block the tool forever and a device
// such as /dev/zero would never end, so only what the option reads is accepted. `what` completes "expected ...",
// e.g. "a record file". Throws UsageError "OPTION PATH: does not exist (expected WHAT)", "... is a directory",
// "... is a FIFO (named pipe), not a regular file", "... cannot be read: REASON".
void check_input_file(const std::string& option, const std::string& path, const char* what);
// The same for a directory (a suite directory): it must exist and be a directory.
void check_input_directory(const std::string& option, const std::string& path, const char* what);
// "a FIFO (named pipe)", "a character device", "a directory", ... for the file type of `mode` (struct stat st_mode).
const char* file_kind_text(unsigned mode);

// Shortest text that reads back as the same double ("0.05", not "0.050000000000000003").
std::string number_text(double value);

}  // namespace rockwatch::options
