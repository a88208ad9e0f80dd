#include "study/study_mpi.hpp"

#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::cli {

bool built_with_mpi() { return false; }

int run_mpi_study(const StudyRequest&) {
  throw UsageError("--mpi: this rockwatch was built without MPI (install libopenmpi-dev and configure again, or run "
                   "the study in shards: --shard K/N)");
}

}  // namespace rockwatch::cli
