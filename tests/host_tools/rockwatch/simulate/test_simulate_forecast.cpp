// `rockwatch simulate --forecast-members N --forecast-horizon-s H [--forecast-every-s S]` (issue 29, SPEC §10): the JSON
// `forecast` object and its series (one entry every S s while the wall moves, the alarm's level beside each with
// --alarms), an entry equal to sim::EnsembleForecaster run in-process on sim::analyse's state, the same output on a
// second run, a wall at rest, and out-of-range options refused naming the option; with --wall-sensors, an entry equal
// to the forecaster on the fused state with the observer's spread and estimated wall.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;
namespace core = rockwatch::core;

namespace {

const char* const kElCentro180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";

std::vector<std::string> el_centro(const std::string& pga_g, const std::vector<std::string>& more) {
  std::vector<std::string> a{"simulate", "--record", record_path(kElCentro180), "--scale-pga", pga_g};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

const std::vector<std::string> kForecast{"--forecast-members", "20", "--forecast-horizon-s", "1",
                                         "--forecast-every-s", "0.25"};

// The record of el_centro(pga_g, ...) as simulate runs it: scaled to pga_g.
sim::GroundMotion el_centro_motion(double pga_g) {
  const rockwatch::records::Record rec = rockwatch::records::read_record(record_path(kElCentro180));
  sim::GroundMotion m;
  m.dt_s = rec.dt_s;
  m.ug_mps2 = rec.horizontal_mps2;
  const double factor = pga_g * kG / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  return m;
}

// The last row at or before t_s (the rows in time order), as run_forecasts picks the state of a forecast time.
template <typename Row>
std::size_t row_at(const std::vector<Row>& rows, double t_s) {
  std::size_t row = 0;
  while (row + 1 < rows.size() && rows[row + 1].t_s <= t_s + 1e-9) ++row;
  return row;
}

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

}  // namespace

TEST_GROUP(SimulateForecast){};

TEST(SimulateForecast, SeriesWhileTheWallMovesWithTheAlarmBeside) {
  std::vector<std::string> args = kForecast;
  args.insert(args.end(), {"--alarms", "--json"});
  const ProcessResult r = run_rockwatch(el_centro("0.3", args));
  check_ok(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK_TRUE(j["collapsed"].get<bool>());
  const double t_collapse = j["t_collapse_s"].get<double>();
  const nlohmann::json& f = j["forecast"];
  std::vector<std::string> keys;
  for (auto it = f.begin(); it != f.end(); ++it) keys.push_back(it.key());
  const std::vector<std::string> expected{"at_rest_skipped", "calibration", "every_s", "horizon_s", "members", "seed",
                                          "series", "step_s"};
  CHECK_TRUE(keys == expected);  // nlohmann::json sorts its keys
  LONGS_EQUAL(20, f["members"].get<int>());
  DOUBLES_EQUAL(1.0, f["horizon_s"].get<double>(), 0.0);
  DOUBLES_EQUAL(0.25, f["every_s"].get<double>(), 0.0);
  const nlohmann::json& series = f["series"];
  CHECK_TRUE(series.size() >= 2);
  // Every forecast time before the collapse is either an entry or a time at rest.
  const std::size_t times = static_cast<std::size_t>(std::floor(t_collapse / 0.25 - 1e-9)) + 1;
  LONGS_EQUAL(times, series.size() + f["at_rest_skipped"].get<std::size_t>());
  double previous_t = -1.0;
  for (const nlohmann::json& e : series) {
    const double t = e["t_s"].get<double>();
    CHECK_TRUE(t > previous_t && t < t_collapse);
    DOUBLES_EQUAL(0.0, std::remainder(t, 0.25), 1e-9);
    previous_t = t;
    const double p = e["p_collapse"].get<double>();
    CHECK_TRUE(p >= 0.0 && p <= 1.0);
    DOUBLES_EQUAL(std::sqrt(p * (1.0 - p) / 20.0), e["p_collapse_se"].get<double>(), 1e-15);
    CHECK_TRUE(e["q90_max_x_over_x_inst"].get<double>() >= e["q50_max_x_over_x_inst"].get<double>());
    CHECK_TRUE(e["q90_max_x_over_x_inst"].get<double>() <= 2.0);
    CHECK_TRUE(e["alarm"].is_string());
  }
  // No coefficients are shipped for H = 1 s: no calibrated P (SPEC §10 "Calibrated P").
  CHECK_FALSE(f["calibration"]["applied"].get<bool>());
  CHECK_TRUE(series[0]["p_collapse_calibrated"].is_null());
  // Just before the collapse the wall is past x_inst moving out: every member falls.
  DOUBLES_EQUAL(1.0, series.back()["p_collapse"].get<double>(), 0.0);
  // The same command gives the same bytes.
  CHECK_TRUE(run_rockwatch(el_centro("0.3", args)).out == r.out);
  // Without --alarms no alarm beside the entries.
  std::vector<std::string> plain = kForecast;
  plain.push_back("--json");
  const ProcessResult p = run_rockwatch(el_centro("0.3", plain));
  check_ok(p);
  const nlohmann::json jp = nlohmann::json::parse(p.out);
  CHECK_FALSE(jp["forecast"]["series"][0].contains("alarm"));
  DOUBLES_EQUAL(series[0]["p_collapse"].get<double>(), jp["forecast"]["series"][0]["p_collapse"].get<double>(), 0.0);
}

TEST(SimulateForecast, AnEntryIsTheForecasterOnTheAnalysedState) {
  std::vector<std::string> args = kForecast;
  args.push_back("--json");
  const ProcessResult r = run_rockwatch(el_centro("0.3", args));
  check_ok(r);
  const nlohmann::json e = nlohmann::json::parse(r.out)["forecast"]["series"][0];
  const double t = e["t_s"].get<double>();

  const sim::GroundMotion m = el_centro_motion(0.3);
  sim::AnalysisOptions o;
  o.keep_history = true;
  const core::WallParameters w = core::paper_wall();
  const sim::AnalysisResult a = sim::analyse(w, m, o);
  const std::size_t row = row_at(a.history, t);
  sim::ForecastSettings s;
  s.members = 20;
  s.horizon_s = 1.0;
  sim::EnsembleForecaster f(w, o.model, a.r, o.kappa, s);
  sim::ForecastState st;
  st.moving = true;
  st.x_m = a.history[row].x_m;
  st.xd_mps = a.history[row].xd_mps;
  st.ug_now_mps2 = a.history[row].ug_mps2;
  const std::size_t n = static_cast<std::size_t>(std::floor(a.history[row].t_s / m.dt_s + 1e-9)) + 1;
  const sim::ForecastResult fr = f.forecast(st, m.ug_mps2.data(), n, m.dt_s);
  DOUBLES_EQUAL(fr.p_collapse, e["p_collapse"].get<double>(), 0.0);
  DOUBLES_EQUAL(fr.q50_max_x_over_x_inst, e["q50_max_x_over_x_inst"].get<double>(), 0.0);
  DOUBLES_EQUAL(fr.q90_max_x_over_x_inst, e["q90_max_x_over_x_inst"].get<double>(), 0.0);
}

// With --wall-sensors the members start from the fused state with the observer's σ_x, σ_ẋ, √r̂, κc and κk at that
// time (SPEC §10 "State uncertainty"), as rockwatch-monitor --forecast passes them: a wall 10 % thinner than the
// nominal one the monitor is told, its transducer read at the record's rate (0.5 mm noise).
TEST(SimulateForecast, WithWallSensorsTheMembersStartFromTheObserversEstimates) {
  TempDir dir;
  const std::string truth_csv = dir.file("truth.csv");
  check_ok(run_rockwatch(el_centro("0.3", {"--b", "0.09", "--sensors-out", truth_csv})));
  std::vector<std::string> args = kForecast;
  args.insert(args.end(), {"--wall-sensors", truth_csv, "--json"});
  const ProcessResult r = run_rockwatch(el_centro("0.3", args));
  check_ok(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& series = j["forecast"]["series"];
  CHECK_TRUE(series.size() >= 4);

  // The same analysis in-process, with its history and the observer's.
  const sim::GroundMotion m = el_centro_motion(0.3);
  const std::vector<core::WallSensorSample> samples = rockwatch::cli::read_wall_sensor_samples(truth_csv);
  sim::AnalysisOptions o;
  o.keep_history = true;
  o.wall_sensors = &samples;
  const core::WallParameters w = core::paper_wall();
  const sim::AnalysisResult a = sim::analyse(w, m, o);
  CHECK_TRUE(a.observer_history.size() > 100);
  sim::ForecastSettings fs;
  fs.members = 20;
  fs.horizon_s = 1.0;
  sim::EnsembleForecaster f(w, o.model, a.r, o.kappa, fs);
  const double open_loop_sigma_x_m = fs.default_sigma_fraction * a.x_inst_m;

  int differs_from_open_loop = 0;
  double last_capacity_scale = 1.0;
  for (const nlohmann::json& e : series) {
    const double t = e["t_s"].get<double>();
    const std::size_t row = row_at(a.history, t);
    const sim::ObserverHistoryRow& est = a.observer_history[row_at(a.observer_history, a.history[row].t_s)];
    CHECK_TRUE(est.t_s <= a.history[row].t_s + 1e-9);
    // What the entry says it started from: the observer's estimates at that time.
    DOUBLES_EQUAL(est.sigma_x_m, e["sigma_x_m"].get<double>(), 0.0);
    DOUBLES_EQUAL(est.sigma_xd_mps, e["sigma_xd_mps"].get<double>(), 0.0);
    DOUBLES_EQUAL(est.sqrt_r * est.sqrt_r, e["r_estimate"].get<double>(), 0.0);
    DOUBLES_EQUAL(est.capacity_scale, e["capacity_scale"].get<double>(), 0.0);
    DOUBLES_EQUAL(est.stiffness_scale, e["stiffness_scale"].get<double>(), 0.0);
    // A transducer of 0.5 mm pins the state far tighter than the open loop's 5 % of x_inst.
    CHECK_TRUE(est.sigma_x_m > 0.0 && est.sigma_x_m < 0.5 * open_loop_sigma_x_m);
    last_capacity_scale = est.capacity_scale;

    sim::ForecastState st;
    st.moving = true;
    st.x_m = a.history[row].x_m;
    st.xd_mps = a.history[row].xd_mps;
    st.ug_now_mps2 = a.history[row].ug_mps2;
    const std::size_t n = static_cast<std::size_t>(std::floor(a.history[row].t_s / m.dt_s + 1e-9)) + 1;
    const sim::ForecastResult open = f.forecast(st, m.ug_mps2.data(), n, m.dt_s);
    st.sigma_x_m = est.sigma_x_m;
    st.sigma_xd_mps = est.sigma_xd_mps;
    st.sqrt_r = est.sqrt_r;
    st.capacity_scale = est.capacity_scale;
    st.stiffness_scale = est.stiffness_scale;
    const sim::ForecastResult fused = f.forecast(st, m.ug_mps2.data(), n, m.dt_s);
    DOUBLES_EQUAL(fused.p_collapse, e["p_collapse"].get<double>(), 0.0);
    DOUBLES_EQUAL(fused.q50_max_x_over_x_inst, e["q50_max_x_over_x_inst"].get<double>(), 0.0);
    DOUBLES_EQUAL(fused.q90_max_x_over_x_inst, e["q90_max_x_over_x_inst"].get<double>(), 0.0);
    if (open.p_collapse != fused.p_collapse || open.q50_max_x_over_x_inst != fused.q50_max_x_over_x_inst ||
        open.q90_max_x_over_x_inst != fused.q90_max_x_over_x_inst) {
      ++differs_from_open_loop;
    }
  }
  // The estimates change the members (not the open loop's spread and wall under another name) ...
  CHECK_TRUE(differs_from_open_loop * 2 > static_cast<int>(series.size()));
  // ... and by the last forecast the observer has moved the capacity towards the thinner wall's (κc 0.9).
  CHECK_TRUE(last_capacity_scale < 0.99);

  // Without --wall-sensors the entries carry no estimates.
  std::vector<std::string> plain = kForecast;
  plain.push_back("--json");
  const nlohmann::json p = nlohmann::json::parse(run_rockwatch(el_centro("0.3", plain)).out);
  CHECK_FALSE(p["forecast"]["series"][0].contains("sigma_x_m"));
  // The text says where the members start.
  std::vector<std::string> text = kForecast;
  text.insert(text.end(), {"--wall-sensors", truth_csv});
  const ProcessResult tr = run_rockwatch(el_centro("0.3", text));
  check_ok(tr);
  CHECK_TEXT(tr.out.find("from the fused state, with the observer's") != std::string::npos, tr.out.c_str());
}

TEST(SimulateForecast, AWallThatNeverMovesHasNoForecastAndSaysSo) {
  const ProcessResult j = run_rockwatch(el_centro("0.05", {"--forecast-members", "10", "--forecast-horizon-s", "1",
                                                           "--forecast-every-s", "1", "--json"}));
  check_ok(j);
  const nlohmann::json f = nlohmann::json::parse(j.out)["forecast"];
  CHECK_TRUE(f["series"].empty());
  CHECK_TRUE(f["at_rest_skipped"].get<int>() > 0);
  const ProcessResult t = run_rockwatch(el_centro("0.05", {"--forecast-members", "10", "--forecast-horizon-s", "1",
                                                           "--forecast-every-s", "1"}));
  check_ok(t);
  CHECK_TEXT(t.out.find("at rest at every forecast time: no forecast") != std::string::npos, t.out.c_str());
}

TEST(SimulateForecast, OptionsOutOfRangeAreRefusedNamingTheOption) {
  const std::string rec = record_path(kElCentro180);
  auto reject = [&](const std::vector<std::string>& more, const std::string& option) {
    std::vector<std::string> a{"--record", rec};
    a.insert(a.end(), more.begin(), more.end());
    expect_command_rejected("simulate", a, {option});
  };
  reject({"--forecast-members", "0", "--forecast-horizon-s", "1"}, "--forecast-members");
  reject({"--forecast-members", "100001", "--forecast-horizon-s", "1"}, "--forecast-members");
  reject({"--forecast-members", "2.5", "--forecast-horizon-s", "1"}, "--forecast-members");
  reject({"--forecast-members", "10", "--forecast-horizon-s", "0"}, "--forecast-horizon-s");
  reject({"--forecast-members", "10", "--forecast-horizon-s", "61"}, "--forecast-horizon-s");
  reject({"--forecast-members", "10", "--forecast-horizon-s", "1", "--forecast-every-s", "0.001"},
         "--forecast-every-s");
  reject({"--forecast-members", "10"}, "--forecast-horizon-s");
  reject({"--forecast-every-s", "0.5"}, "--forecast-every-s");
}

// The calibration's inputs recomputed independently of the tool and of the forecaster (issue 42: they were only read
// back from the same JSON): from sim::analyse's history, E/E_barrier of every row with the core model's energy and
// barrier on the row's side, its maximum over the rows of the 2 s up to the entry's row (both ends included), and
// |x| / x_inst of the entry's row, at 0.2 g (where the energy also decays: the window's first row is its maximum at some
// entries). An energy window one sample short (tests/mutants/energy_window_one_sample_short.patch) fails here.
TEST(SimulateForecast, CalibrationInputsAreTheAnalysedHistorys) {
  std::vector<std::string> args = kForecast;
  args.insert(args.end(), {"--json", "--forecast-calibration", "-1,0.5,0.25,2"});
  const ProcessResult r = run_rockwatch(el_centro("0.2", args));
  check_ok(r);
  const nlohmann::json series = nlohmann::json::parse(r.out)["forecast"]["series"];
  const sim::GroundMotion m = el_centro_motion(0.2);
  sim::AnalysisOptions o;
  o.keep_history = true;
  const core::WallParameters w = core::paper_wall();
  const sim::AnalysisResult a = sim::analyse(w, m, o);
  const core::ModelConstants<double> c = core::model_constants(w, o.model);
  const auto side_of = [](int s) { return s > 0 ? core::Side::positive : core::Side::negative; };
  const auto energy_ratio = [&](const sim::HistoryRow& h) {
    const core::Side side = side_of(h.side);
    return core::mechanical_energy(core::evaluate(c, side, 0.0, w.g_mps2), h.x_m, h.xd_mps) /
           core::energy_barrier_jpm(c, side, w.g_mps2);
  };
  CHECK(series.size() >= 20);  // (0.2 g: 43 entries; the wall rocks, its energy rises and decays, and collapses)
  int rocking = 0;
  double largest = 0.0;
  for (const nlohmann::json& e : series) {
    const std::size_t row = row_at(a.history, e["t_s"].get<double>());
    const sim::HistoryRow& h = a.history[row];
    double e_max = 0.0;
    for (std::size_t i = 0; i <= row; ++i) {
      if (a.history[i].t_s >= h.t_s - 2.0 - 1e-9) e_max = std::max(e_max, energy_ratio(a.history[i]));
    }
    const double x_over = std::fabs(h.x_m) / core::x_inst_m(c, side_of(h.side), w.g_mps2);
    const std::string what = "t " + std::to_string(e["t_s"].get<double>());
    DOUBLES_EQUAL_TEXT(e_max, e["energy_ratio_max_2s"].get<double>(), 1e-12 * std::max(1.0, e_max), what.c_str());
    DOUBLES_EQUAL_TEXT(x_over, e["x_over_x_inst"].get<double>(), 1e-12, what.c_str());
    if (x_over > 0.05) ++rocking;
    largest = std::max(largest, e_max);
  }
  // Not a trivial record: the wall rocks at several entries and its energy reaches a good part of the barrier.
  CHECK(rocking >= 10);
  CHECK(largest > 0.1);
}

// The calibrated P beside the raw one (SPEC §10 "Calibrated P"): with given coefficients, the logistic of
// c0 + c1 logit(clamped P) + c2 energy_ratio_max_2s + c3 x_over_x_inst of each entry; at H = 3 s the shipped ones.
// Forecasts from the fused state (--wall-sensors) publish the P of the coefficients fitted on fused forecasts (SPEC
// §10 "From the fused state"), the open loop's the other shipped ones; a given --forecast-calibration serves both.
TEST(SimulateForecast, FusedForecastsTakeTheFusedStatesCalibration) {
  TempDir dir;
  const std::string truth_csv = dir.file("truth.csv");
  check_ok(run_rockwatch(el_centro("0.3", {"--b", "0.09", "--sensors-out", truth_csv})));
  const std::vector<std::string> five{"--forecast-members", "20", "--forecast-horizon-s", "5", "--forecast-every-s",
                                      "0.1", "--json"};
  int fused_checked = 0;
  for (const bool with_sensors : {true, false}) {
    std::vector<std::string> args = five;
    if (with_sensors) args.insert(args.end(), {"--wall-sensors", truth_csv});
    const ProcessResult r = run_rockwatch(el_centro("0.3", args));
    check_ok(r);
    const nlohmann::json f = nlohmann::json::parse(r.out)["forecast"];
    const sim::ForecastCalibration want = *sim::default_forecast_calibration(5.0, with_sensors);
    const sim::ForecastCalibration other = *sim::default_forecast_calibration(5.0, !with_sensors);
    CHECK_EQUAL(want.source, f["calibration"]["source"].get<std::string>());
    CHECK_TRUE(f["series"].size() >= 4);
    for (const nlohmann::json& e : f["series"]) {
      const double p = e["p_collapse"].get<double>(), rho = e["energy_ratio_max_2s"].get<double>(),
                   xr = e["x_over_x_inst"].get<double>();
      const double pc = e["p_collapse_calibrated"].get<double>();
      DOUBLES_EQUAL(sim::calibrated_probability(want, p, 20, rho, xr), pc, 1e-12);
      if (with_sensors && std::fabs(sim::calibrated_probability(other, p, 20, rho, xr) - pc) > 1e-3) ++fused_checked;
    }
  }
  CHECK_TRUE(fused_checked >= 3);  // the two sets of coefficients tell apart
  std::vector<std::string> given = five;
  given.insert(given.end(), {"--wall-sensors", truth_csv, "--forecast-calibration", "-1,0.5,0.25,2"});
  const nlohmann::json g = nlohmann::json::parse(run_rockwatch(el_centro("0.3", given)).out)["forecast"];
  CHECK_EQUAL(std::string("given: -1,0.5,0.25,2"), g["calibration"]["source"].get<std::string>());
}

// Without a displacement reading within the observer's dropout time (a transducer whose one reading is at t = 0)
// the filter's σ grows with its process noise alone; a forecast drawn from it said P ≈ 1 where the wall had seconds
// left (on the real records, Brier skill −3.0 against the open loop's 0.40). Such forecasts start at the state
// without σ and take the open loop's coefficients ("fused": false, SPEC §10 "From the fused state"): here, where the
// observer's model is the run's own wall, the very forecasts of the open loop.
TEST(SimulateForecast, WithoutADisplacementReadingTheForecastsDropTheFiltersSpread) {
  TempDir dir;
  const std::string truth_csv = dir.file("truth.csv"), first_csv = dir.file("first.csv");
  check_ok(run_rockwatch(el_centro("0.3", {"--b", "0.09", "--sensors-out", truth_csv})));
  std::ifstream truth(truth_csv);
  std::string header, first;
  CHECK_TRUE(std::getline(truth, header) && std::getline(truth, first));
  rockwatch::test::write_text(first_csv, header + "\n" + first + "\n");
  const std::vector<std::string> five{"--b", "0.09", "--forecast-members", "20", "--forecast-horizon-s", "5",
                                      "--json"};
  std::vector<std::string> args = five;
  args.insert(args.end(), {"--wall-sensors", first_csv});
  const ProcessResult alone = run_rockwatch(el_centro("0.3", args));
  const ProcessResult open = run_rockwatch(el_centro("0.3", five));
  check_ok(alone);
  check_ok(open);
  const nlohmann::json f = nlohmann::json::parse(alone.out)["forecast"];
  const nlohmann::json o = nlohmann::json::parse(open.out)["forecast"];
  const sim::ForecastCalibration want = *sim::default_forecast_calibration(5.0, false);
  CHECK_EQUAL(want.source, f["calibration"]["not_fused"]["source"].get<std::string>());
  CHECK_EQUAL(sim::default_forecast_calibration(5.0, true)->source, f["calibration"]["source"].get<std::string>());
  CHECK_TRUE(f["series"].size() >= 4);
  LONGS_EQUAL(o["series"].size(), f["series"].size());
  for (std::size_t i = 0; i < f["series"].size(); ++i) {
    const nlohmann::json& e = f["series"][i];
    CHECK_FALSE(e["fused"].get<bool>());
    CHECK_TRUE(e["sigma_xd_mps"].get<double>() > 0.0);  // the filter's σ, published, not drawn from
    DOUBLES_EQUAL(o["series"][i]["t_s"].get<double>(), e["t_s"].get<double>(), 1e-12);
    DOUBLES_EQUAL(o["series"][i]["p_collapse"].get<double>(), e["p_collapse"].get<double>(), 1e-12);
    DOUBLES_EQUAL(sim::calibrated_probability(want, e["p_collapse"].get<double>(), 20,
                                              e["energy_ratio_max_2s"].get<double>(),
                                              e["x_over_x_inst"].get<double>()),
                  e["p_collapse_calibrated"].get<double>(), 1e-12);
  }
  // The report says so.
  const ProcessResult text = run_rockwatch(el_centro(
      "0.3", {"--b", "0.09", "--forecast-members", "20", "--forecast-horizon-s", "5", "--wall-sensors", first_csv}));
  check_ok(text);
  const std::string said = std::to_string(f["series"].size()) + " forecasts had no displacement reading";
  CHECK_TEXT(text.out.find(said) != std::string::npos, text.out.c_str());
}

TEST(SimulateForecast, CalibratedProbabilityBesideTheRawOne) {
  std::vector<std::string> args = kForecast;
  args.insert(args.end(), {"--json", "--forecast-calibration", "-1,0.5,0.25,2"});
  const ProcessResult r = run_rockwatch(el_centro("0.3", args));
  check_ok(r);
  const nlohmann::json f = nlohmann::json::parse(r.out)["forecast"];
  CHECK_TRUE(f["calibration"]["applied"].get<bool>());
  for (const nlohmann::json& e : f["series"]) {
    const double p = std::min(std::max(e["p_collapse"].get<double>(), 0.5 / 20.0), 1.0 - 0.5 / 20.0);
    const double z = -1.0 + 0.5 * std::log(p / (1.0 - p)) + 0.25 * e["energy_ratio_max_2s"].get<double>() +
                     2.0 * e["x_over_x_inst"].get<double>();
    DOUBLES_EQUAL(1.0 / (1.0 + std::exp(-z)), e["p_collapse_calibrated"].get<double>(), 1e-12);
    CHECK_TRUE(e["energy_ratio_max_2s"].get<double>() >= 0.0);
  }
  std::vector<std::string> three{"--forecast-members", "20", "--forecast-horizon-s", "3", "--forecast-every-s", "0.5",
                                 "--json"};
  const ProcessResult s3 = run_rockwatch(el_centro("0.3", three));
  check_ok(s3);
  const nlohmann::json g = nlohmann::json::parse(s3.out)["forecast"];
  CHECK_TRUE(g["calibration"]["applied"].get<bool>());
  DOUBLES_EQUAL(3.0, g["calibration"]["horizon_s"].get<double>(), 0.0);
  for (const nlohmann::json& e : g["series"]) {
    const double pc = e["p_collapse_calibrated"].get<double>();
    CHECK_TRUE(pc > 0.0 && pc < 1.0);
  }
  for (const char* bad : {"1,2", "1,2,3,x"}) {
    expect_command_rejected("simulate",
                            {"--record", record_path(kElCentro180), "--scale-pga", "0.3", "--forecast-members", "20",
                             "--forecast-horizon-s", "1", "--forecast-calibration", bad},
                            {"--forecast-calibration"});
  }
  expect_command_rejected("simulate",
                          {"--record", record_path(kElCentro180), "--scale-pga", "0.3", "--forecast-calibration",
                           "0,1,0,0"},
                          {"--forecast-calibration", "--forecast-members"});
}
