// The plan of a `rockwatch study` (records, PGA levels, cases, wall and engine settings) as the batch engine takes
// it, its description in JSON with a digest (what summary.json reports and what --resume compares), the study's
// cases in the order of the paper's Table 3, and the static capacities the collapse probabilities are read at.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "study/plan/study_records.hpp"
#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

// Moves the records into the plan; the request supplies levels, cases, wall and engine settings.
sim::study::StudyPlan build_study_plan(const StudyRequest& request, StudyRecords& records);

// One case of the study: a restitution with a vertical setting.
struct StudyCase {
  std::size_t restitution_index = 0;
  std::size_t vertical_index = 0;
};

// Restitution outer, vertical inner, as the plan lists them: r_ana H-only, r_ana H+V, r_exp H-only, r_exp H+V for
// the defaults, the rows of the paper's Table 3.
std::vector<StudyCase> study_cases(const sim::study::StudyPlan& plan);

// "r_exp H+V", "r_0.5 H-only": the case as the paper's table names it.
std::string case_title(const sim::study::StudyPlan& plan, const StudyCase& c);

// "exp_HV", "0.5_H": the case in file names.
std::string case_tag(const sim::study::StudyPlan& plan, const StudyCase& c);

// FNV-1a (64 bit) of the record's grid and samples as stored: two records hash equal exactly when the study would
// run the same input.
std::uint64_t samples_hash(const sim::study::StudyRecord& record);

// The plan: "records" [{name, component, dt_s, samples, vertical_partner, samples_hash}], "pga_g", "restitutions"
// [{r, r_value}], "vertical" [bool], "cases" [{vertical, r}], "wall", "model", "kappa", "max_step_s", "dt_check",
// "arithmetic" ("double" | "fixed"), "alarm" ({lambda_warning, hold_s, energy_margin} or null without --alarms;
// work_overflow, imminent_horizon_s and energy_min_x only when not at their defaults).
// Everything that decides the results, nothing that does not (paths, --jobs, --plots).
nlohmann::ordered_json plan_json(const sim::study::StudyPlan& plan);

// "fnv1a64:0123456789abcdef" of the plan's compact JSON text.
std::string plan_digest(const nlohmann::ordered_json& plan);

// The label "ana", "exp", "impulse" as JSON text, a value restitution as its number.
nlohmann::ordered_json restitution_json(const sim::study::RestitutionCase& c);

// The allowable PGA of the static check (core::run_static_check, SPEC section 5) of the study's wall with the
// npr9998-2015 spectrum (back-calculated), lambda 0.4 (NTC 2008) and 0.6 (NZSEE 2016).
struct StaticCapacities {
  double ntc2008_g = 0.0;
  double nzsee2016_g = 0.0;
  bool general_case = false;  // Fp > 0: K, X, T derived by virtual work
};

// Throws UsageError when the static check refuses the wall (h1 + h2 not above b and the like).
StaticCapacities static_capacities(const core::WallParameters& wall);

}  // namespace rockwatch::cli
