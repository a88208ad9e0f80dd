// study.json, the state file of a `rockwatch study`: the plan with its digest (what --resume compares, so a study is
// never continued with other records, levels, cases, wall or engine settings), whether the study is running, was
// interrupted or is complete, and the command that started it.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

inline constexpr const char* kStudyStateFormat = "rockwatch-study";

enum class StudyState { running, interrupted, complete };

// Writes DIR/study.json: format, version, tool, command (the study's options, without --resume and --force), state,
// runs_done, runs_total, plan_digest, plan.
void write_study_state(const StudyRequest& request, const nlohmann::ordered_json& plan, StudyState state,
                       std::size_t runs_done, std::size_t runs_total);

// --resume: DIR/study.json must hold this plan. Throws UsageError naming the file and what differs (e.g. "pga_g:
// there 0.15 to 0.19 g (5 levels), now 0.15 to 0.18 g (4 levels)").
void check_same_plan(const StudyRequest& request, const nlohmann::ordered_json& plan);

// "rockwatch study ARGUMENTS --resume": the command that continues this study (--force dropped, shell-quoted).
std::string resume_command(const StudyRequest& request);

}  // namespace rockwatch::cli
