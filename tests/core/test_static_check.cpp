// The static non-linear kinematic check (SPEC §5) and the design spectrum shapes it uses: the SPEC regression
// table, the paper's rounded results, every branch of the spectrum, the general (virtual-work) case and every
// validation rejection.
#include <cmath>
#include <cstring>
#include <limits>

#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/static_check.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_static_check {

using namespace rockwatch::core;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

StaticInputs wall(double h_m, double b_m, double lambda) {
  StaticInputs in;
  in.b_m = b_m;
  set_total_height(in, h_m);
  in.lambda = lambda;
  return in;
}

StaticResult checked(const StaticInputs& in) {
  StaticResult r;
  const StaticCheck check = run_static_check(in, r);
  CHECK_TEXT(check.ok(), check.message);
  return r;
}

void expect_rejected(const StaticInputs& in, StaticError code, const char* field) {
  StaticResult r;
  const StaticCheck check = run_static_check(in, r);
  CHECK_FALSE(check.ok());
  CHECK_EQUAL(static_cast<int>(code), static_cast<int>(check.code));
  STRCMP_EQUAL(field, check.field);
  CHECK_TRUE(std::strlen(check.message) > 0);
  CHECK_EQUAL(static_cast<int>(code), static_cast<int>(validate_static_inputs(in).code));
}

}  // namespace

TEST_GROUP(StaticCheck){};

// SPEC §5 regression table (npr9998-2015 defaults). The table has six decimals: agreement to 1e-6 covers its
// rounding and is tighter than the 1e-5 s / 1e-5 g asked for.
TEST(StaticCheck, SpecRegressionTable) {
  struct Row {
    double h_m, lambda, period_s, pga_g;
  };
  const Row rows[] = {
      {3.5, 0.4, 0.579102, 0.138984},  // NTC 2008
      {3.5, 0.6, 0.995166, 0.180193},  // NZSEE 2016
      {2.0, 0.1, 0.100809, 0.986013},  // h/b = 20
      {4.0, 0.5, 0.818973, 0.150161},  // h/b = 40
  };
  for (const Row& row : rows) {
    const StaticResult r = checked(wall(row.h_m, 0.1, row.lambda));
    DOUBLES_EQUAL(row.period_s, r.period_s, 1e-6);
    DOUBLES_EQUAL(row.pga_g, r.allowable_pga_g, 1e-6);
    DOUBLES_EQUAL(row.pga_g * kG, r.allowable_pga_mps2, 1e-5);
    DOUBLES_EQUAL(0.4 / row.h_m, r.k, 1e-15);
    DOUBLES_EQUAL(0.05, r.x_m, 1e-15);
    DOUBLES_EQUAL(row.lambda * 0.05, r.x_eq_max_m, 1e-15);
    CHECK_FALSE(r.general_case);
  }
}

TEST(StaticCheck, PaperRoundedResults) {
  const StaticResult ntc = checked(paper_static_inputs(InstabilityCode::ntc2008));
  const StaticResult nzsee = checked(paper_static_inputs(InstabilityCode::nzsee2016));
  DOUBLES_EQUAL(0.14, std::round(ntc.allowable_pga_g * 100.0) / 100.0, 1e-12);
  DOUBLES_EQUAL(0.18, std::round(nzsee.allowable_pga_g * 100.0) / 100.0, 1e-12);
  // The paper prints T = 0.573 s (NTC), a misprint of 0.579 (SPEC §5), and 0.996 s (NZSEE), within 1e-3 of ours.
  DOUBLES_EQUAL(0.579, ntc.period_s, 5e-4);
  DOUBLES_EQUAL(0.996, nzsee.period_s, 1e-3);
}

TEST(StaticCheck, DemandEqualsCapacityAtTheAllowablePga) {
  for (const double lambda : {0.1, 0.25, 0.4, 0.6, 0.9}) {
    const StaticResult r = checked(wall(3.5, 0.1, lambda));
    DOUBLES_EQUAL(r.x_eq_max_m, r.sd_m, 1e-15);
    DOUBLES_EQUAL(r.allowable_pga_mps2 * r.shape, r.se_mps2, 1e-15);
    const double t_over_2pi = r.period_s / (2.0 * kPi);
    DOUBLES_EQUAL(r.se_mps2 * t_over_2pi * t_over_2pi, r.sd_m, 1e-15);
    // Closed form of the chain: a_g = K g (1 − λ²) / (λ shape(T)).
    DOUBLES_EQUAL(r.k * kG * (1.0 - lambda * lambda) / (lambda * r.shape), r.allowable_pga_mps2, 1e-12);
    DOUBLES_EQUAL(r.allowable_pga_mps2 / kG, r.allowable_pga_g, 1e-15);
  }
}

TEST(StaticCheck, CodesAndTheirLambdas) {
  DOUBLES_EQUAL(0.4, code_lambda(InstabilityCode::ntc2008), 0.0);
  DOUBLES_EQUAL(0.6, code_lambda(InstabilityCode::nzsee2016), 0.0);
  InstabilityCode c = InstabilityCode::ntc2008;
  CHECK_TRUE(parse_code_name("nzsee2016", c));
  CHECK_TRUE(c == InstabilityCode::nzsee2016);
  CHECK_TRUE(parse_code_name("ntc2008", c));
  CHECK_TRUE(c == InstabilityCode::ntc2008);
  CHECK_FALSE(parse_code_name("NTC2008", c));
  CHECK_FALSE(parse_code_name("both", c));
  STRCMP_EQUAL("ntc2008", code_name(InstabilityCode::ntc2008));
  STRCMP_EQUAL("NZSEE 2016", code_title(InstabilityCode::nzsee2016));
}

// Only h = h1 + h2 enters: any split gives the same numbers.
TEST(StaticCheck, OnlyTheTotalHeightMatters) {
  StaticInputs even = paper_static_inputs();
  StaticInputs uneven = even;
  uneven.h1_m = 1.0;
  uneven.h2_m = 2.5;
  const StaticResult a = checked(even), b = checked(uneven);
  DOUBLES_EQUAL(a.period_s, b.period_s, 0.0);
  DOUBLES_EQUAL(a.allowable_pga_g, b.allowable_pga_g, 0.0);
  DOUBLES_EQUAL(3.5, b.h_m, 0.0);
  // A total height alone needs only h > b; blocks that were given must each exceed b.
  StaticInputs squat = wall(0.15, 0.1, 0.4);
  CHECK_TRUE(validate_static_inputs(squat).ok());
  squat.blocks_given = true;
  expect_rejected(squat, StaticError::h1_not_above_b, "h1");
}

TEST_GROUP(DesignSpectrum){};

TEST(DesignSpectrum, EveryBranchOfTheBackCalculatedShape) {
  const SpectrumShape s = spectrum_npr9998_2015();
  CHECK_TRUE(s.kind == SpectrumKind::npr9998_2015);
  DOUBLES_EQUAL(1.0, spectrum_shape(s, 0.0), 1e-15);
  DOUBLES_EQUAL(1.0 + 0.5 * 1.5, spectrum_shape(s, 0.075), 1e-15);      // rising: T < TB
  DOUBLES_EQUAL(2.5, spectrum_shape(s, 0.3), 1e-15);                    // plateau
  DOUBLES_EQUAL(2.5 * 0.4 / 0.5, spectrum_shape(s, 0.5), 1e-15);        // TC < T <= TD
  DOUBLES_EQUAL(2.5 * 0.4 * 0.67 / 1.0, spectrum_shape(s, 1.0), 1e-15);  // beyond TD
  DOUBLES_EQUAL(2.5 * 0.4 * 0.67 / 4.0, spectrum_shape(s, 2.0), 1e-15);
}

TEST(DesignSpectrum, ContinuousAtTheCorners) {
  for (const SpectrumShape& s : {spectrum_npr9998_2015(), spectrum_ec8_1A(), spectrum_ec8_2A(),
                                 spectrum_vertical_default(), spectrum_custom(3.2, 0.08, 0.35, 1.7)}) {
    for (const double corner : {s.tb_s, s.tc_s, s.td_s}) {
      const double eps = 1e-9 * corner;
      const double at = spectrum_shape(s, corner);
      DOUBLES_EQUAL(at, spectrum_shape(s, corner - eps), 1e-7);
      DOUBLES_EQUAL(at, spectrum_shape(s, corner + eps), 1e-7);
    }
    DOUBLES_EQUAL(s.p, spectrum_shape(s, s.tb_s), 1e-15);
    DOUBLES_EQUAL(s.p, spectrum_shape(s, s.tc_s), 1e-15);
    DOUBLES_EQUAL(s.p * s.tc_s / s.td_s, spectrum_shape(s, s.td_s), 1e-15);
  }
}

// EN 1998-1 ground A (S = 1), 5 % damping (η = 1), values by hand.
TEST(DesignSpectrum, Eurocode8GroundA) {
  const SpectrumShape t1 = spectrum_ec8_1A();
  DOUBLES_EQUAL(1.0 + (0.1 / 0.15) * 1.5, spectrum_shape(t1, 0.1), 1e-15);  // 2.0
  DOUBLES_EQUAL(2.0, spectrum_shape(t1, 0.1), 1e-12);
  DOUBLES_EQUAL(2.5, spectrum_shape(t1, 0.25), 1e-15);
  DOUBLES_EQUAL(1.0, spectrum_shape(t1, 1.0), 1e-15);      // 2.5 · 0.4 / 1
  DOUBLES_EQUAL(2.0 / 9.0, spectrum_shape(t1, 3.0), 1e-15);  // 2.5 · 0.4 · 2 / 9
  const SpectrumShape t2 = spectrum_ec8_2A();
  DOUBLES_EQUAL(1.75, spectrum_shape(t2, 0.025), 1e-15);   // 1 + 0.5 · 1.5
  DOUBLES_EQUAL(2.5, spectrum_shape(t2, 0.1), 1e-15);
  DOUBLES_EQUAL(1.25, spectrum_shape(t2, 0.5), 1e-15);     // 2.5 · 0.25 / 0.5
  DOUBLES_EQUAL(0.1875, spectrum_shape(t2, 2.0), 1e-15);   // 2.5 · 0.25 · 1.2 / 4
  SpectrumShape parsed;
  CHECK_TRUE(parse_spectrum_name("ec8-2A", parsed));
  CHECK_TRUE(parsed.kind == SpectrumKind::ec8_2A);
  DOUBLES_EQUAL(1.2, parsed.td_s, 0.0);
  CHECK_FALSE(parse_spectrum_name("ec8-3A", parsed));
  STRCMP_EQUAL("ec8-1A", spectrum_name(SpectrumKind::ec8_1A));
}

TEST(DesignSpectrum, ValidityOfTheParameters) {
  CHECK_TRUE(spectrum_valid(spectrum_custom(1.0, 0.1, 0.2, 0.3)));
  CHECK_FALSE(spectrum_valid(spectrum_custom(0.9, 0.1, 0.2, 0.3)));   // p < 1
  CHECK_FALSE(spectrum_valid(spectrum_custom(2.5, 0.0, 0.2, 0.3)));   // TB = 0
  CHECK_FALSE(spectrum_valid(spectrum_custom(2.5, 0.2, 0.2, 0.3)));   // TB = TC
  CHECK_FALSE(spectrum_valid(spectrum_custom(2.5, 0.1, 0.4, 0.3)));   // TD < TC
  CHECK_FALSE(spectrum_valid(spectrum_custom(2.5, 0.1, 0.2, kNaN)));
  STRCMP_CONTAINS("back-calculated", spectrum_provenance(SpectrumKind::npr9998_2015));
}

// The static chain on each branch: λ picks the period, the allowable PGA follows the branch's formula.
TEST(StaticCheck, EachSpectrumBranch) {
  const StaticResult below_tb = checked(wall(2.0, 0.1, 0.1));
  CHECK_TRUE(below_tb.period_s < 0.15);
  DOUBLES_EQUAL(1.0 + below_tb.period_s / 0.15 * 1.5, below_tb.shape, 1e-15);
  const StaticResult plateau = checked(wall(3.5, 0.1, 0.25));
  CHECK_TRUE(plateau.period_s > 0.15 && plateau.period_s < 0.40);
  DOUBLES_EQUAL(2.5, plateau.shape, 0.0);
  const StaticResult tc_td = checked(wall(3.5, 0.1, 0.4));
  CHECK_TRUE(tc_td.period_s > 0.40 && tc_td.period_s < 0.67);
  DOUBLES_EQUAL(2.5 * 0.4 / tc_td.period_s, tc_td.shape, 1e-15);
  const StaticResult beyond_td = checked(wall(3.5, 0.1, 0.6));
  CHECK_TRUE(beyond_td.period_s > 0.67);
  DOUBLES_EQUAL(2.5 * 0.4 * 0.67 / (beyond_td.period_s * beyond_td.period_s), beyond_td.shape, 1e-15);
  // Beyond TD, K ∝ 1/h and shape ∝ 1/T² ∝ 1/h: the allowable PGA no longer depends on the slenderness.
  DOUBLES_EQUAL(beyond_td.allowable_pga_g, checked(wall(2.5, 0.1, 0.6)).allowable_pga_g, 1e-12);
}

TEST(StaticCheck, CustomSpectrum) {
  StaticInputs in = paper_static_inputs(InstabilityCode::ntc2008);
  in.spectrum = spectrum_custom(3.0, 0.1, 0.3, 0.5);  // T = 0.579 s is beyond this TD
  const StaticResult r = checked(in);
  const double shape = 3.0 * 0.3 * 0.5 / (r.period_s * r.period_s);
  DOUBLES_EQUAL(shape, r.shape, 1e-15);
  const double omega = 2.0 * kPi / r.period_s;
  DOUBLES_EQUAL(0.02 * omega * omega / shape / kG, r.allowable_pga_g, 1e-12);
  DOUBLES_EQUAL(0.579102, r.period_s, 1e-6);  // the period does not depend on the spectrum
}

// With Fp = 0 and ψ = 0 the general formulas must give the simple case's numbers exactly, whatever a is.
TEST(StaticCheck, GeneralCaseReducesExactlyToTheSimpleOne) {
  for (const double a : {0.0, 0.3, 1.0}) {
    for (const double lambda : {0.1, 0.4, 0.6, 0.85}) {
      for (const double h_m : {2.0, 3.5, 4.0}) {
        StaticInputs in = wall(h_m, 0.1, lambda);
        in.a = a;
        in.rho_kgpm3 = 2400.0;  // ρ enters only through f = Fp / W
        const StaticResult r = checked(in);
        CHECK_FALSE(r.general_case);
        DOUBLES_EQUAL(0.0, r.f, 0.0);
        DOUBLES_EQUAL(4.0 * 0.1 / h_m, r.k, 0.0);
        DOUBLES_EQUAL(0.1 / 2.0, r.x_m, 0.0);
        const double simple_t = 2.0 * kPi * lambda * std::sqrt(h_m / (8.0 * kG * (1.0 - lambda * lambda)));
        DOUBLES_EQUAL(simple_t, r.period_s, 1e-15 * simple_t);
        DOUBLES_EQUAL(lambda * 0.05, r.x_eq_max_m, 0.0);
        const StaticResult paper = checked(wall(h_m, 0.1, lambda));
        DOUBLES_EQUAL(paper.allowable_pga_g, r.allowable_pga_g, 0.0);
      }
    }
  }
}

// Fp = 2000 N/m at a = 0.5, ψ = 0.01 rad on the paper's wall, λ = 0.4. Expected values computed by hand from the
// SPEC §5 formulas: W = 1800 · 9.81 · 0.1 · 3.5 = 6180.3 N/m, f = 0.3236088863,
// K = (4 · 0.1/3.5)(1 + 1.5 f) − 0.01, X = (0.1(1 + 1.5 f) − 0.01 · 3.5/4) / (2(1 + 2f)),
// T = 2π · 0.4 √(3.5 / (8 · 9.81 (1 + 2f)(1 − 0.16))), on the TC–TD branch.
TEST(StaticCheck, GeneralCaseByHand) {
  StaticInputs in = paper_static_inputs(InstabilityCode::ntc2008);
  in.fp_npm = 2000.0;
  in.a = 0.5;
  in.psi_rad = 0.01;
  const StaticResult r = checked(in);
  CHECK_TRUE(r.general_case);
  DOUBLES_EQUAL(6180.3, r.weight_npm, 1e-9);
  DOUBLES_EQUAL(0.3236088863000177, r.f, 1e-14);
  DOUBLES_EQUAL(0.15976152336571733, r.k, 1e-14);
  DOUBLES_EQUAL(0.04243255969863364, r.x_m, 1e-14);
  DOUBLES_EQUAL(0.45121053582222764, r.period_s, 1e-14);
  DOUBLES_EQUAL(0.016973023879453455, r.x_eq_max_m, 1e-14);
  DOUBLES_EQUAL(2.5 * 0.4 / 0.45121053582222764, r.shape, 1e-12);
  DOUBLES_EQUAL(0.1513807733794034, r.allowable_pga_g, 1e-13);

  // Each term on its own flags the general case; a alone (Fp = 0) changes nothing.
  StaticInputs psi_only = paper_static_inputs();
  psi_only.psi_rad = -0.01;
  CHECK_TRUE(checked(psi_only).general_case);
  DOUBLES_EQUAL(0.4 / 3.5 + 0.01, checked(psi_only).k, 1e-15);
  StaticInputs fp_only = paper_static_inputs();
  fp_only.fp_npm = 100.0;
  CHECK_TRUE(checked(fp_only).general_case);
  StaticInputs fp_at_a1 = fp_only;
  fp_at_a1.a = 1.0;  // the load at the far edge helps less
  CHECK_TRUE(checked(fp_at_a1).k < checked(fp_only).k);
}

TEST(StaticCheck, ValidationRejections) {
  const StaticInputs ok = paper_static_inputs();
  CHECK_TRUE(validate_static_inputs(ok).ok());
  struct Rejection {
    void (*change)(StaticInputs&);
    StaticError code;
    const char* field;
  };
  const Rejection rejections[] = {
      {[](StaticInputs& in) { in.lambda = 0.0; }, StaticError::lambda_out_of_range, "lambda"},
      {[](StaticInputs& in) { in.lambda = 1.0; }, StaticError::lambda_out_of_range, "lambda"},
      {[](StaticInputs& in) { in.lambda = -0.4; }, StaticError::lambda_out_of_range, "lambda"},
      {[](StaticInputs& in) { in.lambda = kNaN; }, StaticError::not_finite, "lambda"},
      {[](StaticInputs& in) { in.b_m = 0.0; }, StaticError::b_not_positive, "b"},
      {[](StaticInputs& in) { in.b_m = kInf; }, StaticError::not_finite, "b"},
      {[](StaticInputs& in) { set_total_height(in, 0.1); }, StaticError::h_not_above_b, "h"},
      {[](StaticInputs& in) { set_total_height(in, 0.05); }, StaticError::h_not_above_b, "h"},
      {[](StaticInputs& in) { set_total_height(in, kNaN); }, StaticError::not_finite, "h"},
      {[](StaticInputs& in) { in.h1_m = 0.1; }, StaticError::h1_not_above_b, "h1"},
      {[](StaticInputs& in) { in.h2_m = 0.05; }, StaticError::h2_not_above_b, "h2"},
      {[](StaticInputs& in) { in.h1_m = in.h2_m = 1.7e308; }, StaticError::not_finite, "h"},  // the sum overflows
      {[](StaticInputs& in) { in.fp_npm = -1.0; }, StaticError::fp_negative, "fp"},
      {[](StaticInputs& in) { in.a = -0.1; }, StaticError::a_out_of_range, "a"},
      {[](StaticInputs& in) { in.a = 1.5; }, StaticError::a_out_of_range, "a"},
      {[](StaticInputs& in) { in.rho_kgpm3 = 0.0; }, StaticError::rho_not_positive, "rho"},
      {[](StaticInputs& in) { in.g_mps2 = -9.81; }, StaticError::g_not_positive, "g"},
      {[](StaticInputs& in) { in.psi_rad = kInf; }, StaticError::not_finite, "psi"},
      // K = 4b/h − ψ: ψ at or above 4b/h = 0.1142857 leaves no restoring moment.
      {[](StaticInputs& in) { in.psi_rad = 0.4 / 3.5; }, StaticError::psi_too_large, "psi"},
      {[](StaticInputs& in) { in.psi_rad = 0.2; }, StaticError::psi_too_large, "psi"},
      {[](StaticInputs& in) { in.spectrum = spectrum_custom(2.5, 0.4, 0.3, 0.67); }, StaticError::spectrum_invalid,
       "spectrum"},
      {[](StaticInputs& in) { in.spectrum = spectrum_custom(0.5, 0.1, 0.3, 0.67); }, StaticError::spectrum_invalid,
       "spectrum"},
      // Finite inputs whose chain overflows are refused rather than reported as inf.
      {[](StaticInputs& in) {
         in.b_m = 1e300;
         set_total_height(in, 1e305);
       },
       StaticError::result_not_finite, ""},
  };
  for (const Rejection& r : rejections) {
    StaticInputs in = ok;
    r.change(in);
    expect_rejected(in, r.code, r.field);
  }
  StaticInputs leaning = ok;
  leaning.psi_rad = 0.11;  // just below 4b/h
  CHECK_TRUE(validate_static_inputs(leaning).ok());
}

}  // namespace unity_test_static_check
