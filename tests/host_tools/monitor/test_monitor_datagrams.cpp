// rockwatch-monitor live against datagrams an outsider on the lab network can send to its multicast group: the two
// that crash liblcm 1.3.1's reassembly, and the fragment and channel-name cases around them, sent with a plain UDP
// socket. The monitor must go on answering (statuses, samples processed after the attack, a clean SIGTERM), flag
// QUALITY_BAD_DATAGRAM and count each datagram by reason in its summary. A message that liblcm itself fragments
// (over 1400 bytes) reassembles through the monitor's own path.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "lcm_transport.hpp"
#include "monitor_live_support.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/monitor_status_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_datagrams {

using nlohmann::json;
using rockwatch::test::now_s;
using rockwatch::test::TempDir;
using Bytes = std::vector<std::uint8_t>;

namespace {

struct Channels : rockwatch::test::LiveChannels {
  Channels() : LiveChannels("RWD") {}
};

constexpr const char* kGroup = "239.255.76.67";
int test_port() { return rockwatch::test::live_test_port(1); }
std::string test_url() { return rockwatch::test::live_test_url(1); }

void put32(Bytes& b, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<std::uint8_t>(v >> s));
}
void put16(Bytes& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}
Bytes lc03(std::uint32_t seq, std::uint32_t size, std::uint32_t offset, std::uint16_t number, std::uint16_t count) {
  Bytes b;
  put32(b, 0x4c433033u);
  put32(b, seq);
  put32(b, size);
  put32(b, offset);
  put16(b, number);
  put16(b, count);
  return b;
}
Bytes lc02(std::uint32_t seq) {
  Bytes b;
  put32(b, 0x4c433032u);
  put32(b, seq);
  return b;
}
void append(Bytes& b, const std::string& s, bool nul = true) {
  b.insert(b.end(), s.begin(), s.end());
  if (nul) b.push_back(0);
}

// A plain UDP sender to the group (ttl 0: the datagrams stay on this machine).
class RawSender {
 public:
  RawSender() {
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    const unsigned char ttl = 0;
    setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
    to_.sin_family = AF_INET;
    to_.sin_port = htons(static_cast<std::uint16_t>(test_port()));
    inet_pton(AF_INET, kGroup, &to_.sin_addr);
  }
  ~RawSender() { close(fd_); }
  void send(const Bytes& b) {
    CHECK(sendto(fd_, b.data(), b.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_) ==
          static_cast<ssize_t>(b.size()));
    usleep(2000);  // keep the order on loopback and let the monitor drain
  }

 private:
  int fd_ = -1;
  sockaddr_in to_{};
};

Bytes sample_payload(std::int64_t utime, std::int64_t seq) {
  rockwatch::ground_accel_t m{};
  m.utime = utime;
  m.seq = seq;
  m.schema_version = 1;
  m.ug_mps2 = 0.01;
  Bytes b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

void on_status(const lcm::ReceiveBuffer* rbuf, const std::string&, std::vector<rockwatch::monitor_status_t>* out) {
  rockwatch::monitor_status_t m;
  if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) out->push_back(m);
}

// Handles LCM until a received status carries QUALITY_BAD_DATAGRAM (true) or 5 s pass (false).
bool wait_for_bad_datagram_flag(lcm::LCM& lcm, const std::vector<rockwatch::monitor_status_t>& statuses) {
  const double deadline = now_s() + 5.0;
  while (now_s() < deadline) {
    lcm.handleTimeout(50);
    for (const auto& s : statuses) {
      if ((s.data_quality & rockwatch::monitor_status_t::QUALITY_BAD_DATAGRAM) != 0) return true;
    }
  }
  return false;
}

}  // namespace

TEST_GROUP(MonitorDatagrams){};

TEST(MonitorDatagrams, CraftedDatagramsAreCountedAndTheMonitorGoesOn) {
  const std::string url = test_url();
  if (rockwatch::test::skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  std::vector<rockwatch::monitor_status_t> statuses;
  lcm.subscribeFunction(c.status, &on_status, &statuses);
  const pid_t pid = rockwatch::test::start_monitor_listening(
      {"--config", rockwatch::test::write_channels_config(dir, c, "datagrams.json"), "--lcm-url", url},
      dir.file("stdout"), dir.file("stderr"));

  RawSender raw;
  const std::string& accel = c.accel;
  // 1. The liblcm crash pair: fragment 0 of a 48-byte message, then fragment 1 whose end wraps 2^32.
  Bytes first = lc03(1, 48, 0, 0, 2);
  append(first, accel);
  first.resize(first.size() + 20, 0);
  raw.send(first);
  Bytes second = lc03(1, 48, 0xfffffff0u, 1, 2);
  second.resize(second.size() + 16, 0);
  raw.send(second);
  // 2. Fragment 0 whose channel name runs past the end of the datagram (liblcm's length underflow).
  Bytes unterminated = lc03(2, 48, 0, 0, 2);
  append(unterminated, accel, false);
  raw.send(unterminated);
  // 3. A short message whose channel name runs past the end, one with a name over 63 bytes, one with an empty name.
  Bytes short_unterminated = lc02(3);
  append(short_unterminated, accel, false);
  raw.send(short_unterminated);
  Bytes too_long = lc02(4);
  append(too_long, std::string(64, 'A'));
  raw.send(too_long);
  Bytes empty_name = lc02(5);
  append(empty_name, "");
  raw.send(empty_name);
  // 4. Truncated headers, a bad magic, fragment counts out of range, a message too large.
  raw.send(Bytes{0x4c, 0x43, 0x30});
  raw.send(lc03(6, 48, 0, 0, 2));                                     // 20 bytes: header only, no channel
  raw.send(Bytes(16, 0x4c));
  raw.send(lc03(7, 48, 0, 0, 0));                                     // n_fragments 0
  raw.send(lc03(8, 48, 0, 3, 2));                                     // fragment 3 of 2
  raw.send(lc03(9, 1u << 30, 0, 1, 2));                               // payload of 1 GiB: skipped, not an error
  const int bad = 10;  // from the crash pair's second datagram through 4
  // 5. A valid ground_accel_t in two fragments (as a publisher that fragments would send it), then a duplicate.
  const std::int64_t t0 = rockwatch::monitor::realtime_utime();
  const Bytes payload = sample_payload(t0, 100);
  Bytes part0 = lc03(10, static_cast<std::uint32_t>(payload.size()), 0, 0, 2);
  append(part0, accel);
  part0.insert(part0.end(), payload.begin(), payload.begin() + 20);
  Bytes part1 = lc03(10, static_cast<std::uint32_t>(payload.size()), 20, 1, 2);
  part1.insert(part1.end(), payload.begin() + 20, payload.end());
  raw.send(part0);
  raw.send(part0);  // duplicate
  raw.send(part1);
  // 6. Then ordinary samples through liblcm: the monitor processes them.
  for (int i = 1; i <= 20; ++i) {
    const Bytes b = sample_payload(t0 + i * 5000, 100 + i);
    CHECK(lcm.publish(accel, b.data(), static_cast<unsigned int>(b.size())) == 0);
  }
  // 7. Another program's traffic on the group: a message liblcm sends in one datagram (3000 bytes) and one it
  //    fragments (over 64 KiB, in 2 fragments): neither is an error.
  const Bytes big(3000, 0x5a);
  CHECK(lcm.publish(c.accel + "_BIG", big.data(), static_cast<unsigned int>(big.size())) == 0);
  const Bytes huge(70000, 0x5b);
  CHECK(lcm.publish(c.accel + "_HUGE", huge.data(), static_cast<unsigned int>(huge.size())) == 0);

  // Still answering: a status after the attack carries the flag.
  CHECK_TEXT(wait_for_bad_datagram_flag(lcm, statuses), "no status with QUALITY_BAD_DATAGRAM within 5 s");
  // The status counts them too (it may trail the last datagrams by one status period).
  CHECK_TRUE(statuses.back().datagrams_rejected >= 1);

  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  const std::string err = rockwatch::test::read_file(dir.file("stderr"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(dir.file("stdout")));
  CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), err.c_str());
  const json& s = lines.back().at("summary");
  const json& d = s.at("datagrams");
  LONGS_EQUAL(bad + 1, d.at("rejected").get<long>());  // + the duplicate fragment
  const json& why = d.at("rejected_by_reason");
  LONGS_EQUAL(1, why.at("fragment_bounds").get<long>());
  LONGS_EQUAL(3, why.at("channel_unterminated").get<long>());  // 2, 3 (short), and the header-only fragment
  LONGS_EQUAL(2, why.at("channel_length").get<long>());
  LONGS_EQUAL(1, why.at("truncated_header").get<long>());
  LONGS_EQUAL(1, why.at("bad_magic").get<long>());
  LONGS_EQUAL(2, why.at("fragment_count").get<long>());
  LONGS_EQUAL(0, why.at("(retired)").get<long>());
  LONGS_EQUAL(1 + 2, d.at("skipped_too_large").get<long>());  // the 1 GiB fragment, liblcm's two fragments
  LONGS_EQUAL(1, why.at("fragment_duplicate").get<long>());
  LONGS_EQUAL_TEXT(1, d.at("messages_reassembled").get<long>(), d.dump().c_str());  // the sample in two parts
  // The reassembled sample and the 20 published ones, in order: 21 processed, no fault.
  const json& counters = s.at("counters");
  LONGS_EQUAL(21, counters.at("samples_received").get<long>());
  LONGS_EQUAL(21, counters.at("samples_processed").get<long>());
  LONGS_EQUAL(0, counters.at("decode_errors").get<long>());
  LONGS_EQUAL(0, counters.at("duplicates").get<long>());
}

// --accept-from: datagrams from any other source are dropped before they are parsed, counted, and flagged.
TEST(MonitorDatagrams, SourcesNotAcceptedAreDroppedAndCounted) {
  const std::string url = test_url();
  if (rockwatch::test::skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  std::vector<rockwatch::monitor_status_t> statuses;
  lcm.subscribeFunction(c.status, &on_status, &statuses);
  // No datagram comes from 0.0.0.1 (this machine's own come from one of its interface addresses, which on some
  // machines are in the documentation networks: 192.0.2.2 here).
  const pid_t pid = rockwatch::test::start_monitor_listening(
      {"--config", rockwatch::test::write_channels_config(dir, c, "accept.json"), "--lcm-url", url, "--accept-from",
       "0.0.0.1"},
      dir.file("stdout"), dir.file("stderr"));
  const std::int64_t t0 = rockwatch::monitor::realtime_utime();
  for (int i = 0; i < 5; ++i) {
    const Bytes b = sample_payload(t0 + i * 5000, i);
    CHECK(lcm.publish(c.accel, b.data(), static_cast<unsigned int>(b.size())) == 0);
  }
  CHECK_TEXT(wait_for_bad_datagram_flag(lcm, statuses), "no status with QUALITY_BAD_DATAGRAM within 5 s");
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  const std::string err = rockwatch::test::read_file(dir.file("stderr"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(dir.file("stdout")));
  const json& s = lines.back().at("summary");
  CHECK_TEXT(s.at("datagrams").at("from_other_sources").get<long>() >= 5, s.dump().c_str());
  LONGS_EQUAL(0, s.at("datagrams").at("short_messages").get<long>());
  LONGS_EQUAL(0, s.at("counters").at("samples_received").get<long>());
}

}  // namespace unity_test_monitor_datagrams
