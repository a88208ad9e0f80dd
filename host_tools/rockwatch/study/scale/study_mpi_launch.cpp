// `rockwatch study --mpi` in the `rockwatch` executable, which does not link MPI: hands the process over to
// `rockwatch-mpi` (study_mpi.hpp says why).
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/scale/study_mpi.hpp"

namespace rockwatch::cli {

namespace {
MpiStudyFn g_in_process = nullptr;
}  // namespace

void set_in_process_mpi_study(MpiStudyFn run) { g_in_process = run; }

bool built_with_mpi() {
#ifdef ROCKWATCH_HAVE_MPI_EXECUTABLE
  return true;
#else
  return false;
#endif
}

int run_mpi_study(const StudyRequest& q) {
  if (g_in_process) return g_in_process(q);
  if (!built_with_mpi()) {
    throw UsageError("--mpi: this rockwatch was built without MPI (install libopenmpi-dev and configure again, or run "
                     "the study in shards: --shard K/N)");
  }
  std::string path;
  if (const char* env = std::getenv("ROCKWATCH_MPI_EXECUTABLE"); env != nullptr && *env != '\0') {
    path = env;
  } else {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) throw UsageError("--mpi: cannot find this executable to start rockwatch-mpi next to it: " + ec.message());
    path = (self.parent_path() / "rockwatch-mpi").string();
  }
  std::vector<std::string> args{path, "study"};
  args.insert(args.end(), q.arguments.begin(), q.arguments.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(path.c_str(), argv.data());
  throw UsageError("--mpi: cannot run " + path + " (the MPI build of the study, next to rockwatch): " +
                   std::strerror(errno));
}

}  // namespace rockwatch::cli
