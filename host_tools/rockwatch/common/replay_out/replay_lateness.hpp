// Lateness of a paced replay: for each message, the time its publish call returned minus its deadline. Kept per
// message (8 bytes each) so the percentiles are exact; summarised as p50, p99, max, mean and a fixed histogram.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rockwatch::cli {

struct LatenessBin {
  std::optional<double> from_us;  // none for the first bin (everything below its upper edge, early ones included)
  std::optional<double> to_us;    // none for the last bin
  std::size_t count = 0;
};

struct LatenessSummary {
  std::size_t count = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0, mean_us = 0.0;  // nearest-rank percentiles
  std::vector<LatenessBin> histogram;                              // < 10 us, 10-20, 20-50, ..., 5-10 ms, >= 10 ms
};

// Empty `lateness_ns` gives count 0 and empty bins.
LatenessSummary summarise_lateness(std::vector<std::int64_t> lateness_ns);

// "p50 12 us, p99 85 us, max 0.41 ms, mean 15 us over 4001 messages" and the histogram, one bin a line, each line
// starting with `indent`.
std::string lateness_text(const LatenessSummary& s, const std::string& indent);

// {"count", "p50_us", "p99_us", "max_us", "mean_us", "histogram": [{"from_us", "to_us", "count"}]}
nlohmann::ordered_json lateness_json(const LatenessSummary& s);

// "85 us", "1.2 ms": a duration in microseconds as people read it.
std::string microseconds_text(double us);

}  // namespace rockwatch::cli
