#include "study/plan/study_plan.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

void hash_bytes(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= bytes[i];
    h *= kFnvPrime;
  }
}

void hash_doubles(std::uint64_t& h, const std::vector<double>& values) {
  const std::uint64_t count = values.size();
  hash_bytes(h, &count, sizeof count);
  if (!values.empty()) hash_bytes(h, values.data(), values.size() * sizeof(double));
}

std::string hex(std::uint64_t value) { return format("%016llx", static_cast<unsigned long long>(value)); }

double allowable_pga_g(const core::WallParameters& wall, core::InstabilityCode code) {
  core::StaticInputs in;
  in.b_m = wall.b_m;
  in.h1_m = wall.h1_m;
  in.h2_m = wall.h2_m;
  in.fp_npm = wall.fp_npm;
  in.a = wall.a;  // the static chain has one eccentricity: the x < 0 side's
  in.rho_kgpm3 = wall.rho_kgpm3;
  in.g_mps2 = wall.g_mps2;
  in.lambda = core::code_lambda(code);
  in.spectrum = core::spectrum_npr9998_2015();
  core::StaticResult result;
  const core::StaticCheck check = core::run_static_check(in, result);
  if (!check.ok()) {
    throw UsageError(std::string("the static check (for the capacities at which the study reports P(collapse)) "
                                 "refuses the wall: ") +
                     (*check.field != '\0' ? std::string(check.field) + " " : std::string()) + check.message);
  }
  return result.allowable_pga_g;
}

}  // namespace

study::StudyPlan build_study_plan(const StudyRequest& q, StudyRecords& records) {
  study::StudyPlan plan;
  plan.wall = q.wall.wall;
  plan.records = std::move(records.records);
  records.records.clear();
  plan.pga_g = q.pga_g;
  plan.restitutions = q.restitutions;
  plan.vertical = q.vertical;
  plan.analysis = q.analysis;
  plan.dt_check = q.dt_check;
  return plan;
}

std::vector<StudyCase> study_cases(const study::StudyPlan& plan) {
  std::vector<StudyCase> cases;
  for (std::size_t r = 0; r < plan.restitutions.size(); ++r) {
    for (std::size_t v = 0; v < plan.vertical.size(); ++v) cases.push_back(StudyCase{r, v});
  }
  return cases;
}

std::string case_title(const study::StudyPlan& plan, const StudyCase& c) {
  return "r_" + plan.restitutions[c.restitution_index].label + (plan.vertical[c.vertical_index] ? " H+V" : " H-only");
}

std::string case_tag(const study::StudyPlan& plan, const StudyCase& c) {
  return plan.restitutions[c.restitution_index].label + (plan.vertical[c.vertical_index] ? "_HV" : "_H");
}

std::uint64_t samples_hash(const study::StudyRecord& r) {
  std::uint64_t h = kFnvOffset;
  hash_bytes(h, &r.dt_s, sizeof r.dt_s);
  hash_doubles(h, r.ug_mps2);
  hash_doubles(h, r.vg_mps2);
  return h;
}

nlohmann::ordered_json restitution_json(const study::RestitutionCase& c) {
  if (c.restitution.kind == core::RestitutionKind::value) return c.restitution.value;
  return c.label;
}

nlohmann::ordered_json plan_json(const study::StudyPlan& plan) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json records = nlohmann::ordered_json::array();
  for (const study::StudyRecord& r : plan.records) {
    nlohmann::ordered_json record;
    record["name"] = r.name;
    record["component"] = r.component;
    record["dt_s"] = r.dt_s;
    record["samples"] = r.ug_mps2.size();
    record["vertical_partner"] = !r.vg_mps2.empty();
    record["samples_hash"] = "fnv1a64:" + hex(samples_hash(r));
    records.push_back(record);
  }
  j["records"] = records;
  j["pga_g"] = plan.pga_g;
  nlohmann::ordered_json restitutions = nlohmann::ordered_json::array();
  for (const study::RestitutionCase& c : plan.restitutions) {
    restitutions.push_back({{"r", restitution_json(c)},
                            {"r_value", core::restitution_energy_ratio(plan.wall, c.restitution)}});
  }
  j["restitutions"] = restitutions;
  j["vertical"] = plan.vertical;
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const StudyCase& c : study_cases(plan)) {
    cases.push_back({{"vertical", static_cast<bool>(plan.vertical[c.vertical_index])},
                     {"r", restitution_json(plan.restitutions[c.restitution_index])}});
  }
  j["cases"] = cases;
  const core::WallParameters& w = plan.wall;
  j["wall"] = {{"b_m", w.b_m},       {"h1_m", w.h1_m}, {"h2_m", w.h2_m},       {"rho_kgpm3", w.rho_kgpm3},
               {"fp_npm", w.fp_npm}, {"a", w.a},       {"a_prime", w.a_prime}, {"g_mps2", w.g_mps2}};
  j["model"] = model_name(plan.analysis.model);
  j["kappa"] = plan.analysis.kappa;
  j["max_step_s"] = plan.analysis.max_step_s;
  j["dt_check"] = plan.dt_check;
  j["arithmetic"] = arithmetic_name(plan.analysis.arithmetic);
  const core::AlarmSettings& a = plan.analysis.alarm;
  j["alarm"] = plan.analysis.evaluate_alarm
                   ? nlohmann::ordered_json{{"lambda_warning", a.lambda_warning},
                                            {"hold_s", a.hold_s},
                                            {"energy_margin", a.energy_margin}}
                   : nlohmann::ordered_json(nullptr);
  // The publication's overflow policy changes its columns; absent at the default (the digest of existing plans stays).
  if (plan.analysis.work_overflow != core::WorkOverflow::shed) {
    j["alarm"]["work_overflow"] = work_overflow_name(plan.analysis.work_overflow);
  }
  // Likewise the look-ahead rule (SPEC §11; named when not 0): shards run with another horizon are another plan.
  if (plan.analysis.evaluate_alarm && a.imminent_horizon_s > 0.0) {
    j["alarm"]["imminent_horizon_s"] = a.imminent_horizon_s;
  }
  if (plan.analysis.evaluate_alarm && a.energy_min_x > 0.0) j["alarm"]["energy_min_x"] = a.energy_min_x;
  return j;
}

std::string plan_digest(const nlohmann::ordered_json& plan) {
  const std::string text = plan.dump();
  std::uint64_t h = kFnvOffset;
  hash_bytes(h, text.data(), text.size());
  return "fnv1a64:" + hex(h);
}

StaticCapacities static_capacities(const core::WallParameters& wall) {
  StaticCapacities c;
  c.ntc2008_g = allowable_pga_g(wall, core::InstabilityCode::ntc2008);
  c.nzsee2016_g = allowable_pga_g(wall, core::InstabilityCode::nzsee2016);
  c.general_case = wall.fp_npm != 0.0;
  return c;
}

}  // namespace rockwatch::cli
