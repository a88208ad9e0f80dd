#include "monitor_command_line.hpp"

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

#ifndef ROCKWATCH_VERSION
#define ROCKWATCH_VERSION "unknown"
#endif

namespace rockwatch::monitor::config_detail {

using options::UsageError;

namespace {

const char* const kFooter =
    "Reads ground_accel_t / ground_accel_batch_t samples from LCM, runs the fixed-point rocking engine and the\n"
    "instability alarm once per sample, and publishes wall_state_t (every sample), alarm_event_t (every alarm level\n"
    "change) and monitor_status_t (once per second and on exit). Each alarm change is also printed on stdout as one\n"
    "JSON line: utime, seq, input_seq, level, previous (QUIET, ROCKING, WARNING, IMMINENT, COLLAPSED), reason (names)\n"
    "and reason_bits, x_m, xd_mps, energy_ratio, t_to_instability_s (null: the wall would turn back). On SIGINT or\n"
    "SIGTERM (or the end of an offline log) it publishes a final status, prints {\"summary\": {...}} as the last\n"
    "line on stdout and a human summary on stderr, and exits 0.\n"
    "\n"
    "Configuration file (--config, JSON; every key optional, unknown keys refused; the command line overrides it):\n"
    "  wall {b, h1, h2, rho, fp, a, a_prime, g}   fields replacing the paper wall's (as --b ... --g)\n"
    "  wall_file \"W.json\"   base wall and r from a wall file (rockwatch identify --wall-out; as --wall-file;\n"
    "    relative to the configuration's folder); the wall fields above and r replace its values\n"
    "  r \"ana\"|\"exp\"|\"impulse\"|number   model \"linear\"   kappa K\n"
    "  alarm {lambda_w, hold_s, energy_margin, imminent_horizon_s, energy_min_x}   (as --lambda-w, --alarm-hold,\n"
    "    --energy-margin, --imminent-horizon, --energy-min-x)\n"
    "  sample_rate_hz (--rate, 200)   max_step_s (--max-step, 0.001)   sensor_range_mps2 (80)   late_limit_s (0.05)\n"
    "  max_bridge_samples (0.1 s of samples, 10 to 1000): longest gap of lost samples bridged by interpolating the\n"
    "    ground between the samples on either side; a longer one restarts the wall from rest (state unknown)\n"
    "  work_budget_units (--work-budget, 0): the fixed-point engine's work per sample in Cortex-M4 instructions; a\n"
    "    sample whose work does not fit is finished (and published, with its own time) at later samples' calls.\n"
    "    0 on a host (every sample in its own call); 23000 runs as the Cortex-M4 firmware does\n"
    "  work_overflow (--work-overflow, \"shed\"): with a work budget, what the engine does when 64 samples wait:\n"
    "    \"shed\" (events no longer located; every call within the budget) or \"finish\" (the oldest sample finished\n"
    "    beyond the budget; the answers always as without a budget). Counted in the summary (samples_work_shed,\n"
    "    samples_over_budget)\n"
    "  clock_tolerance_s (--clock-tolerance, 10): samples stamped further than this from the monitor's clock have a\n"
    "    time it does not trust (counted, flagged, not used to detect publisher restarts)\n"
    "  channels {accel, accel_batch, wall_state, alarm, status, wall_sensor, wall_estimate}   (ROCKWATCH_ACCEL, ...)\n"
    "  observer {enabled, x_noise_m, a_noise_mps2, process_accel_mps2, gate_chi2, dropout_s, max_age_s,\n"
    "            capacity_sigmas, accel_inform_peak_noises, doubt_nis, quiet_motion_spread_noises,\n"
    "            model_form_sigma, doubt_model_form_sigma, capacity_min_x, doubt_capacity_min_x,\n"
    "            capacity_correlation, noise_learn_readings}\n"
    "    the wall observer (--observer: enabled with the defaults): fuses wall_sensor_t samples (channel\n"
    "    wall_sensor) with the model, publishes wall_estimate_t (channel wall_estimate) and alarms on the fused state\n"
    "  forecast {enabled, members, horizon_s, rate_hz, seed, channel, calibration [c0, c1, c2, c3(, c4)]}\n"
    "    (--forecast N,H, --forecast-rate, --forecast-calibration; off by\n"
    "    default; 200 members, 5 s, 10 Hz, seed 29, ROCKWATCH_WALL_FORECAST): the ensemble forecast of collapse\n"
    "    (SPEC section 10) from the latest (fused, with the observer) state, on a thread of its own, published as\n"
    "    wall_forecast_t (P(collapse within H), its standard error, quantiles of max |x|/x_inst, compute_us,\n"
    "    ticks_skipped); one wall only; not written to --log\n"
    "  lcm_url (--lcm-url; default $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0)\n"
    "  accept_from [\"ADDR\" or \"ADDR/PREFIX\", ...]   (--accept-from; sources of input datagrams, default any)\n"
    "  realtime_priority (--realtime)   cpu (--cpu)   busy_poll_us (--busy-poll-us)   live mode, not in the digest\n"
    "  walls [{name, wall {...}, r, channels {accel, accel_batch, wall_sensor}}, ...]   one monitor, up to 64 walls:\n"
    "    each the settings above with its own wall fields (replacing the top-level ones) and r; it publishes on the\n"
    "    output channels suffixed _NAME (ROCKWATCH_WALL_STATE_north, ROCKWATCH_ALARM_north, ROCKWATCH_STATUS_north;\n"
    "    the wall named \"wall\": unsuffixed) and reads the top-level ground channels (shared) unless given its own;\n"
    "    alarm lines on stdout name the wall (\"wall\"), the summary lists the walls\n"
    "\n"
    "Offline mode (--offline-in LOG --offline-out LOG): every event of the input log on the two input channels is\n"
    "fed to the loop in order with its log timestamp as the receive time; the messages published go to the output\n"
    "log with the timestamp of the input event that caused them; a status at the first event, at each whole second\n"
    "of log time after it and at the last event. Deterministic: the same input gives the same output, byte for byte.\n"
    "\n"
    "Exit status: 0 stopped by SIGINT/SIGTERM or end of the offline log, 2 invalid options, configuration or\n"
    "files (message naming the option or key), 1 runtime failure (LCM, writing the output log).\n"
    "\n"
    "Examples:\n"
    "  rockwatch-monitor --config wall.json\n"
    "  rockwatch-monitor --h1 1.5 --h2 1.5 --r ana --rate 100 --lcm-url 'udpm://239.255.76.67:7667?ttl=0'\n"
    "  rockwatch-monitor --offline-in sensor.lcmlog --offline-out monitor.lcmlog\n";

}  // namespace

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--config", raw.config, "JSON configuration file (keys below); the command line overrides it")
      ->type_name("FILE");
  app.add_option("--lcm-url", raw.lcm_url, "LCM URL (default: the file's lcm_url, $LCM_DEFAULT_URL, "
                                           "udpm://239.255.76.67:7667?ttl=0)")
      ->type_name("URL");
  app.add_option("--arith", raw.arith,
                 "Engine arithmetic: fixed (default; the firmware's engine, = `rockwatch simulate --arith fixed`) | "
                 "double (= `rockwatch simulate --arith double`; linear or full model)")
      ->type_name("fixed|double");
  options::add_wall_options(app, raw.wall);
  options::add_restitution_option(app, raw.r);
  app.add_option("--model", raw.model, "Equation of motion: linear (default, the paper's; the fixed-point engine's "
                                       "only model) | full (with --arith double)")
      ->type_name("linear|full");
  options::add_kappa_option(app, raw.kappa);
  options::add_alarm_setting_options(app, raw.alarm, "");
  app.add_option("--rate", raw.rate, "Expected input sample rate [Hz] (default 200); the alarm runs once per sample")
      ->type_name("HZ");
  options::add_max_step_option(app, raw.max_step, "; the sample interval is 1/rate");
  app.add_option("--work-budget", raw.work_budget,
                 "The fixed-point engine's work per sample [Cortex-M4 instructions] (default 0: every sample finished "
                 "in its own call, as a host can afford); " + std::to_string(core::kDefaultWorkBudgetUnits) +
                     " runs as the Cortex-M4 firmware does: a sample whose work does not fit is published at later "
                     "samples' calls, the same answers later (carry-over)")
      ->type_name("UNITS");
  app.add_option("--work-overflow", raw.work_overflow,
                 "With --work-budget, what the engine does when 64 samples wait: shed (default; events no longer "
                 "located, every call within the budget) | finish (the oldest sample finished beyond the budget, the "
                 "answers as without a budget)")
      ->type_name("shed|finish");
  app.add_option("--clock-tolerance", raw.clock_tolerance,
                 "How far a sample's time may be from the monitor's clock at reception, ahead or behind [s] (default " +
                     options::number_text(firmware::kDefaultClockTolerance_us * 1e-6) +
                     "; up to 86400): a sample beyond it is counted and flagged (time untrusted) and its time is not "
                     "used to detect a publisher restart")
      ->type_name("S");
  app.add_option("--offline-in", raw.offline_in, "Offline mode: read this LCM log instead of listening")
      ->type_name("LOG");
  app.add_option("--offline-out", raw.offline_out, "Offline mode: write the published messages to this LCM log")
      ->type_name("LOG");
  app.add_option("--log", raw.log,
                 "Live mode: record every input message received and every message published to this LCM log "
                 "(written and synced once per second by its own thread; a full disk is reported and counted, "
                 "monitoring goes on; an existing log is appended to after its last complete event)")
      ->type_name("FILE");
  app.add_option("--accept-from", raw.accept_from,
                 "Live mode: accept input datagrams only from this IPv4 address or network (ADDR or ADDR/PREFIX; "
                 "repeatable; default: any source). Others are dropped and counted")
      ->type_name("ADDR[/PREFIX]");
  app.add_option("--receive-path", raw.receive_path,
                 "Live mode: own (default: the monitor's checked datagram path) or liblcm (liblcm's receive thread, "
                 "for measuring the two side by side only: it crashes on crafted datagrams)")
      ->type_name("own|liblcm");
  options::add_realtime_options(app, raw.timing, "the receive and processing thread (live mode)");
  app.add_flag("--observer", raw.observer,
               "Run the wall observer: fuse the wall sensors (wall_sensor_t) with the model, publish wall_estimate_t "
               "and alarm on the fused state (settings: the file's observer object, else the defaults)");
  app.add_option("--forecast", raw.forecast,
                 "Publish the ensemble forecast of collapse (SPEC section 10) as wall_forecast_t: N members over a "
                 "horizon of H seconds, e.g. 200,5 (N in [1, 100000], H in (0, 60]); computed on a thread of its own, "
                 "never holding the sample path")
      ->type_name("N,H");
  app.add_option("--forecast-rate", raw.forecast_rate,
                 "With --forecast: forecasts per second, in [0.1, 100] (default 10); when one takes longer than the "
                 "period the ticks it overran are skipped and counted (ticks_skipped)")
      ->type_name("HZ");
  app.add_option("--forecast-calibration", raw.forecast_calibration,
                 "With --forecast: the coefficients c0,c1,c2,c3[,c4] of the calibrated P (SPEC section 10 "
                 "'Calibrated P'; four numbers: c4 = 0; default: the shipped ones, fitted at H = 3 s and 5 s and "
                 "applied only at those horizons)")
      ->type_name("C0,C1,C2,C3[,C4]");
  app.add_flag("--print-config", raw.print_config,
               "Print the normalised settings and their digest as one JSON object and exit");
  app.add_flag("--version", raw.version, "Print the version and exit");
  app.footer(kFooter);
}

// As options::parse_command_line, with this program's name in the hint.
std::optional<std::string> parse_arguments(CLI::App& app, int argc, const char* const* argv) {
  const std::string hint = " (see rockwatch-monitor --help)";
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.help();
    const std::vector<std::string> extras = app.remaining();
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && !extras.empty()) {
      const std::string& first = extras.front();
      const bool is_option = first.size() > 1 && first.front() == '-';
      throw UsageError(std::string(is_option ? "unknown option " : "unexpected argument ") + options::quoted(first) + hint);
    }
    throw UsageError(e.what() + hint);
  }
  return std::nullopt;
}

firmware::MonitorArithmetic parse_arith(const std::string& name, const std::string& text) {
  if (text == "fixed") return firmware::MonitorArithmetic::fixed_point;
  if (text == "double") return firmware::MonitorArithmetic::double_precision;
  throw UsageError(name + " must be fixed or double (got " + options::quoted(text) + ")");
}

const char* arith_name(firmware::MonitorArithmetic a) {
  return a == firmware::MonitorArithmetic::double_precision ? "double" : "fixed";
}

}  // namespace rockwatch::monitor::config_detail
