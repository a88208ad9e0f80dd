// The engine-input file: what `rockwatch simulate --engine-input-out FILE` writes and the Cortex-M4 replay image
// (firmware/embedded/m4_replay/, scripts/m4-replay.sh) reads through semihosting, so that the image runs
// firmware::WallEngine on exactly the configuration and the inputs the host's fixed-point analysis ran.
//
// Layout (little-endian, every field 8 bytes, so the image reads it with memcpy and no parsing):
//   magic "RWENGIN2"
//   uint64 n_config, then n_config pairs {uint64 key (EngineInputKey), double value}
//   uint64 n_samples, then n_samples pairs {double ug_mps2, double vg_mps2}: the wall-frame inputs of the engine's
//     start (sample 0) and of each sample after it (samples 1 …), as simulate fed them to its engine — the record's
//     samples (the engine integrates each in ceil(dt_s / max_step_s) sub-steps), then zeros for the free rocking after
//     the record, up to where simulate stopped (collapse, or the verdict after the record).
//   uint64 n_sensor, then n_sensor wall-sensor samples (kEngineInputSensorFields fields each: int64 utime_us, double
//     x_mid_m, double a_mid_mps2, uint64 valid (bit 0 x, bit 1 a), int64 sensor_status): what `simulate
//     --wall-sensors` gave its observer (0 without). Sample k ≥ 1 ends at core::observed_step_end_us((k − 1)·dt_s, dt_s)
//     on the sensors' clock; before stepping it, the sensor samples with utime ≤ that are pushed
//     (WallEngine::push_sensor), as the analysis does.
// A key the reader does not know is an error (the file is newer than the image): keys are never renumbered or reused.
// Version 1 (RWENGIN1, without the sensor section) is no longer read: the image and the tool come from one tree.
#pragma once

#include <cstdint>

#include "rockwatch/core/sample_engine.hpp"

namespace rockwatch::firmware {

inline constexpr char kEngineInputMagic[8] = {'R', 'W', 'E', 'N', 'G', 'I', 'N', '2'};
inline constexpr std::uint64_t kEngineInputSensorFields = 5;  // 8-byte fields per wall-sensor sample
inline constexpr std::uint64_t kEngineInputSensorValidX = 1;  // valid bits of a wall-sensor sample
inline constexpr std::uint64_t kEngineInputSensorValidA = 2;
inline constexpr std::uint64_t kEngineInputMaxConfig = 64;  // more pairs than keys: a corrupt file

// Keys of the configuration pairs. Values are stable: append, never renumber or reuse.
enum class EngineInputKey : std::uint64_t {
  wall_b_m = 1,
  wall_h1_m = 2,
  wall_h2_m = 3,
  wall_rho_kgpm3 = 4,
  wall_fp_npm = 5,
  wall_a = 6,
  wall_a_prime = 7,
  wall_g_mps2 = 8,
  r_energy = 9,
  kappa = 10,
  model = 11,             // core::ModelKind as a number
  dt_s = 12,
  alarm_lambda_warning = 13,
  alarm_hold_s = 14,
  alarm_energy_margin = 15,
  max_step_s = 16,        // longest integration step: ceil(dt_s / max_step_s) sub-steps per input
  observer_enabled = 17,  // 1: the wall observer runs on the sensor section's samples (core::ObserverOptions below)
  observer_x_noise_m = 18,
  observer_a_noise_mps2 = 19,
  observer_process_accel_mps2 = 20,
  observer_r_sigma0 = 21,
  observer_r_walk = 22,
  observer_bias_sigma0_m = 23,
  observer_bias_walk_m = 24,
  observer_gate_chi2 = 25,
  observer_reinit_after = 26,
  observer_dropout_s = 27,
  observer_max_age_s = 28,
  observer_x_range_m = 29,
  observer_a_range_mps2 = 30,
  observer_stuck_after = 31,
  observer_quiet_fraction = 32,
  observer_v_min_mps = 33,
  work_overflow = 34,     // core::WorkOverflow as a number (the budgeted step()'s policy at a full queue)
  observer_alarm_capacity_sigmas = 35,     // the alarm's margin k_σ (`--observer-capacity-sigmas`)
  observer_accel_inform_peak_noises = 36,  // `--observer-accel-inform-peak-noises`
  // 37–52 (issue 40's settings and the rest of core::ObserverOptions): before them a file or the monitor image's
  // configuration could not carry them, and the image ran their defaults while the host ran what it was told.
  alarm_imminent_horizon_s = 37,  // the alarm's look-ahead horizon (`--imminent-horizon`)
  observer_capacity_reopen_after = 38,
  observer_rest_from_accel_after = 39,
  observer_inform_sigmas = 40,
  observer_inform_peak_noises = 41,
  observer_capacity_sigma0 = 42,
  observer_capacity_walk = 43,
  observer_doubt_nis = 44,  // model doubt (SPEC §11): `--observer-doubt-nis`
  observer_doubt_window = 45,
  observer_doubt_capacity_sigma = 46,
  observer_doubt_r_sigma = 47,
  observer_capacity_min_x_fraction = 48,  // `--observer-capacity-min-x`
  observer_doubt_capacity_min_x_fraction = 49,  // `--observer-doubt-capacity-min-x`
  observer_model_form_sigma = 50,  // `--observer-model-form-sigma`
  observer_doubt_model_form_sigma = 51,  // `--observer-doubt-model-form-sigma`
  observer_quiet_motion_spread_noises = 52,  // `--observer-quiet-motion-noises`
  alarm_energy_min_x = 53,  // the energy margin's rule from |x| ≥ this × x_inst (`--energy-min-x`, issue 40)
  observer_capacity_correlation = 54,  // `--observer-capacity-correlation` (issue 40)
  observer_noise_learn_readings = 55,  // `--observer-noise-learn-readings` (issue 40)
};

// Every configuration field with its key, in key order: the one list both the writer and the reader use.
// `visit(key, field)` is called with a double&, core::ModelKind&, core::WorkOverflow&, bool& or std::int32_t& (const
// for a const config).
template <typename Config, typename Visit>
void visit_engine_input_fields(Config& c, Visit&& visit) {
  visit(EngineInputKey::wall_b_m, c.wall.b_m);
  visit(EngineInputKey::wall_h1_m, c.wall.h1_m);
  visit(EngineInputKey::wall_h2_m, c.wall.h2_m);
  visit(EngineInputKey::wall_rho_kgpm3, c.wall.rho_kgpm3);
  visit(EngineInputKey::wall_fp_npm, c.wall.fp_npm);
  visit(EngineInputKey::wall_a, c.wall.a);
  visit(EngineInputKey::wall_a_prime, c.wall.a_prime);
  visit(EngineInputKey::wall_g_mps2, c.wall.g_mps2);
  visit(EngineInputKey::r_energy, c.r_energy);
  visit(EngineInputKey::kappa, c.kappa);
  visit(EngineInputKey::model, c.model);
  visit(EngineInputKey::dt_s, c.dt_s);
  visit(EngineInputKey::alarm_lambda_warning, c.alarm.lambda_warning);
  visit(EngineInputKey::alarm_hold_s, c.alarm.hold_s);
  visit(EngineInputKey::alarm_energy_margin, c.alarm.energy_margin);
  visit(EngineInputKey::max_step_s, c.max_step_s);
  visit(EngineInputKey::observer_enabled, c.observer_enabled);
  visit(EngineInputKey::observer_x_noise_m, c.observer.x_noise_m);
  visit(EngineInputKey::observer_a_noise_mps2, c.observer.a_noise_mps2);
  visit(EngineInputKey::observer_process_accel_mps2, c.observer.process_accel_mps2);
  visit(EngineInputKey::observer_r_sigma0, c.observer.r_sigma0);
  visit(EngineInputKey::observer_r_walk, c.observer.r_walk);
  visit(EngineInputKey::observer_bias_sigma0_m, c.observer.bias_sigma0_m);
  visit(EngineInputKey::observer_bias_walk_m, c.observer.bias_walk_m);
  visit(EngineInputKey::observer_gate_chi2, c.observer.gate_chi2);
  visit(EngineInputKey::observer_reinit_after, c.observer.reinit_after);
  visit(EngineInputKey::observer_dropout_s, c.observer.dropout_s);
  visit(EngineInputKey::observer_max_age_s, c.observer.max_age_s);
  visit(EngineInputKey::observer_x_range_m, c.observer.x_range_m);
  visit(EngineInputKey::observer_a_range_mps2, c.observer.a_range_mps2);
  visit(EngineInputKey::observer_stuck_after, c.observer.stuck_after);
  visit(EngineInputKey::observer_quiet_fraction, c.observer.quiet_fraction);
  visit(EngineInputKey::observer_v_min_mps, c.observer.v_min_mps);
  visit(EngineInputKey::work_overflow, c.work_overflow);
  visit(EngineInputKey::observer_alarm_capacity_sigmas, c.observer.alarm_capacity_sigmas);
  visit(EngineInputKey::observer_accel_inform_peak_noises, c.observer.accel_inform_peak_noises);
  visit(EngineInputKey::alarm_imminent_horizon_s, c.alarm.imminent_horizon_s);
  visit(EngineInputKey::observer_capacity_reopen_after, c.observer.capacity_reopen_after);
  visit(EngineInputKey::observer_rest_from_accel_after, c.observer.rest_from_accel_after);
  visit(EngineInputKey::observer_inform_sigmas, c.observer.inform_sigmas);
  visit(EngineInputKey::observer_inform_peak_noises, c.observer.inform_peak_noises);
  visit(EngineInputKey::observer_capacity_sigma0, c.observer.capacity_sigma0);
  visit(EngineInputKey::observer_capacity_walk, c.observer.capacity_walk);
  visit(EngineInputKey::observer_doubt_nis, c.observer.doubt_nis);
  visit(EngineInputKey::observer_doubt_window, c.observer.doubt_window);
  visit(EngineInputKey::observer_doubt_capacity_sigma, c.observer.doubt_capacity_sigma);
  visit(EngineInputKey::observer_doubt_r_sigma, c.observer.doubt_r_sigma);
  visit(EngineInputKey::observer_capacity_min_x_fraction, c.observer.capacity_min_x_fraction);
  visit(EngineInputKey::observer_doubt_capacity_min_x_fraction, c.observer.doubt_capacity_min_x_fraction);
  visit(EngineInputKey::observer_model_form_sigma, c.observer.model_form_sigma);
  visit(EngineInputKey::observer_doubt_model_form_sigma, c.observer.doubt_model_form_sigma);
  visit(EngineInputKey::observer_quiet_motion_spread_noises, c.observer.quiet_motion_spread_noises);
  visit(EngineInputKey::alarm_energy_min_x, c.alarm.energy_min_x);
  visit(EngineInputKey::observer_capacity_correlation, c.observer.capacity_correlation);
  visit(EngineInputKey::observer_noise_learn_readings, c.observer.noise_learn_readings);
}

// A field's value as the file carries it (a double).
inline double engine_input_value(double v) { return v; }
inline double engine_input_value(core::ModelKind v) { return double(static_cast<int>(v)); }
inline double engine_input_value(core::WorkOverflow v) { return double(static_cast<int>(v)); }
inline double engine_input_value(bool v) { return v ? 1.0 : 0.0; }
inline double engine_input_value(std::int32_t v) { return double(v); }

// A value from the file into its field; false when the field cannot hold it exactly (a model kind that does not
// exist, a flag that is not 0 or 1, an integer that is not one).
inline bool engine_input_set(double& field, double v) {
  field = v;
  return true;
}
inline bool engine_input_set(core::ModelKind& field, double v) {
  if (v == double(static_cast<int>(core::ModelKind::linear))) {
    field = core::ModelKind::linear;
  } else if (v == double(static_cast<int>(core::ModelKind::full))) {
    field = core::ModelKind::full;
  } else {
    return false;
  }
  return true;
}
inline bool engine_input_set(core::WorkOverflow& field, double v) {
  const core::WorkOverflow w = v == 1.0 ? core::WorkOverflow::finish : core::WorkOverflow::shed;
  if (v != double(static_cast<int>(w))) return false;
  field = w;
  return true;
}
inline bool engine_input_set(bool& field, double v) {
  if (v != 0.0 && v != 1.0) return false;
  field = v == 1.0;
  return true;
}
inline bool engine_input_set(std::int32_t& field, double v) {
  if (!(v >= -2147483648.0 && v <= 2147483647.0) || double(static_cast<std::int32_t>(v)) != v) return false;
  field = static_cast<std::int32_t>(v);
  return true;
}

// Sets one configuration field; false for an unknown key or a value its field cannot hold.
inline bool apply_engine_input_key(core::WallEngineConfig& c, std::uint64_t key, double v) {
  bool known = false, ok = false;
  visit_engine_input_fields(c, [&](EngineInputKey k, auto& field) {
    if (static_cast<std::uint64_t>(k) != key) return;
    known = true;
    ok = engine_input_set(field, v);
  });
  return known && ok;
}

// Every pair of a configuration, in key order (the writer's list; the reader needs none of them to be present, but
// the writer always writes all).
template <typename Sink>
void for_each_engine_input_key(const core::WallEngineConfig& c, Sink&& sink) {
  visit_engine_input_fields(c, [&sink](EngineInputKey k, const auto& field) { sink(k, engine_input_value(field)); });
}

}  // namespace rockwatch::firmware
