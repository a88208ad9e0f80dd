// Statistical recalibration of the ensemble forecast (SPEC §10 "Calibrated P", issue 29): the ensemble's raw
// P(collapse within H) post-processed as weather services post-process their ensembles (ensemble MOS, Platt
// scaling), stacked with the wall's state: a logistic regression
//
//   P_cal = 1 / (1 + exp(−(c0 + c1·logit(p̃) + c2·ρ_max + c3·|x|/x_inst + c4·logit(p̃)·min(ρ_max, 2)))),
//   p̃ = clamp(p, 0.5/N, 1 − 0.5/N),
//
// ρ_max the largest E/E_barrier (SPEC §2, free motion) over the last 2 s, |x|/x_inst the state now (the state-only
// baseline's two features): the ensemble's P adds what the state alone does not know, and the state corrects what
// the ensemble gets wrong. The interaction (c4, issue 29's second calibration) lets the weight of the ensemble's
// logit depend on the energy (fitted c4 < 0: the ensemble's P is trusted less where the state is energetic, which
// removed the over-confidence of the first calibration at P 0.5-0.9, docs/BENCHMARKS.md); ρ_max is capped at 2 in
// it so that the few forecasts far over the barrier (0.3 % of the default study's) do not lever it. Four
// coefficients (the first calibration's) mean c4 = 0. The coefficients are fitted by maximum likelihood
// (fit_logistic_regression); in `rockwatch study --forecast` leave one record out, for the live monitor and `simulate` on real
// records (default_forecast_calibration, issue 40; an option overrides them). They hold for the horizon they were fitted at.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rockwatch::sim {

inline constexpr int kCalibrationFeatures = 5;  // 1, logit(p̃), ρ_max, |x|/x_inst, logit(p̃)·min(ρ_max, 2)
// The cap of ρ_max in the interaction term.
inline constexpr double kCalibrationInteractionEnergyCap = 2.0;
// The window of the energy feature ρ_max [s] (the state-only baseline's, the same).
inline constexpr double kCalibrationEnergyWindow_s = 2.0;

struct ForecastCalibration {
  // c0 (constant), c1 (logit p̃), c2 (ρ_max), c3 (|x|/x_inst), c4 (logit p̃ · min(ρ_max, 2); 0: the first calibration)
  std::array<double, kCalibrationFeatures> c{};
  double horizon_s = 0.0;                         // the horizon H the coefficients were fitted at [s]
  std::string source;                             // where they come from (for reports)
};

// The shipped coefficients (SPEC §10) for a horizon: fitted on every forecast of every event of real records
// (scripts/forecast-real-records.py --refit-all: 24 components of 12 earthquakes, r_ana and r_exp, 0.8-1.6 x each
// record's collapse PGA; 200 members; issue 40) at H = 3 s and H = 5 s; none for another horizon. from_fused_state:
// the forecast starts from the observer's fused state (simulate --wall-sensors, the monitor with its observer), and
// the coefficients are those fitted on such forecasts (the same records with --wall-sensors).
std::optional<ForecastCalibration> default_forecast_calibration(double horizon_s, bool from_fused_state = false);
// The horizons default_forecast_calibration has coefficients for, as text ("3 s and 5 s"), for messages.
const char* shipped_calibration_horizons();

// "c0,c1,c2,c3[,c4]" (an option's text) as coefficients for horizon_s (four numbers: c4 = 0, the first
// calibration's model); none (and *error set) when it is not four or five finite numbers separated by commas.
std::optional<ForecastCalibration> parse_forecast_calibration(const std::string& text, double horizon_s,
                                                              std::string* error = nullptr);

// logit of the ensemble's P, clamped to [0.5/N, 1 − 0.5/N] (a fraction of N members is never exactly 0 or 1 in
// truth; the clamp is half a member).
double ensemble_logit(double p_collapse, int members);

// The features (1, logit(p̃), ρ_max, |x|/x_inst, logit(p̃)·min(ρ_max, 2)).
std::array<double, kCalibrationFeatures> calibration_features(double p_collapse, int members, double energy_ratio_max,
                                                              double x_over_x_inst);

// P_cal for the features.
double calibrated_probability(const ForecastCalibration& cal, double p_collapse, int members,
                              double energy_ratio_max, double x_over_x_inst);

// Maximum-likelihood logistic regression by Newton–Raphson (a `ridge` on every weight keeps the Hessian invertible
// when the classes separate): rows x[i] (k features each, the constant included by the caller), outcomes y[i],
// only the rows with use[i] (every row when use is empty). Returns the k weights (zeros when no row is used).
std::vector<double> fit_logistic_regression(const std::vector<double>& x, std::size_t k,
                                            const std::vector<std::uint8_t>& y,
                                            const std::vector<std::uint8_t>& use = {}, double ridge = 1e-6);

// The largest value over a trailing time window, allocation-free after construction (a ring of the last samples):
// the live monitor's ρ_max from the wall states its forecast thread reads.
class TrailingMax {
 public:
  explicit TrailingMax(std::size_t capacity = 4096, double window_s = kCalibrationEnergyWindow_s);
  void reset() { count_ = 0; }
  // A sample at time t_s (non-decreasing; an earlier one resets the window).
  void push(double t_s, double value);
  // The largest value over [t_last − window, t_last]; none before the first sample.
  std::optional<double> max() const;

 private:
  std::vector<double> t_, v_;
  std::size_t next_ = 0, count_ = 0;
  double window_s_;
};

}  // namespace rockwatch::sim
