// No allocation per sample in firmware::WallEngine: replaces malloc/calloc/realloc/free (and the aligned
// variants), forwarding to glibc's __libc_* implementations, and every global operator new/delete, counting each
// call; initialises a WallEngine (allocation allowed), then counts around 100 000 process() calls (with impacts,
// collapses and reset()) and exits 1 unless the count is 0. A self-check first makes sure that a deliberate
// malloc and operator new in a window are counted.
//
// A plain program, not a CppUTest suite (CppUTest replaces operator new for its leak bookkeeping), and not built
// with sanitizers (ASan replaces malloc itself): tests/firmware/proofs/CMakeLists.txt registers it as `engine_allocations`
// only in builds without -fsanitize.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "engine_test_input.hpp"

#include "counting_allocator.hpp"

namespace {
namespace et = rockwatch::engine_test;

}  // namespace

int main() {
  if (!counting_allocator::self_check()) {
    std::fprintf(stderr, "FAIL: the allocation counters do not see deliberate allocations\n");
    return 1;
  }
  const std::vector<rockwatch::firmware::SensorSampleQ> cycle = et::make_cycle();
  rockwatch::firmware::WallEngine engine;
  const std::uint64_t before_init = g_calls;
  const rockwatch::firmware::WallEngineError e = engine.init(et::paper_config());
  const std::uint64_t init_calls = g_calls - before_init;
  if (e != rockwatch::firmware::WallEngineError::ok) {
    std::fprintf(stderr, "FAIL: WallEngine::init: %s\n", rockwatch::firmware::wall_engine_error_message(e));
    return 1;
  }

  const std::uint64_t before = g_calls;
  const et::RunCounts c = et::run_engine(engine, cycle, et::kMeasuredSamples);
  const std::uint64_t calls = g_calls - before;

  std::printf("init: %llu allocation calls (allowed)\n", static_cast<unsigned long long>(init_calls));
  std::printf("process: %llu samples, %llu impacts, %llu collapses (each followed by reset), %llu moving samples,"
              " %llu IMMINENT samples, %llu saturated samples\n",
              static_cast<unsigned long long>(c.samples), static_cast<unsigned long long>(c.impacts),
              static_cast<unsigned long long>(c.collapses), static_cast<unsigned long long>(c.moving_samples),
              static_cast<unsigned long long>(c.imminent_samples),
              static_cast<unsigned long long>(c.saturated_samples));
  std::printf("allocation calls during process()/reset(): %llu\n", static_cast<unsigned long long>(calls));
  if (!et::run_was_eventful(c)) {
    std::fprintf(stderr, "FAIL: the input did not produce impacts and a collapse; the count would prove nothing\n");
    return 1;
  }
  if (calls != 0) {
    std::fprintf(stderr, "FAIL: WallEngine::process/reset allocated (%llu calls)\n",
                 static_cast<unsigned long long>(calls));
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
