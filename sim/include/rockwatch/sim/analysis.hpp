// Double-precision response analysis of a wall to a ground motion: the verified engine every tool uses.
// Runs core::StepperAlarmChain over a record sample by sample (each sample interval in ceil(dt / max_step)
// sub-steps, the input linear between samples; the alarm once per sample, as the monitor does), then decides the outcome after the
// record by energy (SPEC §4.3), and summarises the response.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/core/work_meter.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::sim {

// Ground acceleration sampled at a constant interval; linear between samples (SPEC §4).
struct GroundMotion {
  double dt_s = 0.0;                    // sample interval [s]
  std::vector<double> ug_mps2;          // horizontal out-of-plane ü [m/s²]; ü > 0 pushes the wall towards x < 0
  std::vector<double> vg_mps2;          // vertical v̈ [m/s², up +]; empty = none; else same length as ug
  double duration_s() const { return ug_mps2.empty() ? 0.0 : dt_s * double(ug_mps2.size() - 1); }
};

// The engine's arithmetic: the verified double-precision engine, or the real-time fixed-point engine
// (core/fixed_rocking_stepper.hpp; linear model only) that the monitor runs.
enum class Arithmetic : std::uint8_t { double_precision = 0, fixed_point = 1 };

struct AnalysisOptions {
  Arithmetic arithmetic = Arithmetic::double_precision;
  core::ModelKind model = core::ModelKind::linear;
  core::Restitution restitution{};      // default r_exp
  double kappa = 2.0;                   // collapse at κ·x_inst [-], ≥ 1
  double max_step_s = core::kDefaultMaxStep_s;  // longest integration step: ceil(dt / max_step) sub-steps per
                                        // record sample (at most core::kMaxSubsteps) [s]
  std::optional<double> t_end_s;        // integrate the input to this time (zero input past the record) [s]
  // A release (snap-back) test: the wall starts at x = initial_x_m with ẋ = 0 instead of at rest, and the free
  // motion after the record goes on until the wall is at rest (or collapses), not only until it is safe, so the
  // whole decay is integrated. None: the wall starts at rest [m].
  std::optional<double> initial_x_m;
  double free_motion_limit_s = 600.0;   // longest free motion after t_end before giving up [s]
  bool keep_history = false;            // fill AnalysisResult::history (one row per integration step)
  std::size_t max_impacts_kept = 32;    // impacts listed in AnalysisResult::impacts
  bool evaluate_alarm = false;          // run the instability alarm every integration step (AnalysisResult::alarm)
  core::AlarmSettings alarm{};
  std::size_t max_alarm_transitions_kept = 64;  // transitions listed in AlarmSummary::transitions
  // The wall observer (core/wall_observer.hpp). When wall_sensors is set (not owned; utime ascending, in µs on the
  // record's clock: t = 0 at its first sample), the observer corrects the stepper's state after every integration
  // step with the samples whose time has come (utime ≤ the step end), so the history, the summary and the alarm are
  // those of the fused state (AnalysisResult::observer). Null: open loop, exactly as without these fields.
  const std::vector<core::WallSensorSample>* wall_sensors = nullptr;
  core::ObserverOptions observer{};
  int observer_r_after_impacts = 5;     // ObserverSummary::r_estimate_after_impacts after this many impacts
  // ObserverSummary::r_estimate_before_time / x_inst_estimate_before_time_m: the estimates as they stood before the
  // input sample whose interval holds this time (e.g. another wall's impact, AnalysisResult::t_counted_impact_s) [s].
  std::optional<double> observer_estimate_before_s;
  // n > 0: AnalysisResult::t_counted_impact_s is the time of counted impact number n (|ẋ⁻| ≥ 1 mm/s).
  int mark_counted_impact = 0;
  // When set (not owned), receives the engine's input of every sample as run, in double before any conversion: the
  // input the engine was reset with, then one {ü, v̈} [m/s²] per record sample (the engine sub-steps between them;
  // then the zeros of the free motion after the record), up to where the analysis stopped. `rockwatch simulate --engine-input-out` writes it for
  // the Cortex-M4 replay (scripts/m4-replay.sh), which must run exactly the steps the host ran.
  std::vector<std::array<double, 2>>* engine_inputs_out = nullptr;
  // The monitor's latency (fixed point with evaluate_alarm, open loop): > 0 also runs the engine's inputs through the
  // monitor's budgeted engine (core::StepperAlarmChain::call with this many work units a call; the monitor's default
  // is core::kDefaultWorkBudgetUnits; docs/FIXED_POINT.md "carry-over") and reports when each alarm would be
  // published (AlarmSummary::published). The answers are the same; 0: not measured.
  std::int32_t work_budget_units = 0;
  // And what that engine does when its queue is full (core::WorkOverflow: shed, or finish beyond the budget).
  core::WorkOverflow work_overflow = core::WorkOverflow::shed;
};

// One change of alarm level, at the end of the integration step where it happened.
struct AlarmTransition {
  double t_s = 0.0;                          // [s]
  core::AlarmLevel level = core::AlarmLevel::quiet;
  core::AlarmLevel previous = core::AlarmLevel::quiet;
  std::uint32_t reasons = 0;                 // core::alarm_reason bits
  double x_m = 0.0;                          // mid-height displacement at the transition [m]
  double xd_mps = 0.0;                       // [m/s]
  std::optional<double> t_to_instability_s;  // predicted time to |x| = x_inst under zero further input [s]
  double energy_ratio = 0.0;                 // E / E_barrier in free motion [-]
};

struct AlarmSummary {
  bool evaluated = false;
  core::AlarmLevel max_level = core::AlarmLevel::quiet;
  std::optional<double> t_first_warning_s;   // first step end at WARNING or above [s]
  std::optional<double> t_first_imminent_s;  // first step end at IMMINENT or above [s]
  std::optional<double> t_first_collapsed_s; // first step end at COLLAPSED [s]
  std::size_t n_transitions = 0;             // all transitions
  std::vector<AlarmTransition> transitions;  // the first max_alarm_transitions_kept
  // As the monitor publishes it (AnalysisOptions::work_budget_units): a sample whose work exceeds a call's budget is
  // published at the call of a later input sample.
  // The calls' tally (late samples, the longest wait, samples shed, overruns, the most work in a call) as the
  // firmware's engine counts it.
  struct Published : core::WorkTally {
    bool measured = false;
    std::optional<double> t_first_imminent_s;  // time of the input sample whose call published IMMINENT or above [s]
    std::uint32_t imminent_late_calls = 0;      // calls that sample waited
    std::optional<double> t_first_collapsed_s; // ... COLLAPSED [s]
  } published;
};

// What the observer did over the analysis (AnalysisOptions::wall_sensors).
struct ObserverSummary {
  bool evaluated = false;
  double r_estimate = 0.0;              // r̂ = ê² at the end [-]
  double sigma_r = 0.0;                 // its standard deviation [-]
  double bias_estimate_m = 0.0;         // zero offset of the displacement transducer [m]
  double sigma_bias_m = 0.0;            // [m]
  double x_noise_m = 0.0;               // the transducer's σ the filter used at the end: told, or measured at rest [m]
  std::int32_t x_noise_readings = 0;    // readings at rest before the shaking that measured it [-]
  double sigma_x_m = 0.0;               // σ of x at the end [m]
  double x_rms_innovation_m = 0.0;      // RMS of the accepted displacement innovations [m]
  std::int64_t n_updates = 0;           // accepted displacement updates
  std::int64_t n_accel_updates = 0;     // accepted acceleration updates
  std::int64_t n_rejected = 0;          // innovations gated out
  std::uint32_t flags_seen = 0;         // core::observer_flag bits of any step
  core::ObserverCounters counters{};    // all of the observer's counters
  std::size_t samples_given = 0;        // samples in AnalysisOptions::wall_sensors
  std::size_t samples_pushed = 0;       // handed to the observer (the others came after the end of the analysis)
  std::size_t steps_sensor_lost = 0;    // steps that ended with the sensor lost (model alone)
  std::optional<double> r_estimate_after_impacts;  // r̂ just before impact number n+1 (n = observer_r_after_impacts
                                                   // counted impacts, |ẋ⁻| ≥ 1 mm/s), or at the end after n; none
                                                   // with fewer impacts [-]
  // The wall's capacity and stiffness (SPEC §9, side +1, ü = v̈ = 0) at the end, with their σ: x_inst = c/k,
  // ω = √k, c, k per unit p1, the energy barrier per unit p1 c²/(2k); the scales κc, κk on the nominal c, k.
  double x_inst_estimate_m = 0.0, sigma_x_inst_m = 0.0;
  double omega_estimate_rps = 0.0, sigma_omega_rps = 0.0;
  double c_estimate_mps2 = 0.0, sigma_c_mps2 = 0.0;
  double k_estimate_ps2 = 0.0, sigma_k_ps2 = 0.0;
  double barrier_estimate_m2ps2 = 0.0;
  double capacity_scale = 1.0, sigma_capacity_scale = 0.0;
  double stiffness_scale = 1.0, sigma_stiffness_scale = 0.0;
  std::optional<double> x_inst_estimate_after_impacts_m;  // x̂_inst when r_estimate_after_impacts was taken [m]
  // The published σ of r̂ and of x̂_inst at that same moment (the end's sigma_r, sigma_x_inst_m are later) [-, m].
  std::optional<double> sigma_r_after_impacts, sigma_x_inst_after_impacts_m;
  // The same count over rocking impacts only: those after a half-cycle of the fused wall whose |x| peaked at
  // ≥ inform_peak_noises × x_noise_m (5 mm by default: the size from which the observer learns √r, SPEC §8). The
  // first impacts of a record are often smaller, and r̂ after them is the prior. [-]
  int rocking_impacts = 0;
  std::optional<double> r_estimate_after_rocking_impacts, sigma_r_after_rocking_impacts;
  // r̂ and x̂_inst before AnalysisOptions::observer_estimate_before_s (none when not set or not reached) [-, m].
  std::optional<double> r_estimate_before_time, x_inst_estimate_before_time_m;
};

struct HistoryRow {
  double t_s, ug_mps2, vg_mps2;         // time [s], inputs [m/s²]
  double x_m, xd_mps, xdd_mps2;         // mid-height displacement and its derivatives
  double alpha1_rad, alpha2_rad;        // block rotations α1 = −x/h1, α2 = x/h2 [rad]
  int side;                             // +1 / −1
};

// The wall observer's estimates as they stood at the end of one input sample (AnalysisOptions::wall_sensors with
// keep_history): what an ensemble forecast from the fused state needs beside it (SPEC §10 "State uncertainty").
struct ObserverHistoryRow {
  double t_s;                           // the sample's end (the time of the history row that ends it) [s]
  double sigma_x_m, sigma_xd_mps;       // the fused state's standard deviations [m], [m/s]
  double sqrt_r;                        // √r̂ [-]
  double capacity_scale, stiffness_scale;  // κc, κk: c and k of the wall over the nominal's [-]
  // A displacement reading was fused within the dropout time (core::observer_flag::x_active of the sample's last
  // step): σ_x and σ_ẋ describe a measured state. Without one the filter's process noise widens them without a
  // measurement to bound them, so the forecast does not take them (SPEC §10 "From the fused state").
  bool x_active = false;
  // For simulate --observer-out (the estimates a lab plots beside its wall): the fused state, r̂, x̂_inst with their
  // σ, and the observer_flag bits of the sample's steps.
  double x_m = 0.0, xd_mps = 0.0;       // the fused state [m], [m/s]
  double r = 0.0, sigma_r = 0.0;        // r̂ and its σ [-]
  double x_inst_m = 0.0, sigma_x_inst_m = 0.0;  // x̂_inst and its σ [m]
  std::uint32_t flags = 0;              // core::observer_flag bits of the sample's steps
};

struct ImpactEvent {
  double t_s;                           // time of the impact [s]
  double v_before_mps, v_after_mps;     // ẋ⁻, ẋ⁺ [m/s]
};

struct AnalysisResult {
  double max_abs_x_m = 0.0;             // max |x| over the analysis [m]
  double t_max_abs_x_s = 0.0;           // when (t_collapse if collapsed) [s]
  bool collapsed = false;               // |x| reached κ·x_inst by t_end
  bool collapse_after_end = false;      // not collapsed by t_end, but free motion after it collapses
  std::optional<double> t_collapse_s;   // time |x| reached κ·x_inst (during or after the record) [s]
  std::optional<double> t_exceed_s;     // first time |x| reached x_inst [s]
  std::optional<double> t_first_motion_s;
  int n_impacts = 0;                    // impacts with |ẋ⁻| ≥ 1 mm/s
  int n_impacts_total = 0;              // every impact (depends on the rest threshold)
  std::optional<double> t_counted_impact_s;  // counted impact number AnalysisOptions::mark_counted_impact [s]
  bool free_motion_undecided = false;   // free motion hit free_motion_limit_s without a verdict
  double x_inst_m = 0.0;                // smaller side [m]
  double threshold_mps2 = 0.0;          // smaller side, with v̈ = 0 [m/s²]
  double r = 0.0;                       // energy ratio used [-]
  double pga_mps2 = 0.0;                // peak |ü| of the input as run [m/s²]
  double dt_s = 0.0;                    // integration step [s]
  double sample_dt_s = 0.0;             // record sample interval: ceil(sample_dt / max_step) sub-steps of dt_s [s]
  double duration_s = 0.0;              // record duration [s]
  double t_end_s = 0.0;                 // end of the forced phase [s]
  double t_final_s = 0.0;               // where integration stopped [s]
  std::vector<ImpactEvent> impacts;     // the first max_impacts_kept impacts
  std::vector<HistoryRow> history;      // when keep_history
  std::vector<ObserverHistoryRow> observer_history;  // when keep_history and wall_sensors: one row per input sample
  AlarmSummary alarm;                   // when evaluate_alarm
  ObserverSummary observer;             // when AnalysisOptions::wall_sensors is set
  Arithmetic arithmetic = Arithmetic::double_precision;
  bool saturated = false;               // fixed point only: a quantity reached its range limit (result unreliable)
  bool verdict_collapse() const { return collapsed || collapse_after_end; }
};

class AnalysisError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws AnalysisError for an invalid wall, option or input (G = g + v̈ ≤ 0, non-finite samples, …).
AnalysisResult analyse(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& options);

// Analytic/sampled input on a step grid, for tests and synthetic pulses: ü(t) sampled at dt from t = 0 to t_end.
template <typename Fn>
GroundMotion sample_motion(Fn&& ug_of_t, double dt_s, double t_end_s) {
  GroundMotion m;
  m.dt_s = dt_s;
  const auto n = static_cast<std::size_t>(t_end_s / dt_s + 0.5);
  m.ug_mps2.reserve(n + 1);
  for (std::size_t k = 0; k <= n; ++k) m.ug_mps2.push_back(ug_of_t(double(k) * dt_s));
  return m;
}

// Peak absolute value [same unit as input].
double peak_abs(const std::vector<double>& v);

}  // namespace rockwatch::sim
