#include "study/scale/study_mpi.hpp"

#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

#ifdef ROCKWATCH_HAVE_MPI

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/process/commands.hpp"
#include "common/process/progress_line.hpp"
#include "common/process/signal_interrupt.hpp"
#include "study/plan/study_plan.hpp"
#include "study/run/study_progress.hpp"
#include "study/scale/study_scaled.hpp"

#endif

namespace rockwatch::cli {

#ifdef ROCKWATCH_HAVE_MPI

namespace {

namespace study = sim::study;

constexpr int kTagRequest = 1;  // worker -> rank 0: the results of its last chunk, and a request for the next
constexpr int kTagWork = 2;     // rank 0 -> worker: the next chunk's global run indices (none: stop)
// The longest chunk: at the study's ~5000 analyses/s per core, 128 runs are ~25 ms, so a rank asks rank 0 ~40 times
// a second and a stop (SIGTERM) waits at most that long for the chunks in flight.
constexpr std::size_t kMaxMpiChunk = 128;
constexpr auto kPollInterval = std::chrono::microseconds(200);

// MPI_THREAD_FUNNELED: only the main thread of a rank calls MPI (rank 0 computes on a thread of its own).
class MpiSession {
 public:
  MpiSession() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiSession() { MPI_Finalize(); }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

// Results travel as bytes: every field as stored (doubles bit for bit), so rank 0 holds exactly what the worker
// computed and the files are those of the single-process study.
class Writer {
 public:
  template <typename T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const unsigned char*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put_optional(const std::optional<double>& value) {
    put<std::uint8_t>(value ? 1 : 0);
    if (value) put(*value);
  }
  std::vector<unsigned char> bytes;
};

class Reader {
 public:
  explicit Reader(const std::vector<unsigned char>& bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    if (at_ + sizeof(T) > bytes_.size()) throw std::runtime_error("MPI message shorter than its contents");
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::optional<double> get_optional() {
    if (get<std::uint8_t>() == 0) return std::nullopt;
    return get<double>();
  }
  std::string get_string(std::size_t size) {
    if (at_ + size > bytes_.size()) throw std::runtime_error("MPI message shorter than its contents");
    std::string text(reinterpret_cast<const char*>(bytes_.data() + at_), size);
    at_ += size;
    return text;
  }

 private:
  const std::vector<unsigned char>& bytes_;
  std::size_t at_ = 0;
};

void put_result(Writer& w, std::uint64_t global, const study::RunResult& r) {
  w.put(global);
  w.put<std::uint8_t>(r.collapsed ? 1 : 0);
  w.put_optional(r.t_collapse_s);
  w.put_optional(r.t_exceed_s);
  w.put(r.max_abs_x_m);
  w.put<std::int32_t>(r.n_impacts);
  w.put_optional(r.t_first_imminent_s);
  w.put_optional(r.t_first_imminent_published_s);
  w.put<std::uint32_t>(r.imminent_late_samples);
  w.put<std::uint32_t>(r.max_late_samples);
  w.put<std::uint32_t>(r.shed_samples);
  w.put<std::uint32_t>(r.overrun_calls);
  w.put<std::int32_t>(r.max_call_units);
  w.put<std::uint8_t>(r.saturated ? 1 : 0);
  w.put<std::uint8_t>(r.reference ? 1 : 0);
  if (r.reference) {
    w.put<std::uint8_t>(r.reference->collapsed ? 1 : 0);
    w.put_optional(r.reference->t_collapse_s);
    w.put(r.reference->max_abs_x_m);
    w.put_optional(r.reference->t_first_imminent_s);
  }
  w.put<std::uint8_t>(r.collapsed_reference ? (*r.collapsed_reference ? 2 : 1) : 0);
  w.put_optional(r.max_abs_x_reference_m);
  w.put<std::uint64_t>(r.error.size());
  w.bytes.insert(w.bytes.end(), r.error.begin(), r.error.end());
}

study::RunResult get_result(Reader& in, std::uint64_t& global) {
  global = in.get<std::uint64_t>();
  study::RunResult r;
  r.done = true;
  r.collapsed = in.get<std::uint8_t>() != 0;
  r.t_collapse_s = in.get_optional();
  r.t_exceed_s = in.get_optional();
  r.max_abs_x_m = in.get<double>();
  r.n_impacts = in.get<std::int32_t>();
  r.t_first_imminent_s = in.get_optional();
  r.t_first_imminent_published_s = in.get_optional();
  r.imminent_late_samples = in.get<std::uint32_t>();
  r.max_late_samples = in.get<std::uint32_t>();
  r.shed_samples = in.get<std::uint32_t>();
  r.overrun_calls = in.get<std::uint32_t>();
  r.max_call_units = in.get<std::int32_t>();
  r.saturated = in.get<std::uint8_t>() != 0;
  if (in.get<std::uint8_t>() != 0) {
    study::DoubleReference d;
    d.collapsed = in.get<std::uint8_t>() != 0;
    d.t_collapse_s = in.get_optional();
    d.max_abs_x_m = in.get<double>();
    d.t_first_imminent_s = in.get_optional();
    r.reference = d;
  }
  const auto reference_verdict = in.get<std::uint8_t>();  // 0 none, 1 survives, 2 collapses
  if (reference_verdict != 0) r.collapsed_reference = reference_verdict == 2;
  r.max_abs_x_reference_m = in.get_optional();
  r.error = in.get_string(static_cast<std::size_t>(in.get<std::uint64_t>()));
  return r;
}

std::vector<unsigned char> receive_bytes(int source, int tag, MPI_Status& status) {
  MPI_Probe(source, tag, MPI_COMM_WORLD, &status);
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

void send_bytes(const std::vector<unsigned char>& bytes, int destination, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD);
}

// Rank 0's hand-out: the runs still to do in order, a chunk of one wall at a time, chunks shrinking towards the end
// (guided self-scheduling: what is left over 4 x the ranks, at most kMaxMpiChunk), so the ranks finish together.
class WorkQueue {
 public:
  WorkQueue(const std::vector<std::size_t>& todo, std::size_t runs_per_wall, std::size_t ranks)
      : todo_(todo), runs_per_wall_(runs_per_wall), ranks_(ranks) {}

  std::vector<std::size_t> take() {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::size_t> chunk;
    if (stopped_ || next_ >= todo_.size()) return chunk;
    const std::size_t left = todo_.size() - next_;
    const std::size_t size = std::clamp<std::size_t>(left / (4 * ranks_), 1, kMaxMpiChunk);
    const std::size_t wall = todo_[next_] / runs_per_wall_;
    while (next_ < todo_.size() && chunk.size() < size && todo_[next_] / runs_per_wall_ == wall) {
      chunk.push_back(todo_[next_++]);
    }
    return chunk;
  }
  void stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
  }

 private:
  const std::vector<std::size_t>& todo_;
  std::size_t runs_per_wall_, ranks_;
  std::mutex mutex_;
  std::size_t next_ = 0;
  bool stopped_ = false;
};

int run_worker(ScaledStudy& s, const MpiSession& mpi) {
  const SignalInterrupt interrupt;
  Writer results;
  std::uint64_t count = 0;
  std::vector<study::RunResult> out;
  bool stopping = false;
  for (;;) {
    // The request carries the last chunk's results: [stopping][count][(global, result)...].
    Writer message;
    message.put<std::uint8_t>(stopping ? 1 : 0);
    message.put(count);
    message.bytes.insert(message.bytes.end(), results.bytes.begin(), results.bytes.end());
    send_bytes(message.bytes, 0, kTagRequest);
    results.bytes.clear();
    count = 0;
    MPI_Status status;
    const std::vector<unsigned char> work = receive_bytes(0, kTagWork, status);
    const std::size_t n = work.size() / sizeof(std::uint64_t);
    if (n == 0) break;
    std::vector<std::size_t> indices(n);
    for (std::size_t k = 0; k < n; ++k) {
      std::uint64_t g = 0;
      std::memcpy(&g, work.data() + k * sizeof g, sizeof g);
      indices[k] = static_cast<std::size_t>(g);
    }
    const std::size_t wall = indices.front() / s.runs_per_wall;
    set_wall(s, wall);
    run_wall_chunk(s.plan, s.runs_per_wall, wall, indices, out, s.request.jobs, {}, interrupt.flag());
    for (std::size_t k = 0; k < n; ++k) {
      if (!out[k].done) continue;
      put_result(results, indices[k], out[k]);
      ++count;
    }
    stopping = interrupt.interrupted();
  }
  (void)mpi;
  return interrupt.interrupted() ? kExitInterrupted : kExitOk;
}

int run_rank0(ScaledStudy& s, const MpiSession& mpi, std::size_t resumed) {
  const std::vector<std::size_t> todo = runs_to_do(s);
  const std::size_t in_shard = runs_in_shard(s);
  if (s.request.resume) {
    std::cerr << "study: resuming: " << resumed << " of " << in_shard << " analyses done, running the other "
              << todo.size() << '\n';
  }
  std::cerr << "study: " << in_shard << " analyses";
  if (s.portfolio) std::cerr << " (" << s.walls.size() << " walls x " << s.runs_per_wall << ")";
  std::cerr << " on " << mpi.size() << " MPI rank" << (mpi.size() == 1 ? "" : "s") << '\n';
  write_scaled_state_running(s);

  const SignalInterrupt interrupt;
  WorkQueue queue(todo, s.runs_per_wall, static_cast<std::size_t>(mpi.size()));
  std::mutex results_mutex;  // rank 0's thread and the receiving main thread store into s.results
  std::atomic<std::size_t> done{0};
  std::atomic<bool> computing{true};
  std::exception_ptr failure;

  // Rank 0's own share, on a thread: its main thread answers the other ranks meanwhile.
  study::StudyPlan own_plan = s.plan;  // the thread's wall changes independently of the main thread's writing
  std::thread compute([&] {
    try {
      std::vector<study::RunResult> out;
      for (std::vector<std::size_t> chunk = queue.take(); !chunk.empty(); chunk = queue.take()) {
        const std::size_t wall = chunk.front() / s.runs_per_wall;
        own_plan.wall = s.walls[wall].wall;
        run_wall_chunk(own_plan, s.runs_per_wall, wall, chunk, out, s.request.jobs, {}, interrupt.flag());
        const std::lock_guard<std::mutex> lock(results_mutex);
        for (std::size_t k = 0; k < chunk.size(); ++k) {
          if (!out[k].done) continue;
          s.results[wall][chunk[k] - wall * s.runs_per_wall] = std::move(out[k]);
          ++done;
        }
        if (interrupt.interrupted()) break;
      }
    } catch (...) {
      failure = std::current_exception();
      queue.stop();
    }
    computing = false;
  });

  StudyProgress progress(std::cerr, stderr_is_terminal(), resumed, in_shard, interrupt.flag());
  const double interval_s = checkpoint_interval_s();
  auto last_checkpoint = std::chrono::steady_clock::now();
  int active = mpi.size() - 1;
  std::size_t reported = 0;
  while (active > 0 || computing) {
    if (interrupt.interrupted()) queue.stop();
    int pending = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &pending, &status);
    if (pending != 0) {
      const std::vector<unsigned char> bytes = receive_bytes(status.MPI_SOURCE, kTagRequest, status);
      Reader in(bytes);
      if (in.get<std::uint8_t>() != 0) queue.stop();  // the worker was signalled
      {
        const std::lock_guard<std::mutex> lock(results_mutex);
        const auto count = in.get<std::uint64_t>();
        for (std::uint64_t k = 0; k < count; ++k) {
          std::uint64_t global = 0;
          study::RunResult r = get_result(in, global);
          const std::size_t wall = static_cast<std::size_t>(global) / s.runs_per_wall;
          s.results.at(wall).at(static_cast<std::size_t>(global) - wall * s.runs_per_wall) = std::move(r);
        }
        done += static_cast<std::size_t>(count);
      }
      const std::vector<std::size_t> chunk = queue.take();
      std::vector<unsigned char> work(chunk.size() * sizeof(std::uint64_t));
      for (std::size_t k = 0; k < chunk.size(); ++k) {
        const auto g = static_cast<std::uint64_t>(chunk[k]);
        std::memcpy(work.data() + k * sizeof g, &g, sizeof g);
      }
      send_bytes(work, status.MPI_SOURCE, kTagWork);
      if (chunk.empty()) --active;
    } else {
      std::this_thread::sleep_for(kPollInterval);
    }
    if (done != reported) {
      reported = done;
      progress.report(reported, todo.size());
    }
    const auto now = std::chrono::steady_clock::now();
    if (!interrupt.interrupted() && std::chrono::duration<double>(now - last_checkpoint).count() >= interval_s &&
        (active > 0 || computing)) {
      const std::lock_guard<std::mutex> lock(results_mutex);
      write_scaled_checkpoint(s);
      last_checkpoint = now;
    }
  }
  compute.join();
  progress.finish();
  if (failure) std::rethrow_exception(failure);
  return finish_scaled_study(s, interrupt.signal_number());
}

// Every rank builds the plan; rank 0 also prepares --out. Then all learn whether every rank succeeded and holds the
// same plan, so a failure anywhere ends every rank (exit 2) instead of leaving the others waiting.
struct Agreement {
  bool ok = false;
  std::string message;  // what to print on this rank
};

Agreement agree(const MpiSession& mpi, bool ok, const std::string& digest, const std::string& own_error) {
  constexpr std::size_t kDigestChars = 40;
  std::vector<char> mine(kDigestChars + 1, '\0');
  mine[0] = ok ? 1 : 0;
  std::memcpy(mine.data() + 1, digest.data(), std::min(digest.size(), kDigestChars));
  std::vector<char> all(mine.size() * static_cast<std::size_t>(mpi.size()));
  MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_CHAR, all.data(), static_cast<int>(mine.size()),
                MPI_CHAR, MPI_COMM_WORLD);
  const auto entry = [&](int rank) { return all.data() + static_cast<std::size_t>(rank) * mine.size(); };
  Agreement a;
  const bool rank0_ok = entry(0)[0] != 0;
  if (!ok) {
    // Rank 0's message speaks for all; another rank's only when rank 0 had none.
    if (mpi.rank() == 0 || rank0_ok) {
      a.message = (mpi.rank() == 0 ? std::string() : "rank " + std::to_string(mpi.rank()) + ": ") + own_error;
    }
    return a;
  }
  for (int r = 0; r < mpi.size(); ++r) {
    if (entry(r)[0] == 0) return a;  // that rank says why
    const std::string theirs(entry(r) + 1, strnlen(entry(r) + 1, kDigestChars));
    if (theirs != digest) {
      if (mpi.rank() == 0) {
        a.message = "rank " + std::to_string(r) + " built another plan (" + theirs + ") than rank 0 (" + digest +
                    "): every rank must read the same records and walls";
      }
      return a;
    }
  }
  a.ok = true;
  return a;
}

}  // namespace

int run_mpi_study_in_process(const StudyRequest& q) {
  const MpiSession mpi;
  std::optional<ScaledStudy> s;
  std::size_t resumed = 0;
  std::string error;
  int error_status = kExitUsageError;
  try {
    s.emplace(load_scaled_study(q, /*print_notes=*/mpi.rank() == 0));
    if (mpi.rank() == 0) resumed = prepare_scaled_directory(*s);
  } catch (const UsageError& e) {
    error = e.what();
  } catch (const std::exception& e) {
    error = e.what();
    error_status = kExitInternalError;
  }
  const Agreement agreed = agree(mpi, error.empty(), s ? plan_digest(s->plan_description) : std::string(), error);
  if (!agreed.ok) {
    if (!agreed.message.empty()) std::cerr << "rockwatch study: error: " << agreed.message << '\n';
    return error.empty() ? kExitUsageError : error_status;
  }
  try {
    return mpi.rank() == 0 ? run_rank0(*s, mpi, resumed) : run_worker(*s, mpi);
  } catch (const std::exception& e) {
    // The other ranks would wait for this one for ever.
    std::cerr << "rockwatch study: error: rank " << mpi.rank() << ": " << e.what() << '\n';
    MPI_Abort(MPI_COMM_WORLD, kExitInternalError);
    return kExitInternalError;
  }
}

#endif

}  // namespace rockwatch::cli
