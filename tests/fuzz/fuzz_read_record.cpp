// records::read_record: format detection from the content (miniSEED, suite, ESM, ITACA, AT2, else plain) and the
// reader it dispatches to, on any bytes. Seeds: every record corpus (tests/fuzz/corpus/read_record holds a few of
// each format; scripts/fuzz.sh also passes the per-format corpora).
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_read_record");
  // No options (what `rockwatch simulate --record FILE` passes), and the options a user adds when told to.
  static const std::vector<records::ReadOptions> options{
      {}, fuzz::options_with(records::AccelUnit::cmps2, 0.01),
      fuzz::options_with(std::nullopt, std::nullopt, std::nullopt, "X"),
      fuzz::options_with(std::nullopt, std::nullopt, 1000.0)};
  fuzz::read_with_each(file.write(data, size), options, records::read_record);
  return 0;
}
