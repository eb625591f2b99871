// The wall z >= h, and displacement control: the constraint mean(z) = d beside it.
#ifndef GFMD_SRC_CONSTRAINT_HPP
#define GFMD_SRC_CONSTRAINT_HPP

#include "fft_grid.hpp"
#include "fields.hpp"

namespace gfmd {

// A point the wall holds: at the wall and pressed onto it (its projected force is zero; a CG's
// direction or a Newton step's block must not move it).  The surface CG's and the Newton method's
// one definition of their held set.
inline bool held_by_wall(double z, double h, double f) { return z <= h && f <= 0.0; }

// The nearest configuration (Euclidean) with mean(z) = d and z >= h: z_i = max(h_i, z_i + c) with
// the one shift c that gives the mean (found by Newton's method on the convex, piecewise linear
// mean(c), from the right: finitely many steps); points it puts on the wall stop (v = 0).
// A shift c > 0 within the mean's rounding is not applied: it would lift the whole contact set
// off the wall by ~1e-14 (constraint.cpp).
// Needs d >= mean(h) (checked by the caller).
void project_mean(const FftGrid &grid, Fields &fields, double d);

}  // namespace gfmd

#endif
