// Elastic design spectrum shapes (SPEC §5): the EC8 four-branch form, normalised to a_g = 1.
//   1 + (T/TB)(p − 1)   for T < TB
//   p                   for TB ≤ T ≤ TC
//   p·TC/T              for TC < T ≤ TD
//   p·TC·TD/T²          for T > TD
// Se(T) = a_g · shape(T). Header-only, no heap, no exceptions.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace rockwatch::core {

// Stable codes; new kinds are appended.
enum class SpectrumKind : std::uint8_t {
  npr9998_2015 = 0,  // horizontal, back-calculated from the paper's two static results (SPEC §5) — say so in output
  ec8_1A = 1,        // EC8 type 1, ground A
  ec8_2A = 2,        // EC8 type 2, ground A
  custom = 3,        // user's (p, TB, TC, TD), e.g. from the NEN web tool
  vertical_default = 4,  // EC8 vertical shape, the default for the vertical records (SPEC §5)
};

struct SpectrumShape {
  SpectrumKind kind = SpectrumKind::npr9998_2015;
  double p = 2.5;      // plateau amplification [-]
  double tb_s = 0.15;  // start of the plateau [s]
  double tc_s = 0.40;  // end of the plateau [s]
  double td_s = 0.67;  // start of the constant-displacement branch [s]
};

inline constexpr SpectrumShape spectrum_npr9998_2015() { return {SpectrumKind::npr9998_2015, 2.5, 0.15, 0.40, 0.67}; }
inline constexpr SpectrumShape spectrum_ec8_1A() { return {SpectrumKind::ec8_1A, 2.5, 0.15, 0.40, 2.0}; }
inline constexpr SpectrumShape spectrum_ec8_2A() { return {SpectrumKind::ec8_2A, 2.5, 0.05, 0.25, 1.2}; }
inline constexpr SpectrumShape spectrum_vertical_default() {
  return {SpectrumKind::vertical_default, 3.0, 0.05, 0.15, 1.0};
}
inline constexpr SpectrumShape spectrum_custom(double p, double tb_s, double tc_s, double td_s) {
  return {SpectrumKind::custom, p, tb_s, tc_s, td_s};
}

// 0 < TB < TC < TD and p ≥ 1, all finite.
inline bool spectrum_valid(const SpectrumShape& s) {
  return std::isfinite(s.p) && std::isfinite(s.tb_s) && std::isfinite(s.tc_s) && std::isfinite(s.td_s) &&
         s.p >= 1.0 && s.tb_s > 0.0 && s.tb_s < s.tc_s && s.tc_s < s.td_s;
}

// Normalised spectral acceleration Se(T)/a_g at period T ≥ 0 [s].
inline double spectrum_shape(const SpectrumShape& s, double period_s) {
  if (period_s < s.tb_s) return 1.0 + period_s / s.tb_s * (s.p - 1.0);
  if (period_s <= s.tc_s) return s.p;
  if (period_s <= s.td_s) return s.p * s.tc_s / period_s;
  return s.p * s.tc_s * s.td_s / (period_s * period_s);
}

inline const char* spectrum_name(SpectrumKind k) {
  switch (k) {
    case SpectrumKind::npr9998_2015: return "npr9998-2015";
    case SpectrumKind::ec8_1A: return "ec8-1A";
    case SpectrumKind::ec8_2A: return "ec8-2A";
    case SpectrumKind::custom: return "custom";
    case SpectrumKind::vertical_default: return "vertical-default";
  }
  return "?";
}

// The npr9998-2015 parameters are not public: outputs that use them must carry this label.
inline const char* spectrum_provenance(SpectrumKind k) {
  switch (k) {
    case SpectrumKind::npr9998_2015: return "back-calculated from the design paper's static results (NPR 9998:2015 bedrock parameters are not public)";
    case SpectrumKind::ec8_1A: return "EN 1998-1 type 1, ground type A";
    case SpectrumKind::ec8_2A: return "EN 1998-1 type 2, ground type A";
    case SpectrumKind::custom: return "user-supplied parameters";
    case SpectrumKind::vertical_default: return "EN 1998-1 vertical shape (default for bedrock vertical motion; a_vg = a_g)";
  }
  return "";
}

// Parses "npr9998-2015", "ec8-1A", "ec8-2A", "vertical-default" (custom needs its parameters: not parsed here).
inline bool parse_spectrum_name(const char* text, SpectrumShape& out) {
  if (std::strcmp(text, "npr9998-2015") == 0) out = spectrum_npr9998_2015();
  else if (std::strcmp(text, "ec8-1A") == 0) out = spectrum_ec8_1A();
  else if (std::strcmp(text, "ec8-2A") == 0) out = spectrum_ec8_2A();
  else if (std::strcmp(text, "vertical-default") == 0) out = spectrum_vertical_default();
  else return false;
  return true;
}

}  // namespace rockwatch::core
