// The wall observer's settings (core::WallObserver, core/wall_observer.hpp), why init() refuses them, and the one
// range check. SI units; every default says what it was chosen against.
#pragma once

#include <cstdint>

namespace rockwatch::core {

// Settings, SI units. Defaults: a displacement transducer of 0.5 mm noise and an accelerometer of 0.05 m/s².
struct ObserverOptions {
  double x_noise_m = 0.5e-3;            // σ of the displacement transducer [m]
  double a_noise_mps2 = 0.05;           // σ of the mid-height accelerometer [m/s²]
  double process_accel_mps2 = 0.2;      // σ of the model's acceleration error per step [m/s²] (docs/BENCHMARKS.md: the choice)
  double r_sigma0 = 0.1;                // initial σ of √r [-]
  double r_walk = 1e-5;                 // random walk of √r per step [-]
  double bias_sigma0_m = 5e-3;          // initial σ of the transducer's zero offset [m]
  double bias_walk_m = 1e-7;            // random walk of the zero offset per step [m]
  double gate_chi2 = 16.0;              // innovation gate, χ² with one degree of freedom (16: 4σ) [-]
  std::int32_t reinit_after = 8;        // consecutive rejections (ground shaking) that re-initialise the motion
  // Consecutive accelerometer rejections, while the displacement agrees and the motion informs the capacity, that
  // re-open the capacity's covariance (0: never). An accelerometer sees c and k directly (ẍ jumps by 2c at the
  // hinge), so a wall whose capacity lies far outside the prior (an overburden: κ ≈ 1.65 at 2 kN/m, 1.97 at 3 kN/m
  // against 1 ± 0.15) has every acceleration gated out; only the few that happen to agree were used, and their
  // selection drove κc, κk the wrong way (to 0.4 on set 11 Y at 0.28 g). SPEC §8; docs/BENCHMARKS.md
  // "Observer evaluation": 16 against 8 (more false alarms on Fp 3 kN/m) and never.
  std::int32_t capacity_reopen_after = 16;
  // Consecutive accelerometer readings that say the wall is at rest (a − ü within the gate of the accelerometer's
  // noise) while the model rocks and its rocking prediction is gated out, the displacement agreeing, that put the
  // model to rest (0: never). A rocking wall's acceleration differs from the ground's by ẍ − G·x/h1, ≈ c_s (1.7 m/s²
  // for the paper wall, 30 σ), which a transducer cannot see when the motion is sub-millimetre: the model chattered
  // where the real wall stood still (or had stopped), and every acceleration was rejected. SPEC §8; docs/BENCHMARKS.md
  // "Observer evaluation": 8 against 4 and never.
  std::int32_t rest_from_accel_after = 8;
  double dropout_s = 0.25;              // no usable displacement sample for this long: sensor lost [s]
  double max_age_s = 0.05;              // older samples (behind the ground stream) are dropped [s]
  // The sample interval the counts in samples mean (reinit_after, stuck_after, capacity_reopen_after,
  // rest_from_accel_after, doubt_window): a reading counts as floor(Δt / this) samples, 1 to 8, Δt the shorter of its
  // interval since its sensor's previous reading and the interval before (a single gap does not count; issue 40).
  // The counts were chosen on sensors at 100 and 200 Hz; at 50 Hz a count of 8 rejections meant 160 ms instead of
  // 80, and the model ran that much longer on a wall it did not describe (docs/BENCHMARKS.md "Model error", "Slower
  // sensors"). Bit-identical at 100 Hz and faster; 0: every reading one sample, whatever its rate (the rule before) [s].
  double count_interval_s = 0.01;
  double x_range_m = 0.5;               // |x_mid| beyond this: out of range [m]
  double a_range_mps2 = 80.0;           // |a_mid| beyond this: out of range [m/s²]
  std::int32_t stuck_after = 40;        // identical consecutive displacement readings while rocking: stuck
  double quiet_fraction = 0.5;          // the ground is quiet when |ü| < this × the smaller start threshold [-]
  double v_min_mps = 0.01;              // |ẋ⁻| floor in the saltation matrix (bounds it at grazing impacts) [m/s]
  double inform_sigmas = 3.0;           // an impact informs √r only when |ẋ⁻| ≥ this × σ(ẋ⁻) and ≥ v_min [-]
  double inform_peak_noises = 10.0;     // … and the half-cycle before it peaked at ≥ this × x_noise [-]
  // The same gate for the accelerometer's updates of κc, κk [-]. At the start of motion (x ≈ 0) a − ü measures the
  // threshold c_s/γ, i.e. κc alone; x_inst = κc/κk · x_inst,nominal then moves with κc while κk keeps its prior. That
  // is right for a wall thinner or thicker than its drawings (κk ≈ 1) and wrong for an overburden or other heights
  // (κk moves with κc): 0 (learn from the first motion) meets the 3 % x_inst goal on the thickness cases but costs the
  // overburden cases their false-alarm rate (Fp 2 kN/m + accel 0.018 → 0.137). For a wall whose overburden and
  // heights are known. SPEC §8; docs/BENCHMARKS.md "Observer evaluation", "The capacity from the first motion".
  double accel_inform_peak_noises = 10.0;
  double capacity_sigma0 = 0.15;        // prior σ of κc and κk (the wall's c and k relative to the nominal) [-]
  double capacity_walk = 0.0;           // random walk of κc and κk per step [-]
  // The prior correlation of κc and κk (issue 40, SPEC §11; opt-in, 0 = independent, as before). κc is learned from
  // the first motion (an accelerometer reads the threshold at once); κk only once the wall has rocked far enough to
  // show its restoring force's decline. x_inst = κc/κk · x_inst,nominal, so with independent priors an overburden or
  // other heights than drawn (which move c and k together) read as a capacity that grew with κc: on a thick wall whose
  // overburdens collapse within a second of the first motion, x̂_inst 80 % high and IMMINENT late. A thickness other
  // than drawn moves c alone, and there the correlation is wrong (x̂_inst after impacts 4 → 15 % off at b × 0.85 on
  // `rockwatch study --alarms --observer`). Measured (docs/BENCHMARKS.md "Model error", "The capacity's prior
  // correlation"): 0.9 brings every robust alarm right on both paper-wall truth sets (held out 56 → 57 of 57), the
  // kept truths' largest x̂_inst error 100 → 33 %, the synthetic study's fused false alarms 3.3 → 2.9 %.
  double capacity_correlation = 0.0;
  // The alarm's margin on the estimated capacity k_σ: it uses x_inst,est − k_σ·σ(x_inst) (and λ_w times it, the
  // energy barrier and the time to instability of that x_inst with the estimated k), at least 0.3 × nominal.
  // Measured on `rockwatch study --alarms --observer` (3520 runs, 972 true collapses; recall 1.0 for every k_σ):
  //   k_σ      0      0.5    1      2
  //   false    3.2 %  4.3 %  6.1 %  14.1 %   (nominal constants before: 5.0 %)
  //   lead p05 0.398  0.405  0.419  0.446 s  (median 0.63, 0.65, 0.69, 0.88 s)
  // On the 16 mismatch cases of issue 27 (14 080 runs, 3092 true collapses; recall 3091/3092 at both):
  //   k_σ 0.5: false 3.8 %, ≤ 0.03 in 6 of 16 cases; lead median 0.634 s, p05 0.368 s, ≥ 0.6 s in 10 of 16
  //   k_σ 0:   false 3.0 %, ≤ 0.03 in 10 of 16 cases; lead median 0.613 s, p05 0.359 s, ≥ 0.6 s in the same 10
  // 0 (issue 27): the cases short of 0.6 s lead (stiffer walls, which rock faster) are short at either value.
  double alarm_capacity_sigmas = 0.0;
  // Model doubt (issue 40, SPEC §11): the wall is not the model. The displacement's normalised innovation squared
  // y²/S (χ² with one degree of freedom: mean 1 when the model and its covariance are right), capped at the gate and
  // averaged over about `doubt_window` samples (exponentially), above `doubt_nis` says the innovations are larger
  // than the covariance allows: flagged (model_doubt) and counted, and while it lasts σ(κc), σ(κk) are held at least
  // `doubt_capacity_sigma` and σ(√r) at least `doubt_r_sigma`, so that a misfit the filter cannot represent (other
  // heights, crushed hinges, corner impacts) does not go into the capacity with full confidence. 0 turns it off.
  double doubt_nis = 4.0;
  // The displacement transducer's noise measured before the shaking (issue 40, SPEC §11 "The transducer's noise"):
  // from the run's start until the ground first reaches half the quiet level (quiet_fraction / 2 of the threshold: a
  // wall whose threshold is lower than told may rock on a ground the model calls quiet) or the model first moves, the readings
  // of the wall at rest give the noise by their second differences (a slow motion barely enters them); after at
  // least `noise_learn_readings` of them, an estimate at least (1.5 x_noise)² and clearly above x_noise² (by more than
  // 4 of the mean's standard deviations) becomes R, and every threshold counted in transducer σ with it
  // (the informative-motion gates, the quiet-motion spread, the re-initialisation's σ(x)). Never below x_noise.
  // A lab whose transducer is noisier than it said (its cabling, its mounting) is otherwise read as a wall that moves
  // where the model cannot: on the kept truths with a 2 mm / 0.2 m/s² transducer told 0.5 mm / 0.05 m/s², 7 false
  // alarms of 32 survivors. 0 turns it off.
  std::int32_t noise_learn_readings = 64;
  std::int32_t doubt_window = 64;         // samples of the displacement's NIS average [-]
  double doubt_capacity_sigma = 0.05;     // σ floor of κc, κk while in doubt [-]
  double doubt_r_sigma = 0.02;            // σ floor of √r while in doubt; in the published σ(r) after it [-]
  // The capacity from the decline of the restoring force (issue 40, SPEC §11): a reading (displacement or
  // acceleration) may teach κc, κk only while the model's |x| ≥ `capacity_min_x_fraction` × x_inst,nominal, and
  // ≥ `doubt_capacity_min_x_fraction` × x_inst,nominal once model doubt has been raised in the run; below, the
  // capacity is considered, not estimated (Schmidt: x, ẋ, √r and the offset still learn). Near x = 0 a crushed
  // hinge's force–displacement curve is an elastic rise and a plateau, which the rigid model's line c − k·x
  // extrapolates to a capacity far out; the decline beyond it reads the wall's own. A wall that is the model (no
  // doubt) learns from its first motion, as before. Measured on the truths (docs/BENCHMARKS.md "Model error"):
  // 0 and 0.25 (the defaults since 2026-11-30) bring the crushed family's x̂_inst from 19.6 % to 1.9 % at the median
  // (max 132 → 35 %), r̂ 0.036 → 0.020, lead 0.41 → 0.43 s, every robust alarm right, the rigid families the same or
  // better; the synthetic mismatch study's fused false alarms 3.08 → 3.3 % (the overburden seen by an accelerometer,
  // 3 kN/m: 2.8 → 5.0 %). 0.1 always and 0.2 in doubt (the option before): crushed 2.7 %, lead 0.39 s, 3.6 %. 0.3
  // in doubt: a false alarm on a crack-height survivor.
  double capacity_min_x_fraction = 0.0;
  double doubt_capacity_min_x_fraction = 0.25;
  // The model's form (issue 40, SPEC §11): no wall is the two-rigid-block model, so the published σ(x_inst) adds, in
  // quadrature to the filter's own, `model_form_sigma` × x̂_inst, and `doubt_model_form_sigma` × x̂_inst once model
  // doubt has been raised in the run (a wall that has shown it is not the model: its capacity is an extrapolation of
  // the wrong curve). The filter, its gains and the alarm's margin (alarm_capacity_sigmas) keep the filter's σ
  // (sigma_x_inst_filter_m). Measured on the truths of tests/data/truths (docs/BENCHMARKS.md "Model error"): the rigid
  // families' x̂_inst ends 0.5–3.3 % off at the median (at most 7.7 %), with filter σ as small as 0.1 % (z up to 24);
  // crushed hinges up to 130 % (survivors: the rigid model extrapolates a plateau). 0.03 and 0.2 put x_inst within 3 σ
  // at the end in 16 of 16 cases of every family (before: 9–13), after five impacts in 11–15 of 11–15.
  // Before doubt the form is at least doubt_model_form_sigma × (1 − the run's largest |x| / x̂_inst): the capacity is
  // extrapolated beyond what the wall has shown, the further the less sure (a held-out crushed survivor without doubt:
  // z 8.9 → 2.8; SPEC §11). doubt_model_form_sigma = 0 turns that term off too.
  double model_form_sigma = 0.03;
  double doubt_model_form_sigma = 0.2;
  // A wall that moves where the model says it cannot (issue 40): while the model rests and the ground is quiet,
  // `reinit_after` displacement rejections in a row whose readings spread over at least this many σ of the
  // transducer are motion, not a fault (a fault reads a constant or jumps once): the motion is re-initialised from
  // the measurement and model doubt is raised. 0: every such reading stays a fault (before issue 40). 20 (1 cm at the
  // default noise), not 8: a crushed hinge's elastic phase moves the wall a few millimetres below the threshold, and
  // re-initialising the rigid model there taught it a wrong capacity (x_inst median error 35 % against 20 % on the
  // crushed truths; docs/BENCHMARKS.md "Model error").
  double quiet_motion_spread_noises = 20.0;
};

// Why init() refused: the group of the first parameter out of its range (kObserverParameters). Values are stable:
// append, never renumber.
enum class ObserverError : std::uint8_t {
  ok = 0,
  noise_out_of_range = 1,     // a sensor's or the model's noise
  prior_out_of_range = 2,     // an initial σ, a random walk, the alarm's capacity margin
  gate_out_of_range = 3,      // the χ² gate and the counts of the health rules
  timing_out_of_range = 4,    // the dropout time, the oldest usable sample, the step (init's setup)
  range_out_of_range = 5,     // the sensors' ranges, the quiet ground, the informative-motion gates
  doubt_out_of_range = 6,     // model doubt and the model's form
};

// One setting's accepted range: the one table the check (validate_observer_options), its messages
// (observer_error_message), the command line's checks and help (host_tools/options) and the docs table
// (docs/observer_parameters.md, checked against this by tests/core) are written from.
struct ObserverParameter {
  const char* name;             // the ObserverOptions field
  double min, max;              // accepted: [min, max], or (min, max] when min_open
  bool min_open;                // min itself is refused
  bool zero_allowed;            // 0 (off) is accepted besides [min, max]
  const char* min_text;         // min and max as the messages and docs print them
  const char* max_text;
  const char* unit;             // SI unit in ASCII (m/s2: messages go to terminals); "-" for a ratio or a count
  const char* meaning;          // what it sets
  ObserverError group;          // what init() reports when it is out of range
  double (*value)(const ObserverOptions&);  // the field, as a double (counts are exact)

  constexpr bool accepts(double v) const {
    if (zero_allowed && v == 0.0) return true;
    return (min_open ? v > min : v >= min) && v <= max;  // NaN fails both
  }
};

// In the order init() checks them: by group, a group's first failure is reported (the order of the groups is the
// ObserverError's).
inline constexpr ObserverParameter kObserverParameters[] = {
    {"x_noise_m", 1e-6, 0.1, false, false, "1e-6", "0.1", "m", "σ of the displacement transducer",
     ObserverError::noise_out_of_range, [](const ObserverOptions& o) { return o.x_noise_m; }},
    {"a_noise_mps2", 1e-4, 10.0, false, false, "1e-4", "10", "m/s2", "σ of the mid-height accelerometer",
     ObserverError::noise_out_of_range, [](const ObserverOptions& o) { return o.a_noise_mps2; }},
    {"noise_learn_readings", 8.0, 100000.0, false, true, "8", "100000", "-",
     "readings at rest before the shaking that measure the displacement transducer's noise (0: off)",
     ObserverError::noise_out_of_range, [](const ObserverOptions& o) { return double(o.noise_learn_readings); }},
    {"process_accel_mps2", 1e-4, 100.0, false, false, "1e-4", "100", "m/s2",
     "σ of the model's acceleration error per step", ObserverError::noise_out_of_range,
     [](const ObserverOptions& o) { return o.process_accel_mps2; }},
    {"r_sigma0", 0.0, 1.0, true, false, "0", "1", "-", "initial σ of √r", ObserverError::prior_out_of_range,
     [](const ObserverOptions& o) { return o.r_sigma0; }},
    {"bias_sigma0_m", 0.0, 0.1, true, false, "0", "0.1", "m", "initial σ of the transducer's zero offset",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.bias_sigma0_m; }},
    {"r_walk", 0.0, 0.01, false, false, "0", "0.01", "-", "random walk of √r per step",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.r_walk; }},
    {"bias_walk_m", 0.0, 0.01, false, false, "0", "0.01", "m", "random walk of the zero offset per step",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.bias_walk_m; }},
    {"capacity_sigma0", 1e-4, 1.0, false, false, "1e-4", "1", "-", "prior σ of κc and κk",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.capacity_sigma0; }},
    {"capacity_walk", 0.0, 0.01, false, false, "0", "0.01", "-", "random walk of κc and κk per step",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.capacity_walk; }},
    {"capacity_correlation", 0.0, 0.99, false, false, "0", "0.99", "-", "prior correlation of κc and κk",
     ObserverError::prior_out_of_range, [](const ObserverOptions& o) { return o.capacity_correlation; }},
    {"alarm_capacity_sigmas", 0.0, 10.0, false, false, "0", "10", "-",
     "the alarm's margin k_σ: it uses x_inst,est − k_σ·σ(x_inst)", ObserverError::prior_out_of_range,
     [](const ObserverOptions& o) { return o.alarm_capacity_sigmas; }},
    {"gate_chi2", 1.0, 1000.0, false, false, "1", "1000", "-", "innovation gate, χ² with one degree of freedom",
     ObserverError::gate_out_of_range, [](const ObserverOptions& o) { return o.gate_chi2; }},
    {"reinit_after", 1.0, 1000.0, false, false, "1", "1000", "-",
     "consecutive rejections (ground shaking) that re-initialise the motion", ObserverError::gate_out_of_range,
     [](const ObserverOptions& o) { return double(o.reinit_after); }},
    {"stuck_after", 2.0, 100000.0, false, false, "2", "100000", "-",
     "identical consecutive displacement readings while rocking: stuck", ObserverError::gate_out_of_range,
     [](const ObserverOptions& o) { return double(o.stuck_after); }},
    {"capacity_reopen_after", 0.0, 1000.0, false, false, "0", "1000", "-",
     "accelerometer rejections in a row that re-open the capacity's covariance (0: never)",
     ObserverError::gate_out_of_range, [](const ObserverOptions& o) { return double(o.capacity_reopen_after); }},
    {"rest_from_accel_after", 0.0, 1000.0, false, false, "0", "1000", "-",
     "accelerometer readings of a wall at rest in a row that put the model to rest (0: never)",
     ObserverError::gate_out_of_range, [](const ObserverOptions& o) { return double(o.rest_from_accel_after); }},
    {"dropout_s", 0.0, 60.0, true, false, "0", "60", "s", "no usable displacement sample for this long: sensor lost",
     ObserverError::timing_out_of_range, [](const ObserverOptions& o) { return o.dropout_s; }},
    {"max_age_s", 0.0, 10.0, false, false, "0", "10", "s", "older samples (behind the ground stream) are dropped",
     ObserverError::timing_out_of_range, [](const ObserverOptions& o) { return o.max_age_s; }},
    {"count_interval_s", 0.0, 1.0, false, false, "0", "1", "s",
     "a reading Δt after its sensor's previous ones counts floor(Δt / this) samples (1 to 8) in the counts; 0: one",
     ObserverError::timing_out_of_range, [](const ObserverOptions& o) { return o.count_interval_s; }},
    {"x_range_m", 0.0, 2.0, true, false, "0", "2", "m", "a displacement reading beyond ± this: out of range",
     ObserverError::range_out_of_range, [](const ObserverOptions& o) { return o.x_range_m; }},
    {"a_range_mps2", 0.0, 128.0, true, false, "0", "128", "m/s2", "an acceleration reading beyond ± this: out of range",
     ObserverError::range_out_of_range, [](const ObserverOptions& o) { return o.a_range_mps2; }},
    {"quiet_fraction", 0.0, 1.0, false, false, "0", "1", "-",
     "the ground is quiet below this fraction of the smaller start threshold", ObserverError::range_out_of_range,
     [](const ObserverOptions& o) { return o.quiet_fraction; }},
    {"v_min_mps", 0.0, 1.0, true, false, "0", "1", "m/s", "floor of the impact speed ẋ⁻ in the saltation matrix",
     ObserverError::range_out_of_range, [](const ObserverOptions& o) { return o.v_min_mps; }},
    {"inform_sigmas", 0.0, 100.0, false, false, "0", "100", "-",
     "an impact informs √r only when its speed is ≥ this × σ(ẋ⁻)", ObserverError::range_out_of_range,
     [](const ObserverOptions& o) { return o.inform_sigmas; }},
    {"inform_peak_noises", 0.0, 1000.0, false, false, "0", "1000", "-",
     "… and the half-cycle before it peaked at ≥ this × x_noise", ObserverError::range_out_of_range,
     [](const ObserverOptions& o) { return o.inform_peak_noises; }},
    {"accel_inform_peak_noises", 0.0, 1000.0, false, false, "0", "1000", "-",
     "the same gate for the accelerometer's updates of κc, κk (0: from the first motion)",
     ObserverError::range_out_of_range, [](const ObserverOptions& o) { return o.accel_inform_peak_noises; }},
    {"doubt_nis", 1.0, 1000.0, false, true, "1", "1000", "-",
     "model doubt above this average NIS of the displacement (0: off)", ObserverError::doubt_out_of_range,
     [](const ObserverOptions& o) { return o.doubt_nis; }},
    {"doubt_window", 1.0, 100000.0, false, false, "1", "100000", "-", "samples of the displacement's NIS average",
     ObserverError::doubt_out_of_range, [](const ObserverOptions& o) { return double(o.doubt_window); }},
    {"doubt_capacity_sigma", 0.0, 1.0, false, false, "0", "1", "-", "σ floor of κc, κk while in doubt",
     ObserverError::doubt_out_of_range, [](const ObserverOptions& o) { return o.doubt_capacity_sigma; }},
    {"doubt_r_sigma", 0.0, 1.0, false, false, "0", "1", "-",
     "σ floor of √r while in doubt, and in the published σ(r) once doubt was raised",
     ObserverError::doubt_out_of_range, [](const ObserverOptions& o) { return o.doubt_r_sigma; }},
    {"capacity_min_x_fraction", 0.0, 1.0, false, false, "0", "1", "-",
     "κc, κk learned only at x beyond ± this × x_inst,nominal (0: always)", ObserverError::doubt_out_of_range,
     [](const ObserverOptions& o) { return o.capacity_min_x_fraction; }},
    {"doubt_capacity_min_x_fraction", 0.0, 1.0, false, false, "0", "1", "-",
     "the same once model doubt has been raised in the run", ObserverError::doubt_out_of_range,
     [](const ObserverOptions& o) { return o.doubt_capacity_min_x_fraction; }},
    {"quiet_motion_spread_noises", 0.0, 1000.0, false, false, "0", "1000", "-",
     "rejected readings on a quiet ground spreading over this × x_noise are motion, not a fault (0: always a fault)",
     ObserverError::doubt_out_of_range, [](const ObserverOptions& o) { return o.quiet_motion_spread_noises; }},
    {"model_form_sigma", 0.0, 1.0, false, false, "0", "1", "-",
     "the model's form in the published σ(x_inst), × x̂_inst", ObserverError::doubt_out_of_range,
     [](const ObserverOptions& o) { return o.model_form_sigma; }},
    {"doubt_model_form_sigma", 0.0, 1.0, false, false, "0", "1", "-",
     "the same once model doubt has been raised in the run; before it, × (1 − the run's largest displacement / x̂_inst) "
     "when larger than model_form_sigma (the capacity extrapolated)",
     ObserverError::doubt_out_of_range, [](const ObserverOptions& o) { return o.doubt_model_form_sigma; }},
};

// The table's row of a setting by its field name (nullptr: no such setting).
constexpr const ObserverParameter* observer_parameter(const char* name) {
  for (const ObserverParameter& p : kObserverParameters) {
    int i = 0;
    while (p.name[i] != '\0' && p.name[i] == name[i]) ++i;
    if (p.name[i] == '\0' && name[i] == '\0') return &p;
  }
  return nullptr;
}

// The first setting out of its range (nullptr: all accepted).
inline const ObserverParameter* first_observer_parameter_out_of_range(const ObserverOptions& o) {
  for (const ObserverParameter& p : kObserverParameters) {
    if (!p.accepts(p.value(o))) return &p;
  }
  return nullptr;
}

inline ObserverError validate_observer_options(const ObserverOptions& o) {
  const ObserverParameter* p = first_observer_parameter_out_of_range(o);
  return p == nullptr ? ObserverError::ok : p->group;
}

namespace observer_detail {

// Each group's message, written from the table at compile time: "observer noise out of range (x_noise_m in
// [1e-6, 0.1] m, …)" (no heap, no formatting at run time).
inline constexpr int kGroups = 7, kMessageChars = 640;
struct ErrorMessages {
  char text[kGroups][kMessageChars];
};
constexpr void append(char* out, int& n, const char* s) {
  for (int i = 0; s[i] != '\0' && n < kMessageChars - 1; ++i) out[n++] = s[i];
  out[n] = '\0';
}
constexpr ErrorMessages make_error_messages() {
  ErrorMessages m{};
  const char* heads[kGroups] = {"ok",
                                "observer noise out of range (",
                                "observer prior out of range (",
                                "observer gate out of range (",
                                "observer timing out of range (",
                                "observer ranges invalid (",
                                "observer model doubt out of range ("};
  for (int g = 0; g < kGroups; ++g) {
    int n = 0;
    append(m.text[g], n, heads[g]);
    if (g == 0) continue;
    bool first = true;
    for (const ObserverParameter& p : kObserverParameters) {
      if (static_cast<int>(p.group) != g) continue;
      if (!first) append(m.text[g], n, ", ");
      first = false;
      append(m.text[g], n, p.name);
      append(m.text[g], n, p.zero_allowed ? " 0 or in " : " in ");
      append(m.text[g], n, p.min_open ? "(" : "[");
      append(m.text[g], n, p.min_text);
      append(m.text[g], n, ", ");
      append(m.text[g], n, p.max_text);
      append(m.text[g], n, "]");
      if (p.unit[0] != '-') {
        append(m.text[g], n, " ");
        append(m.text[g], n, p.unit);
      }
    }
    if (g == static_cast<int>(ObserverError::timing_out_of_range)) append(m.text[g], n, ", the step in (0, 0.1] s");
    append(m.text[g], n, ")");
  }
  return m;
}
inline constexpr ErrorMessages kErrorMessages = make_error_messages();

}  // namespace observer_detail

inline const char* observer_error_message(ObserverError e) {
  const int g = static_cast<int>(e);
  return g >= 0 && g < observer_detail::kGroups ? observer_detail::kErrorMessages.text[g] : "?";
}

}  // namespace rockwatch::core
