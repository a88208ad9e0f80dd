// `rockwatch` itself: help, version, and clear errors for what is not a command.
#include <string>

#include "cli_process.hpp"
#include "cli_test_files.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;

TEST_GROUP(Dispatch){};

TEST(Dispatch, HelpListsTheCommands) {
  const ProcessResult r = run_rockwatch({"--help"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("simulate", r.out.c_str());
  STRCMP_CONTAINS("Usage", r.out.c_str());
}

TEST(Dispatch, Version) {
  const ProcessResult r = run_rockwatch({"--version"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  CHECK_TRUE(r.out.rfind("rockwatch ", 0) == 0);
  CHECK_TRUE(r.out.find("unknown") == std::string::npos);
}

TEST(Dispatch, SimulateHelpListsItsOptions) {
  for (const char* form : {"--help", "-h"}) {
    const ProcessResult r = run_rockwatch({"simulate", form});
    CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
    for (const char* option : {"--record", "--vertical", "--scale-pga", "--r", "--kappa", "--out", "--json", "--g"}) {
      STRCMP_CONTAINS(option, r.out.c_str());
    }
  }
  const ProcessResult help_command = run_rockwatch({"help", "simulate"});
  CHECK_EQUAL_TEXT(0, help_command.exit_status, describe(help_command).c_str());
  STRCMP_CONTAINS("--record", help_command.out.c_str());
}

TEST(Dispatch, UnknownCommand) {
  const ProcessResult r = run_rockwatch({"frobnicate", "--record", "x"});
  CHECK_EQUAL_TEXT(2, r.exit_status, describe(r).c_str());
  CHECK_TRUE(r.out.empty());
  STRCMP_CONTAINS("rockwatch: error: unknown command 'frobnicate'", r.err.c_str());
  STRCMP_CONTAINS("simulate", r.err.c_str());
}

TEST(Dispatch, UnknownTopLevelOption) {
  const ProcessResult r = run_rockwatch({"--frobnicate"});
  CHECK_EQUAL_TEXT(2, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("'--frobnicate'", r.err.c_str());
}

TEST(Dispatch, NoCommand) {
  const ProcessResult r = run_rockwatch({});
  CHECK_EQUAL_TEXT(2, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("no command", r.err.c_str());
}
