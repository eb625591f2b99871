#include "solver.hpp"

#include <cmath>
#include <string>

#include "../error.hpp"
#include "cg.hpp"
#include "fire.hpp"
#include "mass_weighted_fire.hpp"
#include "approach_then_fire.hpp"
#include "newton.hpp"
#include "verlet.hpp"

namespace gfmd {

Dynamics dynamics_for(const Params &p, const Body &body) {
    Dynamics d;
    d.dt = (p.dt_user > 0.0) ? p.dt_user : kDtFactor / std::sqrt(body.k_max + p.adhesive_stiffness());
    d.eta = (p.eta_user > 0.0) ? p.eta_user : 2.0 * kZeta * std::sqrt(body.k_min);
    return d;
}

void Solver::set_grid_state(std::vector<RealBuffer> &&fields) {
    if (!fields.empty()) fail(GFMD_ERR_FORMAT, "grid-sized state for a solver that has none");
}

namespace {
// (the body's part of newton_refusal() the caller checked: the grid's is checked here too, so that
// no caller can make the cycle for a grid it cannot take)
std::unique_ptr<Solver> make_newton(const FftGrid &grid) {
    const std::string why = newton_grid_refusal(grid);
    if (!why.empty()) fail(GFMD_ERR_STATE, why);
    check_memory(grid.nx(), grid.ny(), ActiveSetNewton::bytes_per_point());
    return std::make_unique<ActiveSetNewton>(grid.nx());
}
}  // namespace

std::unique_ptr<Solver> make_solver(int32_t kind, const FftGrid &grid, const Dynamics &d) {
    std::unique_ptr<Solver> s;
    switch (kind) {  // one line per solver
        case GFMD_SOLVER_VERLET: s = std::make_unique<Verlet>(); break;
        case GFMD_SOLVER_FIRE: s = std::make_unique<Fire>(); break;
        case GFMD_SOLVER_MASS_WEIGHTED_FIRE: s = std::make_unique<MassWeightedFire>(grid); break;
        case GFMD_SOLVER_APPROACH_THEN_FIRE: s = std::make_unique<ApproachThenFire>(grid); break;
        case GFMD_SOLVER_CG: s = std::make_unique<ConjugateGradient>(grid); break;
        case GFMD_SOLVER_NEWTON: s = make_newton(grid); break;
        default: fail(GFMD_ERR_BAD_ENUM, "unknown solver " + std::to_string(kind));
    }
    s->restart(d);
    return s;
}

}  // namespace gfmd
