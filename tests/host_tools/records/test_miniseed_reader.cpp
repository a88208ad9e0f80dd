// miniSEED reader: the real KNMI file NL.BGAR.mseed (tests/data/records, see SOURCES.md) against the collection's
// derived m/s² file made from it, channel choice and its messages, damaged and truncated copies of the real file,
// and small files packed here with libmseed (float32 with --units, int32 counts with gaps, overlaps and two
// stations).
#include <libmseed.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "reference_data.hpp"
#include "rockwatch/records/record.hpp"
#include "record_test_support.hpp"
#include "rockwatch/records/record_error.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;
using rockwatch::records::AccelUnit;
using rockwatch::records::looks_like_miniseed;
using rockwatch::records::looks_like_peer_at2;
using rockwatch::records::read_miniseed;
using rockwatch::records::read_record;
using rockwatch::records::ReadOptions;
using rockwatch::records::Record;
using rockwatch::records::RecordError;
using rockwatch::test::failure_of;
using rockwatch::test::Failure;
using rockwatch::test::has_note_with;
using rockwatch::test::data_path;

namespace {

// InstrumentSensitivity of every BGAR channel in NL.BGAR.xml [counts per m/s²].
constexpr double kBgarGain = 213867.4766;
// 2020-05-02T03:13:05 UTC, the derived file's first row.
constexpr std::int64_t kWindowStartNs = 1588389185LL * 1000000000LL;
constexpr std::int64_t kMicrosecondNs = 1000;

std::string bgar_path() { return data_path("records/NL.BGAR.mseed"); }

ReadOptions bgar_options(const std::string& channel) {
  ReadOptions options;
  options.channel = channel;
  options.gain_counts_per_mps2 = kBgarGain;
  return options;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The derived file's columns time_s, HGE, HGN, HGZ [m/s²].
std::vector<std::vector<double>> derived_columns() {
  std::ifstream in(data_path("records/NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt"));
  std::vector<std::vector<double>> columns(4);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    for (std::vector<double>& column : columns) {
      double value = 0.0;
      row >> value;
      column.push_back(value);
    }
  }
  return columns;
}

void append_record(char* record, int length, void* out) {
  static_cast<std::string*>(out)->append(record, static_cast<std::size_t>(length));
}

// Packs `samples` into 512-byte miniSEED records with libmseed, as a recorder would write them.
template <typename Sample>
std::string pack(const std::string& network, const std::string& station, const std::string& channel,
                 std::int64_t start_us, double rate_hz, std::vector<Sample> samples, char sample_type,
                 std::int8_t encoding) {
  MSRecord* msr = msr_init(nullptr);
  msr->network[0] = msr->station[0] = msr->location[0] = msr->channel[0] = '\0';
  network.copy(msr->network, 2);
  station.copy(msr->station, 5);
  channel.copy(msr->channel, 3);
  msr->dataquality = 'D';
  msr->starttime = start_us;
  msr->samprate = rate_hz;
  msr->reclen = 512;
  msr->encoding = encoding;
  msr->byteorder = 1;
  msr->datasamples = samples.data();
  msr->numsamples = static_cast<std::int64_t>(samples.size());
  msr->sampletype = sample_type;
  std::string out;
  std::int64_t packed = 0;
  const int records = msr_pack(msr, append_record, &out, &packed, 1, 0);
  msr->datasamples = nullptr;  // owned by `samples`, not by libmseed
  msr_free(&msr);
  CHECK_TRUE_TEXT(records > 0 && packed == static_cast<std::int64_t>(samples.size()), "msr_pack failed");
  return out;
}

std::string pack_float32(const std::string& channel, std::int64_t start_us, double rate_hz,
                         const std::vector<float>& samples) {
  return pack("XX", "TEST", channel, start_us, rate_hz, samples, 'f', DE_FLOAT32);
}

std::string pack_counts(const std::string& station, const std::string& channel, std::int64_t start_us, double rate_hz,
                        const std::vector<std::int32_t>& samples) {
  return pack("XX", station, channel, start_us, rate_hz, samples, 'i', DE_STEIM2);
}

// 2021-01-01T00:00:00 UTC in microseconds.
constexpr std::int64_t kTestStartUs = 1609459200LL * 1000000LL;

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// The real file

TEST_GROUP(MiniseedRealRecord){};

TEST(MiniseedRealRecord, DetectedByContent) {
  CHECK_TRUE(looks_like_miniseed(bgar_path()));
  CHECK_FALSE(looks_like_miniseed(data_path("records/RSN6_IMPVALL.I_I-ELC180-hor1.AT2")));
  CHECK_FALSE(looks_like_miniseed(data_path("records/NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt")));
  CHECK_FALSE(looks_like_miniseed(data_path("records/no-such-file.mseed")));
  CHECK_FALSE(looks_like_peer_at2(bgar_path()));
}

TEST(MiniseedRealRecord, EachChannelMatchesTheDerivedFile) {
  const std::vector<std::vector<double>> derived = derived_columns();
  LONGS_EQUAL(12000, derived[0].size());
  const char* const channels[] = {"HGE", "HGN", "HGZ"};
  const std::size_t npts[] = {144496, 144410, 144734};  // the collection's manifest
  for (std::size_t c = 0; c < 3; ++c) {
    const Record r = read_record(bgar_path(), bgar_options(channels[c]));
    STRCMP_EQUAL("miniseed", r.format.c_str());
    STRCMP_EQUAL((std::string("NL.BGAR..") + channels[c]).c_str(), r.description.c_str());
    CHECK(r.units_in_file == AccelUnit::mps2);
    DOUBLES_EQUAL(0.005, r.dt_s, 1e-15);
    DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
    LONGS_EQUAL(npts[c], r.horizontal_mps2.size());
    CHECK(r.vertical_mps2.empty());
    CHECK(has_note_with(r, {"NL.BGAR.mseed", "removed the pre-event mean", "counts (first 60 s)", "213867.4766"}));
    CHECK_TRUE(r.start_time_ns.has_value());

    // The window starts on a sample: every channel's start is a whole number of 5 ms before it.
    const std::int64_t offset_ns = kWindowStartNs - *r.start_time_ns;
    LONGS_EQUAL(0, offset_ns % 5000000);
    const auto first = static_cast<std::size_t>(offset_ns / 5000000);
    CHECK_TRUE(first + derived[0].size() <= r.horizontal_mps2.size());
    // The derived file prints 7 significant digits: each value agrees to half a unit of its last digit, at most
    // 5e-7 of the value (its maker's float32 SAC step leaves no trace at that precision).
    double worst = 0.0;
    for (std::size_t k = 0; k < derived[0].size(); ++k) {
      const double expected = derived[c + 1][k];
      const double error = std::fabs(r.horizontal_mps2[first + k] - expected);
      worst = std::max(worst, error - 5e-7 * std::fabs(expected));
      DOUBLES_EQUAL(static_cast<double>(k) * 0.005, derived[0][k], 1e-9);
    }
    CHECK_TEXT(worst <= 1e-15, (std::string(channels[c]) + ": worst difference beyond print precision " +
                                std::to_string(worst) + " m/s2")
                                   .c_str());
  }
}

TEST(MiniseedRealRecord, StartTimesAndPeaks) {
  const Record e = read_record(bgar_path(), bgar_options("HGE"));
  // 2020-05-02T03:11:14.395 UTC (libmseed's trace list of the file).
  CHECK(*e.start_time_ns == (1588389074LL * 1000000000LL + 395000000LL));
  double peak = 0.0;
  for (const double a : e.horizontal_mps2) peak = std::max(peak, std::fabs(a));
  DOUBLES_EQUAL(0.08054, peak, 5e-6);  // the collection's manifest: 0.08054 m/s²
}

TEST(MiniseedRealRecord, ChannelByFullIdOrAnyCase) {
  const Record by_id = read_record(bgar_path(), bgar_options("NL.BGAR..HGN"));
  STRCMP_EQUAL("NL.BGAR..HGN", by_id.description.c_str());
  const Record lower = read_record(bgar_path(), bgar_options("hgz"));
  STRCMP_EQUAL("NL.BGAR..HGZ", lower.description.c_str());
}

TEST(MiniseedRealRecord, NoChannelListsThem) {
  ReadOptions options;
  options.gain_counts_per_mps2 = kBgarGain;
  const Failure f = failure_of([&] { read_record(bgar_path(), options); });
  STRCMP_CONTAINS("NL.BGAR.mseed: the file holds 3 channels", f.message.c_str());
  STRCMP_CONTAINS("NL.BGAR..HGE, NL.BGAR..HGN, NL.BGAR..HGZ", f.message.c_str());
  STRCMP_CONTAINS("choose one with --channel", f.message.c_str());
  LONGS_EQUAL(0, f.line);
}

TEST(MiniseedRealRecord, UnknownChannelListsThem) {
  const Failure f = failure_of([&] { read_record(bgar_path(), bgar_options("HHZ")); });
  STRCMP_CONTAINS("no channel 'HHZ' in the file", f.message.c_str());
  STRCMP_CONTAINS("NL.BGAR..HGE, NL.BGAR..HGN, NL.BGAR..HGZ", f.message.c_str());
  STRCMP_CONTAINS("--channel", f.message.c_str());
}

TEST(MiniseedRealRecord, CountsNeedAGainAndNoUnits) {
  ReadOptions no_gain;
  no_gain.channel = "HGE";
  const Failure f = failure_of([&] { read_record(bgar_path(), no_gain); });
  STRCMP_CONTAINS("NL.BGAR.mseed: the file holds integer counts", f.message.c_str());
  STRCMP_CONTAINS("give --gain COUNTS_PER_MPS2 (the station's InstrumentSensitivity, e.g. from StationXML)",
                  f.message.c_str());
  ReadOptions units = bgar_options("HGE");
  units.units = AccelUnit::mps2;
  STRCMP_CONTAINS("--units mps2 does not apply", failure_of([&] { read_record(bgar_path(), units); }).message.c_str());
  ReadOptions negative = bgar_options("HGE");
  negative.gain_counts_per_mps2 = -1.0;
  STRCMP_CONTAINS("--gain -1: expected a positive number",
                  failure_of([&] { read_record(bgar_path(), negative); }).message.c_str());
}

// ---------------------------------------------------------------------------------------------------------------
// Damaged copies and packed files

TEST_GROUP_BASE(MiniseedHandMade, rockwatch::test::HandMadeFileTest){};

TEST(MiniseedHandMade, TruncatedCopiesAreRejected) {
  const std::string bytes = file_bytes(bgar_path());
  // Cut inside the 11th 512-byte record.
  const std::string cut = write("cut.mseed", bytes.substr(0, 512 * 10 + 100));
  CHECK_TRUE(looks_like_miniseed(cut));
  const Failure f = failure_of([&] { read_record(cut, bgar_options("HGE")); });
  STRCMP_CONTAINS("cut.mseed: byte offset 5120: the file ends inside a miniSEED record", f.message.c_str());
  STRCMP_CONTAINS("truncated", f.message.c_str());
  // Too short for a header: not detected as miniSEED, and the text reader refuses it.
  const std::string stub = write("stub.mseed", bytes.substr(0, 40));
  CHECK_FALSE(looks_like_miniseed(stub));
  CHECK(failure_of([&] { read_record(stub, bgar_options("HGE")); }).line >= 0);
  STRCMP_CONTAINS("file of 40 bytes", failure_of([&] { read_miniseed(stub, bgar_options("HGE")); }).message.c_str());
  // Every cut of the first records fails cleanly or reads the whole records before it.
  for (std::size_t length = 48; length < 512 * 3; length += 37) {
    const std::string path = write("cuts.mseed", bytes.substr(0, length));
    try {
      read_record(path, bgar_options("HGE"));
    } catch (const RecordError&) {
    }
  }
}

TEST(MiniseedHandMade, DamagedSteimDataIsRejected) {
  std::string bytes = file_bytes(bgar_path());
  // Record 5 (HGE): its Steim frames start at byte 64 of the record; flip a bit of the first frame's X0 (the
  // record's first sample), which libmseed's integrity check against Xn catches.
  const std::size_t record = 5 * 512;
  bytes[record + 64 + 4 + 1] = static_cast<char>(bytes[record + 64 + 4 + 1] ^ 0x10);
  const std::string path = write("damaged.mseed", bytes);
  const Failure f = failure_of([&] { read_record(path, bgar_options("HGE")); });
  STRCMP_CONTAINS("damaged.mseed: byte offset 2560: damaged miniSEED record", f.message.c_str());
  STRCMP_CONTAINS("libmseed says", f.message.c_str());
}

TEST(MiniseedHandMade, ARecordClaimingAnotherEncodingIsRejected) {
  std::string bytes = file_bytes(bgar_path());
  // Record 2's blockette 1000 encoding byte (record offset 52): one flipped bit turns Steim2 (11) into int32 (3).
  // libmseed would decode its 599 "int32 samples" from 2396 bytes, far past the record's 448 bytes of data (into the
  // next records: counts of ±1e9); the data section check refuses the record first.
  bytes[2 * 512 + 52] = static_cast<char>(bytes[2 * 512 + 52] ^ 0x08);
  const std::string path = write("encoding.mseed", bytes);
  const Failure f = failure_of([&] { read_record(path, bgar_options("HGE")); });
  STRCMP_CONTAINS("encoding.mseed: byte offset 1024: the header announces 599 samples of 4 bytes", f.message.c_str());
  STRCMP_CONTAINS("the record holds 448 bytes of data", f.message.c_str());

  // A record that does fit its data section but changes the channel's encoding (float32, then float64) is refused.
  ReadOptions options;
  options.units = AccelUnit::mps2;
  const std::string mixed = pack_float32("HNE", kTestStartUs, 100.0, {1.0f, 2.0f, 3.0f}) +
                            pack("XX", "TEST", "HNE", kTestStartUs + 30000, 100.0, std::vector<double>{4.0, 5.0},
                                 'd', DE_FLOAT64);
  const Failure g = failure_of([&] { read_record(write("mixed.mseed", mixed), options); });
  STRCMP_CONTAINS("mixed.mseed: byte offset 512: XX.TEST..HNE changes encoding from", g.message.c_str());
  STRCMP_CONTAINS("at 2021-01-01T00:00:00.030000Z: expected one encoding per channel", g.message.c_str());
}

TEST(MiniseedHandMade, DamagedHeaderIsRejected) {
  std::string bytes = file_bytes(bgar_path());
  // Record 7's data-record indicator 'D' becomes 'X': no longer a miniSEED record.
  bytes[7 * 512 + 6] = 'X';
  const std::string path = write("header.mseed", bytes);
  const Failure f = failure_of([&] { read_record(path, bgar_options("HGE")); });
  STRCMP_CONTAINS("header.mseed: byte offset 3584: not a valid miniSEED data record", f.message.c_str());
}

TEST(MiniseedHandMade, FlippedBytesNeverCrash) {
  const std::string original = file_bytes(bgar_path());
  int rejected = 0;
  // Single-byte damage all over the first 8 records (headers, blockettes, Steim frames): every read either
  // returns a record or throws a RecordError (under ASan/UBSan in the debug build: with no memory error either).
  for (std::size_t at = 0; at < 8 * 512; at += 13) {
    std::string bytes = original;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x5A);
    const std::string path = write("flip.mseed", bytes);
    try {
      const Record r = read_record(path, bgar_options("HGE"));
      CHECK_FALSE(r.horizontal_mps2.empty());
    } catch (const RecordError& error) {
      CHECK(std::string(error.what()).find("flip.mseed") != std::string::npos);
      ++rejected;
    }
  }
  CHECK_TRUE(rejected > 0);
}

TEST(MiniseedHandMade, Float32NeedsUnits) {
  const std::vector<float> samples{0.5f, -1.25f, 2.0f, 0.0f, -0.75f};
  const std::string path = write("float.mseed", pack_float32("HNE", kTestStartUs, 100.0, samples));
  CHECK_TRUE(looks_like_miniseed(path));
  ReadOptions options;
  options.units = AccelUnit::cmps2;
  const Record r = read_record(path, options);  // one channel: no --channel needed
  STRCMP_EQUAL("miniseed", r.format.c_str());
  STRCMP_EQUAL("XX.TEST..HNE", r.description.c_str());
  CHECK(r.units_in_file == AccelUnit::cmps2);
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  LONGS_EQUAL(samples.size(), r.horizontal_mps2.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    DOUBLES_EQUAL(0.01 * static_cast<double>(samples[k]), r.horizontal_mps2[k], 1e-17);
  }
  CHECK(*r.start_time_ns == kTestStartUs * kMicrosecondNs);
  CHECK(r.notes.empty());

  const Failure no_units = failure_of([&] { read_record(path); });
  STRCMP_CONTAINS("float.mseed: the file holds floating-point samples of unknown units", no_units.message.c_str());
  STRCMP_CONTAINS("give --units", no_units.message.c_str());
  ReadOptions gain = options;
  gain.gain_counts_per_mps2 = 1000.0;
  STRCMP_CONTAINS("not integer counts; --gain does not apply",
                  failure_of([&] { read_record(path, gain); }).message.c_str());
}

TEST(MiniseedHandMade, Float32NonFiniteSampleIsRejected) {
  const std::vector<float> samples{0.5f, std::nanf(""), 2.0f};
  const std::string path = write("nan.mseed", pack_float32("HNZ", kTestStartUs, 100.0, samples));
  ReadOptions options;
  options.units = AccelUnit::mps2;
  const Failure f = failure_of([&] { read_record(path, options); });
  STRCMP_CONTAINS("nan.mseed: XX.TEST..HNZ: sample 1 at 2021-01-01T00:00:00.010000Z", f.message.c_str());
  STRCMP_CONTAINS("expected a finite acceleration", f.message.c_str());
}

TEST(MiniseedHandMade, CountsRemoveTheMeanOfTheFirstMinute) {
  // 10 Hz, 70 s: the first 600 samples (60 s) average 1003; then an "event".
  std::vector<std::int32_t> counts;
  for (int k = 0; k < 700; ++k) counts.push_back(k < 600 ? 1000 + (k % 7) : 1003 + 50 * ((k % 3) - 1));
  double mean = 0.0;
  for (int k = 0; k < 600; ++k) mean += counts[static_cast<std::size_t>(k)];
  mean /= 600.0;
  const std::string path = write("counts.mseed", pack_counts("STA", "HNN", kTestStartUs, 10.0, counts));
  ReadOptions options;
  options.gain_counts_per_mps2 = 250.0;
  const Record r = read_record(path, options);
  LONGS_EQUAL(700, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.1, r.dt_s, 1e-15);
  for (std::size_t k = 0; k < counts.size(); ++k) {
    DOUBLES_EQUAL((counts[k] - mean) / 250.0, r.horizontal_mps2[k], 1e-12);
  }
  CHECK(has_note_with(r, {"counts.mseed", "XX.STA..HNN", "removed the pre-event mean", "first 60 s", "--gain 250"}));

  // Shorter than a minute: the whole trace's mean.
  const std::vector<std::int32_t> short_counts{10, 20, 30, 40};
  const Record s =
      read_record(write("short.mseed", pack_counts("STA", "HNN", kTestStartUs, 10.0, short_counts)), options);
  DOUBLES_EQUAL(-15.0 / 250.0, s.horizontal_mps2[0], 1e-15);
  DOUBLES_EQUAL(15.0 / 250.0, s.horizontal_mps2[3], 1e-15);
  CHECK(has_note_with(s, {"first 0.4 s"}));
}

TEST(MiniseedHandMade, AGainThatOverflowsIsRejected) {
  const std::string path = write("tiny.mseed", pack_counts("STA", "HNN", kTestStartUs, 10.0, {0, 1000, -1000}));
  ReadOptions options;
  options.gain_counts_per_mps2 = 1e-310;
  const Failure f = failure_of([&] { read_record(path, options); });
  STRCMP_CONTAINS("tiny.mseed: XX.STA..HNN: sample 1 overflows with --gain 1e-310", f.message.c_str());
}

TEST(MiniseedHandMade, ImplausibleStartTimeIsRejected) {
  // 1850-01-01T00:00:00 UTC: a valid miniSEED time, but no accelerometer's.
  const std::string path = write("old.mseed", pack_counts("STA", "HNN", -3786825600LL * 1000000LL, 10.0, {1, 2, 3}));
  ReadOptions options;
  options.gain_counts_per_mps2 = 1.0;
  const Failure f = failure_of([&] { read_record(path, options); });
  STRCMP_CONTAINS("old.mseed: byte offset 0: record start time outside the years 1900-2199", f.message.c_str());
}

TEST(MiniseedHandMade, ContiguousFilesAreMergedInTimeOrder) {
  // Two halves, the later one first in the file: read as one trace.
  std::vector<std::int32_t> first(300), second(300);
  for (int k = 0; k < 300; ++k) {
    first[static_cast<std::size_t>(k)] = k;
    second[static_cast<std::size_t>(k)] = 300 + k;
  }
  const std::string bytes = pack_counts("STA", "HNE", kTestStartUs + 30 * 1000000LL, 10.0, second) +
                            pack_counts("STA", "HNE", kTestStartUs, 10.0, first);
  ReadOptions options;
  options.gain_counts_per_mps2 = 1.0;
  const Record r = read_record(write("halves.mseed", bytes), options);
  LONGS_EQUAL(600, r.horizontal_mps2.size());
  CHECK(*r.start_time_ns == kTestStartUs * kMicrosecondNs);
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[1] - r.horizontal_mps2[0], 1e-12);
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[300] - r.horizontal_mps2[299], 1e-12);
}

TEST(MiniseedHandMade, GapsAndOverlapsAreRejectedWithTheirTime) {
  const std::vector<std::int32_t> samples(100, 7);
  ReadOptions options;
  options.gain_counts_per_mps2 = 1.0;
  // 100 samples at 10 Hz end at +10 s; the next record starts 2.5 s later.
  const std::string gap = write("gap.mseed", pack_counts("STA", "HNE", kTestStartUs, 10.0, samples) +
                                                 pack_counts("STA", "HNE", kTestStartUs + 12500000LL, 10.0, samples));
  const Failure g = failure_of([&] { read_record(gap, options); });
  STRCMP_CONTAINS("gap.mseed: XX.STA..HNE has a gap of 2.5 s at 2021-01-01T00:00:10.000000Z", g.message.c_str());
  STRCMP_CONTAINS("data resume at 2021-01-01T00:00:12.500000Z", g.message.c_str());
  const std::string overlap =
      write("overlap.mseed", pack_counts("STA", "HNE", kTestStartUs, 10.0, samples) +
                                 pack_counts("STA", "HNE", kTestStartUs + 9000000LL, 10.0, samples));
  const Failure o = failure_of([&] { read_record(overlap, options); });
  STRCMP_CONTAINS("overlap.mseed: XX.STA..HNE has records overlapping by 1 s at 2021-01-01T00:00:09.000000Z",
                  o.message.c_str());
  // Within half a sample of contiguous (a 30 ms clock correction at 10 Hz) is contiguous.
  const std::string jitter =
      write("jitter.mseed", pack_counts("STA", "HNE", kTestStartUs, 10.0, samples) +
                                pack_counts("STA", "HNE", kTestStartUs + 10030000LL, 10.0, samples));
  LONGS_EQUAL(200, read_record(jitter, options).horizontal_mps2.size());
}

TEST(MiniseedHandMade, AChannelCodeAtTwoStationsNeedsTheFullId) {
  const std::vector<std::int32_t> samples(50, 1);
  const std::string path = write("two.mseed", pack_counts("AAA", "HNE", kTestStartUs, 10.0, samples) +
                                                  pack_counts("BBB", "HNE", kTestStartUs, 10.0, samples));
  ReadOptions options;
  options.gain_counts_per_mps2 = 1.0;
  options.channel = "HNE";
  const Failure f = failure_of([&] { read_record(path, options); });
  STRCMP_CONTAINS("channel code 'HNE' matches XX.AAA..HNE, XX.BBB..HNE", f.message.c_str());
  STRCMP_CONTAINS("--channel NET.STA.LOC.CHA", f.message.c_str());
  options.channel = "XX.BBB..HNE";
  STRCMP_EQUAL("XX.BBB..HNE", read_record(path, options).description.c_str());
}

TEST(MiniseedHandMade, GarbageAfterTheRecordsIsRejectedButPaddingIsNot) {
  const std::vector<float> samples{1.0f, 2.0f, 3.0f};
  ReadOptions options;
  options.units = AccelUnit::mps2;
  const std::string packed = pack_float32("HNE", kTestStartUs, 100.0, samples);
  LONGS_EQUAL(3, read_record(write("padded.mseed", packed + std::string(512, '\0')), options).horizontal_mps2.size());
  const Failure f = failure_of([&] { read_record(write("junk.mseed", packed + std::string(600, 'x')), options); });
  STRCMP_CONTAINS("junk.mseed: byte offset 512: not a valid miniSEED data record", f.message.c_str());
}

// --- Fuzzing regressions (tests/fuzz/regressions/record_miniseed, docs/RELIABILITY.md) ---------------------------

// Big-endian sample count of the fixed header (bytes 30-31) of the record at `record_offset`.
void set_sample_count(std::string& bytes, std::size_t record_offset, std::uint16_t count) {
  bytes[record_offset + 30] = static_cast<char>(count >> 8);
  bytes[record_offset + 31] = static_cast<char>(count & 0xFF);
}

// libmseed 2 copies as many uncompressed samples as the header announces, past the end of the record: a float32
// record announcing 3000 samples read 12 kB beyond it (ASan: heap-buffer-overflow in msr_unpack_data). The reader now
// checks the announced samples against the record's data section before unpacking them.
TEST(MiniseedHandMade, MoreUncompressedSamplesThanTheRecordHoldsIsRejected) {
  std::string bytes = pack_float32("HNE", kTestStartUs, 100.0, {1.0f, 2.0f, 3.0f});
  set_sample_count(bytes, 0, 3000);
  ReadOptions options;
  options.units = AccelUnit::mps2;
  const Failure f = failure_of([&] { read_record(write("count.mseed", bytes), options); });
  STRCMP_CONTAINS("count.mseed: byte offset 0: the header announces 3000 samples of 4 bytes", f.message.c_str());
  STRCMP_CONTAINS("but the record holds 456 bytes of data", f.message.c_str());
  STRCMP_CONTAINS("expected an undamaged header", f.message.c_str());
}

// The same over-read through a text (ASCII) record, which carries no waveform: such records are now skipped without
// unpacking them. Input: tests/fuzz/regressions/record_miniseed/ascii_record_sample_count_overread.mseed.
TEST(MiniseedHandMade, ATextRecordIsSkippedWithoutUnpackingIt) {
  const std::vector<float> samples{1.0f, 2.0f, 3.0f};
  std::string text = pack("XX", "TEST", "LOG", kTestStartUs, 0.0, std::vector<char>{'o', 'k'}, 'a', DE_ASCII);
  set_sample_count(text, 0, 12052);
  ReadOptions options;
  options.units = AccelUnit::mps2;
  options.channel = "HNE";
  const Record r = read_record(write("text.mseed", pack_float32("HNE", kTestStartUs, 100.0, samples) + text), options);
  LONGS_EQUAL(samples.size(), r.horizontal_mps2.size());
}
