// A simulation: the grid, the parameters, the body, the fields and a solver, composed; every
// change checked before it is made and undone if the new state overflows.  The physics lives in
// the parts: green (body), forces, solvers/, observables, substrate; this class only sequences
// them and keeps their results consistent (forces always those of the current z).
#ifndef GFMD_SRC_SIMULATION_HPP
#define GFMD_SRC_SIMULATION_HPP

#include <cstdint>
#include <memory>
#include <optional>

#include "fft_grid.hpp"
#include "fields.hpp"
#include "forces.hpp"
#include "green.hpp"
#include "params.hpp"
#include "plasticity.hpp"
#include "solver_choice.hpp"
#include "solvers/solver.hpp"
#include "substrate.hpp"

namespace gfmd {

class Simulation {
public:
    // threads 0 = the default; the FFT is planned once, with these settings.  Throws
    // GFMD_ERR_INVALID_ARG / GFMD_ERR_BAD_ENUM for bad sizes, threads or planner, GFMD_ERR_NOMEM
    // (before allocating) when the grid does not fit in the memory available.
    // With a distribution (libgfmd_mpi) the grid is split over its ranks and construction is
    // collective; the caller has checked the memory of this rank's slab.
    // boundary GFMD_BOUNDARY_FREE: the nx x ny grid is the whole region of a half-space whose
    // surface beyond it carries no load, solved on the zero-padded 2nx x 2ny cell (grid());
    // GFMD_ERR_STATE with a distribution.
    Simulation(int64_t nx, int64_t ny, double lx, double ly, int threads = 0, int32_t planner = GFMD_PLANNER_MEASURE,
               const Distribution *dist = nullptr, int32_t boundary = GFMD_BOUNDARY_PERIODIC);
    // Deep copy: an independent simulation in the same state (parameters, fields, solver state),
    // planned once with this one's threads and planner.
    std::unique_ptr<Simulation> clone() const;

    // Checkpoint and restart (checkpoint.cpp): the complete state in a portable binary file.
    void save(const char *path) const;
    // Collective with a distribution (libgfmd_mpi): every rank reads its own rows.
    static std::unique_ptr<Simulation> load(const char *path, const Distribution *dist = nullptr);

    // The grid the body is solved on: the user's grid, or with free boundaries the padded cell.
    const FftGrid &grid() const { return grid_; }
    // The user's grid (the region with free boundaries): every field a caller passes or receives.
    int64_t nx() const { return rx_; }
    int64_t ny() const { return ry_; }
    double lx() const { return free() ? 0.5 * grid_.lx() : grid_.lx(); }
    double ly() const { return free() ? 0.5 * grid_.ly() : grid_.ly(); }
    int64_t points() const { return rx_ * ry_; }
    bool free() const { return params_.boundary == GFMD_BOUNDARY_FREE; }
    // The same body, parameters and substrate with this boundary, flat at rest (a new grid: the
    // padded cell or the region's).  Throws as the setters for what the boundary does not take.
    std::unique_ptr<Simulation> with_boundary(int32_t boundary) const;
    // U_el and U_ad of the configuration.  With free boundaries U_el is (1/2) sum p u of the
    // region's pressure and its free-space displacement: the padded cell's energy plus the part its
    // uniform mode holds at force balance.
    double elastic_energy() const;
    double adhesive_energy() const { return forces_.u_ad; }

    // Setters check everything before changing anything (a failed call changes nothing).  Those
    // that change the energy landscape or the dynamics restart the solver.
    void set_modulus(double e_star);
    void set_green(int32_t kind, double width);
    void set_poisson(double nu);
    void set_heights(const double *h);
    void generate_selfaffine(const SelfAffineParams &p);
    void set_pressure(double sigma0);  // pressure control
    // Displacement control: mean(z) = d; throws GFMD_ERR_INVALID_ARG if d < mean(h) (or not finite).
    void set_mean_displacement(double d);
    // Throws GFMD_ERR_INVALID_ARG unless d is finite and >= the mean of the substrate h.
    void check_mean_displacement(double d, const double *h) const;
    void set_adhesion(double gamma0, double rho);
    // Perfect plasticity at hardness H (plasticity.hpp); +inf: none.  Throws GFMD_ERR_INVALID_ARG
    // for H <= 0 or NaN, GFMD_ERR_STATE with adhesion, a solver that does not take it, or a
    // distributed grid.  A change of a finite H commits the load step made at the old one.
    void set_hardness(double hardness);
    // The fraction of the points yielding now, and the volume the substrate lost (0 without hardness).
    double plastic_area() const;
    double plastic_volume() const;
    void set_timestep(double dt);
    void set_damping(double eta);
    void set_solver(int32_t solver);
    void set_threads(int threads);  // 0 = the default
    void set_planner(int32_t planner);
    void reset();
    void restart_solver() { solver_->restart(dynamics_); }
    double hardness() const { return params_.hardness; }

    const Dynamics &dynamics() const { return dynamics_; }
    // The solver that steps now: the one set, or the one GFMD_SOLVER_AUTO chose.
    int32_t active_solver() const { return active_solver_; }

    // Dynamics: both continue the solver's trajectory where the last call stopped.  Throw
    // Error(GFMD_ERR_DIVERGED) after restoring the state of the call's start.
    void step(int64_t nsteps);
    // Returns true if converged; steps_taken receives the number of steps made.
    bool relax(double tol, int64_t max_steps, int64_t &steps_taken) { return relax_from(tol, max_steps, steps_taken, nullptr); }
    // The same, started from a coarser problem: the body relaxed on the grid coarsened levels - 1
    // times by 2 (the substrate and the surface filtered to each grid), its surface interpolated
    // to the next finer grid, down to this one.  steps_taken counts this grid's steps,
    // coarse_steps those of the coarser grids.  Throws GFMD_ERR_INVALID_ARG for levels < 1 or
    // grids that do not halve to at least kMinCoarse points a side.
    bool relax_multilevel(double tol, int64_t max_steps, int levels, int64_t &steps_taken, int64_t &coarse_steps);
    static constexpr int64_t kMinCoarse = 8;

    // Observables of the current configuration.
    const ForceState &forces() const { return forces_; }
    double contact_area() const;
    double mean_gap() const;
    void heights(double *out) const;
    void gap(double *out) const;
    void surface(double *out) const;
    void pressure(double *out) const;
    void contact_set(unsigned char *out) const;  // 1 where the gap is zero (the points counted in contact)
    double persson_variance() const;
    double persson_contact_area(double sigma0) const;
    double persson_load(double rel_area) const;
    // mean(z); with free boundaries the level of the surface far from the region (the body's
    // rigid position: mean(z) of the padded cell plus the uniform mode's displacement)
    double mean_displacement() const;
    double mean_pressure() const { return forces_.mean_pressure / load_fraction(); }

private:
    void refresh_forces();  // forces_ of the current z
    // relax(); with call_start, the caller saved the fields to restore on divergence in undo_ and
    // passes the solver state that goes with them
    bool relax_from(double tol, int64_t max_steps, int64_t &steps_taken, const std::vector<double> *call_start);
    // This body on the grid coarsened by 2, substrate and surface filtered to it, at rest
    std::unique_ptr<Simulation> coarsened();  // uses this grid's work array
    void coarse_start(double tol, int64_t max_steps, int levels, int64_t &coarse_steps);
    // The Newton method's start from a flat surface: the levels of the multilevel start relax()
    // makes first (1: none).  From flat the first Newton steps mostly find the long waves' contacts
    // again and again; on coarser grids they are cheap.  Each coarse grid relaxed to
    // kNewtonStartTol, at most kNewtonStartSteps steps, the coarsest kNewtonCoarsest points a side
    // or more, at most kNewtonStartLevels levels (docs/decisions.md, "The active-set Newton method").
    int newton_start_levels() const;
    static constexpr int kNewtonStartLevels = 4;
    static constexpr int64_t kNewtonCoarsest = 64;
    static constexpr double kNewtonStartTol = 1e-6;
    static constexpr int64_t kNewtonStartSteps = 1000;
    bool nested_ = false;  // a coarse grid of a multilevel start
    template <class Apply, class Undo>
    void change(const char *what, Apply &&apply, Undo &&undo);
    void change_body(const char *what, const Params &p);
    void change_substrate(RealBuffer &&h);
    void apply_control();  // under displacement control: z projected onto mean(z) = mean_z
    void commit_plastic_step();  // with hardness: a change of load begins a new plastic step
    // The substrate the theory and the automatic choice see: with hardness the one the load step
    // began from (it does not change within the step), else nullptr (fields_.h)
    const double *step_substrate() const { return plastic_ ? plastic_->substrate.data() : nullptr; }
    // GFMD_SOLVER_AUTO's choice for the current problem (solver_choice.hpp), or the one requested
    int32_t resolve_solver(int32_t requested) const;
    ChoiceFeatures choice_features() const;
    bool surface_flat() const;  // z the same everywhere (a reset or new substrate; no load carried yet)
    double overlap_fraction() const;  // the points whose substrate lies above the prescribed mean position
    double roughness_thickness() const;  // 2 sqrt(2) q_s w: the width against the substrate's shortest wave
    // under GFMD_SOLVER_AUTO: the solver for the current problem; returns the one it replaced
    // (null if kept), for a caller that must restore it
    std::unique_ptr<Solver> follow_auto_choice();
    [[noreturn]] void diverged(int64_t step, const std::vector<double> &solver_state);
    // Free boundaries: the region's share of the padded cell (1/4; 1 periodic): the pressure on
    // the padded cell that makes the region's total force sigma0 lx ly
    double load_fraction() const { return free() ? 0.25 : 1.0; }
    // index of region point (x, y) in the grid's fields
    std::size_t at(int64_t x, int64_t y) const { return static_cast<std::size_t>(y * grid_.nx() + x); }
    void crop(const double *field, double *out) const;  // the region's values of a grid field
    // The padded substrate of region heights h: below the region by more than any surface of a
    // body pressed onto it reaches, and 1000 adhesive ranges rho, so that it neither touches nor
    // attracts (free boundaries only)
    RealBuffer padded_substrate(const double *h, double rho) const;
    void require_periodic(const char *what) const;  // GFMD_ERR_STATE with free boundaries

    FftGrid grid_;
    Params params_;
    Body body_;
    Dynamics dynamics_;
    Fields fields_;
    Snapshot undo_;
    ForceState forces_;
    // Persson's full-contact pressure variance: a function of the substrate and the body only,
    // computed (one transform of h, a half-spectrum for the call) at its first use after either
    // changed, not at every change of load that asks for it (the automatic choice, persson_load)
    mutable std::optional<double> persson_v_;
    // The substrate's shortest wave (substrate_shortest_wave), a function of the substrate only,
    // computed at its first use by the automatic choice after it changed
    mutable std::optional<double> substrate_q_;
    int64_t rx_, ry_;      // the user's grid (the region)
    int32_t active_solver_;
    std::unique_ptr<Solver> solver_;
    std::unique_ptr<Plasticity> plastic_;  // with a finite hardness only
};

}  // namespace gfmd

#endif
