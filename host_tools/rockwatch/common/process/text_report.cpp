#include "common/process/text_report.hpp"

#include <cstdarg>
#include <cstddef>
#include <cstdio>

#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, args);
  va_end(args);
  std::string text;
  if (n > 0) {
    text.resize(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(text.data(), text.size(), fmt, again);
    text.resize(static_cast<std::size_t>(n));
  }
  va_end(again);
  return text;
}

void line(std::string& out, const char* label, const std::string& text) { out += format("  %-24s %s\n", label, text.c_str()); }

nlohmann::ordered_json number_or_null(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

std::string time_text(const std::optional<double>& t_s, const char* when_absent) {
  return t_s ? format("t = %.4f s", *t_s) : std::string(when_absent);
}

std::string file_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string format_name(const std::string& format_id) {
  if (format_id == "peer-at2") return "PEER AT2";
  if (format_id == "plain") return "plain columns";
  if (format_id == "esm") return "ESM ASCII";
  if (format_id == "itaca-cor-acc") return "ITACA .cor.acc";
  if (format_id == "miniseed") return "miniSEED";
  if (format_id == "rockwatch-suite") return "rockwatch suite set file";
  return format_id;
}

std::string printable(std::string text) {
  for (char& c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) c = '?';
  }
  return text;
}

std::string shell_quoted(const std::string& argument) {
  const bool plain = !argument.empty() && argument.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                                      "0123456789_./:,=+-@%") == std::string::npos;
  if (plain) return argument;
  std::string quoted_text = "'";
  for (const char c : argument) quoted_text += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted_text + "'";
}

std::string spectrum_text(const core::SpectrumShape& s) {
  return std::string(core::spectrum_name(s.kind)) + ": p " + number_text(s.p) + ", TB " + number_text(s.tb_s) +
         " s, TC " + number_text(s.tc_s) + " s, TD " + number_text(s.td_s) + " s";
}

}  // namespace rockwatch::cli
