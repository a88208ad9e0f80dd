#include "rockwatch/options/observer_options.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::options {

namespace {

std::string range_text(double low, double high, const char* unit) {
  return "in [" + number_text(low) + ", " + number_text(high) + "]" + unit;
}

double parse_in_range(const CLI::App& app, const char* option, const std::string& text, double low, double high,
                      const char* unit, double fallback) {
  if (!given(app, option)) return fallback;
  const double value = parse_finite_number(option, text);
  if (!(value >= low && value <= high)) {
    throw UsageError(std::string(option) + " must be " + range_text(low, high, unit) + " (got " + number_text(value) +
                     ")");
  }
  return value;
}

}  // namespace

void add_observer_options(CLI::App& app, ObserverOptionTexts& texts, const std::string& help_prefix) {
  const core::ObserverOptions d{};
  app.add_option("--observer-x-noise-m", texts.x_noise,
                 help_prefix + "standard deviation of the displacement transducer [m], " +
                     range_text(kMinObserverXNoise_m, kMaxObserverXNoise_m, "") + " (default " +
                     number_text(d.x_noise_m) + ")")
      ->type_name("M");
  app.add_option("--observer-a-noise-mps2", texts.a_noise,
                 help_prefix + "standard deviation of the mid-height accelerometer [m/s2], " +
                     range_text(kMinObserverANoise_mps2, kMaxObserverANoise_mps2, "") + " (default " +
                     number_text(d.a_noise_mps2) + ")")
      ->type_name("A");
  app.add_option("--observer-process-mps2", texts.process,
                 help_prefix + "standard deviation of the model's acceleration error per step [m/s2], " +
                     range_text(kMinObserverProcess_mps2, kMaxObserverProcess_mps2, "") + " (default " +
                     number_text(d.process_accel_mps2) + ")")
      ->type_name("A");
  app.add_option("--observer-gate-chi2", texts.gate,
                 help_prefix + "innovation gate, chi-square with one degree of freedom (16 = 4 sigma), " +
                     range_text(kMinObserverGateChi2, kMaxObserverGateChi2, "") + " (default " +
                     number_text(d.gate_chi2) + ")")
      ->type_name("X");
  app.add_option("--observer-capacity-sigmas", texts.capacity_sigmas,
                 help_prefix + "the alarm's margin on the estimated capacity: it uses x_inst - K sigma(x_inst), " +
                     range_text(kMinObserverCapacitySigmas, kMaxObserverCapacitySigmas, "") + " (default " +
                     number_text(d.alarm_capacity_sigmas) + ")")
      ->type_name("K");
  app.add_option("--observer-accel-inform-peak-noises", texts.accel_inform_peak_noises,
                 help_prefix + "the accelerometer informs the capacity once the half-cycle peaks at N x the "
                     "transducer's sigma; 0: from the first motion, for a wall whose overburden and heights are known "
                     "(SPEC 8), " +
                     range_text(kMinObserverAccelInformPeakNoises, kMaxObserverAccelInformPeakNoises, "") +
                     " (default " + number_text(d.accel_inform_peak_noises) + ")")
      ->type_name("N");
  app.add_option("--observer-doubt-nis", texts.doubt_nis,
                 help_prefix + "model doubt: when the displacement's normalised innovation squared, averaged over " +
                     std::to_string(d.doubt_window) + " samples, exceeds X the model is doubted (flag model_doubt; "
                     "the capacity's and r's sigma held wide; SPEC 11); 0 turns it off, else X >= 1 (default " +
                     number_text(d.doubt_nis) + ")")
      ->type_name("X");
  app.add_option("--observer-quiet-motion-noises", texts.quiet_motion_noises,
                 help_prefix + "while the model rests on a quiet ground, rejected displacement readings that spread "
                     "over N x the transducer's sigma are motion, not a fault: the motion is re-initialised from them "
                     "(SPEC 11); 0: always a fault (before issue 40), " +
                     range_text(kMinObserverQuietMotionNoises, kMaxObserverQuietMotionNoises, "") + " (default " +
                     number_text(d.quiet_motion_spread_noises) + ")")
      ->type_name("N");
  app.add_option("--observer-model-form-sigma", texts.model_form_sigma,
                 help_prefix + "the model's form in the published sigma(x_inst): F x x_inst added in quadrature to the "
                     "filter's own (no wall is the model; SPEC 11), " +
                     range_text(kMinObserverModelFormSigma, kMaxObserverModelFormSigma, "") + " (default " +
                     number_text(d.model_form_sigma) + ")")
      ->type_name("F");
  app.add_option("--observer-doubt-model-form-sigma", texts.doubt_model_form_sigma,
                 help_prefix + "the same once model doubt has been raised in the run (SPEC 11), " +
                     range_text(kMinObserverModelFormSigma, kMaxObserverModelFormSigma, "") + " (default " +
                     number_text(d.doubt_model_form_sigma) + ")")
      ->type_name("F");
  app.add_option("--observer-capacity-min-x", texts.capacity_min_x,
                 help_prefix + "a reading teaches the capacity (kappa_c, kappa_k) only while the model's |x| >= F x "
                     "the nominal x_inst: its decline, not a crushed hinge's elastic rise and plateau near x = 0 "
                     "(SPEC 11); 0: always, " +
                     range_text(kMinObserverCapacityMinX, kMaxObserverCapacityMinX, "") + " (default " +
                     number_text(d.capacity_min_x_fraction) + ")")
      ->type_name("F");
  app.add_option("--observer-doubt-capacity-min-x", texts.doubt_capacity_min_x,
                 help_prefix + "the same once model doubt has been raised in the run (the larger applies; SPEC 11), " +
                     range_text(kMinObserverCapacityMinX, kMaxObserverCapacityMinX, "") + " (default " +
                     number_text(d.doubt_capacity_min_x_fraction) + ")")
      ->type_name("F");
  app.add_option("--observer-capacity-correlation", texts.capacity_correlation,
                 help_prefix + "the prior correlation of kappa_c and kappa_k: an overburden or other heights than "
                     "drawn move both, a thickness other than drawn kappa_c alone (SPEC 11); 0: independent, " +
                     range_text(kMinObserverCapacityCorrelation, kMaxObserverCapacityCorrelation, "") +
                     " (default " + number_text(d.capacity_correlation) + ")")
      ->type_name("R");
  app.add_option("--observer-noise-learn-readings", texts.noise_learn_readings,
                 help_prefix + "the displacement transducer's noise measured before the shaking: once N readings of "
                     "the wall at rest on a quiet ground show a noise clearly above --observer-x-noise-m (by their "
                     "second differences), the filter uses it (SPEC 11); 0: off, else an integer in [8, " +
                     number_text(kMaxObserverNoiseLearnReadings) + "] (default " +
                     std::to_string(d.noise_learn_readings) + ")")
      ->type_name("N");
}

bool observer_option_given(const CLI::App& app) {
  for (const char* name : kObserverOptionNames) {
    if (given(app, name)) return true;
  }
  return false;
}

core::ObserverOptions parse_observer_options(const CLI::App& app, const ObserverOptionTexts& texts) {
  core::ObserverOptions o;
  o.x_noise_m = parse_in_range(app, "--observer-x-noise-m", texts.x_noise, kMinObserverXNoise_m, kMaxObserverXNoise_m,
                               " m", o.x_noise_m);
  o.a_noise_mps2 = parse_in_range(app, "--observer-a-noise-mps2", texts.a_noise, kMinObserverANoise_mps2,
                                  kMaxObserverANoise_mps2, " m/s2", o.a_noise_mps2);
  o.process_accel_mps2 = parse_in_range(app, "--observer-process-mps2", texts.process, kMinObserverProcess_mps2,
                                        kMaxObserverProcess_mps2, " m/s2", o.process_accel_mps2);
  o.gate_chi2 = parse_in_range(app, "--observer-gate-chi2", texts.gate, kMinObserverGateChi2, kMaxObserverGateChi2, "",
                               o.gate_chi2);
  o.alarm_capacity_sigmas = parse_in_range(app, "--observer-capacity-sigmas", texts.capacity_sigmas,
                                           kMinObserverCapacitySigmas, kMaxObserverCapacitySigmas, "",
                                           o.alarm_capacity_sigmas);
  o.accel_inform_peak_noises =
      parse_in_range(app, "--observer-accel-inform-peak-noises", texts.accel_inform_peak_noises,
                     kMinObserverAccelInformPeakNoises, kMaxObserverAccelInformPeakNoises, "",
                     o.accel_inform_peak_noises);
  o.doubt_nis = parse_in_range(app, "--observer-doubt-nis", texts.doubt_nis, kMinObserverDoubtNis, kMaxObserverDoubtNis,
                               "", o.doubt_nis);
  o.quiet_motion_spread_noises =
      parse_in_range(app, "--observer-quiet-motion-noises", texts.quiet_motion_noises, kMinObserverQuietMotionNoises,
                     kMaxObserverQuietMotionNoises, "", o.quiet_motion_spread_noises);
  o.model_form_sigma = parse_in_range(app, "--observer-model-form-sigma", texts.model_form_sigma,
                                      kMinObserverModelFormSigma, kMaxObserverModelFormSigma, "", o.model_form_sigma);
  o.doubt_model_form_sigma =
      parse_in_range(app, "--observer-doubt-model-form-sigma", texts.doubt_model_form_sigma,
                     kMinObserverModelFormSigma, kMaxObserverModelFormSigma, "", o.doubt_model_form_sigma);
  o.capacity_min_x_fraction = parse_in_range(app, "--observer-capacity-min-x", texts.capacity_min_x,
                                             kMinObserverCapacityMinX, kMaxObserverCapacityMinX, "",
                                             o.capacity_min_x_fraction);
  o.doubt_capacity_min_x_fraction =
      parse_in_range(app, "--observer-doubt-capacity-min-x", texts.doubt_capacity_min_x, kMinObserverCapacityMinX,
                     kMaxObserverCapacityMinX, "", o.doubt_capacity_min_x_fraction);
  o.capacity_correlation =
      parse_in_range(app, "--observer-capacity-correlation", texts.capacity_correlation,
                     kMinObserverCapacityCorrelation, kMaxObserverCapacityCorrelation, "", o.capacity_correlation);
  {
    const double n = parse_in_range(app, "--observer-noise-learn-readings", texts.noise_learn_readings,
                                    kMinObserverNoiseLearnReadings, kMaxObserverNoiseLearnReadings, "",
                                    double(o.noise_learn_readings));
    if (n != double(static_cast<std::int32_t>(n))) {
      throw UsageError("--observer-noise-learn-readings must be an integer (got " + number_text(n) + ")");
    }
    o.noise_learn_readings = static_cast<std::int32_t>(n);
  }
  // The core's own check, in case its ranges ever become narrower than the ones above.
  const core::ObserverError err = core::validate_observer_options(o);
  if (err != core::ObserverError::ok) throw UsageError(core::observer_error_message(err));
  return o;
}

std::vector<std::string> observer_flag_list(std::uint32_t flags) {
  namespace bit = core::observer_flag;
  const struct {
    std::uint32_t bit;
    const char* name;
  } names[] = {{bit::x_active, "x_active"},
               {bit::a_active, "a_active"},
               {bit::sensor_lost, "sensor_lost"},
               {bit::rejected, "rejected"},
               {bit::not_finite, "not_finite"},
               {bit::out_of_range, "out_of_range"},
               {bit::stuck, "stuck"},
               {bit::motion_while_quiet, "motion_while_quiet"},
               {bit::misaligned, "misaligned"},
               {bit::stale, "stale"},
               {bit::queue_overflow, "queue_overflow"},
               {bit::reinitialised, "reinitialised"},
               {bit::sensor_flag, "sensor_flag"},
               {bit::jump, "jump"},
               {bit::estimate_clamped, "estimate_clamped"},
               {bit::model_doubt, "model_doubt"}};
  std::vector<std::string> list;
  std::uint32_t known = 0;
  for (const auto& n : names) {
    known |= n.bit;
    if ((flags & n.bit) != 0) list.emplace_back(n.name);
  }
  for (int b = 0; b < 32; ++b) {
    const std::uint32_t mask = std::uint32_t{1} << b;
    if ((flags & mask & ~known) != 0) list.push_back("bit" + std::to_string(b));  // a flag newer than this tool
  }
  return list;
}

std::string observer_flag_names(std::uint32_t flags) {
  std::string text;
  for (const std::string& name : observer_flag_list(flags)) text += (text.empty() ? "" : ", ") + name;
  return text.empty() ? std::string("none") : text;
}

}  // namespace rockwatch::options
