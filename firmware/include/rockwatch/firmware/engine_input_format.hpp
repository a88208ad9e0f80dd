// The engine-input file: what `rockwatch simulate --engine-input-out FILE` writes and the Cortex-M4 replay image
// (firmware/embedded/m4_replay/, scripts/m4-replay.sh) reads through semihosting, so that the image runs
// firmware::WallEngine on exactly the configuration and the inputs the host's fixed-point analysis ran.
//
// Layout (little-endian, every field 8 bytes, so the image reads it with memcpy and no parsing):
//   magic "RWENGIN1"
//   uint64 n_config, then n_config pairs {uint64 key (EngineInputKey), double value}
//   uint64 n_samples, then n_samples pairs {double ug_mps2, double vg_mps2}: the wall-frame inputs of the engine's
//     start (sample 0) and of each sample after it (samples 1 …), as simulate fed them to its engine — the record's
//     samples (the engine integrates each in ceil(dt_s / max_step_s) sub-steps), then zeros for the free rocking after
//     the record, up to where simulate stopped (collapse, or the verdict after the record).
// A key the reader does not know is an error (the file is newer than the image): keys are never renumbered or reused.
#pragma once

#include <cstdint>

#include "rockwatch/core/sample_engine.hpp"

namespace rockwatch::firmware {

inline constexpr char kEngineInputMagic[8] = {'R', 'W', 'E', 'N', 'G', 'I', 'N', '1'};
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
};

// Sets one configuration field; false for an unknown key or a value that is not a model kind.
inline bool apply_engine_input_key(core::WallEngineConfig& c, std::uint64_t key, double v) {
  switch (static_cast<EngineInputKey>(key)) {
    case EngineInputKey::wall_b_m: c.wall.b_m = v; return true;
    case EngineInputKey::wall_h1_m: c.wall.h1_m = v; return true;
    case EngineInputKey::wall_h2_m: c.wall.h2_m = v; return true;
    case EngineInputKey::wall_rho_kgpm3: c.wall.rho_kgpm3 = v; return true;
    case EngineInputKey::wall_fp_npm: c.wall.fp_npm = v; return true;
    case EngineInputKey::wall_a: c.wall.a = v; return true;
    case EngineInputKey::wall_a_prime: c.wall.a_prime = v; return true;
    case EngineInputKey::wall_g_mps2: c.wall.g_mps2 = v; return true;
    case EngineInputKey::r_energy: c.r_energy = v; return true;
    case EngineInputKey::kappa: c.kappa = v; return true;
    case EngineInputKey::model:
      if (v == double(static_cast<int>(core::ModelKind::linear))) {
        c.model = core::ModelKind::linear;
      } else if (v == double(static_cast<int>(core::ModelKind::full))) {
        c.model = core::ModelKind::full;
      } else {
        return false;
      }
      return true;
    case EngineInputKey::dt_s: c.dt_s = v; return true;
    case EngineInputKey::alarm_lambda_warning: c.alarm.lambda_warning = v; return true;
    case EngineInputKey::alarm_hold_s: c.alarm.hold_s = v; return true;
    case EngineInputKey::alarm_energy_margin: c.alarm.energy_margin = v; return true;
    case EngineInputKey::max_step_s: c.max_step_s = v; return true;
  }
  return false;
}

// Every pair of a configuration, in key order (the writer's list; the reader needs none of them to be present, but
// the writer always writes all).
template <typename Sink>
void for_each_engine_input_key(const core::WallEngineConfig& c, Sink&& sink) {
  sink(EngineInputKey::wall_b_m, c.wall.b_m);
  sink(EngineInputKey::wall_h1_m, c.wall.h1_m);
  sink(EngineInputKey::wall_h2_m, c.wall.h2_m);
  sink(EngineInputKey::wall_rho_kgpm3, c.wall.rho_kgpm3);
  sink(EngineInputKey::wall_fp_npm, c.wall.fp_npm);
  sink(EngineInputKey::wall_a, c.wall.a);
  sink(EngineInputKey::wall_a_prime, c.wall.a_prime);
  sink(EngineInputKey::wall_g_mps2, c.wall.g_mps2);
  sink(EngineInputKey::r_energy, c.r_energy);
  sink(EngineInputKey::kappa, c.kappa);
  sink(EngineInputKey::model, double(static_cast<int>(c.model)));
  sink(EngineInputKey::dt_s, c.dt_s);
  sink(EngineInputKey::alarm_lambda_warning, c.alarm.lambda_warning);
  sink(EngineInputKey::alarm_hold_s, c.alarm.hold_s);
  sink(EngineInputKey::alarm_energy_margin, c.alarm.energy_margin);
  sink(EngineInputKey::max_step_s, c.max_step_s);
}

}  // namespace rockwatch::firmware
