// Every way `rockwatch simulate` must refuse to run: exit status 2, nothing on stdout, one message on stderr that
// starts with "rockwatch simulate: error: " and names the option or file at fault. Never a crash.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cli_process.hpp"
#include "cli_test_files.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_simulate_rejections {

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;

namespace {

const std::string kElCentro180 = record_path("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");

void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  rockwatch::test::expect_command_rejected("simulate", args, mentions);
}

void expect_rejected_option(const std::string& option, const std::string& value, const std::string& mention) {
  expect_rejected({"--record", kElCentro180, option, value}, {option, mention});
}

}  // namespace

TEST_GROUP(SimulateRejectsOptions){};

TEST(SimulateRejectsOptions, MissingRecord) { expect_rejected({"--json"}, {"--record"}); }
TEST(SimulateRejectsOptions, RecordOptionWithoutValue) { expect_rejected({"--record"}, {"--record"}); }
TEST(SimulateRejectsOptions, UnknownOption) { expect_rejected({"--record", kElCentro180, "--frobnicate"}, {"--frobnicate"}); }
TEST(SimulateRejectsOptions, StrayArgument) { expect_rejected({"--record", kElCentro180, "extra"}, {"extra"}); }
TEST(SimulateRejectsOptions, RAboveOne) { expect_rejected_option("--r", "1.5", "ana, exp, impulse"); }
TEST(SimulateRejectsOptions, RNotANameNorANumber) { expect_rejected_option("--r", "foo", "'foo'"); }
TEST(SimulateRejectsOptions, RNan) { expect_rejected_option("--r", "nan", "[0, 1]"); }
TEST(SimulateRejectsOptions, KappaBelowOne) { expect_rejected_option("--kappa", "0.5", ">= 1"); }
TEST(SimulateRejectsOptions, H1NotAboveB) {
  expect_rejected({"--record", kElCentro180, "--h1", "0.05"}, {"--h1 must be greater than b (got 0.05)"});
}
TEST(SimulateRejectsOptions, DefaultH1BelowAGivenB) { expect_rejected_option("--b", "2", "--h1 must be greater than b"); }
TEST(SimulateRejectsOptions, NegativeB) { expect_rejected_option("--b", "-1", "> 0"); }
TEST(SimulateRejectsOptions, AOutOfRange) { expect_rejected_option("--a", "2", "[0, 1]"); }
TEST(SimulateRejectsOptions, APrimeOutOfRange) { expect_rejected_option("--a-prime", "-0.1", "[0, 1]"); }
TEST(SimulateRejectsOptions, NegativeRho) { expect_rejected_option("--rho", "0", "> 0"); }
TEST(SimulateRejectsOptions, NegativeFp) { expect_rejected_option("--fp", "-5", ">= 0"); }
TEST(SimulateRejectsOptions, GravityNotPositive) { expect_rejected_option("--g", "0", "> 0"); }
TEST(SimulateRejectsOptions, InfiniteGravity) { expect_rejected_option("--g", "inf", "finite"); }
TEST(SimulateRejectsOptions, WallTooExtremeToCompute) { expect_rejected_option("--rho", "1e308", "cannot compute"); }
TEST(SimulateRejectsOptions, WallNumberWithTrailingText) { expect_rejected_option("--h2", "1.5m", "'1.5m'"); }
TEST(SimulateRejectsOptions, UnknownModel) { expect_rejected_option("--model", "cubic", "linear or full"); }
TEST(SimulateRejectsOptions, UnknownWall) { expect_rejected_option("--wall", "brick", "paper"); }
TEST(SimulateRejectsOptions, ScalePgaZero) { expect_rejected_option("--scale-pga", "0", "> 0"); }
TEST(SimulateRejectsOptions, ScalePgaNan) { expect_rejected_option("--scale-pga", "nan", "finite"); }
TEST(SimulateRejectsOptions, ScalePgaNegativeInfinity) { expect_rejected_option("--scale-pga", "-inf", "finite"); }
TEST(SimulateRejectsOptions, MaxStepZero) { expect_rejected_option("--max-step", "0", "> 0"); }
TEST(SimulateRejectsOptions, MaxStepAbsurdlySmall) { expect_rejected_option("--max-step", "1e-12", "steps"); }
TEST(SimulateRejectsOptions, TEndNegative) { expect_rejected_option("--t-end", "-1", ">= 0"); }
TEST(SimulateRejectsOptions, TEndAbsurdlyLong) { expect_rejected_option("--t-end", "1e300", "--t-end"); }
TEST(SimulateRejectsOptions, DtNotPositive) { expect_rejected_option("--dt", "-0.01", "> 0"); }
TEST(SimulateRejectsOptions, UnknownUnits) { expect_rejected_option("--units", "furlongs", "g, mps2, cmps2 or mmps2"); }
TEST(SimulateRejectsOptions, OptionGivenTwice) {
  expect_rejected({"--record", kElCentro180, "--b", "0.1", "--b", "0.2"}, {"--b"});
}

TEST_GROUP(SimulateRejectsFiles) {
  std::unique_ptr<TempDir> dir;
  void setup() override { dir = std::make_unique<TempDir>(); }
  void teardown() override { dir.reset(); }
};

TEST(SimulateRejectsFiles, NonexistentRecord) {
  const std::string missing = dir->file("no_such_record.AT2");
  expect_rejected({"--record", missing}, {missing, "does not exist"});
}

TEST(SimulateRejectsFiles, NonexistentVertical) {
  const std::string missing = dir->file("no_such_vertical.AT2");
  expect_rejected({"--record", kElCentro180, "--vertical", missing}, {missing});
}

TEST(SimulateRejectsFiles, RecordIsADirectory) { expect_rejected({"--record", dir->path()}, {dir->path()}); }

TEST(SimulateRejectsFiles, OutIntoNonexistentDirectory) {
  const std::string out = dir->file("no_such_dir/history.csv");
  expect_rejected({"--record", kElCentro180, "--out", out}, {"--out", out});
  CHECK_FALSE(std::filesystem::exists(out));
}

TEST(SimulateRejectsFiles, OutOverAnInputRecord) {
  const std::string copy = dir->file("copy.AT2");
  std::filesystem::copy_file(kElCentro180, copy);
  const auto size = std::filesystem::file_size(copy);
  expect_rejected({"--record", copy, "--out", copy}, {"--out"});
  CHECK_EQUAL(size, std::filesystem::file_size(copy));
}

TEST(SimulateRejectsFiles, PlainFileWithoutUnits) {
  const std::string path = dir->file("no_units.txt");
  rockwatch::test::write_text(path, "0.00 0.1\n0.01 0.2\n0.02 -0.1\n");
  expect_rejected({"--record", path}, {path, "--units"});
}

TEST(SimulateRejectsFiles, PlainOneColumnWithoutDt) {
  const std::string path = dir->file("one_column.txt");
  rockwatch::test::write_text(path, "# units: g\n0.1\n0.2\n-0.1\n");
  expect_rejected({"--record", path}, {path, "--dt"});
}

TEST(SimulateRejectsFiles, UnitsOptionAndDtMakeABareFileReadable) {
  // The counterpart of the two rejections above: the same kind of file runs once the options supply what it lacks.
  const std::string path = dir->file("bare.txt");
  rockwatch::test::write_text(path, "0.1\n0.2\n-0.1\n0.0\n");
  const ProcessResult r = run_rockwatch({"simulate", "--record", path, "--units", "g", "--dt", "0.01", "--json"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
}

TEST(SimulateRejectsFiles, ZeroRecordCannotBeScaled) {
  const std::string path = dir->file("zero.txt");
  rockwatch::test::write_plain_record(path, [](double) { return 0.0; }, 0.01, 1.0);
  expect_rejected({"--record", path, "--scale-pga", "0.2"}, {"--scale-pga", path, "peak"});
}

TEST(SimulateRejectsFiles, VerticalLiftOff) {
  const std::string horizontal = dir->file("h.txt"), vertical = dir->file("v.txt");
  rockwatch::test::write_plain_record(horizontal, rockwatch::test::g7_ug_mps2, 0.005, 2.0);
  rockwatch::test::write_plain_record(vertical, [](double t) { return t > 0.3 && t < 0.4 ? -1.2 * kG : 0.0; }, 0.005, 2.0);
  expect_rejected({"--record", horizontal, "--vertical", vertical}, {vertical, "G = g + v''", "<= 0", "lifts off"});
}

TEST(SimulateRejectsFiles, LiftOffCausedByScaling) {
  const std::string horizontal = dir->file("h.txt"), vertical = dir->file("v.txt");
  rockwatch::test::write_plain_record(horizontal, rockwatch::test::g7_ug_mps2, 0.005, 2.0);
  rockwatch::test::write_plain_record(vertical, [](double t) { return t > 0.3 && t < 0.4 ? -0.6 * kG : 0.0; }, 0.005, 2.0);
  // 0.6 g vertical is fine as it is, but not once scaled by 2 (horizontal 0.2 g -> 0.4 g).
  const ProcessResult ok = run_rockwatch({"simulate", "--record", horizontal, "--vertical", vertical, "--json"});
  CHECK_EQUAL_TEXT(0, ok.exit_status, describe(ok).c_str());
  expect_rejected({"--record", horizontal, "--vertical", vertical, "--scale-pga", "0.4"}, {"--scale-pga", "G = g + v''"});
}

TEST(SimulateRejectsFiles, ThirdColumnAndVerticalFileAreAmbiguous) {
  const std::string three = dir->file("three.txt"), vertical = dir->file("v.txt");
  const std::function<double(double)> vg = [](double) { return 0.1; };
  rockwatch::test::write_plain_record(three, rockwatch::test::g7_ug_mps2, 0.005, 2.0, &vg);
  rockwatch::test::write_plain_record(vertical, vg, 0.005, 2.0);
  expect_rejected({"--record", three, "--vertical", vertical}, {"ambiguous", three, "--vertical"});
}

TEST(SimulateRejectsFiles, ThreeColumnVerticalFile) {
  const std::string horizontal = dir->file("h.txt"), three = dir->file("three.txt");
  const std::function<double(double)> vg = [](double) { return 0.1; };
  rockwatch::test::write_plain_record(horizontal, rockwatch::test::g7_ug_mps2, 0.005, 2.0);
  rockwatch::test::write_plain_record(three, rockwatch::test::g7_ug_mps2, 0.005, 2.0, &vg);
  expect_rejected({"--record", horizontal, "--vertical", three}, {"--vertical", three});
}

TEST(SimulateRejectsFiles, MalformedRecordNamesTheLine) {
  const std::string path = dir->file("bad.txt");
  rockwatch::test::write_text(path, "# units: g\n0.00 0.1\n0.01 zero\n");
  expect_rejected({"--record", path}, {path + ":3"});
}

}  // namespace unity_test_simulate_rejections
