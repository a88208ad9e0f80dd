// The alarm options (--arith, --lambda-w, --alarm-hold, --energy-margin), shared by `rockwatch simulate` and
// `rockwatch study`: every bad value is rejected by both commands naming the option, and nothing is written.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;
const char* const kElCentro180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

namespace {

void expect_simulate_rejected(const std::vector<std::string>& options, const std::vector<std::string>& mentions) {
  rockwatch::test::expect_command_rejected("simulate", with({"--record", record_path(kElCentro180)}, options),
                                           mentions);
}

// Nothing is written: the directory is not even created.
void expect_study_rejected(const std::vector<std::string>& options, const std::vector<std::string>& mentions) {
  const TempDir tmp;
  const std::string dir = tmp.file("study");
  rockwatch::test::expect_command_rejected("study", with({"--suite", kSuite, "--sets", "1", "--out", dir}, options),
                                           mentions);
  CHECK_TEXT(!std::filesystem::exists(dir), dir.c_str());
}

// The same rejections for both commands.
void expect_both_rejected(const std::vector<std::string>& options, const std::vector<std::string>& mentions) {
  expect_simulate_rejected(options, mentions);
  expect_study_rejected(options, mentions);
}

}  // namespace

TEST_GROUP(AlarmOptionsRejected){};

TEST(AlarmOptionsRejected, ArithUnknown) { expect_both_rejected({"--arith", "float"}, {"--arith", "fixed or double", "'float'"}); }
TEST(AlarmOptionsRejected, ArithEmpty) { expect_both_rejected({"--arith", ""}, {"--arith"}); }
TEST(AlarmOptionsRejected, ArithFixedWithTheFullModel) {
  expect_both_rejected({"--arith", "fixed", "--model", "full"}, {"--arith fixed", "linear model only"});
}
TEST(AlarmOptionsRejected, LambdaWZero) { expect_both_rejected({"--alarms", "--lambda-w", "0"}, {"--lambda-w", "(0, 1]"}); }
TEST(AlarmOptionsRejected, LambdaWAboveOne) {
  expect_both_rejected({"--alarms", "--lambda-w", "1.5"}, {"--lambda-w", "(0, 1]", "1.5"});
}
TEST(AlarmOptionsRejected, LambdaWNan) { expect_both_rejected({"--alarms", "--lambda-w", "nan"}, {"--lambda-w", "finite"}); }
TEST(AlarmOptionsRejected, LambdaWNotANumber) {
  expect_both_rejected({"--alarms", "--lambda-w", "0.4x"}, {"--lambda-w", "'0.4x'"});
}
TEST(AlarmOptionsRejected, HoldNegative) {
  expect_both_rejected({"--alarms", "--alarm-hold", "-1"}, {"--alarm-hold", "[0, 3600] s"});
}
TEST(AlarmOptionsRejected, HoldTooLong) {
  expect_both_rejected({"--alarms", "--alarm-hold", "1e6"}, {"--alarm-hold", "[0, 3600] s"});
}
TEST(AlarmOptionsRejected, HoldInfinite) { expect_both_rejected({"--alarms", "--alarm-hold", "inf"}, {"--alarm-hold", "finite"}); }
TEST(AlarmOptionsRejected, EnergyMarginBelowOne) {
  expect_both_rejected({"--alarms", "--energy-margin", "0.9"}, {"--energy-margin", "[1, 100]", "0.9"});
}
TEST(AlarmOptionsRejected, EnergyMarginTooLarge) {
  expect_both_rejected({"--alarms", "--energy-margin", "101"}, {"--energy-margin", "[1, 100]"});
}
TEST(AlarmOptionsRejected, AlarmSettingWithoutAlarms) {
  expect_both_rejected({"--lambda-w", "0.5"}, {"--lambda-w", "--alarms"});
  expect_both_rejected({"--alarm-hold", "2"}, {"--alarm-hold", "--alarms"});
  expect_both_rejected({"--energy-margin", "1.5"}, {"--energy-margin", "--alarms"});
}
