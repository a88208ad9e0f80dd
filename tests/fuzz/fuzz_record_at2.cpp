// PEER NGA .AT2 reader (records::read_peer_at2) and its detector, on any bytes. Seeds: tests/fuzz/corpus/record_at2.
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_at2");
  // The header's units, and --units/--dt given (notes, the units override).
  static const std::vector<records::ReadOptions> options{{}, fuzz::options_with(records::AccelUnit::cmps2, 0.02)};
  const std::string& path = file.write(data, size);
  (void)records::looks_like_peer_at2(path);
  fuzz::read_with_each(path, options, records::read_peer_at2);
  return 0;
}
