#include "static/static_report.hpp"

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

constexpr int kLabelWidth = 26;
constexpr int kColumnWidth = 16;

// One table row: a label, then one value per case (by index) in its column.
void row(std::string& out, const std::string& label, std::size_t cases,
         const std::function<std::string(std::size_t)>& value) {
  std::string text = format("  %-*s", kLabelWidth - 2, label.c_str());
  for (std::size_t i = 0; i < cases; ++i) text += format(" %-*s", kColumnWidth - 1, value(i).c_str());
  while (!text.empty() && text.back() == ' ') text.pop_back();
  out += text + '\n';
}

bool any_general(const std::vector<core::StaticResult>& results) {
  for (const core::StaticResult& r : results) {
    if (r.general_case) return true;
  }
  return false;
}

}  // namespace

std::string case_title(const StaticCase& c) {
  return c.code ? core::code_title(*c.code) : std::string("given lambda");
}

std::string spectrum_branch_text(const core::SpectrumShape& s, double period_s) {
  // The same comparisons as core::spectrum_shape, so the branch named is the branch used.
  if (period_s < s.tb_s) return "T < TB";
  if (period_s <= s.tc_s) return "TB-TC plateau";
  if (period_s <= s.td_s) return "TC-TD (p TC/T)";
  return "T > TD (p TC TD/T2)";
}

std::vector<std::string> static_labels(const core::StaticInputs& inputs, bool general_case) {
  std::vector<std::string> labels;
  if (general_case) {
    labels.push_back("K, X and T derived by virtual work (general case of SPEC 5: Fp = " + number_text(inputs.fp_npm) +
                     " N/m at a = " + number_text(inputs.a) + ", psi = " + number_text(inputs.psi_rad) + " rad)");
  }
  labels.push_back("spectrum " + spectrum_text(inputs.spectrum) + ": " +
                   core::spectrum_provenance(inputs.spectrum.kind));
  return labels;
}

nlohmann::ordered_json static_case_json(const StaticRequest& q, const StaticCase& c, const core::StaticResult& r) {
  nlohmann::ordered_json j;
  j["T_s"] = r.period_s;
  j["x_eq_max_m"] = r.x_eq_max_m;
  j["allowable_pga_g"] = r.allowable_pga_g;
  j["K"] = r.k;
  j["X_m"] = r.x_m;
  j["lambda"] = c.lambda;
  j["spectrum"] = core::spectrum_name(q.inputs.spectrum.kind);
  return j;
}

nlohmann::ordered_json static_json(const StaticRequest& q, const std::vector<core::StaticResult>& results) {
  if (q.cases.size() == 1) return static_case_json(q, q.cases.front(), results.front());
  nlohmann::ordered_json array = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < q.cases.size(); ++i) array.push_back(static_case_json(q, q.cases[i], results[i]));
  return array;
}

std::string static_summary_text(const StaticRequest& q, const std::vector<core::StaticResult>& results) {
  const core::StaticInputs& in = q.inputs;
  const core::StaticResult& first = results.front();
  const bool general = any_general(results);
  std::string out;
  out += "rockwatch static: static non-linear kinematic analysis (SPEC 5, design paper section 3), "
         "per metre of wall\n\n";

  out += "Wall\n";
  std::string base = "paper wall (design paper, Table 2)";
  if (!q.wall_options_given.empty()) {
    base += " with ";
    for (std::size_t i = 0; i < q.wall_options_given.size(); ++i) {
      base += (i == 0 ? "" : ", ") + q.wall_options_given[i];
    }
    base += " given";
  }
  line(out, "base wall", base);
  const std::string split = in.blocks_given ? format("h1 %s m + h2 %s m; only h enters the static check",
                                                     number_text(in.h1_m).c_str(), number_text(in.h2_m).c_str())
                                            : std::string("total height given");
  line(out, "geometry", format("b %s m, h %s m (%s), h/b %.4g", number_text(in.b_m).c_str(),
                               number_text(first.h_m).c_str(), split.c_str(), first.h_m / in.b_m));
  if (in.fp_npm == 0.0) {
    line(out, "overburden", "none (Fp 0 N/m)");
  } else {
    line(out, "overburden", format("Fp %s N/m at a = %s; W = rho g b h = %.6g N/m (rho %s kg/m3), f = Fp/W = %.6g",
                                   number_text(in.fp_npm).c_str(), number_text(in.a).c_str(), first.weight_npm,
                                   number_text(in.rho_kgpm3).c_str(), first.f));
  }
  line(out, "out of plumb", "psi " + number_text(in.psi_rad) + " rad");
  line(out, "gravity", number_text(in.g_mps2) + " m/s2");
  line(out, "mechanism", general ? "general case (Fp > 0 or psi != 0): K, X and T derived by virtual work"
                                 : "simple case (Fp = 0, psi = 0): K = 4b/h, X = b/2");

  out += "\nSpectrum\n";
  line(out, "shape", spectrum_text(in.spectrum));
  line(out, "provenance", core::spectrum_provenance(in.spectrum.kind));

  out += '\n';
  std::string header = format("  %-*s", kLabelWidth - 2, "");
  for (const StaticCase& c : q.cases) header += format(" %-*s", kColumnWidth - 1, case_title(c).c_str());
  while (!header.empty() && header.back() == ' ') header.pop_back();
  out += header + '\n';
  const std::size_t n = results.size();
  const auto fixed6 = [&](double core::StaticResult::*member) {
    return [&results, member](std::size_t i) { return format("%.6f", results[i].*member); };
  };
  row(out, "lambda [-]", n, [&](std::size_t i) { return number_text(q.cases[i].lambda); });
  const std::string derived = general ? " (virtual work)" : "";
  row(out, "K [-]" + derived, n, fixed6(&core::StaticResult::k));
  row(out, "X [m]" + derived, n, fixed6(&core::StaticResult::x_m));
  row(out, "T [s]" + derived, n, fixed6(&core::StaticResult::period_s));
  row(out, "x_eq,max = lambda X [m]", n, fixed6(&core::StaticResult::x_eq_max_m));
  row(out, "spectrum branch", n, [&](std::size_t i) { return spectrum_branch_text(in.spectrum, results[i].period_s); });
  row(out, "Se(T)/a_g [-]", n, fixed6(&core::StaticResult::shape));
  row(out, "Se(T) [m/s2]", n, fixed6(&core::StaticResult::se_mps2));
  row(out, "Sd(T) [m]", n, fixed6(&core::StaticResult::sd_m));
  row(out, "allowable PGA [g]", n, fixed6(&core::StaticResult::allowable_pga_g));
  row(out, "allowable PGA [m/s2]", n, fixed6(&core::StaticResult::allowable_pga_mps2));
  out += "\n  Se and Sd are at the allowable PGA, where Sd(T) = Se(T) (T/2pi)^2 reaches x_eq,max.\n";
  const bool back_calculated = in.spectrum.kind == core::SpectrumKind::npr9998_2015;
  out += std::string("  Se(T), Sd(T) and the allowable PGA use the ") + core::spectrum_name(in.spectrum.kind) +
         " spectrum" + (back_calculated ? ", back-calculated (its NPR 9998:2015 parameters are not public).\n" : ".\n");
  if (general) out += "  K, X and T are derived by virtual work (SPEC 5 general case).\n";
  return out;
}

}  // namespace rockwatch::cli
