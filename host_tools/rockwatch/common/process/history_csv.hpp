// The time history as CSV: one row per integration step, every number exact (shortest round-trip text), so a
// plot or a regression script sees what the engine computed.
#pragma once

#include <ostream>
#include <vector>

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

inline constexpr const char* kHistoryCsvHeader =
    "t_s,ug_mps2,vg_mps2,x_m,xd_mps,xdd_mps2,alpha1_rad,alpha2_rad,side";

// Writes the header and the rows; the caller checks the stream.
void write_history_csv(std::ostream& out, const std::vector<sim::HistoryRow>& history);

inline constexpr const char* kObserverHistoryCsvHeader =
    "t_s,x_m,xd_mps,sigma_x_m,sigma_xd_mps,r,sigma_r,capacity_scale,stiffness_scale,x_inst_m,sigma_x_inst_m,x_active,"
    "flags,flag_names";

// The observer's estimates at the end of every input sample (simulate --observer-out): flags as the integer of
// core::observer_flag bits and as their names joined by '|'.
void write_observer_history_csv(std::ostream& out, const std::vector<sim::ObserverHistoryRow>& history);

}  // namespace rockwatch::cli
