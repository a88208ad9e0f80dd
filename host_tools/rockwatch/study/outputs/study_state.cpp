#include "study/outputs/study_state.hpp"

#include <cstddef>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "common/process/text_report.hpp"
#include "common/process/tool_version.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/outputs/study_files.hpp"
#include "study/plan/study_plan.hpp"

namespace rockwatch::cli {

namespace {

const char* state_name(StudyState state) {
  switch (state) {
    case StudyState::running: return "running";
    case StudyState::interrupted: return "interrupted";
    case StudyState::complete: return "complete";
  }
  return "?";
}

// The options of the study itself, without --resume and --force (how it was started, not how this run treats DIR).
std::string command_text(const StudyRequest& q) {
  std::string text = "rockwatch study";
  for (const std::string& a : q.arguments) {
    if (a != "--resume" && a != "--force") text += " " + shell_quoted(a);
  }
  return text;
}

std::string levels_text(const nlohmann::json& levels) {
  if (!levels.is_array() || levels.empty()) return levels.dump();
  return levels.front().dump() + " to " + levels.back().dump() + " g (" + std::to_string(levels.size()) + " level" +
         (levels.size() == 1 ? "" : "s") + ")";
}

std::string records_difference(const nlohmann::json& there, const nlohmann::json& now) {
  if (!there.is_array() || there.size() != now.size()) {
    return "records: there " + std::to_string(there.is_array() ? there.size() : 0) + ", now " +
           std::to_string(now.size());
  }
  for (std::size_t i = 0; i < now.size(); ++i) {
    if (there[i] == now[i]) continue;
    const std::string name = now[i].value("name", std::string()) + " " + now[i].value("component", std::string());
    if (there[i].value("name", std::string()) != now[i].value("name", std::string())) {
      return "records: record " + std::to_string(i + 1) + " there " + there[i].value("name", std::string()) +
             ", now " + now[i].value("name", std::string());
    }
    return "records: " + name + " has other samples or settings (samples_hash, dt_s, vertical_partner)";
  }
  return "records";
}

// What differs, key by key, in words a user can act on.
std::string plan_differences(const nlohmann::json& there, const nlohmann::json& now) {
  std::string text;
  for (const auto& item : now.items()) {
    const std::string& key = item.key();
    const nlohmann::json old = there.contains(key) ? there[key] : nlohmann::json();
    if (old == item.value()) continue;
    std::string difference;
    if (key == "records") {
      difference = records_difference(old, item.value());
    } else if (key == "pga_g") {
      difference = "pga_g: there " + levels_text(old) + ", now " + levels_text(item.value());
    } else {
      difference = key + ": there " + old.dump() + ", now " + item.value().dump();
    }
    text += (text.empty() ? "" : "; ") + difference;
  }
  return text.empty() ? std::string("the plan digest") : text;
}

}  // namespace

void write_study_state(const StudyRequest& q, const nlohmann::ordered_json& plan, StudyState state,
                       std::size_t runs_done, std::size_t runs_total) {
  nlohmann::ordered_json j;
  j["format"] = kStudyStateFormat;
  j["version"] = 1;
  j["tool"] = std::string("rockwatch ") + tool_version();
  j["command"] = command_text(q);
  j["state"] = state_name(state);
  j["runs_done"] = runs_done;
  j["runs_total"] = runs_total;
  j["plan_digest"] = plan_digest(plan);
  j["plan"] = plan;
  write_study_file(study_file(q, kStudyStateName), [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

void check_same_plan(const StudyRequest& q, const nlohmann::ordered_json& plan) {
  const std::string path = study_file(q, kStudyStateName);
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json stored = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!stored.is_object() || stored.value("format", std::string()) != kStudyStateFormat || !stored.contains("plan")) {
    throw UsageError("--resume: " + path + " is not a rockwatch study state file (expected \"format\": \"" +
                     kStudyStateFormat + "\" and a \"plan\"); give --force to start the study again");
  }
  const nlohmann::json now = nlohmann::json::parse(plan.dump());
  if (stored.value("plan_digest", std::string()) == plan_digest(plan) && stored["plan"] == now) return;
  throw UsageError("--resume: the study in " + quoted(q.out_dir) + " was planned differently (" + path +
                   "): " + plan_differences(stored["plan"], now) +
                   ". It was started with: " + stored.value("command", std::string("?")) +
                   "; resume with those options and --resume, or give --force to replace it");
}

std::string resume_command(const StudyRequest& q) { return command_text(q) + " --resume"; }

}  // namespace rockwatch::cli
