// The instability alarm (levels, hold time, latch, reason bitmask): pure integer logic, the same for every
// arithmetic. The physical conditions it acts on are evaluated by the engine in its own arithmetic
// (instability_indicators.hpp for double/float, FixedRockingStepper::indicators() for fixed point).
//
// Levels rise at once; they fall only after the conditions have stayed below the current level's entry
// condition for hold_samples consecutive samples (then straight to the level the conditions give); COLLAPSED
// is latched until reset().
#pragma once

#include <cstdint>

namespace rockwatch::core {

// Values are part of the message format (firmware/lcmtypes): append, never renumber.
enum class AlarmLevel : std::uint8_t { quiet = 0, rocking = 1, warning = 2, imminent = 3, collapsed = 4 };

constexpr const char* alarm_level_name(AlarmLevel l) {
  switch (l) {
    case AlarmLevel::quiet: return "QUIET";
    case AlarmLevel::rocking: return "ROCKING";
    case AlarmLevel::warning: return "WARNING";
    case AlarmLevel::imminent: return "IMMINENT";
    case AlarmLevel::collapsed: return "COLLAPSED";
  }
  return "?";
}

// Reason bits. A bit keeps its meaning forever: new reasons take new bits, retired bits are never reused.
namespace alarm_reason {
inline constexpr std::uint32_t moving = 1u << 0;                 // the wall is rocking (not at rest)
inline constexpr std::uint32_t over_warning_displacement = 1u << 1;  // |x| ≥ λ_w·x_inst
inline constexpr std::uint32_t energy_over_barrier_outward = 1u << 2;  // E ≥ E_barrier while moving outward
inline constexpr std::uint32_t over_instability_displacement = 1u << 3;  // |x| ≥ x_inst
inline constexpr std::uint32_t over_collapse_displacement = 1u << 4;  // |x| ≥ κ·x_inst (this sample or latched)
inline constexpr std::uint32_t held = 1u << 5;                   // level held by the hold time; conditions are lower
inline constexpr std::uint32_t input_invalid = 1u << 6;          // G = g + v̈ ≤ 0 or unusable input: state held
inline constexpr std::uint32_t arithmetic_saturated = 1u << 7;   // a fixed-point quantity hit its range limit
// Set by the monitor when it runs the wall observer (core/wall_observer.hpp), never by the alarm itself: which state
// the alarm saw, and whether a sensor fault coincides with it (an alarm never follows a sensor fault silently).
inline constexpr std::uint32_t measured = 1u << 8;         // the state was corrected by the wall sensors within the dropout time
inline constexpr std::uint32_t predicted = 1u << 9;        // observer on but no usable sensor: the model alone
inline constexpr std::uint32_t sensor_fault = 1u << 10;    // a sensor fault (observer_flag::faults) was raised at this sample
}  // namespace alarm_reason

// What the engine found at the end of a sample.
struct AlarmConditions {
  bool moving = false;
  bool over_warning_displacement = false;
  bool energy_over_barrier_outward = false;
  bool over_instability_displacement = false;
  bool over_collapse_displacement = false;
  bool input_invalid = false;
  bool arithmetic_saturated = false;
};

// Energy margin: the wall is certain to pass x_inst in free motion once E ≥ E_barrier moving outward, but the ground
// can still pull it back; the margin trades lead time for false alarms (survivors flagged). 1.5 is the default: the
// longest lead with the false-alarm rate under 0.05 in every r / vertical case of the default study (the figures per
// margin: docs/BENCHMARKS.md, "The alarm's energy margin").
struct AlarmSettings {
  double lambda_warning = 0.4;  // WARNING at |x| ≥ λ_w·x_inst [-], 0 < λ_w ≤ 1 (0.4: the NTC 2008 allowable)
  double hold_s = 1.0;          // time below a level's entry condition before the level falls [s], ≥ 0
  double energy_margin = 1.5;   // IMMINENT by energy when E ≥ margin·E_barrier moving outward [-], ≥ 1 (see above)
  // IMMINENT also when E ≥ E_barrier moving outward and the predicted time to x_inst under zero further input is at
  // most this [s] (the wall about to pass x_inst in free motion; reason bit energy_over_barrier_outward); 0 = off.
  // 0.13 with energy_min_x 0.5 since 2026-12-01 (0 and 0 before; SPEC §11 "The alarm's defaults of 2026-12-01"):
  // together more lead and fewer false alarms than either alone or neither, on the truths and the synthetic studies.
  double imminent_horizon_s = 0.13;
  // IMMINENT by the energy margin only from |x| ≥ this × x_inst [-] (0 = everywhere): a wall near the
  // vertical with E ≥ margin·E_barrier is far from its barrier in time, and the ground's next reversal often stops it
  // (SPEC §11 "The energy rule near the vertical"). Not applied to the horizon rule or to |x| ≥ x_inst.
  double energy_min_x = 0.5;
};

// The ranges of the settings, one check each (callers name the field at fault); alarm_settings_valid: all of them.
inline bool lambda_warning_valid(double v) { return v > 0.0 && v <= 1.0; }     // (0, 1]
inline bool hold_valid(double s) { return s >= 0.0 && s <= 3600.0; }           // [0, 3600] s
inline bool energy_margin_valid(double m) { return m >= 1.0 && m <= 100.0; }   // [1, 100]
inline bool imminent_horizon_valid(double s) { return s >= 0.0 && s <= 10.0; }   // [0, 10] s
inline bool energy_min_x_valid(double f) { return f >= 0.0 && f <= 1.0; }        // [0, 1]

inline bool alarm_settings_valid(const AlarmSettings& s) {
  return lambda_warning_valid(s.lambda_warning) && hold_valid(s.hold_s) && energy_margin_valid(s.energy_margin) &&
         imminent_horizon_valid(s.imminent_horizon_s) && energy_min_x_valid(s.energy_min_x);
}

// Samples of the hold time at a sample interval dt_s (rounded to nearest). Initialisation-time code.
inline std::uint32_t hold_samples(const AlarmSettings& s, double dt_s) {
  const double n = s.hold_s / dt_s + 0.5;
  return n >= 4.0e9 ? 4000000000u : static_cast<std::uint32_t>(n);
}

struct AlarmUpdate {
  AlarmLevel level = AlarmLevel::quiet;     // after this sample
  AlarmLevel previous = AlarmLevel::quiet;  // before this sample
  std::uint32_t reasons = 0;                // alarm_reason bits of this sample
  bool changed = false;                     // level != previous
};

class InstabilityAlarm {
 public:
  void init(std::uint32_t hold_samples) {
    hold_samples_ = hold_samples;
    reset();
  }
  void reset() {
    level_ = AlarmLevel::quiet;
    below_count_ = 0;
  }

  // Constant work: a fixed sequence of comparisons, no loops.
  AlarmUpdate update(const AlarmConditions& c) {
    std::uint32_t reasons = 0;
    if (c.moving) reasons |= alarm_reason::moving;
    if (c.over_warning_displacement) reasons |= alarm_reason::over_warning_displacement;
    if (c.energy_over_barrier_outward) reasons |= alarm_reason::energy_over_barrier_outward;
    if (c.over_instability_displacement) reasons |= alarm_reason::over_instability_displacement;
    if (c.over_collapse_displacement) reasons |= alarm_reason::over_collapse_displacement;
    if (c.input_invalid) reasons |= alarm_reason::input_invalid;
    if (c.arithmetic_saturated) reasons |= alarm_reason::arithmetic_saturated;

    AlarmLevel target = AlarmLevel::quiet;
    if (c.over_collapse_displacement) {
      target = AlarmLevel::collapsed;
    } else if (c.energy_over_barrier_outward || c.over_instability_displacement) {
      target = AlarmLevel::imminent;
    } else if (c.over_warning_displacement) {
      target = AlarmLevel::warning;
    } else if (c.moving) {
      target = AlarmLevel::rocking;
    }

    AlarmUpdate u;
    u.previous = level_;
    if (level_ == AlarmLevel::collapsed) {
      reasons |= alarm_reason::over_collapse_displacement;  // latched
    } else if (target >= level_) {
      level_ = target;
      below_count_ = 0;
    } else if (++below_count_ > hold_samples_) {
      level_ = target;
      below_count_ = 0;
    } else {
      reasons |= alarm_reason::held;
    }
    u.level = level_;
    u.reasons = reasons;
    u.changed = u.level != u.previous;
    return u;
  }

  AlarmLevel level() const { return level_; }

 private:
  std::uint32_t hold_samples_ = 0;
  AlarmLevel level_ = AlarmLevel::quiet;
  std::uint32_t below_count_ = 0;
};

}  // namespace rockwatch::core
