// No per-run heap churn in sim::study::run_study: counts every global operator new while a study runs, for a
// small plan and for a plan with many more runs of the same kind, and fails (exit status 1) when the count grows
// with the number of runs. A plain program, not a CppUTest suite: it replaces the global allocation functions,
// which CppUTest also does for its leak bookkeeping. Registered with CTest (tests/bench/CMakeLists.txt).
//
// Also with the instability alarm evaluated in every analysis (AnalysisOptions::evaluate_alarm; the batch engine keeps
// no transitions) and with the fixed-point engine (each run also analysed by the double engine), and checks that 1 and
// 2 jobs give identical results.
//
// Usage: bench_study_allocations   (prints one line per case: runs, allocations, bytes)
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

namespace {

std::atomic<std::size_t> g_allocations{0};
std::atomic<std::size_t> g_bytes{0};

void* counted_alloc(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  g_bytes.fetch_add(size, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}

void* counted_aligned_alloc(std::size_t size, std::align_val_t align) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  g_bytes.fetch_add(size, std::memory_order_relaxed);
  const auto a = static_cast<std::size_t>(align);
  void* p = nullptr;
  if (posix_memalign(&p, a < sizeof(void*) ? sizeof(void*) : a, size == 0 ? 1 : size) != 0) return nullptr;
  return p;
}

// Out of line, so the compiler does not pair the replaced operator new with a visible free() (-Wmismatched-new-delete).
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }

}  // namespace

void* operator new(std::size_t size) {
  if (void* p = counted_alloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = counted_alloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_alloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_alloc(size); }
void* operator new(std::size_t size, std::align_val_t align) {
  if (void* p = counted_aligned_alloc(size, align)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) {
  if (void* p = counted_aligned_alloc(size, align)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }

namespace {

namespace sim = rockwatch::sim;
namespace core = rockwatch::core;
namespace study = rockwatch::sim::study;

constexpr double kPi = 3.14159265358979323846;

// Sine pulse trains of different frequency and length (the worker's buffer shrinks and grows between runs), each
// with a vertical partner; 0.12 … 0.40 g gives safe runs, collapses and free motions after the record.
study::StudyRecord make_record(const char* name, double f_hz, double cycles, double t_end_s, double fv_hz) {
  auto pulse = [](double f, double n, double phase, double t_end) {
    return sim::sample_motion(
               [&](double t) { return t <= n / f ? std::sin(2.0 * kPi * f * t + phase) : 0.0; }, 0.005, t_end)
        .ug_mps2;
  };
  study::StudyRecord r;
  r.name = name;
  r.dt_s = 0.005;
  r.ug_mps2 = pulse(f_hz, cycles, 0.0, t_end_s);
  r.vg_mps2 = pulse(fv_hz, 3.0 * fv_hz, 0.4, t_end_s);
  for (double& v : r.vg_mps2) v *= 0.5;  // half the horizontal: no lift-off (no AnalysisError) at these levels
  r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
  return r;
}

// 2 records × 2 restitutions × 2 vertical settings × n_levels PGA levels.
study::StudyPlan make_plan(std::size_t n_levels, bool dt_check, bool alarms,
                          sim::Arithmetic arithmetic = sim::Arithmetic::double_precision) {
  study::StudyPlan plan;
  plan.records.push_back(make_record("pulse3hz", 3.0, 3.0, 4.0, 5.0));
  plan.records.push_back(make_record("pulse1.5hz", 1.5, 1.0, 6.0, 7.0));
  for (std::size_t i = 0; i < n_levels; ++i) {
    plan.pga_g.push_back(0.12 + 0.28 * double(i) / double(n_levels - 1));
  }
  plan.restitutions = {{core::Restitution{core::RestitutionKind::ana, 0.0}, "ana"},
                       {core::Restitution{core::RestitutionKind::exp, 0.0}, "exp"}};
  plan.vertical = {false, true};
  plan.dt_check = dt_check;
  plan.analysis.evaluate_alarm = alarms;
  plan.analysis.arithmetic = arithmetic;
  return plan;
}

struct Count {
  std::size_t runs = 0, allocations = 0, bytes = 0, collapsed = 0, errors = 0, imminent = 0;
};

// Allocations made inside run_study only (the plan and the results vector's owner are outside the window; the
// results vector is sized inside it, as a caller's empty vector is).
Count count_study(const study::StudyPlan& plan, std::size_t jobs) {
  std::vector<study::RunResult> results;
  std::size_t progress_calls = 0;
  const study::ProgressFn progress = [&progress_calls](std::size_t, std::size_t) { ++progress_calls; };
  const std::size_t a0 = g_allocations.load(), b0 = g_bytes.load();
  study::run_study(plan, results, jobs, progress);
  Count c;
  c.allocations = g_allocations.load() - a0;
  c.bytes = g_bytes.load() - b0;
  c.runs = results.size();
  for (const study::RunResult& r : results) {
    c.collapsed += r.collapsed ? 1U : 0U;
    c.errors += r.error.empty() ? 0U : 1U;
    c.imminent += r.t_first_imminent_s ? 1U : 0U;
  }
  if (progress_calls != c.runs) {
    std::fprintf(stderr, "progress was called %zu times for %zu runs\n", progress_calls, c.runs);
    std::exit(1);
  }
  return c;
}

bool check(const char* label, std::size_t jobs, bool dt_check, bool alarms = false,
           sim::Arithmetic arithmetic = sim::Arithmetic::double_precision) {
  const study::StudyPlan small = make_plan(3, dt_check, alarms, arithmetic);   //  24 runs
  const study::StudyPlan large = make_plan(25, dt_check, alarms, arithmetic);  // 200 runs
  const Count s = count_study(small, jobs);
  const Count l = count_study(large, jobs);
  const long extra_allocations = static_cast<long>(l.allocations) - static_cast<long>(s.allocations);
  const double per_run = double(extra_allocations) / double(l.runs - s.runs);
  // With alarms the study must really have evaluated them: some runs reach IMMINENT (the collapses at least).
  const bool alarms_seen = !alarms || (l.imminent > 0 && l.imminent >= l.collapsed);
  const bool ok = extra_allocations <= 0 && s.errors == 0 && l.errors == 0 && alarms_seen;
  std::printf("%-22s jobs %zu: %3zu runs -> %3zu allocations (%6zu bytes), %3zu runs -> %3zu allocations (%6zu bytes);"
              " per extra run %.3f; collapses %zu/%zu, %zu/%zu; IMMINENT %zu/%zu  %s\n",
              label, jobs, s.runs, s.allocations, s.bytes, l.runs, l.allocations, l.bytes, per_run, s.collapsed,
              s.runs, l.collapsed, l.runs, l.imminent, l.runs, ok ? "ok" : "FAIL");
  return ok;
}

// Not an allocation figure, but cheap here and outside CppUTest (which must not see threads): the results of 1 and 2
// jobs are identical, bit for bit.
bool same_results_for_one_and_two_jobs() {
  const study::StudyPlan plan = make_plan(25, true, true);
  std::vector<study::RunResult> one, two;
  study::run_study(plan, one, 1);
  study::run_study(plan, two, 2);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    const study::RunResult& a = one[i];
    const study::RunResult& b = two[i];
    const bool same = a.done && b.done && a.collapsed == b.collapsed && a.max_abs_x_m == b.max_abs_x_m &&
                      a.t_collapse_s == b.t_collapse_s && a.t_exceed_s == b.t_exceed_s && a.n_impacts == b.n_impacts &&
                      a.collapsed_reference == b.collapsed_reference && a.error == b.error &&
                      a.t_first_imminent_s == b.t_first_imminent_s;
    differ += same ? 0U : 1U;
  }
  std::printf("jobs 1 vs 2: %zu of %zu results differ  %s\n", differ, one.size(), differ == 0 ? "ok" : "FAIL");
  return differ == 0;
}

}  // namespace

int main() {
  bool ok = true;
  ok = check("study", 1, false) && ok;
  ok = check("study with dt check", 1, true) && ok;
  ok = check("study", 2, false) && ok;
  ok = check("study with dt check", 2, true) && ok;
  ok = check("study with alarms", 1, false, true) && ok;
  ok = check("alarms with dt check", 2, true, true) && ok;
  ok = check("fixed point, alarms", 1, true, true, sim::Arithmetic::fixed_point) && ok;
  ok = check("fixed point, alarms", 2, true, true, sim::Arithmetic::fixed_point) && ok;
  if (!same_results_for_one_and_two_jobs()) {
    std::fprintf(stderr, "run_study's results depend on the number of jobs\n");
    return 1;
  }
  if (!ok) {
    std::fprintf(stderr, "run_study allocates per run: the allocation count grows with the number of runs\n");
    return 1;
  }
  return 0;
}
