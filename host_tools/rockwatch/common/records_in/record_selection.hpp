// The record options of every tool that reads a ground motion (simulate, spectrum; later study and replay): a file
// (--record) or a record of a rockwatch suite (--suite DIR --set N --component X|Y|Z), the channel of a
// multi-channel file, the vertical that goes with it, and how to read the values (--units, --dt, --gain). One piece,
// so every tool accepts the same options with the same help and the same messages.
#pragma once

#include <optional>
#include <string>

#include "rockwatch/options/cli11_fwd.hpp"
#include <nlohmann/json.hpp>

#include "rockwatch/records/record.hpp"

namespace rockwatch::cli {

// The options as typed; parse_record_selection converts and checks them, so every message has one form.
struct RecordOptionTexts {
  std::string record, suite, set, component, channel, vertical, vertical_channel, gain, units, dt;
  bool vertical_from_suite = false;
};

// A tool that measures one record (spectrum) takes no vertical; one that runs a wall (simulate) does.
enum class VerticalOptions { none, allowed };

// Registers --record, --suite, --set, --component, --channel, --gain, --units, --dt and, with
// VerticalOptions::allowed, --vertical, --vertical-channel and --vertical-from-suite.
void add_record_options(CLI::App& app, RecordOptionTexts& texts, VerticalOptions vertical);

// Where a suite record came from, for the reports.
struct SuiteSelection {
  std::string dir;         // --suite as given
  std::string name;        // the manifest's "suite" (e.g. "npr9998-2015"); empty when it has none
  int set = 0;             // --set, 1-based
  char component = 'X';    // --component: 'X' or 'Y' (horizontal), 'Z' (vertical)
};

struct RecordSelection {
  std::string record_path;                      // the file read: --record, or the set file of --suite
  std::optional<SuiteSelection> suite;          // set when the record comes from --suite
  std::optional<std::string> channel;           // what the reader picks from record_path: --channel or --component
  bool channel_is_component = false;            // channel came from --component (a suite record's X, Y or Z)
  std::optional<std::string> vertical_path;     // --vertical, or the set file again with --vertical-from-suite
  std::optional<std::string> vertical_channel;  // --vertical-channel, or "Z" with --vertical-from-suite
  bool vertical_from_suite = false;
  std::optional<double> gain_counts_per_mps2;   // --gain: miniSEED counts per m/s2
  records::ReadOptions read_options;            // --units, --dt, --gain, g and the channel of record_path

  // The options for the vertical file: the same units, dt and g, its own channel, and the gain when the vertical
  // file is miniSEED (the --record file always gets it, so a gain given for nothing is still refused).
  records::ReadOptions vertical_read_options() const;
};

// The record options as typed values: what was given (an empty optional: not given). The command line's parser
// converts its texts into them, the Python module (rockwatch.read_record) fills them from its keywords; both call
// check_record_selection, so the checks and the messages (naming the option) are the same.
struct RecordSelectionSettings {
  std::optional<std::string> record, suite;        // --record FILE | --suite DIR
  std::optional<long long> set;                    // --set N (from 1)
  std::optional<std::string> component, channel;   // --component X|Y|Z, --channel CODE
  std::optional<std::string> vertical, vertical_channel;  // --vertical FILE, --vertical-channel CODE
  bool vertical_from_suite = false;                // --vertical-from-suite
  std::optional<std::string> units;                // --units: g | mps2 | cmps2 | mmps2 (and their spellings)
  std::optional<double> dt_s;                      // --dt [s]
  std::optional<double> gain_counts_per_mps2;      // --gain [counts per m/s2]
};

// Checks the settings. `g_mps2` converts records in units of g (the wall's or the --g value). Finds the set file of
// --suite in the suite's manifest (records::suite_set_path: a RecordError names the manifest and lists its sets when
// the set is not there). Throws UsageError naming the option at fault and what it expects.
RecordSelection check_record_selection(const RecordSelectionSettings& settings, double g_mps2);

// The texts of the options given, converted (a number that is not one: "--dt expects a finite number").
RecordSelectionSettings record_selection_settings(const CLI::App& app, const RecordOptionTexts& texts);

// record_selection_settings, then check_record_selection. `g_mps2` converts records in units of g (the wall's or the --g value). Finds the
// set file of --suite in the suite's manifest (records::suite_set_path: a RecordError names the manifest and lists
// its sets when the set is not there). Throws UsageError naming the option at fault and what it expects.
RecordSelection parse_record_selection(const CLI::App& app, const RecordOptionTexts& texts, double g_mps2);

// "suite npr9998-2015 set 3 component X", "component X" (a set file as --record), "channel HNE", or empty for a
// plain --record: the line the summaries add under the file name.
std::string selection_text(const RecordSelection& selection);

// "suite npr9998-2015 set 3 component Z" (the directory when the manifest has no name).
std::string suite_record_text(const SuiteSelection& suite, char component);

// What the vertical is, for messages: "--vertical FILE" or "component Z of suite set 3 (FILE)".
std::string vertical_source_text(const RecordSelection& selection);

// Adds to a report's JSON object only the keys of the options used, so a plain --record leaves the documented keys
// unchanged: "suite" {"dir", "name", "set", "component", "file", "vertical_component"} with --suite, "component"
// with --component on a --record file, "channel" with --channel, "vertical_channel" with --vertical-channel,
// "gain_counts_per_mps2" with --gain.
void add_selection_json(nlohmann::ordered_json& j, const RecordSelection& selection);

// g | mps2 | cmps2 | mmps2 and the spellings records::parse_accel_unit knows.
records::AccelUnit parse_units(const std::string& option, const std::string& text);

}  // namespace rockwatch::cli
