// ITACA .cor.acc reader (records::read_itaca_cor_acc) and its detector, on any bytes. Seeds:
// tests/fuzz/corpus/record_itaca.
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_itaca");
  static const std::vector<records::ReadOptions> options{{}, fuzz::options_with(records::AccelUnit::g, 0.01)};
  const std::string& path = file.write(data, size);
  (void)records::looks_like_itaca_cor_acc(path);
  fuzz::read_with_each(path, options, records::read_itaca_cor_acc);
  return 0;
}
