// Plain text / CSV reader (records::read_plain_text) on any bytes. Seeds: tests/fuzz/corpus/record_plain.
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_plain");
  // Units from the file (comment, column names), and --units g --dt 0.01 (one-column files, the override notes).
  static const std::vector<records::ReadOptions> options{{}, fuzz::options_with(records::AccelUnit::g, 0.01)};
  fuzz::read_with_each(file.write(data, size), options, records::read_plain_text);
  return 0;
}
