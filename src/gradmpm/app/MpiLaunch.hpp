#pragma once
// Whether this process was started as one of several MPI ranks (mpirun -n N, mpiexec),
// read from the variables the launchers set: Open MPI's OMPI_COMM_WORLD_SIZE and _RANK,
// MPICH's and Intel MPI's PMI_SIZE and PMI_RANK. gradmpm does not run distributed yet
// (issue 14): N ranks would each run the whole case and write the same output folder, so
// `gradmpm run` refuses to start instead. Nothing here initialises MPI.
namespace gradmpm {

struct MpiLaunch {
  int size = 1;  ///< ranks started together (1 without a launcher)
  int rank = 0;  ///< this process's rank
};

/// The launch this process is part of, from the environment.
MpiLaunch mpi_launch_from_environment();

}  // namespace gradmpm
