#include "rockwatch/options/engine_options.hpp"

#include <string>

#include <CLI/CLI.hpp>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::options {

double default_kappa() { return sim::AnalysisOptions{}.kappa; }

void add_restitution_option(CLI::App& app, std::string& text) {
  app.add_option("--r", text, "Energy ratio at impact: ana | exp (default, 0.9 ana) | impulse | a value in [0, 1]")
      ->type_name("R");
}

void add_model_option(CLI::App& app, std::string& text) {
  app.add_option("--model", text, "Equation of motion: linear (default, the paper's) | full")->type_name("linear|full");
}

void add_kappa_option(CLI::App& app, std::string& text) {
  app.add_option("--kappa", text,
                 "Collapse at |x| >= kappa * x_inst (default " + number_text(default_kappa()) + ", >= 1)")
      ->type_name("K");
}

void add_max_step_option(CLI::App& app, std::string& text, const std::string& extra) {
  app.add_option("--max-step", text,
                 "Longest integration step [s] (default " + number_text(core::kDefaultMaxStep_s) +
                     "): each input sample is integrated in ceil(sample interval / max-step) sub-steps, the input "
                     "linear between samples (no added latency), the alarm once per sample; the sample interval gives "
                     "one step per sample (the paper's 5 ms at 200 Hz)" + extra)
      ->type_name("S");
}

}  // namespace rockwatch::options
