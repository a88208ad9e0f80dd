#include "rockwatch/options/option_values.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/records/text_format.hpp"

namespace rockwatch::options {

namespace {

// The readers' strict parser: whole token, leading '+' allowed, NaN/Inf and overflow refused.
std::optional<double> strict_number(const std::string& text) {
  double value = 0.0;
  if (text::parse_number(text, value) != text::NumberStatus::ok) return std::nullopt;
  return value;
}

}  // namespace

std::string quoted(const std::string& text) { return text::shown(text); }

std::string number_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec != std::errc{}) return "?";
  return std::string(buffer, result.ptr);
}

std::optional<std::uint64_t> whole_number(const std::string& text, std::uint64_t min, std::uint64_t max) {
  std::uint64_t value = 0;
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (!digits || result.ec != std::errc{} || value < min || value > max) return std::nullopt;
  return value;
}

std::vector<std::string> split_fields(const std::string& text, char separator) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = text.find(separator, start);
    fields.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) return fields;
    start = at + 1;
  }
}

double parse_finite_number(const std::string& option, const std::string& text) {
  const std::optional<double> value = strict_number(text);
  if (!value) throw UsageError(option + " expects a finite number (got " + quoted(text) + ")");
  return *value;
}

double parse_positive_number(const std::string& option, const std::string& text, const char* unit) {
  return check_positive_number(option, parse_finite_number(option, text), unit);
}

double check_finite_number(const std::string& option, double value) {
  if (!std::isfinite(value)) throw UsageError(option + " expects a finite number (got " + quoted(number_text(value)) + ")");
  return value;
}

double check_positive_number(const std::string& option, double value, const char* unit) {
  check_finite_number(option, value);
  if (!(value > 0.0)) throw UsageError(option + " must be > 0" + unit + " (got " + number_text(value) + ")");
  return value;
}

double parse_number_in(const std::string& option, const std::string& text, double low, double high, const char* unit) {
  const double value = parse_finite_number(option, text);
  if (!(value >= low && value <= high)) {
    throw UsageError(option + " must be in [" + number_text(low) + ", " + number_text(high) + "]" + unit + " (got " +
                     number_text(value) + ")");
  }
  return value;
}

core::Restitution parse_restitution(const std::string& option, const std::string& text) {
  core::Restitution r;
  if (text == "ana") {
    r.kind = core::RestitutionKind::ana;
  } else if (text == "exp") {
    r.kind = core::RestitutionKind::exp;
  } else if (text == "impulse") {
    r.kind = core::RestitutionKind::impulse;
  } else {
    const std::optional<double> value = strict_number(text);
    if (!value || *value < 0.0 || *value > 1.0) {
      throw UsageError(option + " must be ana, exp, impulse or an energy ratio in [0, 1] (got " + quoted(text) + ")");
    }
    r.kind = core::RestitutionKind::value;
    r.value = *value;
  }
  return r;
}

core::Restitution restitution_value(const std::string& option, double value) {
  if (!(value >= 0.0 && value <= 1.0)) {
    throw UsageError(option + " must be ana, exp, impulse or an energy ratio in [0, 1] (got " +
                     quoted(number_text(value)) + ")");
  }
  core::Restitution r;
  r.kind = core::RestitutionKind::value;
  r.value = value;
  return r;
}

double parse_kappa(const std::string& option, const std::string& text) {
  return check_kappa(option, parse_finite_number(option, text));
}

double check_kappa(const std::string& option, double kappa) {
  check_finite_number(option, kappa);
  if (!(kappa >= 1.0)) {
    throw UsageError(option + " must be >= 1: collapse cannot come before x_inst (got " + number_text(kappa) + ")");
  }
  return kappa;
}

core::ModelKind parse_model(const std::string& option, const std::string& text) {
  if (text == "linear") return core::ModelKind::linear;
  if (text == "full") return core::ModelKind::full;
  throw UsageError(option + " must be linear or full (got " + quoted(text) + ")");
}

const char* model_name(core::ModelKind kind) { return kind == core::ModelKind::full ? "full" : "linear"; }

core::WorkOverflow parse_work_overflow(const std::string& option, const std::string& text) {
  if (text == "shed") return core::WorkOverflow::shed;
  if (text == "finish") return core::WorkOverflow::finish;
  throw UsageError(option + " must be shed or finish (got " + quoted(text) + ")");
}

const char* work_overflow_name(core::WorkOverflow overflow) {
  return overflow == core::WorkOverflow::finish ? "finish" : "shed";
}

const char* file_kind_text(unsigned mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a regular file";
  return "not a regular file";
}

namespace {

// stat() of an input path, or a UsageError naming the option: missing, or not reachable.
struct stat input_status(const std::string& option, const std::string& path, const char* what) {
  if (path.empty()) throw UsageError(option + " needs a file name");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int code = errno;
    if (code == ENOENT || code == ENOTDIR) {
      throw UsageError(option + " " + path + ": cannot open the file: it does not exist (expected " + what +
                       ")");
    }
    throw UsageError(option + " " + path + ": cannot be read: " + std::strerror(code) + " (expected " + what +
                     ")");
  }
  return st;
}

}  // namespace

void check_input_file(const std::string& option, const std::string& path, const char* what) {
  const struct stat st = input_status(option, path, what);
  if (S_ISDIR(st.st_mode)) throw UsageError(option + " " + path + ": is a directory, expected " + what);
  if (!S_ISREG(st.st_mode)) {
    // A FIFO without a writer blocks the open for ever, a device such as /dev/zero never ends.
    throw UsageError(option + " " + path + ": is " + file_kind_text(st.st_mode) +
                     ", not a regular file: expected " + what);
  }
  if (::access(path.c_str(), R_OK) != 0) {
    throw UsageError(option + " " + path + ": cannot be read: " + std::strerror(errno) + " (expected " + what +
                     ")");
  }
}

void check_input_directory(const std::string& option, const std::string& path, const char* what) {
  if (path.empty()) throw UsageError(option + " needs a directory name");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int code = errno;
    throw UsageError(option + " " + path + ": " +
                     (code == ENOENT || code == ENOTDIR ? std::string("no such directory")
                                                        : std::string("cannot be read: ") + std::strerror(code)) +
                     " (expected " + what + ")");
  }
  if (!S_ISDIR(st.st_mode)) {
    throw UsageError(option + " " + path + ": is " + file_kind_text(st.st_mode) + ", expected " + what);
  }
}

}  // namespace rockwatch::options
