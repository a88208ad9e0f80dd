#include "common/process/history_csv.hpp"

#include <charconv>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

namespace rockwatch::cli {

namespace {

void append_number(std::string& row, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec == std::errc{}) row.append(buffer, result.ptr);
  row += ',';
}

}  // namespace

void write_history_csv(std::ostream& out, const std::vector<sim::HistoryRow>& history) {
  out << kHistoryCsvHeader << '\n';
  std::string row;
  for (const sim::HistoryRow& h : history) {
    row.clear();
    for (const double value : {h.t_s, h.ug_mps2, h.vg_mps2, h.x_m, h.xd_mps, h.xdd_mps2, h.alpha1_rad, h.alpha2_rad}) {
      append_number(row, value);
    }
    row += h.side > 0 ? "1\n" : "-1\n";
    out << row;
  }
}

}  // namespace rockwatch::cli
