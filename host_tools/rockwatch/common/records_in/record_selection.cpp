#include "common/records_in/record_selection.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/records/text_format.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace record_selection {

// given() for options a tool may not have registered (spectrum has no vertical options).
bool used(const CLI::App& app, const char* option) {
  const CLI::Option* o = app.get_option_no_throw(option);
  return o != nullptr && o->count() > 0;
}

constexpr const char* kSourceHint = "give --record FILE, or --suite DIR --set N --component X|Y|Z";

// The manifest's "suite" name, for the reports only: a manifest without one (hand-made suites) is not an error, and
// suite_set_path has already checked everything the record needs.
std::string suite_name(const std::string& dir) {
  std::ifstream in(std::filesystem::path(dir) / records::kSuiteManifestName, std::ios::binary);
  const nlohmann::json manifest = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!manifest.is_object()) return {};
  const auto name = manifest.find("suite");
  return name != manifest.end() && name->is_string() ? name->get<std::string>() : std::string();
}

constexpr const char* kSetExpected = "--set must be a whole number >= 1, the set of the suite (got ";
constexpr long long kMaxSet = 999999999;  // nine digits: what the command line reads

// A plain decimal integer >= 1, so "1.5", "1e1" and "+3" are refused rather than read as something else.
long long parse_set_number(const std::string& text) {
  const bool digits = !text.empty() && text.size() <= 9 && text.find_first_not_of("0123456789") == std::string::npos;
  const long long value = digits ? std::stoll(text) : 0;
  if (value < 1) throw UsageError(kSetExpected + quoted(text) + ")");
  return value;
}

int check_set_number(long long value) {
  if (value < 1 || value > kMaxSet) throw UsageError(kSetExpected + std::to_string(value) + ")");
  return static_cast<int>(value);
}

char parse_component(const std::string& text) {
  const char letter = text.size() == 1 ? static_cast<char>(std::toupper(static_cast<unsigned char>(text[0]))) : '\0';
  if (letter != 'X' && letter != 'Y' && letter != 'Z') {
    throw UsageError("--component must be X or Y (horizontal) or Z (vertical, up positive) (got " + quoted(text) + ")");
  }
  return letter;
}

std::string parse_name(const char* option, const std::string& text, const char* what) {
  if (text.empty()) throw UsageError(std::string(option) + " needs " + what);
  return text;
}

void reject_together(bool first_used, const char* first, bool second_used, const char* second,
                     const std::string& why) {
  if (first_used && second_used) {
    throw UsageError(std::string(first) + " cannot be combined with " + second + ": " + why);
  }
}

// --suite DIR --set N --component X: all three, or --set and --component (the latter also names the channel of a
// suite set file given as --record) without --suite.
void check_source(const RecordSelectionSettings& t) {
  reject_together(bool(t.record), "--record", bool(t.suite), "--suite", "give one record source");
  if (!t.record && !t.suite) throw UsageError(std::string("no record: ") + kSourceHint);
  if (t.suite) {
    std::string missing;
    if (!t.set) missing = "--set";
    if (!t.component) missing += (missing.empty() ? "" : " and ") + std::string("--component");
    if (!missing.empty()) {
      throw UsageError("--suite needs --set N (the record set, from 1) and --component X|Y|Z (missing " + missing + ")");
    }
  } else if (t.set) {
    throw UsageError("--set selects a record set of a suite: give --suite DIR too");
  }
  reject_together(bool(t.component), "--component", bool(t.channel), "--channel",
                  "--component X|Y|Z selects the component of a rockwatch suite record, --channel CODE the channel "
                  "of a multi-channel file (miniSEED); give one");
}

// Before the manifest is read, so a wrong combination is reported as such rather than as a manifest problem.
void check_vertical(const RecordSelectionSettings& t, const std::optional<std::string>& channel) {
  if (t.vertical_channel && !t.vertical) {
    throw UsageError("--vertical-channel selects the channel of the --vertical file: give --vertical too");
  }
  if (!t.vertical_from_suite) return;
  if (!t.suite) {
    throw UsageError("--vertical-from-suite pairs the Z component of the same suite set: it needs --suite DIR --set N "
                     "--component X|Y");
  }
  reject_together(t.vertical_from_suite, "--vertical-from-suite", bool(t.vertical), "--vertical", "give one vertical");
  if (channel && *channel == "Z") {
    throw UsageError("--vertical-from-suite needs a horizontal --component, X or Y (got Z: the vertical itself)");
  }
}

}  // namespace record_selection
}  // namespace

void add_record_options(CLI::App& app, RecordOptionTexts& texts, VerticalOptions vertical) {
  using namespace record_selection;
  const bool with_vertical = vertical == VerticalOptions::allowed;
  app.add_option("--record", texts.record,
                 with_vertical ? "Horizontal (out-of-plane) record: PEER AT2, ESM ASCII, ITACA .cor.acc, miniSEED "
                                 "(--channel), rockwatch suite set file (--component), or plain columns [time] u'' [v'']"
                               : "Ground-acceleration record: PEER AT2, ESM ASCII, ITACA .cor.acc, miniSEED (--channel), "
                                 "rockwatch suite set file (--component), or plain columns [time] a [v]")
      ->type_name("FILE");
  app.add_option("--suite", texts.suite, "Record of a rockwatch suite (rockwatch generate) instead of --record: the "
                                         "directory with its manifest.json; needs --set and --component")
      ->type_name("DIR");
  app.add_option("--set", texts.set, "Record set of --suite, from 1")->type_name("N");
  app.add_option("--component", texts.component,
                 "Component of a suite record (--suite, or a suite set file as --record): X or Y (horizontal), "
                 "Z (vertical, up +)")
      ->type_name("X|Y|Z");
  app.add_option("--channel", texts.channel, "Channel of a multi-channel --record file (miniSEED), e.g. HNE")
      ->type_name("CODE");
  if (with_vertical) {
    app.add_option("--vertical", texts.vertical,
                   "Vertical record (up +), resampled onto the --record time grid; zero outside its span")
        ->type_name("FILE");
    app.add_option("--vertical-channel", texts.vertical_channel, "Channel of a multi-channel --vertical file, e.g. HNZ")
        ->type_name("CODE");
    app.add_flag("--vertical-from-suite", texts.vertical_from_suite,
                 "With --suite and --component X or Y: the Z component of the same set as the vertical");
  }
  app.add_option("--units", texts.units,
                 with_vertical ? "Acceleration units of the record files: g|mps2|cmps2|mmps2 (overrides the file)"
                               : "Acceleration units of the record: g|mps2|cmps2|mmps2 (overrides the file)")
      ->type_name("U");
  app.add_option("--dt", texts.dt, "Sample interval of one-column plain files [s]")->type_name("S");
  app.add_option("--gain", texts.gain,
                 with_vertical ? "Sensor gain of miniSEED files in counts per m/s2 (> 0): converts their counts"
                               : "Sensor gain of a miniSEED file in counts per m/s2 (> 0): converts counts")
      ->type_name("COUNTS_PER_MPS2");
}

records::ReadOptions RecordSelection::vertical_read_options() const {
  records::ReadOptions options = read_options;
  options.channel = vertical_channel;
  // --gain converts miniSEED counts: the readers of other formats reject a gain, and a horizontal miniSEED record
  // may well come with a vertical in another format.
  if (vertical_path && !records::looks_like_miniseed(*vertical_path)) options.gain_counts_per_mps2.reset();
  return options;
}

RecordSelection check_record_selection(const RecordSelectionSettings& t, double g_mps2) {
  using namespace record_selection;
  check_source(t);
  RecordSelection s;
  s.read_options.g_mps2 = g_mps2;
  if (t.units) s.read_options.units = parse_units("--units", *t.units);
  if (t.dt_s) s.read_options.dt_s = check_positive_number("--dt", *t.dt_s, " s");
  if (t.gain_counts_per_mps2) {
    s.gain_counts_per_mps2 = check_positive_number("--gain", *t.gain_counts_per_mps2, " counts per m/s2");
    s.read_options.gain_counts_per_mps2 = *s.gain_counts_per_mps2;
  }
  if (t.component) {
    s.channel = std::string(1, parse_component(*t.component));
    s.channel_is_component = true;
  }
  if (t.channel) s.channel = parse_name("--channel", *t.channel, "a channel code");
  check_vertical(t, s.channel);

  if (t.suite) {
    SuiteSelection suite;
    suite.dir = parse_name("--suite", *t.suite, "a suite directory");
    check_input_directory("--suite", suite.dir, "a suite directory written by rockwatch generate");
    suite.set = check_set_number(*t.set);
    suite.component = s.channel->front();
    s.record_path = records::suite_set_path(suite.dir, suite.set);
    suite.name = suite_name(suite.dir);
    s.suite = suite;
  } else {
    s.record_path = parse_name("--record", *t.record, "a file name");
    check_input_file("--record", s.record_path, "a readable record file");
  }
  if (s.channel) s.read_options.channel = *s.channel;

  s.vertical_from_suite = t.vertical_from_suite;
  if (t.vertical) {
    s.vertical_path = parse_name("--vertical", *t.vertical, "a file name");
    check_input_file("--vertical", *s.vertical_path, "a readable record file");
  }
  if (t.vertical_channel) s.vertical_channel = parse_name("--vertical-channel", *t.vertical_channel, "a channel code");
  if (s.vertical_from_suite) {
    s.vertical_path = s.record_path;
    s.vertical_channel = "Z";
  }
  return s;
}

RecordSelectionSettings record_selection_settings(const CLI::App& app, const RecordOptionTexts& t) {
  using namespace record_selection;
  RecordSelectionSettings s;
  using Settings = RecordSelectionSettings;
  const std::pair<const char*, std::optional<std::string> Settings::*> names[] = {
      {"--record", &Settings::record},       {"--suite", &Settings::suite},
      {"--component", &Settings::component}, {"--channel", &Settings::channel},
      {"--vertical", &Settings::vertical},   {"--vertical-channel", &Settings::vertical_channel},
      {"--units", &Settings::units}};
  const std::string* const texts[] = {&t.record,  &t.suite,    &t.component, &t.channel,
                                      &t.vertical, &t.vertical_channel, &t.units};
  for (std::size_t i = 0; i < std::size(names); ++i) {
    if (used(app, names[i].first)) s.*names[i].second = *texts[i];
  }
  s.vertical_from_suite = t.vertical_from_suite;
  // --set is read only with --suite, so "--set 1.5" without --suite is reported as the missing --suite.
  if (used(app, "--set")) s.set = used(app, "--suite") ? parse_set_number(t.set) : 1;
  if (used(app, "--dt")) s.dt_s = parse_finite_number("--dt", t.dt);
  if (used(app, "--gain")) s.gain_counts_per_mps2 = parse_finite_number("--gain", t.gain);
  return s;
}

RecordSelection parse_record_selection(const CLI::App& app, const RecordOptionTexts& t, double g_mps2) {
  using namespace record_selection;
  return check_record_selection(record_selection_settings(app, t), g_mps2);
}

std::string suite_record_text(const SuiteSelection& suite, char component) {
  using namespace record_selection;
  const std::string& name = suite.name.empty() ? suite.dir : suite.name;
  return "suite " + name + " set " + std::to_string(suite.set) + " component " + component;
}

std::string selection_text(const RecordSelection& s) {
  using namespace record_selection;
  if (s.suite) return suite_record_text(*s.suite, s.suite->component);
  if (s.channel) return (s.channel_is_component ? "component " : "channel ") + *s.channel;
  return {};
}

std::string vertical_source_text(const RecordSelection& s) {
  using namespace record_selection;
  if (s.vertical_from_suite) {
    return "component Z of suite set " + std::to_string(s.suite->set) + " (" + s.record_path + ")";
  }
  std::string text = "--vertical " + s.vertical_path.value_or(std::string());
  if (s.vertical_channel) text += " channel " + *s.vertical_channel;
  return text;
}

void add_selection_json(nlohmann::ordered_json& j, const RecordSelection& s) {
  using namespace record_selection;
  if (s.suite) {
    nlohmann::ordered_json suite;
    suite["dir"] = s.suite->dir;
    suite["name"] = s.suite->name;
    suite["set"] = s.suite->set;
    suite["component"] = std::string(1, s.suite->component);
    suite["file"] = s.record_path;
    suite["vertical_component"] =
        s.vertical_from_suite ? nlohmann::ordered_json("Z") : nlohmann::ordered_json(nullptr);
    j["suite"] = suite;
  } else if (s.channel) {
    j[s.channel_is_component ? "component" : "channel"] = *s.channel;
  }
  if (s.vertical_channel && !s.vertical_from_suite) j["vertical_channel"] = *s.vertical_channel;
  if (s.gain_counts_per_mps2) j["gain_counts_per_mps2"] = *s.gain_counts_per_mps2;
}

records::AccelUnit parse_units(const std::string& option, const std::string& text) {
  using namespace record_selection;
  const std::optional<records::AccelUnit> unit = records::parse_accel_unit(text);
  if (!unit) {
    throw UsageError(option + " must be g, mps2, cmps2 or mmps2 (also m/s2, cm/s2, gal, mm/s2) (got " + quoted(text) +
                     ")");
  }
  return *unit;
}

}  // namespace rockwatch::cli
