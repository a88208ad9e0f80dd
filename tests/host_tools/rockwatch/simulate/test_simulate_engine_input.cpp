// `rockwatch simulate --engine-input-out FILE`: the file holds the engine's configuration as the analysis ran it and
// every input the engine stepped on (checked against sim::analyse in-process through the same hook, value for value),
// in the format the Cortex-M4 replay image reads; and the option's misuses are refused.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/sample_engine.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/engine_input_format.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "common/records_in/wall_sensors.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;
namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;

namespace {

const char* const kElCentro180Input = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";  // dt 0.01 s: two steps per sample

struct EngineInputFile {
  std::uint64_t n_config = 0;
  core::WallEngineConfig config;
  bool keys_known = true;
  std::vector<std::array<double, 2>> inputs;
  std::vector<core::WallSensorSample> sensors;
  bool complete = false;
};

EngineInputFile read_engine_input(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EngineInputFile r;
  std::size_t pos = 0;
  const auto u64 = [&]() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8 && pos < bytes.size(); ++i, ++pos) {
      v |= std::uint64_t(static_cast<unsigned char>(bytes[pos])) << (8 * i);
    }
    return v;
  };
  const auto dbl = [&]() {
    const std::uint64_t b = u64();
    double d = 0.0;
    std::memcpy(&d, &b, sizeof d);
    return d;
  };
  if (bytes.compare(0, 8, std::string(firmware::kEngineInputMagic, 8)) != 0) return r;
  pos = 8;
  r.n_config = u64();
  for (std::uint64_t i = 0; i < r.n_config; ++i) {
    const std::uint64_t key = u64();
    r.keys_known = firmware::apply_engine_input_key(r.config, key, dbl()) && r.keys_known;
  }
  const std::uint64_t n = u64();
  for (std::uint64_t i = 0; i < n && pos + 16 <= bytes.size(); ++i) {
    const double ug = dbl();
    r.inputs.push_back({ug, dbl()});
  }
  const std::uint64_t n_sensor = u64();
  for (std::uint64_t i = 0; i < n_sensor && pos + 8 * firmware::kEngineInputSensorFields <= bytes.size(); ++i) {
    core::WallSensorSample s;
    s.utime_us = static_cast<std::int64_t>(u64());
    s.x_mid_m = dbl();
    s.a_mid_mps2 = dbl();
    const std::uint64_t valid = u64();
    s.x_valid = (valid & firmware::kEngineInputSensorValidX) != 0;
    s.a_valid = (valid & firmware::kEngineInputSensorValidA) != 0;
    s.sensor_status = static_cast<std::int32_t>(static_cast<std::int64_t>(u64()));
    r.sensors.push_back(s);
  }
  r.complete = r.inputs.size() == n && r.sensors.size() == n_sensor && pos == bytes.size();
  return r;
}

}  // namespace

TEST_GROUP(SimulateEngineInput){};

TEST(SimulateEngineInput, HoldsTheConfigurationAndEveryInputTheEngineSteppedOn) {
  TempDir dir;
  const std::string path = dir.path() + "/input.bin";
  const ProcessResult r = run_rockwatch({"simulate", "--record", record_path(kElCentro180Input), "--scale-pga", "0.25",
                                         "--arith", "fixed", "--alarms", "--lambda-w", "0.3", "--alarm-hold", "0.5",
                                         "--b", "0.12", "--h1", "1.6", "--r", "ana", "--kappa", "1.5", "--json",
                                         "--engine-input-out", path, "--work-overflow", "finish",
                                         "--imminent-horizon", "0.17"});
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const EngineInputFile f = read_engine_input(path);
  CHECK_TRUE(f.complete);
  CHECK_TRUE(f.keys_known);
  // Every key of firmware::EngineInputKey (36 before the alarm's horizon and the rest of ObserverOptions, keys 37–52;
  // 53 the energy rule's displacement, 54 the capacity's prior correlation, 55 the transducer's noise measured before
  // the shaking, issue 40).
  LONGS_EQUAL(55, f.n_config);
  CHECK_TRUE(f.config.work_overflow == core::WorkOverflow::finish);  // the firmware's policy, for the M4 replay
  STRCMP_EQUAL("finish", j["alarm"]["published"]["work_overflow"].get<std::string>().c_str());
  CHECK_FALSE(f.config.observer_enabled);
  LONGS_EQUAL(0, f.sensors.size());

  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.12;
  wall.h1_m = 1.6;
  DOUBLES_EQUAL(0.12, f.config.wall.b_m, 0.0);
  DOUBLES_EQUAL(1.6, f.config.wall.h1_m, 0.0);
  DOUBLES_EQUAL(wall.h2_m, f.config.wall.h2_m, 0.0);
  DOUBLES_EQUAL(wall.g_mps2, f.config.wall.g_mps2, 0.0);
  DOUBLES_EQUAL(j["r"].get<double>(), f.config.r_energy, 0.0);
  DOUBLES_EQUAL(1.5, f.config.kappa, 0.0);
  DOUBLES_EQUAL(0.01, f.config.dt_s, 1e-15);  // the record's sample interval, integrated in sub-steps of max_step
  DOUBLES_EQUAL(core::kDefaultMaxStep_s, f.config.max_step_s, 0.0);
  DOUBLES_EQUAL(j["dt_s"].get<double>() * 10.0, f.config.dt_s, 1e-15);
  CHECK_TRUE(f.config.model == core::ModelKind::linear);
  DOUBLES_EQUAL(0.3, f.config.alarm.lambda_warning, 0.0);
  DOUBLES_EQUAL(0.5, f.config.alarm.hold_s, 0.0);
  DOUBLES_EQUAL(core::AlarmSettings{}.energy_margin, f.config.alarm.energy_margin, 0.0);
  DOUBLES_EQUAL(0.17, f.config.alarm.imminent_horizon_s, 0.0);

  // The same analysis in-process: the same inputs, value for value (one per record sample).
  const rockwatch::records::Record rec = rockwatch::records::read_record(record_path(kElCentro180Input));
  sim::GroundMotion m;
  m.dt_s = rec.dt_s;
  m.ug_mps2 = rec.horizontal_mps2;
  const double factor = 0.25 * kG / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  sim::AnalysisOptions o;
  o.arithmetic = sim::Arithmetic::fixed_point;
  o.restitution = core::Restitution{core::RestitutionKind::ana, 0.0};
  o.kappa = 1.5;
  o.evaluate_alarm = true;
  o.alarm = core::AlarmSettings{0.3, 0.5, 1.5, 0.17};
  std::vector<std::array<double, 2>> expected;
  o.engine_inputs_out = &expected;
  const sim::AnalysisResult e = sim::analyse(wall, m, o);
  DOUBLES_EQUAL(e.r, f.config.r_energy, 0.0);
  LONGS_EQUAL(std::llround(e.t_final_s / m.dt_s) + 1, expected.size());
  LONGS_EQUAL(expected.size(), f.inputs.size());
  CHECK_TRUE(expected == f.inputs);
  DOUBLES_EQUAL(m.ug_mps2[1], f.inputs[1][0], 0.0);
  DOUBLES_EQUAL(m.ug_mps2[2], f.inputs[2][0], 0.0);
}

// With --wall-sensors the file also carries the observer's settings and every sensor sample it was given, as read.
TEST(SimulateEngineInput, CarriesTheObserverSettingsAndTheWallSensorSamples) {
  TempDir dir;
  const std::string sensors = dir.path() + "/sensors.csv", path = dir.path() + "/input.bin";
  const std::vector<std::string> record = {"simulate", "--record", record_path(kElCentro180Input), "--scale-pga", "0.3",
                                           "--b", "0.12", "--h1", "1.6", "--arith", "fixed"};
  std::vector<std::string> truth = record;
  for (const char* a : {"--r", "ana", "--sensors-out", sensors.c_str(), "--sensor-accel-noise-mps2", "0.05",
                        "--sensor-bias-m", "0.001"}) {
    truth.push_back(a);
  }
  const ProcessResult t = run_rockwatch(truth);
  CHECK_EQUAL_TEXT(0, t.exit_status, describe(t).c_str());
  std::vector<std::string> fused = record;
  for (const char* a : {"--wall-sensors", sensors.c_str(), "--observer-gate-chi2", "25", "--observer-process-mps2",
                        "0.3", "--observer-capacity-sigmas", "0.5", "--observer-accel-inform-peak-noises", "0",
                        "--observer-doubt-nis", "8", "--observer-quiet-motion-noises", "30",
                        "--observer-model-form-sigma", "0.05", "--observer-doubt-model-form-sigma", "0.3",
                        "--observer-capacity-min-x", "0.1", "--observer-doubt-capacity-min-x", "0.2",
                        "--engine-input-out", path.c_str()}) {
    fused.push_back(a);
  }
  const ProcessResult r = run_rockwatch(fused);
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const EngineInputFile f = read_engine_input(path);
  CHECK_TRUE(f.complete);
  CHECK_TRUE(f.keys_known);
  CHECK_TRUE(f.config.observer_enabled);
  DOUBLES_EQUAL(25.0, f.config.observer.gate_chi2, 0.0);
  DOUBLES_EQUAL(0.3, f.config.observer.process_accel_mps2, 0.0);
  DOUBLES_EQUAL(0.5, f.config.observer.alarm_capacity_sigmas, 0.0);
  DOUBLES_EQUAL(0.0, f.config.observer.accel_inform_peak_noises, 0.0);
  // Issue 40's settings (keys 44–52): before they had keys the M4 replay ran their defaults.
  DOUBLES_EQUAL(8.0, f.config.observer.doubt_nis, 0.0);
  DOUBLES_EQUAL(30.0, f.config.observer.quiet_motion_spread_noises, 0.0);
  DOUBLES_EQUAL(0.05, f.config.observer.model_form_sigma, 0.0);
  DOUBLES_EQUAL(0.3, f.config.observer.doubt_model_form_sigma, 0.0);
  DOUBLES_EQUAL(0.1, f.config.observer.capacity_min_x_fraction, 0.0);
  DOUBLES_EQUAL(0.2, f.config.observer.doubt_capacity_min_x_fraction, 0.0);
  LONGS_EQUAL(core::ObserverOptions{}.doubt_window, f.config.observer.doubt_window);
  DOUBLES_EQUAL(core::ObserverOptions{}.x_noise_m, f.config.observer.x_noise_m, 0.0);
  LONGS_EQUAL(core::ObserverOptions{}.stuck_after, f.config.observer.stuck_after);
  const std::vector<core::WallSensorSample> expected = rockwatch::cli::read_wall_sensor_samples(sensors);
  CHECK_TRUE(expected.size() > 100);
  LONGS_EQUAL(expected.size(), f.sensors.size());
  bool accel_seen = false;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK_EQUAL(expected[i].utime_us, f.sensors[i].utime_us);
    DOUBLES_EQUAL(expected[i].x_mid_m, f.sensors[i].x_mid_m, 0.0);
    DOUBLES_EQUAL(expected[i].a_mid_mps2, f.sensors[i].a_mid_mps2, 0.0);
    CHECK_EQUAL(expected[i].x_valid, f.sensors[i].x_valid);
    CHECK_EQUAL(expected[i].a_valid, f.sensors[i].a_valid);
    CHECK_EQUAL(expected[i].sensor_status, f.sensors[i].sensor_status);
    accel_seen = accel_seen || f.sensors[i].a_valid;
  }
  CHECK_TRUE(accel_seen);
  // A key value the image cannot take is refused, not guessed.
  core::WallEngineConfig c;
  CHECK_FALSE(firmware::apply_engine_input_key(c, std::uint64_t(firmware::EngineInputKey::observer_enabled), 0.5));
  CHECK_FALSE(firmware::apply_engine_input_key(c, std::uint64_t(firmware::EngineInputKey::observer_reinit_after), 2.5));
  CHECK_FALSE(firmware::apply_engine_input_key(c, 999, 1.0));
}

TEST(SimulateEngineInput, MisusesAreRefusedNamingTheOption) {
  TempDir dir;
  const std::string record = record_path(kElCentro180Input);
  rockwatch::test::expect_command_rejected("simulate", {"--record", record, "--engine-input-out", ""},
                                           {"--engine-input-out", "file name"});
  rockwatch::test::expect_command_rejected("simulate", {"--record", record, "--engine-input-out", dir.path()},
                                           {"--engine-input-out", "directory"});
  rockwatch::test::expect_command_rejected(
      "simulate", {"--record", record, "--engine-input-out", dir.path() + "/a", "--out", dir.path() + "/a"},
      {"--engine-input-out", "--out"});
  rockwatch::test::expect_command_rejected("simulate", {"--record", record, "--engine-input-out", record},
                                           {"--engine-input-out", "input record"});
}

// Every key carries its own field: each field set to a value other than its default and other than every other
// field's, written as the writer writes and read back into a default configuration, comes back (a key that shared a
// field with another, or was read into the wrong one, would not).
TEST(SimulateEngineInput, EveryKeyCarriesItsOwnField) {
  core::WallEngineConfig told;
  int n = 0;
  firmware::visit_engine_input_fields(told, [&n](firmware::EngineInputKey k, auto& field) {
    using T = std::decay_t<decltype(field)>;
    ++n;
    const auto key = static_cast<std::uint64_t>(k);
    if constexpr (std::is_same_v<T, bool>) {
      field = !field;
    } else if constexpr (std::is_same_v<T, core::ModelKind>) {
      field = core::ModelKind::full;
    } else if constexpr (std::is_same_v<T, core::WorkOverflow>) {
      field = core::WorkOverflow::finish;
    } else if constexpr (std::is_same_v<T, std::int32_t>) {
      field = static_cast<std::int32_t>(1000 + key);
    } else {
      field = 1000.0 + static_cast<double>(key) / 8.0;
    }
  });
  LONGS_EQUAL(55, n);
  core::WallEngineConfig read;
  int pairs = 0;
  firmware::for_each_engine_input_key(told, [&](firmware::EngineInputKey k, double v) {
    ++pairs;
    CHECK_TRUE(firmware::apply_engine_input_key(read, static_cast<std::uint64_t>(k), v));
  });
  LONGS_EQUAL(n, pairs);
  std::vector<double> want, got;
  firmware::for_each_engine_input_key(told, [&want](firmware::EngineInputKey, double v) { want.push_back(v); });
  firmware::for_each_engine_input_key(read, [&got](firmware::EngineInputKey, double v) { got.push_back(v); });
  CHECK_TRUE(want == got);
}
