/* Preloaded into the MPI tests of the sanitizer build: dlclose does nothing, so Open MPI's
 * components (mca_*.so) stay mapped until exit and LeakSanitizer can name their frames in the
 * report it makes at exit (Open MPI unloads them in MPI_Finalize, before that report; their
 * frames were "<unknown module>" and no suppression could match them).  Nothing else changes:
 * a component that is never reopened is never used again. */
int dlclose(void *handle);
int dlclose(void *handle) {
  (void)handle;
  return 0;
}
