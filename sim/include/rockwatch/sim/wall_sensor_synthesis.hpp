// Sensor samples of a simulated wall: what a displacement transducer at the mid-height hinge and an accelerometer at
// mid-height would have measured on the wall of an analysis (its history), with a sensor model — rate, Gaussian
// noise, a zero offset, quantisation, dropouts. The truth for testing the wall observer: simulate a *true* wall, make
// its sensor samples, run the nominal wall fused with them (`rockwatch simulate --sensors-out`, `rockwatch study
// --observer`).
//
// Measurement equations (core/wall_observer.hpp): x_mid = x + bias + noise, then rounded to the quantum;
// a_mid = ü + ẍ − G·x/h1 + noise with G = g + v̈ (the absolute horizontal acceleration of the hinge on block 1).
// Between the integration steps of the history the true response is interpolated linearly. The noise comes from
// synthesis::RandomStream (the same on every machine): per sample one normal draw for x, then one for a when the
// accelerometer is modelled, drawn also for samples a dropout removes, so a dropout never changes the other samples.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim {

struct SensorDropout {
  double from_s = 0.0, to_s = 0.0;      // no samples with from_s ≤ t < to_s [s]
};

struct SensorModel {
  double rate_hz = 0.0;                 // samples per second; 0: the record's rate (1 / its dt)
  double x_noise_m = 0.5e-3;            // σ of the displacement transducer's noise [m]
  double x_bias_m = 0.0;                // its zero offset [m]
  double x_quantum_m = 0.0;             // its resolution: readings rounded to multiples of it; 0 = none [m]
  std::optional<double> a_noise_mps2;   // σ of the accelerometer's noise [m/s²]; none: no acceleration samples
  std::vector<SensorDropout> dropouts;
  std::uint64_t seed = 1;
};

class SensorModelError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Limits of the model: rate in (0, 100 kHz], σ and |bias| ≤ 1 m (σ_a ≤ 1000 m/s²), quantum in [0, 1 m], dropout
// windows with finite from_s < to_s. Throws SensorModelError naming the field.
void check_sensor_model(const SensorModel& model);

// The samples at t_k = k / rate, k = 0, 1, … while t_k ≤ the last history row (the end of the analysis: the wall
// settled, or collapsed), minus the dropouts. `truth` must hold the history (AnalysisOptions::keep_history) of the
// analysis of `wall` on a motion sampled at record_dt_s. Throws SensorModelError for an invalid model or
// AnalysisError for a result without history.
std::vector<core::WallSensorSample> synthesize_wall_sensors(const core::WallParameters& wall,
                                                            const AnalysisResult& truth, double record_dt_s,
                                                            const SensorModel& model);

}  // namespace rockwatch::sim
