// `rockwatch replay` end to end: every invalid option refused with a message naming it; --log writes a standard LCM
// log that lcm::LogFile reads back (events, channels, seq 0..n-1, utime on the sample grid, values equal to
// --samples-out); --batch packs consecutive samples; --dropout leaves seq gaps that --samples-out marks; --speed 0
// is not paced; the --samples-out file is a plain record that `rockwatch simulate --arith fixed` reads sample for
// sample; and over real UDP multicast on this machine (ttl=0) a receiver in this process gets every sample at 1 kHz
// (skipped, with a note, when multicast does not work here: the probe of `rockwatch demo`).
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/replay_out/lcm_multicast.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"

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
  expect_command_rejected("replay", concat(rec, {"--b", "0.2"}), {"unknown option", "--b"});
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
    std::printf("\nnote: LCM multicast does not work on this machine (%s): ReplayMulticast skipped\n",
                probe.problem.c_str());
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
