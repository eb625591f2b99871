/*
 * gfmd status codes: the single list from which the C enum, gfmd_status_string()
 * and the Fortran constants are generated.  New codes are only ever appended.
 */
#ifndef GFMD_STATUS_H
#define GFMD_STATUS_H

/* X(name, value, description) */
#define GFMD_STATUS_LIST(X)                                                         \
    X(GFMD_OK,                 0, "success")                                        \
    X(GFMD_ERR_NULL,           1, "a required pointer argument is NULL")            \
    X(GFMD_ERR_INVALID_ARG,    2, "an argument is out of range, NaN or infinite")   \
    X(GFMD_ERR_BAD_ENUM,       3, "unknown enumeration value")                      \
    X(GFMD_ERR_STATE,          4, "the call is not possible in the current state")  \
    X(GFMD_ERR_NOMEM,          5, "out of memory")                                  \
    X(GFMD_ERR_NOT_CONVERGED,  6, "relaxation did not converge within the step limit") \
    X(GFMD_ERR_DIVERGED,       7, "the dynamics diverged; the state was restored")  \
    X(GFMD_ERR_RANGE,          8, "the result is not representable as a double")    \
    X(GFMD_ERR_TRUNCATED,      9, "the output buffer was too small; output truncated") \
    X(GFMD_ERR_INTERNAL,      10, "internal error")                                \
    X(GFMD_ERR_IO,            11, "a file could not be read or written")           \
    X(GFMD_ERR_FORMAT,        12, "the file is not a valid gfmd checkpoint (truncated or corrupted)") \
    X(GFMD_ERR_VERSION,       13, "the checkpoint's format version is not supported")

#endif
