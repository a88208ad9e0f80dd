// `rockwatch-mpi study --mpi [study options]`: `rockwatch study --mpi` with MPI linked. `rockwatch` execs it when --mpi
// is given (study/study_mpi.hpp), so only a study over MPI pays for loading libmpi; run directly, it does the same.
#include <cstring>
#include <iostream>

#include "common/process/commands.hpp"
#include "study/scale/study_mpi.hpp"

int main(int argc, char** argv) {
  using namespace rockwatch::cli;
  set_in_process_mpi_study(run_mpi_study_in_process);
  if (argc < 2 || std::strcmp(argv[1], "study") != 0) {
    std::cerr << "rockwatch-mpi: runs `study --mpi` only (usage: mpirun -np N rockwatch study --mpi [options])\n";
    return kExitUsageError;
  }
  return study_main(argc - 1, argv + 1);
}
