#pragma once
// Whether this process was started as one of several MPI ranks (mpirun -n N, mpiexec),
// read from the variables the launchers set: Open MPI's OMPI_COMM_WORLD_SIZE and _RANK,
// MPICH's and Intel MPI's PMI_SIZE and PMI_RANK. main() starts an MPI session
// (core/Ranks.hpp) only then, so a serial run never initialises MPI.
namespace gradmpm {

struct MpiLaunch {
  int size = 1;  ///< ranks started together (1 without a launcher)
  int rank = 0;  ///< this process's rank
};

/// The launch this process is part of, from the environment.
MpiLaunch mpi_launch_from_environment();

}  // namespace gradmpm
