// The wall-sensor CSV reader (records::read_wall_sensor_csv): every accepted variant and every rejection, each
// rejection naming the file, the line and what was expected.
#include <string>
#include <vector>

#include "record_test_support.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/wall_sensor_csv.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

using rockwatch::records::read_wall_sensor_csv;
using rockwatch::records::WallSensorFile;
using rockwatch::records::WallSensorRow;
using rockwatch::test::check_rejection;
using rockwatch::test::failure_of;

TEST_GROUP_BASE(WallSensorCsv, rockwatch::test::HandMadeFileTest) {
  WallSensorFile read(const std::string& content) { return read_wall_sensor_csv(write("sensors.csv", content)); }
  void expect_refused(const std::string& content, int line, const std::vector<std::string>& fragments) {
    const std::string path = write("bad.csv", content);
    check_rejection(failure_of([&] { read_wall_sensor_csv(path); }), "bad.csv", line, fragments);
  }
};

TEST(WallSensorCsv, ReadsDisplacementAndAccelerationWithAbsentFields) {
  const WallSensorFile f = read("t_s,x_mid_m,a_mid_mps2\n0,0.001,0.5\n0.005,,-0.25\n0.01,-2e-3,\n0.015,,\n");
  CHECK(f.has_x_column);
  CHECK(f.has_a_column);
  LONGS_EQUAL(4, f.rows.size());
  const WallSensorRow& r0 = f.rows[0];
  LONGS_EQUAL(0, r0.utime_us);
  CHECK(r0.x_valid && r0.a_valid);
  DOUBLES_EQUAL(0.001, r0.x_mid_m, 0.0);
  DOUBLES_EQUAL(0.5, r0.a_mid_mps2, 0.0);
  LONGS_EQUAL(5000, f.rows[1].utime_us);
  CHECK(!f.rows[1].x_valid && f.rows[1].a_valid);
  DOUBLES_EQUAL(-0.25, f.rows[1].a_mid_mps2, 0.0);
  CHECK(f.rows[2].x_valid && !f.rows[2].a_valid);
  DOUBLES_EQUAL(-2e-3, f.rows[2].x_mid_m, 0.0);
  CHECK(!f.rows[3].x_valid && !f.rows[3].a_valid);
  LONGS_EQUAL(4, f.rows[2].line);  // 1-based: the header is line 1
}

TEST(WallSensorCsv, ColumnsInAnyOrderCommentsBlanksCrlfAndBom) {
  const WallSensorFile f =
      read("\xEF\xBB\xBF# made by a logger\r\n\r\n X_MID_M , t_s \r\n# a comment between rows\r\n 0.25 , -0.1 \r\n0.5,0.2e0\r\n");
  CHECK(f.has_x_column);
  CHECK(!f.has_a_column);
  LONGS_EQUAL(2, f.rows.size());
  LONGS_EQUAL(-100000, f.rows[0].utime_us);
  DOUBLES_EQUAL(0.25, f.rows[0].x_mid_m, 0.0);
  LONGS_EQUAL(200000, f.rows[1].utime_us);
  LONGS_EQUAL(6, f.rows[1].line);
}

TEST(WallSensorCsv, AccelerometerOnlyAndTimesRoundedToMicroseconds) {
  const WallSensorFile f = read("t_s,a_mid_mps2\n0.0000004,1\n0.0000016,2\n1.2345675,+3\n");
  CHECK(!f.has_x_column);
  LONGS_EQUAL(0, f.rows[0].utime_us);
  LONGS_EQUAL(2, f.rows[1].utime_us);
  LONGS_EQUAL(1234568, f.rows[2].utime_us);  // llround of 1234567.5
  DOUBLES_EQUAL(3.0, f.rows[2].a_mid_mps2, 0.0);
}

TEST(WallSensorCsv, RefusesAMissingOrWrongHeader) {
  expect_refused("", 0, {"no header line", "t_s"});
  expect_refused("# only comments\n\n", 0, {"no header line"});
  expect_refused("0,0.001\n", 1, {"found a number '0' where the header belongs", "t_s,x_mid_m"});
  expect_refused("t_s,x_mid_m,z_m\n0,1,2\n", 1, {"unknown column 'z_m'", "x_mid_m"});
  expect_refused("x_mid_m,a_mid_mps2\n0,1\n", 1, {"no t_s column"});
  expect_refused("t_s\n0\n", 1, {"no sensor column"});
  expect_refused("t_s,x_mid_m,x_mid_m\n0,1,2\n", 1, {"column 'x_mid_m' named twice"});
  expect_refused("t_s,,x_mid_m\n0,,1\n", 1, {"unknown column ''"});
  expect_refused("t_s,x_mid_m\n", 0, {"no sample rows after the header"});
}

TEST(WallSensorCsv, RefusesBadRowsNamingTheLine) {
  expect_refused("t_s,x_mid_m\n0,0.1\n0.1\n", 3, {"found 1 field, expected 2"});
  expect_refused("t_s,x_mid_m\n0,0.1,\n", 2, {"found 3 fields, expected 2"});
  expect_refused("t_s,x_mid_m\n,0.1\n", 2, {"t_s is empty"});
  expect_refused("t_s,x_mid_m\n0,0.1\n0.005,1.5mm\n", 3, {"x_mid_m: expected a decimal number, found '1.5mm'"});
  expect_refused("t_s,x_mid_m,a_mid_mps2\n0,0.1,nan\n", 2, {"a_mid_mps2: expected a finite number", "empty field"});
  expect_refused("t_s,x_mid_m\n0,1e999\n", 2, {"out of the range of double"});
  expect_refused("t_s,x_mid_m\n0.0.1,1\n", 2, {"t_s: expected a decimal number"});
  expect_refused("t_s,x_mid_m\ninf,1\n", 2, {"t_s: expected a finite number"});
  expect_refused("t_s,x_mid_m\n2e9,1\n", 2, {"t_s = 2000000000", "within"});
}

TEST(WallSensorCsv, RefusesTimesThatDoNotIncrease) {
  expect_refused("t_s,x_mid_m\n0,0\n0.01,0\n# gap\n0.005,0\n", 5, {"t_s = 0.005 s does not follow t_s = 0.01 s of line 3",
                                                                   "strictly increasing"});
  expect_refused("t_s,x_mid_m\n0.01,0\n0.01,0\n", 3, {"does not follow"});
  expect_refused("t_s,x_mid_m\n0.0100001,0\n0.0100004,0\n", 3, {"at least 1 us apart"});
}

TEST(WallSensorCsv, RefusesWhatIsNotAFile) {
  check_rejection(failure_of([&] { read_wall_sensor_csv((dir / "missing.csv").string()); }), "missing.csv", 0,
                  {"does not exist"});
  check_rejection(failure_of([&] { read_wall_sensor_csv(dir.string()); }), dir.filename().string(), 0,
                  {"is a directory"});
}
