// Perfect plasticity of the substrate's asperities at a hardness H (the model of ContactMechanics'
// plastic system and of docs/model.md): the contact pressure never exceeds H; where the body would
// press harder, the substrate yields and its height is lowered to the body's surface, for good.
// One load step is the minimum of the convex energy U_el - (work of the load) + H V_p, V_p the
// volume by which the body's surface z lies below the substrate hs as the step began (a yielding
// point feels the substrate's pressure H, whatever its depth); the substrate the body sees is
// h = min(hs, z).  A change of load commits the step: hs = h.
//
// In the relaxation this is a wall that gives way: a yielding point -- below hs, or at hs and
// pressed beyond H -- is free, pushed up by H, and stops at hs on its way up; every other point
// meets the wall at hs as without hardness.  While a solver steps, fields.h holds -infinity at the
// yielding points and the force there includes H (release); after the step the force evaluation
// restores h = min(hs, z) (settle) and classifies the points again (yield).  Without a yielding
// point every number is the elastic one, bit for bit.
#ifndef GFMD_SRC_PLASTICITY_HPP
#define GFMD_SRC_PLASTICITY_HPP

#include <cstdint>
#include <vector>

#include "buffer.hpp"
#include "fft_grid.hpp"
#include "fields.hpp"
#include "forces.hpp"
#include "params.hpp"

namespace gfmd {

struct Plasticity {
    // hs = the substrate h now (16 B/pt: this and the yield marks, checked by the caller)
    Plasticity(const FftGrid &grid, const RealBuffer &h);
    Plasticity(const Plasticity &o);
    RealBuffer substrate;                // hs: the substrate as the load step began
    std::vector<unsigned char> yielding;  // the yielding points of the last classification
    double committed_volume = 0.0;       // the volume flattened before this load step
    int64_t yielding_points = 0;         // over the whole grid
};

// h = min(hs, z): the substrate the body sees.
void settle(const FftGrid &grid, const Plasticity &pl, Fields &fields);
// After evaluate_forces (fields.f the force without hardness): marks the yielding points and, if
// there are any, the forces' sums of the yielding wall (and, under displacement control, the
// mean pressure that keeps the yielding points' mean force balanced too).
void yield(const FftGrid &grid, const Params &p, Plasticity &pl, Fields &fields, ForceState &fs);
// Before a step: the yielding points free (h = -inf) and pushed up by H.
void release(const FftGrid &grid, const Params &p, const Plasticity &pl, Fields &fields);
// The step committed: hs = h, the flattened volume carried over.
void commit(const FftGrid &grid, Plasticity &pl, const Fields &fields);
// The volume the substrate lost: the committed one and this step's sum of hs - h.
double plastic_volume(const FftGrid &grid, const Plasticity &pl, const Fields &fields);

}  // namespace gfmd

#endif
