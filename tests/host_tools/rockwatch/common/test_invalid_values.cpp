// Invalid values and hangs (reliability): one table row per invalid value of every `rockwatch` subcommand
// (wrong type, NaN/inf, negative or zero where a positive number is needed, out of range, empty, a missing file, a
// directory, a FIFO or device instead of a file, options that conflict). Each row runs the real tool and expects exit
// status 2, nothing on stdout and a message "rockwatch COMMAND: error: ..." naming the option and, where it has one,
// the value. Every process has a 20 s deadline: a FIFO with no writer (or no reader), /dev/zero or an absurd work size
// must be refused at once, never waited on.
#include <sys/stat.h>
#include <sys/sysmacros.h>  // makedev
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_process.hpp"
#include "cli_test_files.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::spawn_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::wait_status;
using rockwatch::test::write_text;

namespace {

constexpr double kDeadline_s = 20.0;

// Placeholders in the rows, replaced by the fixture's paths.
struct Fixture {
  TempDir dir;
  std::string record = record_path("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");
  std::string suite = ROCKWATCH_SHIPPED_SUITE_DIR;
  std::string fifo = dir.file("fifo");            // a FIFO no process writes to or reads from
  std::string fifo_png = dir.file("fifo.png");    // the same for --plot, which needs .png
  std::string subdir = dir.file("subdir");        // an existing directory
  std::string missing = dir.file("missing.txt");  // does not exist
  std::string out = dir.file("out.csv");          // a new output file
  std::string list = dir.file("list.txt");        // a --records list naming the record
  std::string study_dir = dir.file("study");      // holds a FIFO named study.json
  std::string device;                             // a character device for outputs: never /dev/null itself as root

  Fixture() {
    if (mkfifo(fifo.c_str(), 0600) != 0 || mkfifo(fifo_png.c_str(), 0600) != 0) throw std::runtime_error("mkfifo");
    if (mkdir(subdir.c_str(), 0700) != 0 || mkdir(study_dir.c_str(), 0700) != 0) throw std::runtime_error("mkdir");
    if (mkfifo((study_dir + "/study.json").c_str(), 0600) != 0) throw std::runtime_error("mkfifo study.json");
    write_text(list, record + "\n");
    // As root a defect that removed a failed run's output would delete /dev/null: use a private copy of the device.
    // Without root /dev/null cannot be removed, so it is safe to name.
    if (geteuid() == 0) {
      device = dir.file("null");
      if (mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) device.clear();
    } else {
      device = "/dev/null";
    }
  }

  std::string expand(const std::string& text) const {
    const std::pair<const char*, const std::string*> names[] = {
        {"{REC}", &record},   {"{SUITE}", &suite},     {"{FIFO}", &fifo}, {"{FIFO_PNG}", &fifo_png},
        {"{DIR}", &subdir},   {"{MISSING}", &missing}, {"{OUT}", &out},   {"{LIST}", &list},
        {"{STUDY}", &study_dir}, {"{DEV}", &device}};
    std::string result = text;
    for (const auto& [name, value] : names) {
      for (std::size_t at = result.find(name); at != std::string::npos; at = result.find(name, at + value->size())) {
        result.replace(at, std::string(name).size(), *value);
      }
    }
    return result;
  }
};

struct Row {
  const char* command;
  std::vector<std::string> args;      // after the command; placeholders expanded
  std::vector<std::string> mentions;  // each must appear in the message; placeholders expanded
};

// clang-format off
const std::vector<Row> kRows = {
    // simulate: numbers
    {"simulate", {"--record", "{REC}", "--scale-pga", "abc"}, {"--scale-pga", "'abc'"}},
    {"simulate", {"--record", "{REC}", "--scale-pga", "nan"}, {"--scale-pga", "'nan'"}},
    {"simulate", {"--record", "{REC}", "--scale-pga", "-0.2"}, {"--scale-pga", "> 0", "-0.2"}},
    {"simulate", {"--record", "{REC}", "--scale-pga", ""}, {"--scale-pga", "''"}},
    {"simulate", {"--record", "{REC}", "--scale-pga", "1e400"}, {"--scale-pga", "'1e400'"}},
    {"simulate", {"--record", "{REC}", "--b", "inf"}, {"--b", "'inf'"}},
    {"simulate", {"--record", "{REC}", "--h1", "0x10"}, {"--h1", "'0x10'"}},
    {"simulate", {"--record", "{REC}", "--h2", " 1.75"}, {"--h2", "' 1.75'"}},
    {"simulate", {"--record", "{REC}", "--rho", "-1800"}, {"--rho", "> 0", "-1800"}},
    {"simulate", {"--record", "{REC}", "--fp", "nan"}, {"--fp", "'nan'"}},
    {"simulate", {"--record", "{REC}", "--a", "1.5"}, {"--a", "[0, 1]", "1.5"}},
    {"simulate", {"--record", "{REC}", "--a-prime", "abc"}, {"--a-prime", "'abc'"}},
    {"simulate", {"--record", "{REC}", "--g", "-9.81"}, {"--g", "> 0", "-9.81"}},
    {"simulate", {"--record", "{REC}", "--wall", ""}, {"--wall", "''"}},
    {"simulate", {"--record", "{REC}", "--r", "-0.1"}, {"--r", "'-0.1'"}},
    {"simulate", {"--record", "{REC}", "--r", ""}, {"--r", "''"}},
    {"simulate", {"--record", "{REC}", "--model", ""}, {"--model", "''"}},
    {"simulate", {"--record", "{REC}", "--kappa", "inf"}, {"--kappa", "'inf'"}},
    {"simulate", {"--record", "{REC}", "--max-step", "-0.001"}, {"--max-step", "> 0", "-0.001"}},
    {"simulate", {"--record", "{REC}", "--max-step", "1e-300"}, {"--max-step", "steps"}},
    {"simulate", {"--record", "{REC}", "--t-end", "nan"}, {"--t-end", "'nan'"}},
    {"simulate", {"--record", "{REC}", "--t-end", "-1"}, {"--t-end", ">= 0", "-1"}},
    {"simulate", {"--record", "{REC}", "--t-end", "1e12"}, {"--t-end", "steps"}},
    {"simulate", {"--record", "{REC}", "--arith", ""}, {"--arith", "''"}},
    {"simulate", {"--record", "{REC}", "--arith", "fixed", "--model", "full"}, {"--arith fixed", "--model full"}},
    {"simulate", {"--record", "{REC}", "--alarms", "--lambda-w", "nan"}, {"--lambda-w", "'nan'"}},
    {"simulate", {"--record", "{REC}", "--alarms", "--lambda-w", "1.5"}, {"--lambda-w", "1.5"}},
    {"simulate", {"--record", "{REC}", "--alarms", "--alarm-hold", "-1"}, {"--alarm-hold", "-1"}},
    {"simulate", {"--record", "{REC}", "--alarms", "--alarm-hold", "1e9"}, {"--alarm-hold", "1e+09"}},
    {"simulate", {"--record", "{REC}", "--alarms", "--energy-margin", "0.5"}, {"--energy-margin", "0.5"}},
    {"simulate", {"--record", "{REC}", "--energy-margin", "2"}, {"--energy-margin", "--alarms"}},
    // simulate: record selection
    {"simulate", {"--record", ""}, {"--record", "a file name"}},
    {"simulate", {"--record", "{MISSING}"}, {"--record", "{MISSING}", "does not exist"}},
    {"simulate", {"--record", "{DIR}"}, {"--record", "{DIR}", "is a directory"}},
    {"simulate", {"--record", "{FIFO}"}, {"--record", "{FIFO}", "FIFO", "not a regular file"}},
    {"simulate", {"--record", "/dev/zero"}, {"--record", "/dev/zero", "character device"}},
    {"simulate", {"--record", "/dev/stdin"}, {"--record", "/dev/stdin", "not a regular file"}},
    {"simulate", {"--record", "{REC}", "--vertical", "{MISSING}"}, {"--vertical", "{MISSING}", "does not exist"}},
    {"simulate", {"--record", "{REC}", "--vertical", "{FIFO}"}, {"--vertical", "{FIFO}", "FIFO"}},
    {"simulate", {"--record", "{REC}", "--vertical", "{DIR}"}, {"--vertical", "is a directory"}},
    {"simulate", {"--record", "{REC}", "--units", "furlongs"}, {"--units", "'furlongs'"}},
    {"simulate", {"--record", "{REC}", "--units", ""}, {"--units", "''"}},
    {"simulate", {"--record", "{REC}", "--dt", "0"}, {"--dt", "> 0"}},
    {"simulate", {"--record", "{REC}", "--dt", "nan"}, {"--dt", "'nan'"}},
    {"simulate", {"--record", "{REC}", "--gain", "-5"}, {"--gain", "> 0", "-5"}},
    {"simulate", {"--record", "{REC}", "--channel", ""}, {"--channel", "a channel code"}},
    {"simulate", {"--record", "{REC}", "--component", "W"}, {"--component", "'W'"}},
    {"simulate", {"--record", "{REC}", "--component", ""}, {"--component", "''"}},
    {"simulate", {"--record", "{REC}", "--component", "X", "--channel", "HNE"}, {"--component", "--channel"}},
    {"simulate", {"--record", "{REC}", "--suite", "{SUITE}"}, {"--record", "--suite"}},
    {"simulate", {"--suite", "{SUITE}", "--set", "0", "--component", "X"}, {"--set", "'0'"}},
    {"simulate", {"--suite", "{SUITE}", "--set", "1.5", "--component", "X"}, {"--set", "'1.5'"}},
    {"simulate", {"--suite", "{SUITE}", "--set", "99999999999", "--component", "X"}, {"--set", "'99999999999'"}},
    {"simulate", {"--suite", "{MISSING}", "--set", "1", "--component", "X"}, {"--suite", "{MISSING}", "no such directory"}},
    {"simulate", {"--suite", "{FIFO}", "--set", "1", "--component", "X"}, {"--suite", "{FIFO}", "FIFO"}},
    {"simulate", {"--suite", "", "--set", "1", "--component", "X"}, {"--suite", "a suite directory"}},
    {"simulate", {"--suite", "{SUITE}", "--set", "1", "--component", "Z", "--vertical-from-suite"}, {"--vertical-from-suite", "Z"}},
    {"simulate", {"--record", "{REC}", "--vertical-channel", "HNZ"}, {"--vertical-channel", "--vertical"}},
    // simulate: the output file
    {"simulate", {"--record", "{REC}", "--out", ""}, {"--out", "a file name"}},
    {"simulate", {"--record", "{REC}", "--out", "{DIR}"}, {"--out", "{DIR}", "is a directory"}},
    {"simulate", {"--record", "{REC}", "--out", "{FIFO}"}, {"--out", "{FIFO}", "FIFO", "not a regular file"}},
    {"simulate", {"--record", "{REC}", "--out", "{DEV}"}, {"--out", "{DEV}", "character device"}},
    {"simulate", {"--record", "{REC}", "--out", "{REC}"}, {"--out", "input record"}},
    {"simulate", {"--record", "{REC}", "--out", "{MISSING}/x.csv"}, {"--out", "{MISSING}/x.csv"}},

    // spectrum
    {"spectrum", {"--record", "{REC}", "--g", "0"}, {"--g", "> 0"}},
    {"spectrum", {"--record", "{REC}", "--damping", "1"}, {"--damping", "[0, 1)", "1"}},
    {"spectrum", {"--record", "{REC}", "--damping", "nan"}, {"--damping", "'nan'"}},
    {"spectrum", {"--record", "{REC}", "--damping", "-0.05"}, {"--damping", "-0.05"}},
    {"spectrum", {"--record", "{REC}", "--periods", "abc"}, {"--periods", "'abc'"}},
    {"spectrum", {"--record", "{REC}", "--periods", "0.02:4:1e9"}, {"--periods", "N"}},
    {"spectrum", {"--record", "{REC}", "--periods", "4:0.02:100"}, {"--periods", "TO", "'4:0.02:100'"}},
    {"spectrum", {"--record", "{REC}", "--periods", "0.02:4:99999999"}, {"--periods", "'0.02:4:99999999'"}},
    {"spectrum", {"--record", "{REC}", "--periods", ""}, {"--periods", "''"}},
    {"spectrum", {"--record", "{REC}", "--target", "ec9"}, {"--target", "'ec9'"}},
    {"spectrum", {"--record", "{REC}", "--target", "ec8-1A"}, {"--target", "--pga"}},
    {"spectrum", {"--record", "{REC}", "--target", "ec8-1A", "--pga", "inf"}, {"--pga", "'inf'"}},
    {"spectrum", {"--record", "{REC}", "--pga", "0.2"}, {"--pga", "--target"}},
    {"spectrum", {"--record", "{REC}", "--target", "custom", "--pga", "0.2", "--p", "2.5", "--tb", "0.3", "--tc", "0.1", "--td", "1"}, {"--tc", "--tb"}},
    {"spectrum", {"--record", "{REC}", "--target", "custom", "--pga", "0.2", "--p", "nan", "--tb", "0.1", "--tc", "0.3", "--td", "1"}, {"--p", "'nan'"}},
    {"spectrum", {"--record", "{REC}", "--target", "custom", "--pga", "0.2"}, {"--target custom", "--p"}},
    {"spectrum", {"--record", "{FIFO}"}, {"--record", "{FIFO}", "FIFO"}},
    {"spectrum", {"--record", "/dev/zero"}, {"--record", "/dev/zero", "character device"}},
    {"spectrum", {"--record", "{REC}", "--vertical", "{REC}"}, {"--vertical"}},
    {"spectrum", {"--record", "{REC}", "--out", "{FIFO}"}, {"--out", "{FIFO}", "FIFO"}},
    {"spectrum", {"--record", "{REC}", "--out", "{DEV}"}, {"--out", "{DEV}", "character device"}},
    {"spectrum", {"--record", "{REC}", "--out", "{DIR}"}, {"--out", "{DIR}", "is a directory"}},
    {"spectrum", {"--record", "{REC}", "--plot", "{FIFO_PNG}"}, {"--plot", "{FIFO_PNG}", "FIFO"}},
    {"spectrum", {"--record", "{REC}", "--plot", "{DEV}"}, {"--plot", "{DEV}", ".png"}},
    {"spectrum", {"--record", "{REC}", "--plot", "{OUT}"}, {"--plot", "{OUT}", ".png"}},
    {"spectrum", {"--record", "{REC}", "--plot", "figure"}, {"--plot", "'figure'", ".png"}},
    {"spectrum", {"--record", "{REC}", "--plot", ""}, {"--plot", "a file name"}},

    // static
    {"static", {"--b", "abc"}, {"--b", "'abc'"}},
    {"static", {"--h", "nan"}, {"--h", "'nan'"}},
    {"static", {"--h", "0.05"}, {"--h", "greater than b"}},
    {"static", {"--h", "3", "--h1", "1.5"}, {"--h", "--h1"}},
    {"static", {"--fp", "-1"}, {"--fp", "-1"}},
    {"static", {"--a", "inf"}, {"--a", "'inf'"}},
    {"static", {"--psi", "1"}, {"--psi", "K > 0"}},
    {"static", {"--rho", "0"}, {"--rho", "0"}},
    {"static", {"--g", ""}, {"--g", "''"}},
    {"static", {"--lambda", "1"}, {"--lambda", "(0, 1)"}},
    {"static", {"--lambda", "0"}, {"--lambda", "(0, 1)"}},
    {"static", {"--lambda", "1e-320"}, {"--lambda"}},
    {"static", {"--lambda", "0.5", "--code", "ntc2008"}, {"--lambda", "--code"}},
    {"static", {"--code", "ec8"}, {"--code", "'ec8'"}},
    {"static", {"--spectrum", ""}, {"--spectrum", "''"}},
    {"static", {"--spectrum", "custom", "--p", "0.5", "--tb", "0.1", "--tc", "0.3", "--td", "1"}, {"--p", "0.5"}},
    {"static", {"--p", "2.5"}, {"--p", "--spectrum custom"}},
    {"static", {"--wall", "brick"}, {"--wall", "'brick'"}},
    {"static", {"--sweep"}, {"--sweep", "--out"}},
    {"static", {"--out", "{DIR}"}, {"--out", "--sweep"}},
    {"static", {"--sweep", "--out", "{FIFO}"}, {"--out", "{FIFO}"}},
    {"static", {"--sweep", "--out", "{OUT}", "--json"}, {"--json", "--sweep"}},

    // generate
    {"generate", {}, {"--out"}},
    {"generate", {"--out", ""}, {"--out"}},
    {"generate", {"--out", "{FIFO}"}, {"--out", "{FIFO}"}},
    {"generate", {"--out", "{DIR}", "--sets", "0"}, {"--sets", "'0'"}},
    {"generate", {"--out", "{DIR}", "--sets", "abc"}, {"--sets", "'abc'"}},
    {"generate", {"--out", "{DIR}", "--sets", "101"}, {"--sets", "'101'"}},
    {"generate", {"--out", "{DIR}", "--seed", "-1"}, {"--seed", "'-1'"}},
    {"generate", {"--out", "{DIR}", "--seed", "18446744073709551616"}, {"--seed", "'18446744073709551616'"}},
    {"generate", {"--out", "{DIR}", "--target", "ec9"}, {"--target", "'ec9'"}},
    {"generate", {"--out", "{DIR}", "--target", "custom:2.5,0.1,0.3"}, {"--target", "'custom:2.5,0.1,0.3'"}},
    {"generate", {"--out", "{DIR}", "--vertical-target", "custom:nan,0.1,0.3,1"}, {"--vertical-target", "'custom:nan,0.1,0.3,1'"}},
    {"generate", {"--out", "{DIR}", "--pga", "inf"}, {"--pga", "'inf'"}},
    {"generate", {"--out", "{DIR}", "--pga", "1e-320"}, {"--pga", "1e-06"}},
    {"generate", {"--out", "{DIR}", "--pga", "1e9"}, {"--pga", "1e+09"}},
    {"generate", {"--out", "{DIR}", "--vertical-ratio", "1e-320"}, {"--vertical-ratio", "0.001"}},
    {"generate", {"--out", "{DIR}", "--vertical-ratio", "abc"}, {"--vertical-ratio", "'abc'"}},
    {"generate", {"--out", "{DIR}", "--dt", "1e9"}, {"--dt", "0.025", "1e+09"}},
    {"generate", {"--out", "{DIR}", "--dt", "nan"}, {"--dt", "'nan'"}},
    {"generate", {"--out", "{DIR}", "--duration", "1e9"}, {"--duration", "samples"}},
    {"generate", {"--out", "{DIR}", "--duration", "5"}, {"duration"}},
    {"generate", {"--out", "{DIR}", "--iterations", "0"}, {"--iterations", "'0'"}},
    {"generate", {"--out", "{DIR}", "--iterations", "1.5"}, {"--iterations", "'1.5'"}},

    // study
    {"study", {"--sets", "1"}, {"--out"}},
    {"study", {"--out", "{DIR}", "--sets", "0"}, {"--sets", "'0'"}},
    {"study", {"--out", "{DIR}", "--sets", "3-1"}, {"--sets", "'3-1'"}},
    {"study", {"--out", "{DIR}", "--sets", ""}, {"--sets", "''"}},
    {"study", {"--out", "{DIR}", "--pga", "0.1:0.2"}, {"--pga", "'0.1:0.2'"}},
    {"study", {"--out", "{DIR}", "--pga", "nan:0.2:0.01"}, {"--pga", "FROM"}},
    {"study", {"--out", "{DIR}", "--pga", "0.01:100:1e-9"}, {"--pga", "levels"}},
    {"study", {"--out", "{DIR}", "--r", "ana,,exp"}, {"--r", "'ana,,exp'"}},
    {"study", {"--out", "{DIR}", "--r", "exp,exp"}, {"--r", "twice"}},
    {"study", {"--out", "{DIR}", "--vertical", "sometimes"}, {"--vertical", "'sometimes'"}},
    {"study", {"--out", "{DIR}", "--kappa", "0"}, {"--kappa", ">= 1"}},
    {"study", {"--out", "{DIR}", "--max-step", "1e-320"}, {"--max-step", "1e-06"}},
    {"study", {"--out", "{DIR}", "--max-step", "1e-9"}, {"--max-step", "1e-09"}},
    {"study", {"--out", "{DIR}", "--jobs", "-1"}, {"--jobs", "'-1'"}},
    {"study", {"--out", "{DIR}", "--jobs", "1e3"}, {"--jobs", "'1e3'"}},
    {"study", {"--out", "{DIR}", "--arith", "float"}, {"--arith", "'float'"}},
    {"study", {"--out", "{DIR}", "--lambda-w", "0.5"}, {"--lambda-w", "--alarms"}},
    {"study", {"--out", "{DIR}", "--units", "g"}, {"--units", "--records"}},
    {"study", {"--out", "{DIR}", "--suite", "{SUITE}", "--records", "{LIST}"}, {"--suite", "--records"}},
    {"study", {"--out", "{DIR}", "--records", "{LIST}", "--sets", "1"}, {"--sets", "--records"}},
    {"study", {"--out", "{DIR}", "--records", "{LIST}", "--dt", "-1"}, {"--dt", "> 0"}},
    {"study", {"--out", "{DIR}", "--records", "{LIST}", "--gain", "nan"}, {"--gain", "'nan'"}},
    {"study", {"--out", "{DIR}", "--records", "{MISSING}"}, {"--records", "{MISSING}", "does not exist"}},
    {"study", {"--out", "{DIR}", "--records", "{DIR}"}, {"--records", "{DIR}", "is a directory"}},
    {"study", {"--out", "{DIR}", "--records", "{FIFO}"}, {"--records", "{FIFO}", "FIFO"}},
    {"study", {"--out", "{DIR}", "--records", "/dev/zero"}, {"--records", "/dev/zero", "character device"}},
    {"study", {"--out", "{DIR}", "--suite", "{MISSING}"}, {"--suite", "{MISSING}", "no such directory"}},
    {"study", {"--out", "{DIR}", "--suite", "{LIST}"}, {"--suite", "{LIST}", "regular file"}},
    {"study", {"--out", "{FIFO}"}, {"--out", "{FIFO}"}},
    {"study", {"--out", "{STUDY}", "--resume"}, {"--out", "study.json", "FIFO"}},
    {"study", {"--out", "{DIR}", "--resume", "--force"}, {"--resume", "--force"}},

    // replay (--log alone: no network needed)
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--rate", "1e-320"}, {"--rate", "at least 1 Hz"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--rate", "0.5"}, {"--rate", "0.5"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--rate", "nan"}, {"--rate", "'nan'"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--rate", "1e6"}, {"--rate", "10000"}},
    {"replay", {"--record", "{REC}", "--lcm-url", "memq://", "--speed", "1e-9"}, {"--speed", "0.01", "1e-09"}},
    {"replay", {"--record", "{REC}", "--lcm-url", "memq://", "--speed", "inf"}, {"--speed", "'inf'"}},
    {"replay", {"--record", "{REC}", "--lcm-url", ""}, {"--lcm-url", "URL"}},
    {"replay", {"--record", "{REC}", "--lcm-channel", ""}, {"--lcm-channel", "channel name"}},
    {"replay", {"--record", "{REC}", "--lcm-channel", std::string(64, 'C')}, {"--lcm-channel", "63"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--batch", "0"}, {"--batch", "'0'"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--batch", "51"}, {"--batch", "'51'"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--noise-mps2", "-1"}, {"--noise-mps2", "-1"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--seed", "abc"}, {"--seed", "'abc'"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--bias-mps2", "inf"}, {"--bias-mps2", "'inf'"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--quantum-mps2", "0"}, {"--quantum-mps2", "> 0"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--dropout", "1"}, {"--dropout", "[0, 1)"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--scale-pga", "0"}, {"--scale-pga", "> 0"}},
    {"replay", {"--record", "{FIFO}", "--log", "{OUT}"}, {"--record", "{FIFO}", "FIFO"}},
    {"replay", {"--record", "/dev/zero", "--log", "{OUT}"}, {"--record", "/dev/zero", "character device"}},
    {"replay", {"--record", "{REC}", "--log", "{FIFO}"}, {"--log", "{FIFO}", "FIFO"}},
    {"replay", {"--record", "{REC}", "--log", "{DEV}"}, {"--log", "{DEV}", "character device"}},
    {"replay", {"--record", "{REC}", "--log", "{DIR}"}, {"--log", "{DIR}", "is a directory"}},
    {"replay", {"--record", "{REC}", "--log", ""}, {"--log", "a file name"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--samples-out", "{FIFO}"}, {"--samples-out", "{FIFO}", "FIFO"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--samples-out", "{OUT}"}, {"--log", "--samples-out"}},
    {"replay", {"--record", "{REC}", "--log", "{REC}"}, {"--log", "input record"}},
    {"replay", {"--record", "{REC}", "--log", "{OUT}", "--speed", "2"}, {"--speed", "--log"}},

    // demo (rejected while the command line is parsed: no monitor, no network)
    {"demo", {"--set", "0"}, {"--set", "'0'"}},
    {"demo", {"--set", "abc"}, {"--set", "'abc'"}},
    {"demo", {"--pga", "nan"}, {"--pga", "'nan'"}},
    {"demo", {"--pga", "1e9"}, {"--pga", "1e+09"}},
    {"demo", {"--rate", "1e-320"}, {"--rate", "the monitor's range"}},
    {"demo", {"--rate", "20"}, {"--rate", "20"}},
    {"demo", {"--rate", "1e6"}, {"--rate", "10000"}},
    {"demo", {"--speed", "1e-320"}, {"--speed", "0.01", "1e-320"}},
    {"demo", {"--speed", "inf"}, {"--speed", "'inf'"}},
    {"demo", {"--lcm-url", "memq://"}, {"--lcm-url", "'memq://'"}},
    {"demo", {"--monitor", ""}, {"--monitor"}},
    {"demo", {"--out", ""}, {"--out"}},
    {"demo", {"--suite", "{MISSING}"}, {"--suite", "{MISSING}", "no such directory"}},
    {"demo", {"--suite", "{FIFO}"}, {"--suite", "{FIFO}", "FIFO"}},
    {"demo", {"--suite", ""}, {"--suite"}},
};
// clang-format on

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string row_text(const std::string& command, const std::vector<std::string>& args) {
  std::string text = "rockwatch " + command;
  for (const std::string& a : args) text += " '" + a + "'";
  return text;
}

// Runs one row with the short deadline; returns what is wrong with it, or nothing.
std::string check_row(const Fixture& f, const Row& row) {
  std::vector<std::string> args{row.command};
  for (const std::string& a : row.args) args.push_back(f.expand(a));
  const std::string shown = row_text(row.command, std::vector<std::string>(args.begin() + 1, args.end()));
  const TempDir capture;
  const std::string out_path = capture.file("stdout"), err_path = capture.file("stderr");
  int status = 0;
  try {
    status = wait_status(spawn_rockwatch(args, out_path, err_path), kDeadline_s);
  } catch (const std::exception& e) {
    return shown + ": " + e.what();
  }
  ProcessResult r;
  if (WIFEXITED(status)) r.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  std::string problems;
  if (r.signal != 0) problems += " killed by signal " + std::to_string(r.signal) + ";";
  if (r.exit_status != 2) problems += " exit status " + std::to_string(r.exit_status) + ", expected 2;";
  if (!r.out.empty()) problems += " stdout not empty;";
  if (r.err.rfind(std::string("rockwatch ") + row.command + ": error: ", 0) != 0) problems += " no error prefix;";
  for (const std::string& m : row.mentions) {
    const std::string expected = f.expand(m);
    if (r.err.find(expected) == std::string::npos) problems += " message lacks \"" + expected + "\";";
  }
  if (problems.empty()) return {};
  return shown + ":" + problems + "\n  stderr: " + r.err;
}

}  // namespace

TEST_GROUP(InvalidValues){};

namespace {

// The rows [begin, end) of the table, each reported on its own when it fails; returns how many were run.
int check_rows(std::size_t begin, std::size_t end) {
  const Fixture f;
  std::string failures;
  int checked = 0;
  for (std::size_t i = begin; i < end && i < kRows.size(); ++i) {
    const Row& row = kRows[i];
    const bool needs_device = std::find(row.args.begin(), row.args.end(), "{DEV}") != row.args.end();
    if (needs_device && f.device.empty()) continue;  // no device could be made (root without mknod)
    failures += check_row(f, row);
    ++checked;
  }
  CHECK_TEXT(failures.empty(), ("\n" + failures).c_str());
  return checked;
}

}  // namespace

// Every row of the table, in two halves so that each half (a sanitized process per row) is a ctest entry of its own.
TEST(InvalidValues, EveryRowIsRefusedNamingTheOptionFirstHalf) {
  CHECK(check_rows(0, kRows.size() / 2) >= 95);
}

TEST(InvalidValues, EveryRowIsRefusedNamingTheOptionSecondHalf) {
  CHECK(check_rows(kRows.size() / 2, kRows.size()) >= 95);
}

// A failed run must not remove a device given as its output (as root, /dev/null itself would go): the device is
// refused before anything is opened, and it is still there afterwards.
TEST(InvalidValues, ADeviceGivenAsOutputIsLeftInPlace) {
  const Fixture f;
  if (f.device.empty()) return;
  const std::vector<std::vector<std::string>> runs = {
      {"simulate", "--record", f.record, "--out", f.device, "--t-end", "-1"},
      {"spectrum", "--record", f.record, "--plot", f.device},
      {"replay", "--record", f.record, "--log", f.device, "--rate", "0"},
  };
  for (const auto& args : runs) {
    const TempDir capture;
    const int status = wait_status(spawn_rockwatch(args, "/dev/null", capture.file("err")), kDeadline_s);
    CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 2, row_text(args[0], args).c_str());
    struct stat st {};
    CHECK_TEXT(stat(f.device.c_str(), &st) == 0 && S_ISCHR(st.st_mode), ("device removed by " + args[0]).c_str());
  }
}

// A FIFO that gets a writer later still must not be read: the tool refuses it at once rather than blocking in open().
TEST(InvalidValues, AFifoRecordIsNotOpened) {
  const Fixture f;
  const TempDir capture;
  const pid_t pid = spawn_rockwatch({"simulate", "--record", f.fifo}, "/dev/null", capture.file("err"));
  const int status = wait_status(pid, kDeadline_s);
  CHECK(WIFEXITED(status));
  LONGS_EQUAL(2, WEXITSTATUS(status));
  STRCMP_CONTAINS("not a regular file", slurp(capture.file("err")).c_str());
}
