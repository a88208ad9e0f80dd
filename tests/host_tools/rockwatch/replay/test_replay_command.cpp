// `rockwatch replay` end to end: every invalid option refused with a message naming it; --log writes a standard LCM
// log that lcm::LogFile reads back (events, channels, seq 0..n-1, utime on the sample grid, values equal to
// --samples-out); --batch packs consecutive samples; --dropout leaves seq gaps that --samples-out marks; --speed 0
// is not paced; the --samples-out file is a plain record that `rockwatch simulate --arith fixed` reads sample for
// sample; and over real UDP multicast on this machine (ttl=0) a receiver in this process gets every sample at 1 kHz
// (skipped, with a note, when multicast does not work here: the probe of `rockwatch demo`). With --wall-file (the wall
// as a plant): the same messages as `simulate --wall-file --sensors-out` then `replay --wall-sensors`, the plant's
// verdict that of `simulate --wall-file --json`, and the option combinations it refuses.
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "ci_skip.hpp"
#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/replay_out/lcm_multicast.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;

std::vector<std::string> suite_record(const char* set, const char* component) {
  return {"--suite", kSuite, "--set", set, "--component", component};
}

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A --samples-out file: one row per seq, '#' comments, a header line, "# dropped" on the rows not sent.
struct SamplesCsv {
  std::vector<double> t, ug, vg;
  std::vector<bool> dropped;
};

SamplesCsv read_samples(const std::string& path) {
  std::ifstream in(path);
  if (!in) FAIL(("cannot open " + path).c_str());
  SamplesCsv csv;
  std::string line;
  bool header_seen = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header_seen) {
      STRCMP_EQUAL("t_s,ug_mps2,vg_mps2", line.c_str());
      header_seen = true;
      continue;
    }
    const std::size_t hash = line.find('#');
    csv.dropped.push_back(hash != std::string::npos && line.find("dropped", hash) != std::string::npos);
    std::stringstream fields(line.substr(0, hash));
    std::string field;
    std::vector<double> row;
    while (std::getline(fields, field, ',')) row.push_back(std::strtod(field.c_str(), nullptr));
    CHECK_EQUAL(3u, row.size());
    csv.t.push_back(row[0]);
    csv.ug.push_back(row[1]);
    csv.vg.push_back(row[2]);
  }
  CHECK_TEXT(header_seen, path.c_str());
  return csv;
}

struct LoggedSample {
  std::int64_t seq, utime, timestamp;
  double ug, vg;
};

struct LogContent {
  std::size_t events = 0;
  std::set<std::string> channels;
  std::vector<LoggedSample> samples;  // single and batched, in log order
  std::vector<std::int32_t> batch_counts;
};

LogContent read_log(const std::string& path) {
  LogContent log;
  lcm::LogFile file(path, "r");
  CHECK_TEXT(file.good(), path.c_str());
  for (const lcm::LogEvent* e = file.readNextEvent(); e != nullptr; e = file.readNextEvent()) {
    ++log.events;
    log.channels.insert(e->channel);
    if (e->channel == "ROCKWATCH_ACCEL") {
      rockwatch::ground_accel_t m;
      CHECK_EQUAL(e->datalen, m.decode(e->data, 0, e->datalen));
      CHECK_EQUAL(rockwatch::ground_accel_t::SCHEMA_VERSION, m.schema_version);
      log.samples.push_back({m.seq, m.utime, e->timestamp, m.ug_mps2, m.vg_mps2});
    } else {
      rockwatch::ground_accel_batch_t m;
      CHECK_EQUAL(e->datalen, m.decode(e->data, 0, e->datalen));
      log.batch_counts.push_back(m.count);
      for (std::int32_t k = 0; k < m.count; ++k) {
        log.samples.push_back({m.seq + k, m.utime + k * m.sample_period_us, e->timestamp, m.ug_mps2[k], m.vg_mps2[k]});
      }
    }
  }
  return log;
}

nlohmann::json run_json(const std::vector<std::string>& args) {
  const ProcessResult r = run_rockwatch(concat({"replay"}, concat(args, {"--json"})));
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
  CHECK_TEXT(j.is_object(), what.c_str());
  return j;
}

// The values sent for seq i equal the CSV row i (exactly: both are the same doubles, the CSV in shortest form).
void check_log_equals_samples(const LogContent& log, const SamplesCsv& csv, std::int64_t start_utime, double rate_hz) {
  for (const LoggedSample& s : log.samples) {
    const auto i = static_cast<std::size_t>(s.seq);
    CHECK(i < csv.ug.size());
    CHECK_FALSE(csv.dropped[i]);
    DOUBLES_EQUAL(csv.ug[i], s.ug, 0.0);
    DOUBLES_EQUAL(csv.vg[i], s.vg, 0.0);
    CHECK_EQUAL(start_utime + std::llround(static_cast<double>(s.seq) * 1e6 / rate_hz), s.utime);
  }
}

}  // namespace

TEST_GROUP(ReplayRejections){};

TEST(ReplayRejections, BadValuesNameTheOption) {
  const std::vector<std::string> rec = suite_record("1", "X");
  expect_command_rejected("replay", concat(rec, {"--rate", "0"}), {"--rate", "> 0"});
  expect_command_rejected("replay", concat(rec, {"--rate", "fast"}), {"--rate", "fast"});
  expect_command_rejected("replay", concat(rec, {"--rate", "20000"}), {"--rate", "10000"});
  expect_command_rejected("replay", concat(rec, {"--speed", "-1"}), {"--speed", ">= 0"});
  expect_command_rejected("replay", concat(rec, {"--batch", "51"}), {"--batch", "50"});
  expect_command_rejected("replay", concat(rec, {"--batch", "0"}), {"--batch"});
  expect_command_rejected("replay", concat(rec, {"--batch", "2.5"}), {"--batch"});
  expect_command_rejected("replay", concat(rec, {"--batch", "10", "--rate", "300"}), {"--batch", "microseconds"});
  expect_command_rejected("replay", concat(rec, {"--dropout", "1"}), {"--dropout", "[0, 1)"});
  expect_command_rejected("replay", concat(rec, {"--dropout", "-0.1"}), {"--dropout"});
  expect_command_rejected("replay", concat(rec, {"--noise-mps2", "-0.1"}), {"--noise-mps2", ">= 0"});
  expect_command_rejected("replay", concat(rec, {"--quantum-mps2", "0"}), {"--quantum-mps2", "> 0"});
  expect_command_rejected("replay", concat(rec, {"--bias-mps2", "nan"}), {"--bias-mps2"});
  expect_command_rejected("replay", concat(rec, {"--seed", "-3"}), {"--seed"});
  expect_command_rejected("replay", concat(rec, {"--lcm-channel", ""}), {"--lcm-channel"});
  expect_command_rejected("replay", concat(rec, {"--lcm-channel", std::string(64, 'C')}), {"--lcm-channel", "63"});
  expect_command_rejected("replay", concat(rec, {"--scale-pga", "-0.2"}), {"--scale-pga"});
  expect_command_rejected("replay", {"--rate", "200"}, {"no record"});
  expect_command_rejected("replay", concat(rec, {"--no-such-option", "0.2"}), {"unknown option", "--no-such-option"});
  expect_command_rejected("replay", concat(rec, {"--lcm-url", "nosuch://x"}), {"--lcm-url", "nosuch"});
}

TEST(ReplayRejections, OutputFilesAreCheckedBeforeAnythingIsSent) {
  const TempDir dir;
  const std::vector<std::string> rec = suite_record("1", "X");
  expect_command_rejected("replay", concat(rec, {"--log", dir.file("a"), "--samples-out", dir.file("a")}),
                          {"--log", "--samples-out", "same file"});
  expect_command_rejected("replay", concat(rec, {"--log", dir.file("no/such/dir/x.lcmlog")}), {"--log"});
  expect_command_rejected(
      "replay", concat(rec, {"--samples-out", dir.file("no/such/dir/x.csv"), "--speed", "0", "--lcm-url", "memq://"}),
      {"--samples-out"});
  expect_command_rejected("replay", concat(rec, {"--log", dir.file("x.lcmlog"), "--speed", "2"}), {"--speed", "--log"});
  const std::string input = rockwatch::test::record_path("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");
  expect_command_rejected("replay", {"--record", input, "--samples-out", input}, {"--samples-out", "input record"});
  CHECK_FALSE(std::ifstream(dir.file("a")).good());
  CHECK_FALSE(std::ifstream(dir.file("x.lcmlog")).good());
}

TEST(ReplayRejections, WallSensorFilesAndChannelsAreChecked) {
  const TempDir dir;
  const std::vector<std::string> rec = suite_record("1", "X");
  const std::string bad = dir.file("bad.csv");
  std::ofstream(bad) << "t_s,x_mid_m\n0,0.001\n0.005,abc\n";
  // A malformed file: exit 2 naming the file and the line, before anything is sent or written.
  expect_command_rejected("replay", concat(rec, {"--wall-sensors", bad, "--log", dir.file("x.lcmlog")}),
                          {"bad.csv:3", "x_mid_m", "abc"});
  CHECK_FALSE(std::ifstream(dir.file("x.lcmlog")).good());
  expect_command_rejected("replay", concat(rec, {"--wall-sensors", dir.file("missing.csv")}), {"missing.csv"});
  expect_command_rejected("replay", concat(rec, {"--wall-sensor-channel", "W"}), {"--wall-sensor-channel", "--wall-sensors"});
  const std::string good = dir.file("good.csv");
  std::ofstream(good) << "t_s,x_mid_m\n0,0.001\n";
  expect_command_rejected("replay", concat(rec, {"--wall-sensors", good, "--wall-sensor-channel", "ROCKWATCH_ACCEL"}),
                          {"--wall-sensor-channel", "ground channel"});
}

TEST_GROUP(ReplayLog){};

TEST(ReplayLog, LogHasOneEventPerSampleWithTheValuesOfSamplesOut) {
  const TempDir dir;
  const std::string log_path = dir.file("replay.lcmlog"), csv_path = dir.file("sent.csv");
  const nlohmann::json j = run_json(concat(suite_record("3", "Y"), {"--scale-pga", "0.25", "--vertical-from-suite",
                                                                    "--log", log_path, "--samples-out", csv_path}));
  CHECK(j["lcm_url"].is_null());  // --log alone: the log instead of the network, no pacing
  CHECK_FALSE(j["paced"].get<bool>());
  CHECK(j["lateness"].is_null());
  const std::size_t n = j["samples"].get<std::size_t>();
  CHECK_EQUAL(4001u, n);  // 20 s at 200 Hz: the suite's own grid
  CHECK_FALSE(j["resampled"].get<bool>());
  CHECK_EQUAL(n, j["log"]["events"].get<std::size_t>());

  const LogContent log = read_log(log_path);
  const SamplesCsv csv = read_samples(csv_path);
  CHECK_EQUAL(n, log.events);
  CHECK_EQUAL(1u, log.channels.size());
  CHECK_EQUAL(1u, log.channels.count("ROCKWATCH_ACCEL"));
  CHECK_EQUAL(n, csv.ug.size());
  const auto start = j["start_utime"].get<std::int64_t>();
  for (std::size_t i = 0; i < n; ++i) {
    CHECK_EQUAL(static_cast<std::int64_t>(i), log.samples[i].seq);
    CHECK_EQUAL(log.samples[i].utime, log.samples[i].timestamp);  // events stamped with the sample times
    DOUBLES_EQUAL(static_cast<double>(i) * 0.005, csv.t[i], 1e-12);
  }
  check_log_equals_samples(log, csv, start, 200.0);
  // The vertical came along, and the record was scaled: peak |ü| = 0.25 g.
  double peak = 0.0, peak_v = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    peak = std::fmax(peak, std::fabs(csv.ug[i]));
    peak_v = std::fmax(peak_v, std::fabs(csv.vg[i]));
  }
  DOUBLES_EQUAL(0.25 * 9.81, peak, 1e-9);
  CHECK(peak_v > 0.1);
}

TEST(ReplayLog, BatchesCarryConsecutiveSamples) {
  const TempDir dir;
  const std::string log_path = dir.file("batch.lcmlog"), csv_path = dir.file("sent.csv");
  const nlohmann::json j = run_json(concat(
      suite_record("1", "X"), {"--rate", "1000", "--batch", "50", "--log", log_path, "--samples-out", csv_path}));
  CHECK(j["resampled"].get<bool>());
  const std::size_t n = j["samples"].get<std::size_t>();
  CHECK_EQUAL(20001u, n);
  const LogContent log = read_log(log_path);
  CHECK_EQUAL((n + 49) / 50, log.events);
  CHECK_EQUAL(1u, log.channels.count("ROCKWATCH_ACCEL_BATCH"));
  CHECK_EQUAL(n, log.samples.size());
  for (std::size_t b = 0; b + 1 < log.batch_counts.size(); ++b) CHECK_EQUAL(50, log.batch_counts[b]);
  CHECK_EQUAL(1, log.batch_counts.back());
  for (std::size_t i = 0; i < n; ++i) CHECK_EQUAL(static_cast<std::int64_t>(i), log.samples[i].seq);
  // A batch's event is stamped with its last sample's time, when it is complete and sent.
  CHECK_EQUAL(log.samples[49].utime, log.samples[0].timestamp);
  check_log_equals_samples(log, read_samples(csv_path), j["start_utime"].get<std::int64_t>(), 1000.0);
}

TEST(ReplayLog, DropoutsLeaveSeqGapsThatSamplesOutMarks) {
  const TempDir dir;
  const std::string log_path = dir.file("drop.lcmlog"), csv_path = dir.file("sent.csv");
  const std::vector<std::string> args =
      concat(suite_record("2", "X"), {"--dropout", "0.2", "--seed", "7", "--noise-mps2", "0.05", "--quantum-mps2",
                                      "0.001", "--bias-mps2", "0.01", "--log", log_path, "--samples-out", csv_path});
  const nlohmann::json j = run_json(args);
  const std::size_t n = j["samples"].get<std::size_t>();
  const auto sent = j["samples_sent"].get<std::size_t>(), dropped = j["samples_dropped"].get<std::size_t>();
  CHECK_EQUAL(n, sent + dropped);
  CHECK(dropped > n / 10 && dropped < n * 3 / 10);  // about 20 %

  const LogContent log = read_log(log_path);
  const SamplesCsv csv = read_samples(csv_path);
  CHECK_EQUAL(sent, log.events);
  std::size_t gaps = 0, marked = 0;
  for (std::size_t k = 1; k < log.samples.size(); ++k) {
    CHECK(log.samples[k].seq > log.samples[k - 1].seq);
    if (log.samples[k].seq != log.samples[k - 1].seq + 1) ++gaps;
  }
  CHECK(gaps > 0);
  for (const bool d : csv.dropped) marked += d ? 1 : 0;
  CHECK_EQUAL(dropped, marked);
  check_log_equals_samples(log, csv, j["start_utime"].get<std::int64_t>(), 200.0);
  // Quantised to 1 mm/s2, with noise: the values sent are multiples of the quantum.
  for (const LoggedSample& s : log.samples) DOUBLES_EQUAL(std::nearbyint(s.ug / 0.001) * 0.001, s.ug, 1e-12);

  // The seed fixes the draws: the same seqs are dropped again.
  const std::string log2 = dir.file("drop2.lcmlog");
  std::vector<std::string> again = args;
  again[again.size() - 3] = log2;
  run_json(again);
  const LogContent second = read_log(log2);
  CHECK_EQUAL(log.samples.size(), second.samples.size());
  for (std::size_t k = 0; k < log.samples.size(); ++k) {
    CHECK_EQUAL(log.samples[k].seq, second.samples[k].seq);
    DOUBLES_EQUAL(log.samples[k].ug, second.samples[k].ug, 0.0);
  }
}

TEST(ReplayLog, SpeedZeroIsNotPaced) {
  // memq:// publishes inside the process: no network needed to see that a 20 s record is not paced.
  const nlohmann::json j = run_json(concat(suite_record("1", "Y"), {"--speed", "0", "--lcm-url", "memq://"}));
  CHECK_FALSE(j["paced"].get<bool>());
  CHECK(j["lateness"].is_null());
  CHECK_EQUAL(4001u, j["samples_sent"].get<std::size_t>());
  CHECK_EQUAL(4001u, j["messages"].get<std::size_t>());
  CHECK(j["elapsed_s"].get<double>() < 10.0);  // the record lasts 20 s
  STRCMP_EQUAL("memq://", j["lcm_url"].get<std::string>().c_str());
}

TEST(ReplayLog, SimulateReadsSamplesOutSampleForSample) {
  const TempDir dir;
  const std::string csv_path = dir.file("sent.csv"), history = dir.file("history.csv");
  run_json(concat(suite_record("3", "X"), {"--scale-pga", "0.25", "--noise-mps2", "0.02", "--quantum-mps2", "0.0005",
                                           "--speed", "0", "--lcm-url", "memq://", "--samples-out", csv_path}));
  const SamplesCsv csv = read_samples(csv_path);
  const ProcessResult r =
      run_rockwatch({"simulate", "--record", csv_path, "--arith", "fixed", "--dt", "0.005", "--max-step", "0.005",
                     "--out", history});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const rockwatch::test::Csv h = rockwatch::test::read_csv(history);
  CHECK(h.rows.size() >= csv.ug.size());
  // One integration step per sample (dt = max step = 5 ms): row k is sample k, as sent, to the engine's input
  // precision (the fixed-point engine takes u'' as Q7.56, as the monitor does: 2^-56 m/s2).
  for (std::size_t k = 0; k < csv.ug.size(); ++k) {
    DOUBLES_EQUAL(csv.t[k], h.rows[k][0], 1e-9);
    DOUBLES_EQUAL(csv.ug[k], h.rows[k][1], 0x1p-56);
  }
}

TEST_GROUP(ReplayMulticast){};

// Every sample of a 1 kHz replay arrives, exactly once and as sent, at a receiver in this process: the replay runs
// as a process of its own, the test receives with handleTimeout (no thread of its own).
namespace {

struct Received {
  std::map<std::int64_t, rockwatch::ground_accel_t> samples;
  std::size_t duplicates = 0;
};

void on_sample(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/, Received* received) {
  rockwatch::ground_accel_t m;
  if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
  if (!received->samples.emplace(m.seq, m).second) ++received->duplicates;
}

void on_batch(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/, Received* received) {
  rockwatch::ground_accel_batch_t b;
  if (b.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
  for (std::int32_t k = 0; k < b.count; ++k) {
    rockwatch::ground_accel_t m{};
    m.seq = b.seq + k;
    m.utime = b.utime + k * b.sample_period_us;
    m.ug_mps2 = b.ug_mps2[k];
    m.vg_mps2 = b.vg_mps2[k];
    if (!received->samples.emplace(m.seq, m).second) ++received->duplicates;
  }
}

void check_every_sample_arrives(int batch) {
  const std::string url = rockwatch::cli::kDefaultLcmUrl;
  const rockwatch::cli::MulticastProbe probe = rockwatch::cli::probe_multicast(url, 1000);
  if (!probe.ok) {
    if (rockwatch::test::skip_or_fail_in_ci("LCM multicast does not work on this machine (" + probe.problem + ")"))
      return;
  }
  const TempDir dir;
  const std::string record = dir.file("sine.txt"), csv_path = dir.file("sent.csv");
  rockwatch::test::write_plain_record(
      record, [](double t) { return 1.5 * std::sin(2.0 * 3.14159265358979 * 3.0 * t); }, 0.005, 2.0);
  // A channel of this test only: other processes on this machine may use the default channels at the same time.
  const std::string channel =
      "RWTEST_REPLAY_" + std::to_string(static_cast<long>(getpid())) + "_" + std::to_string(batch);
  Received received;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  lcm::Subscription* subscription = batch > 0 ? lcm.subscribeFunction(channel, &on_batch, &received)
                                              : lcm.subscribeFunction(channel, &on_sample, &received);
  CHECK(subscription != nullptr);
  subscription->setQueueCapacity(100000);

  std::vector<std::string> args{"replay", "--record",      record,  "--rate",        "1000",   "--lcm-url",
                                url,      "--lcm-channel", channel, "--samples-out", csv_path, "--json"};
  if (batch > 0) args.insert(args.end(), {"--batch", std::to_string(batch)});
  const pid_t pid = rockwatch::test::spawn_rockwatch(args, dir.file("out"), dir.file("err"));
  int status = 0;
  bool ended = false;
  // Receive until the replay has ended and then half a second more: loopback delivers in microseconds.
  for (int quiet_ms = 0; !ended || quiet_ms < 500;) {
    const int rc = lcm.handleTimeout(50);
    if (ended && rc == 0) quiet_ms += 50;
    if (!ended) {
      if (const std::optional<int> st = rockwatch::process::poll_status(pid)) {
        status = *st;
        ended = true;
      }
    }
  }
  lcm.unsubscribe(subscription);
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, slurp(dir.file("err")).c_str());

  const SamplesCsv csv = read_samples(csv_path);
  CHECK_EQUAL(2001u, csv.ug.size());
  CHECK_EQUAL(csv.ug.size(), received.samples.size());
  CHECK_EQUAL(0u, received.duplicates);
  std::int64_t expected = 0;
  for (const auto& [seq, m] : received.samples) {
    CHECK_EQUAL(expected, seq);
    DOUBLES_EQUAL(csv.ug[static_cast<std::size_t>(seq)], m.ug_mps2, 0.0);
    DOUBLES_EQUAL(0.0, m.vg_mps2, 0.0);
    if (seq > 0) CHECK_EQUAL(received.samples.at(seq - 1).utime + 1000, m.utime);
    ++expected;
  }
}

// Whether process `pid` has a handler for SIGINT (bit SIGINT - 1 of SigCgt in /proc/PID/status).
bool catches_sigint(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("SigCgt:", 0) != 0) continue;
    const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
    return ((mask >> (SIGINT - 1)) & 1ULL) != 0;
  }
  return false;
}

}  // namespace

TEST(ReplayMulticast, EverySampleArrivesAtOneKilohertz) { check_every_sample_arrives(0); }

TEST(ReplayMulticast, EverySampleArrivesInBatches) { check_every_sample_arrives(10); }

TEST_GROUP(ReplayInterrupt){};

// Ctrl-C (SIGINT) during a real-time replay: it stops between messages, reports how far it got and exits with 130;
// --samples-out holds the samples handled.
TEST(ReplayInterrupt, SigintStopsAndReports) {
  const TempDir dir;
  const std::string csv_path = dir.file("sent.csv");
  const pid_t pid = rockwatch::test::spawn_rockwatch(
      concat({"replay"}, concat(suite_record("1", "X"), {"--lcm-url", "memq://", "--samples-out", csv_path, "--json"})),
      dir.file("out"), dir.file("err"));
  // The record lasts 20 s in real time. Signal once the replay catches SIGINT (its handler is installed when the
  // paced loop starts; a sanitized build can take longer than a fixed sleep to get there), then a little later.
  for (int k = 0; k < 2000 && !catches_sigint(pid); ++k) usleep(10000);
  usleep(300000);
  kill(pid, SIGINT);
  const int status = rockwatch::test::wait_status(pid);
  const std::string out = slurp(dir.file("out")), err = slurp(dir.file("err"));
  CHECK_TEXT(WIFEXITED(status), err.c_str());
  CHECK_EQUAL_TEXT(130, WEXITSTATUS(status), err.c_str());
  const nlohmann::json j = nlohmann::json::parse(out, nullptr, false);
  CHECK_TEXT(j.is_object(), out.c_str());
  CHECK(j["interrupted"].get<bool>());
  const auto done = j["samples_done"].get<std::size_t>();
  CHECK(done > 0 && done < j["samples"].get<std::size_t>());
  CHECK_EQUAL(done, j["samples_sent"].get<std::size_t>());
  CHECK_EQUAL(done, read_samples(csv_path).ug.size());
}

TEST_GROUP(ReplayPlant){};

namespace {

// A wall file as `rockwatch identify --wall-out` writes it (the fields every reader requires): 5 % thinner than the
// paper's wall, r = 0.85. On set 3 of the shipped suite at 0.25 g it survives component X and collapses under Y.
std::string write_wall_file(const TempDir& dir) {
  const std::string path = dir.file("wall.json");
  rockwatch::test::write_text(path,
                              "{\"format\": \"rockwatch-wall\", \"version\": 1, \"b_m\": 0.095, \"h1_m\": 1.75, "
                              "\"h2_m\": 1.75, \"rho_kgpm3\": 1800, \"fp_npm\": 0, \"a\": 0, \"a_prime\": 0, "
                              "\"g_mps2\": 9.81, \"r\": 0.85, \"comment\": \"replay plant test\"}");
  return path;
}

// One event of an LCM log, decoded, its times relative to the replay's start (start_utime of its --json), so the
// logs of two runs compare field by field.
struct DecodedEvent {
  std::string channel;
  std::int64_t timestamp_us = 0;  // the event's stamp - start
  std::int64_t utime_us = 0;      // the message's utime - start
  std::int64_t seq = 0;
  std::int32_t schema_version = 0, valid = 0, sensor_status = 0;
  double first = 0.0, second = 0.0;  // ug_mps2, vg_mps2 | x_mid_m, a_mid_mps2
};

std::vector<DecodedEvent> read_events(const std::string& path, std::int64_t start_utime) {
  std::vector<DecodedEvent> events;
  lcm::LogFile file(path, "r");
  CHECK_TEXT(file.good(), path.c_str());
  for (const lcm::LogEvent* e = file.readNextEvent(); e != nullptr; e = file.readNextEvent()) {
    DecodedEvent d;
    d.channel = e->channel;
    d.timestamp_us = e->timestamp - start_utime;
    if (e->channel == "ROCKWATCH_ACCEL") {
      rockwatch::ground_accel_t m;
      CHECK_EQUAL(e->datalen, m.decode(e->data, 0, e->datalen));
      d.utime_us = m.utime - start_utime;
      d.seq = m.seq;
      d.schema_version = m.schema_version;
      d.sensor_status = m.sensor_status;
      d.first = m.ug_mps2;
      d.second = m.vg_mps2;
    } else {
      STRCMP_EQUAL("ROCKWATCH_WALL_SENSOR", e->channel.c_str());
      rockwatch::wall_sensor_t m;
      CHECK_EQUAL(e->datalen, m.decode(e->data, 0, e->datalen));
      d.utime_us = m.utime - start_utime;
      d.seq = m.seq;
      d.schema_version = m.schema_version;
      d.valid = m.valid;
      d.sensor_status = m.sensor_status;
      d.first = m.x_mid_m;
      d.second = m.a_mid_mps2;
    }
    events.push_back(d);
  }
  return events;
}

std::string event_text(const DecodedEvent& e) {
  char text[256];
  std::snprintf(text, sizeof text, "%s t %lld utime %lld seq %lld schema %d valid %d status %d values %.17g %.17g",
                e.channel.c_str(), static_cast<long long>(e.timestamp_us), static_cast<long long>(e.utime_us),
                static_cast<long long>(e.seq), e.schema_version, e.valid, e.sensor_status, e.first, e.second);
  return text;
}

// Empty when the two logs hold the same messages in the same order, field by field (values bit for bit); else the
// first difference.
std::string first_difference(const std::vector<DecodedEvent>& a, const std::vector<DecodedEvent>& b) {
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const DecodedEvent& x = a[i];
    const DecodedEvent& y = b[i];
    const bool same = x.channel == y.channel && x.timestamp_us == y.timestamp_us && x.utime_us == y.utime_us &&
                      x.seq == y.seq && x.schema_version == y.schema_version && x.valid == y.valid &&
                      x.sensor_status == y.sensor_status && std::memcmp(&x.first, &y.first, sizeof x.first) == 0 &&
                      std::memcmp(&x.second, &y.second, sizeof x.second) == 0;
    if (!same) return "event " + std::to_string(i) + ":\n  " + event_text(x) + "\n  " + event_text(y);
  }
  if (a.size() != b.size()) return std::to_string(a.size()) + " events against " + std::to_string(b.size());
  return {};
}

// The record both routes run: resampled to 1 kHz with a noisy, biased ground sensor that drops samples (the replay's
// model of the ground accelerometer, which the plant must not see), a vertical, and a plant that survives it.
std::vector<std::string> plant_record() {
  return concat(suite_record("3", "X"), {"--vertical-from-suite", "--scale-pga", "0.25"});
}
const std::vector<std::string> kGroundSensor{"--rate",      "1000", "--noise-mps2", "0.05", "--bias-mps2",
                                             "0.02",        "--seed", "5",          "--dropout", "0.01"};
// The wall's sensors: noise, offset, quantum, their own rate, a gap and the accelerometer column.
std::vector<std::string> plant_sensors(const char* seed) {
  return {"--sensor-noise-m",  "0.001", "--sensor-bias-m",           "0.002", "--sensor-quantum-m", "0.0001",
          "--sensor-rate-hz",  "250",   "--sensor-dropout",          "2:2.5", "--sensor-accel-noise-mps2", "0.05",
          "--sensor-seed",     seed};
}

std::vector<DecodedEvent> replay_events(const std::vector<std::string>& args, const std::string& log_path) {
  const nlohmann::json j = run_json(concat(args, {"--log", log_path}));
  return read_events(log_path, j["start_utime"].get<std::int64_t>());
}

}  // namespace

// The wall as a plant sends what the two-step route sends: `simulate --wall-file --sensors-out` then
// `replay --wall-sensors`, message for message. A different --sensor-seed on one route must show (the comparison
// can fail).
TEST(ReplayPlant, SendsWhatSimulateSensorsOutThenReplayWallSensorsSends) {
  const TempDir dir;
  const std::string wall = write_wall_file(dir);
  const auto two_step = [&](const char* seed) {
    const std::string sensors = dir.file(std::string("sensors_") + seed + ".csv");
    const ProcessResult sim = run_rockwatch(
        concat(concat({"simulate", "--wall-file", wall}, plant_record()), concat({"--sensors-out", sensors},
                                                                                 plant_sensors(seed))));
    CHECK_EQUAL_TEXT(0, sim.exit_status, describe(sim).c_str());
    return replay_events(concat(concat(plant_record(), kGroundSensor), {"--wall-sensors", sensors}),
                         dir.file(std::string("two_step_") + seed + ".lcmlog"));
  };
  const std::vector<DecodedEvent> plant = replay_events(
      concat(concat(plant_record(), kGroundSensor), concat({"--wall-file", wall}, plant_sensors("11"))),
      dir.file("plant.lcmlog"));
  const std::vector<DecodedEvent> route = two_step("11");

  const std::string difference = first_difference(route, plant);
  CHECK_TEXT(difference.empty(), difference.c_str());
  // The log holds what the comparison is about: both kinds of message, the accelerometer column, the sensors' gap.
  std::size_t ground = 0, wall_sensors = 0, with_accel = 0, in_gap = 0;
  for (const DecodedEvent& e : plant) {
    if (e.channel == "ROCKWATCH_ACCEL") {
      ++ground;
      continue;
    }
    ++wall_sensors;
    if (e.valid == (rockwatch::wall_sensor_t::VALID_X | rockwatch::wall_sensor_t::VALID_A)) ++with_accel;
    if (e.utime_us >= 2000000 && e.utime_us < 2500000) ++in_gap;
  }
  CHECK(ground > 19000 && ground < 20001);  // 20 s at 1 kHz, about 1 % dropped
  // 20 s at 250 Hz minus the 0.5 s gap (none after the last ground message sent, which may be a little early).
  CHECK(wall_sensors <= 5001u - 125u && wall_sensors > 5001u - 125u - 10u);
  CHECK_EQUAL(wall_sensors, with_accel);
  CHECK_EQUAL(0u, in_gap);

  const std::string other = first_difference(two_step("12"), plant);
  CHECK_TEXT(!other.empty(), "another --sensor-seed gave the same messages: the comparison cannot fail");
}

// The plant's verdict in --json is the engine's: that of `simulate --wall-file --json` on the same record, for a wall
// that collapses (with the vertical, which delays it) and one that survives.
TEST(ReplayPlant, VerdictIsSimulates) {
  const TempDir dir;
  const std::string wall = write_wall_file(dir);
  const std::vector<std::vector<std::string>> records{
      concat(suite_record("3", "Y"), {"--vertical-from-suite", "--scale-pga", "0.25"}),
      concat(suite_record("3", "X"), {"--scale-pga", "0.25"})};
  bool collapsed_seen = false, survived_seen = false;
  for (const std::vector<std::string>& record : records) {
    const ProcessResult sim = run_rockwatch(concat(concat({"simulate", "--wall-file", wall}, record), {"--json"}));
    CHECK_EQUAL_TEXT(0, sim.exit_status, describe(sim).c_str());
    const nlohmann::json expected = nlohmann::json::parse(sim.out);
    const nlohmann::json j = run_json(concat(
        record, {"--wall-file", wall, "--wall-sensor-channel", "RIG_WALL", "--log", dir.file("plant.lcmlog")}));
    const nlohmann::json& plant = j.at("plant");
    const std::string what = plant.dump(1) + "\nsimulate:\n" + sim.out.substr(0, 2000);
    STRCMP_EQUAL_TEXT(wall.c_str(), plant.at("wall_file").get<std::string>().c_str(), what.c_str());
    STRCMP_EQUAL_TEXT("RIG_WALL", plant.at("channel").get<std::string>().c_str(), what.c_str());
    for (const char* key : {"collapsed", "collapse_after_end", "t_collapse_s", "t_exceed_s", "max_abs_x_m",
                            "t_max_abs_x_s", "x_inst_m", "r", "n_impacts", "kappa", "model"}) {
      CHECK_TEXT(expected.at(key) == plant.at(key), (std::string(key) + "\n" + what).c_str());
    }
    // The samples up to the collapse are all sent; a surviving wall may rock on after the record, unsent.
    const auto made = plant.at("sensor_samples").get<std::size_t>();
    const auto sent = plant.at("sensor_samples_sent").get<std::size_t>();
    CHECK_TEXT(expected.at("collapsed").get<bool>() ? sent == made : sent > 3000 && sent <= made, what.c_str());
    (expected.at("collapsed").get<bool>() ? collapsed_seen : survived_seen) = true;
  }
  CHECK(collapsed_seen);
  CHECK(survived_seen);
}

TEST(ReplayPlant, WrongCombinationsAndWallFilesAreRefused) {
  const TempDir dir;
  const std::string wall = write_wall_file(dir), log = dir.file("x.lcmlog");
  const std::vector<std::string> rec = concat(suite_record("1", "X"), {"--log", log});
  const std::string sensors = dir.file("sensors.csv");
  std::ofstream(sensors) << "t_s,x_mid_m\n0,0.001\n";
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--wall-sensors", sensors}),
                          {"--wall-file", "--wall-sensors"});
  for (const char* option : {"--sensor-noise-m", "--sensor-bias-m", "--sensor-quantum-m", "--sensor-rate-hz",
                             "--sensor-accel-noise-mps2", "--sensor-seed"}) {
    expect_command_rejected("replay", concat(rec, {option, "1"}), {option, "--wall-file"});
  }
  expect_command_rejected("replay", concat(rec, {"--sensor-dropout", "1:2"}), {"--sensor-dropout", "--wall-file"});
  for (const char* option : {"--b", "--r", "--kappa", "--max-step", "--g"}) {
    expect_command_rejected("replay", concat(rec, {option, "0.2"}), {option, "--wall-file"});
  }
  expect_command_rejected("replay", concat(rec, {"--wall", "paper"}), {"--wall", "--wall-file"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--wall-sensor-channel", "ROCKWATCH_ACCEL"}),
                          {"--wall-sensor-channel", "ground channel"});
  // The plant's options are checked as simulate checks them.
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--sensor-noise-m", "2"}),
                          {"--sensor-noise-m", "[0, 1]"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--sensor-dropout", "3:1"}),
                          {"--sensor-dropout", "T0 < T1"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--kappa", "0.5"}), {"--kappa"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", wall, "--max-step", "1e-9"}), {"--max-step"});
  // A bad wall file: the file and the field.
  const std::string good = slurp(wall);
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    const std::string path = dir.file("bad.json");
    rockwatch::test::write_text(path, text);
    return path;
  };
  expect_command_rejected("replay", concat(rec, {"--wall-file", with("\"h1_m\": 1.75, ", "")}),
                          {"--wall-file", "bad.json", "'h1_m'", "missing"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", with("\"r\": 0.85", "\"r\": 1.5")}),
                          {"bad.json", "'r'", "[0, 1]"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", with("\"r\": 0.85", "\"r\": 0.85, \"thick\": 1")}),
                          {"bad.json", "unknown field", "'thick'"});
  expect_command_rejected("replay", concat(rec, {"--wall-file", dir.file("missing.json")}), {"missing.json"});
  // Refused before anything is written.
  CHECK_FALSE(std::ifstream(log).good());
}
