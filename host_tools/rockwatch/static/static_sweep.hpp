// `rockwatch static --sweep`: the allowable PGA over a grid of slenderness and instability factor (the design
// paper's Figure 3), as a CSV table and a matplotlib PNG.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "rockwatch/core/static_check.hpp"
#include "static/static_request.hpp"

namespace rockwatch::cli {

inline constexpr const char* kSweepCsvName = "static_sweep.csv";
inline constexpr const char* kSweepPngName = "static_sweep.png";
inline constexpr const char* kSweepCsvHeader = "h_over_b,h_m,lambda,T_s,x_eq_max_m,allowable_pga_g";

struct SweepRow {
  double h_over_b = 0.0;
  double lambda = 0.0;
  core::StaticResult result;
};

// Every h/b of kSweepSlenderness (b = kSweepB_m) by every lambda from 0.10 to 0.90 in steps of 0.01, h/b outer.
// `base` supplies overburden, psi, rho, g and the spectrum; the request parser has validated every point.
std::vector<SweepRow> compute_sweep(const core::StaticInputs& base);

// The header and one row per point, numbers as shortest round-trip text; the caller checks the stream.
void write_sweep_csv(std::ostream& out, const std::vector<SweepRow>& rows);

// The plot's title: what was swept and the spectrum with its provenance ("back-calculated" for npr9998-2015).
std::string sweep_plot_title(const core::StaticInputs& base, bool general_case);

}  // namespace rockwatch::cli
