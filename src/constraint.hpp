// Displacement control: the constraint mean(z) = d beside z >= h.
#ifndef GFMD_SRC_CONSTRAINT_HPP
#define GFMD_SRC_CONSTRAINT_HPP

#include "fft_grid.hpp"
#include "fields.hpp"

namespace gfmd {

// The nearest configuration (Euclidean) with mean(z) = d and z >= h: z_i = max(h_i, z_i + c) with
// the one shift c that gives the mean (found by Newton's method on the convex, piecewise linear
// mean(c), from the right: finitely many steps); points it puts on the wall stop (v = 0).
// A shift c > 0 within the mean's rounding is not applied: it would lift the whole contact set
// off the wall by ~1e-14 (constraint.cpp).
// Needs d >= mean(h) (checked by the caller).
void project_mean(const FftGrid &grid, Fields &fields, double d);

}  // namespace gfmd

#endif
