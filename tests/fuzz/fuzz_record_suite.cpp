// rockwatch suite set files (records::read_suite_record, read_suite_component and the detector) on any bytes.
// Seeds: tests/fuzz/corpus/record_suite (cut from sim/suites/npr9998-2015).
#include <cstddef>
#include <cstdint>

#include "record_fuzz_support.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/suite_format.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_record_suite");
  static const std::vector<records::ReadOptions> options{
      fuzz::options_with(std::nullopt, std::nullopt, std::nullopt, "z")};
  const std::string& path = file.write(data, size);
  (void)records::looks_like_suite_record(path);
  try {
    const records::SuiteRecordFile suite = records::read_suite_record(path);
    // suite_format.hpp: three components of equal, non-zero length, finite values, a positive dt.
    ROCKWATCH_FUZZ_CHECK(std::isfinite(suite.dt_s) && suite.dt_s > 0.0);
    ROCKWATCH_FUZZ_CHECK(!suite.components_mps2[0].empty());
    for (const std::vector<double>& component : suite.components_mps2) {
      ROCKWATCH_FUZZ_CHECK(component.size() == suite.components_mps2[0].size());
      ROCKWATCH_FUZZ_CHECK(fuzz::all_finite(component));
    }
    fuzz::read_with_each(path, options, records::read_suite_component);
  } catch (const records::RecordError&) {
  }
  return 0;
}
