#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <future>
#include <string>
#include <vector>

#include "real_fft.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"
#include "trapezoid_baseline.hpp"

namespace rockwatch::sim::synthesis {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Below this envelope value the clipped signal is not divided back by the envelope (it would amplify noise).
constexpr double kEnvelopeFloor = 1e-3;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

void require(bool ok, const std::string& what) {
  if (!ok) throw GeneratorError("generator settings: " + what);
}

// Fourier-amplitude correction factors at every FFT bin, from ratios at the matching periods: linear in ln f
// between matching frequencies, held beyond the band's ends; the DC bin is removed (a record has no mean).
std::vector<double> bin_factors(const std::vector<double>& periods_s, const std::vector<double>& ratio,
                                std::size_t bins, double df_hz) {
  const std::size_t m = periods_s.size();
  std::vector<double> log_f(m), r(m);
  for (std::size_t i = 0; i < m; ++i) {  // ascending frequency = descending period
    log_f[i] = std::log(1.0 / periods_s[m - 1 - i]);
    r[i] = ratio[m - 1 - i];
  }
  std::vector<double> factor(bins, 0.0);
  std::size_t j = 0;
  for (std::size_t k = 1; k < bins; ++k) {
    const double lf = std::log(static_cast<double>(k) * df_hz);
    if (lf <= log_f.front()) {
      factor[k] = r.front();
    } else if (lf >= log_f.back()) {
      factor[k] = r.back();
    } else {
      while (log_f[j + 1] < lf) ++j;
      const double w = (lf - log_f[j]) / (log_f[j + 1] - log_f[j]);
      factor[k] = r[j] + w * (r[j + 1] - r[j]);
    }
  }
  return factor;
}

// The worst deviation from the matched level over the check band, each side measured in units of its distance to
// the acceptance limit on that side (the band is not symmetric about the level: 0.9–1.3 around 1.0), so the kept
// iterate is the one with the most margin; ≤ 1 means inside the band.
double worst_band_deviation(const std::vector<double>& ratio, double level, double accept_min, double accept_max) {
  const double low_room = std::log(level / accept_min);
  const double high_room = std::log(accept_max / level);
  double worst = 0.0;
  for (const double r : ratio) {
    const double d = std::log(r / level);
    worst = std::max(worst, d < 0.0 ? -d / low_room : d / high_room);
  }
  return worst;
}

// The record a candidate stationary signal gives: enveloped, baseline-corrected, scaled to the target PGA.
std::vector<double> finished_record(const std::vector<double>& stationary, const std::vector<double>& envelope,
                                    const TrapezoidBaseline& baseline, double dt_s, double pga_mps2) {
  std::vector<double> a(envelope.size());
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = envelope[k] * stationary[k];
  baseline.correct(a, dt_s);
  const double peak = peak_abs(a);
  if (peak > 0.0) {
    const double scale = pga_mps2 / peak;
    for (double& v : a) v *= scale;
  }
  return a;
}

}  // namespace

double envelope_value(const Envelope& e, double t_s, double duration_s) {
  if (t_s < e.lead_s || t_s >= duration_s) return 0.0;
  const double u = t_s - e.lead_s;
  double v = 1.0;
  if (u < e.rise_s) {
    v = (u / e.rise_s) * (u / e.rise_s);
  } else if (u > e.rise_s + e.strong_s) {
    const double tau = u - e.rise_s - e.strong_s;
    v = (1.0 - e.coda_fraction) * std::exp(-e.decay_per_s * tau) + e.coda_fraction * std::exp(-e.coda_decay_per_s * tau);
  }
  const double taper_start_s = duration_s - e.taper_s;
  if (e.taper_s > 0.0 && t_s > taper_start_s) v *= 0.5 * (1.0 + std::cos(kPi * (t_s - taper_start_s) / e.taper_s));
  return v;
}

double ground_filter_gain(const GroundFilter& g, double f_hz) {
  if (!(f_hz > 0.0)) return 0.0;
  const double rg2 = (f_hz / g.fg_hz) * (f_hz / g.fg_hz);
  const double rf2 = (f_hz / g.ff_hz) * (f_hz / g.ff_hz);
  const double kanai_tajimi = (1.0 + 4.0 * g.zg * g.zg * rg2) / ((1.0 - rg2) * (1.0 - rg2) + 4.0 * g.zg * g.zg * rg2);
  const double clough_penzien = rf2 * rf2 / ((1.0 - rf2) * (1.0 - rf2) + 4.0 * g.zf * g.zf * rf2);
  return std::sqrt(kanai_tajimi * clough_penzien);
}

ComponentTarget component_target(const GeneratorSettings& s, Component c) {
  ComponentTarget t;
  if (is_vertical(c)) {
    // The vertical (P-wave dominated) arrives earlier, is shorter and has its energy at higher frequencies, where
    // the EC8 vertical plateau lies (0.05–0.15 s).
    t.spectrum = s.vertical_target;
    t.pga_mps2 = s.pga_g * s.vertical_pga_ratio * s.g_mps2;
    t.envelope.lead_s = 0.6;
    t.envelope.rise_s = 0.5;
    t.envelope.strong_s = 0.8;
    t.envelope.decay_per_s = 0.5;
    t.envelope.coda_fraction = 0.0;
    t.filter = GroundFilter{10.0, 0.6, 0.5, 0.6};
  } else {
    t.spectrum = s.horizontal_target;
    t.pga_mps2 = s.pga_g * s.g_mps2;
    t.envelope = Envelope{};
    t.filter = GroundFilter{};
  }
  return t;
}

std::uint64_t component_seed(std::uint64_t suite_seed, int set_number, Component c) {
  std::uint64_t state = suite_seed;
  const std::uint64_t mixed = splitmix64(state);
  state = mixed ^ ((static_cast<std::uint64_t>(set_number) << 8) | static_cast<std::uint64_t>(c));
  return splitmix64(state);
}

BandRatio spectral_ratio(const std::vector<double>& acc_mps2, double dt_s, const core::SpectrumShape& shape,
                         double pga_mps2, double from_s, double to_s, std::size_t n_periods, double damping) {
  BandRatio out;
  out.periods_s = log_spaced_periods(from_s, to_s, n_periods);
  const ResponseSpectrum rs = response_spectrum(acc_mps2, dt_s, out.periods_s, damping);
  out.ratio.resize(n_periods);
  for (std::size_t i = 0; i < n_periods; ++i) {
    out.ratio[i] = rs.psa_mps2[i] / (pga_mps2 * core::spectrum_shape(shape, out.periods_s[i]));
  }
  out.min = *std::min_element(out.ratio.begin(), out.ratio.end());
  out.max = *std::max_element(out.ratio.begin(), out.ratio.end());
  return out;
}

void validate_settings(const GeneratorSettings& s) {
  require(finite_positive(s.dt_s), "dt must be a finite value > 0 s (got " + number(s.dt_s) + ")");
  require(finite_positive(s.g_mps2), "g must be a finite value > 0 m/s2 (got " + number(s.g_mps2) + ")");
  require(finite_positive(s.pga_g), "the PGA a_g must be a finite value > 0 g (got " + number(s.pga_g) + ")");
  require(finite_positive(s.vertical_pga_ratio),
          "the vertical PGA ratio must be a finite value > 0 (got " + number(s.vertical_pga_ratio) + ")");
  require(core::spectrum_valid(s.horizontal_target), "the horizontal target needs p >= 1 and 0 < TB < TC < TD");
  require(core::spectrum_valid(s.vertical_target), "the vertical target needs p >= 1 and 0 < TB < TC < TD");
  require(std::isfinite(s.damping) && s.damping >= 0.0 && s.damping < 1.0,
          "damping must be in [0, 1) (got " + number(s.damping) + ")");
  for (const Component c : kAllComponents) {
    const Envelope e = component_target(s, c).envelope;
    const double needed_s = e.lead_s + e.rise_s + e.strong_s * (1.0 + s.envelope_spread) + e.taper_s + 2.0;
    require(std::isfinite(s.duration_s) && s.duration_s >= needed_s,
            "duration must be at least " + number(needed_s) + " s for the envelope of component " +
                std::string(1, component_letter(c)) + " (got " + number(s.duration_s) + ")");
  }
  require(s.duration_s / s.dt_s <= 1e7, "duration/dt gives more than 1e7 samples");
  require(finite_positive(s.match_from_s) && std::isfinite(s.match_to_s) && s.match_to_s > s.match_from_s,
          "the matching band needs 0 < from < to");
  require(finite_positive(s.check_from_s) && std::isfinite(s.check_to_s) && s.check_to_s > s.check_from_s,
          "the check band needs 0 < from < to");
  require(s.match_to_s <= s.duration_s && s.check_to_s <= s.duration_s,
          "the matching and check bands must end below the record duration");
  require(s.match_periods >= 2 && s.check_periods >= 2, "the bands need at least 2 periods each");
  require(finite_positive(s.accept_min) && std::isfinite(s.accept_max) && s.accept_max > s.accept_min,
          "the acceptance limits need 0 < min < max");
  require(finite_positive(s.suite_mean_tolerance) && s.suite_mean_tolerance < 1.0,
          "the suite-mean tolerance must be in (0, 1)");
  require(s.iterations >= 1 && s.iterations <= 1000, "iterations must be 1 to 1000");
  require(finite_positive(s.match_level) && s.match_level > s.accept_min && s.match_level < s.accept_max,
          "the matched level must lie inside the acceptance limits");
  require(finite_positive(s.correction_exponent) && s.correction_exponent <= 1.0,
          "the correction exponent must be in (0, 1]");
  require(std::isfinite(s.clip_fraction) && s.clip_fraction >= 0.0 && s.clip_fraction <= 1.0,
          "the clipping fraction must be in [0, 1]");
  require(s.fft_padding >= 1 && s.fft_padding <= 16, "the FFT padding must be 1 to 16");
  for (const DurationWindow* w : {&s.horizontal_d5_75_s, &s.horizontal_d5_95_s, &s.vertical_d5_75_s,
                                  &s.vertical_d5_95_s}) {
    require(finite_positive(w->min_s) && std::isfinite(w->max_s) && w->max_s > w->min_s,
            "duration windows need 0 < min < max");
  }
  require(s.max_attempts >= 1 && s.max_attempts <= 1000, "max attempts must be 1 to 1000");
  require(std::isfinite(s.envelope_spread) && s.envelope_spread >= 0.0 && s.envelope_spread < 0.9,
          "the envelope spread must be in [0, 0.9)");
}

namespace {

// One draw: envelope variation and noise from `stream`, then the Fourier-correction loop; returns the best iterate.
std::vector<double> match_one_draw(const GeneratorSettings& s, ComponentTarget target, RandomStream& stream) {
  // Drawn first and in this order, so the noise below is the same whatever the spread.
  target.envelope.strong_s *= stream.uniform(1.0 - s.envelope_spread, 1.0 + s.envelope_spread);
  target.envelope.decay_per_s *= stream.uniform(1.0 - s.envelope_spread, 1.0 + s.envelope_spread);

  const auto n = static_cast<std::size_t>(std::llround(s.duration_s / s.dt_s)) + 1;
  std::vector<double> envelope(n);
  for (std::size_t k = 0; k < n; ++k) {
    envelope[k] = envelope_value(target.envelope, static_cast<double>(k) * s.dt_s, s.duration_s);
  }
  const TrapezoidBaseline baseline(envelope, s.dt_s);

  // Stationary filtered noise, padded: the envelope cuts the record out of a signal padding × longer, so the
  // Fourier bins are finely spaced and the correction can act on each matching period separately.
  RealFft fft(s.fft_padding * n);
  const double df_hz = 1.0 / (static_cast<double>(fft.size()) * s.dt_s);
  std::vector<double> noise(fft.size());
  for (double& v : noise) v = stream.normal();
  std::vector<std::complex<double>> spectrum;
  fft.forward(noise, spectrum);
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    spectrum[k] *= ground_filter_gain(target.filter, static_cast<double>(k) * df_hz);
  }
  std::vector<double> x;
  fft.inverse(spectrum, x);
  x.resize(n);
  {
    double peak = 0.0;
    for (std::size_t k = 0; k < n; ++k) peak = std::max(peak, std::abs(envelope[k] * x[k]));
    for (double& v : x) v *= target.pga_mps2 / peak;
  }

  const std::vector<double> match_periods = log_spaced_periods(s.match_from_s, s.match_to_s, s.match_periods);
  const auto clip_iterations =
      static_cast<std::size_t>(std::floor(s.clip_fraction * static_cast<double>(s.iterations)));
  std::vector<double> best;
  double best_deviation = 0.0;
  std::vector<double> enveloped(n);
  for (std::size_t it = 0; it <= s.iterations; ++it) {
    // Every iterate is a candidate: the best one is kept, because the correction does not converge monotonically.
    std::vector<double> candidate = finished_record(x, envelope, baseline, s.dt_s, target.pga_mps2);
    const BandRatio check = spectral_ratio(candidate, s.dt_s, target.spectrum, target.pga_mps2, s.check_from_s,
                                           s.check_to_s, s.check_periods, s.damping);
    const double deviation = worst_band_deviation(check.ratio, s.match_level, s.accept_min, s.accept_max);
    if (best.empty() || deviation < best_deviation) {
      best = std::move(candidate);
      best_deviation = deviation;
    }
    if (it == s.iterations) break;

    for (std::size_t k = 0; k < n; ++k) enveloped[k] = envelope[k] * x[k];
    const ResponseSpectrum rs = response_spectrum(enveloped, s.dt_s, match_periods, s.damping);
    std::vector<double> ratio(match_periods.size());
    for (std::size_t i = 0; i < ratio.size(); ++i) {
      const double wanted = s.match_level * target.pga_mps2 * core::spectrum_shape(target.spectrum, match_periods[i]);
      ratio[i] = std::pow(wanted / rs.psa_mps2[i], s.correction_exponent);
    }
    const std::vector<double> factor = bin_factors(match_periods, ratio, fft.bins(), df_hz);
    fft.forward(x, spectrum);
    for (std::size_t k = 0; k < spectrum.size(); ++k) spectrum[k] *= factor[k];
    fft.inverse(spectrum, x);
    x.resize(n);
    for (double& v : x) v /= static_cast<double>(fft.size());

    // PGA anchoring: clipping the peaks above a_g and letting the next corrections restore the spectrum lowers
    // the record's peak-to-spectrum ratio until PGA = a_g and the spectrum sit together (SPEC §6).
    if (it < clip_iterations) {
      for (std::size_t k = 0; k < n; ++k) {
        if (envelope[k] <= kEnvelopeFloor) continue;
        const double a = envelope[k] * x[k];
        if (std::abs(a) > target.pga_mps2) x[k] = std::copysign(target.pga_mps2, a) / envelope[k];
      }
    }
  }
  return best;
}

// How far outside its window a value is, relative to the window (0 inside).
double window_miss(const DurationWindow& w, double d_s) {
  if (d_s < w.min_s) return (w.min_s - d_s) / w.min_s;
  if (d_s > w.max_s) return (d_s - w.max_s) / w.max_s;
  return 0.0;
}

// 0 for an accepted record, else a measure of how far it misses, to keep the closest when none is accepted.
double acceptance_miss(const GeneratorSettings& s, const GeneratedComponent& c) {
  const bool vertical = is_vertical(c.component);
  const double spectral = std::max({0.0, std::log(s.accept_min / c.check.min), std::log(c.check.max / s.accept_max)});
  return spectral + window_miss(vertical ? s.vertical_d5_75_s : s.horizontal_d5_75_s, c.d5_75_s) +
         window_miss(vertical ? s.vertical_d5_95_s : s.horizontal_d5_95_s, c.d5_95_s);
}

}  // namespace

GeneratedComponent generate_component(const GeneratorSettings& s, int set_number, Component c) {
  validate_settings(s);
  if (set_number < 1) throw GeneratorError("set numbers start at 1 (got " + std::to_string(set_number) + ")");

  const std::uint64_t seed = component_seed(s.seed, set_number, c);
  RandomStream stream(seed);
  const ComponentTarget target = component_target(s, c);
  const bool vertical = is_vertical(c);
  const DurationWindow& window_75 = vertical ? s.vertical_d5_75_s : s.horizontal_d5_75_s;
  const DurationWindow& window_95 = vertical ? s.vertical_d5_95_s : s.horizontal_d5_95_s;

  GeneratedComponent best;
  double best_miss = 0.0;
  for (std::size_t attempt = 1; attempt <= s.max_attempts; ++attempt) {
    GeneratedComponent out;
    out.component = c;
    out.seed = seed;
    out.attempts = attempt;
    out.acc_mps2 = match_one_draw(s, target, stream);
    out.check = spectral_ratio(out.acc_mps2, s.dt_s, target.spectrum, target.pga_mps2, s.check_from_s, s.check_to_s,
                               s.check_periods, s.damping);
    const std::vector<double> husid = husid_curve(out.acc_mps2, s.dt_s);
    const double t5 = husid_time_s(husid, s.dt_s, 0.05).value_or(0.0);
    out.d5_75_s = husid_time_s(husid, s.dt_s, 0.75).value_or(0.0) - t5;
    out.d5_95_s = husid_time_s(husid, s.dt_s, 0.95).value_or(0.0) - t5;
    out.spectrum_accepted = out.check.min >= s.accept_min && out.check.max <= s.accept_max;
    out.durations_accepted = window_75.contains(out.d5_75_s) && window_95.contains(out.d5_95_s);
    out.accepted = out.spectrum_accepted && out.durations_accepted;
    const TrapezoidEnd end = trapezoid_end(out.acc_mps2, s.dt_s);
    out.final_velocity_mps = end.velocity_mps;
    out.final_displacement_m = end.displacement_m;
    const double miss = acceptance_miss(s, out);
    if (attempt == 1 || miss < best_miss) {
      best = std::move(out);
      best_miss = miss;
    }
    if (best.accepted) break;
  }
  if (!best.accepted) best.attempts = s.max_attempts;  // every draw was made
  return best;
}

GeneratedSet generate_set(const GeneratorSettings& s, int set_number) {
  validate_settings(s);
  if (set_number < 1) throw GeneratorError("set numbers start at 1 (got " + std::to_string(set_number) + ")");
  // The three components are independent streams: computed concurrently, each deterministic on its own.
  std::array<std::future<GeneratedComponent>, 3> futures;
  for (std::size_t i = 0; i < 3; ++i) {
    futures[i] = std::async(std::launch::async, generate_component, std::cref(s), set_number, kAllComponents[i]);
  }
  GeneratedSet out;
  out.set_number = set_number;
  for (std::size_t i = 0; i < 3; ++i) out.components[i] = futures[i].get();
  return out;
}

SuiteMean suite_mean(const GeneratorSettings& s, const std::vector<GeneratedSet>& sets) {
  SuiteMean out;
  const auto mean_of = [&](bool vertical, BandRatio& band) {
    band.periods_s = log_spaced_periods(s.check_from_s, s.check_to_s, s.check_periods);
    band.ratio.assign(band.periods_s.size(), 0.0);
    std::size_t count = 0;
    for (const GeneratedSet& set : sets) {
      for (const GeneratedComponent& c : set.components) {
        if (is_vertical(c.component) != vertical) continue;
        if (c.check.ratio.size() != band.ratio.size()) throw GeneratorError("suite mean: components checked on other periods");
        for (std::size_t i = 0; i < band.ratio.size(); ++i) band.ratio[i] += c.check.ratio[i];
        ++count;
      }
    }
    if (count == 0) throw GeneratorError("suite mean: no records");
    for (double& r : band.ratio) r /= static_cast<double>(count);
    band.min = *std::min_element(band.ratio.begin(), band.ratio.end());
    band.max = *std::max_element(band.ratio.begin(), band.ratio.end());
    return band.min >= 1.0 - s.suite_mean_tolerance && band.max <= 1.0 + s.suite_mean_tolerance;
  };
  out.horizontal_accepted = mean_of(false, out.horizontal);
  out.vertical_accepted = mean_of(true, out.vertical);
  return out;
}

}  // namespace rockwatch::sim::synthesis
