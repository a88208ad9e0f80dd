// Google Benchmark of the collapse-probability study's batch engine (sim::study::run_study): the default study of
// SPEC §6 on the shipped suite (sim/suites/npr9998-2015): 22 horizontal records (X and Y of 11 sets) × 20 PGA levels
// (0.11 … 0.30 g) × r ana/exp × without/with the vertical Z = 1760 analyses, on 1 and 2 threads. One iteration is
// one whole study (wall time). Target: under 2 s on 2 cores. Figures and commands: docs/BENCHMARKS.md.
//
// The set files are read here with a minimal parser ('#' header lines, dt from "# dt_s:", then "time x y z" rows
// in m/s²), so the benchmark depends on the engine only, not on the record readers.
#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

namespace {

namespace core = rockwatch::core;
namespace sim = rockwatch::sim;
namespace study = rockwatch::sim::study;

struct SetFile {
  double dt_s = 0.0;
  std::vector<double> x, y, z;
};

SetFile read_set(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  SetFile f;
  std::string line;
  std::vector<double> t;
  while (std::getline(in, line)) {
    if (line.rfind("# dt_s:", 0) == 0) f.dt_s = std::stod(line.substr(7));
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    double ti = 0.0, xi = 0.0, yi = 0.0, zi = 0.0;
    if (!(row >> ti >> xi >> yi >> zi)) throw std::runtime_error(path + ": bad row: " + line);
    t.push_back(ti);
    f.x.push_back(xi);
    f.y.push_back(yi);
    f.z.push_back(zi);
  }
  if (t.size() < 2) throw std::runtime_error(path + ": fewer than two rows");
  if (!(f.dt_s > 0.0)) f.dt_s = (t.back() - t.front()) / double(t.size() - 1);  // no header: from the time column
  return f;
}

study::StudyRecord make_record(const std::string& name, const std::string& component, double dt_s,
                               const std::vector<double>& ug, const std::vector<double>& vg) {
  study::StudyRecord r;
  r.name = name;
  r.component = component;
  r.dt_s = dt_s;
  r.ug_mps2 = ug;
  r.vg_mps2 = vg;
  r.peak_ug_mps2 = sim::peak_abs(ug);
  return r;
}

study::StudyPlan default_plan() {
  study::StudyPlan plan;
  for (int set = 1; set <= 11; ++set) {
    char name[16];
    std::snprintf(name, sizeof name, "set%02d", set);
    const SetFile f = read_set(std::string(ROCKWATCH_SUITE_DIR) + "/" + name + ".txt");
    plan.records.push_back(make_record(name, "X", f.dt_s, f.x, f.z));
    plan.records.push_back(make_record(name, "Y", f.dt_s, f.y, f.z));
  }
  for (int i = 0; i < 20; ++i) plan.pga_g.push_back(double(11 + i) / 100.0);
  plan.restitutions = {{core::Restitution{core::RestitutionKind::ana, 0.0}, "ana"},
                       {core::Restitution{core::RestitutionKind::exp, 0.0}, "exp"}};
  plan.vertical = {false, true};
  return plan;
}

void BM_DefaultStudy(benchmark::State& state, bool dt_check) {
  study::StudyPlan plan = default_plan();
  plan.dt_check = dt_check;
  const auto jobs = static_cast<std::size_t>(state.range(0));
  std::vector<study::RunResult> results;
  for (auto _ : state) {
    results.clear();
    study::run_study(plan, results, jobs);
    benchmark::DoNotOptimize(results.data());
  }
  std::size_t collapsed = 0, errors = 0, reference_differs = 0, samples = 0;
  for (const study::RunResult& r : results) {
    collapsed += r.collapsed ? 1U : 0U;
    errors += r.error.empty() ? 0U : 1U;
    reference_differs += r.collapsed_reference && *r.collapsed_reference != r.collapsed ? 1U : 0U;
  }
  for (const study::StudyRecord& r : plan.records) samples = std::max(samples, r.ug_mps2.size());
  const double runs = double(results.size());
  state.counters["runs"] = runs;
  state.counters["collapsed"] = double(collapsed);
  state.counters["errors"] = double(errors);
  if (dt_check) state.counters["reference_differs"] = double(reference_differs);
  state.counters["samples"] = double(samples);
  // Per analysis (per run; with the dt check a run is two analyses), from the wall time of a study.
  state.counters["per_run"] =
      benchmark::Counter(runs, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

BENCHMARK_CAPTURE(BM_DefaultStudy, suite, false)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DefaultStudy, suite_dt_check, true)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("study", "22 suite records x 20 PGA (0.11-0.30 g) x r ana/exp x without/with vertical");
  benchmark::AddCustomContext("suite", ROCKWATCH_SUITE_DIR);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
