// Observables of a configuration, and Persson's theory for the same substrate and body.
#ifndef GFMD_SRC_OBSERVABLES_HPP
#define GFMD_SRC_OBSERVABLES_HPP

#include "fft_grid.hpp"
#include "fields.hpp"
#include "forces.hpp"
#include "green.hpp"
#include "params.hpp"

namespace gfmd {

// A/A0 from the contact count of the last force evaluation.
double contact_area(const FftGrid &grid, const ForceState &forces);
double mean_gap(const FftGrid &grid, const Fields &fields);
void gap(const Fields &fields, double *out);
// Substrate on body: contact pressure max(0, -F) where the gap is zero, minus the adhesive pull.
void pressure(const Params &p, const Fields &fields, double *out);

// Persson's theory (non-adhesive): the variance of the contact pressure the body would carry in
// full contact, sum over q != 0 of (|h(q)| / G(q))^2; throws GFMD_ERR_RANGE if it overflows.
// h: the substrate's heights (nullptr: fields.h).
double persson_variance(const FftGrid &grid, const Body &body, const Fields &fields, const double *h = nullptr);
// The substrate's shortest wave: the |q| below which all but 1e-4 of its slope variance (the
// full plane's sum of q^2 |h(q)|^2) lies, to 1e-4 of the grid's corner; the corner itself for a
// flat substrate.  One transform of h in the solvers' scratch, as persson_variance.
double substrate_shortest_wave(const FftGrid &grid, const Fields &fields, const double *h = nullptr);
// A/A0 = erf(sigma0 / sqrt(2 variance)) (Persson, J. Chem. Phys. 115, 3840 (2001)); full contact
// under any load on a flat substrate.  sigma0 finite and >= 0.
double persson_contact_area(double variance, double sigma0);
// The load at which persson_contact_area(variance, sigma0) = area, for variance > 0 and area in
// [0, 1): bisection on erf (erfc above area 1/2) until the bracket cannot shrink.
double persson_load(double variance, double area);

}  // namespace gfmd

#endif
