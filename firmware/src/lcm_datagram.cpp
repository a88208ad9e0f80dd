#include "rockwatch/firmware/lcm_datagram.hpp"

#include <cstring>

namespace rockwatch::firmware {
namespace {

std::uint32_t read_be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}
std::uint16_t read_be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((std::uint32_t{p[0]} << 8) | std::uint32_t{p[1]});
}

bool same_source(DatagramSource a, DatagramSource b) { return a.ipv4 == b.ipv4 && a.port == b.port; }

// The channel name starting at `p` with `available` bytes left in the datagram: its length (without the NUL) in
// *length, or the reject reason. Scans at most kMaxChannelLength + 1 bytes.
std::uint32_t scan_channel(const std::uint8_t* p, std::size_t available, std::size_t* length) {
  const std::size_t limit = available < LcmDatagramReassembler::kMaxChannelLength + 1
                                ? available
                                : LcmDatagramReassembler::kMaxChannelLength + 1;
  for (std::size_t i = 0; i < limit; ++i) {
    if (p[i] == 0) {
      if (i == 0) return kRejectChannelLength;
      *length = i;
      return 0;
    }
  }
  // No NUL within the allowed length: too long if the datagram had more bytes, else unterminated.
  return available > LcmDatagramReassembler::kMaxChannelLength ? kRejectChannelLength : kRejectChannelUnterminated;
}

}  // namespace

DatagramOutcome LcmDatagramReassembler::reject(std::uint32_t reasons, std::uint32_t* out_reasons) {
  ++counters_.rejected;
  for (int k = 0; k < kDatagramRejectReasons; ++k) {
    if ((reasons & (1u << k)) != 0) ++counters_.rejected_by_reason[k];
  }
  if (out_reasons != nullptr) *out_reasons = reasons;
  return DatagramOutcome::rejected;
}

DatagramOutcome LcmDatagramReassembler::accept(const std::uint8_t* data, std::size_t size, DatagramSource source,
                                               std::int64_t now_us, LcmMessageView* out, std::uint32_t* reasons) {
  ++counters_.datagrams;
  if (reasons != nullptr) *reasons = 0;
  expire(now_us);
  if (data == nullptr || size < 4) return reject(kRejectTruncatedHeader, reasons);
  const std::uint32_t magic = read_be32(data);
  if (magic == kMagicShort) return accept_short(data, size, source, out, reasons);
  if (magic == kMagicFragment) return accept_fragment(data, size, source, now_us, out, reasons);
  return reject(kRejectBadMagic, reasons);
}

DatagramOutcome LcmDatagramReassembler::accept_short(const std::uint8_t* data, std::size_t size,
                                                     DatagramSource source, LcmMessageView* out,
                                                     std::uint32_t* reasons) {
  if (size < kShortHeaderBytes) return reject(kRejectTruncatedHeader, reasons);
  std::size_t channel_length = 0;
  const std::uint32_t bad = scan_channel(data + kShortHeaderBytes, size - kShortHeaderBytes, &channel_length);
  if (bad != 0) return reject(bad, reasons);
  const std::size_t payload_offset = kShortHeaderBytes + channel_length + 1;  // ≤ size: the NUL was inside
  const std::size_t payload_size = size - payload_offset;
  ++counters_.short_messages;
  if (out != nullptr) {
    out->channel = reinterpret_cast<const char*>(data + kShortHeaderBytes);
    out->payload = data + payload_offset;
    out->size = payload_size;
    out->sequence_number = read_be32(data + 4);
    out->source = source;
  }
  return DatagramOutcome::message;
}

void LcmDatagramReassembler::expire(std::int64_t now_us) {
  for (Slot& s : slots_) {
    // A clock that went backwards (realtime adjusted) also ends the wait: the age is unknown.
    if (s.used && (now_us - s.first_us > kFragmentTimeout_us || now_us < s.first_us)) {
      s.used = false;
      ++counters_.expired;
    }
  }
}

LcmDatagramReassembler::Slot& LcmDatagramReassembler::slot_for(DatagramSource source, std::uint32_t sequence_number,
                                                               std::int64_t now_us) {
  Slot* free_slot = nullptr;
  Slot* oldest = &slots_[0];
  for (Slot& s : slots_) {
    if (s.used && same_source(s.source, source)) {
      if (s.sequence_number == sequence_number) return s;
      s.used = false;  // the sender moved on: its previous message will not complete
      ++counters_.abandoned;
    }
    if (!s.used) {
      if (free_slot == nullptr) free_slot = &s;
    } else if (s.last_us < oldest->last_us || !oldest->used) {
      oldest = &s;
    }
  }
  Slot* chosen = free_slot;
  if (chosen == nullptr) {
    chosen = oldest;
    ++counters_.evicted;
  }
  Slot& s = *chosen;
  s.used = true;
  s.source = source;
  s.sequence_number = sequence_number;
  s.payload_size = 0;
  s.n_fragments = 0;  // 0: not yet set by a fragment
  s.fragments_received = 0;
  s.bytes_received = 0;
  s.first_us = now_us;
  s.last_us = now_us;
  s.have_channel = false;
  s.channel[0] = '\0';
  std::memset(s.received, 0, sizeof(s.received));
  return s;
}

DatagramOutcome LcmDatagramReassembler::accept_fragment(const std::uint8_t* data, std::size_t size,
                                                        DatagramSource source, std::int64_t now_us,
                                                        LcmMessageView* out, std::uint32_t* reasons) {
  if (size < kFragmentHeaderBytes) return reject(kRejectTruncatedHeader, reasons);
  const std::uint32_t sequence_number = read_be32(data + 4);
  const std::uint32_t payload_size = read_be32(data + 8);
  const std::uint32_t fragment_offset = read_be32(data + 12);
  const std::uint16_t fragment_number = read_be16(data + 16);
  const std::uint16_t n_fragments = read_be16(data + 18);

  // Everything that can be checked on the datagram alone, before any slot is touched.
  if (n_fragments == 0 || n_fragments > kMaxFragments || fragment_number >= n_fragments) {
    return reject(kRejectFragmentCount, reasons);
  }
  std::size_t data_offset = kFragmentHeaderBytes;
  std::size_t channel_length = 0;
  if (fragment_number == 0) {
    const std::uint32_t bad = scan_channel(data + kFragmentHeaderBytes, size - kFragmentHeaderBytes, &channel_length);
    if (bad != 0) return reject(bad, reasons);
    data_offset += channel_length + 1;  // ≤ size: the NUL was inside
    if (fragment_offset != 0) return reject(kRejectFragmentBounds, reasons);
  }
  const std::uint64_t data_length = size - data_offset;
  if (std::uint64_t{fragment_offset} + data_length > std::uint64_t{payload_size}) {
    return reject(kRejectFragmentBounds, reasons);
  }

  if (payload_size > kMaxMessageBytes) {
    ++counters_.skipped_too_large;
    return DatagramOutcome::skipped;
  }

  Slot& s = slot_for(source, sequence_number, now_us);
  if (s.n_fragments == 0) {
    s.payload_size = payload_size;
    s.n_fragments = n_fragments;
  } else if (s.payload_size != payload_size || s.n_fragments != n_fragments) {
    s.used = false;  // one of the two is wrong; the message cannot be trusted
    return reject(kRejectFragmentMismatch, reasons);
  }
  const std::uint8_t bit = static_cast<std::uint8_t>(1u << (fragment_number % 8));
  if ((s.received[fragment_number / 8] & bit) != 0) return reject(kRejectFragmentDuplicate, reasons);
  s.received[fragment_number / 8] = static_cast<std::uint8_t>(s.received[fragment_number / 8] | bit);
  ++s.fragments_received;
  s.bytes_received += data_length;
  s.last_us = now_us;
  if (fragment_number == 0) {
    std::memcpy(s.channel, data + kFragmentHeaderBytes, channel_length);
    s.channel[channel_length] = '\0';
    s.have_channel = true;
  }
  if (data_length > 0) std::memcpy(s.payload + fragment_offset, data + data_offset, static_cast<std::size_t>(data_length));

  if (s.fragments_received < s.n_fragments) {
    ++counters_.fragments;
    return DatagramOutcome::fragment_stored;
  }
  // All fragments arrived: their lengths must cover the payload exactly (overlaps or holes otherwise). The last
  // fragment counts as a fragment or as the rejected datagram, never both (found by fuzz_monitor_datagrams).
  s.used = false;
  if (s.bytes_received != s.payload_size || !s.have_channel) return reject(kRejectFragmentMismatch, reasons);
  ++counters_.fragments;
  ++counters_.messages_reassembled;
  std::memcpy(completed_channel_, s.channel, sizeof(completed_channel_));
  if (out != nullptr) {
    out->channel = completed_channel_;
    out->payload = s.payload;  // the slot is free but untouched until the next accept()
    out->size = s.payload_size;
    out->sequence_number = s.sequence_number;
    out->source = s.source;
  }
  return DatagramOutcome::message;
}

std::size_t LcmDatagramReassembler::in_flight() const {
  std::size_t n = 0;
  for (const Slot& s : slots_) n += s.used ? 1u : 0u;
  return n;
}

}  // namespace rockwatch::firmware
