#include "common/replay_out/replay_lateness.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace rockwatch::cli {

namespace {

// Bin edges [us]: a 1-2-5 series from 10 us to 10 ms.
constexpr double kEdgesUs[] = {10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000};

double percentile_us(const std::vector<std::int64_t>& sorted_ns, double p) {
  const auto n = static_cast<double>(sorted_ns.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(p * n)));
  return static_cast<double>(sorted_ns[rank - 1]) * 1e-3;
}

std::string bin_label(const LatenessBin& b) {
  if (!b.from_us) return "< " + microseconds_text(*b.to_us);
  if (!b.to_us) return ">= " + microseconds_text(*b.from_us);
  return microseconds_text(*b.from_us) + " - " + microseconds_text(*b.to_us);
}

}  // namespace

std::string microseconds_text(double us) {
  char text[32];
  if (std::fabs(us) < 1000.0) {
    std::snprintf(text, sizeof text, "%.0f us", us);
  } else if (std::fabs(us) < 1e6) {
    std::snprintf(text, sizeof text, "%.3g ms", us * 1e-3);
  } else {
    std::snprintf(text, sizeof text, "%.3g s", us * 1e-6);
  }
  return text;
}

LatenessSummary summarise_lateness(std::vector<std::int64_t> lateness_ns) {
  LatenessSummary s;
  constexpr std::size_t kBins = sizeof kEdgesUs / sizeof kEdgesUs[0] + 1;
  s.histogram.resize(kBins);
  for (std::size_t b = 0; b < kBins; ++b) {
    if (b > 0) s.histogram[b].from_us = kEdgesUs[b - 1];
    if (b + 1 < kBins) s.histogram[b].to_us = kEdgesUs[b];
  }
  s.count = lateness_ns.size();
  if (lateness_ns.empty()) return s;
  std::sort(lateness_ns.begin(), lateness_ns.end());
  double sum_ns = 0.0;
  for (const std::int64_t ns : lateness_ns) {
    sum_ns += static_cast<double>(ns);
    const double us = static_cast<double>(ns) * 1e-3;
    std::size_t b = 0;
    while (b + 1 < kBins && us >= kEdgesUs[b]) ++b;
    ++s.histogram[b].count;
  }
  s.p50_us = percentile_us(lateness_ns, 0.50);
  s.p99_us = percentile_us(lateness_ns, 0.99);
  s.max_us = static_cast<double>(lateness_ns.back()) * 1e-3;
  s.mean_us = sum_ns / static_cast<double>(lateness_ns.size()) * 1e-3;
  return s;
}

std::string lateness_text(const LatenessSummary& s, const std::string& indent) {
  if (s.count == 0) return indent + "lateness: no message was paced\n";
  std::string text = indent + "lateness (publish returned - deadline): p50 " + microseconds_text(s.p50_us) + ", p99 " +
                     microseconds_text(s.p99_us) + ", max " + microseconds_text(s.max_us) + ", mean " +
                     microseconds_text(s.mean_us) + " over " + std::to_string(s.count) + " messages\n";
  std::size_t largest = 1;
  for (const LatenessBin& b : s.histogram) largest = std::max(largest, b.count);
  constexpr std::size_t kBarWidth = 40;
  for (const LatenessBin& b : s.histogram) {
    const std::size_t bar = b.count == 0 ? 0 : std::max<std::size_t>(1, b.count * kBarWidth / largest);
    char line[160];
    std::snprintf(line, sizeof line, "  %-17s %8zu  %s\n", bin_label(b).c_str(), b.count,
                  std::string(bar, '#').c_str());
    text += indent + line;
  }
  return text;
}

nlohmann::ordered_json lateness_json(const LatenessSummary& s) {
  nlohmann::ordered_json j;
  j["count"] = s.count;
  const auto value = [&s](double v) {
    return s.count == 0 ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v);
  };
  j["p50_us"] = value(s.p50_us);
  j["p99_us"] = value(s.p99_us);
  j["max_us"] = value(s.max_us);
  j["mean_us"] = value(s.mean_us);
  nlohmann::ordered_json bins = nlohmann::ordered_json::array();
  for (const LatenessBin& b : s.histogram) {
    nlohmann::ordered_json bin;
    bin["from_us"] = b.from_us ? nlohmann::ordered_json(*b.from_us) : nlohmann::ordered_json(nullptr);
    bin["to_us"] = b.to_us ? nlohmann::ordered_json(*b.to_us) : nlohmann::ordered_json(nullptr);
    bin["count"] = b.count;
    bins.push_back(bin);
  }
  j["histogram"] = bins;
  return j;
}

}  // namespace rockwatch::cli
