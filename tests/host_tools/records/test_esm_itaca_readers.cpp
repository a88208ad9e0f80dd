// ESM ASCII and ITACA .cor.acc readers: the real ITACA file from the shared collection (tests/data/records, see
// SOURCES.md) against its own header, and hand-made files, written to a temporary directory, for every format
// variant and rejection path.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "reference_data.hpp"
#include "rockwatch/records/record.hpp"
#include "record_test_support.hpp"
#include "rockwatch/records/record_error.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;
using rockwatch::records::AccelUnit;
using rockwatch::records::looks_like_esm_ascii;
using rockwatch::records::looks_like_itaca_cor_acc;
using rockwatch::records::looks_like_peer_at2;
using rockwatch::records::read_esm_ascii;
using rockwatch::records::read_itaca_cor_acc;
using rockwatch::records::read_record;
using rockwatch::records::ReadOptions;
using rockwatch::records::Record;
using rockwatch::records::RecordError;
using rockwatch::test::failure_of;
using rockwatch::test::Failure;
using rockwatch::test::has_note_with;
using rockwatch::test::data_path;

namespace {

double peak_abs(const std::vector<double>& values) {
  double peak = 0.0;
  for (const double v : values) peak = std::max(peak, std::fabs(v));
  return peak;
}

// --- ESM ---------------------------------------------------------------------------------------------------------

struct HeaderLine {
  std::string key;
  std::string value;
};

// The 64 header keys of an ESM .ACC.ASC file in ESM's order (as in the ESM files among usgs/groundmotion-processing's
// test data), with made-up values describing 4 values in cm/s² at 0.01 s.
std::vector<HeaderLine> esm_header() {
  return {{"EVENT_NAME", "TEST EVENT"},
          {"EVENT_ID", "TEST-20190728_0000001"},
          {"EVENT_DATE_YYYYMMDD", "20190728"},
          {"EVENT_TIME_HHMMSS", "160908"},
          {"EVENT_LATITUDE_DEGREE", "45.0000"},
          {"EVENT_LONGITUDE_DEGREE", "10.0000"},
          {"EVENT_DEPTH_KM", "5.0"},
          {"HYPOCENTER_REFERENCE", "TEST"},
          {"MAGNITUDE_W", ""},
          {"MAGNITUDE_W_REFERENCE", ""},
          {"MAGNITUDE_L", "4.0"},
          {"MAGNITUDE_L_REFERENCE", "TEST"},
          {"FOCAL_MECHANISM", ""},
          {"NETWORK", "XX"},
          {"STATION_CODE", "TST1"},
          {"STATION_NAME", "Test site, Nowhere"},
          {"STATION_LATITUDE_DEGREE", "45.100000"},
          {"STATION_LONGITUDE_DEGREE", "10.100000"},
          {"STATION_ELEVATION_M", "10"},
          {"LOCATION", ""},
          {"SENSOR_DEPTH_M", "0.0"},
          {"VS30_M/S", ""},
          {"SITE_CLASSIFICATION_EC8", ""},
          {"MORPHOLOGIC_CLASSIFICATION", ""},
          {"EPICENTRAL_DISTANCE_KM", "13.6"},
          {"EARTHQUAKE_BACKAZIMUTH_DEGREE", "210.0"},
          {"DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS", "20190728_160919.870"},
          {"DATE_TIME_FIRST_SAMPLE_PRECISION", "milliseconds"},
          {"SAMPLING_INTERVAL_S", "0.010000"},
          {"NDATA", "4"},
          {"DURATION_S", "0.040"},
          {"STREAM", "HNE"},
          {"UNITS", "cm/s^2"},
          {"INSTRUMENT", "sensor = TEST_ACCELEROMETER [Unknown] | digitizer = Unknown [Unknown]"},
          {"INSTRUMENT_ANALOG/DIGITAL", "D"},
          {"INSTRUMENTAL_FREQUENCY_HZ", ""},
          {"INSTRUMENTAL_DAMPING", ""},
          {"FULL_SCALE_G", ""},
          {"N_BIT_DIGITAL_CONVERTER", ""},
          {"PGA_CM/S^2", "100.000000"},
          {"TIME_PGA_S", "0.030000"},
          {"BASELINE_CORRECTION", "BASELINE REMOVED"},
          {"FILTER_TYPE", "BUTTERWORTH"},
          {"FILTER_ORDER", "2"},
          {"LOW_CUT_FREQUENCY_HZ", "0.100"},
          {"HIGH_CUT_FREQUENCY_HZ", "30.000"},
          {"LATE/NORMAL_TRIGGERED", "NT"},
          {"DATABASE_VERSION", "DYNA 1.0"},
          {"HEADER_FORMAT", "DYNA 1.2"},
          {"DATA_TYPE", "ACCELERATION"},
          {"PROCESSING", "manual"},
          {"DATA_TIMESTAMP_YYYYMMDD_HHMMSS", "20190730_115604.782"},
          {"DATA_LICENSE", ""},
          {"DATA_CITATION", ""},
          {"DATA_CREATOR", ""},
          {"ORIGINAL_DATA_MEDIATOR_CITATION", ""},
          {"ORIGINAL_DATA_MEDIATOR", ""},
          {"ORIGINAL_DATA_CREATOR_CITATION", ""},
          {"ORIGINAL_DATA_CREATOR", ""},
          {"USER1", "hand-made test file: a value with a colon: ok"},
          {"USER2", ""},
          {"USER3", ""},
          {"USER4", ""},
          {"USER5", ""}};
}

constexpr int kEsmHeaderLines = 64;
const char* const kEsmValues = "0.000000\n1.500000\n-2.250000\n100.000000\n";

std::vector<HeaderLine> with_value(std::vector<HeaderLine> header, const std::string& key, const std::string& value) {
  for (HeaderLine& line : header) {
    if (line.key == key) line.value = value;
  }
  return header;
}

std::vector<HeaderLine> without(std::vector<HeaderLine> header, const std::string& key) {
  header.erase(std::remove_if(header.begin(), header.end(), [&key](const HeaderLine& l) { return l.key == key; }),
               header.end());
  return header;
}

std::string esm_text(const std::vector<HeaderLine>& header, const std::string& values = kEsmValues) {
  std::string text;
  for (const HeaderLine& line : header) text += line.key + ": " + line.value + "\n";
  return text + values;
}

// --- ITACA -------------------------------------------------------------------------------------------------------

// One 14-character field as ITACA writes it: "-1.3724600E-07", " 5.0693293E+00".
std::string itaca_field(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%14.7E", value);
  return buffer;
}

std::string itaca_rows(const std::vector<double>& values, std::size_t per_line = 5) {
  std::string text;
  for (std::size_t i = 0; i < values.size(); ++i) {
    text += itaca_field(values[i]);
    if ((i + 1) % per_line == 0 || i + 1 == values.size()) text += "\n";
  }
  return text;
}

std::string itaca_header(const std::string& npts = "7", const std::string& dt = "0.010",
                         const std::string& series = "Acceleration time series in m/s/s") {
  return "Event Date & Time             : 2009-04-06 01:32:39\n"
         "Station Code / Name           : 9999 / Test Station, Italy\n"
         "Network                       : TEST\n"
         "Orientation                   : WE\n"
         "Processing Info               : none\n"
         "Filter Cut-off Frequency (Hz) : 0.100 - 50.000\n"
         "Time Increment (s)            : " +
         dt +
         "\n"
         "Number of Data                : " +
         npts +
         "\n"
         "PGA (m/s/s)                   : 3.0000000E+00\n" +
         series + "\n";
}

constexpr int kItacaHeaderLines = 10;
const std::vector<double> kItacaValues{1.0, -2.0, 3.0, -1.5, 0.25, -0.1, 0.05};

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// The real ITACA file

TEST_GROUP(ItacaRealRecord){};

TEST(ItacaRealRecord, LAquilaAqgNorthSouth) {
  const std::string path = data_path("records/16833_H1.cor.acc");
  CHECK_TRUE(looks_like_itaca_cor_acc(path));
  CHECK_FALSE(looks_like_peer_at2(path));
  CHECK_FALSE(looks_like_esm_ascii(path));
  const Record r = read_record(path);
  STRCMP_EQUAL("itaca-cor-acc", r.format.c_str());
  STRCMP_CONTAINS("L Aquila - V. Aterno - Colle Grilli", r.description.c_str());
  STRCMP_CONTAINS("2009-04-06 01:32:39", r.description.c_str());
  STRCMP_CONTAINS("NS", r.description.c_str());
  LONGS_EQUAL(59220, r.horizontal_mps2.size());
  CHECK(r.vertical_mps2.empty());
  DOUBLES_EQUAL(0.005, r.dt_s, 1e-15);
  DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
  CHECK(r.units_in_file == AccelUnit::mps2);
  CHECK_FALSE(r.start_time_ns);
  CHECK(r.notes.empty());
  // Header: "PGA (m/s/s) : 5.0693293E+00", 8 significant digits.
  DOUBLES_EQUAL(5.0693293, peak_abs(r.horizontal_mps2), 5e-8);
  // First and last fields as printed (the first line runs its fields together).
  DOUBLES_EQUAL(-1.3724600e-07, r.horizontal_mps2.front(), 1e-21);
  DOUBLES_EQUAL(-2.6835700e-07, r.horizontal_mps2[1], 1e-21);
  DOUBLES_EQUAL(-1.4384400e-06, r.horizontal_mps2.back(), 1e-20);
}

TEST(ItacaRealRecord, ComponentOrGainOptionsAreRejected) {
  const std::string path = data_path("records/16833_H1.cor.acc");
  ReadOptions channel;
  channel.channel = "X";
  const Failure f = failure_of([&] { read_record(path, channel); });
  STRCMP_CONTAINS("16833_H1.cor.acc: the file holds one component", f.message.c_str());
  STRCMP_CONTAINS("--channel/--component 'X' does not apply", f.message.c_str());
  ReadOptions gain;
  gain.gain_counts_per_mps2 = 1000.0;
  STRCMP_CONTAINS("--gain applies to miniSEED integer counts only",
                  failure_of([&] { read_record(path, gain); }).message.c_str());
}

// ---------------------------------------------------------------------------------------------------------------
// Hand-made files

TEST_GROUP_BASE(EsmItacaHandMade, rockwatch::test::HandMadeFileTest){};

// --- ESM: accepted --------------------------------------------------------------------------------------------

TEST(EsmItacaHandMade, EsmGoodFileInCmps2) {
  // Named like an AT2 download to show that the content decides.
  const std::string path = write("XX.TST1..HNE.D.20190728.160908.C.ACC.ASC.txt", esm_text(esm_header()));
  CHECK_TRUE(looks_like_esm_ascii(path));
  CHECK_FALSE(looks_like_itaca_cor_acc(path));
  const Record r = read_record(path);
  STRCMP_EQUAL("esm", r.format.c_str());
  STRCMP_EQUAL("TEST EVENT, XX.TST1, HNE", r.description.c_str());
  CHECK(r.units_in_file == AccelUnit::cmps2);
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
  LONGS_EQUAL(4, r.horizontal_mps2.size());
  CHECK(r.vertical_mps2.empty());
  DOUBLES_EQUAL(0.0, r.horizontal_mps2[0], 0.0);
  DOUBLES_EQUAL(0.015, r.horizontal_mps2[1], 1e-17);
  DOUBLES_EQUAL(-0.0225, r.horizontal_mps2[2], 1e-17);
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[3], 1e-15);
  CHECK(r.notes.empty());
  // 2019-07-28 16:09:19.870 UTC = 1564330159.870 s after the epoch.
  CHECK_TRUE(r.start_time_ns.has_value());
  CHECK(*r.start_time_ns == 1564330159870000000LL);
}

TEST(EsmItacaHandMade, EsmUnitsSpellingsAndCrlf) {
  const Record m = read_esm_ascii(write("m.ASC", esm_text(with_value(esm_header(), "UNITS", "m/s^2"))));
  CHECK(m.units_in_file == AccelUnit::mps2);
  DOUBLES_EQUAL(100.0, m.horizontal_mps2[3], 0.0);
  ReadOptions g_option;
  g_option.g_mps2 = 9.80665;
  const Record g = read_esm_ascii(write("g.ASC", esm_text(with_value(esm_header(), "UNITS", "g"))), g_option);
  CHECK(g.units_in_file == AccelUnit::g);
  DOUBLES_EQUAL(1.5 * 9.80665, g.horizontal_mps2[1], 1e-14);
  std::string crlf;
  for (const char c : esm_text(esm_header())) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  const Record r = read_record(write("crlf.ASC", crlf));
  STRCMP_EQUAL("esm", r.format.c_str());
  LONGS_EQUAL(4, r.horizontal_mps2.size());
}

TEST(EsmItacaHandMade, EsmUnitsOptionOverridesWithANote) {
  ReadOptions options;
  options.units = AccelUnit::mps2;
  const Record r = read_record(write("override.ASC", esm_text(esm_header())), options);
  CHECK(r.units_in_file == AccelUnit::mps2);
  DOUBLES_EQUAL(1.5, r.horizontal_mps2[1], 0.0);
  CHECK(has_note_with(r, {"override.ASC", "mps2", "cm/s^2"}));
  // --units supplies the units a header does not understand.
  const Record odd =
      read_record(write("odd.ASC", esm_text(with_value(esm_header(), "UNITS", "furlongs/fortnight^2"))), options);
  DOUBLES_EQUAL(1.5, odd.horizontal_mps2[1], 0.0);
}

TEST(EsmItacaHandMade, EsmDtOptionIsIgnoredWithANote) {
  ReadOptions options;
  options.dt_s = 0.02;
  const Record r = read_record(write("dt.ASC", esm_text(esm_header())), options);
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  CHECK(has_note_with(r, {"--dt 0.02 s ignored", "SAMPLING_INTERVAL_S"}));
}

TEST(EsmItacaHandMade, EsmUnreadableStartTimeIsANoteNotAnError) {
  const Record r = read_record(
      write("time.ASC", esm_text(with_value(esm_header(), "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS", "soon"))));
  CHECK_FALSE(r.start_time_ns);
  CHECK(has_note_with(r, {"time.ASC:27", "'soon'", "not understood"}));
  for (const char* odd : {"99990728_160919.870", "20191328_160919", "20190728_250919", "20190728-160919"}) {
    const Record o = read_record(
        write("odd.ASC", esm_text(with_value(esm_header(), "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS", odd))));
    CHECK_FALSE(o.start_time_ns);
    CHECK(has_note_with(o, {"not understood"}));
  }
}

// --- ESM: rejected --------------------------------------------------------------------------------------------

TEST(EsmItacaHandMade, EsmMissingNdata) {
  // The header ends on line 63 (one key fewer); a missing key is reported there.
  expect_rejected("nondata.ASC", esm_text(without(esm_header(), "NDATA")), kEsmHeaderLines - 1,
                  {"no NDATA", "expected a line 'NDATA: "});
}

TEST(EsmItacaHandMade, EsmBadNdata) {
  for (const char* bad : {"0", "-4", "4.5", "four", ""}) {
    expect_rejected("badndata.ASC", esm_text(with_value(esm_header(), "NDATA", bad)), 30,
                    {"NDATA", "expected a positive whole number of values"});
  }
}

TEST(EsmItacaHandMade, EsmMissingOrInvalidSamplingInterval) {
  expect_rejected("nodt.ASC", esm_text(without(esm_header(), "SAMPLING_INTERVAL_S")), kEsmHeaderLines - 1,
                  {"no SAMPLING_INTERVAL_S", "expected a line 'SAMPLING_INTERVAL_S: "});
  for (const char* bad : {"0.000000", "-0.01", "nan", "0.01s", ""}) {
    expect_rejected("baddt.ASC", esm_text(with_value(esm_header(), "SAMPLING_INTERVAL_S", bad)), 29,
                    {"SAMPLING_INTERVAL_S", "expected a positive sample interval in seconds"});
  }
}

TEST(EsmItacaHandMade, EsmUnknownOrMissingUnits) {
  expect_rejected("furlongs.ASC", esm_text(with_value(esm_header(), "UNITS", "furlongs/s^2")), 33,
                  {"UNITS: 'furlongs/s^2'", "expected acceleration units", "--units"});
  // Velocity units in an acceleration header are not acceleration units either.
  expect_rejected("cms.ASC", esm_text(with_value(esm_header(), "UNITS", "cm/s")), 33, {"'cm/s'", "--units"});
  expect_rejected("nounits.ASC", esm_text(without(esm_header(), "UNITS")), kEsmHeaderLines - 1,
                  {"no UNITS", "--units"});
}

TEST(EsmItacaHandMade, EsmVelocityOrDisplacementIsRejected) {
  expect_rejected("vel.ASC", esm_text(with_value(esm_header(), "DATA_TYPE", "VELOCITY")), 50,
                  {"DATA_TYPE: 'VELOCITY'", "expected ACCELERATION"});
  expect_rejected("dis.ASC", esm_text(with_value(esm_header(), "DATA_TYPE", "DISPLACEMENT")), 50,
                  {"'DISPLACEMENT'", "expected ACCELERATION"});
}

TEST(EsmItacaHandMade, EsmFewerOrMoreValuesThanNdata) {
  expect_rejected("few.ASC", esm_text(esm_header(), "0.000000\n1.500000\n-2.250000\n"), kEsmHeaderLines + 3,
                  {"ends after 3 of NDATA=4 values", "truncated"});
  expect_rejected("none.ASC", esm_text(esm_header(), ""), kEsmHeaderLines, {"ends after 0 of NDATA=4 values"});
  expect_rejected("many.ASC", esm_text(esm_header(), std::string(kEsmValues) + "7.000000\n"), kEsmHeaderLines + 5,
                  {"more values than NDATA=4", "the last on line 68"});
}

TEST(EsmItacaHandMade, EsmNonNumericValueNamesItsLine) {
  expect_rejected("word.ASC", esm_text(esm_header(), "0.000000\n1.500000\noops\n100.000000\n"), kEsmHeaderLines + 3,
                  {"'oops'", "expected a decimal number"});
  expect_rejected("nan.ASC", esm_text(esm_header(), "0.000000\nnan\n-2.250000\n100.000000\n"), kEsmHeaderLines + 2,
                  {"'nan'", "expected a finite number"});
  expect_rejected("comma.ASC", esm_text(esm_header(), "0.000000\n1,500000\n-2.250000\n100.000000\n"),
                  kEsmHeaderLines + 2, {"'1,500000'"});
  expect_rejected("two.ASC", esm_text(esm_header(), "0.000000 1.5\n-2.250000\n100.000000\n"), kEsmHeaderLines + 1,
                  {"found 2 values", "expected one value per line"});
}

TEST(EsmItacaHandMade, EsmDuplicateKeyAndOptions) {
  std::vector<HeaderLine> twice = esm_header();
  twice.insert(twice.begin() + 40, HeaderLine{"NDATA", "5"});
  expect_rejected("twice.ASC", esm_text(twice), 41, {"NDATA appears twice", "also on line 30"});
  ReadOptions channel;
  channel.channel = "HNE";
  expect_rejected("channel.ASC", esm_text(esm_header()), 0,
                  {"holds one component (an ESM ASCII record)", "'HNE' does not apply"}, channel);
  ReadOptions gain;
  gain.gain_counts_per_mps2 = 0.0;
  expect_rejected("gain0.ASC", esm_text(esm_header()), 0, {"--gain 0", "expected a positive number"}, gain);
}

// --- ITACA: accepted ------------------------------------------------------------------------------------------

TEST(EsmItacaHandMade, ItacaCorrectSpellingAndShortLastLine) {
  const std::string path = write("small.cor.acc", itaca_header() + itaca_rows(kItacaValues));
  CHECK_TRUE(looks_like_itaca_cor_acc(path));
  const Record r = read_record(path);
  STRCMP_EQUAL("itaca-cor-acc", r.format.c_str());
  STRCMP_EQUAL("2009-04-06 01:32:39, 9999 / Test Station, Italy, WE", r.description.c_str());
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  LONGS_EQUAL(kItacaValues.size(), r.horizontal_mps2.size());
  for (std::size_t i = 0; i < kItacaValues.size(); ++i) DOUBLES_EQUAL(kItacaValues[i], r.horizontal_mps2[i], 1e-15);
  CHECK(r.notes.empty());
}

TEST(EsmItacaHandMade, ItacaMisspeltSeriesLineCrlfAndCmUnits) {
  std::string text = itaca_header("7", "0.010", "Accelaration time series in cm/s/s") + itaca_rows(kItacaValues);
  std::string crlf;
  for (const char c : text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  const Record r = read_record(write("crlf.cor.acc", crlf));
  CHECK(r.units_in_file == AccelUnit::cmps2);
  DOUBLES_EQUAL(-0.02, r.horizontal_mps2[1], 1e-17);
  LONGS_EQUAL(kItacaValues.size(), r.horizontal_mps2.size());
}

TEST(EsmItacaHandMade, ItacaHeaderPgaDisagreeingWithTheValuesIsNoted) {
  const Record r =
      read_record(write("pga.cor.acc", itaca_header() + itaca_rows({1.0, -2.0, 2.5, -1.5, 0.25, -0.1, 0.05})));
  CHECK(has_note_with(r, {"pga.cor.acc:9", "header PGA 3", "peak at 2.5"}));
}

TEST(EsmItacaHandMade, ItacaUnitsOptionOverridesWithANote) {
  ReadOptions options;
  options.units = AccelUnit::g;
  const Record r = read_record(write("g.cor.acc", itaca_header() + itaca_rows(kItacaValues)), options);
  CHECK(r.units_in_file == AccelUnit::g);
  DOUBLES_EQUAL(9.81, r.horizontal_mps2[0], 1e-15);
  CHECK(has_note_with(r, {"g.cor.acc", "units taken as g", "'m/s/s'"}));
}

// --- ITACA: rejected ------------------------------------------------------------------------------------------

TEST(EsmItacaHandMade, ItacaFewerOrMoreValuesThanNumberOfData) {
  const std::vector<double> six(kItacaValues.begin(), kItacaValues.end() - 1);
  expect_rejected("few.cor.acc", itaca_header() + itaca_rows(six), kItacaHeaderLines + 2,
                  {"ends after 6 of 7 values", "truncated"});
  std::vector<double> twelve = kItacaValues;
  twelve.insert(twelve.end(), {1.0, 2.0, 3.0, 4.0, 5.0});
  expect_rejected("many.cor.acc", itaca_header() + itaca_rows(twelve), kItacaHeaderLines + 2,
                  {"more values than 'Number of Data : 7'"});
  expect_rejected("headonly.cor.acc", itaca_header(), kItacaHeaderLines, {"ends after 0 of 7 values"});
}

TEST(EsmItacaHandMade, ItacaBadHeaderValues) {
  expect_rejected("npts0.cor.acc", itaca_header("0") + itaca_rows(kItacaValues), 8,
                  {"Number of Data", "expected a positive whole number"});
  expect_rejected("nptsword.cor.acc", itaca_header("seven") + itaca_rows(kItacaValues), 8, {"'seven'"});
  expect_rejected("dt0.cor.acc", itaca_header("7", "0.000") + itaca_rows(kItacaValues), 7,
                  {"Time Increment (s)", "expected a positive sample interval"});
  expect_rejected("dtneg.cor.acc", itaca_header("7", "-0.01") + itaca_rows(kItacaValues), 7,
                  {"expected a positive sample interval"});
  expect_rejected("units.cor.acc",
                  itaca_header("7", "0.01", "Acceleration time series in furlongs") + itaca_rows(kItacaValues), 10,
                  {"unknown units 'furlongs'", "--units"});
}

TEST(EsmItacaHandMade, ItacaMissingHeaderLines) {
  std::string no_npts = itaca_header();
  no_npts.erase(no_npts.find("Number of Data"),
                no_npts.find('\n', no_npts.find("Number of Data")) - no_npts.find("Number of Data") + 1);
  expect_rejected("nonpts.cor.acc", no_npts + itaca_rows(kItacaValues), 9, {"no 'Number of Data : ...'"});
  std::string no_series = itaca_header();
  no_series.erase(no_series.find("Acceleration"));
  expect_rejected("noseries.cor.acc", no_series + itaca_rows(kItacaValues), 10,
                  {"values before the line 'Acceleration time series in m/s/s'"});
  expect_rejected("velocity.cor.acc",
                  itaca_header("7", "0.01", "Velocity time series in m/s") + itaca_rows(kItacaValues), 10,
                  {"expected an acceleration time series"});
}

TEST(EsmItacaHandMade, ItacaFieldsAreSplitByColumn) {
  // Blank-separated values are not 14-character fields.
  expect_rejected("blanks.cor.acc", itaca_header() + "1.0 -2.0 3.0 -1.5 0.25\n-0.1 0.05\n", 11,
                  {"line of 22 characters", "fixed-width fields of 14 characters"});
  // A field that is not a number names its columns.
  expect_rejected("word.cor.acc", itaca_header() + itaca_field(1.0) + "  not a number" + itaca_field(3.0) + "\n", 11,
                  {"columns 15-28", "'not a number'"});
  expect_rejected("blankfield.cor.acc",
                  itaca_header() + itaca_field(1.0) + std::string(14, ' ') + itaca_field(3.0) + "\n", 11,
                  {"columns 15-28 are blank"});
  // A line cut in the middle of a field.
  expect_rejected("cut.cor.acc", itaca_header() + itaca_rows(kItacaValues).substr(0, 80), 12, {"line of 9 characters"});
  // A short line in the middle of the values.
  expect_rejected("shortline.cor.acc",
                  itaca_header("10") + itaca_rows({1.0, 2.0, 3.0, 4.0, 5.0}) + itaca_rows({6.0, 7.0}) +
                      itaca_rows({8.0, 9.0, 10.0}),
                  12, {"only 2 fields where the lines before have 5", "expected a short line only at the end"});
  expect_rejected("longline.cor.acc", itaca_header() + itaca_rows({1.0, 2.0}) + itaca_rows({3.0, 4.0, 5.0}, 3), 12,
                  {"3 fields: expected at most 2 per line"});
  expect_rejected("naninfield.cor.acc", itaca_header() + itaca_field(1.0) + "           NaN\n", 11,
                  {"columns 15-28", "expected a finite number"});
}

// --- Fuzzing regressions (tests/fuzz/regressions, docs/RELIABILITY.md) ----------------------------------------

// The readers reserved the header's value count before reading the values: a few bytes claiming 99 999 999 999 values
// asked for 800 GB (std::bad_alloc in a release build, an allocator abort under ASan). Now such a file is what it is,
// a truncated one. Inputs: tests/fuzz/regressions/record_esm/ndata_huge_reserve.ASC,
// tests/fuzz/regressions/record_itaca/npts_huge_reserve.cor.acc.
TEST(EsmItacaHandMade, EsmHugeNdataIsATruncatedFileNotAnAllocation) {
  expect_rejected("hugendata.ASC", esm_text(with_value(esm_header(), "NDATA", "99999999999")), kEsmHeaderLines + 4,
                  {"the file ends after 4 of NDATA=99999999999 values", "a truncated file?"});
}

TEST(EsmItacaHandMade, ItacaHugeNumberOfDataIsATruncatedFileNotAnAllocation) {
  expect_rejected("hugenpts.cor.acc", itaca_header("99999999999") + itaca_rows(kItacaValues), kItacaHeaderLines + 2,
                  {"the file ends after 7 of 99999999999 values", "a truncated file?"});
}
