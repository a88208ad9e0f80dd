// LCM's UDP multicast wire format, received without trusting the datagram: LC02 short messages and LC03 fragments
// (LCM's "UDP Multicast Protocol Description"), reassembled into caller-visible messages with every length, offset
// and count checked in 64-bit arithmetic against fixed buffers.
//
// Why our own: liblcm 1.3.1 checks a fragment's bounds in 32-bit unsigned arithmetic that wraps, and lets a first
// fragment whose channel name runs past the datagram underflow its length; two crafted datagrams crash any
// liblcm subscriber (docs/RELIABILITY.md, "The receive path"). This class is the monitor's only parser of datagrams.
//
// Firmware rules: no allocation (all buffers are members; the caller owns the object), bounded work per datagram
// (one pass over its bytes, a scan of kSlots slots), no exceptions. A bad datagram is rejected with reason bits
// and counted; it never changes a message in flight from another sender.
//
// Reassembly, per sender (IPv4 address and port) one message in flight, at most kSlots in flight in all:
// - a fragment of a new sequence number from a sender replaces that sender's message in flight (liblcm does the
//   same: a publisher's fragments arrive in order, so an older message will not complete) — counted as abandoned;
// - with every slot busy, a new sender's fragment takes the slot unused for longest — counted as evicted;
// - a message in flight older than kFragmentTimeout_us (by the receive time) is dropped — counted as expired;
// - fragments may arrive in any order; a duplicate fragment is rejected, a fragment that disagrees with the
//   message in flight (payload size, fragment count, offset of fragment 0) is rejected and drops that message;
// - the message completes when all n_fragments have arrived and their lengths sum to payload_size exactly.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rockwatch::firmware {

// Where a datagram came from: IPv4 address and UDP port, host byte order.
struct DatagramSource {
  std::uint32_t ipv4 = 0;
  std::uint16_t port = 0;
};

// Why a datagram was rejected. One bit per reason; bits are never reused.
enum DatagramReject : std::uint32_t {
  kRejectTruncatedHeader = 1u << 0,        // shorter than the 8-byte (LC02) or 20-byte (LC03) header
  kRejectBadMagic = 1u << 1,               // neither LC02 nor LC03
  kRejectChannelUnterminated = 1u << 2,    // no NUL after the channel name within the datagram
  kRejectChannelLength = 1u << 3,          // channel name empty or longer than kMaxChannelLength
  kRejectRetired4 = 1u << 4,               // (was: message too large; now DatagramOutcome::skipped, not an error)
  kRejectFragmentCount = 1u << 5,          // n_fragments 0 or > kMaxFragments, or fragment_number ≥ n_fragments
  kRejectFragmentBounds = 1u << 6,         // fragment_offset + data length > payload_size, or fragment 0 at offset ≠ 0
  kRejectFragmentMismatch = 1u << 7,       // disagrees with the message in flight (size, count) or lengths ≠ size
  kRejectFragmentDuplicate = 1u << 8,      // this fragment of this message arrived before
};
inline constexpr int kDatagramRejectReasons = 9;

struct DatagramCounters {
  std::int64_t datagrams = 0;               // every datagram given to accept()
  std::int64_t short_messages = 0;          // LC02 accepted
  std::int64_t fragments = 0;               // LC03 accepted (stored, or completing a message)
  std::int64_t messages_reassembled = 0;    // LC03 messages completed
  std::int64_t skipped_too_large = 0;       // valid LC03 fragments of a message over kMaxMessageBytes (not stored)
  std::int64_t rejected = 0;                // datagrams rejected (any reason)
  std::int64_t rejected_by_reason[kDatagramRejectReasons] = {};  // index k: bit 1 << k
  std::int64_t abandoned = 0;               // in flight, replaced by the same sender's next message
  std::int64_t evicted = 0;                 // in flight, replaced by another sender's message (slots full)
  std::int64_t expired = 0;                 // in flight longer than kFragmentTimeout_us
};

// A received message. Points into the datagram (LC02) or into the reassembler's slot (LC03): valid until the next
// call of accept().
struct LcmMessageView {
  const char* channel = nullptr;  // NUL-terminated, 1..kMaxChannelLength characters
  const std::uint8_t* payload = nullptr;
  std::size_t size = 0;           // payload bytes
  std::uint32_t sequence_number = 0;
  DatagramSource source{};
};

enum class DatagramOutcome : std::uint8_t {
  message = 0,          // *out holds a complete message
  fragment_stored = 1,  // a valid fragment of a message not yet complete
  rejected = 2,         // *reasons holds DatagramReject bits
  skipped = 3,          // a well-formed fragment of a message too large to reassemble (another program's traffic)
};

class LcmDatagramReassembler {
 public:
  static constexpr std::uint32_t kMagicShort = 0x4c433032u;  // "LC02"
  static constexpr std::uint32_t kMagicFragment = 0x4c433033u;  // "LC03"
  static constexpr std::size_t kShortHeaderBytes = 8;
  static constexpr std::size_t kFragmentHeaderBytes = 20;
  static constexpr std::size_t kMaxChannelLength = 63;  // LCM's limit (LCM_MAX_CHANNEL_NAME_LENGTH)
  // The largest fragmented message reassembled. The monitor's largest input (ground_accel_batch_t) encodes to 840
  // bytes; liblcm sends messages up to 64 KiB in one LC02 datagram (passed through whatever their size, without a
  // copy) and fragments only larger ones, which are not the monitor's inputs: their fragments are skipped, not stored.
  static constexpr std::size_t kMaxMessageBytes = 4096;
  static constexpr std::size_t kMaxFragments = 64;  // ≥ kMaxMessageBytes / (smallest useful fragment, 64 B)
  static constexpr std::size_t kSlots = 4;          // messages in flight (senders fragmenting at once)
  static constexpr std::int64_t kFragmentTimeout_us = 1000000;

  // One datagram of `size` bytes from `source`, received at now_us [µs, any monotonic or realtime clock]. On
  // DatagramOutcome::message, *out describes the message; on rejected, *reasons the DatagramReject bits (either
  // pointer may be null). Never reads outside [data, data + size).
  DatagramOutcome accept(const std::uint8_t* data, std::size_t size, DatagramSource source, std::int64_t now_us,
                         LcmMessageView* out, std::uint32_t* reasons);

  const DatagramCounters& counters() const { return counters_; }
  // Messages in flight (incomplete).
  std::size_t in_flight() const;

 private:
  struct Slot {
    bool used = false;
    DatagramSource source{};
    std::uint32_t sequence_number = 0;
    std::uint32_t payload_size = 0;
    std::uint16_t n_fragments = 0;
    std::uint16_t fragments_received = 0;
    std::uint64_t bytes_received = 0;
    std::int64_t first_us = 0, last_us = 0;
    bool have_channel = false;
    char channel[kMaxChannelLength + 1] = {};
    std::uint8_t received[kMaxFragments / 8] = {};  // bit k: fragment k arrived
    std::uint8_t payload[kMaxMessageBytes] = {};
  };

  DatagramOutcome reject(std::uint32_t reasons, std::uint32_t* out_reasons);
  DatagramOutcome accept_short(const std::uint8_t* data, std::size_t size, DatagramSource source, LcmMessageView* out,
                               std::uint32_t* reasons);
  DatagramOutcome accept_fragment(const std::uint8_t* data, std::size_t size, DatagramSource source,
                                  std::int64_t now_us, LcmMessageView* out, std::uint32_t* reasons);
  void expire(std::int64_t now_us);
  Slot& slot_for(DatagramSource source, std::uint32_t sequence_number, std::int64_t now_us);

  DatagramCounters counters_{};
  Slot slots_[kSlots]{};
  // The completed message's channel is copied here, so its slot can be freed before the caller reads the view.
  char completed_channel_[kMaxChannelLength + 1] = {};
};

}  // namespace rockwatch::firmware
