#include "study/report/study_table3.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "common/process/text_report.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

// The paper's fit: P(collapse | a) = Phi((a - mean) / sd).
double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

std::string g_cell(const std::optional<double>& value_g) { return value_g ? format("%.3f", *value_g) : "-"; }

std::string fit_cell(bool ok, double value_g) { return ok ? format("%.3f", value_g) : "-"; }

std::string paper_cell(const std::optional<PaperRow>& row, double PaperRow::*member, int decimals) {
  return row ? format("%.*f", decimals, (*row).*member) : "-";
}

std::string paper_probability(const std::optional<PaperRow>& row, double capacity_g) {
  if (!row) return "-";
  return format("%.3f", normal_cdf((capacity_g - row->mean_g) / row->std_g));
}

bool is_paper_wall(const core::WallParameters& w) {
  const core::WallParameters p = core::paper_wall();
  return w.b_m == p.b_m && w.h1_m == p.h1_m && w.h2_m == p.h2_m && w.rho_kgpm3 == p.rho_kgpm3 && w.fp_npm == p.fp_npm &&
         w.a == p.a && w.a_prime == p.a_prime && w.g_mps2 == p.g_mps2;
}

}  // namespace

std::optional<PaperRow> paper_row(const std::string& r_label, bool vertical) {
  for (const PaperRow& row : kPaperTable3) {
    if (r_label == row.r_label && vertical == row.vertical) return row;
  }
  return std::nullopt;
}

std::string table3_markdown(const study::StudyPlan& plan, const StudyRecords& records, const StudyOutcome& o) {
  const double ntc = o.capacities.ntc2008_g, nzsee = o.capacities.nzsee2016_g;
  std::string md = "# Table 3: probability of collapse by dynamic analysis\n\n";
  md += "The design paper's study (its section 3 and Table 3; SPEC section 6) run by `rockwatch study`. The paper used "
        "the eleven NPR 9998 (2015) bedrock record sets, which are not public; this study used " +
        records_text(records) + ". ";
  if (records.from_suite && records.suite_name == "npr9998-2015") {
    md += "The project's suite is generated to be NPR 9998-compatible (SPEC section 6), not the paper's records, so "
          "the numbers are comparable, not equal. ";
  }
  md += "PGA levels " + number_text(plan.pga_g.front()) + " to " + number_text(plan.pga_g.back()) + " g (" +
        std::to_string(plan.pga_g.size()) + "), model " + model_name(plan.analysis.model) + ", kappa " +
        number_text(plan.analysis.kappa) + ", " + std::to_string(study::run_count(plan)) + " analyses. Integration step: " +
        "at most " + number_text(plan.analysis.max_step_s) + " s (`--max-step`; " +
        (plan.analysis.max_step_s < 0.005
             ? "record samples of 5 ms in sub-steps, the input linear between samples; the paper integrated at the "
               "records' 5 ms: `--max-step 0.005`)"
             : plan.analysis.max_step_s == 0.005 ? "the paper's step: one step per 5 ms sample)"
                                                 : "coarser than the paper's 5 ms)") +
        ".\n";
  if (!is_paper_wall(plan.wall)) {
    md += "\nThe wall is not the paper's (b 0.1 m, h1 = h2 = 1.75 m): the paper's numbers are for its own wall.\n";
  }
  md += "\n| case | runs | min PGA collapse [g] | paper | mean [g] | paper | sd [g] | paper | P(collapse) at " +
        format("%.3f", ntc) + " g (NTC 2008) | paper's fit | P(collapse) at " + format("%.3f", nzsee) +
        " g (NZSEE 2016) | paper's fit |\n";
  md += "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  bool other_cases = false;
  for (const CaseOutcome& c : o.cases) {
    const std::string& label = plan.restitutions[c.study_case.restitution_index].label;
    const bool vertical = plan.vertical[c.study_case.vertical_index];
    const std::optional<PaperRow> paper = paper_row(label, vertical);
    other_cases = other_cases || !paper;
    const study::CaseStatistics empty;
    const study::CaseStatistics& s = c.statistics ? *c.statistics : empty;
    md += "| " + c.title + " | " + std::to_string(s.n_runs) + " | " + g_cell(s.min_pga_collapse_g) + " | " +
          paper_cell(paper, &PaperRow::min_pga_collapse_g, 2) + " | " + fit_cell(s.normal.ok, s.normal.mean_g) +
          " | " + paper_cell(paper, &PaperRow::mean_g, 3) + " | " + fit_cell(s.normal.ok, s.normal.std_g) + " | " +
          paper_cell(paper, &PaperRow::std_g, 3) + " | " + probability_text(s.at_ntc2008.normal_fit) + " | " +
          paper_probability(paper, ntc) + " | " + probability_text(s.at_nzsee2016.normal_fit) + " | " +
          paper_probability(paper, nzsee) + " |\n";
  }
  md += "\nH-only: the horizontal record alone; H+V: with its vertical partner, scaled by the same factor. "
        "Mean and sd: the cumulative normal distribution fitted by least squares to the collapse fraction per PGA "
        "level (the paper's method). P(collapse): that fit at the wall's static capacities, the allowable PGA of the "
        "static non-linear kinematic check (SPEC section 5) with the npr9998-2015 spectrum (back-calculated from the "
        "paper's static results; the NPR 9998:2015 bedrock parameters are not public) for lambda 0.4 (NTC 2008) and "
        "0.6 (NZSEE 2016). \"paper's fit\": the same probability from the paper's mean and sd. \"-\": undetermined "
        "(nothing collapsed, or everything did) or not in the paper.";
  if (other_cases) md += " Cases the paper's table does not have (another restitution) are listed without its numbers.";
  md += " The lognormal fit, the empirical probabilities and the survival rates are in summary.json.\n";
  return md;
}

}  // namespace rockwatch::cli
