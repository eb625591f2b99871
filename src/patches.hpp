// How a contact is made: its connected patches, and the distribution of its pressures.
#ifndef GFMD_SRC_PATCHES_HPP
#define GFMD_SRC_PATCHES_HPP

#include <cstdint>
#include <vector>

namespace gfmd {

// The patches of a set of grid points, one entry per patch, in label order.
struct Patches {
    int64_t count = 0;
    std::vector<double> points;  // points of the patch
    std::vector<double> edges_x;  // boundary edges between the patch and a point out of it along x
    std::vector<double> edges_y;  // ... along y
    std::vector<double> mean_x, mean_y;  // mean unwrapped grid coordinates (units of the spacing)
};

// Throws GFMD_ERR_INVALID_ARG unless connectivity is 4 or 8.
void check_connectivity(int32_t connectivity);

// Connected-component labelling of the points with in[i] != 0 on an nx x ny grid (x fastest):
// labels[i] = 0 outside the set, 1..count inside, numbered in the order of each patch's first
// point (index i = ix + nx iy ascending), so the labels are a function of the set alone.
// Neighbours: the 4 points sharing an edge, or those 8 and the 4 diagonal ones; with periodic the
// grid wraps around in both directions (a patch crossing the border is one patch).  Breadth-first
// from each patch's first point; a point's unwrapped coordinates are its predecessor's plus the
// step, so a patch crossing the border has a mean position next to it (a patch that wraps all the
// way around the cell has the mean of that one unwrapping).  An edge is counted where a point of
// the set meets one of its 4 edge neighbours outside it (or the grid's border, not periodic).
// Throws std::bad_alloc if the search queue does not fit (at most the largest patch's size).
Patches label_patches(int64_t nx, int64_t ny, const unsigned char *in, int32_t connectivity, bool periodic,
                      int64_t *labels);

// The values of one property (GFMD_PATCH_*) of every patch of `patches`, made by label_patches
// on a grid of nx x ny points on a cell lx x ly: point counts, areas, edge counts, perimeters
// (the edges' length times pi/4, the mean ratio of a randomly oriented curve's length to that of
// its staircase on a square grid), centroids in [0, lx) x [0, ly), loads (the sum of pressure[i]
// times the area per point over each patch, in index order).  Throws GFMD_ERR_BAD_ENUM for an
// unknown property.
std::vector<double> patch_values(const Patches &patches, int32_t property, int64_t nx, int64_t ny, double lx,
                                 double ly, const int64_t *labels, const double *pressure);

// The histogram of pressure[i] over the points with in[i] != 0 in nbins equal bins on [lo, hi]
// (values beyond the range counted in the end bins): fraction[b] = the bin's points / n, and
// mean[b] = the mean pressure of its points (0 for an empty bin), so that sum fraction = the
// set's share of the n points and sum fraction[b] mean[b] = the sum of its pressures / n.
// lo = hi = 0: the range of the set's pressures.  Throws GFMD_ERR_INVALID_ARG for nbins < 1 or a
// range that is not finite with lo < hi.
void pressure_histogram(int64_t n, const unsigned char *in, const double *pressure, int64_t nbins, double &lo,
                        double &hi, double *fraction, double *mean);

class Simulation;

// The whole grid's contact set (and pressure) of a handle, on every rank: a distributed handle's
// rows are gathered (1 B/pt, and 8 B/pt with the pressure, of the whole grid on each rank), after
// every rank agreed that they fit, so that no rank waits in the gather for one that failed: a
// grid beyond the gather's 2 GB is refused with GFMD_ERR_STATE, one beyond the memory with
// GFMD_ERR_NOMEM, on every rank.  Collective.
struct WholeContact {
    std::vector<unsigned char> in;
    std::vector<double> pressure;  // with_pressure only
};
WholeContact whole_contact(const Simulation &m, bool with_pressure);

// Persson's distribution of the contact pressure (J. Chem. Phys. 115, 3840 (2001), Eq. 17 with
// the absorbing boundary P(0) = 0 of the non-adhesive contact): a diffusion in p of variance V
// from the delta at sigma0, P(p) = [N(p - sigma0) - N(p + sigma0)] for p >= 0 (0 below), N the
// normal density of variance V; it integrates to erf(sigma0 / sqrt(2 V)), the theory's A/A0,
// and its first moment is sigma0.  V = 0 (a flat substrate) is the delta: density 0 away from
// sigma0, +inf at it.
double persson_pressure_density(double variance, double sigma0, double p);

}  // namespace gfmd

#endif
