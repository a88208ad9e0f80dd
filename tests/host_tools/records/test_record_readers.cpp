// Record readers: real PEER AT2 files from the shared collection (tests/data/records, see SOURCES.md) against the
// values in its manifest, and hand-made files for every format variant and every rejection path.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "record_test_support.hpp"
#include "rockwatch/records/record_error.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;
using rockwatch::records::accel_unit_name;
using rockwatch::records::accel_unit_to_mps2;
using rockwatch::records::AccelUnit;
using rockwatch::records::looks_like_peer_at2;
using rockwatch::records::parse_accel_unit;
using rockwatch::records::read_peer_at2;
using rockwatch::records::read_plain_text;
using rockwatch::records::read_record;
using rockwatch::records::ReadOptions;
using rockwatch::records::Record;
using rockwatch::records::RecordError;
using rockwatch::test::failure_of;
using rockwatch::test::Failure;
using rockwatch::test::has_note_with;

namespace {

const std::string kRecordsDir = std::string(ROCKWATCH_TEST_DATA_DIR) + "/records/";

std::string data_file(const std::string& name) { return kRecordsDir + name; }

double pga_g(const Record& record, double g_mps2) {
  double peak_mps2 = 0.0;
  for (const double a : record.horizontal_mps2) peak_mps2 = std::max(peak_mps2, std::fabs(a));
  return peak_mps2 / g_mps2;
}

ReadOptions with_units(AccelUnit unit) {
  ReadOptions options;
  options.units = unit;
  return options;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Units

TEST_GROUP(Units){};

TEST(Units, ParsesEverySpelling) {
  CHECK(parse_accel_unit("g") == AccelUnit::g);
  CHECK(parse_accel_unit("G") == AccelUnit::g);
  CHECK(parse_accel_unit("mps2") == AccelUnit::mps2);
  CHECK(parse_accel_unit("m/s2") == AccelUnit::mps2);
  CHECK(parse_accel_unit("m/s^2") == AccelUnit::mps2);
  CHECK(parse_accel_unit("m/s\xC2\xB2") == AccelUnit::mps2);
  CHECK(parse_accel_unit("ms2") == AccelUnit::mps2);
  CHECK(parse_accel_unit("cmps2") == AccelUnit::cmps2);
  CHECK(parse_accel_unit("cm/s2") == AccelUnit::cmps2);
  CHECK(parse_accel_unit("cm/s^2") == AccelUnit::cmps2);
  CHECK(parse_accel_unit("gal") == AccelUnit::cmps2);
  CHECK(parse_accel_unit("Gal") == AccelUnit::cmps2);
  CHECK(parse_accel_unit("mmps2") == AccelUnit::mmps2);
  CHECK(parse_accel_unit("mm/s2") == AccelUnit::mmps2);
  CHECK(parse_accel_unit("mm/s^2") == AccelUnit::mmps2);
  CHECK_FALSE(parse_accel_unit(""));
  CHECK_FALSE(parse_accel_unit("s"));
  CHECK_FALSE(parse_accel_unit("m/s"));
  CHECK_FALSE(parse_accel_unit("furlongs"));
}

TEST(Units, NamesRoundTrip) {
  for (const AccelUnit unit : {AccelUnit::g, AccelUnit::mps2, AccelUnit::cmps2, AccelUnit::mmps2}) {
    CHECK(parse_accel_unit(accel_unit_name(unit)) == unit);
  }
  STRCMP_EQUAL("g", std::string(accel_unit_name(AccelUnit::g)).c_str());
  STRCMP_EQUAL("mps2", std::string(accel_unit_name(AccelUnit::mps2)).c_str());
  STRCMP_EQUAL("cmps2", std::string(accel_unit_name(AccelUnit::cmps2)).c_str());
  STRCMP_EQUAL("mmps2", std::string(accel_unit_name(AccelUnit::mmps2)).c_str());
}

TEST(Units, FactorsToMps2) {
  DOUBLES_EQUAL(9.81, accel_unit_to_mps2(AccelUnit::g, 9.81), 0.0);
  DOUBLES_EQUAL(9.80665, accel_unit_to_mps2(AccelUnit::g, 9.80665), 0.0);
  DOUBLES_EQUAL(1.0, accel_unit_to_mps2(AccelUnit::mps2, 9.81), 0.0);
  DOUBLES_EQUAL(0.01, accel_unit_to_mps2(AccelUnit::cmps2, 9.81), 0.0);
  DOUBLES_EQUAL(0.001, accel_unit_to_mps2(AccelUnit::mmps2, 9.81), 0.0);
}

TEST(Units, ErrorTextNamesFileAndLine) {
  STRCMP_EQUAL("a/b.txt:7: expected x", RecordError("a/b.txt", 7, "expected x").what());
  STRCMP_EQUAL("a/b.txt: cannot open", RecordError("a/b.txt", 0, "cannot open").what());
  const RecordError error("f.AT2", 4, "m");
  STRCMP_EQUAL("f.AT2", error.path().c_str());
  LONGS_EQUAL(4, error.line());
}

// ---------------------------------------------------------------------------------------------------------------
// Real PEER files (values from the shared collection's MANIFEST; PGA = max |a| over the file, in g)

TEST_GROUP(RealRecords){};

TEST(RealRecords, ElCentro180) {
  const ReadOptions options;
  const Record r = read_record(data_file("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"), options);
  STRCMP_EQUAL("peer-at2", r.format.c_str());
  STRCMP_CONTAINS("El Centro Array #9", r.description.c_str());
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
  LONGS_EQUAL(5372, r.horizontal_mps2.size());
  CHECK(r.vertical_mps2.empty());
  CHECK(r.units_in_file == AccelUnit::g);
  CHECK(r.notes.empty());
  DOUBLES_EQUAL(0.2808, pga_g(r, options.g_mps2), 5e-5);
  // First value as printed, .9984852E-03 g.
  DOUBLES_EQUAL(0.9984852e-3 * 9.81, r.horizontal_mps2.front(), 1e-15);
}

TEST(RealRecords, ElCentro270) {
  const ReadOptions options;
  const Record r = read_peer_at2(data_file("RSN6_IMPVALL.I_I-ELC270-hor2.AT2"), options);
  LONGS_EQUAL(5346, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.2107, pga_g(r, options.g_mps2), 5e-5);
}

TEST(RealRecords, ElCentroVertical) {
  const ReadOptions options;
  const Record r = read_record(data_file("RSN6_IMPVALL.I_I-ELC-UP.AT2"), options);
  LONGS_EQUAL(5378, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.1781, pga_g(r, options.g_mps2), 5e-5);
}

TEST(RealRecords, ImperialValley1979WithCrlfLines) {
  ReadOptions options;
  options.g_mps2 = 9.80665;  // the manifest's g; PGA in g must not depend on it
  const Record r = read_record(data_file("RSN175_IMPVALL.H_H-E12140.AT2"), options);
  DOUBLES_EQUAL(0.005, r.dt_s, 1e-15);
  LONGS_EQUAL(7814, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.1449, pga_g(r, options.g_mps2), 5e-5);
  CHECK(r.notes.empty());
}

TEST(RealRecords, Northridge960ReadsNptsAndNotesTheExtraValue) {
  const ReadOptions options;
  const Record r = read_record(data_file("RSN960_NORTHR_LOS270.AT2"), options);
  LONGS_EQUAL(1999, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  CHECK(has_note_with(r, {"RSN960_NORTHR_LOS270.AT2", "1999", "2000"}));
  DOUBLES_EQUAL(0.4716, pga_g(r, options.g_mps2), 5e-5);
}

TEST(RealRecords, BevagnaSpacedHeaderVariant) {
  const ReadOptions options;
  const Record r = read_record(data_file("RSN4346_UBMARCHE.P_A-BEV000.AT2"), options);
  DOUBLES_EQUAL(0.005, r.dt_s, 1e-15);
  LONGS_EQUAL(10102, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.0785, pga_g(r, options.g_mps2), 5e-5);
  CHECK(r.notes.empty());
}

TEST(RealRecords, DetectsAt2ByContent) {
  CHECK_TRUE(looks_like_peer_at2(data_file("RSN6_IMPVALL.I_I-ELC180-hor1.AT2")));
  CHECK_TRUE(looks_like_peer_at2(data_file("RSN4346_UBMARCHE.P_A-BEV000.AT2")));
  CHECK_TRUE(looks_like_peer_at2(data_file("RSN960_NORTHR_LOS270.AT2")));
  CHECK_FALSE(looks_like_peer_at2(data_file("NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt")));
  CHECK_FALSE(looks_like_peer_at2(data_file("no-such-file.AT2")));
}

TEST(RealRecords, UnitsOptionOverridesAt2Header) {
  const Record in_g = read_record(data_file("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"));
  const Record in_cm = read_record(data_file("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"), with_units(AccelUnit::cmps2));
  CHECK(in_cm.units_in_file == AccelUnit::cmps2);
  LONGS_EQUAL(in_g.horizontal_mps2.size(), in_cm.horizontal_mps2.size());
  DOUBLES_EQUAL(in_g.horizontal_mps2[100] / 9.81 * 0.01, in_cm.horizontal_mps2[100], 1e-15);
  CHECK(has_note_with(in_cm, {"cmps2"}));
}

TEST(RealRecords, KnmiFourColumnFileIsRejectedNamingTheColumnCount) {
  const std::string path = data_file("NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt");
  for (const ReadOptions& options : {ReadOptions{}, with_units(AccelUnit::mps2)}) {
    const Failure f = failure_of([&] { read_record(path, options); });
    STRCMP_CONTAINS("NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt:7:", f.message.c_str());
    STRCMP_CONTAINS("found 4 columns", f.message.c_str());
    STRCMP_CONTAINS("accepted are 1 column", f.message.c_str());
    STRCMP_CONTAINS("3 columns (time, horizontal, vertical", f.message.c_str());
    LONGS_EQUAL(7, f.line);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Hand-made files

TEST_GROUP_BASE(HandMade, rockwatch::test::HandMadeFileTest){};

const char* const kAt2Head =
    "PEER NGA STRONG MOTION DATABASE RECORD\n"
    "Test Event, 1/2/2000, Test Station, 090\n"
    "ACCELERATION TIME SERIES IN UNITS OF G\n";

// --- plain text: accepted shapes -------------------------------------------------------------------------------

TEST(HandMade, OneColumnNeedsDtAndUsesG) {
  ReadOptions options = with_units(AccelUnit::g);
  options.dt_s = 0.02;
  const Record r = read_record(write("one.txt", "0.1\n-0.2\n0.05\n"), options);
  STRCMP_EQUAL("plain", r.format.c_str());
  LONGS_EQUAL(3, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.1 * 9.81, r.horizontal_mps2[0], 1e-15);
  DOUBLES_EQUAL(-0.2 * 9.81, r.horizontal_mps2[1], 1e-15);
  DOUBLES_EQUAL(0.02, r.dt_s, 0.0);
  DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
  CHECK(r.vertical_mps2.empty());
}

TEST(HandMade, OneColumnWithoutDtIsRejected) {
  expect_rejected("one_nodt.txt", "# units: g\n0.1\n0.2\n", 2, {"--dt", "expected the sample interval"});
}

TEST(HandMade, TwoColumnCsvWithHeaderUnitsInG) {
  const Record r = read_record(write("two.csv", "time_s,accel_g\n0.00,0.10\n0.01,-0.20\n0.02,0.30\n"));
  CHECK(r.units_in_file == AccelUnit::g);
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-12);
  DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
  LONGS_EQUAL(3, r.horizontal_mps2.size());
  DOUBLES_EQUAL(0.30 * 9.81, r.horizontal_mps2[2], 1e-15);
  CHECK(r.notes.empty());
}

TEST(HandMade, TwoColumnsStartingAtAnyTimeWithUnitsComment) {
  const Record r = read_record(write("t0.txt", "# units: cmps2\n12.5  100\n12.6  -50\n12.7  25\n12.8  0\n"));
  CHECK(r.units_in_file == AccelUnit::cmps2);
  DOUBLES_EQUAL(12.5, r.t0_s, 0.0);
  DOUBLES_EQUAL(0.1, r.dt_s, 1e-12);
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[0], 1e-15);
  DOUBLES_EQUAL(-0.5, r.horizontal_mps2[1], 1e-15);
}

TEST(HandMade, ThreeColumnsWithBracketedUnitsInHeader) {
  const Record r = read_record(write("three.txt", "t [s]   ah [m/s2]   av [m/s2]\n0 1.5 -0.5\n0.005 2.5 0.25\n"));
  CHECK(r.units_in_file == AccelUnit::mps2);
  DOUBLES_EQUAL(0.005, r.dt_s, 1e-15);
  LONGS_EQUAL(2, r.horizontal_mps2.size());
  LONGS_EQUAL(2, r.vertical_mps2.size());
  DOUBLES_EQUAL(2.5, r.horizontal_mps2[1], 0.0);
  DOUBLES_EQUAL(-0.5, r.vertical_mps2[0], 0.0);
  DOUBLES_EQUAL(0.25, r.vertical_mps2[1], 0.0);
}

TEST(HandMade, CommentsAnywhereAndMmps2) {
  const Record r = read_record(write("comments.txt",
                                     "# a hand-made record\n"
                                     "# Units = mm/s^2\n"
                                     "\n"
                                     "0.0  1000  # first sample\n"
                                     "# a comment between rows\n"
                                     "0.5  -2000\n"
                                     "   \n"
                                     "1.0  500 # last\n"));
  CHECK(r.units_in_file == AccelUnit::mmps2);
  LONGS_EQUAL(3, r.horizontal_mps2.size());
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[0], 1e-15);
  DOUBLES_EQUAL(-2.0, r.horizontal_mps2[1], 1e-15);
  DOUBLES_EQUAL(0.5, r.horizontal_mps2[2], 1e-15);
  DOUBLES_EQUAL(0.5, r.dt_s, 0.0);
}

TEST(HandMade, HeaderSuffixSpellings) {
  const Record cm = read_record(write("cm.csv", "time_s, acc_cmps2\n0, 981\n0.01, 0\n"));
  CHECK(cm.units_in_file == AccelUnit::cmps2);
  DOUBLES_EQUAL(9.81, cm.horizontal_mps2[0], 1e-12);
  const Record ms2 = read_record(write("ms2.csv", "time_s;acc_ms2\n0;1.25\n0.01;0\n"));
  CHECK(ms2.units_in_file == AccelUnit::mps2);
  DOUBLES_EQUAL(1.25, ms2.horizontal_mps2[0], 0.0);
  const Record slash = read_record(write("slash.txt", "time_s  HGE(East)_m/s2\n0 0.5\n0.01 0.25\n"));
  CHECK(slash.units_in_file == AccelUnit::mps2);
  const Record paren = read_record(write("paren.txt", "\"t (s)\",\"a (g)\"\n0,1\n0.01,2\n"));
  CHECK(paren.units_in_file == AccelUnit::g);
}

TEST(HandMade, UnitsOptionOverridesHeaderAndIsNoted) {
  const Record r = read_record(write("override.csv", "time_s,accel_g\n0,2\n1,4\n"), with_units(AccelUnit::mps2));
  CHECK(r.units_in_file == AccelUnit::mps2);
  DOUBLES_EQUAL(2.0, r.horizontal_mps2[0], 0.0);
  CHECK(has_note_with(r, {"override.csv", "mps2", "g"}));
}

TEST(HandMade, EveryUnitFactorFromTheOption) {
  const std::string path = write("factor.txt", "0 2\n0.1 -4\n");
  ReadOptions g = with_units(AccelUnit::g);
  g.g_mps2 = 9.81;
  DOUBLES_EQUAL(2.0 * 9.81, read_record(path, g).horizontal_mps2[0], 1e-15);
  DOUBLES_EQUAL(2.0, read_record(path, with_units(AccelUnit::mps2)).horizontal_mps2[0], 0.0);
  DOUBLES_EQUAL(0.02, read_record(path, with_units(AccelUnit::cmps2)).horizontal_mps2[0], 1e-17);
  DOUBLES_EQUAL(0.002, read_record(path, with_units(AccelUnit::mmps2)).horizontal_mps2[0], 1e-18);
  DOUBLES_EQUAL(-0.004, read_record(path, with_units(AccelUnit::mmps2)).horizontal_mps2[1], 1e-18);
}

TEST(HandMade, CrlfPlusSignAndUnderflow) {
  const Record r = read_record(write("crlf.txt", "# units: mps2\r\n0\t+1.5e0\r\n0.25\t1e-400\r\n0.5\t-2\r\n"));
  LONGS_EQUAL(3, r.horizontal_mps2.size());
  DOUBLES_EQUAL(1.5, r.horizontal_mps2[0], 0.0);
  DOUBLES_EQUAL(0.0, r.horizontal_mps2[1], 0.0);
  DOUBLES_EQUAL(0.25, r.dt_s, 0.0);
}

TEST(HandMade, SpreadsheetByteOrderMarkIsSkipped) {
  const Record r = read_record(write("bom.csv", "\xEF\xBB\xBFtime_s,accel_g\r\n0,1\r\n0.01,2\r\n"));
  CHECK(r.units_in_file == AccelUnit::g);
  LONGS_EQUAL(2, r.horizontal_mps2.size());
  expect_rejected("bomonly.txt", "\xEF\xBB\xBF", 1, {"empty file"});
}

TEST(HandMade, DtIsTheMeanStepAndLargeStartTimesAreFine) {
  std::string text = "# units: g\n";
  for (int i = 0; i < 1000; ++i) text += std::to_string(1588389185.0 + 0.005 * i) + " 0\n";
  const Record r = read_record(write("epoch.txt", text));
  DOUBLES_EQUAL(1588389185.0, r.t0_s, 0.0);
  DOUBLES_EQUAL(0.005, r.dt_s, 1e-9);
}

TEST(HandMade, DetectionGoesByContentNotExtension) {
  const std::string at2_as_txt =
      write("at2.txt", std::string(kAt2Head) + "NPTS=      3, DT=   .0200 SEC,\n  .1E-01  .2E-01  .3E-01\n");
  CHECK_TRUE(looks_like_peer_at2(at2_as_txt));
  STRCMP_EQUAL("peer-at2", read_record(at2_as_txt).format.c_str());
  const std::string plain_as_at2 = write("plain.AT2", "# units: g\n0 1\n1 2\n2 3\n3 4\n");
  CHECK_FALSE(looks_like_peer_at2(plain_as_at2));
  STRCMP_EQUAL("plain", read_record(plain_as_at2).format.c_str());
}

// --- AT2 variants ----------------------------------------------------------------------------------------------

TEST(HandMade, At2OldStyleNumbersFirstHeader) {
  const std::string path = write("old.AT2", std::string(kAt2Head) +
                                                "   5    0.0100    NPTS, DT\n"
                                                "  .1000000E-01 -.2000000E-01  .3000000E-01\n"
                                                " -.78E-03  .9984852E-03\n");
  CHECK_TRUE(looks_like_peer_at2(path));
  const Record r = read_record(path);
  STRCMP_EQUAL("peer-at2", r.format.c_str());
  STRCMP_EQUAL("Test Event, 1/2/2000, Test Station, 090", r.description.c_str());
  DOUBLES_EQUAL(0.01, r.dt_s, 1e-15);
  LONGS_EQUAL(5, r.horizontal_mps2.size());
  DOUBLES_EQUAL(-0.02 * 9.81, r.horizontal_mps2[1], 1e-15);
  DOUBLES_EQUAL(-0.78e-3 * 9.81, r.horizontal_mps2[3], 1e-15);
  CHECK(r.notes.empty());
}

TEST(HandMade, At2KeyedHeadersWithTrailingText) {
  const Record a = read_record(
      write("a.AT2", std::string(kAt2Head) + "NPTS=   2, DT=   .0100 SEC,   0 POLE @    30.00000 HZ\n.1E+00 .2E+00\n"));
  LONGS_EQUAL(2, a.horizontal_mps2.size());
  const Record b =
      read_record(write("b.AT2", std::string(kAt2Head) + "NPTS =  2 , DT =   .0050 SEC,\n.1E+00 .2E+00\n"));
  DOUBLES_EQUAL(0.005, b.dt_s, 1e-15);
  const Record c = read_record(write("c.AT2", std::string(kAt2Head) + "npts=2, dt=0.02\n0.1 0.2\n"));
  DOUBLES_EQUAL(0.02, c.dt_s, 1e-15);
}

TEST(HandMade, DtOptionNeverOverridesTheFile) {
  ReadOptions options;
  options.dt_s = 0.02;
  const Record at2 = read_record(write("dt.AT2", std::string(kAt2Head) + "NPTS= 1, DT= .01\n.5E+00\n"), options);
  DOUBLES_EQUAL(0.01, at2.dt_s, 1e-15);
  CHECK(has_note_with(at2, {"dt.AT2", "--dt 0.02", "ignored"}));
  options.units = AccelUnit::g;
  const Record plain = read_record(write("dt.txt", "0 1\n0.01 2\n"), options);
  DOUBLES_EQUAL(0.01, plain.dt_s, 1e-15);
  CHECK(has_note_with(plain, {"dt.txt", "--dt 0.02", "ignored"}));
}

TEST(HandMade, At2UsesTheOptionGravity) {
  ReadOptions options;
  options.g_mps2 = 9.80665;
  const Record r = read_record(write("grav.AT2", std::string(kAt2Head) + "NPTS= 1, DT= .01\n.5E+00\n"), options);
  DOUBLES_EQUAL(0.5 * 9.80665, r.horizontal_mps2[0], 1e-15);
}

TEST(HandMade, At2FewerValuesThanNptsAreKeptAndNoted) {
  const Record r =
      read_record(write("short.AT2", std::string(kAt2Head) + "NPTS= 6, DT= .01 SEC\n .1E-01 .2E-01\n .3E-01\n"));
  LONGS_EQUAL(3, r.horizontal_mps2.size());
  CHECK(has_note_with(r, {"short.AT2", "NPTS=6", "3 values"}));
}

TEST(HandMade, At2FewerValuesWithoutFinalNewlineButWholeNumbers) {
  const Record r = read_record(write("nonl.AT2", std::string(kAt2Head) + "NPTS= 6, DT= .01 SEC\n .1E-01 .2E-01  "));
  LONGS_EQUAL(2, r.horizontal_mps2.size());
  CHECK(has_note_with(r, {"nonl.AT2", "NPTS=6", "2 values"}));
}

TEST(HandMade, At2MoreValuesThanNptsReadsNpts) {
  const Record r = read_record(write("long.AT2", std::string(kAt2Head) + "NPTS= 2, DT= .01 SEC\n .1E-01 .2E-01 .0\n"));
  LONGS_EQUAL(2, r.horizontal_mps2.size());
  CHECK(has_note_with(r, {"long.AT2", "NPTS=2", "3 values", "read 2"}));
}

TEST(HandMade, At2OtherUnitsNeedTheOption) {
  const std::string content =
      "PEER NGA STRONG MOTION DATABASE RECORD\nX, 1/1/2000, Y, 0\nACCELERATION TIME SERIES IN UNITS OF CM/S/S\n"
      "NPTS= 2, DT= .01 SEC\n 100. -50.\n";
  expect_rejected("cms.AT2", content, 3, {"expected 'ACCELERATION TIME SERIES IN UNITS OF G'", "--units"});
  const Record r = read_record(write("cms2.AT2", content), with_units(AccelUnit::cmps2));
  DOUBLES_EQUAL(1.0, r.horizontal_mps2[0], 1e-15);
}

// --- rejections: files -----------------------------------------------------------------------------------------

TEST(HandMade, MissingFile) {
  const std::string path = (dir / "absent.AT2").string();
  for (const auto& read : std::vector<std::function<Record(const std::string&, const ReadOptions&)>>{
           read_record, read_peer_at2, read_plain_text}) {
    const Failure f = failure_of([&] { read(path, ReadOptions{}); });
    STRCMP_CONTAINS("absent.AT2: cannot open", f.message.c_str());
    STRCMP_CONTAINS("does not exist", f.message.c_str());
    LONGS_EQUAL(0, f.line);
  }
}

TEST(HandMade, DirectoryIsNotARecord) {
  const Failure f = failure_of([&] { read_record(dir.string()); });
  STRCMP_CONTAINS("directory", f.message.c_str());
  STRCMP_CONTAINS("expected a record file", f.message.c_str());
  LONGS_EQUAL(0, f.line);
}

TEST(HandMade, EmptyFiles) {
  expect_rejected("empty.txt", "", 1, {"empty file", "expected rows of numbers"});
  expect_rejected("blank.txt", "  \n\n", 1, {"empty file"});
  const std::string path = write("empty.AT2", "");
  const Failure f = failure_of([&] { read_peer_at2(path); });
  STRCMP_CONTAINS("empty.AT2:1: empty file", f.message.c_str());
}

TEST(HandMade, CommentsButNoData) {
  expect_rejected("nodata.txt", "# units: g\n# nothing here\ntime_s accel_g\n", 3, {"no data values", "expected rows"});
}

TEST(HandMade, BinaryGarbageIsRejectedReadably) {
  std::string garbage = "\x01\x02\xff\xfe\x00\x10 binary\n";
  garbage.push_back('\0');
  garbage += "\x80\x81 \x90\n\x7f\x7f 1\n";
  const std::string path = write("garbage.bin", garbage);
  const Failure f = failure_of([&] { read_record(path); });
  STRCMP_CONTAINS("garbage.bin:", f.message.c_str());
  CHECK(f.line > 0);
  CHECK(std::all_of(f.message.begin(), f.message.end(), [](char c) { return c != '\0'; }));
}

// --- rejections: plain text ------------------------------------------------------------------------------------

TEST(HandMade, NonNumericFieldIsQuoted) {
  expect_rejected("word.txt", "# units: g\n0 1\n0.01 2\n0.02 abc\n", 4, {"'abc'", "expected a decimal number"});
  expect_rejected("partial.txt", "# units: g\n0 1\n0.01 2.5x\n", 3, {"'2.5x'", "expected a decimal number"});
  expect_rejected("first.txt", "0 1.0q\n", 1, {"'1.0q'", "expected a decimal number"});
}

TEST(HandMade, NanInfAndOverflowAreRejected) {
  expect_rejected("nan.txt", "# units: g\n0 1\n0.01 nan\n", 3, {"'nan'", "expected a finite number"});
  expect_rejected("NaN.txt", "# units: g\n0 NaN\n0.01 1\n", 2, {"'NaN'", "expected a finite number"});
  expect_rejected("inf.txt", "# units: g\n0 1\n0.01 inf\n", 3, {"'inf'", "expected a finite number"});
  expect_rejected("minf.txt", "# units: g\n0 1\n0.01 -Infinity\n", 3, {"'-Infinity'", "finite"});
  expect_rejected("big.txt", "# units: g\n0 1\n0.01 1e999\n", 3, {"'1e999'", "expected a finite number", "range"});
  expect_rejected("bigt.txt", "# units: g\n0 1\n1e999 1\n", 3, {"'1e999'", "finite"});
}

TEST(HandMade, ValueOverflowingOnConversionIsRejected) {
  expect_rejected("huge.txt", "# units: g\n0 1\n0.01 1e308\n", 3, {"overflows", "expected a finite acceleration"});
}

TEST(HandMade, NumberCutShortIsRejected) {
  expect_rejected("cut.txt", "# units: g\n0 1\n0.01 2.5e-", 3, {"'2.5e-'", "expected a decimal number"});
}

TEST(HandMade, RowWithFewerColumnsIsRejected) {
  expect_rejected("ragged.txt", "# units: g\n0 1 0\n0.01 2 0\n0.02 3 0\n0.03 4\n", 5,
                  {"found 2 columns", "expected 3", "line 2", "truncated"});
  expect_rejected("wide.txt", "# units: g\n0 1\n0.01 2 3\n", 3, {"found 3 columns", "expected 2"});
}

TEST(HandMade, FourOrMoreColumnsAreRejected) {
  expect_rejected("four.txt", "# units: g\n\n0 1 2 3\n", 3, {"found 4 columns", "accepted are 1 column"});
  expect_rejected("five.csv", "t,a,b,c,d\n0,1,2,3,4\n", 2, {"found 5 columns", "accepted are"});
}

TEST(HandMade, MissingUnitsAskForTheOption) {
  expect_rejected("nounits.txt", "0 1\n0.01 2\n", 1, {"does not state its units", "--units (g|mps2|cmps2|mmps2)"});
  expect_rejected("nounits_h.csv", "time, accel\n0, 1\n0.01, 2\n", 1, {"--units (g|mps2|cmps2|mmps2)"});
  // With the option the same files read.
  LONGS_EQUAL(2, read_record((dir / "nounits.txt").string(), with_units(AccelUnit::g)).horizontal_mps2.size());
}

TEST(HandMade, UnknownOrConflictingUnitsAreRejected) {
  expect_rejected("furlongs.txt", "# units: furlongs\n0 1\n0.01 2\n", 1, {"unknown units", "'furlongs'", "expected g"});
  expect_rejected("twounits.txt", "# units: g\n# unit: cm/s2\n0 1\n0.01 2\n", 2, {"expected one unit"});
  expect_rejected("mixed.csv", "# units: g\ntime_s,accel_mps2\n0,1\n0.01,2\n", 1, {"expected one unit"});
  expect_rejected("mixedcols.csv", "time_s,ah_g,av_mps2\n0,1,1\n0.01,2,2\n", 1, {"different units"});
}

TEST(HandMade, UnevenTimeStepIsRejected) {
  const Failure f =
      failure_of([&] { read_record(write("uneven.txt", "# units: g\n0.00 1\n0.01 2\n0.02 3\n0.04 4\n0.05 5\n")); });
  STRCMP_CONTAINS("uneven.txt:5:", f.message.c_str());
  STRCMP_CONTAINS("uneven time step", f.message.c_str());
  STRCMP_CONTAINS("expected step 0.01", f.message.c_str());
  STRCMP_CONTAINS("found 0.02", f.message.c_str());
  // A 0.2 % jitter is far beyond the 1e-6 relative tolerance.
  expect_rejected("jitter.txt", "# units: g\n0 1\n0.01 1\n0.02002 1\n", 4, {"uneven time step"});
}

TEST(HandMade, DecreasingOrRepeatedTimeIsRejected) {
  expect_rejected("back.txt", "# units: g\n0 1\n0.01 2\n0.005 3\n", 4, {"expected strictly increasing time"});
  expect_rejected("same.txt", "# units: g\n0 1\n0 2\n", 3, {"expected strictly increasing time"});
  expect_rejected("down.txt", "# units: g\n1 1\n0.5 2\n0 3\n", 3, {"expected strictly increasing time"});
}

TEST(HandMade, OneRowCannotGiveATimeStep) {
  expect_rejected("onerow.txt", "# units: g\n0 1\n", 2, {"at least two rows"});
}

TEST(HandMade, BadDtOrGravityOptionsAreRejected) {
  for (const double dt_s : {0.0, -0.01, std::nan("")}) {
    ReadOptions options = with_units(AccelUnit::g);
    options.dt_s = dt_s;
    expect_rejected("dt.txt", "1\n2\n", 0, {"--dt", "expected a positive number of seconds"}, options);
    expect_rejected("dt.AT2", std::string(kAt2Head) + "NPTS= 1, DT= .01\n.1\n", 0, {"--dt"}, options);
  }
  ReadOptions no_gravity;
  no_gravity.g_mps2 = 0.0;
  expect_rejected("g.AT2", std::string(kAt2Head) + "NPTS= 1, DT= .01\n.1\n", 0, {"expected a positive value"},
                  no_gravity);
}

TEST(HandMade, MalformedSeparatorsAreRejected) {
  expect_rejected("emptyfield.csv", "# units: g\n0,1\n0.01,,2\n", 3, {"empty field", "expected a number"});
  expect_rejected("leading.csv", "# units: g\n,0,1\n", 2, {"empty field"});
  expect_rejected("decimalcomma.csv", "# units: g\n0,000;1,5\n0,005;2,5\n", 2,
                  {"'0,000'", "expected a decimal number"});
  // One trailing separator, as spreadsheets write, is fine.
  LONGS_EQUAL(2, read_record(write("trailing.csv", "# units: g\n0,1,\n0.01,2,\n")).horizontal_mps2.size());
}

TEST(HandMade, OnlyOneHeaderLine) {
  expect_rejected("twoheaders.csv", "time_s,accel_g\ntime,accel\n0,1\n0.01,2\n", 2,
                  {"expected numbers", "'time'", "only one header line"});
}

// --- rejections: AT2 -------------------------------------------------------------------------------------------

TEST(HandMade, At2TruncatedMidNumber) {
  const std::string head = std::string(kAt2Head) + "NPTS=   8, DT=   .0100 SEC,\n";
  expect_rejected("cut1.AT2", head + "  .1234567E-01  -.2345678E-01  .3456789E-01\n  -.12345E-", 6,
                  {"'-.12345E-'", "truncated"});
  // Cut inside the exponent: "-.1234567E-0" parses, but it is not the number that was written.
  expect_rejected("cut2.AT2", head + "  .1234567E-01  -.2345678E-01\n  .3456789E-01  -.1234567E-0", 6,
                  {"'-.1234567E-0'", "truncated"});
  // Cut inside the mantissa: the exponent is gone.
  expect_rejected("cut3.AT2", head + "  .1234567E-01  -.2345678E-01\n  .3456789E-01  -.12345", 6,
                  {"'-.12345'", "truncated"});
  // Cut inside the last expected value.
  expect_rejected("cut4.AT2", std::string(kAt2Head) + "NPTS= 2, DT= .01\n .1234567E-01 -.2345678E-0", 5, {"truncated"});
}

TEST(HandMade, At2BadNptsOrDt) {
  const std::string data = "  .1E-01  .2E-01\n";
  expect_rejected("npts0.AT2", std::string(kAt2Head) + "NPTS=      0, DT=   .0100 SEC,\n" + data, 4,
                  {"NPTS", "expected a positive whole number"});
  expect_rejected("nptsneg.AT2", std::string(kAt2Head) + "NPTS=     -5, DT=   .0100 SEC,\n" + data, 4,
                  {"expected a positive whole number"});
  expect_rejected("nptsfrac.AT2", std::string(kAt2Head) + "NPTS=   2.5, DT=   .0100 SEC,\n" + data, 4,
                  {"'2.5'", "expected a positive whole number"});
  expect_rejected("dt0.AT2", std::string(kAt2Head) + "NPTS=      2, DT=   .0000 SEC,\n" + data, 4,
                  {"DT", "expected a positive sample interval"});
  expect_rejected("dtneg.AT2", std::string(kAt2Head) + "NPTS=      2, DT=  -.0100 SEC,\n" + data, 4,
                  {"expected a positive sample interval"});
  expect_rejected("dtnan.AT2", std::string(kAt2Head) + "NPTS=      2, DT=  nan SEC,\n" + data, 4,
                  {"expected a positive sample interval"});
  expect_rejected("nodt.AT2", std::string(kAt2Head) + "NPTS=      2,\n" + data, 4, {"no 'DT='", "expected"});
  expect_rejected("olddt0.AT2", std::string(kAt2Head) + "   2    0.0000    NPTS, DT\n" + data, 4,
                  {"expected a positive sample interval"});
  expect_rejected("garbled.AT2", std::string(kAt2Head) + "SAMPLES AND STEP UNKNOWN\n" + data, 4,
                  {"expected the NPTS/DT line"});
}

TEST(HandMade, At2HeaderOnlyOrCut) {
  expect_rejected("headonly.AT2", std::string(kAt2Head) + "NPTS=   2, DT=   .0100 SEC,\n", 4,
                  {"no data values", "expected NPTS=2"});
  const std::string cut_header = "PEER NGA STRONG MOTION DATABASE RECORD\nEvent, 1/1/2000, Station, 0\n";
  const std::string path = write("cuthead.AT2", cut_header);
  CHECK_TRUE(looks_like_peer_at2(path));
  const Failure f = failure_of([&] { read_record(path); });
  STRCMP_CONTAINS("cuthead.AT2:2:", f.message.c_str());
  STRCMP_CONTAINS("expected 4 PEER AT2 header lines", f.message.c_str());
}

TEST(HandMade, At2BadValues) {
  const std::string head = std::string(kAt2Head) + "NPTS=   4, DT=   .0100 SEC,\n";
  expect_rejected("at2nan.AT2", head + " .1E-01 .2E-01\n NaN .4E-01\n", 6, {"'NaN'", "expected a finite number"});
  expect_rejected("at2inf.AT2", head + " .1E-01 .2E-01\n .3E-01 -inf\n", 6, {"'-inf'", "finite"});
  expect_rejected("at2big.AT2", head + " .1E+999 .2E-01\n", 5, {"'.1E+999'", "range"});
  expect_rejected("at2word.AT2", head + " .1E-01 .2E-01\n .3E-01 oops\n", 6, {"'oops'", "expected a decimal number"});
  // Fortran fields that ran together are one bad token, never two numbers.
  expect_rejected("at2glued.AT2", head + " .1E-01-.2E-01\n", 5, {"'.1E-01-.2E-01'"});
}

TEST(HandMade, At2VelocityFileIsRejected) {
  expect_rejected("vel.VT2",
                  "PEER NGA STRONG MOTION DATABASE RECORD\nX, 1/1/2000, Y, 0\nVELOCITY TIME SERIES IN UNITS OF CM/SEC\n"
                  "NPTS= 2, DT= .01 SEC\n 1. 2.\n",
                  3, {"expected an ACCELERATION time series"});
}
