// `rockwatch generate`: the project's ground-motion suite (SPEC §6) through sim::synthesis, written as set files, a
// manifest and plots. This file wires the parts together, shows progress and maps failures to messages and exit
// statuses; the generator and the measures are sim's.
#include <array>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/output_file.hpp"
#include "common/process/progress_line.hpp"
#include "common/process/text_report.hpp"
#include "generate/generate_plot.hpp"
#include "generate/generate_report.hpp"
#include "generate/generate_request.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

namespace rockwatch::cli {

namespace {

namespace synthesis = sim::synthesis;

constexpr CommandErrors kErrors{"rockwatch generate: error: ", "out of memory (a very long record?)"};

// A suite that fails its acceptance checks is still a result (the files are written for inspection), but scripts
// that build on it must notice: the same status as a plot that could not be made.
constexpr int kExitNotAccepted = 1;

std::string in_dir(const GenerateRequest& q, const std::string& name) {
  return (std::filesystem::path(q.out_dir) / name).string();
}

// With --force: the old suite goes first, so the directory never mixes two suites (set 12 of an old 12-set suite
// next to a new 11-set one, old plots beside a --no-plots run), and an interrupted run leaves no manifest that
// lists new set files as the old suite's. A malformed old manifest lists nothing; its files are simply replaced.
void remove_old_suite(const GenerateRequest& q) {
  std::vector<std::string> files;
  try {
    for (const int set : records::suite_sets(q.out_dir)) files.push_back(records::suite_set_path(q.out_dir, set));
  } catch (const records::RecordError&) {
    files.clear();
  }
  for (const char* name : {records::kSuiteManifestName, kManifestCsvName}) files.push_back(in_dir(q, name));
  for (const char* name : kSuitePlotNames) files.push_back(in_dir(q, name));
  for (const std::string& file : files) {
    std::error_code ec;
    std::filesystem::remove(file, ec);
    if (ec) throw UsageError("--out: cannot replace " + file + ": " + ec.message());
  }
}

// Creates --out (and its parents) if missing. Refuses a path that is not a directory, and a directory that already
// holds a suite unless --force: regenerating over a suite that studies were run on must be deliberate.
void prepare_directory(const GenerateRequest& q) {
  std::error_code ec;
  if (std::filesystem::exists(q.out_dir, ec) && !std::filesystem::is_directory(q.out_dir, ec)) {
    throw UsageError("--out " + quoted(q.out_dir) + " exists and is not a directory");
  }
  const std::string manifest = in_dir(q, records::kSuiteManifestName);
  if (!q.force && std::filesystem::exists(manifest, ec)) {
    throw UsageError("--out " + quoted(q.out_dir) + " already holds a suite (" + manifest +
                     "): choose another directory, or give --force to replace it");
  }
  std::filesystem::create_directories(q.out_dir, ec);
  if (ec) throw UsageError("--out " + quoted(q.out_dir) + ": cannot create the directory: " + ec.message());
  remove_old_suite(q);
}

std::string accepted_text(const synthesis::GeneratedSet& set) {
  std::string text;
  for (const synthesis::GeneratedComponent& c : set.components) {
    text += format("%s%c ratio %.3f-%.3f%s", text.empty() ? "" : ", ", synthesis::component_letter(c.component),
                   c.check.min, c.check.max, c.accepted ? "" : " NOT ACCEPTED");
  }
  return text;
}

GeneratedSuite generate(const GenerateRequest& q) {
  const synthesis::GeneratorSettings& s = q.settings;
  ProgressLine progress(std::cerr, stderr_is_terminal());
  GeneratedSuite suite;
  for (int n = 1; n <= q.sets; ++n) {
    const std::string of_sets = "set " + std::to_string(n) + "/" + std::to_string(q.sets);
    // generate_set computes X, Y and Z concurrently, so the line names the set, not a component.
    progress.update(of_sets + " X, Y, Z ...");
    synthesis::GeneratedSet set = synthesis::generate_set(s, n);
    std::array<sim::IntensityMeasures, 3> measures;
    for (std::size_t i = 0; i < set.components.size(); ++i) {
      measures[i] = sim::intensity_measures(set.components[i].acc_mps2, s.dt_s, s.g_mps2);
    }
    progress.step(of_sets + " generated: " + accepted_text(set));
    suite.sets.push_back(std::move(set));
    suite.measures.push_back(measures);
  }
  progress.update("suite mean ...");
  suite.mean = synthesis::suite_mean(s, suite.sets);
  progress.clear();
  return suite;
}

void write_suite(const GenerateRequest& q, const GeneratedSuite& suite, const nlohmann::ordered_json& manifest) {
  for (const synthesis::GeneratedSet& set : suite.sets) {
    records::write_suite_record(in_dir(q, set_file_name(set.set_number)), suite_record_file(q, set));
  }
  // The manifest last: a directory with a manifest is a complete suite.
  write_output_file(in_dir(q, kManifestCsvName),
                    [&](std::ostream& out) { write_manifest_csv(out, suite, q.settings.g_mps2); });
  write_output_file(in_dir(q, records::kSuiteManifestName),
                    [&](std::ostream& out) { out << manifest.dump(2) << '\n'; });
}

int run(const GenerateRequest& q) {
  prepare_directory(q);
  GeneratedSuite suite;
  try {
    suite = generate(q);
  } catch (const synthesis::GeneratorError& e) {
    throw UsageError(std::string("the generator refused the settings: ") + e.what());
  }
  const nlohmann::ordered_json manifest = manifest_json(q, suite);
  write_suite(q, suite, manifest);

  if (q.json) {
    std::cout << manifest.dump(2) << '\n';
  } else {
    std::cout << generate_summary_text(q, suite);
  }
  int status = kExitOk;
  if (q.plots) {
    const PlotOutcome plot = plot_suite_spectra(q, suite);
    if (plot.ok) {
      std::string names;
      for (const char* name : kSuitePlotNames) names += (names.empty() ? "" : ", ") + std::string(name);
      std::string text;
      line(text, "plots", names);
      if (!q.json) std::cout << text;
    } else {
      std::cout.flush();
      status = fail(kErrors, "plots not written: " + plot.message, kExitInternalError);
    }
  }
  const std::vector<std::string> failures = not_accepted(q, suite);
  if (!failures.empty()) {
    std::cout.flush();
    std::string message = "the suite is not accepted (its files are written all the same):";
    for (const std::string& f : failures) message += "\n  " + f;
    status = fail(kErrors, message, kExitNotAccepted);
  }
  const int written = finish_stdout(kErrors);
  return written != kExitOk ? written : status;
}

}  // namespace

int generate_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const GenerateParse parsed = parse_generate_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
