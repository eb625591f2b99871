/* The canary of the MPI leak check: it leaks on purpose, through the MPI calls libgfmd_mpi
 * makes (a duplicated communicator, a committed datatype, an opened file's info) and a plain
 * malloc, and its ctest passes only if LeakSanitizer reports each of them despite
 * lsan_openmpi.supp.  A suppression broad enough to hide them (leak:libmpi.so) fails it. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

static void *kept; /* cleared before exit: the malloc below is then unreachable */

static void leak_through_mpi(void) {
  MPI_Comm dup;
  MPI_Comm_dup(MPI_COMM_WORLD, &dup); /* never freed */
  MPI_Datatype row;
  MPI_Type_contiguous(7, MPI_DOUBLE, &row);
  MPI_Type_commit(&row); /* never freed */
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  leak_through_mpi();
  kept = malloc(4242);
  if (kept) ((char *)kept)[0] = 1;
  kept = NULL;
  MPI_Finalize();
  printf("canary: leaked on purpose\n");
  return 0;
}
