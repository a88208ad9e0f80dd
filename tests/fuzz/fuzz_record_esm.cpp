// ESM ASCII reader (records::read_esm_ascii) and its detector, on any bytes. Seeds: tests/fuzz/corpus/record_esm.
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_esm");
  static const std::vector<records::ReadOptions> options{{}, fuzz::options_with(records::AccelUnit::mps2, 0.005)};
  const std::string& path = file.write(data, size);
  (void)records::looks_like_esm_ascii(path);
  fuzz::read_with_each(path, options, records::read_esm_ascii);
  return 0;
}
