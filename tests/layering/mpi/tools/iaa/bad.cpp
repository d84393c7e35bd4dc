// Fixture: MPI outside libiaa/dist/.
#include <mpi.h>
