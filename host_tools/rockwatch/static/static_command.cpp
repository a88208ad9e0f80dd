// `rockwatch static`: the static non-linear kinematic check of SPEC §5 (core::run_static_check) for the codes'
// instability factors, or the allowable-PGA sweep of the paper's Figure 3. This file wires parsing, core and
// output together; the physics is all in core.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/output_file.hpp"
#include "common/plots/python_plot.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "static/static_report.hpp"
#include "static/static_request.hpp"
#include "static/static_sweep.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch static: error: ", "out of memory"};

core::StaticResult evaluate(const core::StaticInputs& in) {
  core::StaticResult r;
  const core::StaticCheck check = core::run_static_check(in, r);
  // The parser ran the same check on the same inputs: a failure here is a bug, not a user mistake.
  if (!check.ok()) throw std::logic_error(std::string("static check refused validated inputs: ") + check.message);
  return r;
}

void print_a_note(const StaticRequest& q) {
  if (q.a_without_fp) std::cerr << "note: --a has no effect without --fp: it only places the overburden\n";
}

int run_cases(const StaticRequest& q) {
  std::vector<core::StaticResult> results;
  bool general = false;
  for (const StaticCase& c : q.cases) {
    results.push_back(evaluate(case_inputs(q, c)));
    general = general || results.back().general_case;
  }
  print_a_note(q);
  if (q.json) {
    for (const std::string& label : static_labels(q.inputs, general)) std::cerr << "note: " << label << '\n';
    std::cout << static_json(q, results).dump(2) << '\n';
  } else {
    std::cout << static_summary_text(q, results);
  }
  return finish_stdout(kErrors);
}

// Creates --out (and its parents) if missing; refuses a path that exists as something else.
void prepare_directory(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
    throw UsageError("--out " + quoted(dir) + " exists and is not a directory");
  }
  std::filesystem::create_directories(dir, ec);
  if (ec) throw UsageError("--out " + quoted(dir) + ": cannot create the directory: " + ec.message());
}

// Allowable PGA at the codes' lambda for each h/b: the figure's two marker lines in numbers.
std::string code_points_text(const std::vector<SweepRow>& rows) {
  std::string out;
  for (const core::InstabilityCode code : {core::InstabilityCode::ntc2008, core::InstabilityCode::nzsee2016}) {
    const double lambda = core::code_lambda(code);
    std::string text;
    for (const SweepRow& r : rows) {
      if (r.lambda != lambda) continue;
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%sh/b %g: %.4f g", text.empty() ? "" : ", ", r.h_over_b,
                    r.result.allowable_pga_g);
      text += buffer;
    }
    out += "  " + std::string(core::code_title(code)) + " (lambda " + number_text(lambda) + "): " + text + '\n';
  }
  return out;
}

int run_sweep(const StaticRequest& q) {
  prepare_directory(q.out_dir);
  const std::string csv_path = (std::filesystem::path(q.out_dir) / kSweepCsvName).string();
  const std::string png_path = (std::filesystem::path(q.out_dir) / kSweepPngName).string();

  const std::vector<SweepRow> rows = compute_sweep(q.inputs);
  const bool general = !rows.empty() && rows.front().result.general_case;
  // A failed write must not leave a truncated table that looks like a result.
  write_output_file(csv_path, [&](std::ostream& out) { write_sweep_csv(out, rows); });

  // An old figure next to the new table would be mistaken for it if the plot fails.
  std::error_code ec;
  std::filesystem::remove(png_path, ec);

  print_a_note(q);
  std::cout << "rockwatch static --sweep: allowable PGA versus lambda (0.10 to 0.90 by 0.01) for h/b = 20, 25, 30, "
               "35, 40 with b = "
            << number_text(kSweepB_m) << " m\n";
  std::cout << "  wrote " << csv_path << " (" << rows.size() << " rows)\n";
  for (const std::string& label : static_labels(q.inputs, general)) std::cout << "  " << label << '\n';
  std::cout << code_points_text(rows);

  const std::vector<std::string> args{csv_path,
                                      png_path,
                                      sweep_plot_title(q.inputs, general),
                                      number_text(core::code_lambda(core::InstabilityCode::ntc2008)),
                                      core::code_title(core::InstabilityCode::ntc2008),
                                      number_text(core::code_lambda(core::InstabilityCode::nzsee2016)),
                                      core::code_title(core::InstabilityCode::nzsee2016)};
  const PlotOutcome plot = run_plot_script("static_sweep", args);
  if (!plot.ok) {
    std::cout.flush();
    return fail(kErrors, "plot not written: " + plot.message + "\n(the CSV " + csv_path + " was written)",
                kExitInternalError);
  }
  std::cout << "  wrote " << png_path << '\n';
  return finish_stdout(kErrors);
}

}  // namespace

int static_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const StaticParse parsed = parse_static_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return parsed.request->sweep ? run_sweep(*parsed.request) : run_cases(*parsed.request);
  });
}

}  // namespace rockwatch::cli
