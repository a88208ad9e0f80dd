// miniSEED 2 records, decoded by libmseed 2.19 (Debian libmseed-dev, legacy API). The file is read whole by the
// same guarded reader as the text formats and parsed record by record from memory with msr_parse, so a truncated
// or damaged file is reported at its byte offset instead of being skipped the way ms_readmsr skips what it cannot
// parse. libmseed is confined to this file.
#include <libmseed.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ios>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "civil_time.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

using detail::shown;

// The smallest record libmseed accepts is 128 bytes; its fixed header alone is 48.
constexpr std::size_t kFixedHeaderBytes = 48;
constexpr double kPreEventSeconds = 60.0;
constexpr std::int64_t kNanosecondsPerTick = detail::kNanosecondsPerSecond / HPTMODULUS;
// Record times accepted: 1900-01-01 to 2199-12-31, in hptime ticks (µs), well inside int64 epoch nanoseconds.
constexpr std::int64_t kEarliestUs = detail::days_from_civil(1900, 1, 1) * detail::kSecondsPerDay * HPTMODULUS;
constexpr std::int64_t kLatestUs = detail::days_from_civil(2200, 1, 1) * detail::kSecondsPerDay * HPTMODULUS;

// libmseed reports problems (including the Steim integrity check, which it only logs) through a global logging
// hook. They are collected here, per thread and in a fixed buffer (no allocation that could outlive a call), and
// turned into RecordErrors. The hook itself is process-wide: readers on several threads share it.
struct LibmseedLog {
  char text[1024];
  std::size_t length;
};
thread_local LibmseedLog g_log{};

void append_log(char* message) {
  if (message == nullptr) return;
  const std::size_t room = sizeof g_log.text - 1 - g_log.length;
  std::size_t n = std::min(std::strlen(message), room);
  // Messages end with a newline; several are joined with "; ".
  while (n > 0 && (message[n - 1] == '\n' || message[n - 1] == '\r')) --n;
  if (n == 0) return;
  if (g_log.length > 0 && room > n + 2) {
    std::memcpy(g_log.text + g_log.length, "; ", 2);
    g_log.length += 2;
  }
  const std::size_t fit = std::min(n, sizeof g_log.text - 1 - g_log.length);
  std::memcpy(g_log.text + g_log.length, message, fit);
  g_log.length += fit;
  g_log.text[g_log.length] = '\0';
}

void clear_log() {
  g_log.length = 0;
  g_log.text[0] = '\0';
}

// The log can quote header fields of a damaged record; keep it printable.
std::string logged() {
  std::string text(g_log.text, g_log.length);
  for (char& c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7F) c = '?';
  }
  return text;
}

void capture_libmseed_log() { ms_loginit(append_log, nullptr, append_log, nullptr); }

struct MsRecordDeleter {
  void operator()(MSRecord* msr) const { msr_free(&msr); }
};
using MsRecordPtr = std::unique_ptr<MSRecord, MsRecordDeleter>;

// One decoded record of one channel.
struct Piece {
  std::int64_t start_us = 0;  // hptime: microseconds since 1970
  double samprate_hz = 0.0;
  char sample_type = 'i';
  std::int8_t encoding = DE_STEIM2;
  std::size_t byte_offset = 0;
  std::vector<double> samples;  // int32 counts and float32 values are exact in double
};

struct Channel {
  std::string id;    // NET.STA.LOC.CHA
  std::string code;  // CHA
  std::vector<Piece> pieces;
};

std::string offset_text(std::size_t offset) { return "byte offset " + std::to_string(offset); }

std::string time_text(std::int64_t hptime_us) { return detail::iso_time_text(hptime_us * kNanosecondsPerTick); }

std::string encoding_name(std::int8_t encoding) {
  std::string name = ms_encodingstr(static_cast<char>(encoding));
  for (char& c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7F) c = '?';
  }
  return name;
}

std::string seconds_text(double seconds) { return detail::number_text(seconds) + " s"; }

bool rest_is_padding(const std::string& content, std::size_t offset) {
  return std::all_of(content.begin() + static_cast<std::ptrdiff_t>(offset), content.end(),
                     [](char c) { return c == '\0' || c == ' '; });
}

void take_samples(const std::string& path, const MSRecord& msr, std::size_t offset, Piece& piece) {
  const auto count = static_cast<std::size_t>(msr.numsamples);
  piece.samples.resize(count);
  switch (msr.sampletype) {
    case 'i': {
      const auto* values = static_cast<const std::int32_t*>(msr.datasamples);
      for (std::size_t k = 0; k < count; ++k) piece.samples[k] = static_cast<double>(values[k]);
      break;
    }
    case 'f': {
      const auto* values = static_cast<const float*>(msr.datasamples);
      for (std::size_t k = 0; k < count; ++k) piece.samples[k] = static_cast<double>(values[k]);
      break;
    }
    case 'd': {
      const auto* values = static_cast<const double*>(msr.datasamples);
      for (std::size_t k = 0; k < count; ++k) piece.samples[k] = values[k];
      break;
    }
    default:
      throw RecordError(path, 0,
                        offset_text(offset) + ": sample type '" + std::string(1, msr.sampletype) +
                            "': expected integer or floating-point samples");
  }
}

// Bytes per sample of the encodings libmseed unpacks sample by sample; 0 for Steim frames (libmseed bounds those by
// the record length itself) and for encodings it refuses.
std::size_t bytes_per_sample(std::int8_t encoding) {
  switch (encoding) {
    case DE_INT32:
    case DE_FLOAT32:
      return 4;
    case DE_FLOAT64:
      return 8;
    case DE_GEOSCOPE24:
      return 3;
    case DE_INT16:
    case DE_GEOSCOPE163:
    case DE_GEOSCOPE164:
    case DE_CDSN:
    case DE_SRO:
    case DE_DWWSSN:
      return 2;
    default:
      return 0;
  }
}

// libmseed 2 copies as many samples as the header announces out of an uncompressed data section without comparing
// them with the record length, and trusts the data offset: a damaged header made it read past the record (and past
// the file in memory). Checked on the parsed header before the samples are unpacked.
void check_data_section(const std::string& path, const MSRecord& msr, std::size_t offset) {
  const std::size_t reclen = static_cast<std::size_t>(msr.reclen);
  const std::size_t data_offset = msr.fsdh != nullptr ? msr.fsdh->data_offset : 0;
  if (data_offset < kFixedHeaderBytes || data_offset > reclen) {
    throw RecordError(path, 0,
                      offset_text(offset) + ": data offset " + std::to_string(data_offset) +
                          " outside the record of " + std::to_string(reclen) +
                          " bytes: expected the data after the 48-byte fixed header (a damaged header?)");
  }
  const std::size_t size = bytes_per_sample(msr.encoding);
  const auto count = static_cast<std::size_t>(msr.samplecnt);
  if (size > 0 && count > (reclen - data_offset) / size) {
    throw RecordError(path, 0,
                      offset_text(offset) + ": the header announces " + std::to_string(count) + " samples of " +
                          std::to_string(size) + " bytes (" + encoding_name(msr.encoding) + "), but the record holds " +
                          std::to_string(reclen - data_offset) + " bytes of data: expected an undamaged header");
  }
}

// Decodes every data record: the header first, then, once its data section is checked, the samples. Text records
// (ASCII encoding, e.g. LOG channels) and records without samples carry no waveform and are left out.
std::vector<Channel> decode(const std::string& path, std::string& content) {
  if (content.size() < kFixedHeaderBytes) {
    throw RecordError(path, 0,
                      "file of " + std::to_string(content.size()) +
                          " bytes: expected miniSEED records (at least 48 bytes of fixed header each)");
  }
  capture_libmseed_log();
  std::vector<Channel> channels;
  std::size_t offset = 0;
  while (offset < content.size()) {
    const std::size_t remaining = content.size() - offset;
    // read_whole_file caps files at 512 MiB, so this never clamps; the cast is guarded all the same.
    const int buffer_length = static_cast<int>(std::min<std::size_t>(remaining, INT_MAX));
    clear_log();
    MSRecord* raw = nullptr;
    const int status = msr_parse(content.data() + offset, buffer_length, &raw, 0, 0, 0);
    MsRecordPtr msr(raw);
    if (status > 0) {
      throw RecordError(path, 0,
                        offset_text(offset) + ": the file ends inside a miniSEED record (" + std::to_string(remaining) +
                            " of " + std::to_string(remaining + static_cast<std::size_t>(status)) +
                            " bytes): it looks truncated");
    }
    if (status < 0 || !msr) {
      if (offset > 0 && rest_is_padding(content, offset)) break;
      std::string message =
          offset_text(offset) + ": not a valid miniSEED data record (" + std::string(ms_errorstr(status)) + ")";
      if (g_log.length > 0) message += ": libmseed says " + logged();
      throw RecordError(path, 0, message + "; expected a complete, undamaged miniSEED file");
    }
    // Header warnings (blockette chain, data offset) are logged the same way.
    if (g_log.length > 0) {
      throw RecordError(
          path, 0,
          offset_text(offset) + ": damaged miniSEED record: libmseed says " + logged() + "; expected undamaged data");
    }
    if (msr->reclen <= 0 || static_cast<std::size_t>(msr->reclen) > remaining) {
      throw RecordError(path, 0,
                        offset_text(offset) + ": miniSEED record length " + std::to_string(msr->reclen) +
                            " does not fit the file: expected a complete record");
    }
    const std::size_t record_offset = offset;
    offset += static_cast<std::size_t>(msr->reclen);
    if (msr->encoding == DE_ASCII || msr->samplecnt <= 0) continue;
    check_data_section(path, *msr, record_offset);
    raw = msr.release();
    const int unpacked = msr_parse(content.data() + record_offset, raw->reclen, &raw, raw->reclen, 1, 0);
    msr.reset(raw);
    if (unpacked != MS_NOERROR || !msr) {
      std::string message = offset_text(record_offset) + ": cannot unpack the samples of the miniSEED record (" +
                            std::string(ms_errorstr(unpacked)) + ")";
      if (g_log.length > 0) message += ": libmseed says " + logged();
      throw RecordError(path, 0, message + "; expected a complete, undamaged miniSEED file");
    }
    // libmseed only logs a failed Steim integrity check or a sample-count mismatch; either means damaged data.
    if (g_log.length > 0) {
      throw RecordError(path, 0,
                        offset_text(record_offset) + ": damaged miniSEED record: libmseed says " + logged() +
                            "; expected undamaged data");
    }
    if (msr->numsamples != msr->samplecnt) {
      throw RecordError(path, 0,
                        offset_text(record_offset) + ": decoded " + std::to_string(msr->numsamples) + " of " +
                            std::to_string(msr->samplecnt) + " samples the header announces: expected them all");
    }
    // A damaged time field can put a record millennia away, beyond what epoch nanoseconds hold.
    if (msr->starttime < kEarliestUs || msr->starttime >= kLatestUs) {
      throw RecordError(path, 0,
                        offset_text(record_offset) +
                            ": record start time outside the years 1900-2199: expected a plausible time (a damaged "
                            "header?)");
    }
    if (!std::isfinite(msr->samprate) || msr->samprate <= 0.0) {
      throw RecordError(path, 0,
                        offset_text(record_offset) + ": sample rate " + detail::number_text(msr->samprate) +
                            " Hz: expected a positive sample rate");
    }

    std::string code = msr->channel;
    std::string id = std::string(msr->network) + "." + msr->station + "." + msr->location + "." + code;
    auto channel = std::find_if(channels.begin(), channels.end(), [&id](const Channel& c) { return c.id == id; });
    if (channel == channels.end()) {
      channels.push_back(Channel{std::move(id), std::move(code), {}});
      channel = channels.end() - 1;
    }
    Piece piece;
    piece.start_us = msr->starttime;
    piece.samprate_hz = msr->samprate;
    piece.sample_type = msr->sampletype;
    piece.encoding = msr->encoding;
    piece.byte_offset = record_offset;
    take_samples(path, *msr, record_offset, piece);
    channel->pieces.push_back(std::move(piece));
  }
  if (channels.empty()) {
    throw RecordError(path, 0, "no waveform samples in the miniSEED file: expected acceleration records");
  }
  return channels;
}

std::string channel_list(const std::vector<const Channel*>& channels) {
  std::string list;
  for (const Channel* channel : channels) {
    if (!list.empty()) list += ", ";
    list += channel->id;
  }
  return list;
}

std::vector<const Channel*> all_of(const std::vector<Channel>& channels) {
  std::vector<const Channel*> pointers;
  for (const Channel& channel : channels) pointers.push_back(&channel);
  return pointers;
}

bool same_text(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
         });
}

const Channel& choose_channel(const std::string& path, const std::vector<Channel>& channels,
                              const std::optional<std::string>& wanted) {
  const std::string list = channel_list(all_of(channels));
  if (!wanted) {
    if (channels.size() == 1) return channels.front();
    throw RecordError(path, 0,
                      "the file holds " + std::to_string(channels.size()) + " channels (" + list +
                          "): choose one with --channel (a channel code such as " + channels.front().code +
                          ", or NET.STA.LOC.CHA)");
  }
  std::vector<const Channel*> matches;
  for (const Channel& channel : channels) {
    if (same_text(channel.id, *wanted)) return channel;
    if (same_text(channel.code, *wanted)) matches.push_back(&channel);
  }
  if (matches.size() == 1) return *matches.front();
  if (matches.empty()) {
    throw RecordError(
        path, 0, "no channel " + shown(*wanted) + " in the file: it holds " + list + "; choose one with --channel");
  }
  throw RecordError(path, 0,
                    "channel code " + shown(*wanted) + " matches " + channel_list(matches) +
                        ": choose one with --channel NET.STA.LOC.CHA");
}

struct Trace {
  std::int64_t start_us = 0;
  double samprate_hz = 0.0;
  char sample_type = 'i';
  std::vector<double> samples;
};

// Joins the channel's records in time order. Records are contiguous when each starts within half a sample of where
// the previous one ends (libmseed's default time tolerance); anything else is a gap or an overlap, which a record
// with one constant dt cannot represent, so it is refused with its time and length.
Trace merge(const std::string& path, const Channel& channel) {
  std::vector<const Piece*> pieces;
  for (const Piece& piece : channel.pieces) pieces.push_back(&piece);
  std::stable_sort(pieces.begin(), pieces.end(),
                   [](const Piece* a, const Piece* b) { return a->start_us < b->start_us; });
  Trace trace;
  trace.start_us = pieces.front()->start_us;
  trace.samprate_hz = pieces.front()->samprate_hz;
  trace.sample_type = pieces.front()->sample_type;
  const double tick_per_sample = static_cast<double>(HPTMODULUS) / trace.samprate_hz;
  const Piece* previous = nullptr;
  for (const Piece* piece : pieces) {
    if (!MS_ISRATETOLERABLE(piece->samprate_hz, trace.samprate_hz)) {
      throw RecordError(path, 0,
                        offset_text(piece->byte_offset) + ": " + channel.id + " changes sample rate from " +
                            detail::number_text(trace.samprate_hz) + " Hz to " +
                            detail::number_text(piece->samprate_hz) + " Hz at " + time_text(piece->start_us) +
                            ": expected one sample rate");
    }
    // Recorders keep one encoding per channel. A record that claims another is almost always damaged: one flipped
    // bit turns Steim2 into raw int32, which decodes without complaint into nonsense.
    if (piece->encoding != pieces.front()->encoding || piece->sample_type != trace.sample_type) {
      throw RecordError(path, 0,
                        offset_text(piece->byte_offset) + ": " + channel.id + " changes encoding from " +
                            encoding_name(pieces.front()->encoding) + " to " + encoding_name(piece->encoding) + " at " +
                            time_text(piece->start_us) + ": expected one encoding per channel (a damaged record?)");
    }
    if (previous != nullptr) {
      const double expected_us =
          static_cast<double>(previous->start_us) + static_cast<double>(previous->samples.size()) * tick_per_sample;
      const double gap_us = static_cast<double>(piece->start_us) - expected_us;
      if (std::fabs(gap_us) > 0.5 * tick_per_sample) {
        const auto at_us = static_cast<std::int64_t>(std::llround(expected_us));
        const std::string length = seconds_text(std::fabs(gap_us) / static_cast<double>(HPTMODULUS));
        if (gap_us > 0.0) {
          throw RecordError(path, 0,
                            channel.id + " has a gap of " + length + " at " + time_text(at_us) + " (data resume at " +
                                time_text(piece->start_us) +
                                "): expected contiguous records; cut the record before or after the gap");
        }
        throw RecordError(path, 0,
                          channel.id + " has records overlapping by " + length + " at " + time_text(piece->start_us) +
                              " (the previous record runs to " + time_text(at_us) +
                              "): expected contiguous records, each sample once");
      }
    }
    trace.samples.insert(trace.samples.end(), piece->samples.begin(), piece->samples.end());
    previous = piece;
  }
  return trace;
}

// Counts to m/s²: a = (counts − offset)/gain, with the offset the mean of the leading 60 s (the whole trace when
// shorter) — the accelerometer's zero before the event, as the shared collection's derived file was made.
void counts_to_mps2(const std::string& path, const ReadOptions& options, Trace& trace, Record& record) {
  if (!options.gain_counts_per_mps2) {
    throw RecordError(path, 0,
                      "the file holds integer counts (" + record.description +
                          "); give --gain COUNTS_PER_MPS2 (the station's InstrumentSensitivity, e.g. from "
                          "StationXML)");
  }
  if (options.units) {
    throw RecordError(path, 0,
                      "the file holds integer counts, converted to m/s² by --gain; --units " +
                          std::string(accel_unit_name(*options.units)) + " does not apply");
  }
  const double gain = *options.gain_counts_per_mps2;
  const auto leading = static_cast<std::size_t>(std::ceil(kPreEventSeconds * trace.samprate_hz - 1e-9));
  const std::size_t n = std::clamp<std::size_t>(leading, 1, trace.samples.size());
  double sum = 0.0;  // int32 counts: every partial sum of up to 2^22 of them is an exact double
  for (std::size_t k = 0; k < n; ++k) sum += trace.samples[k];
  const double offset = sum / static_cast<double>(n);
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    const double a = (trace.samples[k] - offset) / gain;
    // Only a gain near the smallest double can overflow here; it is a typo, not a sensitivity.
    if (!std::isfinite(a)) {
      throw RecordError(path, 0,
                        record.description + ": sample " + std::to_string(k) + " overflows with --gain " +
                            detail::number_text(gain) + ": expected the station's sensitivity in counts per m/s²");
    }
    trace.samples[k] = a;
  }
  record.units_in_file = AccelUnit::mps2;
  record.notes.push_back(detail::file_name_of(path) + ": " + record.description + ": removed the pre-event mean " +
                         detail::number_text(offset) + " counts (first " +
                         seconds_text(static_cast<double>(n) / trace.samprate_hz) + ") and divided by --gain " +
                         detail::number_text(gain) + " counts per m/s²");
}

void floats_to_mps2(const std::string& path, const ReadOptions& options, Trace& trace, Record& record) {
  if (options.gain_counts_per_mps2) {
    throw RecordError(path, 0,
                      "the file holds floating-point samples (" + record.description +
                          "), not integer counts; --gain does not apply, give --units");
  }
  if (!options.units) {
    throw RecordError(path, 0,
                      "the file holds floating-point samples of unknown units (" + record.description +
                          "); give --units (g|mps2|cmps2|mmps2)");
  }
  record.units_in_file = *options.units;
  const double factor = accel_unit_to_mps2(*options.units, options.g_mps2);
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    const double scaled = trace.samples[k] * factor;
    if (!std::isfinite(scaled)) {
      const auto at_us =
          trace.start_us + static_cast<std::int64_t>(std::llround(static_cast<double>(k) *
                                                                  static_cast<double>(HPTMODULUS) / trace.samprate_hz));
      throw RecordError(path, 0,
                        record.description + ": sample " + std::to_string(k) + " at " + time_text(at_us) + " is " +
                            detail::number_text(trace.samples[k]) + ": expected a finite acceleration");
    }
    trace.samples[k] = scaled;
  }
}

}  // namespace

bool looks_like_miniseed(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  // Enough for ms_detect to find blockette 1000 or the next header of the usual 512- and 4096-byte records.
  std::string head(8192, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.size() < kFixedHeaderBytes) return false;
  capture_libmseed_log();
  clear_log();
  const int detected = ms_detect(head.data(), static_cast<int>(head.size()));
  clear_log();
  return detected >= 0;
}

Record read_miniseed(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  std::string content = detail::read_whole_file(path);
  const std::vector<Channel> channels = decode(path, content);
  const Channel& channel = choose_channel(path, channels, options.channel);
  Trace trace = merge(path, channel);

  Record record;
  record.path = path;
  record.format = "miniseed";
  record.description = channel.id;
  record.dt_s = 1.0 / trace.samprate_hz;
  record.t0_s = 0.0;
  record.start_time_ns = trace.start_us * kNanosecondsPerTick;
  detail::note_ignored_dt(path, options, record.dt_s, "the miniSEED sample rate", record);
  if (trace.sample_type == 'i') {
    counts_to_mps2(path, options, trace, record);
  } else {
    floats_to_mps2(path, options, trace, record);
  }
  record.horizontal_mps2 = std::move(trace.samples);
  return record;
}

}  // namespace rockwatch::records
