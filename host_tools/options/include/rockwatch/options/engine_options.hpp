// The engine options that `rockwatch simulate`, `rockwatch study` and rockwatch-monitor share: --r (one restitution)
// and --kappa, declared once so their names, help and defaults cannot drift apart.
#pragma once

#include <string>

#include "rockwatch/options/cli11_fwd.hpp"

namespace rockwatch::options {

// The collapse factor when --kappa is not given (sim::AnalysisOptions's).
double default_kappa();

// Registers --r: one restitution, ana | exp | impulse | a value in [0, 1] (parse_restitution reads it).
void add_restitution_option(CLI::App& app, std::string& text);

// Registers --model, the equation of motion: linear (the paper's, the default) | full (parse_model reads it).
void add_model_option(CLI::App& app, std::string& text);

// Registers --kappa (parse_kappa reads it); the help states default_kappa().
void add_kappa_option(CLI::App& app, std::string& text);

// Registers --max-step, the longest integration step (core::kDefaultMaxStep_s when not given): each input sample is
// integrated in ceil(dt / max_step) sub-steps with the input linear between samples. `extra` ends the help.
void add_max_step_option(CLI::App& app, std::string& text, const std::string& extra = "");

}  // namespace rockwatch::options
