// The suite directory's manifest.json (records::suite_sets, suite_set_path) on any bytes: the input is written as
// manifest.json in a scratch directory. Seeds: tests/fuzz/corpus/suite_manifest (cut from
// sim/suites/npr9998-2015/manifest.json).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/suite_format.hpp"

using namespace rockwatch;

namespace {

// A directory per process, removed at exit.
struct ScratchDir {
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "rockwatch_fuzz_manifest_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) std::abort();
    dir = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
  std::string dir;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static ScratchDir scratch;
  {
    std::ofstream out(scratch.dir + "/manifest.json", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) std::abort();
  }
  try {
    const std::vector<int> sets = records::suite_sets(scratch.dir);
    for (const int set : sets) ROCKWATCH_FUZZ_CHECK(set >= 1);
    const std::string path = records::suite_set_path(scratch.dir, sets.empty() ? 1 : sets.front());
    // check_relative: a set file is inside the suite directory.
    ROCKWATCH_FUZZ_CHECK(path.rfind(scratch.dir + "/", 0) == 0);
    for (const std::filesystem::path& part : std::filesystem::path(path.substr(scratch.dir.size()))) {
      ROCKWATCH_FUZZ_CHECK(part != "..");
    }
  } catch (const records::RecordError& error) {
    ROCKWATCH_FUZZ_CHECK(error.what()[0] != '\0');
  }
  return 0;
}
