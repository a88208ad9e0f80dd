// The matplotlib runner behind the tool's PNG plots: interpreter search order, embedded scripts, failures that
// carry the script's stderr, and no temporary files left behind.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ci_skip.hpp"
#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/plots/python_plot.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::cli::find_matplotlib_python;
using rockwatch::cli::PlotOutcome;
using rockwatch::cli::run_plot_script;
using rockwatch::test::EnvOverride;
using rockwatch::test::TempDir;
using rockwatch::test::write_text;

namespace {

bool directory_is_empty(const std::string& path) {
  return std::filesystem::directory_iterator(path) == std::filesystem::directory_iterator();
}

}  // namespace

TEST_GROUP(PythonPlot){};

TEST(PythonPlot, RockwatchPythonComesFirst) {
  const EnvOverride unset("ROCKWATCH_PYTHON", nullptr);
  const std::optional<std::string> system_python = find_matplotlib_python();
  if (!system_python) {
    if (rockwatch::test::skip_or_fail_in_ci("no Python with matplotlib on this machine")) return;
  }
  // A link to the same interpreter under another name is found by that name: the variable was used first.
  const TempDir dir;
  const std::string link = dir.file("my-python");
  std::filesystem::create_symlink(*system_python, link);
  {
    const EnvOverride chosen("ROCKWATCH_PYTHON", link.c_str());
    const std::optional<std::string> found = find_matplotlib_python();
    CHECK_TRUE(found.has_value());
    STRCMP_EQUAL(link.c_str(), found->c_str());
  }
  // A variable that names nothing usable falls back to the usual search.
  for (const std::string& useless : {dir.file("missing"), std::string("/bin/false")}) {
    const EnvOverride chosen("ROCKWATCH_PYTHON", useless.c_str());
    const std::optional<std::string> found = find_matplotlib_python();
    CHECK_TRUE(found.has_value());
    STRCMP_EQUAL(system_python->c_str(), found->c_str());
  }
}

TEST(PythonPlot, UnknownScriptNamesTheEmbeddedOnes) {
  const PlotOutcome o = run_plot_script("no_such_plot", {});
  CHECK_FALSE(o.ok);
  STRCMP_CONTAINS("no_such_plot", o.message.c_str());
  STRCMP_CONTAINS("static_sweep", o.message.c_str());
}

TEST(PythonPlot, ScriptFailureCarriesItsStderrAndLeavesNoFiles) {
  if (!find_matplotlib_python()) {
    if (rockwatch::test::skip_or_fail_in_ci("no Python with matplotlib on this machine")) return;
  }
  const TempDir scratch;
  const EnvOverride tmpdir("TMPDIR", scratch.path().c_str());
  const PlotOutcome o = run_plot_script("static_sweep", {scratch.file("missing.csv"), scratch.file("out.png"), "t"});
  CHECK_FALSE(o.ok);
  STRCMP_CONTAINS("static_sweep", o.message.c_str());
  STRCMP_CONTAINS("exit status", o.message.c_str());
  STRCMP_CONTAINS("missing.csv", o.message.c_str());  // from the Python traceback
  CHECK_TRUE(directory_is_empty(scratch.path()));
}

TEST(PythonPlot, ScriptRunsWithArgumentsAndCleansUp) {
  if (!find_matplotlib_python()) return;
  const TempDir data;
  const std::string csv = data.file("points.csv");
  write_text(csv,
             "h_over_b,h_m,lambda,T_s,x_eq_max_m,allowable_pga_g\n20,2,0.1,0.1,0.005,0.9\n20,2,0.5,0.5,0.025,0.2\n");
  const TempDir scratch;
  const EnvOverride tmpdir("TMPDIR", scratch.path().c_str());
  const std::string png = data.file("points.png");
  const PlotOutcome o = run_plot_script("static_sweep", {csv, png, "a title with spaces; and $symbols", "0.4", "NTC"});
  CHECK_TEXT(o.ok, o.message.c_str());
  CHECK_TRUE(std::filesystem::file_size(png) > 1000);
  CHECK_TRUE(directory_is_empty(scratch.path()));
}
