// The multilevel start (Simulation::relax_multilevel): the body relaxed on grids coarsened by 2,
// each grid's surface interpolated to the next finer one through the modes they share.
#include <algorithm>
#include <complex>
#include <cstdlib>
#include <string>
#include <vector>

#include "error.hpp"
#include "simulation.hpp"
#include "solvers/newton.hpp"

namespace gfmd {

namespace {

// Copies the modes two grids share from one half-spectrum to the other, scaled, and zeroes the
// rest: the modes strictly below the smaller grid's Nyquist frequencies (its Nyquist lines have
// no partner on the larger grid and are dropped).  Restriction (fine -> coarse) filters,
// prolongation (coarse -> fine) interpolates by zero padding.
void copy_shared_modes(const FftGrid &from, const std::complex<double> *in, const FftGrid &to,
                       std::complex<double> *out, double scale) {
    const int64_t nxs = std::min(from.nx(), to.nx()), nys = std::min(from.ny(), to.ny());
    const int64_t fxh = from.nxh(), width = (nxs + 1) / 2;  // the kx with 2 kx < nxs
    // Each local row of `from` goes to its row of `to` (or nowhere), its shared modes scaled.
    std::vector<int64_t> dest(static_cast<std::size_t>(from.local_mode_rows()), -1);
    std::vector<std::complex<double>> rows(dest.size() * static_cast<std::size_t>(width));
    for (int64_t r = 0; r < from.local_mode_rows(); ++r) {
        const int64_t fy = from.first_mode_row() + r;
        const int64_t k = (2 * fy > from.ny()) ? fy - from.ny() : fy;  // signed wave number
        if (2 * std::abs(k) >= nys) continue;                          // beyond the smaller grid, or its Nyquist
        dest[static_cast<std::size_t>(r)] = (k < 0) ? to.ny() + k : k;
        for (int64_t kx = 0; kx < width; ++kx) rows[static_cast<std::size_t>(r * width + kx)] = scale * in[r * fxh + kx];
    }
    from.send_rows(to, dest.data(), rows.data(), width, out);
}

}  // namespace

std::unique_ptr<Simulation> Simulation::coarsened() {
    auto c = std::make_unique<Simulation>(grid_.nx() / 2, grid_.ny() / 2, grid_.lx(), grid_.ly(), grid_.threads(),
                                          GFMD_PLANNER_ESTIMATE, grid_.distribution());
    c->nested_ = true;  // its relax is part of this grid's start: no start of its own
    c->params_ = params_;
    // the Newton solver where the coarse grid's cycle has levels enough, the default's choice below
    if (params_.solver == GFMD_SOLVER_NEWTON && *newton_refusal(c->grid_, params_) != '\0')
        c->params_.solver = GFMD_SOLVER_AUTO;
    c->body_ = make_body(c->grid_, params_.kind, params_.width, params_.e_star, params_.nu);
    c->dynamics_ = dynamics_for(c->params_, c->body_);
    const double to_coarse = 1.0 / static_cast<double>(grid_.real_size());
    // h and z filtered to the coarse grid through their spectra (this grid's work array is scratch)
    grid_.forward(fields_.h.data(), fields_.work.data());
    copy_shared_modes(grid_, fields_.work.data(), c->grid_, c->fields_.work.data(), to_coarse);
    c->grid_.backward(c->fields_.work.data(), c->fields_.h.data());
    grid_.forward(fields_.z.data(), fields_.work.data());
    copy_shared_modes(grid_, fields_.work.data(), c->grid_, c->fields_.work.data(), to_coarse);
    c->grid_.backward(c->fields_.work.data(), c->fields_.z.data());
    c->fields_.lift_at_rest(c->grid_);
    c->apply_control();
    c->active_solver_ = c->resolve_solver(c->params_.solver);
    c->refresh_forces();
    c->solver_ = make_solver(c->active_solver_, c->grid_, c->dynamics_);
    return c;
}

// The surface relaxed on the grid coarsened levels - 1 times (each grid to tol, at most max_steps
// steps, started from the next coarser one), interpolated to this grid and lifted onto the
// substrate, at rest.  The caller has saved the state in undo_: a failure restores it (and the
// solver's state) and throws.
void Simulation::coarse_start(double tol, int64_t max_steps, int levels, int64_t &coarse_steps) {
    const std::vector<double> solver_state = solver_->state();
    try {
        auto c = coarsened();
        int64_t own = 0, below = 0;
        c->relax_multilevel(tol, max_steps, levels - 1, own, below);  // a start: used converged or not
        coarse_steps = own + below;
        // The coarse surface interpolated to this grid, kept on or above the substrate.
        c->grid_.forward(c->fields_.z.data(), c->fields_.work.data());
        copy_shared_modes(c->grid_, c->fields_.work.data(), grid_, fields_.work.data(),
                          1.0 / static_cast<double>(c->grid_.real_size()));
        grid_.backward(fields_.work.data(), fields_.z.data());
    } catch (...) {
        undo_.restore(fields_);
        refresh_forces();
        solver_->set_state(solver_state);
        throw;
    }
    fields_.lift_at_rest(grid_);
    apply_control();
    refresh_forces();
}

int Simulation::newton_start_levels() const {
    if (active_solver_ != GFMD_SOLVER_NEWTON || nested_ || plastic_ || free()) return 1;
    int levels = 1;
    while (levels < kNewtonStartLevels && (grid_.nx() >> levels) >= kNewtonCoarsest) ++levels;
    return levels > 1 && surface_flat() ? levels : 1;
}

bool Simulation::relax_multilevel(double tol, int64_t max_steps, int levels, int64_t &steps_taken,
                                  int64_t &coarse_steps) {
    if (levels < 1) fail(GFMD_ERR_INVALID_ARG, "levels must be >= 1, got " + std::to_string(levels));
    if (levels > 1) require_periodic("the multilevel start (levels > 1)");
    if (levels > 1 && plastic_)
        fail(GFMD_ERR_STATE, "the multilevel start does not take a hardness (a coarse grid cannot yield as the fine one); "
                             "use gfmd_relax or levels = 1");
    const int64_t factor = int64_t{1} << std::min(levels - 1, 40);
    // levels = 1 is relax() on any grid (no coarse grid to fit: a 64 x 6 grid was refused)
    const bool fits = levels <= 41 && grid_.nx() % factor == 0 && grid_.ny() % factor == 0 &&
                      grid_.nx() / factor >= kMinCoarse && grid_.ny() / factor >= kMinCoarse;
    if (levels > 1 && !fits)
        fail(GFMD_ERR_INVALID_ARG, std::to_string(levels) + " levels need nx and ny divisible by " +
                                       std::to_string(factor) + " with at least " + std::to_string(kMinCoarse) +
                                       " points a side on the coarsest grid; the grid is " +
                                       std::to_string(grid_.nx()) + " x " + std::to_string(grid_.ny()));
    coarse_steps = 0;
    if (levels == 1) return relax(tol, max_steps, steps_taken);
    undo_.save(fields_);  // a failure below restores the state of the call's start
    const std::vector<double> solver_state = solver_->state();
    coarse_start(tol, max_steps, levels, coarse_steps);
    // This grid now starts from a deformed surface, not the one the solver was chosen for: the
    // default chooses again (from 2048^2 on, a layer on a fluid foundation without adhesion takes
    // the approach then FIRE there instead of the CG of a flat start).  The call's solver is kept,
    // so that a failure restores it with its state.
    const int32_t call_kind = active_solver_;
    std::unique_ptr<Solver> call_solver;
    try {
        call_solver = follow_auto_choice();
    } catch (...) {  // std::bad_alloc: nothing changed but the surface, restored
        undo_.restore(fields_);
        refresh_forces();
        throw;
    }
    if (!call_solver) {
        solver_->restart(dynamics_);
        return relax_from(tol, max_steps, steps_taken, &solver_state);
    }
    try {
        const std::vector<double> fresh = solver_->state();  // a new solver: restarted
        return relax_from(tol, max_steps, steps_taken, &fresh);
    } catch (...) {  // diverged: the surface is restored; the solver too
        solver_ = std::move(call_solver);
        active_solver_ = call_kind;
        solver_->set_state(solver_state);
        throw;
    }
}

}  // namespace gfmd
