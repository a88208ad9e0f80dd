#include "study/plan/study_request.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/outputs/study_files.hpp"
#include "study/outputs/study_runs_csv.hpp"
#include "study/scale/study_scale_options.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace study_request {

// The smallest --max-step: each analysis of a 40 s record then takes 4e7 steps. Smaller steps would make every
// analysis run for minutes to hours, and Ctrl-C waits for the analyses in flight, so a typo such as 1e-12 is refused.
constexpr double kMinStudyMaxStep_s = 1e-6;

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  std::string suite, records, sets;
  WallOptionTexts wall;
  AlarmOptionTexts alarm;
  ObserverOptionTexts observer;
  bool observer_evaluation = false;
  bool forecast = false;
  std::string forecast_members, forecast_horizon, forecast_every, forecast_seed;
  std::vector<std::string> forecast_setting;
  std::string pga = kDefaultStudyPga, r = "ana,exp", vertical = "without,with";
  std::string model = "linear", kappa, max_step;
  std::string units, dt, channel, vertical_channel, gain;
  std::string jobs, out;
  bool dt_check = false, plots = false, resume = false, force = false;
  ScaleOptionTexts scale;
};

const char* const kFooter =
    "The collapse-probability study of the design paper (SPEC section 6, its section 3 and Table 3): every\n"
    "horizontal record, without and with its vertical partner, for each restitution, scaled (with its partner, by\n"
    "the same factor) to each PGA level and run through the engine of rockwatch simulate. Per case (restitution x\n"
    "vertical setting): the smallest PGA that collapsed the wall, the survival rate per PGA, the paper's\n"
    "least-squares normal fit to the collapse fraction (mean, sd), a maximum-likelihood lognormal fragility with\n"
    "90 % bootstrap intervals (records resampled), resurrections (a record that survives a PGA above one that\n"
    "collapsed it), and the probability of collapse at the wall's static capacities (rockwatch static with the\n"
    "npr9998-2015 spectrum, back-calculated: NTC 2008 lambda 0.4 and NZSEE 2016 lambda 0.6; 0.139 g and 0.180 g\n"
    "for the paper's wall).\n"
    "\n"
    "Records: without --suite or --records, the shipped suite npr9998-2015, found in $ROCKWATCH_SUITE_DIR, else\n"
    "<bin>/../share/rockwatch/suites/npr9998-2015, else the source tree the tool was built from (the output says\n"
    "which). A suite gives components X and Y of every set (or of --sets), each with the Z of its set as vertical\n"
    "partner. --records LIST is a text file, one record per line: PATH [VERTICAL_PATH] (double quotes around a path\n"
    "with spaces; '#' starts a comment; paths relative to LIST's directory), read as rockwatch simulate reads\n"
    "--record and --vertical (--units, --dt, --channel, --vertical-channel, --gain, --g); a partner on another time\n"
    "grid is resampled onto the record's.\n"
    "\n"
    "Writes into DIR (created if missing):\n"
    "  runs.csv      one row per analysis: record, component, vertical, r, pga_g, collapsed, t_collapse_s,\n"
    "                t_exceed_s, max_abs_x_m, n_impacts, run (its index), with --dt-check collapsed_reference, and\n"
    "                error (why the engine refused the input, e.g. lift-off; such runs have no verdict)\n"
    "                with --alarms also t_first_imminent_s; with --arith fixed also saturated, collapsed_double,\n"
    "                t_collapse_double_s, max_abs_x_double_m, [t_first_imminent_double_s,] verdict_differs, and with\n"
    "                both t_first_imminent_published_s, imminent_late_samples, max_late_samples, shed_samples,\n"
    "                overrun_calls, max_call_units (the alarm as the firmware's monitor publishes it, its engine doing\n"
    "                a budget of work per sample: carry-over; at a full queue it sheds or, --work-overflow finish,\n"
    "                overruns)\n"
    "  summary.json  the plan, the capacities, the dt check and per case vertical, r, r_value, n_runs,\n"
    "                min_pga_collapse_g, fit_mean_g, fit_std_g, survival [{pga_g, survival_rate}],\n"
    "                p_collapse_ntc2008, p_collapse_nzsee2016 (from the normal fit; also _lognormal and _empirical),\n"
    "                lognormal {median_g, beta, median_ci90_g, ...}, resurrections (null where undetermined); with\n"
    "                --alarms alarm (with --arith fixed also alarm.as_published), with --arith fixed\n"
    "                fixed_vs_double (below)\n"
    "  table3.md     the paper's Table 3 with this study's numbers beside the paper's\n"
    "  study.json    the plan and its digest, and the state (running, interrupted, complete): what --resume reads\n"
    "  observer_runs.csv  with --observer: one row per evaluation run (case, record, pga_g, the true verdict, both\n"
    "                first IMMINENT times, x errors, r_hat, the observer's counts)\n"
    "  forecast.csv  with --forecast: one row per forecast (run, record, component, r, pga_g, t_s, p_collapse,\n"
    "                p_collapse_se, the quantiles, the baseline's features and probability, imminent, outcome)\n"
    "  forecast_reliability.png  with --forecast: the reliability diagram (matplotlib)\n"
    "  with --plots  fig6_collapse_map_R_V.png (record x PGA: collapsed or survived) and fig7_max_displacement_R_V.png\n"
    "                (max |x| per run, survival rate per PGA and the fitted curve), per case: R the restitution,\n"
    "                V H (horizontal only) or HV (with the vertical); matplotlib as for rockwatch static --sweep\n"
    "Numbers are written in shortest round-trip form, so the files do not depend on --jobs.\n"
    "\n"
    "--arith fixed runs every analysis on the monitor's fixed-point engine (linear model only) and again on the\n"
    "double engine, whose verdict is the verdict of record: summary.json's fixed_vs_double compares them (verdict\n"
    "flips, which of them also flip at the reference step with --dt-check, the largest difference of max |x| over runs\n"
    "that survive in both, of the first IMMINENT in integration steps). The statistics per case are the fixed\n"
    "engine's; --dt-check then runs the double engine at the reference step.\n"
    "--alarms runs the instability alarm in every analysis (see rockwatch simulate --help; --lambda-w,\n"
    "--alarm-hold, --energy-margin) and adds summary.json's alarm: recall (collapsed runs, by the double verdict,\n"
    "flagged IMMINENT strictly before t_collapse, over the collapsed runs), false_alarm_rate (surviving runs ever\n"
    "flagged IMMINENT, over the survivors), lead_time_s_median and lead_time_s_p05 (t_collapse - first IMMINENT\n"
    "over the collapsed runs flagged in time; percentiles by linear interpolation between order statistics,\n"
    "Hyndman-Fan type 7), with the counts and the settings.\n"
    "--alarms --observer also evaluates the wall observer (see rockwatch simulate --help, --wall-sensors) on walls\n"
    "that differ from the nominal one: for every record x PGA level x vertical setting of the plan and each mismatch\n"
    "case (true r = r_ana; true b = 0.9 b; 1.1 b; h1 : h2 = 1.5 : 2.0, same h) the true wall is simulated (double\n"
    "engine: the verdict of record) and its transducer sampled in memory (the record's rate, 0.5 mm noise, 2 mm zero\n"
    "offset); the nominal wall (r_exp) runs open loop and fused with those samples, both with the alarm.\n"
    "summary.json's observer: open_loop and fused {recall, false_alarm_rate, lead_time_s_median, lead_time_s_p05}\n"
    "against the TRUE wall's verdict (the definitions of --alarms), estimation {x_rms_over_x_inst (RMS of\n"
    "x - x_true over the steps where a wall moves, over the true x_inst), r_error_after_impacts (|r_hat - r_true|\n"
    "after 5 impacts), r_error_final}, per_case, settings; observer_runs.csv the runs. Not checkpointed: an\n"
    "interrupted evaluation is run again by --resume.\n"
    "\n"
    "--forecast evaluates the ensemble forecast of collapse (SPEC section 10): every horizontal-only run (each\n"
    "restitution x record x PGA level) on the double engine with the alarm, a forecast every --forecast-every-s while\n"
    "the wall moves, scored against the run (outcome: collapse within the horizon). Fitted leave one record out (a\n"
    "record = its name; a suite set's X and Y together): the state-only baseline (logistic regression on max\n"
    "E/E_barrier over 2 s and |x|/x_inst) and the thresholds p* (at most 5 % of the other records' surviving runs\n"
    "reach it; and at IMMINENT's false alarms). summary.json's forecast: brier, brier_skill (vs the base rate),\n"
    "reliability, calibration, baseline, brier_skill_vs_baseline, lead {ensemble_5_percent, baseline_5_percent,\n"
    "imminent, ensemble_at_imminent_false_alarms, ...}, goals, definitions. The forecaster's defaults were chosen on\n"
    "sets 1-3 of the shipped suite: --sets 4-11 keeps them apart. Not checkpointed.\n"
    "\n"
    "Progress goes to stderr (a bar on a terminal, else a line every 10 %). Ctrl-C (SIGINT) or SIGTERM lets the\n"
    "analyses in flight finish, writes runs.csv and study.json and exits with status 130; run the same command with\n"
    "--resume to finish the study without redoing what is done. --resume refuses a plan that differs from DIR's.\n"
    "\n"
    "Exit status: 0 done; 2 invalid options, records or DIR (a DIR holding a study needs --resume or --force);\n"
    "1 a plot could not be made (the other files are written) or an internal error; 130 interrupted.\n"
    "\n"
    "Examples:\n"
    "  rockwatch study --out study                                    the paper's study: 1760 analyses\n"
    "  rockwatch study --out quick --sets 1-3 --pga 0.15:0.25:0.02 --r exp --vertical without --plots\n"
    "  rockwatch study --records my-records.txt --vertical without --out real --jobs 4\n"
    "  rockwatch study --out study --resume                           after an interruption\n";

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--suite", raw.suite,
                 "Suite directory (rockwatch generate) whose X and Y records are studied, Z as vertical partner "
                 "(default: the shipped npr9998-2015)")
      ->type_name("DIR");
  app.add_option("--records", raw.records, "Text file listing records, one per line: PATH [VERTICAL_PATH]")
      ->type_name("LIST");
  app.add_option("--sets", raw.sets, "Sets of the suite to study, e.g. 1,2 or 1-3 (default: every set)")
      ->type_name("LIST");
  add_wall_options(app, raw.wall);
  app.add_option("--pga", raw.pga, std::string("PGA levels [g] FROM:TO:STEP (default ") + kDefaultStudyPga + ")")
      ->type_name("FROM:TO:STEP");
  app.add_option("--r", raw.r, "Restitution cases, comma-separated: ana | exp | impulse | a value in [0, 1] "
                               "(default ana,exp)")
      ->type_name("LIST");
  app.add_option("--vertical", raw.vertical, "Vertical settings, comma-separated: without | with (default "
                                             "without,with)")
      ->type_name("LIST");
  app.add_option("--model", raw.model, "Equation of motion: linear (default, the paper's) | full")
      ->type_name("linear|full");
  add_kappa_option(app, raw.kappa);
  add_max_step_option(app, raw.max_step);
  add_alarm_options(app, raw.alarm);
  app.add_flag("--observer", raw.observer_evaluation,
               "With --alarms: evaluate the wall observer on true walls that differ from the nominal one (r, b, h1/h2)");
  add_observer_options(app, raw.observer, "With --observer: ");
  app.add_flag("--forecast", raw.forecast,
               "Evaluate the ensemble forecast of collapse (SPEC section 10) over the horizontal-only runs: "
               "forecast.csv, forecast_reliability.png, summary.json forecast (Brier, skill, baseline, lead times)");
  app.add_option("--forecast-members", raw.forecast_members,
                 "With --forecast: N members per forecast, 1 to 100000 (default 100)")
      ->type_name("N");
  app.add_option("--forecast-horizon-s", raw.forecast_horizon,
                 "With --forecast: P(collapse) within H seconds, H in (0, 60] (default 3)")
      ->type_name("H");
  app.add_option("--forecast-every-s", raw.forecast_every,
                 "With --forecast: one forecast every S seconds of a run while the wall moves, S in [0.01, 60] "
                 "(default 0.1)")
      ->type_name("S");
  app.add_option("--forecast-seed", raw.forecast_seed, "With --forecast: seed of the members, 0 to 2^64-1 (default 29)")
      ->type_name("SEED");
  app.add_option("--forecast-setting", raw.forecast_setting,
                 "With --forecast: one of the forecaster's settings (SPEC section 10), NAME=VALUE, repeatable, to tune "
                 "or compare its ground and state models: intensity_log_sigma, intensity_ramp_s, highpass_ratio, "
                 "growth_max_per_s, damping, window_s, default_sigma_fraction, step_s, condition_on_record (0|1), "
                 "record_noise_var")
      ->type_name("NAME=VALUE");
  app.add_option("--units", raw.units, "Acceleration units of --records files: g|mps2|cmps2|mmps2 (overrides the file)")
      ->type_name("U");
  app.add_option("--dt", raw.dt, "Sample interval of one-column plain --records files [s]")->type_name("S");
  app.add_option("--channel", raw.channel, "Channel of multi-channel --records files (miniSEED), e.g. HNE")
      ->type_name("CODE");
  app.add_option("--vertical-channel", raw.vertical_channel,
                 "Channel of multi-channel vertical partner files, e.g. HNZ")
      ->type_name("CODE");
  app.add_option("--gain", raw.gain, "Sensor gain of miniSEED --records files in counts per m/s2 (> 0)")
      ->type_name("COUNTS_PER_MPS2");
  app.add_option("--jobs", raw.jobs, "Analyses run in parallel; 0 = every hardware thread (default 0)")
      ->type_name("N");
  app.add_flag("--dt-check", raw.dt_check,
               "Convergence check: run every analysis again on the double engine at a reference step (half the max "
               "step, at most 0.5 ms): runs.csv collapsed_reference and max_abs_x_reference_m, summary.json "
               "dt_check (verdicts that change, the survivors' max |x| error: median, p90, max)");
  app.add_option("--out", raw.out, "Directory for runs.csv, summary.json, table3.md, study.json and the plots")
      ->type_name("DIR");
  app.add_flag("--plots", raw.plots, "Draw the paper's Figures 6-8 per case (PNG, matplotlib)");
  app.add_flag("--resume", raw.resume, "Continue the interrupted study in --out: run only the analyses not done");
  app.add_flag("--force", raw.force, "Replace a study already in --out");
  app.footer(kFooter);
  add_scale_options(app, raw.scale);
}

std::vector<sim::study::RestitutionCase> parse_restitution_list(const std::string& text) {
  std::vector<sim::study::RestitutionCase> cases;
  for (const std::string& item : split_fields(text, ',')) {
    sim::study::RestitutionCase c;
    try {
      c.restitution = parse_restitution("--r", item);
    } catch (const UsageError&) {
      throw UsageError("--r must be a comma-separated list of ana, exp, impulse or energy ratios in [0, 1], e.g. "
                       "ana,exp (got " + quoted(item) + " in " + quoted(text) + ")");
    }
    c.label = c.restitution.kind == core::RestitutionKind::value ? number_text(c.restitution.value) : item;
    for (const sim::study::RestitutionCase& earlier : cases) {
      if (earlier.label == c.label) throw UsageError("--r lists " + c.label + " twice (got " + quoted(text) + ")");
    }
    cases.push_back(c);
  }
  return cases;
}

std::vector<bool> parse_vertical_list(const std::string& text) {
  std::vector<bool> settings;
  for (const std::string& item : split_fields(text, ',')) {
    if (item != "without" && item != "with") {
      throw UsageError("--vertical must be a comma-separated list of without (horizontal only) and with (the vertical "
                       "partner too), e.g. without,with (got " + quoted(item) + " in " + quoted(text) + ")");
    }
    const bool with = item == "with";
    if (std::find(settings.begin(), settings.end(), with) != settings.end()) {
      throw UsageError("--vertical lists " + item + " twice (got " + quoted(text) + ")");
    }
    settings.push_back(with);
  }
  return settings;
}

void reject_together(const CLI::App& app, const char* first, const char* second, const std::string& why) {
  if (given(app, first) && given(app, second)) {
    throw UsageError(std::string(first) + " cannot be combined with " + second + ": " + why);
  }
}

std::string parse_name(const char* option, const std::string& text, const char* what) {
  if (text.empty()) throw UsageError(std::string(option) + " needs " + what);
  return text;
}

// Record sources: the default suite, --suite or --records; the reading options belong to the --records files
// (suite files state their units and grid).
void parse_sources(const CLI::App& app, const RawOptions& raw, StudyRequest& q) {
  reject_together(app, "--suite", "--records", "give one record source");
  if (given(app, "--suite")) {
    q.suite_dir = parse_name("--suite", raw.suite, "a suite directory");
    check_input_directory("--suite", *q.suite_dir, "a suite directory written by rockwatch generate");
  }
  if (given(app, "--records")) {
    q.records_list = parse_name("--records", raw.records, "a list file name");
  }
  if (given(app, "--sets")) {
    if (q.records_list) {
      throw UsageError("--sets selects sets of a suite: it cannot be combined with --records (list the records "
                       "you want in LIST)");
    }
    q.sets = parse_set_list("--sets", raw.sets);
    q.sets_text = raw.sets;
  }
  for (const char* option : {"--units", "--dt", "--channel", "--vertical-channel", "--gain"}) {
    if (given(app, option) && !q.records_list) {
      throw UsageError(std::string(option) + " applies to the files of --records LIST; suite records state their "
                                             "units and time step");
    }
  }
  q.read_options.g_mps2 = q.wall.wall.g_mps2;
  if (given(app, "--units")) q.read_options.units = parse_units("--units", raw.units);
  if (given(app, "--dt")) q.read_options.dt_s = parse_positive_number("--dt", raw.dt, " s");
  if (given(app, "--gain")) {
    q.read_options.gain_counts_per_mps2 = parse_positive_number("--gain", raw.gain, " counts per m/s2");
  }
  if (given(app, "--channel")) q.read_options.channel = parse_name("--channel", raw.channel, "a channel code");
  if (given(app, "--vertical-channel")) {
    q.vertical_channel = parse_name("--vertical-channel", raw.vertical_channel, "a channel code");
  }
  // After the combinations, which are the first mistake to report. A FIFO would block the study and /dev/zero would
  // be read until memory runs out.
  if (q.records_list) check_input_file("--records", *q.records_list, "a text file listing records, one per line");
}

void parse_analysis(const CLI::App& app, const RawOptions& raw, StudyRequest& q) {
  q.analysis.model = parse_model("--model", raw.model);
  if (given(app, "--kappa")) q.analysis.kappa = parse_kappa("--kappa", raw.kappa);
  if (given(app, "--max-step")) {
    q.analysis.max_step_s = parse_positive_number("--max-step", raw.max_step, " s");
    if (q.analysis.max_step_s < kMinStudyMaxStep_s) {
      throw UsageError("--max-step must be at least " + number_text(kMinStudyMaxStep_s) +
                       " s: smaller steps make every analysis of the study take hours (got " +
                       number_text(q.analysis.max_step_s) + ")");
    }
  }
  parse_alarm_options(app, raw.alarm, q.analysis);
  if (raw.observer_evaluation) {
    if (!q.analysis.evaluate_alarm) {
      throw UsageError("--observer scores the alarm of the open-loop and the fused wall: give --alarms too");
    }
    q.observer = true;
    q.observer_options = parse_observer_options(app, raw.observer);
  } else if (observer_option_given(app)) {
    for (const char* name : kObserverOptionNames) {
      if (given(app, name)) throw UsageError(std::string(name) + " sets the wall observer: give --observer too");
    }
  }
  if (q.wall.r_from_file && !given(app, "--r")) {
    // A wall file's r is the one restitution case (its label the value), unless --r lists others.
    q.restitutions = parse_restitution_list(number_text(*q.wall.r_from_file));
  } else {
    q.restitutions = parse_restitution_list(raw.r);
  }
  for (const sim::study::RestitutionCase& c : q.restitutions) {
    sim::AnalysisOptions options = q.analysis;
    options.restitution = c.restitution;
    check_computable(q.wall.wall, options);
  }
  q.vertical = parse_vertical_list(raw.vertical);
  q.pga_text = raw.pga;
  q.pga_g = parse_pga_levels("--pga", raw.pga);
}

// --forecast and its settings. The defaults (100 members, 3 s, every 0.1 s) are those of the first evaluation
// (scripts/forecast-evaluation.py, docs/benchmarks-history.md "Ensemble forecast").
void parse_forecast(const CLI::App& app, const RawOptions& raw, StudyRequest& q) {
  if (!raw.forecast) {
    for (const char* name : {"--forecast-members", "--forecast-horizon-s", "--forecast-every-s", "--forecast-seed",
                             "--forecast-setting"}) {
      if (given(app, name)) throw UsageError(std::string(name) + " sets the forecast evaluation: give --forecast too");
    }
    return;
  }
  sim::study::ForecastEvaluationPlan e;
  e.settings.members = 100;
  e.settings.horizon_s = 3.0;
  if (given(app, "--forecast-members")) {
    const std::optional<std::uint64_t> n =
        whole_number(raw.forecast_members, sim::kForecastMembersMin, sim::kForecastMembersMax);
    if (!n) {
      throw UsageError("--forecast-members must be a whole number from " + std::to_string(sim::kForecastMembersMin) +
                       " to " + std::to_string(sim::kForecastMembersMax) + " (got " + quoted(raw.forecast_members) +
                       ")");
    }
    e.settings.members = static_cast<int>(*n);
  }
  if (given(app, "--forecast-horizon-s")) {
    e.settings.horizon_s = parse_finite_number("--forecast-horizon-s", raw.forecast_horizon);
    if (!(e.settings.horizon_s > 0.0 && e.settings.horizon_s <= sim::kForecastHorizonMax_s)) {
      throw UsageError("--forecast-horizon-s must be in (0, " + number_text(sim::kForecastHorizonMax_s) +
                       "] s (got " + number_text(e.settings.horizon_s) + ")");
    }
  }
  if (given(app, "--forecast-every-s")) {
    e.every_s = parse_finite_number("--forecast-every-s", raw.forecast_every);
    if (!(e.every_s >= sim::study::kForecastEveryMin_s && e.every_s <= sim::study::kForecastEveryMax_s)) {
      throw UsageError("--forecast-every-s must be in [" + number_text(sim::study::kForecastEveryMin_s) + ", " +
                       number_text(sim::study::kForecastEveryMax_s) + "] s (got " + number_text(e.every_s) + ")");
    }
  }
  if (given(app, "--forecast-seed")) {
    const std::optional<std::uint64_t> seed = whole_number(raw.forecast_seed, 0, UINT64_MAX);
    if (!seed) {
      throw UsageError("--forecast-seed must be a whole number from 0 to 2^64-1 (got " + quoted(raw.forecast_seed) +
                       ")");
    }
    e.settings.seed = *seed;
  }
  for (const std::string& text : raw.forecast_setting) {
    const std::size_t eq = text.find('=');
    const std::string name = eq == std::string::npos ? text : text.substr(0, eq);
    double* field = nullptr;
    sim::ForecastSettings& fs = e.settings;
    if (name == "intensity_log_sigma") field = &fs.intensity_log_sigma;
    else if (name == "intensity_ramp_s") field = &fs.intensity_ramp_s;
    else if (name == "highpass_ratio") field = &fs.highpass_ratio;
    else if (name == "growth_max_per_s") field = &fs.growth_max_per_s;
    else if (name == "damping") field = &fs.damping;
    else if (name == "window_s") field = &fs.window_s;
    else if (name == "default_sigma_fraction") field = &fs.default_sigma_fraction;
    else if (name == "step_s") field = &fs.step_s;
    else if (name == "record_noise_var") field = &fs.record_noise_var;
    double on_off = fs.condition_on_record ? 1.0 : 0.0;
    if (name == "condition_on_record") field = &on_off;
    if (eq == std::string::npos || field == nullptr) {
      throw UsageError("--forecast-setting takes NAME=VALUE, NAME one of intensity_log_sigma, intensity_ramp_s, "
                       "highpass_ratio, growth_max_per_s, damping, window_s, default_sigma_fraction, step_s, condition_on_record, record_noise_var "
                       "(got " +
                       quoted(text) + ")");
    }
    *field = parse_finite_number("--forecast-setting " + name, text.substr(eq + 1));
    if (name == "condition_on_record") {
      if (on_off != 0.0 && on_off != 1.0) throw UsageError("--forecast-setting condition_on_record takes 0 or 1");
      fs.condition_on_record = on_off == 1.0;
    }
  }
  if (const char* bad = sim::forecast_settings_error(e.settings)) {
    throw UsageError(std::string("--forecast-setting: the forecaster's setting ") + bad +
                     " is out of range (SPEC section 10)");
  }
  if (std::find(q.vertical.begin(), q.vertical.end(), false) == q.vertical.end()) {
    throw UsageError("--forecast evaluates the horizontal-only runs (the members drive no vertical): --vertical must "
                     "include without");
  }
  q.forecast = e;
}

void parse_run_options(const CLI::App& app, const RawOptions& raw, StudyRequest& q) {
  if (!given(app, "--out")) throw UsageError("--out DIR is required: the directory the study is written to");
  q.out_dir = parse_name("--out", raw.out, "a directory name");
  // The files a study reads back (--resume) or replaces: a FIFO or device in their place would block or be removed.
  for (const char* name : {kStudyStateName, kRunsCsvName, kSummaryJsonName, kTable3Name}) {
    const std::string path = q.out_dir + "/" + name;
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
      throw UsageError("--out " + q.out_dir + ": " + std::string(name) + " in it is " + file_kind_text(st.st_mode) +
                       ", not a regular file: remove it or choose another directory");
    }
  }
  if (given(app, "--jobs")) {
    const std::optional<std::uint64_t> jobs = whole_number(raw.jobs, 0, kMaxStudyJobs);
    if (!jobs) {
      throw UsageError("--jobs must be a whole number from 0 (every hardware thread) to " +
                       std::to_string(kMaxStudyJobs) + " (got " + quoted(raw.jobs) + ")");
    }
    q.jobs = static_cast<std::size_t>(*jobs);
  }
  reject_together(app, "--resume", "--force", "--resume continues the study in --out, --force replaces it");
  q.dt_check = raw.dt_check;
  q.plots = raw.plots;
  q.resume = raw.resume;
  q.force = raw.force;
}

}  // namespace study_request
}  // namespace

std::vector<double> parse_pga_levels(const std::string& option, const std::string& text) {
  using namespace study_request;
  const std::vector<std::string> fields = split_fields(text, ':');
  const std::string got = " (got " + quoted(text) + ")";
  if (fields.size() != 3) {
    throw UsageError(option + " expects FROM:TO:STEP in g, e.g. " + kDefaultStudyPga + got);
  }
  double values[3] = {};
  const char* const names[] = {"FROM", "TO", "STEP"};
  for (std::size_t i = 0; i < 3; ++i) {
    try {
      values[i] = parse_finite_number(option, fields[i]);
    } catch (const UsageError&) {
      throw UsageError(option + " expects FROM:TO:STEP in g, three numbers, e.g. " + kDefaultStudyPga + "; " +
                       names[i] + " is not a finite number" + got);
    }
  }
  const double from = values[0], to = values[1], step = values[2];
  if (!(from > 0.0)) throw UsageError(option + ": FROM must be > 0 g, a PGA to scale the records to" + got);
  if (!(to >= from)) throw UsageError(option + ": FROM must not exceed TO (levels ascend from FROM to TO)" + got);
  if (!(step > 0.0)) throw UsageError(option + ": STEP must be > 0 g" + got);
  const double intervals = std::floor((to - from) / step + 1e-9);
  if (!(intervals + 1.0 <= static_cast<double>(kMaxStudyLevels))) {
    throw UsageError(option + " gives " + number_text(intervals + 1.0) + " levels, more than the " +
                     std::to_string(kMaxStudyLevels) + " a study may take: raise STEP" + got);
  }
  std::vector<double> levels;
  const auto count = static_cast<std::size_t>(intervals) + 1;
  for (std::size_t k = 0; k < count; ++k) {
    levels.push_back(std::round((from + static_cast<double>(k) * step) * 1e12) / 1e12);
  }
  return levels;
}

std::vector<int> parse_set_list(const std::string& option, const std::string& text) {
  using namespace study_request;
  const std::string expected =
      option + " must be a list of set numbers (from 1) and ranges, e.g. 1,2 or 1-3 (got " + quoted(text) + ")";
  std::set<int> sets;
  for (const std::string& item : split_fields(text, ',')) {
    const std::size_t dash = item.find('-');
    const std::string first = item.substr(0, dash);
    const std::string last = dash == std::string::npos ? first : item.substr(dash + 1);
    const std::optional<std::uint64_t> a = whole_number(first, 1, 9999);
    const std::optional<std::uint64_t> b = whole_number(last, 1, 9999);
    if (!a || !b || *b < *a) throw UsageError(expected);
    for (std::uint64_t n = *a; n <= *b; ++n) sets.insert(static_cast<int>(n));
  }
  return std::vector<int>(sets.begin(), sets.end());
}

StudyParse parse_study_arguments(int argc, const char* const* argv) {
  using namespace study_request;
  CLI::App app{"Collapse-probability study (SPEC section 6, the design paper's Table 3): a wall through every record "
               "of a suite, without and with the vertical, for each restitution, at each PGA level.",
               "rockwatch study"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "study")) {
    return StudyParse{std::nullopt, std::move(*help)};
  }

  StudyRequest q;
  q.wall = parse_wall_options(app, raw.wall);
  parse_sources(app, raw, q);
  parse_analysis(app, raw, q);
  parse_forecast(app, raw, q);
  parse_run_options(app, raw, q);
  parse_scale_options(app, raw.scale, q);
  for (int i = 1; i < argc; ++i) q.arguments.emplace_back(argv[i]);
  return StudyParse{q, {}};
}

}  // namespace rockwatch::cli
