// Wall properties, model coefficients, thresholds, restitution and instability against the reference JSON.
#include <cmath>
#include <cstring>
#include <string>

#include "reference_data.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;
using rockwatch::test::rel_tol;

namespace {

WallParameters wall_from_json(const nlohmann::json& j) {
  WallParameters w;
  w.b_m = j.at("b");
  w.h1_m = j.at("h1");
  w.h2_m = j.at("h2");
  w.rho_kgpm3 = j.at("rho");
  w.fp_npm = j.at("Fp");
  w.a = j.at("a");
  w.a_prime = j.at("a_prime");
  w.g_mps2 = j.at("g");
  return w;
}

Side side_from(int s) { return s > 0 ? Side::positive : Side::negative; }

// Checks p1…p6, M and F (both models) of one reference row, to a relative 1e-9.
void check_coefficient_row(const WallParameters& w, const nlohmann::json& row, bool check_forces) {
  const double g = w.g_mps2 + row.at("vg").get<double>();
  const Side side = side_from(row.at("side"));
  const double ug = row.at("ug"), x = row.at("x");
  const Coefficients<double> full = evaluate(model_constants(w, ModelKind::full), side, ug, g);
  const Coefficients<double> lin = evaluate(model_constants(w, ModelKind::linear), side, ug, g);
  const double tol = 1e-9;
  DOUBLES_EQUAL(row.at("p1"), full.p1, rel_tol(row.at("p1"), tol));
  DOUBLES_EQUAL(row.at("p2"), full.p2, rel_tol(row.at("p2"), tol));
  DOUBLES_EQUAL(row.at("p3"), full.p3, rel_tol(row.at("p3"), tol));
  DOUBLES_EQUAL(row.at("p4"), full.p4, rel_tol(row.at("p4"), tol));
  DOUBLES_EQUAL(row.at("p5"), full.p5, rel_tol(row.at("p5"), tol));
  DOUBLES_EQUAL(row.at("p6"), full.p6, rel_tol(row.at("p6"), tol));
  // The linear model keeps p1, p4, p6 and drops the rest.
  DOUBLES_EQUAL(full.p1, lin.p1, 0.0);
  DOUBLES_EQUAL(full.p4, lin.p4, 0.0);
  DOUBLES_EQUAL(full.p6, lin.p6, 0.0);
  DOUBLES_EQUAL(0.0, lin.p2, 0.0);
  DOUBLES_EQUAL(0.0, lin.p3, 0.0);
  DOUBLES_EQUAL(0.0, lin.p5, 0.0);
  if (check_forces) {
    DOUBLES_EQUAL(row.at("M_paper_full"), mass_at(full, x), rel_tol(row.at("M_paper_full"), tol));
    DOUBLES_EQUAL(row.at("F_paper_full"), force_at(full, x), 1e-9 * std::fabs(full.p6));
    DOUBLES_EQUAL(row.at("F_paper_linear"), force_at(lin, x), 1e-9 * std::fabs(full.p6));
  }
}

}  // namespace

TEST_GROUP(WallModel) {
  nlohmann::json ref;
  WallParameters paper;
  void setup() override {
    ref = rockwatch::test::load_reference();
    paper = paper_wall();
  }
};

TEST(WallModel, PaperWallIsTheReferenceWall) {
  const WallParameters w = wall_from_json(ref.at("wall"));
  DOUBLES_EQUAL(w.b_m, paper.b_m, 0.0);
  DOUBLES_EQUAL(w.h1_m, paper.h1_m, 0.0);
  DOUBLES_EQUAL(w.h2_m, paper.h2_m, 0.0);
  DOUBLES_EQUAL(w.rho_kgpm3, paper.rho_kgpm3, 0.0);
  DOUBLES_EQUAL(w.g_mps2, paper.g_mps2, 0.0);
  CHECK_TRUE(validate_wall(paper).ok());
}

TEST(WallModel, MassesAndInertias) {
  const auto& p = ref.at("properties");
  const WallProperties wp = wall_properties(paper);
  DOUBLES_EQUAL(p.at("m1"), wp.m1_kgpm, rel_tol(p.at("m1"), 1e-12));
  DOUBLES_EQUAL(p.at("m2"), wp.m2_kgpm, rel_tol(p.at("m2"), 1e-12));
  DOUBLES_EQUAL(p.at("J1"), wp.j1_kgm, rel_tol(p.at("J1"), 1e-9));
  DOUBLES_EQUAL(p.at("J2"), wp.j2_kgm, rel_tol(p.at("J2"), 1e-9));
  DOUBLES_EQUAL(p.at("p1"), model_constants(paper, ModelKind::linear).c1, rel_tol(p.at("p1"), 1e-9));
}

TEST(WallModel, SpecReferenceCoefficientsAtRest) {
  // SPEC §1: paper wall, ü = v̈ = 0, s = +1.
  const Coefficients<double> k = evaluate(model_constants(paper, ModelKind::linear), Side::positive, 0.0, 9.81);
  DOUBLES_EQUAL(212.742857, k.p1, 1e-6);
  DOUBLES_EQUAL(-3520.068245, k.p4, 1e-6);
  DOUBLES_EQUAL(-353.16, k.p6, 1e-9);
}

TEST(WallModel, CoefficientsMatchEveryReferenceRow) {
  for (const auto& row : ref.at("coefficients")) check_coefficient_row(paper, row, true);
}

TEST(WallModel, AccelerationsMatchReferenceForBothModels) {
  // ẍ = F/M at rest velocity-independent parts; the paper models have no ẋ² term, so ẋ does not enter.
  for (const auto& row : ref.at("accelerations")) {
    const double x = row.at("x"), ug = row.at("ug"), g = 9.81 + row.at("vg").get<double>();
    const Side side = x > 0.0 ? Side::positive : Side::negative;
    for (ModelKind kind : {ModelKind::full, ModelKind::linear}) {
      const Coefficients<double> k = evaluate(model_constants(paper, kind), side, ug, g);
      const double expected = row.at(kind == ModelKind::full ? "paper_full" : "paper_linear");
      DOUBLES_EQUAL(expected, force_at(k, x) / mass_at(k, x), rel_tol(expected, 1e-9));
    }
  }
}

TEST(WallModel, ThresholdsIncludingVerticalInput) {
  const auto& p = ref.at("properties");
  const ModelConstants<double> c = model_constants(paper, ModelKind::linear);
  for (Side s : {Side::positive, Side::negative}) {
    DOUBLES_EQUAL(p.at("threshold_mps2"), threshold_mps2(c, s, 9.81), rel_tol(p.at("threshold_mps2"), 1e-9));
    DOUBLES_EQUAL(p.at("threshold_g"), threshold_mps2(c, s, 9.81) / 9.81, rel_tol(p.at("threshold_g"), 1e-9));
  }
  const double minus = p.at("threshold_g_with_vg_minus_0p3g"), plus = p.at("threshold_g_with_vg_plus_0p2g");
  DOUBLES_EQUAL(minus, threshold_mps2(c, Side::positive, 9.81 * 0.7) / 9.81, rel_tol(minus, 1e-9));
  DOUBLES_EQUAL(plus, threshold_mps2(c, Side::positive, 9.81 * 1.2) / 9.81, rel_tol(plus, 1e-9));
  // SPEC §2 printed values.
  DOUBLES_EQUAL(1.121143, threshold_mps2(c, Side::positive, 9.81), 1e-6);
}

TEST(WallModel, RestitutionOptions) {
  const auto& p = ref.at("properties");
  DOUBLES_EQUAL(p.at("r_ana_eq17"), r_ana(paper), rel_tol(p.at("r_ana_eq17"), 1e-9));
  DOUBLES_EQUAL(p.at("r_exp_eq18"), r_exp(paper), rel_tol(p.at("r_exp_eq18"), 1e-9));
  DOUBLES_EQUAL(p.at("e_impulse_rigorous_velocity_ratio"), impulse_velocity_ratio(paper),
                rel_tol(p.at("e_impulse_rigorous_velocity_ratio"), 1e-9));
  DOUBLES_EQUAL(p.at("r_impulse_rigorous_energy_ratio"), r_impulse(paper),
                rel_tol(p.at("r_impulse_rigorous_energy_ratio"), 1e-9));
  DOUBLES_EQUAL(p.at("sqrt_r_exp"), std::sqrt(restitution_energy_ratio(paper, {RestitutionKind::exp, 0.0})),
                rel_tol(p.at("sqrt_r_exp"), 1e-9));
  DOUBLES_EQUAL(0.37, restitution_energy_ratio(paper, {RestitutionKind::value, 0.37}), 0.0);
  CHECK_TRUE(restitution_valid({RestitutionKind::value, 0.0}));
  CHECK_TRUE(restitution_valid({RestitutionKind::value, 1.0}));
  CHECK_FALSE(restitution_valid({RestitutionKind::value, 1.01}));
  CHECK_FALSE(restitution_valid({RestitutionKind::value, -0.1}));
  CHECK_FALSE(restitution_valid({RestitutionKind::value, std::nan("")}));
}

TEST(WallModel, InstabilityDisplacementBothModels) {
  const auto& xi = ref.at("properties").at("x_inst");
  for (Side s : {Side::positive, Side::negative}) {
    DOUBLES_EQUAL(xi.at("paper_linear"), x_inst_m(model_constants(paper, ModelKind::linear), s, 9.81),
                  rel_tol(xi.at("paper_linear"), 1e-9));
    DOUBLES_EQUAL(xi.at("paper_full"), x_inst_m(model_constants(paper, ModelKind::full), s, 9.81),
                  rel_tol(xi.at("paper_full"), 1e-9));
  }
  DOUBLES_EQUAL(0.1003276, x_inst_m(model_constants(paper, ModelKind::linear), Side::positive, 9.81), 1e-7);
}

TEST(WallModel, EnergyBarrierIsPotentialPeak) {
  // Linear model: V(x) = c|x| − ½kx² peaks at x_inst = c/k with V = c²/(2k) (SPEC §2).
  const ModelConstants<double> c = model_constants(paper, ModelKind::linear);
  const double cs = 353.16, k = 3520.0682449;
  DOUBLES_EQUAL(cs * cs / (2.0 * k), energy_barrier_jpm(c, Side::positive, 9.81), 1e-6);
  DOUBLES_EQUAL(cs * cs / (2.0 * k), energy_barrier_jpm(c, Side::negative, 9.81), 1e-6);
  const Coefficients<double> free_k = evaluate(c, Side::positive, 0.0, 9.81);
  const double xi = x_inst_m(c, Side::positive, 9.81);
  CHECK(potential_energy(free_k, xi * 0.99) < potential_energy(free_k, xi));
  CHECK(potential_energy(free_k, xi * 1.01) < potential_energy(free_k, xi));
}

TEST(WallModel, GeneralWallCoefficientsThresholdsAndInstability) {
  const auto& gw = ref.at("general_wall");
  const WallParameters w = wall_from_json(gw.at("wall"));
  CHECK_TRUE(validate_wall(w).ok());
  const WallProperties wp = wall_properties(w);
  DOUBLES_EQUAL(gw.at("m1"), wp.m1_kgpm, rel_tol(gw.at("m1"), 1e-12));
  DOUBLES_EQUAL(gw.at("m2"), wp.m2_kgpm, rel_tol(gw.at("m2"), 1e-12));
  DOUBLES_EQUAL(gw.at("J1"), wp.j1_kgm, rel_tol(gw.at("J1"), 1e-9));
  DOUBLES_EQUAL(gw.at("J2"), wp.j2_kgm, rel_tol(gw.at("J2"), 1e-9));
  DOUBLES_EQUAL(gw.at("d_plus"), wp.d_plus, 1e-12);
  DOUBLES_EQUAL(gw.at("d_minus"), wp.d_minus, 1e-12);
  for (const auto& row : gw.at("coefficients")) check_coefficient_row(w, row, false);
  const ModelConstants<double> lin = model_constants(w, ModelKind::linear);
  const ModelConstants<double> full = model_constants(w, ModelKind::full);
  DOUBLES_EQUAL(gw.at("threshold_plus_mps2"), threshold_mps2(lin, Side::positive, 9.81),
                rel_tol(gw.at("threshold_plus_mps2"), 1e-9));
  DOUBLES_EQUAL(gw.at("threshold_minus_mps2"), threshold_mps2(lin, Side::negative, 9.81),
                rel_tol(gw.at("threshold_minus_mps2"), 1e-9));
  DOUBLES_EQUAL(gw.at("r_ana"), r_ana(w), rel_tol(gw.at("r_ana"), 1e-9));
  DOUBLES_EQUAL(gw.at("r_exp"), r_exp(w), rel_tol(gw.at("r_exp"), 1e-9));
  DOUBLES_EQUAL(gw.at("e_impulse"), impulse_velocity_ratio(w), rel_tol(gw.at("e_impulse"), 1e-9));
  const auto& plus = gw.at("x_inst_plus");
  const auto& minus = gw.at("x_inst_minus");
  DOUBLES_EQUAL(plus.at("paper_linear"), x_inst_m(lin, Side::positive, 9.81), rel_tol(plus.at("paper_linear"), 1e-9));
  DOUBLES_EQUAL(minus.at("paper_linear"), x_inst_m(lin, Side::negative, 9.81),
                rel_tol(minus.at("paper_linear"), 1e-9));
  DOUBLES_EQUAL(plus.at("paper_full"), x_inst_m(full, Side::positive, 9.81), rel_tol(plus.at("paper_full"), 1e-9));
  DOUBLES_EQUAL(minus.at("paper_full"), x_inst_m(full, Side::negative, 9.81), rel_tol(minus.at("paper_full"), 1e-9));
}

TEST(WallModel, WithoutOverburdenTheResponseDoesNotDependOnDensity) {
  // SPEC §1: with Fp = 0 every coefficient scales with ρ, so ẍ = F/M does not change.
  WallParameters heavy = paper;
  heavy.rho_kgpm3 = 2400.0;
  for (ModelKind kind : {ModelKind::linear, ModelKind::full}) {
    const Coefficients<double> a = evaluate(model_constants(paper, kind), Side::positive, -2.0, 9.0);
    const Coefficients<double> b = evaluate(model_constants(heavy, kind), Side::positive, -2.0, 9.0);
    DOUBLES_EQUAL(force_at(a, 0.03) / mass_at(a, 0.03), force_at(b, 0.03) / mass_at(b, 0.03), 1e-12);
  }
}

TEST(WallModel, ValidationNamesTheFieldAndTheRule) {
  struct Bad {
    void (*mutate)(WallParameters&);
    WallError code;
    const char* field;
  };
  const Bad cases[] = {
      {[](WallParameters& w) { w.b_m = 0.0; }, WallError::b_not_positive, "b"},
      {[](WallParameters& w) { w.b_m = -0.1; }, WallError::b_not_positive, "b"},
      {[](WallParameters& w) { w.h1_m = 0.1; }, WallError::h1_not_above_b, "h1"},
      {[](WallParameters& w) { w.h2_m = 0.05; }, WallError::h2_not_above_b, "h2"},
      {[](WallParameters& w) { w.rho_kgpm3 = 0.0; }, WallError::rho_not_positive, "rho"},
      {[](WallParameters& w) { w.fp_npm = -1.0; }, WallError::fp_negative, "fp"},
      {[](WallParameters& w) { w.a = 1.5; }, WallError::a_out_of_range, "a"},
      {[](WallParameters& w) { w.a = -0.01; }, WallError::a_out_of_range, "a"},
      {[](WallParameters& w) { w.a_prime = 2.0; }, WallError::a_prime_out_of_range, "a_prime"},
      {[](WallParameters& w) { w.g_mps2 = 0.0; }, WallError::g_not_positive, "g"},
      {[](WallParameters& w) { w.h1_m = std::nan(""); }, WallError::not_finite, "h1"},
      {[](WallParameters& w) { w.rho_kgpm3 = HUGE_VAL; }, WallError::not_finite, "rho"},
  };
  for (const Bad& c : cases) {
    WallParameters w = paper_wall();
    c.mutate(w);
    const WallCheck check = validate_wall(w);
    CHECK_FALSE(check.ok());
    LONGS_EQUAL(static_cast<int>(c.code), static_cast<int>(check.code));
    STRCMP_EQUAL(c.field, check.field);
    CHECK(std::strlen(check.message) > 0);
  }
  WallParameters edge = paper_wall();
  edge.a = 1.0;
  edge.a_prime = 0.0;
  edge.fp_npm = 0.0;
  CHECK_TRUE(validate_wall(edge).ok());
}
