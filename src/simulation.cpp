#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "constraint.hpp"
#include "error.hpp"
#include "observables.hpp"
#include "solvers/newton.hpp"

namespace gfmd {

namespace {

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

void require_finite(double x, const char *name) {
    if (!std::isfinite(x)) fail(GFMD_ERR_INVALID_ARG, std::string(name) + " must be finite, got " + num(x));
}

// nx, after checking the grid and that it fits in memory: nothing is allocated or planned before.
int64_t admitted(int64_t nx, int64_t ny, double lx, double ly, const Distribution *dist) {
    validate_grid(nx, ny, lx, ly);
    if (dist == nullptr) check_memory(nx, ny);
    return nx;
}

RealBuffer copy_of(const RealBuffer &from) {
    RealBuffer to(from.size());
    std::copy(from.data(), from.data() + from.size(), to.data());
    return to;
}

// With adhesion the CG is the preconditioned surface CG with its adhesive line search (cg.cpp),
// on every body under pressure control; under displacement control the surface CG is neither
// preconditioned nor are its steps checked against the energy, so it does not take adhesion there.
bool cg_takes(const Params &p) { return !(p.gamma0 > 0.0) || p.control == kPressureControl; }

// GFMD_ERR_STATE if the solver set (or kept) by the caller would run p and cannot: GFMD_SOLVER_CG,
// or GFMD_SOLVER_NEWTON (newton.hpp: a thin sheet without adhesion under pressure control, on a
// grid its cycle takes).
void require_solver_takes(const FftGrid &grid, const Params &p, int32_t solver) {
    if (solver == GFMD_SOLVER_CG && !cg_takes(p))
        fail(GFMD_ERR_STATE,
             "the CG solver takes adhesion under pressure control only; under displacement control with "
             "adhesion choose GFMD_SOLVER_FIRE, GFMD_SOLVER_FIRE_MASS, GFMD_SOLVER_VERLET or GFMD_SOLVER_AUTO");
    if (solver == GFMD_SOLVER_NEWTON) {
        const std::string why = newton_refusal(grid, p);
        if (!why.empty()) fail(GFMD_ERR_STATE, why + "; choose another solver or GFMD_SOLVER_AUTO");
    }
}
}  // namespace

Simulation::Simulation(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner,
                       const Distribution *dist)
    : grid_(admitted(nx, ny, lx, ly, dist), ny, lx, ly, threads, planner, dist),
      body_(make_body(grid_, params_.kind, params_.width, params_.e_star, params_.nu)),
      dynamics_(dynamics_for(params_, body_)),
      fields_(grid_),
      undo_(grid_),
      active_solver_(resolve_solver(params_.solver)),
      solver_(make_solver(active_solver_, grid_, dynamics_)) {
    fields_.put_flat_at_rest(grid_);
    refresh_forces();
}

std::unique_ptr<Simulation> Simulation::clone() const {
    auto c = std::make_unique<Simulation>(grid_.nx(), grid_.ny(), grid_.lx(), grid_.ly(), grid_.threads(),
                                          grid_.planner(), grid_.distribution());
    c->params_ = params_;
    c->body_.stiffness = copy_of(body_.stiffness);
    c->body_.k_min = body_.k_min;
    c->body_.k_max = body_.k_max;
    c->dynamics_ = dynamics_;
    c->persson_v_ = persson_v_;
    c->substrate_q_ = substrate_q_;
    c->fields_.h = copy_of(fields_.h);
    c->fields_.z = copy_of(fields_.z);
    c->fields_.v = copy_of(fields_.v);
    c->active_solver_ = active_solver_;
    c->solver_ = solver_->clone();
    c->refresh_forces();
    return c;
}

void Simulation::refresh_forces() { forces_ = evaluate_forces(grid_, params_, body_, fields_); }

// Applies a change, then checks that the forces and energies of the new state are finite; if
// they overflow (extreme but individually valid values, e.g. E* = 1e300 with unit heights), the
// change is undone and the call fails with nothing changed.  A change that holds restarts the
// solver: the energy landscape or the dynamics it adapted to are gone.
template <class Apply, class Undo>
void Simulation::change(const char *what, Apply &&apply, Undo &&undo) {
    apply();
    refresh_forces();
    if (forces_.finite()) {
        try {
            follow_auto_choice();  // CG's fields may not fit (std::bad_alloc): then nothing changed
        } catch (...) {
            undo();
            refresh_forces();
            throw;
        }
        solver_->restart(dynamics_);
        return;
    }
    undo();
    refresh_forces();
    fail(GFMD_ERR_RANGE, std::string(what) + " would make the forces or energies overflow double precision; "
                                             "nothing was changed");
}

// New Green's function, modulus or Poisson ratio: a new body, kept only if the state stays finite.
void Simulation::change_body(const char *what, const Params &p) {
    require_solver_takes(grid_, p, params_.solver);
    Body b = make_body(grid_, p.kind, p.width, p.e_star, p.nu);
    const Params old_params = params_;
    const Dynamics old_dynamics = dynamics_;
    change(
        what,
        [&] {
            params_ = p;
            std::swap(body_, b);
            dynamics_ = dynamics_for(params_, body_);
            persson_v_.reset();
        },
        [&] {
            params_ = old_params;
            std::swap(body_, b);
            dynamics_ = old_dynamics;
            persson_v_.reset();
        });
}

void Simulation::set_modulus(double e_star) {
    require_finite(e_star, "E*");
    if (e_star <= 0.0) fail(GFMD_ERR_INVALID_ARG, "E* must be > 0, got " + num(e_star));
    Params p = params_;
    p.e_star = e_star;
    change_body("E*", p);
}

void Simulation::set_green(int32_t kind, double width) {
    validate_green_kind(kind);
    if (kind == GFMD_GREEN_HALFSPACE) {
        width = 0.0;
    } else {
        require_finite(width, "layer width");
        if (width <= 0.0) fail(GFMD_ERR_INVALID_ARG, "layer width must be > 0, got " + num(width));
    }
    if (kind == GFMD_GREEN_LAYER_BONDED && std::isnan(params_.nu))
        fail(GFMD_ERR_STATE, "the bonded layer needs Poisson's ratio: call gfmd_set_poisson first");
    Params p = params_;
    p.kind = kind;
    p.width = width;
    change_body("this Green's function", p);
}

void Simulation::set_poisson(double nu) {
    validate_poisson(nu);
    Params p = params_;
    p.nu = nu;
    if (params_.kind == GFMD_GREEN_LAYER_BONDED)
        change_body("this Poisson ratio", p);
    else
        params_ = p;  // kept for a bonded layer chosen later; this body does not use it
}

// A new substrate resets the body to flat and at rest; the old substrate comes back, with z and v,
// if the new state overflows.
void Simulation::change_substrate(RealBuffer &&h) {
    if (params_.control == kDisplacementControl) check_mean_displacement(params_.mean_z, h.data());
    undo_.save(fields_);
    change(
        "this substrate",
        [&] {
            std::swap(fields_.h, h);
            persson_v_.reset();
            substrate_q_.reset();
            fields_.put_flat_at_rest(grid_);
            apply_control();
        },
        [&] {
            std::swap(fields_.h, h);
            persson_v_.reset();
            substrate_q_.reset();
            undo_.restore(fields_);
        });
}

void Simulation::set_heights(const double *h) {
    const int64_t n = grid_.local_points();
    grid_.on_all_ranks([&] {
        for (int64_t i = 0; i < n; ++i)
            if (!std::isfinite(h[i]) || std::fabs(h[i]) > kMaxHeight)
                fail(GFMD_ERR_INVALID_ARG, "height " + std::to_string(i + grid_.first_row() * grid_.nx()) + " = " +
                                               num(h[i]) + " is not finite or exceeds 1e100 in magnitude");
    });
    RealBuffer nh(static_cast<std::size_t>(n));  // the new substrate, 8 B/pt for this call
    std::copy(h, h + n, nh.data());
    change_substrate(std::move(nh));
}

void Simulation::generate_selfaffine(const SelfAffineParams &p) {
    validate_selfaffine(grid_, p);
    RealBuffer nh(static_cast<std::size_t>(grid_.local_points()));  // the new substrate, 8 B/pt for this call
    gfmd::generate_selfaffine(grid_, p, fields_.work.data(), nh.data());
    change_substrate(std::move(nh));
}

void Simulation::set_pressure(double sigma0) {
    require_finite(sigma0, "sigma0");
    if (sigma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "sigma0 must be >= 0, got " + num(sigma0));
    const Params old = params_;
    change(
        "sigma0",
        [&] {
            params_.sigma0 = sigma0;
            params_.control = kPressureControl;
        },
        [&] { params_ = old; });
}

void Simulation::check_mean_displacement(double d, const double *h) const {
    require_finite(d, "the mean displacement");
    const double mean_h = grid_.mean(h);
    if (d < mean_h)
        fail(GFMD_ERR_INVALID_ARG, "the mean displacement " + num(d) + " is below the substrate's mean height " +
                                       num(mean_h) + ": a body with z >= h cannot have that mean");
}

void Simulation::apply_control() {
    if (params_.control == kDisplacementControl) project_mean(grid_, fields_, params_.mean_z);
}

void Simulation::set_mean_displacement(double d) {
    check_mean_displacement(d, fields_.h.data());
    Params asked = params_;
    asked.control = kDisplacementControl;
    require_solver_takes(grid_, asked, params_.solver);
    const Params old = params_;
    undo_.save(fields_);
    change(
        "this mean displacement",
        [&] {
            params_.control = kDisplacementControl;
            params_.mean_z = d;
            apply_control();
        },
        [&] {
            params_ = old;
            undo_.restore(fields_);
        });
}

double Simulation::mean_displacement() const { return grid_.mean(fields_.z.data()); }

void Simulation::set_adhesion(double gamma0, double rho) {
    require_finite(gamma0, "gamma0");
    require_finite(rho, "rho");
    if (gamma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "gamma0 must be >= 0, got " + num(gamma0));
    if (rho <= 0.0) fail(GFMD_ERR_INVALID_ARG, "rho must be > 0, got " + num(rho));
    if (!std::isfinite(gamma0 / (rho * rho)) || !std::isfinite(gamma0 / rho))
        fail(GFMD_ERR_RANGE, "the adhesive stiffness gamma0/rho^2 overflows");
    Params asked = params_;
    asked.gamma0 = gamma0;
    require_solver_takes(grid_, asked, params_.solver);
    const Params old = params_;
    const Dynamics old_dynamics = dynamics_;
    change(
        "this adhesion",
        [&] {
            params_.gamma0 = gamma0;
            params_.rho = rho;
            dynamics_ = dynamics_for(params_, body_);
        },
        [&] {
            params_ = old;
            dynamics_ = old_dynamics;
        });
}

void Simulation::set_timestep(double dt) {
    require_finite(dt, "dt");
    if (dt < 0.0) fail(GFMD_ERR_INVALID_ARG, "dt must be >= 0 (0 = automatic), got " + num(dt));
    params_.dt_user = dt;
    dynamics_ = dynamics_for(params_, body_);
    solver_->restart(dynamics_);
}

void Simulation::set_damping(double eta) {
    require_finite(eta, "damping");
    if (eta < 0.0) fail(GFMD_ERR_INVALID_ARG, "damping must be >= 0 (0 = automatic), got " + num(eta));
    params_.eta_user = eta;
    dynamics_ = dynamics_for(params_, body_);
    solver_->restart(dynamics_);
}

// GFMD_SOLVER_AUTO's rule, from measurements (docs/performance.md, "Choosing the solver"): the
// Polonsky-Keer CG works on the contact set with the compliance 1/k(q); its iterations grow with
// the softness of the long waves against the short ones, S = k(q_max)/k_min (a half-space: 0.7 n;
// a bonded coating: bounded, whatever the grid; a layer on a fluid foundation: huge), and mildly
// with the grid.  An iteration costs about three FIRE steps.  Measured from flat (self-affine,
// A/A0 ~ 0.1, 128^2-1024^2), CG was faster where S sqrt(N) < 4e4 and as fast or slower beyond
// (ties: the 256^2 half-space, S sqrt(N) = 4.6e4; a bonded layer w = 32 at 1024^2, 5.9e4).
constexpr double kAutoCgBound = 4e4;
// A bonded layer's iterations grow less with S sqrt(N) than the half-space's (w = 8 at 2048^2,
// 3.0e4: 16 iterations; the 256^2 half-space, 4.6e4: 40).  Once the pressure CG's passes were
// vectorized (docs/performance.md, "The pressure CG's passes"; gfmd_bench --bonded 0.3 and 0.5,
// one thread, to 0.1 %), CG took 0.85-0.94x FIRE's time on w = 32 at 1024^2 (6.1e4; nu = 0.5,
// 4.7e4: 0.77-0.88x), 0.29x on w = 8 at 2048^2 and 1.19x on w = 32 at 2048^2 (1.2e5); the
// half-space stayed FIRE's at 256^2 (1.12x).  So bonded layers take CG up to 8e4, between those.
constexpr double kAutoCgBoundBonded = 8e4;
// Those bounds were measured at A/A0 ~ 0.1.  At lower loads the half-space's CG needs far fewer
// iterations (few contact points) while FIRE needs more steps (the long waves move far), and the
// CG won beyond the bound: from flat, H = 0.8, lambda_s = 4a, lambda_r = n a/8, g = 1, one thread
// (gfmd_bench --loads 0.003,0.01,0.05 --widths 0 --sizes 512,1024, and a scratch program at 2048^2;
// docs/performance.md "The half-space at low loads"), at Persson's A/A0 = 0.005 CG took 0.35x
// FIRE's time at 1024^2 and 0.41x at 2048^2, at 0.016 0.41x at 512^2, 0.68x at 1024^2 and 1.08x
// at 2048^2, at 0.08 1.3x at 512^2 and 2.5x at 1024^2 (about even at 256^2).  Ordered by Persson's
// A/A0 times sqrt(N) the wins end between 16 and 20 and the losses begin from 21-33: the half-space
// takes CG where that is below 20, whatever S sqrt(N).  So do bonded layers beyond their bound
// (2026-11-27, afternoon; gfmd_bench --sizes 512,1024 --widths 16,32,128 --bonded 0.3 and 0.5
// --sigma0 0.003, 0.01, 0.05, to A/A0 within 0.1 %, docs/performance.md "Bonded layers at low
// loads"): where the product was 2.5-8.2 (512^2) and 4.9 (1024^2) CG took 0.28-0.71x FIRE's time
// on all 14 rows; at 16.3 (1024^2) 0.45-0.70x on w = 64 a and 128 a, 1.22-1.28x on w = 512 a in
// that run and 0.95x in the run after the change; at 41-82 FIRE won 9 of 10 rows, the tenth a
// tie (CG 0.93x).  At 2048^2, w = 128 a, 9.7: CG 12.2 s against FIRE's 30.8 s.
constexpr double kAutoCgHalfspaceLowLoad = 20.0;
// And within the bounds the CG loses at high loads: its iterations grow with the contact set while
// FIRE's steps fall (the wall pins most points).  Measured (2026-11-27, afternoon; gfmd_bench
// --sizes 128,256,512 and 1024 --widths 0,2,4,8,16,32 --bonded 0.3 --sigma0 0.1, 0.2, 0.3, 0.5
// --no-cg, to A/A0 within 0.1 %; docs/performance.md "The pressure CG at high loads"), ordered by
// S times Persson's A/A0: CG faster on every row up to 9.9 but two at 9.1-9.2 (1.34x, 1.50x at
// 512^2; 0.56-1.00x at the other sizes), mixed from 13 to 14.4 (0.49-1.34x), and from 18 on
// slower by more than 1.1x on 25 of 30 rows (up to 7.3x: 256^2, w = 128 a, A/A0 0.76), the other
// five 0.79-1.07x.  So the CG within the bounds where that product is below 14 -- the same as the
// low-load rule on a half-space (S = 0.7 sqrt(N) there: 0.7 x 20).
constexpr double kAutoCgDenseContacts = 14.0;
// On a layer on a fluid foundation CG iterates on the surface, preconditioned by the inverse
// stiffness (cg.cpp).  Without adhesion, from flat (gfmd_bench --loads 0.002,0.01,0.05, one
// thread) it took 0.17-0.54x FIRE's time at 256^2 and 512^2 (W = 0.0625 ... 4) and was faster
// than mass-weighted FIRE and the approach then FIRE there; 0.33-0.50x at 1024^2 (W = 1, 4),
// 0.22x at 1024^2 on W = 10 but 1.24x at sigma0 = 0.05; 0.30x, 0.48x and 1.06x (sigma0 = 0.05)
// at 2048^2 on W = 10.  In the study's sweeps, each load continuing from the last, 0.40-0.85x
// FIRE's time on every layer (256^2: W = 100 ... 0.0625; 1024^2: W = 100, 10, 4, 1).  So CG on
// every such body: at worst 1.24x slower than FIRE, where FIRE was at worst 5.8x slower.
// Not so in the study's sweeps at 2048^2 with lambda_r = 64 lambda_s (gfmd_paper --full,
// docs/paper/full.md): there the loads that continue from the last equilibrium took CG 0.7-1.4x
// as many iterations as FIRE steps (W = 100: 2771 against 1975; W = 0.0625: 6882 against 9549),
// at 2.3-3.8x a step's time, so the thin sheets W <= 0.25 and W = 100 took 1.3-3.3x the seconds
// of the approach then FIRE, W = 0.5-4 0.84-1.02x; the first loads from flat stayed CG's
// (W = 10 at 2048^2: 0.30-1.06x; 4096^2, W = 1: 22.0 s against 39.8 s).  At 1024^2 with the same
// spectrum (lambda_r = 256 a) the continuing loads of W = 100 were still CG's (0.73x) and a thin
// sheet's (W = 0.0625) 1.39x FIRE's.  So from 2048^2 on, a load that starts from a deformed
// surface takes the approach then FIRE (GFMD_SOLVER_MASS_FIRE); a flat surface (a first load)
// takes CG at every size.  Measured with the rule (five bodies of --full, full.md): W = 100,
// 0.25, 0.125, 0.0625 0.42-0.92x the all-CG seconds, but W = 1 1.5x (its high loads are CG's):
// the middle widths lost, hence the bounds below.  The grids of a multilevel start
// above the coarsest start from an interpolated, deformed surface: relax_multilevel chooses again
// for them (until then a first load's CG, chosen for the flat surface, ran on every grid: in the
// default --full run of 2026-11-25 the thin sheets' multilevel first loads, W = 0.088-0.044, took
// 3.6-4.5x the seconds of the all-FIRE ones of the 5205.9 s run, where the continuing loads took
// 2.2-2.8x, same steps, on that slower instance; docs/paper/full.md).
constexpr double kAutoContinueFirePoints = 2048.0 * 2048.0;
// The middle widths, measured once both solvers' passes were built for AVX2 (gfmd_bench --sweep
// --sizes 2048: the study's nine continuing loads on --full's substrate, one thread, two bodies
// side by side; docs/performance.md "The study's continuing loads at 2048^2"): CG took 0.64-0.66x
// the approach then FIRE's seconds on W = 0.5, 1, 4 (f(q_min w) = 2.6e7, 3.3e6, 5.1e4; q_max w =
// 8.9 ... 71), but 0.97x on W = 10 (f = 3.3e3), 2.38x on W = 100 (f = 4.45), 1.01x on W = 0.25
// (q_max w = 4.4, w = a) and 1.29x on W = 0.177 (3.1).  So a continuing load at >= 2048^2 stays CG's on a layer whose longest
// wave is plate-like, f(q_min w) >= 1e4, and which is not thinner than the grid resolves,
// q_max w >= 6 (q_max = pi sqrt(2)/a, the grid's corner): both bounds between the rows above.
// Below 2048^2 the same choice on the thin sheets (q_max w < 6) whose longest wave is very soft,
// f(q_min w) >= 1e6, and that are thin against the substrate's shortest wave, 2 sqrt(2) q_s w < 4.5
// (roughness_thickness(); = q_max w where lambda_s = 4a), on grids of at least 128^2 points,
// where the CG had stayed.  Measured 2026-11-28 (gfmd_bench --sweep --columns cg,auto --verbose:
// the study's nine continuing loads, one thread, two runs side by side; log
// docs/performance_logs/thin_continuing_2026-11-28.log; docs/performance.md "The thin sheets'
// continuing loads below 2048^2"), on the study's substrate (lambda_s = 4a): the rule's choices
// took 0.32-0.70x the CG's seconds at 1024^2 (W = 0.044 ... 0.25: f = 2.6e7 ... 4.8e9, q_max w =
// 0.78 ... 4.4; log thin_continuing_1024_2026-11-28_committed.log), 0.46-0.89x at 512^2 (W = 0.044 ... 0.25), 0.57-0.84x at 256^2 (W = 0.044 ... 0.177,
// f >= 1.1e6) and 0.75x, 0.81x at 128^2 (W = 0.044, 0.0625: f = 9.3e6, 3.3e6); on others at 512^2
// (--substrate): lambda_s = 8a (H = 0.5) w = 0.25 a and a 0.38x, 0.70x, lambda_s = 2a (H = 0.5)
// w = 0.25 a and 0.5 a 0.78x, 0.96x.  The CG stays on the rest, where it won or tied: at the bound
// 4.5's other side 512^2, W = 0.3, 0.33 (5.3, 5.9; f = 1.9e6, 1.4e6: the rule's 1.05x, 1.16x the
// CG's seconds, 0.98x, 0.97x in a noisier run) and lambda_s = 2a, w = a (8.9, q_max w = 4.4: 1.27x
// in a scratch run); below f = 1e6 256^2, W = 0.25 (4.1e5: 1.02-1.05x), W = 0.3, 0.33 (2.4e5,
// 1.8e5: 1.3-1.6x), 128^2, W = 0.125, 0.177 (4.1e5, 1.4e5: 0.91x, 0.96x, ties) and W = 0.25 (5.1e4:
// 1.43x); and on the smallest grid, 64^2, W = 0.044 (f = 1.2e6: 2.2x, 0.11 s against 0.05 s).  From
// 2048^2 on every thin sheet (q_max w < 6) keeps the choice above, measured there.
constexpr double kAutoContinueThinSoftness = 1e6;
constexpr double kAutoContinueThinThickness = 4.5;
constexpr double kAutoContinueThinPoints = 128.0 * 128.0;
constexpr double kAutoContinueCgSoftness = 1e4;
constexpr double kAutoContinueCgThickness = 6.0;
// Of the rest, the sheets thinner than the grid resolves (q_max w < 6) take mass-weighted FIRE
// throughout at the lower loads, once its step fit the masked dynamics (commit 33d8dd2), the
// longer the thinner the sheet: while Persson's A/A0 < 0.15/(q_max w).  Measured at 2048^2
// (gfmd_bench --sweep --sizes 2048 --verbose: the study's continuing loads, one thread, two runs
// side by side; docs/performance.md "The thin sheets' continuing loads" and "The thin sheets'
// bounds by thickness"), mass weighting won the loads up to 0.18 on W = 0.044 (q_max w = 0.78;
// 20.4 s against FIRE's 26.9 at 0.18, FIRE 15.7 against 21.6 at 0.27), up to 0.05-0.08 on
// W = 0.125 (2.2; 0.45-0.90x the approach's seconds to 0.05, 27.5 against 29.6 at 0.08, 26.9
// against 23.2 at 0.12) and up to 0.03 on W = 0.25 (4.4; 26.0 s against 29.1 at 0.03, 21.6 against
// FIRE's 18.1 at 0.05): bounds 0.19, 0.068, 0.034, each between the rows.
constexpr double kAutoContinueMassThicknessArea = 0.15;
// And the approach's 100 mass-weighted steps (two FFT pairs each) pay only while FIRE needs many
// steps: at the higher loads plain FIRE.  Measured at 2048^2 on --full's substrate (gfmd_bench
// --sweep --verbose, one thread, two runs side by side; docs/performance.md "Plain FIRE at the
// higher loads"): the approach won at A/A0 = 0.008-0.03 on W = 10 (44.1 s against FIRE's
// 45.9 s, 28.6 against 40.7, 25.4 against 31.5) and at 0.008 and 0.03 on W = 100, FIRE every
// load from 0.05 on (W = 100: 9.1-16.3 s against 14.3-19.1 s; W = 10: 9.0-21.2 s against
// 14.4-23.4 s): the bound 0.04 between.  The thin sheets need FIRE's many steps longer: on
// W = 0.125 (--from 0.05) the approach won at 0.05-0.12 (39.2 s against 46.4, 29.6 against 42.3, 23.2 against 31.7), FIRE
// from 0.18 on (18.3 s against 19.3, 14.8 against 20.0, 12.3 against 16.0): their bound 0.15, or
// twice the mass-weighted bound if lower: on W = 0.25 (bound 0.068) the approach about even at
// 0.05 (17.5 s against FIRE's 18.1), FIRE from 0.08 (13.5 against 15.4, 11.0 against 15.6); on
// W = 0.044 (mass-weighted up to 0.19) FIRE next (15.7 s against the approach's 20.7 at 0.27).
// Below that bound the thick layers now take CG instead of the approach: since its preconditioner's
// floor stops below the contacts' scale at dense contacts (src/solvers/cg.cpp) the CG won the
// loads below it on both (gfmd_bench --sweep --sizes 2048 --widths 10, and 100, --columns
// m+fire,cg,auto --verbose, one thread, the two side by side; docs/performance.md "The
// preconditioner's floor at dense contacts"): W = 10 at A/A0 = 0.008, 0.016, 0.03 54.14, 35.61,
// 36.42 s against the approach's 92.85, 64.10, 46.00 s; W = 100 22.52, 28.59, 43.34 s against
// 52.00, 45.08, 40.73 s; above it FIRE still won most loads (W = 10 at 0.05, 0.08 39.36, 30.60 s
// against CG's 52.70, 41.83 s).  The continuing loads in all: 0.78x (W = 10) and 0.85x (W = 100)
// the old rule's seconds.
constexpr double kAutoContinueFireArea = 0.04;
constexpr double kAutoContinueThinFireArea = 0.15;
// The thin sheets' loads from a deformed surface at the lower loads, where the grid admits it, take
// the active-set Newton method (GFMD_SOLVER_NEWTON, newton.hpp): a step solves the free points'
// equilibrium for the held set, preconditioned by the thin-plate stencil's multigrid cycle.
// Measured 2026-11-29 (gfmd_bench --sweep --columns newton,auto --verbose, one thread, the study's
// nine continuing loads on --full's substrate; log docs/performance_logs/newton_sweep_2026-11-29.log;
// docs/performance.md "The active-set Newton method in the library"): at 2048^2 it won every load
// up to Persson's A/A0 = 0.12 on W = 0.044, 0.088, 0.25 (1.2-1.9x the default's speed then), was
// about even at 0.18 (0.96-1.05x) and lost at 0.27 and 0.4 (0.70-0.92x): bound 0.15, between.
// The same at 1024^2 (W = 0.044, 0.088, 0.25: 1.2-1.8x up to 0.12, 0.81-0.92x from 0.18 on); at
// 512^2 it won only up to 0.03-0.05 and by less (1.04-1.3x), lost beyond: from 1024^2 on.
// Its passes vectorized since (0.81x its seconds on a sticky sheet's load at 2048^2; docs/
// performance.md "The Newton method's passes vectorized"), it won the higher loads too (2026-11-29,
// gfmd_bench --sweep --from 0.18 --columns newton,auto --verbose, one thread, two runs side by
// side as the study runs its bodies; log docs/performance_logs/newton_high_loads_2026-11-29.log;
// docs/performance.md "The Newton method at the higher loads"): at 2048^2 on every one of the
// loads at Persson's A/A0 = 0.18, 0.27, 0.4 on W = 0.044, 0.0625, 0.088, 0.25 without adhesion and
// W = 0.0625, 0.088, 0.25 with the study's adhesion (1.08-2.03x the default's speed); at 1024^2 on
// W = 0.044, 0.088, 0.25 with and without adhesion it won or tied every such load (1.00-1.36x
// without adhesion, 1.20-2.14x with).  So from 1024^2 on, to 0.45: the last measured load, 0.4, and a margin below
// what was not measured (at denser contacts FIRE's steps keep falling, the Newton method's not).
constexpr double kAutoNewtonArea = 0.45;
constexpr double kAutoNewtonPoints = 1024.0 * 1024.0;
// With adhesion (CG minimizes the quadratic problem only), at most 100 mass-weighted FIRE steps
// after each restart, then FIRE (GFMD_SOLVER_MASS_FIRE), where the longest wave is much softer
// than on a half-space, f(q_min w) = k_halfspace(q_min)/k(q_min) >= 2e4, and the load is low,
// Persson's A/A0 < 0.1: the approach costs 100 steps of two FFT pairs, which pays only where
// FIRE needs many steps.  Measured from flat (gfmd_bench --loads 0.002,0.01,0.05 --sizes 256,512
// --widths 0.25,1,4; --first-load at 512^2 and 2048^2; docs/performance.md): where the rule takes
// it, 0.08-0.88x FIRE's time (12.7x faster on the adhesive W = 0.0625 sheet at 2048^2); of the
// rows it leaves to FIRE, 8 of 12 were slower with it (up to 1.45x: A/A0 ~ 0.1-0.2, or f = 6.4e3
// at 256^2), 4 faster (at most 1.35x).
constexpr double kAutoApproachSoftness = 2e4;
constexpr double kAutoApproachArea = 0.1;
// Mass-weighted FIRE throughout, once its step fit its masked dynamics (commit 33d8dd2), on the
// adhesive sheets thinner than the grid resolves, q_max w < 6 (W <= 0.25 with a = lambda_s/4), at
// the lowest of those loads, Persson's A/A0 < 0.02 (between the study's 0.016 and 0.03, so that
// no load of the study sits on the bound).  Measured (docs/performance.md, "Mass-weighted
// FIRE's step"): the 256^2 study's adhesive sheets W = 0.25 ... 0.0625 at its loads 0.004, 0.008,
// 0.016 took 2.3-4.2x fewer steps than with the approach then FIRE (once 0.56x: W = 0.0625's first
// load), at 0.03 1.6-3.0x, above 1.3-2.5x, against about 2.2x the cost of a step; at 2048^2 the
// W = 0.125 sheet's first two loads 1418 and 2120 steps (264 s, 288 s) against 7572 and 7611
// (560 s, 450 s).  The wider sheets (W >= 0.5) were not measured so: they keep the approach.
constexpr double kAutoMassArea = 0.02;
constexpr double kAutoMassThickness = 6.0;
// The thinner of those sheets keep it at every load the approach would take, A/A0 < 0.1, where
// q_max w < 4 (W <= 0.177 at a = lambda_s/4).  Measured at 2048^2 (gfmd_bench --sweep --adhesion
// --verbose, the study's continuing loads, one thread, two runs side by side; docs/performance.md
// "The thin sheets' continuing loads"): on W = 0.177 (q_max w = 3.1) mass weighting against the
// approach then FIRE at A/A0 = 0.03, 0.05, 0.08: 38.0 s against 50.5 s, 33.1 against 40.2, 26.9
// against 28.9; on W = 0.125 (2.2; whole bodies by gfmd_paper --full, "At 2048^2" there) 64.6
// against 139.5, 36.4 against 73.2, 29.8 against 49.8; but on W = 0.25 (4.4) 32.6 against 31.6,
// 30.2 against 25.6, 23.5 against 20.4.
constexpr double kAutoMassThinnerThickness = 4.0;
// With adhesion under pressure control the CG (the surface CG with its adhesive line search,
// since 2026-11-27, late night) on every body but the adhesive sheets thinner than the grid
// resolves, q_t w < 6 (kAutoMassThickness, the mass-weighted rule's bound): its iteration costs
// about 2.5 FFT pairs and a few passes with an exponential, 2.9 times a FIRE step at 512^2 and
// 2048^2, and wins where it needs about a third of the steps or fewer.  Measured
// (docs/performance.md "The adhesive CG"): the 40
// random bodies of gfmd_bench --random 40 --seed 1 (128^2-256^2), the CG the fastest solver on
// every adhesive body under pressure control (half-spaces 2.0x and 2.8x, bonded layers 1.7-3.5x,
// fluid layers w = 1.9a-63a with q_t w = 8.4-280 1.8-5.3x faster than the default of then), on
// the one with q_t w = 4.4 even with mass weighting (0.688 s against 0.693 s); the study's
// continuing loads (gfmd_bench --sweep --adhesion) at 512^2 W = 10 and 4 (q_t w = 178, 71)
// 0.60x and 0.68x the default's seconds, W = 0.5 (8.9) 0.91x, W = 0.25 (4.4) 1.43x, W = 1 (17.8)
// 1.13x, at 2048^2 W = 4 0.71x, W = 1 0.98x, and the study's whole sweeps at 256^2 and 512^2
// (W = 2 ... 40, the first load from flat) 0.40-0.57x, all with the CG's passes before they were
// merged; after, at 2048^2 the half-space 0.88x FIRE's seconds, W = 0.5 0.88x the approach's.
// The thin sheets below the bound keep their rule: there the CG lost (W = 0.25 above; W = 0.088's
// whole sweep at 256^2 2.4x the default's seconds).
constexpr double kAutoAdhesiveCgThickness = kAutoMassThickness;

// Under displacement control, mass-weighted FIRE on a layer on a fluid foundation whose longest
// wave is at least this much softer than the half-space's, f(q_min w) >= 2, FIRE otherwise.
// Measured from flat at 256^2 (gfmd_bench --displacement: the mean position 1 a below the highest
// peak, A/A0 ~ 1e-5 to 1e-3; docs/performance.md, "Mass-weighted FIRE under displacement
// control"), seconds without and with adhesion (gamma0 = 5e-4, rho = 1), mass weighting against
// FIRE: W = 0.25 (f = 4e5) 2.33 against 154.35 and 13.45 against 150.80, W = 1 (6e3) 0.75 against
// 17.60 and 1.46 against 22.94, W = 4 (100) 0.79 against 2.57 and 0.91 against 3.83, W = 8 (14)
// 0.48 against 1.29 and 0.53 against 1.28; near the bound either way, W = 16 (2.6) 0.63 against
// 0.49 and 0.87 against 1.41, the half-space (f = 1) 0.60 against 0.69 and 0.77 against 0.82.  A
// scratch run on another surface (seed 1) gave the same picture: w = 64 a (f = 2.6) 0.78 against
// 1.00 and 0.51 against 0.96, the half-space 0.77 against 0.53 and 1.06 against 1.09.
constexpr double kAutoDisplacementMassSoftness = 2.0;
// Those rows lay at A/A0 ~ 1e-5 to 1e-3.  Nearer the substrate mass weighting loses where the
// contacts pin the soft long waves, and its step costs two FFT pairs.  Measured without adhesion
// (2026-11-27, afternoon; gfmd_bench --displacement --no-adhesion --gap G, G = 1, 0.75, 0.5, 0.25,
// 0.1 rms heights above the substrate's mean, 128^2-1024^2, W = 1, 4, 16; docs/performance.md
// "Mass-weighted FIRE under displacement control near the substrate"), ordered by the fraction of
// the substrate above the prescribed mean position (Gaussian heights: 0.16 at G = 1, 0.22 at 0.75,
// 0.31 at 0.5, 0.40 at 0.25, 0.46 at 0.1): up to 0.22 mass weighting won on 7 of 10 rows (FIRE
// 1.08-3.2x its time; W = 1 at 256^2-1024^2) and lost on three (0.75-0.76x: W = 4 at 256^2 and
// 512^2, W = 16 at 512^2); at 0.31 FIRE won on all 6 layers with f(q_min w) < 1e4 (0.5-0.84x its
// time: W = 1 at 128^2 and 256^2, W = 4 at 256^2-1024^2, W = 16) but lost on the softest two (W = 1
// at 512^2, f = 5e4: 1.15x; at 1024^2, f = 4e5: 1.25x); from 0.40 on FIRE won on all 14 rows
// (0.44-0.84x, the softest included; the CG faster still on 5 of the 6 at 0.46).  With the
// study's adhesion (gamma0 = 5e-4, rho = a; --adhesion --gap 0.5 and 0.25, 256^2 and 512^2) the
// same: at 0.31 FIRE 0.53-0.92x on the five layers with f < 1e4, mass weighting faster on the
// softest (512^2, W = 1: FIRE 1.38x); at 0.40 FIRE 0.56-0.79x on all six.  So FIRE from the
// fraction 0.35, and from 0.25 where f(q_min w) < 1e4.
constexpr double kAutoDisplacementMassOverlap = 0.25;
constexpr double kAutoDisplacementMassOverlapSoftest = 0.35;
constexpr double kAutoDisplacementMassSoftest = 1e4;
// Checked first, without adhesion: the library's CG (the surface CG, the mean held) where the long
// waves are stiff enough for it, S sqrt(N) <= 2e5 with S = k_halfspace(q_max)/k_min as in the
// pressure CG's bound above (a half-space up to about 530^2, a bonded layer w = 64 a up to about
// 1700^2, thinner ones at every size measured, a layer on a fluid foundation only where its
// longest wave is nearly a half-space's).  Its iterations grow faster with the long waves'
// softness than FIRE's steps.  Measured from flat (gfmd_bench --displacement --no-adhesion --gap
// 2 and --gap 1: the mean position 2 and 1 rms heights above the substrate's mean, A/A0 ~ 0.01
// and ~ 0.1; 128^2-2048^2, one thread; docs/performance.md "CG under displacement control"): an
// iteration took about 1.3 FIRE steps' time (1.28 on the 256^2 half-space, 1.34 on a bonded layer
// w = 16 a at 2048^2, gap 1: steps are exact, this VM's seconds were not), so
// CG wins where 1.3 x its iterations < FIRE's steps.  That ratio on the half-space, gap 2 / gap
// 1: 0.50 / 0.42 at 128^2 (S sqrt(N) = 1.2e4), 0.54 / 0.77 at 256^2 (4.6e4), 0.62 / 1.02 at 512^2
// (1.9e5), 0.97 / 1.27 at 1024^2 (7.4e5), 1.41 / 2.64 at 2048^2 (3.0e6: 542 and 820 iterations
// against 501 and 404 steps); on a bonded layer w = 64 a (nu = 0.3, S = 116) 0.49 / 0.43 at
// 128^2, 0.72 / 1.02 at 1024^2 (1.2e5), 0.96 / 1.19 at 2048^2 (2.4e5); w = 4 a and 16 a (S = 7,
// 29) 0.18-0.58 at every size; on a layer on a fluid foundation w = 400 a 0.59 / 1.16 at 512^2
// (f(q_min w) = 1.01, 1.9e5), 0.85 / 1.23 at 1024^2 (f = 1.33, 9.9e5); w = 64 a at 256^2 (f = 2.6,
// 1.2e5) 0.72 of FIRE's at gap 1 and 0.56 of mass-weighted FIRE's (a step of which took 2.3 FIRE
// steps' time) at gap 2.  The bound where the ratio at A/A0 ~ 0.1 crosses 1 (1.2e5-2.4e5): beyond it CG
// lost up to 2.6x, below it at most 1.16x (w = 400 a at 512^2, gap 1: 1.25x in seconds) where it
// won 0.59-0.62 at gap 2; the win it leaves out, 0.85 at 9.9e5, is smaller than the losses beside.
constexpr double kAutoDisplacementCgBound = 2e5;

int32_t Simulation::resolve_solver(int32_t requested) const {
    if (requested != GFMD_SOLVER_AUTO) return requested;
    const bool quadratic = !(params_.gamma0 > 0.0);
    const double softness = long_wave_softness(grid_, body_, params_.e_star);  // S
    const double cg_cost = softness * std::sqrt(static_cast<double>(grid_.real_size()));
    if (params_.control != kPressureControl) {
        if (quadratic && cg_cost <= kAutoDisplacementCgBound) return GFMD_SOLVER_CG;
        const double f = longest_wave_softness(grid_, body_, params_.e_star);
        if (params_.kind != GFMD_GREEN_LAYER_FLUID || f < kAutoDisplacementMassSoftness) return GFMD_SOLVER_FIRE;
        const double overlap = overlap_fraction();  // near the substrate: one pass over h
        const bool near = overlap >= kAutoDisplacementMassOverlapSoftest ||
                          (overlap >= kAutoDisplacementMassOverlap && f < kAutoDisplacementMassSoftest);
        return near ? GFMD_SOLVER_FIRE : GFMD_SOLVER_FIRE_MASS;
    }
    if (params_.kind == GFMD_GREEN_LAYER_FLUID) {
        if (quadratic) {
            const double points = static_cast<double>(grid_.real_size());
            const double thickness = shortest_wave_q(grid_) * params_.width;
            const bool thin = thickness < kAutoContinueCgThickness;
            const double f = longest_wave_softness(grid_, body_, params_.e_star);
            const bool thin_soft = thin && points >= kAutoContinueThinPoints && f >= kAutoContinueThinSoftness &&
                                   roughness_thickness() < kAutoContinueThinThickness;
            if (!(points >= kAutoContinueFirePoints || thin_soft) || surface_flat()) return GFMD_SOLVER_CG;
            const bool soft = f >= kAutoContinueCgSoftness;
            if (soft && !thin) return GFMD_SOLVER_CG;  // the middle widths
            const double area = persson_contact_area(params_.sigma0);
            if (!thin) return area < kAutoContinueFireArea ? GFMD_SOLVER_CG : GFMD_SOLVER_FIRE;
            if (newton_takes_load(area)) return GFMD_SOLVER_NEWTON;
            const double mass_area = kAutoContinueMassThicknessArea / thickness;
            if (area < mass_area) return GFMD_SOLVER_FIRE_MASS;
            return area < std::min(2.0 * mass_area, kAutoContinueThinFireArea) ? GFMD_SOLVER_MASS_FIRE
                                                                                : GFMD_SOLVER_FIRE;
        }
        const double thickness = adhesive_thickness();
        if (thickness >= kAutoAdhesiveCgThickness) return GFMD_SOLVER_CG;
        const double area = persson_contact_area(params_.sigma0);
        const bool soft = longest_wave_softness(grid_, body_, params_.e_star) >= kAutoApproachSoftness;
        // The Newton method with its trust region (newton.hpp) on a load from a deformed surface at
        // Persson's A/A0 < kAutoNewtonArea from kAutoNewtonPoints on, the bounds without adhesion.
        // Measured 2026-11-29 (gfmd_bench --sweep --adhesion --columns newton,auto --verbose, one
        // thread, the study's nine continuing loads; log docs/performance_logs/
        // newton_adhesive_2026-11-29.log): at 2048^2 W = 0.088 356.39 s against the default's 614.36
        // s, faster on every load (1.08-2.57x), W = 0.125 to 0.05 236.55 s against 447.43 s; at
        // 1024^2 W = 0.088 and 0.177 76.14 s and 45.59 s against 107.73 s and 67.88 s, every load to
        // 0.12 but one won (0.95x), above 0.15 0.88-1.68x; at 512^2 to 0.05-0.08 (1.01-1.64x), mixed
        // above (0.66-1.32x; the nine loads 1.11x and 1.19x): from 1024^2 on, as without adhesion:
        // to 0.15 then, to kAutoNewtonArea = 0.45 since its passes were vectorized (measured with
        // adhesion too: 1.30-1.68x at 2048^2 and 1.20-2.14x at 1024^2 from 0.18 to 0.4).
        if (soft && !surface_flat() && newton_takes_load(area)) return GFMD_SOLVER_NEWTON;
        if (!soft || !(area < kAutoApproachArea)) return GFMD_SOLVER_FIRE;
        const bool mass = thickness < kAutoMassThinnerThickness || (thickness < kAutoMassThickness && area < kAutoMassArea);
        return mass ? GFMD_SOLVER_FIRE_MASS : GFMD_SOLVER_MASS_FIRE;
    }
    if (!quadratic) return GFMD_SOLVER_CG;  // the adhesive CG (kAutoAdhesiveCgThickness)
    const double bound = (params_.kind == GFMD_GREEN_LAYER_BONDED) ? kAutoCgBoundBonded : kAutoCgBound;
    // (no load: no contact, and Persson's variance, a transform of the substrate, not computed)
    if (!(params_.sigma0 > 0.0)) return GFMD_SOLVER_CG;
    const double area = persson_contact_area(params_.sigma0);
    if (cg_cost <= bound && softness * area < kAutoCgDenseContacts) return GFMD_SOLVER_CG;
    return area * std::sqrt(static_cast<double>(grid_.real_size())) < kAutoCgHalfspaceLowLoad ? GFMD_SOLVER_CG
                                                                                             : GFMD_SOLVER_FIRE;
}

// The adhesive sheets' thickness q_max w (the grid's corner q_max = pi sqrt(2)/a times the
// layer's width) was measured on substrates whose shortest wave lambda_s = 4a, where q_max =
// 2 sqrt(2) q_s; what orders mass weighting against the approach is the width against the
// roughness' shortest wave.  So that rule reads min(q_max, 2 sqrt(2) q_s) w, q_s the substrate's
// (substrate_shortest_wave, within 1e-3 of 2 pi/lambda_s on generated substrates): q_max w on
// those substrates and wherever the substrate is rough down to the grid spacing (lambda_s <= 4a,
// a measured topography), smaller on a smoother substrate.  Found by gfmd_bench --random
// (docs/performance.md "Bodies drawn at random": an adhesive sheet w = 2a at 256^2 on lambda_s =
// 8a, q_max w = 8.9, took the approach's 2.3 s against mass weighting's 0.594 s); a scratch scan
// from flat at 256^2 and 512^2, lambda_s = 2, 4, 8 a, ordered the two by w/lambda_s, not by
// q_max w (its figures in commit 9cf5fc3's message).  The rules without adhesion, measured at
// 2048^2 on the study's substrate alone, keep q_max w.
constexpr double kRuleWaveRatio = 2.0 * 1.4142135623730951;

double Simulation::roughness_thickness() const {
    if (!substrate_q_) substrate_q_ = substrate_shortest_wave(grid_, fields_);
    return kRuleWaveRatio * *substrate_q_ * params_.width;
}

double Simulation::adhesive_thickness() const {
    return std::min(shortest_wave_q(grid_) * params_.width, roughness_thickness());
}

double Simulation::overlap_fraction() const {
    const double *h = fields_.h.data(), mean = params_.mean_z;
    const auto above = grid_.sum_points<1>([&](int64_t i0, int64_t i1, double *acc) {  // every rank: the same answer
        double c = 0.0;
        for (int64_t i = i0; i < i1; ++i) c += (h[i] > mean) ? 1.0 : 0.0;
        acc[0] += c;
    });
    return above[0] / static_cast<double>(grid_.real_size());
}

bool Simulation::newton_takes_load(double area) const {
    return static_cast<double>(grid_.real_size()) >= kAutoNewtonPoints && area < kAutoNewtonArea &&
           newton_refusal(grid_, params_)[0] == '\0';
}

bool Simulation::surface_flat() const {
    const double *z = fields_.z.data();
    const auto m = grid_.max_points<2>([&](int64_t i0, int64_t i1, double *top) {  // every rank: the same answer
        for (int64_t i = i0; i < i1; ++i) {
            top[0] = std::max(top[0], z[i]);
            top[1] = std::max(top[1], -z[i]);
        }
    });
    return !(m[0] + m[1] > 0.0);
}

std::unique_ptr<Solver> Simulation::follow_auto_choice() {
    const int32_t kind = resolve_solver(params_.solver);
    if (kind == active_solver_) return nullptr;
    // make_solver may throw std::bad_alloc (CG's 16 B/pt): then nothing changed
    std::unique_ptr<Solver> replaced = std::exchange(solver_, make_solver(kind, grid_, dynamics_));
    active_solver_ = kind;
    return replaced;
}

void Simulation::set_solver(int32_t solver) {
    require_solver_takes(grid_, params_, solver);
    const int32_t kind = resolve_solver(solver);
    solver_ = make_solver(kind, grid_, dynamics_);  // a new, restarted solver; the old one freed
    active_solver_ = kind;
    params_.solver = solver;
}

void Simulation::set_threads(int threads) { grid_.replan(threads, grid_.planner()); }

void Simulation::set_planner(int32_t planner) { grid_.replan(grid_.threads(), planner); }

void Simulation::reset() {
    // Even a flat surface can overflow: the FFT's rounding leaves modes of order eps * max h,
    // which an extreme E* turns into infinite stresses (a fuzz finding). Undo if so.
    undo_.save(fields_);
    change(
        "resetting the surface",
        [&] {
            fields_.put_flat_at_rest(grid_);
            apply_control();
        },
        [&] { undo_.restore(fields_); });
}

void Simulation::diverged(int64_t step, const std::vector<double> &solver_state) {
    undo_.restore(fields_);
    refresh_forces();
    solver_->set_state(solver_state);
    fail(GFMD_ERR_DIVERGED, "a non-finite value appeared at step " + std::to_string(step) + " (dt = " +
                                num(dynamics_.dt) + ", stability limit 2/omega_max = " +
                                num(2.0 / std::sqrt(body_.k_max + params_.adhesive_stiffness())) +
                                "); the state before the call was restored");
}

void Simulation::step(int64_t nsteps) {
    int64_t taken = 0;
    relax(-1.0, nsteps, taken);  // a residual is never below -1: exactly nsteps steps
}

bool Simulation::relax_from(double tol, int64_t max_steps, int64_t &steps_taken,
                            const std::vector<double> *call_start) {
    if (call_start == nullptr) undo_.save(fields_);
    const std::vector<double> solver_state = call_start ? *call_start : solver_->state();
    StepContext c{grid_, params_, body_, dynamics_, forces_, fields_};
    steps_taken = 0;
    // The forces are evaluated after every step the solver asks the test for, and after the
    // last step of the call (between calls they always describe z); a solver that asks only
    // every few steps is tested only there, so one call and a relax in chunks stop alike.
    while (!solver_->at_check(params_) || forces_.residual > tol) {
        if (steps_taken == max_steps) return false;
        solver_->advance(c);
        apply_control();
        ++steps_taken;
        if (steps_taken == max_steps || solver_->at_check(params_)) {
            refresh_forces();
            if (!forces_.finite()) diverged(steps_taken, solver_state);
        }
    }
    return true;
}

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

bool Simulation::relax_multilevel(double tol, int64_t max_steps, int levels, int64_t &steps_taken,
                                  int64_t &coarse_steps) {
    if (levels < 1) fail(GFMD_ERR_INVALID_ARG, "levels must be >= 1, got " + std::to_string(levels));
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

double Simulation::contact_area() const { return gfmd::contact_area(grid_, forces_); }
double Simulation::mean_gap() const { return gfmd::mean_gap(grid_, fields_); }
void Simulation::heights(double *out) const { std::copy(fields_.h.data(), fields_.h.data() + fields_.h.size(), out); }
void Simulation::gap(double *out) const { gfmd::gap(fields_, out); }
void Simulation::surface(double *out) const { std::copy(fields_.z.data(), fields_.z.data() + fields_.z.size(), out); }
void Simulation::pressure(double *out) const { gfmd::pressure(params_, fields_, out); }
double Simulation::persson_variance() const {
    if (!persson_v_) persson_v_ = gfmd::persson_variance(grid_, body_, fields_);
    return *persson_v_;
}
double Simulation::persson_contact_area(double sigma0) const {
    require_finite(sigma0, "sigma0");
    if (sigma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "sigma0 must be >= 0, got " + num(sigma0));
    return gfmd::persson_contact_area(persson_variance(), sigma0);
}
double Simulation::persson_load(double rel_area) const {
    require_finite(rel_area, "rel_area");
    if (!(rel_area >= 0.0 && rel_area < 1.0))
        fail(GFMD_ERR_INVALID_ARG, "rel_area must be in [0, 1), got " + num(rel_area));
    if (rel_area == 0.0) return 0.0;
    const double variance = persson_variance();
    if (!(variance > 0.0))
        fail(GFMD_ERR_STATE, "the substrate is flat: Persson's A/A0 is 1 under any positive load, never " + num(rel_area));
    return gfmd::persson_load(variance, rel_area);
}

}  // namespace gfmd
