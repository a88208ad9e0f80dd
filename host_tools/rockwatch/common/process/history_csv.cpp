#include "common/process/history_csv.hpp"

#include "rockwatch/options/observer_options.hpp"

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

void write_observer_history_csv(std::ostream& out, const std::vector<sim::ObserverHistoryRow>& history) {
  out << kObserverHistoryCsvHeader << '\n';
  std::string row;
  for (const sim::ObserverHistoryRow& h : history) {
    row.clear();
    for (const double value : {h.t_s, h.x_m, h.xd_mps, h.sigma_x_m, h.sigma_xd_mps, h.r, h.sigma_r, h.capacity_scale,
                               h.stiffness_scale, h.x_inst_m, h.sigma_x_inst_m}) {
      append_number(row, value);
    }
    row += h.x_active ? "1," : "0,";
    row += std::to_string(h.flags);
    row += ',';
    const std::vector<std::string> names = options::observer_flag_list(h.flags);
    for (std::size_t i = 0; i < names.size(); ++i) row += (i ? "|" : "") + names[i];
    row += '\n';
    out << row;
  }
}

}  // namespace rockwatch::cli
