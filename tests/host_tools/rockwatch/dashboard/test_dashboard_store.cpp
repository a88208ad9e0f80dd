// The dashboard's snapshot store and wall discovery: walls from channel names (default and suffixed, the longer base
// winning, bad suffixes ignored), decimation of x(t) to <= 30 points per second of sample time and of the WebSocket
// stream to <= 30 updates per second per wall, the transitions capped at 50, COLLAPSED latched until the monitor
// restarts, undecodable messages counted, P(collapse) over time from the monitor's forecasts.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "dashboard/dashboard_channels.hpp"
#include "dashboard/dashboard_receiver.hpp"
#include "dashboard/dashboard_store.hpp"

#include <CppUTest/TestHarness.h>

using nlohmann::json;
using rockwatch::cli::ChannelKind;
using rockwatch::cli::DashboardChannels;
using rockwatch::cli::match_channel;
using rockwatch::cli::SnapshotStore;
using rockwatch::cli::StoreSettings;

namespace {

constexpr std::int64_t kStartUtime = 1700000000000000;  // µs
constexpr std::int64_t kSecondNs = 1000000000;

rockwatch::wall_state_t state(std::int64_t seq, std::int64_t utime, double x_m, int level) {
  rockwatch::wall_state_t m{};
  m.utime = utime;
  m.seq = seq;
  m.input_seq = seq;
  m.schema_version = rockwatch::wall_state_t::SCHEMA_VERSION;
  m.x_m = x_m;
  m.xd_mps = 0.5;
  m.side = 1;
  m.moving = 1;
  m.energy_ratio = 0.25;
  m.alarm_level = static_cast<std::int8_t>(level);
  m.t_to_instability_s = -1.0;
  return m;
}

rockwatch::alarm_event_t alarm(std::int64_t seq, std::int64_t utime, int level, int previous) {
  rockwatch::alarm_event_t m{};
  m.utime = utime;
  m.seq = seq;
  m.input_seq = seq;
  m.schema_version = rockwatch::alarm_event_t::SCHEMA_VERSION;
  m.level = static_cast<std::int8_t>(level);
  m.previous_level = static_cast<std::int8_t>(previous);
  m.reasons = 1;
  m.t_to_instability_s = 0.25;
  return m;
}

const json& wall_of(const json& state, const std::string& name) {
  for (const json& w : state.at("walls")) {
    if (w.at("name") == name) return w;
  }
  FAIL(("no wall " + name + " in " + state.dump()).c_str());
  return state;
}

// 200 Hz states of wall "wall" for `seconds` of sample time from `first_seq`.
void feed(SnapshotStore& store, std::int64_t first_seq, double seconds, int level = 1) {
  const int n = static_cast<int>(seconds * 200.0);
  for (int i = 0; i < n; ++i) {
    const std::int64_t seq = first_seq + i;
    store.on_state("wall", state(seq, kStartUtime + seq * 5000, 0.01 * std::sin(0.05 * static_cast<double>(seq)), level));
  }
}

}  // namespace

TEST_GROUP(DashboardChannels){};

TEST(DashboardChannels, TheDefaultChannelsAreWallNamedWall) {
  const DashboardChannels c;
  const struct {
    const char* channel;
    ChannelKind kind;
  } cases[] = {{"ROCKWATCH_WALL_STATE", ChannelKind::state},   {"ROCKWATCH_ALARM", ChannelKind::alarm},
               {"ROCKWATCH_STATUS", ChannelKind::status},      {"ROCKWATCH_WALL_SENSOR", ChannelKind::sensor},
               {"ROCKWATCH_WALL_ESTIMATE", ChannelKind::estimate}, {"ROCKWATCH_WALL_FORECAST", ChannelKind::forecast}};
  for (const auto& k : cases) {
    const auto m = match_channel(c, k.channel);
    CHECK_TEXT(m.has_value(), k.channel);
    CHECK_TEXT(m->kind == k.kind, k.channel);
    STRCMP_EQUAL("wall", m->wall.c_str());
  }
}

TEST(DashboardChannels, ASuffixNamesTheWall) {
  const DashboardChannels c;
  auto m = match_channel(c, "ROCKWATCH_WALL_STATE_east");
  CHECK(m.has_value() && m->kind == ChannelKind::state);
  STRCMP_EQUAL("east", m->wall.c_str());
  m = match_channel(c, "ROCKWATCH_STATUS_north-2_b");
  CHECK(m.has_value() && m->kind == ChannelKind::status);
  STRCMP_EQUAL("north-2_b", m->wall.c_str());
  m = match_channel(c, "ROCKWATCH_ALARM_x");
  CHECK(m.has_value() && m->kind == ChannelKind::alarm);
  STRCMP_EQUAL("x", m->wall.c_str());
}

TEST(DashboardChannels, OtherChannelsAndBadSuffixesAreNotWalls) {
  const DashboardChannels c;
  for (const char* channel : {"ROCKWATCH_ACCEL", "ROCKWATCH_ACCEL_BATCH", "ROCKWATCH_WALL_STATE_", "ROCKWATCH_ALARMX",
                              "ROCKWATCH_WALL_STATE_a.b", "ROCKWATCH_WALL_STATE_a b", "XROCKWATCH_STATUS", "",
                              "ROCKWATCH_STATUS_01234567890123456789012345678901234567890"}) {
    CHECK_FALSE_TEXT(match_channel(c, channel).has_value(), channel);
  }
}

TEST(DashboardChannels, TheLongerBaseWins) {
  DashboardChannels c;
  c.alarm = "ROCKWATCH_WALL";  // ROCKWATCH_WALL_STATE_east could be alarm wall "STATE_east"
  auto m = match_channel(c, "ROCKWATCH_WALL_STATE_east");
  CHECK(m.has_value() && m->kind == ChannelKind::state);
  STRCMP_EQUAL("east", m->wall.c_str());
  m = match_channel(c, "ROCKWATCH_WALL_STATE");
  CHECK(m.has_value() && m->kind == ChannelKind::state);
  m = match_channel(c, "ROCKWATCH_WALL_west");
  CHECK(m.has_value() && m->kind == ChannelKind::alarm);
  STRCMP_EQUAL("west", m->wall.c_str());
}

TEST(DashboardChannels, SubscriptionsFindEveryWallOverLcm) {
  // liblcm's own regular-expression matching, through memq:// (the receiver's subscriptions, not a copy of them).
  lcm::LCM lcm("memq://");
  CHECK(lcm.good());
  std::vector<std::string> received;
  const DashboardChannels c;
  lcm.subscribeFunction(
      rockwatch::cli::subscription_regex(c.state),
      +[](const lcm::ReceiveBuffer*, const std::string& channel, std::vector<std::string>* out) { out->push_back(channel); },
      &received);
  const char byte = 0;
  for (const char* channel : {"ROCKWATCH_WALL_STATE", "ROCKWATCH_WALL_STATE_east", "ROCKWATCH_WALL_STATEX",
                              "ROCKWATCH_WALL_SENSOR", "PREFIX_ROCKWATCH_WALL_STATE"}) {
    lcm.publish(channel, &byte, 1);
  }
  while (lcm.handleTimeout(0) > 0) {
  }
  CHECK_EQUAL(2u, received.size());
  STRCMP_EQUAL("ROCKWATCH_WALL_STATE", received[0].c_str());
  STRCMP_EQUAL("ROCKWATCH_WALL_STATE_east", received[1].c_str());
}

TEST_GROUP(DashboardStore){};

TEST(DashboardStore, WallsAppearFromTheirChannelsAndUndecodableMessagesAreCounted) {
  SnapshotStore store{StoreSettings{}};
  const DashboardChannels c;
  for (const char* channel : {"ROCKWATCH_WALL_STATE", "ROCKWATCH_WALL_STATE_east"}) {
    rockwatch::wall_state_t m = state(0, kStartUtime, 0.001, 1);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    CHECK(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())) > 0);
    rockwatch::cli::LcmReceiver::deliver(c, store, channel, bytes.data(), bytes.size());
  }
  // A truncated state, a status where an alarm is expected, a byte of garbage: counted, no wall.
  rockwatch::monitor_status_t status{};
  std::vector<std::uint8_t> status_bytes(static_cast<std::size_t>(status.getEncodedSize()));
  CHECK(status.encode(status_bytes.data(), 0, static_cast<int>(status_bytes.size())) > 0);
  rockwatch::cli::LcmReceiver::deliver(c, store, "ROCKWATCH_ALARM_west", status_bytes.data(), status_bytes.size());
  rockwatch::cli::LcmReceiver::deliver(c, store, "ROCKWATCH_WALL_STATE_north", status_bytes.data(), 10);
  const std::uint8_t garbage = 0xff;
  rockwatch::cli::LcmReceiver::deliver(c, store, "ROCKWATCH_STATUS", &garbage, 1);
  const json s = store.state_json();
  CHECK_EQUAL(2u, s.at("walls").size());
  STRCMP_EQUAL("east", s["walls"][0]["name"].get<std::string>().c_str());
  STRCMP_EQUAL("wall", s["walls"][1]["name"].get<std::string>().c_str());
  CHECK_EQUAL(3, s["receiver"]["decode_errors"].get<int>());
  STRCMP_EQUAL("ROCKING", s["walls"][1]["level"].get<std::string>().c_str());
  DOUBLES_EQUAL(0.001, s["walls"][1]["x_m"].get<double>(), 0.0);
}

// The observer's sensors (wall_estimate_t schema 3) reach the page as one status per sensor: the accelerometer's
// rejected reading with its test ratio, the displacement's last fused time; null where nothing was fused.
TEST(DashboardStore, TheEstimateCarriesEachSensorsFusionStatus) {
  SnapshotStore store{StoreSettings{}};
  store.on_state("wall", state(0, kStartUtime, 0.001, 1));
  rockwatch::wall_estimate_t e{};
  e.utime = kStartUtime;
  e.innovation_x_m = 2e-4;
  e.x_innovation_var_m2 = 4e-7;
  e.x_test_ratio = 0.00625;
  e.x_last_fused_utime = kStartUtime - 5000;
  e.innovation_a_mps2 = 3.0;
  e.a_innovation_var_m2ps4 = 0.01;
  e.a_test_ratio = 56.25;
  e.a_rejected = 1;
  store.on_estimate("wall", e);
  const json s = store.state_json();
  const json& sensors = s["walls"][0]["estimate"]["sensors"];
  DOUBLES_EQUAL(2e-4, sensors["x"]["innovation"].get<double>(), 0.0);
  DOUBLES_EQUAL(4e-7, sensors["x"]["innovation_variance"].get<double>(), 0.0);
  DOUBLES_EQUAL(0.00625, sensors["x"]["test_ratio"].get<double>(), 0.0);
  CHECK_FALSE(sensors["x"]["rejected"].get<bool>());
  CHECK(sensors["x"]["last_fused_utime"].get<std::int64_t>() == kStartUtime - 5000);
  CHECK(sensors["a"]["rejected"].get<bool>());
  DOUBLES_EQUAL(56.25, sensors["a"]["test_ratio"].get<double>(), 0.0);
  CHECK(sensors["a"]["last_fused_utime"].is_null());
}

TEST(DashboardStore, HistoryKeepsAtMost30PointsPerSecondAndTheLast30Seconds) {
  SnapshotStore store{StoreSettings{}};
  feed(store, 0, 40.0);  // 8000 states at 200 Hz
  const json w = wall_of(store.state_json(), "wall");
  const json& points = w.at("points");
  // The window (t - 30 s, t] at 30 points per second.
  CHECK_TEXT(points.size() >= 899u && points.size() <= 900u, std::to_string(points.size()).c_str());
  const double first = points.front()[1].get<double>(), last = points.back()[1].get<double>();
  CHECK(last - first < 30.0);
  DOUBLES_EQUAL(static_cast<double>(kStartUtime) * 1e-6 + 7999 * 0.005, last, 1e-6);
  // No two points in the same 1/30-s bin, and each point is the largest |x| of the states in its bin.
  for (std::size_t i = 1; i < points.size(); ++i) {
    CHECK(std::floor(points[i][1].get<double>() * 30.0) > std::floor(points[i - 1][1].get<double>() * 30.0));
    CHECK(points[i][0].get<std::uint64_t>() == points[i - 1][0].get<std::uint64_t>() + 1);
  }
  for (const json& p : points) CHECK(std::fabs(p[2].get<double>()) <= 0.01);
}

TEST(DashboardStore, TheBinKeepsThePeak) {
  SnapshotStore store{StoreSettings{}};
  // Six states inside one 1/30-s bin (5 ms apart, starting at a bin boundary): the largest |x| stays.
  const std::int64_t t0 = kStartUtime + 1000;  // kStartUtime (1.7e9 s) is a bin boundary: 1.7e9 * 30 is whole
  const double xs[] = {0.001, -0.004, 0.002, 0.003, -0.001, 0.0};
  for (int i = 0; i < 6; ++i) store.on_state("wall", state(i, t0 + i * 5000, xs[i], 1));
  const json w = wall_of(store.state_json(), "wall");
  CHECK_EQUAL(1u, w["points"].size());
  DOUBLES_EQUAL(-0.004, w["points"][0][2].get<double>(), 0.0);
  DOUBLES_EQUAL(0.0, w["x_m"].get<double>(), 0.0);  // the current value is the last one
}

TEST(DashboardStore, TheStreamSendsAtMost30UpdatesPerSecondPerWall) {
  SnapshotStore store{StoreSettings{}};
  std::int64_t seq_wall = 0, seq_east = 0;
  std::int64_t now_ns = 5 * kSecondNs;
  int updates_wall = 0, updates_east = 0;
  std::int64_t last_wall_ns = -kSecondNs;
  std::int64_t min_gap_ns = kSecondNs;
  // Two walls at 200 Hz, polled every 1 ms for 2 s: 400 states each, at most 30 updates per second each.
  for (int ms = 0; ms < 2000; ++ms, now_ns += 1000000) {
    if (ms % 5 == 0) {
      store.on_state("wall", state(seq_wall, kStartUtime + seq_wall * 5000, 0.001, 1));
      ++seq_wall;
      store.on_state("east", state(seq_east, kStartUtime + seq_east * 5000, 0.002, 1));
      ++seq_east;
    }
    for (const std::string& text : store.take_updates(now_ns)) {
      const json u = json::parse(text);
      STRCMP_EQUAL("update", u["type"].get<std::string>().c_str());
      if (u["wall"]["name"] == "wall") {
        ++updates_wall;
        if (updates_wall > 1) min_gap_ns = std::min(min_gap_ns, now_ns - last_wall_ns);
        last_wall_ns = now_ns;
      } else {
        ++updates_east;
      }
    }
  }
  CHECK_TEXT(updates_wall >= 58 && updates_wall <= 60, std::to_string(updates_wall).c_str());
  CHECK_TEXT(updates_east >= 58 && updates_east <= 60, std::to_string(updates_east).c_str());
  CHECK(min_gap_ns * 30 >= kSecondNs);
  // What came after the last update goes out once; then, nothing new, nothing sent.
  CHECK(store.take_updates(now_ns + kSecondNs).size() <= 2u);
  CHECK(store.take_updates(now_ns + 2 * kSecondNs).empty());
}

TEST(DashboardStore, UpdatesCarryOnlyWhatChangedAndResendAReplacedPoint) {
  SnapshotStore store{StoreSettings{}};
  feed(store, 0, 1.0);
  std::vector<std::string> u = store.take_updates(0);
  CHECK_EQUAL(1u, u.size());
  json first = json::parse(u[0])["wall"];
  const std::size_t n = first["points"].size();
  CHECK(n >= 30u && n <= 31u);
  CHECK(first.contains("transitions") && first.contains("status"));
  // One more state in the last point's bin, larger |x|: the next update re-sends that point (same id) only.
  const std::int64_t seq = 200;
  store.on_state("wall", state(seq, kStartUtime + 199 * 5000 + 100, 0.5, 1));
  u = store.take_updates(kSecondNs);
  CHECK_EQUAL(1u, u.size());
  const json second = json::parse(u[0])["wall"];
  CHECK_EQUAL(1u, second["points"].size());
  CHECK_EQUAL(first["points"][n - 1][0].get<std::uint64_t>(), second["points"][0][0].get<std::uint64_t>());
  DOUBLES_EQUAL(0.5, second["points"][0][2].get<double>(), 0.0);
  CHECK_FALSE(second.contains("transitions"));
  CHECK_FALSE(second.contains("status"));
  store.on_alarm("wall", alarm(0, kStartUtime, 2, 1));
  const json third = json::parse(store.take_updates(2 * kSecondNs).at(0))["wall"];
  CHECK_EQUAL(1u, third["transitions"].size());
  CHECK_EQUAL(0u, third["points"].size());
}

TEST(DashboardStore, TransitionsAreCappedAt50) {
  SnapshotStore store{StoreSettings{}};
  for (int i = 0; i < 120; ++i) store.on_alarm("wall", alarm(i, kStartUtime + i * 1000, 1 + i % 3, i % 3));
  const json w = wall_of(store.state_json(), "wall");
  CHECK_EQUAL(50u, w["transitions"].size());
  CHECK_EQUAL(120, w["transitions_total"].get<int>());
  CHECK_EQUAL(70, w["transitions"][0]["seq"].get<int>());  // the last 50: 70 .. 119
  CHECK_EQUAL(119, w["transitions"][49]["seq"].get<int>());
  DOUBLES_EQUAL(0.25, w["transitions"][49]["t_to_instability_s"].get<double>(), 0.0);
}

TEST(DashboardStore, CollapsedIsLatchedUntilTheMonitorRestarts) {
  SnapshotStore store{StoreSettings{}};
  feed(store, 0, 1.0, 3);
  store.on_alarm("wall", alarm(0, kStartUtime + 200 * 5000, 4, 3));
  // A later state that says IMMINENT (a reordered datagram, or a monitor whose alarm forgot): still COLLAPSED.
  store.on_state("wall", state(300, kStartUtime + 300 * 5000, 0.2, 3));
  json w = wall_of(store.state_json(), "wall");
  STRCMP_EQUAL("COLLAPSED", w["level"].get<std::string>().c_str());
  CHECK(w["collapsed_latched"].get<bool>());
  // A duplicate changes nothing; a sequence number that goes back is a new monitor: the wall starts afresh.
  store.on_state("wall", state(300, kStartUtime + 300 * 5000, 0.2, 3));
  CHECK_EQUAL(0, wall_of(store.state_json(), "wall")["counters"]["monitor_restarts"].get<int>());
  store.on_state("wall", state(0, kStartUtime + 400 * 5000, 0.0, 0));
  w = wall_of(store.state_json(), "wall");
  STRCMP_EQUAL("QUIET", w["level"].get<std::string>().c_str());
  CHECK_FALSE(w["collapsed_latched"].get<bool>());
  CHECK_EQUAL(1, w["counters"]["monitor_restarts"].get<int>());
  CHECK_EQUAL(0u, w["transitions"].size());
  CHECK_EQUAL(1u, w["points"].size());
}

TEST(DashboardStore, TheLatchHoldsWhenTheCollapseCameByTheStateAlone) {
  SnapshotStore store{StoreSettings{}};
  store.on_state("wall", state(0, kStartUtime, 0.2, 4));
  store.on_state("wall", state(1, kStartUtime + 5000, 0.0, 0));
  STRCMP_EQUAL("COLLAPSED", wall_of(store.state_json(), "wall")["level"].get<std::string>().c_str());
}

TEST(DashboardStore, ValuesThatAreNotNumbersAreNull) {
  SnapshotStore store{StoreSettings{}};
  rockwatch::wall_state_t m = state(0, kStartUtime, std::nan(""), 9);
  m.energy_ratio = INFINITY;
  store.on_state("wall", m);
  const json w = wall_of(store.state_json(), "wall");
  CHECK(w["x_m"].is_null());
  CHECK(w["energy_ratio"].is_null());
  CHECK(w["t_to_instability_s"].is_null());
  STRCMP_EQUAL("LEVEL_9", w["level"].get<std::string>().c_str());
  CHECK(json::parse(store.state_json().dump()).is_object());
}

TEST(DashboardStore, WallsAreBounded) {
  StoreSettings settings;
  settings.max_walls = 3;
  SnapshotStore store{settings};
  for (int i = 0; i < 10; ++i) store.on_state("w" + std::to_string(i), state(0, kStartUtime, 0.0, 0));
  CHECK_EQUAL(3u, store.wall_count());
  CHECK_EQUAL(7, store.walls_refused());
}

TEST(DashboardStore, StatusAndMeasuredXAreKept) {
  SnapshotStore store{StoreSettings{}};
  rockwatch::monitor_status_t s{};
  s.seq = 4;
  s.samples_received = 1234;
  s.data_quality = rockwatch::monitor_status_t::QUALITY_GAP_BRIDGED | rockwatch::monitor_status_t::QUALITY_LATE;
  store.on_status("east", s);
  rockwatch::wall_sensor_t x{};
  x.utime = kStartUtime;
  x.valid = rockwatch::wall_sensor_t::VALID_X;
  x.x_mid_m = 0.0125;
  store.on_sensor("east", x);
  x.utime += 100000;
  x.valid = rockwatch::wall_sensor_t::VALID_A;  // no displacement: no measured point
  store.on_sensor("east", x);
  const json w = wall_of(store.state_json(), "east");
  CHECK_EQUAL(1234, w["status"]["counters"]["samples_received"].get<int>());
  CHECK(w["status"]["data_quality"] == json({"gap_bridged", "late"}));
  CHECK_EQUAL(1u, w["measured"].size());
  DOUBLES_EQUAL(0.0125, w["measured"][0][2].get<double>(), 0.0);
  CHECK_EQUAL(2, w["counters"]["sensor_samples"].get<int>());
}

// rockwatch-monitor --forecast: P(collapse) over time (0 at rest, nothing without input), the latest forecast; a
// forecast sequence that goes back (the monitor restarted) starts the curve again; the raw message through
// deliver_message as the receiver hands it. Each point carries the ensemble's P and the calibrated P (null where the
// monitor had no coefficients for its horizon).
TEST(DashboardStore, ForecastsGiveTheCollapseOddsOverTime) {
  SnapshotStore store{StoreSettings{}};
  const DashboardChannels channels;
  auto forecast = [](std::int64_t seq, std::int64_t utime, int status, double p,
                     double p_calibrated = std::numeric_limits<double>::quiet_NaN()) {
    rockwatch::wall_forecast_t f{};
    f.utime = utime;
    f.seq = seq;
    f.schema_version = rockwatch::wall_forecast_t::SCHEMA_VERSION;
    f.wall = "wall";
    f.status = static_cast<std::int8_t>(status);
    f.horizon_s = 5.0;
    f.members = status == rockwatch::wall_forecast_t::STATUS_OK ? 200 : 0;
    f.p_collapse = p;
    f.p_collapse_se = std::sqrt(p * (1.0 - p) / 200.0);
    f.p_collapse_calibrated = p_calibrated;
    f.compute_us = 4200;
    return f;
  };
  using F = rockwatch::wall_forecast_t;
  const F sequence[] = {forecast(0, 0, F::STATUS_NO_INPUT, 0.0), forecast(1, kStartUtime, F::STATUS_AT_REST, 0.0),
                        forecast(2, kStartUtime + 100000, F::STATUS_OK, 0.25),
                        forecast(3, kStartUtime + 200000, F::STATUS_OK, 0.75, 0.62)};
  for (const F& f : sequence) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(f.getEncodedSize()));
    f.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    rockwatch::cli::deliver_message(channels, store, "ROCKWATCH_WALL_FORECAST", bytes.data(), bytes.size());
  }
  json w = wall_of(store.state_json(), "wall");
  CHECK_EQUAL(4, w["counters"]["forecasts"].get<int>());
  const json& points = w["forecast_points"];
  CHECK_EQUAL(3u, points.size());  // none for NO_INPUT
  DOUBLES_EQUAL(0.0, points[0][2].get<double>(), 0.0);
  DOUBLES_EQUAL(0.25, points[1][2].get<double>(), 0.0);
  DOUBLES_EQUAL(0.75, points[2][2].get<double>(), 0.0);
  DOUBLES_EQUAL(0.0, points[0][3].get<double>(), 0.0);  // at rest: 0 either way
  CHECK(points[1][3].is_null());                         // no coefficients: the ensemble's alone
  DOUBLES_EQUAL(0.62, points[2][3].get<double>(), 0.0);
  DOUBLES_EQUAL(0.62, w["forecast"]["p_collapse_calibrated"].get<double>(), 0.0);
  DOUBLES_EQUAL(kStartUtime * 1e-6 + 0.2, points[2][1].get<double>(), 1e-6);
  STRCMP_EQUAL("ok", w["forecast"]["status"].get<std::string>().c_str());
  DOUBLES_EQUAL(0.75, w["forecast"]["p_collapse"].get<double>(), 0.0);
  CHECK_EQUAL(200, w["forecast"]["members"].get<int>());
  // The monitor restarted: its forecasts count from 0 again.
  store.on_forecast("wall", forecast(0, kStartUtime + 300000, F::STATUS_OK, 0.5));
  w = wall_of(store.state_json(), "wall");
  CHECK_EQUAL(1u, w["forecast_points"].size());
  DOUBLES_EQUAL(0.5, w["forecast_points"][0][2].get<double>(), 0.0);
}
