// Wall-sensor CSV reader (records::read_wall_sensor_csv) on any bytes. Seeds: tests/fuzz/corpus/wall_sensor_csv.
// Contract: a file with at least one row, a time column and a sensor column, times strictly increasing, every valid
// value finite, and every row's line within the file; or a RecordError.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_support.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/wall_sensor_csv.hpp"

using namespace rockwatch;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file("fuzz_wall_sensor_csv");
  static const bool verbose = std::getenv("ROCKWATCH_FUZZ_VERBOSE") != nullptr;
  try {
    const records::WallSensorFile f = records::read_wall_sensor_csv(file.write(data, size));
    ROCKWATCH_FUZZ_CHECK(!f.rows.empty());
    ROCKWATCH_FUZZ_CHECK(f.has_x_column || f.has_a_column);
    for (std::size_t i = 0; i < f.rows.size(); ++i) {
      const records::WallSensorRow& r = f.rows[i];
      ROCKWATCH_FUZZ_CHECK(i == 0 || r.utime_us > f.rows[i - 1].utime_us);
      ROCKWATCH_FUZZ_CHECK(r.line >= 2 && static_cast<std::size_t>(r.line) <= size);
      ROCKWATCH_FUZZ_CHECK(!r.x_valid || (f.has_x_column && std::isfinite(r.x_mid_m)));
      ROCKWATCH_FUZZ_CHECK(!r.a_valid || (f.has_a_column && std::isfinite(r.a_mid_mps2)));
      ROCKWATCH_FUZZ_CHECK(std::llabs(r.utime_us) <= 1000000000000000LL);
    }
    if (verbose) std::fprintf(stderr, "read: %zu rows\n", f.rows.size());
  } catch (const records::RecordError& error) {
    ROCKWATCH_FUZZ_CHECK(error.what()[0] != '\0');
    if (verbose) std::fprintf(stderr, "RecordError: %s\n", error.what());
  }
  return 0;
}
