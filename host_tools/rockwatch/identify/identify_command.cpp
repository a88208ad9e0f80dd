// `rockwatch identify`: a wall from a test record (SPEC §9) through sim::identify — the engine every tool shares —
// reported as text or JSON, drawn (--plot), and written as a wall file (--wall-out) that the other tools read.
#include <malloc.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/process/output_file.hpp"
#include "common/plots/python_plot.hpp"
#include "common/process/text_report.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "identify/identify_report.hpp"
#include "identify/identify_request.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_file.hpp"
#include "rockwatch/sim/identification.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch identify: error: ", "out of memory (a very long test record?)"};

nlohmann::ordered_json wall_json(const core::WallParameters& w) {
  nlohmann::ordered_json j;
  j["b_m"] = w.b_m;
  j["h1_m"] = w.h1_m;
  j["h2_m"] = w.h2_m;
  j["rho_kgpm3"] = w.rho_kgpm3;
  j["fp_npm"] = w.fp_npm;
  j["a"] = w.a;
  j["a_prime"] = w.a_prime;
  j["g_mps2"] = w.g_mps2;
  return j;
}

template <typename T>
nlohmann::ordered_json or_null(const std::optional<T>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
}

}  // namespace

nlohmann::ordered_json identify_json(const IdentifyRequest& q, const sim::IdentificationResult& r, double start_r) {
  nlohmann::ordered_json j;
  j["test"] = r.snap_back ? "snap-back" : "forced";
  j["r"] = r.r;
  j["sigma_r"] = r.sigma_r;
  j["x_inst_m"] = r.reduced.x_inst_m;
  j["sigma_x_inst_m"] = r.sigma_x_inst_m;
  j["omega_radps"] = r.reduced.omega_radps;
  j["sigma_omega_radps"] = r.sigma_omega_radps;
  j["k_ps2"] = r.reduced.k_ps2;
  j["sigma_k_ps2"] = r.sigma_k_ps2;
  j["c_mps2"] = std::fmin(r.reduced.c_mps2[0], r.reduced.c_mps2[1]);
  j["sigma_c_mps2"] = r.sigma_c_mps2;
  j["gamma"] = r.reduced.gamma;
  j["threshold_mps2"] = r.reduced.threshold_mps2;
  j["offset_m"] = r.offset_m;
  j["sigma_offset_m"] = r.sigma_offset_m;
  j["x0_m"] = or_null(r.x0_m);
  j["sigma_x0_m"] = or_null(r.sigma_x0_m);
  j["sigma_method"] = r.sigma_by_bootstrap ? "bootstrap" : "curvature";
  if (r.bootstrap) {
    const sim::IdentificationBootstrap& b = *r.bootstrap;
    j["bootstrap"] = {{"replicates", b.replicates},
                      {"refused", b.refused},
                      {"flagged", b.flagged},
                      {"used", b.used},
                      {"seed", b.seed},
                      {"curvature_sigma_r", b.curvature_sigma_r},
                      {"curvature_sigma_x_inst_m", b.curvature_sigma_x_inst_m},
                      {"curvature_sigma_omega_radps", b.curvature_sigma_omega_radps},
                      {"curvature_sigma_offset_m", b.curvature_sigma_offset_m}};
  } else {
    j["bootstrap"] = nullptr;
  }
  j["residual_rms_m"] = r.residual_rms_m;
  j["noise_estimate_m"] = r.noise_estimate_m;
  j["fit_explains_record"] = r.fit_explains_record;
  j["wall"] = wall_json(r.wall);
  j["wall_sigma"] = {{"b_m", r.sigma_b_m}, {"h1_m", r.sigma_h1_m}, {"h2_m", r.sigma_h2_m}};
  j["identified"] = {"b_m", "h1_m", "h2_m", "r"};
  j["held"] = {"h1_m:h2_m", "rho_kgpm3", "fp_npm", "a", "a_prime", "g_mps2"};
  j["samples_used"] = r.samples_used;
  j["n_impacts"] = r.n_impacts;
  j["iterations"] = r.iterations;
  j["model_evaluations"] = r.model_evaluations;
  j["converged"] = r.converged;
  j["start_wall"] = wall_json(q.start_wall);
  j["start_r"] = start_r;
  j["wall_sensors"] = q.wall_sensors_path;
  j["record"] = q.record ? nlohmann::ordered_json(q.record->record_path) : nlohmann::ordered_json(nullptr);
  j["max_step_s"] = q.max_step_s;
  j["wall_out"] = or_null(q.wall_out_path);
  return j;
}

namespace {

// "value +- sigma unit" with `digits` decimals.
std::string pm(double value, double sigma, int digits, const std::string& unit) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << value << " +- " << sigma << (unit.empty() ? "" : " " + unit);
  return o.str();
}

// `digits` significant digits (the curvature's errors span 1e-3 to 1e-9).
std::string significant(double value, int digits) {
  std::ostringstream o;
  o.precision(digits);
  o << value;
  return o.str();
}

std::string fixed(double value, int digits) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << value;
  return o.str();
}

std::string summary_text(const IdentifyRequest& q, const sim::IdentificationResult& r, double start_r) {
  std::ostringstream o;
  o << "rockwatch identify: the wall from its own motion (SPEC 9), per metre of wall\n\n";
  o << "  test               " << (r.snap_back ? "snap-back (ground at rest, released at t = 0)" : "forced (record " + q.record->record_path + ")") << '\n';
  o << "  sensors            " << q.wall_sensors_path << ": " << r.samples_used << " displacement samples\n";
  o << "  start              " << q.start_wall_text << ", r " << number_text(start_r) << '\n';
  const bool by_bootstrap = r.sigma_by_bootstrap;
  o << "\nIdentified (estimate +- standard error: "
    << (by_bootstrap ? "the spread of " + std::to_string(r.bootstrap->used) + " bootstrap refits"
                     : std::string("the minimum's curvature"))
    << ")\n";
  o << "  r                  " << pm(r.r, r.sigma_r, 5, "") << '\n';
  o << "  x_inst             " << pm(r.reduced.x_inst_m, r.sigma_x_inst_m, 6, "m") << '\n';
  o << "  omega = sqrt(k)    " << pm(r.reduced.omega_radps, r.sigma_omega_radps, 5, "rad/s") << '\n';
  o << "  offset             " << pm(r.offset_m, r.sigma_offset_m, 6, "m") << '\n';
  if (r.x0_m) o << "  x0 (release)       " << pm(*r.x0_m, *r.sigma_x0_m, 6, "m") << '\n';
  o << "  residual RMS       " << number_text(r.residual_rms_m) + " m (" + std::to_string(r.n_impacts) + " impacts in the fitted response)" << '\n';
  if (!r.fit_explains_record) {
    o << "  WARNING            the residual is " << fixed(r.residual_rms_m / std::fmax(r.noise_estimate_m, 1e-9), 1)
      << " times the transducer's noise (" << number_text(r.noise_estimate_m)
      << " m): the identified wall does not explain the record (a fit a cycle off, a chaotic response near collapse,\n"
         "                     SPEC 4, or a wall the equivalent wall does not describe: a forced test also sees gamma,\n"
         "                     so start it from a wall with the right h1:h2 and overburden, --h1 --h2 --fp): do not use\n"
         "                     these estimates\n";
  }
  if (r.bootstrap) {
    o << "  bootstrap          " << r.bootstrap->replicates << " refits (seed " << r.bootstrap->seed << "), "
      << r.bootstrap->refused << " refused, " << r.bootstrap->flagged << " not explaining their record\n"
      << "  curvature          r +- " << significant(r.bootstrap->curvature_sigma_r, 3) << ", x_inst +- "
      << significant(r.bootstrap->curvature_sigma_x_inst_m, 3) << " m (the minimum's own errors, for comparison)\n";
  } else if (!r.snap_back) {
    o << "  note               a forced test's curvature errors understate the uncertainty (many narrow minima):\n"
         "                     --bootstrap 20 measures it\n";
  }
  o << "\nEquivalent wall (b, h1, h2 identified; h1:h2, rho, Fp, a, a', g held)\n";
  o << "  b                  " << pm(r.wall.b_m, r.sigma_b_m, 6, "m") << '\n';
  o << "  h1                 " << pm(r.wall.h1_m, r.sigma_h1_m, 5, "m") << '\n';
  o << "  h2                 " << pm(r.wall.h2_m, r.sigma_h2_m, 5, "m") << '\n';
  o << "  reduced            " << "c " + fixed(std::fmin(r.reduced.c_mps2[0], r.reduced.c_mps2[1]), 5) + " m/s2, k " + fixed(r.reduced.k_ps2, 5) + " 1/s2"
    << ", gamma " + fixed(r.reduced.gamma, 5) + " (from the geometry), threshold " + fixed(r.reduced.threshold_mps2, 5) + " m/s2" << '\n';
  o << "\n  fit                " << r.iterations << " Levenberg-Marquardt iterations, " << r.model_evaluations
    << " engine runs, " << (r.converged ? "converged" : "NOT converged (iteration limit)") << '\n';
  if (q.wall_out_path) o << "  wall file          " << *q.wall_out_path << " (read it with --wall-file)\n";
  if (q.plot_path) o << "  plot               " << *q.plot_path << '\n';
  return o.str();
}

int run(const IdentifyRequest& q) {
  // The fit runs the engine about a thousand times, each run keeping a history of the record's length (about 1 MB
  // for 10 s): keep freed memory in the heap for the next run instead of returning it to the system at every run
  // (mmap/munmap and page faults were half the run time, docs/BENCHMARKS.md).
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
  sim::IdentificationInput in = identification_input(q);
  in.samples = read_wall_sensor_samples(q.wall_sensors_path);
  const bool terminal = isatty(STDERR_FILENO) != 0;
  if (terminal && q.bootstrap > 0) {
    in.bootstrap_progress = [](std::size_t done, std::size_t total) {
      std::cerr << "\ridentify: bootstrap " << done << '/' << total << (done == total ? "\n" : "") << std::flush;
    };
  }
  std::optional<InputMotion> motion;
  if (q.record) {
    motion = prepare_input(InputRequest{*q.record, q.scale_pga_g, q.start_wall.g_mps2});
    for (const std::string& note : motion->notes) std::cerr << "note: " << note << '\n';
    in.ground = &motion->motion;
  }
  if (terminal) {
    std::cerr << "identify: fitting " << in.samples.size() << " samples through the engine...\n";
  }
  sim::IdentificationResult r;
  try {
    r = sim::identify(in);
  } catch (const sim::IdentificationError& e) {
    throw UsageError("the record does not identify the wall: " + std::string(e.what()) + " (" + q.wall_sensors_path + ")");
  }
  if (q.wall_out_path) {
    const options::WallFile file = identified_wall_file(q, r);
    write_output_file(*q.wall_out_path,
                      [&](std::ostream& out) { out << options::wall_file_json(file).dump(2) << '\n'; });
  }
  if (q.plot_path) {
    const std::string title = "rockwatch identify: " + file_name(q.wall_sensors_path) + " (" +
                              (r.snap_back ? "snap-back" : "forced") + "): r " + fixed(r.r, 4) + ", x_inst " + fixed(r.reduced.x_inst_m, 4) + " m";
    const PlotOutcome plot = run_plot_script_with_data(
        "identify_fit", "fit.csv",
        [&r](std::ostream& out) {
          out << "t_s,measured_m,fitted_m\n";
          out.precision(17);
          for (std::size_t i = 0; i < r.t_s.size(); ++i) out << r.t_s[i] << ',' << r.measured_m[i] << ',' << r.fitted_m[i] << '\n';
        },
        {*q.plot_path, title});
    if (!plot.ok) throw UsageError("--plot " + *q.plot_path + ": " + plot.message);
  }
  if (!r.fit_explains_record && q.json) {
    std::cerr << "warning: the residual RMS " << number_text(r.residual_rms_m) << " m is "
              << fixed(r.residual_rms_m / std::fmax(r.noise_estimate_m, 1e-9), 2) << " times the noise ("
              << number_text(r.noise_estimate_m)
              << " m): the identified wall does not explain the record (for a forced test, start from a wall with the "
                 "right h1:h2 and overburden: --h1 --h2 --fp)\n";
  }
  if (q.json) {
    std::cout << identify_json(q, r, in.start_r).dump(2) << '\n';
  } else {
    std::cout << summary_text(q, r, in.start_r);
  }
  return finish_stdout(kErrors);
}

}  // namespace

options::WallFile identified_wall_file(const IdentifyRequest& q, const sim::IdentificationResult& r) {
  options::WallFile file;
  file.wall = r.wall;
  file.r = r.r;
  file.identified = {{"by", "rockwatch identify"},
                     {"test", r.snap_back ? "snap-back" : "forced"},
                     {"wall_sensors", q.wall_sensors_path},
                     {"sigma_r", r.sigma_r},
                     {"sigma_x_inst_m", r.sigma_x_inst_m},
                     {"sigma_omega_radps", r.sigma_omega_radps},
                     {"sigma_method", r.sigma_by_bootstrap ? "bootstrap" : "curvature"},
                     {"residual_rms_m", r.residual_rms_m},
                     {"identified", {"b_m", "h1_m", "h2_m", "r"}},
                     {"held", {"h1_m:h2_m", "rho_kgpm3", "fp_npm", "a", "a_prime", "g_mps2"}}};
  return file;
}

int identify_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const IdentifyParse parsed = parse_identify_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
