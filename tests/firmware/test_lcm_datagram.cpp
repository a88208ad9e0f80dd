// firmware::LcmDatagramReassembler: LCM's UDP formats (LC02 short, LC03 fragments) built byte by byte as the
// protocol description says, then every way a datagram can lie about its lengths — the two datagrams that crash
// liblcm 1.3.1 among them — each rejected with its reason and counted, without disturbing other messages.
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "rockwatch/firmware/lcm_datagram.hpp"
#include "rockwatch/ground_accel_t.hpp"

#include <CppUTest/TestHarness.h>

namespace fw = rockwatch::firmware;
using Bytes = std::vector<std::uint8_t>;
using R = fw::LcmDatagramReassembler;

namespace {

void put32(Bytes& b, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<std::uint8_t>(v >> s));
}
void put16(Bytes& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}
void put_text(Bytes& b, const std::string& s, bool nul = true) {
  b.insert(b.end(), s.begin(), s.end());
  if (nul) b.push_back(0);
}

Bytes short_datagram(std::uint32_t seq, const std::string& channel, const Bytes& payload) {
  Bytes b;
  put32(b, R::kMagicShort);
  put32(b, seq);
  put_text(b, channel);
  b.insert(b.end(), payload.begin(), payload.end());
  return b;
}

Bytes fragment(std::uint32_t seq, std::uint32_t payload_size, std::uint32_t offset, std::uint16_t number,
               std::uint16_t count, const std::string* channel, const Bytes& data) {
  Bytes b;
  put32(b, R::kMagicFragment);
  put32(b, seq);
  put32(b, payload_size);
  put32(b, offset);
  put16(b, number);
  put16(b, count);
  if (channel != nullptr) put_text(b, *channel);
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

// Splits `payload` into `count` fragments the way an LCM publisher does (channel in fragment 0).
std::vector<Bytes> fragments_of(std::uint32_t seq, const std::string& channel, const Bytes& payload, int count) {
  std::vector<Bytes> out;
  const std::size_t chunk = (payload.size() + static_cast<std::size_t>(count) - 1) / static_cast<std::size_t>(count);
  for (int k = 0; k < count; ++k) {
    const std::size_t begin = std::min(payload.size(), chunk * static_cast<std::size_t>(k));
    const std::size_t end = std::min(payload.size(), begin + chunk);
    out.push_back(fragment(seq, static_cast<std::uint32_t>(payload.size()), static_cast<std::uint32_t>(begin),
                           static_cast<std::uint16_t>(k), static_cast<std::uint16_t>(count),
                           k == 0 ? &channel : nullptr, Bytes(payload.begin() + static_cast<long>(begin),
                                                              payload.begin() + static_cast<long>(end))));
  }
  return out;
}

Bytes pattern(std::size_t n) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>((i * 37u + 11u) & 0xffu);
  return b;
}

constexpr fw::DatagramSource kA{0x7f000001u, 40000};
constexpr fw::DatagramSource kB{0x7f000001u, 40001};

struct Fed {
  fw::DatagramOutcome outcome;
  std::uint32_t reasons;
  fw::LcmMessageView view;
};

Fed feed(R& r, const Bytes& d, fw::DatagramSource src = kA, std::int64_t now_us = 0) {
  Fed f{fw::DatagramOutcome::rejected, 0, {}};
  f.outcome = r.accept(d.data(), d.size(), src, now_us, &f.view, &f.reasons);
  return f;
}

void check_rejected(const Fed& f, std::uint32_t reason) {
  CHECK(f.outcome == fw::DatagramOutcome::rejected);
  UNSIGNED_LONGS_EQUAL(reason, f.reasons);
}

}  // namespace

TEST_GROUP(LcmDatagram){};

TEST(LcmDatagram, ShortMessageCarriesAnEncodedSample) {
  rockwatch::ground_accel_t m{};
  m.utime = 1700000000000000;
  m.seq = 42;
  m.schema_version = 1;
  m.ug_mps2 = -1.25;
  Bytes payload(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(payload.data(), 0, static_cast<int>(payload.size()));
  R r;
  const Bytes datagram = short_datagram(7, "ROCKWATCH_ACCEL", payload);  // the view points into it
  const Fed f = feed(r, datagram);
  CHECK(f.outcome == fw::DatagramOutcome::message);
  STRCMP_EQUAL("ROCKWATCH_ACCEL", f.view.channel);
  UNSIGNED_LONGS_EQUAL(7, f.view.sequence_number);
  UNSIGNED_LONGS_EQUAL(kA.port, f.view.source.port);
  rockwatch::ground_accel_t back{};
  LONGS_EQUAL(static_cast<long>(payload.size()), back.decode(f.view.payload, 0, static_cast<int>(f.view.size)));
  LONGS_EQUAL(42, back.seq);
  CHECK(back.ug_mps2 == -1.25);
  LONGS_EQUAL(1, r.counters().short_messages);
  LONGS_EQUAL(0, r.counters().rejected);
}

TEST(LcmDatagram, EmptyPayloadIsAMessage) {
  R r;
  const Fed f = feed(r, short_datagram(1, "X", {}));
  CHECK(f.outcome == fw::DatagramOutcome::message);
  UNSIGNED_LONGS_EQUAL(0, f.view.size);
}

// The two datagrams of the liblcm crash: fragment 0 of a 48-byte message, then fragment 1 at offset 0xfffffff0,
// whose end wraps around 2^32 in liblcm's 32-bit bound check.
TEST(LcmDatagram, TheLiblcmCrashPairIsStoredThenRejected) {
  R r;
  const std::string channel = "ROCKWATCH_ACCEL";
  const Fed first = feed(r, fragment(1, 48, 0, 0, 2, &channel, Bytes(20, 0)));
  CHECK(first.outcome == fw::DatagramOutcome::fragment_stored);
  const Fed second = feed(r, fragment(1, 48, 0xfffffff0u, 1, 2, nullptr, Bytes(16, 0)));
  check_rejected(second, fw::kRejectFragmentBounds);
  LONGS_EQUAL(1, r.counters().rejected_by_reason[6]);
  // The message in flight is still waiting for a valid fragment 1, which completes it.
  UNSIGNED_LONGS_EQUAL(1, r.in_flight());
  const Fed third = feed(r, fragment(1, 48, 20, 1, 2, nullptr, Bytes(28, 5)));
  CHECK(third.outcome == fw::DatagramOutcome::message);
  UNSIGNED_LONGS_EQUAL(48, third.view.size);
  STRCMP_EQUAL("ROCKWATCH_ACCEL", third.view.channel);
}

// Fragment 0 whose channel name has no NUL before the end of the datagram (liblcm's length underflow).
TEST(LcmDatagram, ChannelRunningPastTheDatagramIsRejected) {
  R r;
  Bytes d = fragment(1, 48, 0, 0, 2, nullptr, {});
  put_text(d, "ROCKWATCH_ACCEL", false);
  check_rejected(feed(r, d), fw::kRejectChannelUnterminated);
  Bytes s;
  put32(s, R::kMagicShort);
  put32(s, 3);
  put_text(s, "ROCKWATCH", false);
  check_rejected(feed(r, s), fw::kRejectChannelUnterminated);
  // Header only: the channel has zero bytes to live in.
  check_rejected(feed(r, fragment(1, 48, 0, 0, 2, nullptr, {})), fw::kRejectChannelUnterminated);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
}

TEST(LcmDatagram, ChannelLengthLimits) {
  R r;
  const std::string longest(R::kMaxChannelLength, 'C');
  CHECK(feed(r, short_datagram(1, longest, {1, 2})).outcome == fw::DatagramOutcome::message);
  check_rejected(feed(r, short_datagram(2, longest + "C", {1, 2})), fw::kRejectChannelLength);
  check_rejected(feed(r, short_datagram(3, "", {1, 2})), fw::kRejectChannelLength);
  const std::string too_long = longest + "C";
  check_rejected(feed(r, fragment(4, 8, 0, 0, 1, &too_long, Bytes(8, 0))), fw::kRejectChannelLength);
}

TEST(LcmDatagram, TruncatedHeadersAndBadMagic) {
  R r;
  const Bytes s = short_datagram(1, "ROCKWATCH_ACCEL", {1});
  for (std::size_t n = 0; n < R::kShortHeaderBytes; ++n) {
    check_rejected(feed(r, Bytes(s.begin(), s.begin() + static_cast<long>(n))), fw::kRejectTruncatedHeader);
  }
  const std::string channel = "C";
  const Bytes f = fragment(1, 4, 0, 0, 1, &channel, Bytes(4, 0));
  for (std::size_t n = 4; n < R::kFragmentHeaderBytes; ++n) {
    check_rejected(feed(r, Bytes(f.begin(), f.begin() + static_cast<long>(n))), fw::kRejectTruncatedHeader);
  }
  Bytes bad = s;
  bad[3] = '4';  // "LC04"
  check_rejected(feed(r, bad), fw::kRejectBadMagic);
  LONGS_EQUAL(static_cast<long>(R::kShortHeaderBytes + R::kFragmentHeaderBytes - 4 + 1), r.counters().rejected);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
}

TEST(LcmDatagram, FragmentsInAnyOrderReassembleExactly) {
  const Bytes payload = pattern(3000);
  const std::vector<Bytes> parts = fragments_of(9, "BIG", payload, 3);
  const int orders[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
  for (const auto& order : orders) {
    R r;
    Fed last{};
    for (int i = 0; i < 3; ++i) last = feed(r, parts[static_cast<std::size_t>(order[i])]);
    CHECK(last.outcome == fw::DatagramOutcome::message);
    STRCMP_EQUAL("BIG", last.view.channel);
    UNSIGNED_LONGS_EQUAL(payload.size(), last.view.size);
    CHECK(std::memcmp(payload.data(), last.view.payload, payload.size()) == 0);
    LONGS_EQUAL(1, r.counters().messages_reassembled);
    UNSIGNED_LONGS_EQUAL(0, r.in_flight());
  }
}

TEST(LcmDatagram, DuplicateFragmentIsRejectedAndTheMessageStillCompletes) {
  R r;
  const Bytes payload = pattern(2000);
  const std::vector<Bytes> parts = fragments_of(3, "BIG", payload, 2);
  CHECK(feed(r, parts[0]).outcome == fw::DatagramOutcome::fragment_stored);
  check_rejected(feed(r, parts[0]), fw::kRejectFragmentDuplicate);
  const Fed done = feed(r, parts[1]);
  CHECK(done.outcome == fw::DatagramOutcome::message);
  CHECK(std::memcmp(payload.data(), done.view.payload, payload.size()) == 0);
}

TEST(LcmDatagram, FragmentDisagreeingWithTheMessageInFlightDropsIt) {
  R r;
  const std::string channel = "C";
  CHECK(feed(r, fragment(5, 100, 0, 0, 2, &channel, Bytes(50, 1))).outcome == fw::DatagramOutcome::fragment_stored);
  check_rejected(feed(r, fragment(5, 120, 50, 1, 2, nullptr, Bytes(50, 1))), fw::kRejectFragmentMismatch);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
  CHECK(feed(r, fragment(6, 100, 0, 0, 2, &channel, Bytes(50, 1))).outcome == fw::DatagramOutcome::fragment_stored);
  check_rejected(feed(r, fragment(6, 100, 50, 1, 3, nullptr, Bytes(50, 1))), fw::kRejectFragmentMismatch);
}

// Overlapping fragments that cover fewer bytes than payload_size: complete by count, wrong by length.
TEST(LcmDatagram, FragmentsThatDoNotCoverThePayloadAreRejected) {
  R r;
  const std::string channel = "C";
  CHECK(feed(r, fragment(5, 100, 0, 0, 2, &channel, Bytes(50, 1))).outcome == fw::DatagramOutcome::fragment_stored);
  check_rejected(feed(r, fragment(5, 100, 10, 1, 2, nullptr, Bytes(40, 1))), fw::kRejectFragmentMismatch);
  LONGS_EQUAL(0, r.counters().messages_reassembled);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
}

TEST(LcmDatagram, FragmentCountsAndBounds) {
  R r;
  const std::string channel = "C";
  check_rejected(feed(r, fragment(1, 10, 0, 0, 0, &channel, Bytes(10, 0))), fw::kRejectFragmentCount);
  check_rejected(feed(r, fragment(1, 10, 0, 2, 2, nullptr, Bytes(10, 0))), fw::kRejectFragmentCount);
  check_rejected(feed(r, fragment(1, 10, 0, 0, static_cast<std::uint16_t>(R::kMaxFragments + 1), &channel, {})),
                 fw::kRejectFragmentCount);
  check_rejected(feed(r, fragment(1, 10, 4, 0, 2, &channel, Bytes(2, 0))), fw::kRejectFragmentBounds);
  check_rejected(feed(r, fragment(1, 10, 5, 1, 2, nullptr, Bytes(6, 0))), fw::kRejectFragmentBounds);
  check_rejected(feed(r, fragment(1, 10, 0xffffffffu, 1, 2, nullptr, Bytes(1, 0))), fw::kRejectFragmentBounds);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
  LONGS_EQUAL(6, r.counters().rejected);
}

// Another program's large messages on the same group: passed through in one datagram, skipped when fragmented.
TEST(LcmDatagram, LargeMessagesAreNotErrors) {
  R r;
  const Bytes big_short = short_datagram(1, "CAMERA", Bytes(60000, 7));
  const Fed f = feed(r, big_short);
  CHECK(f.outcome == fw::DatagramOutcome::message);
  UNSIGNED_LONGS_EQUAL(60000, f.view.size);
  const std::vector<Bytes> parts = fragments_of(2, "CAMERA", Bytes(R::kMaxMessageBytes + 1, 7), 2);
  CHECK(feed(r, parts[0]).outcome == fw::DatagramOutcome::skipped);
  CHECK(feed(r, parts[1]).outcome == fw::DatagramOutcome::skipped);
  LONGS_EQUAL(2, r.counters().skipped_too_large);
  LONGS_EQUAL(0, r.counters().rejected);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
}

TEST(LcmDatagram, InFlightIsBoundedPerSenderAndInAll) {
  R r;
  const std::string channel = "C";
  // A sender's next message abandons its previous one.
  CHECK(feed(r, fragment(1, 100, 0, 0, 2, &channel, Bytes(50, 0)), kA).outcome == fw::DatagramOutcome::fragment_stored);
  CHECK(feed(r, fragment(2, 100, 0, 0, 2, &channel, Bytes(50, 0)), kA).outcome == fw::DatagramOutcome::fragment_stored);
  LONGS_EQUAL(1, r.counters().abandoned);
  UNSIGNED_LONGS_EQUAL(1, r.in_flight());
  // More senders than slots: the slot unused for longest is taken.
  for (std::uint16_t p = 1; p <= R::kSlots; ++p) {
    const fw::DatagramSource s{0x0a000001u, p};
    CHECK(feed(r, fragment(1, 100, 0, 0, 2, &channel, Bytes(50, 0)), s, p).outcome ==
          fw::DatagramOutcome::fragment_stored);
  }
  UNSIGNED_LONGS_EQUAL(R::kSlots, r.in_flight());
  LONGS_EQUAL(1, r.counters().evicted);
  // kA's message was the one evicted: its second fragment starts a new, incomplete message.
  CHECK(feed(r, fragment(2, 100, 50, 1, 2, nullptr, Bytes(50, 0)), kA, 10).outcome ==
        fw::DatagramOutcome::fragment_stored);
  // A short message from anyone passes whatever is in flight.
  CHECK(feed(r, short_datagram(1, "C", {1}), kB, 11).outcome == fw::DatagramOutcome::message);
}

TEST(LcmDatagram, MessagesInFlightExpire) {
  R r;
  const std::string channel = "C";
  CHECK(feed(r, fragment(1, 100, 0, 0, 2, &channel, Bytes(50, 0)), kA, 1000).outcome ==
        fw::DatagramOutcome::fragment_stored);
  CHECK(feed(r, short_datagram(1, "C", {1}), kB, 1000 + R::kFragmentTimeout_us).outcome ==
        fw::DatagramOutcome::message);
  UNSIGNED_LONGS_EQUAL(1, r.in_flight());
  CHECK(feed(r, short_datagram(2, "C", {1}), kB, 1001 + R::kFragmentTimeout_us).outcome ==
        fw::DatagramOutcome::message);
  UNSIGNED_LONGS_EQUAL(0, r.in_flight());
  LONGS_EQUAL(1, r.counters().expired);
  // The late fragment 1 cannot complete the expired message.
  CHECK(feed(r, fragment(1, 100, 50, 1, 2, nullptr, Bytes(50, 0)), kA, 1002 + R::kFragmentTimeout_us).outcome ==
        fw::DatagramOutcome::fragment_stored);
}
