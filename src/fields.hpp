// The grid-sized arrays of a simulation, each with one role, and the memory they take.
#ifndef GFMD_SRC_FIELDS_HPP
#define GFMD_SRC_FIELDS_HPP

#include <cstdint>

#include "buffer.hpp"
#include "fft_grid.hpp"

namespace gfmd {

// Peak bytes per grid point of a handle: the fields below, the undo snapshot, the stiffness, and
// FFTW's planning scratch at creation.  The grid buffers are resident only once written
// (buffer.hpp); gfmd_bench's B/pt column and test_api print the footprint.  The memory guard
// counts 82 B/pt: a margin above those, not a measurement.
constexpr double kPeakBytesPerPoint = 82.0;

// Throws GFMD_ERR_NOMEM, before anything is allocated, if nx x ny points at bytes_per_point (a
// handle's peak, or what a solver adds to it) do not fit in the memory available now
// (MemAvailable; physical memory where it is unknown).
void check_memory(int64_t nx, int64_t ny, double bytes_per_point = kPeakBytesPerPoint);

struct Fields {
    explicit Fields(const FftGrid &grid);
    RealBuffer h;          // rigid substrate heights
    RealBuffer z;          // elastic surface, z >= h
    RealBuffer v;          // velocity of z
    RealBuffer f;          // force per area on z (elastic + external + adhesive); solvers may reuse it
                           // within a step (evaluate_forces() rewrites it after every step)
    // FFT scratch, meaningful only inside one computation; between computations free, also for
    // a const observable (mutable: Persson's variance transforms h into it)
    mutable ComplexBuffer work;
    // Set by a solver whose last act was grid.forward(z, work) (the surface CG's checked step):
    // the force evaluation that follows the step takes the transform from work, and clears it.
    bool work_holds_z = false;

    // The body flat at the highest substrate point, at rest.
    void put_flat_at_rest(const FftGrid &grid);
    // z lifted onto the substrate where it would penetrate, at rest (after z was set from outside).
    void lift_at_rest(const FftGrid &grid);
};

// z and v at the start of a call, to restore them if the call fails half-way (the dynamics
// diverge, a new substrate overflows).  Kept for the handle's life: 16 B/pt, allocated at creation
// so that no step or setter allocates grid-sized memory (a NOMEM in the middle of a run) and the
// peak memory is known when the handle is made.
struct Snapshot {
    explicit Snapshot(const FftGrid &grid);
    void save(const Fields &from);
    void restore(Fields &to) const;
    RealBuffer z, v;
};

}  // namespace gfmd

#endif
