// Text helpers shared by the record readers and the command-line tool: strict number parsing and the
// quoting of user text and numbers in error messages.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>

namespace rockwatch::text {

// A token as it may appear in a message: printable, bounded, so a binary file cannot garble the terminal.
inline std::string shown(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string shown = "'";
  for (std::size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    shown += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
  }
  if (token.size() > kMaxShown) shown += "...";
  shown += "'";
  return shown;
}

// A number for messages: 12 significant digits, so a step computed as 0.03 - 0.01 shows as "0.02", not as
// "0.019999999999999997", while still telling 0.0100001 from 0.01.
inline std::string number_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 12);
  if (result.ec != std::errc{}) return "?";
  return std::string(buffer, result.ptr);
}

enum class NumberStatus { ok, invalid, not_finite, out_of_range };

// The whole token must be one decimal number; "1.5x", "-.12345E-" (cut) and "1,5" are invalid, never 1.5 or -0.12345.
inline NumberStatus parse_number(std::string_view token, double& value) {
  std::string_view body = token;
  // from_chars rejects a leading '+', which spreadsheets and printf("%+e") write.
  if (!body.empty() && body.front() == '+') {
    body.remove_prefix(1);
    if (body.empty() || body.front() == '+' || body.front() == '-') return NumberStatus::invalid;
  }
  if (body.empty()) return NumberStatus::invalid;
  const char* const first = body.data();
  const char* const last = first + body.size();
  double parsed = 0.0;
  const auto result = std::from_chars(first, last, parsed, std::chars_format::general);
  if (result.ec == std::errc::invalid_argument || result.ptr != last) return NumberStatus::invalid;
  if (result.ec == std::errc::result_out_of_range) {
    // Underflow (1e-400) is zero to any accelerometer; overflow (1e999) has no value we could use.
    const std::size_t exponent_at = body.find_first_of("eE");
    const bool negative_exponent =
        exponent_at != std::string_view::npos && exponent_at + 1 < body.size() && body[exponent_at + 1] == '-';
    if (!negative_exponent) return NumberStatus::out_of_range;
    parsed = body.front() == '-' ? -0.0 : 0.0;
  }
  // from_chars accepts "nan", "inf" and "infinity"; a record value must be a measurement.
  if (!std::isfinite(parsed)) return NumberStatus::not_finite;
  value = parsed;
  return NumberStatus::ok;
}

}  // namespace rockwatch::text
