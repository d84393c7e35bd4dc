// What the environment says about mpirun, shared by the MPI and the MPI-less builds of world.h.
#pragma once

#include <cstdlib>

namespace iaa::dist {

/// The variables that MPI launchers set in every process they start: OpenMPI's, and the PMI and
/// PMIx ones of MPICH, Slurm's srun and the others.
inline bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(v)) return true;
  }
  return false;
}

/// The rank the launcher gave this process (0 when none or unknown), for messages printed before
/// MPI is up.
inline int launcher_rank() {
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
    if (const char* s = std::getenv(v)) return std::atoi(s);
  }
  return 0;
}

}  // namespace iaa::dist
