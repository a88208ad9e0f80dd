// miniSEED reader (records::read_miniseed: libmseed's msr_parse from memory, channel choice, merging, counts to m/s²)
// and its detector, on any bytes. Seeds: tests/fuzz/corpus/record_miniseed (records cut from NL.BGAR.mseed).
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_miniseed");
  // Integer counts with --gain (any channel when there is one; HGE by code); floating-point samples with --units.
  static const std::vector<records::ReadOptions> options{
      fuzz::options_with(std::nullopt, std::nullopt, 213867.4766),
      fuzz::options_with(std::nullopt, 0.005, 213867.4766, "HGE"),
      fuzz::options_with(records::AccelUnit::mps2, std::nullopt, std::nullopt, "NL.BGAR..HGZ")};
  const std::string& path = file.write(data, size);
  (void)records::looks_like_miniseed(path);
  fuzz::read_with_each(path, options, records::read_miniseed);
  return 0;
}
