// The study's worker pool, shared by the batch study (batch_study.cpp), the observer and forecast evaluations and the
// identification's bootstrap (identification.cpp): runs the runs not yet done on `jobs` threads, each with a worker of its own (the
// per-thread buffers: one allocation per thread, none per run), the calling thread being one of them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "rockwatch/sim/study/batch_study.hpp"

namespace rockwatch::sim::study {

// For every index of `todo` (in order of claim: each thread takes the next unclaimed one), on its thread's
// worker: `run(worker, index)`. `make_worker()` builds a thread's worker. jobs 0: one thread per core. progress(done,
// total) is called under a lock after each run. `cancel` (may be null) stops every thread before its next run. A
// worker that throws stops the others; the first exception is rethrown once all threads have joined, and the runs
// finished by then are kept (the caller's results are written by `run`).
template <typename MakeWorker, typename Run>
void run_parallel(const std::vector<std::size_t>& todo, std::size_t jobs, const ProgressFn& progress,
                  const std::atomic<bool>* cancel, MakeWorker&& make_worker, Run&& run) {
  if (todo.empty()) return;
  if (jobs == 0) jobs = std::max<std::size_t>(1, std::thread::hardware_concurrency());
  const std::size_t n_threads = std::min(jobs, todo.size());

  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};  // a worker threw: the others stop too
  std::mutex progress_mutex;
  std::size_t done = 0;        // guarded by progress_mutex
  std::exception_ptr failure;  // the first exception, guarded by progress_mutex

  auto work = [&]() {
    try {
      auto worker = make_worker();
      for (;;) {
        if (failed.load(std::memory_order_relaxed)) return;
        if (cancel && cancel->load(std::memory_order_relaxed)) return;
        const std::size_t slot = next.fetch_add(1, std::memory_order_relaxed);
        if (slot >= todo.size()) return;
        run(worker, todo[slot]);
        const std::lock_guard<std::mutex> lock(progress_mutex);
        ++done;
        if (progress) progress(done, todo.size());
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      if (!failure) failure = std::current_exception();
      failed = true;
    }
  };

  // The calling thread is one of the workers: with one job no thread is started at all.
  std::vector<std::thread> threads;
  threads.reserve(n_threads - 1);
  try {
    for (std::size_t t = 1; t < n_threads; ++t) threads.emplace_back(work);
  } catch (...) {
    failed = true;  // could not start a thread: stop those that did, then report it
    for (std::thread& th : threads) th.join();
    throw;
  }
  work();
  for (std::thread& th : threads) th.join();
  if (failure) std::rethrow_exception(failure);
}

// Every run of `results` not yet `done`, in run order: results[i] = worker.run_one(i) on the pool above (the list of
// runs to do is built once: one allocation per call, none per run).
template <typename Result, typename MakeWorker>
void run_pending(std::vector<Result>& results, std::size_t jobs, const ProgressFn& progress,
                 const std::atomic<bool>* cancel, MakeWorker&& make_worker) {
  std::vector<std::size_t> todo;
  todo.reserve(static_cast<std::size_t>(
      std::count_if(results.begin(), results.end(), [](const Result& r) { return !r.done; })));
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (!results[i].done) todo.push_back(i);
  }
  run_parallel(todo, jobs, progress, cancel, make_worker,
               [&results](auto& worker, std::size_t index) { results[index] = worker.run_one(index); });
}

}  // namespace rockwatch::sim::study
