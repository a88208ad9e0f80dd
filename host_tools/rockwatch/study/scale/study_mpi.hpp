// `mpirun -np N rockwatch study --mpi [study options]`: the plan over the ranks of an MPI job (OpenMPI). Every rank
// reads the records and builds the plan itself; rank 0 checks that all hold the same plan (its digest), prepares
// --out (and --resume), hands out the runs still to do a chunk at a time to whichever rank asks (dynamic: shorter
// chunks towards the end), computes chunks itself on a thread of its own, gathers every result, shows the progress
// and writes the files of the single-process study (study_scaled.hpp), byte for byte. SIGINT or SIGTERM (mpirun
// forwards them to every rank) stops the hand-out: the chunks in flight finish, their results reach rank 0, which
// writes runs.csv and study.json for --resume.
#pragma once

#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

// False when rockwatch was built without MPI (no libopenmpi-dev at configure time, or -DROCKWATCH_MPI=OFF).
bool built_with_mpi();

// `rockwatch` itself does not link MPI (loading libmpi, hwloc and PMIx cost every command several ms at start-up):
// --mpi replaces the process (exec, same pid and environment, before MPI_Init: what mpirun started) with
// `rockwatch-mpi` from the same directory ($ROCKWATCH_MPI_EXECUTABLE overrides), which runs the same study command
// with MPI (study_mpi_launch.cpp). Inside rockwatch-mpi the study runs in process (set_in_process_mpi_study).
// Without MPI: a usage error (exit 2) saying so.
int run_mpi_study(const StudyRequest& request);

// rockwatch-mpi's study over the ranks (study_mpi.cpp; only in rockwatch-mpi).
int run_mpi_study_in_process(const StudyRequest& request);
using MpiStudyFn = int (*)(const StudyRequest&);
void set_in_process_mpi_study(MpiStudyFn run);

}  // namespace rockwatch::cli
