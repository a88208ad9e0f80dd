// `mpirun -np N rockwatch study --mpi [study options]`: the plan over the ranks of an MPI job (OpenMPI). Every rank
// reads the records and builds the plan itself; rank 0 checks that all hold the same plan (its digest), prepares
// --out (and --resume), hands out the runs still to do a chunk at a time to whichever rank asks (dynamic: shorter
// chunks towards the end), computes chunks itself on a thread of its own, gathers every result, shows the progress
// and writes the files of the single-process study (study_scaled.hpp), byte for byte. SIGINT or SIGTERM (mpirun
// forwards them to every rank) stops the hand-out: the chunks in flight finish, their results reach rank 0, which
// writes runs.csv and study.json for --resume.
#pragma once

#include "study/study_request.hpp"

namespace rockwatch::cli {

// False when rockwatch was built without MPI (no libopenmpi-dev at configure time, or -DROCKWATCH_MPI=OFF).
bool built_with_mpi();

// Without MPI: a usage error (exit 2) saying so.
int run_mpi_study(const StudyRequest& request);

}  // namespace rockwatch::cli
