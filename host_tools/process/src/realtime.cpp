#include "rockwatch/process/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace rockwatch::process {

namespace {

static_assert(sizeof(cpu_set_t) <= 128, "RealtimeConditions::old_affinity_ holds a cpu_set_t");

std::string errno_text(int code) { return std::strerror(code); }

}  // namespace

int configured_cpus() {
  const long n = sysconf(_SC_NPROCESSORS_CONF);
  if (n < 1) return 1;
  return n > CPU_SETSIZE ? CPU_SETSIZE : static_cast<int>(n);
}

int min_fifo_priority() { return sched_get_priority_min(SCHED_FIFO); }
int max_fifo_priority() { return sched_get_priority_max(SCHED_FIFO); }

RealtimeConditions::RealtimeConditions(const RealtimeRequest& request) {
  if (request.minimal_timer_slack) prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);

  if (request.fifo_priority > 0) {
    sched_param old{};
    int policy = SCHED_OTHER;
    const int got = pthread_getschedparam(pthread_self(), &policy, &old);
    if (got != 0) {
      outcome_.realtime_problem = "pthread_getschedparam: " + errno_text(got);
    } else if (request.only_if_ordinary && policy != SCHED_OTHER) {
      // Left as it was made from outside; nothing to report or undo.
    } else {
      sched_param p{};
      p.sched_priority = request.fifo_priority;
      const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
      if (rc == 0) {
        outcome_.realtime = true;
        restore_policy_ = true;
        old_policy_ = policy;
        old_priority_ = old.sched_priority;
      } else {
        outcome_.realtime_problem =
            "SCHED_FIFO priority " + std::to_string(request.fifo_priority) + ": " + errno_text(rc) +
            (rc == EPERM ? " (needs root, CAP_SYS_NICE or an RLIMIT_RTPRIO allowance, e.g. LimitRTPRIO= in a "
                           "systemd unit)"
                         : std::string());
      }
    }
  }

  if (request.cpu >= 0) {
    cpu_set_t old{};
    CPU_ZERO(&old);
    const int got = pthread_getaffinity_np(pthread_self(), sizeof old, &old);
    cpu_set_t want{};
    CPU_ZERO(&want);
    if (request.cpu < CPU_SETSIZE) CPU_SET(request.cpu, &want);
    const int rc = request.cpu < CPU_SETSIZE ? pthread_setaffinity_np(pthread_self(), sizeof want, &want) : EINVAL;
    if (rc == 0) {
      outcome_.pinned = true;
      if (got == 0) {
        std::memcpy(old_affinity_, &old, sizeof old);
        restore_affinity_ = true;
      }
    } else {
      outcome_.cpu_problem = "CPU " + std::to_string(request.cpu) + ": " + errno_text(rc) +
                             (rc == EINVAL ? " (not a CPU this process may run on: see `taskset -p`, `nproc`)"
                                           : std::string());
    }
  }

  if (request.memory_lock != MemoryLock::none) {
    const int flags = request.memory_lock == MemoryLock::current_and_future ? MCL_CURRENT | MCL_FUTURE : MCL_CURRENT;
    if (mlockall(flags) == 0) {
      outcome_.memory_locked = true;
    } else {
      const int code = errno;
      outcome_.memory_problem =
          std::string("mlockall: ") + errno_text(code) +
          (code == EPERM || code == ENOMEM
               ? " (needs root, CAP_IPC_LOCK or an RLIMIT_MEMLOCK above the process's size, e.g. LimitMEMLOCK=infinity)"
               : std::string());
    }
  }
}

RealtimeConditions::~RealtimeConditions() {
  if (outcome_.memory_locked) munlockall();
  if (restore_affinity_) {
    cpu_set_t old{};
    std::memcpy(&old, old_affinity_, sizeof old);
    pthread_setaffinity_np(pthread_self(), sizeof old, &old);
  }
  if (restore_policy_) {
    sched_param p{};
    p.sched_priority = old_priority_;
    pthread_setschedparam(pthread_self(), old_policy_, &p);
  }
}

}  // namespace rockwatch::process
