// What a timing-critical thread asks of Linux: real-time scheduling (SCHED_FIFO) for the calling thread, the
// process's memory locked (mlockall), the thread pinned to one CPU, a 1 ns timer slack. One implementation for the
// paced loop of `rockwatch replay` / `rockwatch demo` and for rockwatch-monitor's receive and processing thread, so
// that both ask the same way and report a refusal the same way.
//
// Each request is tried on its own and may be refused (SCHED_FIFO needs root, CAP_SYS_NICE or an RLIMIT_RTPRIO
// allowance; mlockall needs CAP_IPC_LOCK or a large enough RLIMIT_MEMLOCK; a CPU must exist and be in the process's
// allowed set): the outcome says which were granted and why the others were not; nothing throws. The destructor
// undoes what was granted (a demo goes on in the same process after the replay).
#pragma once

#include <string>

namespace rockwatch::process {

enum class MemoryLock {
  none,
  current,             // mlockall(MCL_CURRENT): the pages mapped now stay in memory (no page fault mid-stream)
  current_and_future,  // mlockall(MCL_CURRENT | MCL_FUTURE): also every page mapped later (heap, stacks)
};

struct RealtimeRequest {
  int fifo_priority = 0;  // 1..99: SCHED_FIFO at this priority for the calling thread; 0: scheduling left alone
  // With fifo_priority: only when the thread runs under SCHED_OTHER now (a thread already made real-time from
  // outside, e.g. by `chrt -f 60`, keeps its policy and priority).
  bool only_if_ordinary = false;
  MemoryLock memory_lock = MemoryLock::none;
  int cpu = -1;                 // >= 0: pin the calling thread to this CPU (pthread_setaffinity_np)
  bool minimal_timer_slack = false;  // PR_SET_TIMERSLACK 1 ns for this thread (no privilege needed; never undone)
};

struct RealtimeOutcome {
  bool realtime = false;       // the thread runs under SCHED_FIFO at the requested priority (set here)
  bool memory_locked = false;  // mlockall succeeded
  bool pinned = false;         // the thread runs on the requested CPU only
  // Why a request was not granted ("" when granted or not asked for): the system's reason and what would allow it.
  std::string realtime_problem, memory_problem, cpu_problem;
  bool all_granted() const { return realtime_problem.empty() && memory_problem.empty() && cpu_problem.empty(); }
};

// The CPUs a thread may be pinned to: 0 .. configured_cpus() − 1 (sysconf(_SC_NPROCESSORS_CONF)).
int configured_cpus();
// The range of SCHED_FIFO priorities (sched_get_priority_min / max: 1 and 99 on Linux).
int min_fifo_priority();
int max_fifo_priority();

// Applies a request to the calling thread (and, for memory, the process) for the object's lifetime.
class RealtimeConditions {
 public:
  explicit RealtimeConditions(const RealtimeRequest& request);
  ~RealtimeConditions();
  RealtimeConditions(const RealtimeConditions&) = delete;
  RealtimeConditions& operator=(const RealtimeConditions&) = delete;
  const RealtimeOutcome& outcome() const { return outcome_; }

 private:
  RealtimeOutcome outcome_;
  int old_policy_ = 0;
  int old_priority_ = 0;
  bool restore_policy_ = false;
  bool restore_affinity_ = false;
  unsigned char old_affinity_[128] = {};  // a cpu_set_t (1024 CPUs), kept opaque here
};

}  // namespace rockwatch::process
