// Polonsky & Keer's constrained conjugate gradients on the contact pressure (Wear 231, 206 (1999)),
// under pressure control: the dual of the primal CG in cg.hpp.  It iterates on the points in
// contact with the compliance G(q), which is why it needs few iterations on coatings and on a
// half-space of modest size.  Its pressure is grid-sized state (checkpoints keep it).
#ifndef GFMD_SRC_SOLVERS_PK_HPP
#define GFMD_SRC_SOLVERS_PK_HPP

#include "solver.hpp"

namespace gfmd {

class PolonskyKeer {
public:
    explicit PolonskyKeer(const FftGrid &grid);
    PolonskyKeer(const PolonskyKeer &o);
    PolonskyKeer &operator=(const PolonskyKeer &) = delete;
    void restart() {
        fresh_ = true;
        iterations_ = 0;
    }
    // Convergence is tested every kCheckEvery iterations since the restart (pk.cpp).
    bool at_check() const;
    // One iteration: the pressure moves, then z = h where p > 0 and max(h, u + c) elsewhere, with
    // u = G p and c the rigid-body approach that closes the gap on average over the contact set.  fields.v holds the
    // conjugate direction, fields.f is scratch.
    void advance(StepContext &c);
    // fresh, the squared gap norm of the last direction and of the current pressure, the
    // conjugacy flag, the approach c, the iterations since the restart; and the pressure field.
    // set_state() also takes the five numbers of a checkpoint without the count (then 0).
    std::vector<double> state() const;
    void set_state(const std::vector<double> &s);
    const RealBuffer &pressure() const { return p_; }
    // The displacement buffer lent as scratch (to the surface CG on bodies PK does not iterate
    // on): recomputed before PK uses it again.
    RealBuffer &scratch() {
        u_valid_ = false;
        return u_;
    }
    // Throws GFMD_ERR_FORMAT for a pressure that is not finite and >= 0.
    void set_pressure(RealBuffer &&p);

private:
    void start(StepContext &c);                           // p from the current configuration
    // p *= scale, u = G p, then approach_, g_now_; with surface, z of the pressure too (pk.cpp)
    void displacement(const StepContext &c, double scale, bool surface);
    RealBuffer p_, u_;   // pressure and its displacement G p (u_ is recomputed, never saved)
    bool fresh_ = true;  // the next advance starts from the configuration's contact pressures
    bool u_valid_ = false;
    bool conjugate_ = false;  // PK's delta: no point joined the contact set in the last iteration
    double g_old_ = 0.0, g_now_ = 0.0, approach_ = 0.0;
    double in_contact_ = 0.0;  // points with p > 0 (derived, with u_)
    int64_t iterations_ = 0;   // since the restart: the convergence test's schedule
};

}  // namespace gfmd

#endif
