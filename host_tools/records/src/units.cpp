// Acceleration units of record files and their factors to m/s².
#include <algorithm>
#include <array>
#include <cctype>
#include <optional>
#include <string>
#include <string_view>

#include "rockwatch/records/record.hpp"

namespace rockwatch::records {

namespace {

struct UnitSpelling {
  std::string_view text;  // lower case, no blanks
  AccelUnit unit;
};

// Spellings seen in record headers and column names. Matched case-insensitively, so "G", "Gal" and "M/S2" work;
// "ms2" and "m/s/s" are common in column suffixes (`accel_ms2`) and ITACA headers (`m/s/s`).
constexpr std::array<UnitSpelling, 24> kSpellings{{
    {"g", AccelUnit::g},           {"mps2", AccelUnit::mps2},
    {"ms2", AccelUnit::mps2},      {"ms-2", AccelUnit::mps2},
    {"m/s2", AccelUnit::mps2},     {"m/s^2", AccelUnit::mps2},
    {"m/s**2", AccelUnit::mps2},   {"m/s/s", AccelUnit::mps2},
    {"m/sec2", AccelUnit::mps2},   {"m/sec/sec", AccelUnit::mps2},
    {"cmps2", AccelUnit::cmps2},   {"cms2", AccelUnit::cmps2},
    {"cm/s2", AccelUnit::cmps2},   {"cm/s^2", AccelUnit::cmps2},
    {"cm/s**2", AccelUnit::cmps2}, {"cm/s/s", AccelUnit::cmps2},
    {"cm/sec2", AccelUnit::cmps2}, {"cm/sec/sec", AccelUnit::cmps2},
    {"gal", AccelUnit::cmps2},     {"mmps2", AccelUnit::mmps2},
    {"mm/s2", AccelUnit::mmps2},   {"mm/s^2", AccelUnit::mmps2},
    {"mm/s**2", AccelUnit::mmps2}, {"mm/s/s", AccelUnit::mmps2},
}};

}  // namespace

std::optional<AccelUnit> parse_accel_unit(std::string_view text) {
  std::string folded;
  folded.reserve(text.size());
  for (const char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) != 0) continue;
    folded.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  // "m/s²" is written with a UTF-8 superscript two; fold it to the ASCII spelling.
  const std::string_view superscript_two = "\xC2\xB2";
  for (auto pos = folded.find(superscript_two); pos != std::string::npos; pos = folded.find(superscript_two)) {
    folded.replace(pos, superscript_two.size(), "2");
  }
  const auto match =
      std::find_if(kSpellings.begin(), kSpellings.end(), [&folded](const UnitSpelling& s) { return s.text == folded; });
  if (match == kSpellings.end()) return std::nullopt;
  return match->unit;
}

std::string_view accel_unit_name(AccelUnit unit) {
  switch (unit) {
    case AccelUnit::g:
      return "g";
    case AccelUnit::mps2:
      return "mps2";
    case AccelUnit::cmps2:
      return "cmps2";
    case AccelUnit::mmps2:
      return "mmps2";
  }
  return "unknown";
}

double accel_unit_to_mps2(AccelUnit unit, double g_mps2) {
  switch (unit) {
    case AccelUnit::g:
      return g_mps2;
    case AccelUnit::mps2:
      return 1.0;
    case AccelUnit::cmps2:
      return 0.01;
    case AccelUnit::mmps2:
      return 0.001;
  }
  return 1.0;
}

}  // namespace rockwatch::records
