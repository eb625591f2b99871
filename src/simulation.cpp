#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "constraint.hpp"
#include "error.hpp"
#include "observables.hpp"
#include "solver_choice.hpp"
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

// The grid's points a side for the user's n: n, or 2n on the padded cell of free boundaries.
int64_t solved(int64_t n, int32_t boundary) { return boundary == GFMD_BOUNDARY_FREE ? 2 * n : n; }

// nx of the grid solved on, after checking the grid, the boundary and that it fits in memory:
// nothing is allocated or planned before.
int64_t admitted(int64_t nx, int64_t ny, double lx, double ly, const Distribution *dist, int32_t boundary) {
    validate_grid(nx, ny, lx, ly);
    if (boundary != GFMD_BOUNDARY_PERIODIC && boundary != GFMD_BOUNDARY_FREE)
        fail(GFMD_ERR_BAD_ENUM, "unknown boundary " + std::to_string(boundary));
    if (boundary == GFMD_BOUNDARY_FREE) {
        if (dist != nullptr)
            fail(GFMD_ERR_STATE, "free boundaries on a handle distributed over ranks are not supported");
        if (nx > INT64_MAX / 4 / ny) fail(GFMD_ERR_INVALID_ARG, "the padded grid 2nx x 2ny overflows int64_t");
        validate_grid(2 * nx, 2 * ny, 2.0 * lx, 2.0 * ly);
    }
    if (dist == nullptr) check_memory(solved(nx, boundary), solved(ny, boundary));
    return solved(nx, boundary);
}

Params with_boundary_param(int32_t boundary) {
    Params p;
    p.boundary = boundary;
    return p;
}

// The body of parameters p on the grid solved on.
Body body_of(const FftGrid &grid, const Params &p) {
    if (p.boundary == GFMD_BOUNDARY_FREE) return make_free_body(grid, p.e_star);
    return make_body(grid, p.kind, p.width, p.e_star, p.nu);
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

// The solvers that step with the yielding wall of plasticity.hpp: those that see the wall only
// through fields.h and the force only through fields.f and the sums of the force evaluation.
bool takes_plasticity(int32_t solver) {
    return solver == GFMD_SOLVER_FIRE || solver == GFMD_SOLVER_VERLET || solver == GFMD_SOLVER_AUTO;
}

// The solvers that step on the padded cell of free boundaries: those that see the body only
// through its mode stiffness (the mass-weighted family's masses and the Newton method's sheet
// model assume a periodic body's spectrum).
constexpr const char *kFreeSolvers =
    "with free boundaries the solver must be GFMD_SOLVER_CG, GFMD_SOLVER_FIRE, GFMD_SOLVER_VERLET or "
    "GFMD_SOLVER_AUTO (which takes CG)";
bool takes_free_boundaries(int32_t solver) {
    return solver == GFMD_SOLVER_CG || solver == GFMD_SOLVER_FIRE || solver == GFMD_SOLVER_VERLET ||
           solver == GFMD_SOLVER_AUTO;
}

// GFMD_ERR_STATE if the solver set (or kept) by the caller would run p and cannot: GFMD_SOLVER_CG,
// or GFMD_SOLVER_NEWTON (newton.hpp: a thin sheet without adhesion under pressure control, on a
// grid its cycle takes).
void require_solver_takes(const FftGrid &grid, const Params &p, int32_t solver) {
    if (solver == GFMD_SOLVER_CG && !cg_takes(p))
        fail(GFMD_ERR_STATE,
             "the CG solver takes adhesion under pressure control only; under displacement control with "
             "adhesion choose GFMD_SOLVER_FIRE, GFMD_SOLVER_MASS_WEIGHTED_FIRE, GFMD_SOLVER_VERLET or GFMD_SOLVER_AUTO");
    if (std::isfinite(p.hardness) && !takes_plasticity(solver))
        fail(GFMD_ERR_STATE, "with a hardness (plasticity) the solver must be GFMD_SOLVER_FIRE, GFMD_SOLVER_VERLET or "
                             "GFMD_SOLVER_AUTO (which takes FIRE); switch the hardness off (+infinity) first");
    if (p.boundary == GFMD_BOUNDARY_FREE && !takes_free_boundaries(solver))
        fail(GFMD_ERR_STATE, kFreeSolvers);
    if (solver == GFMD_SOLVER_NEWTON) {
        const std::string why = newton_refusal(grid, p);
        if (!why.empty()) fail(GFMD_ERR_STATE, why + "; choose another solver or GFMD_SOLVER_AUTO");
    }
}
}  // namespace

Simulation::Simulation(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner,
                       const Distribution *dist, int32_t boundary)
    : grid_(admitted(nx, ny, lx, ly, dist, boundary), solved(ny, boundary), solved(1, boundary) * lx,
            solved(1, boundary) * ly, threads, planner, dist),
      params_(with_boundary_param(boundary)),
      body_(body_of(grid_, params_)),
      dynamics_(dynamics_for(params_, body_)),
      fields_(grid_),
      undo_(grid_),
      rx_(nx),
      ry_(ny),
      active_solver_(resolve_solver(params_.solver)),
      solver_(make_solver(active_solver_, grid_, dynamics_)) {
    if (free()) {
        RealBuffer flat(static_cast<std::size_t>(points()));
        std::fill(flat.data(), flat.data() + flat.size(), 0.0);
        fields_.h = padded_substrate(flat.data(), params_.rho);
    }
    fields_.put_flat_at_rest(grid_);
    refresh_forces();
}

std::unique_ptr<Simulation> Simulation::clone() const {
    auto c = std::make_unique<Simulation>(nx(), ny(), lx(), ly(), grid_.threads(), grid_.planner(),
                                          grid_.distribution(), params_.boundary);
    c->params_ = params_;
    c->body_.stiffness = copy_of(body_.stiffness);
    c->body_.k_min = body_.k_min;
    c->body_.k_max = body_.k_max;
    c->body_.compliance0 = body_.compliance0;
    c->dynamics_ = dynamics_;
    c->persson_v_ = persson_v_;
    c->substrate_q_ = substrate_q_;
    c->fields_.h = copy_of(fields_.h);
    c->fields_.z = copy_of(fields_.z);
    c->fields_.v = copy_of(fields_.v);
    c->active_solver_ = active_solver_;
    c->solver_ = solver_->clone();
    if (plastic_) c->plastic_ = std::make_unique<Plasticity>(*plastic_);
    c->refresh_forces();
    return c;
}

void Simulation::refresh_forces() {
    if (plastic_) settle(grid_, *plastic_, fields_);
    forces_ = evaluate_forces(grid_, params_, body_, fields_);
    if (plastic_) yield(grid_, params_, *plastic_, fields_, forces_);
}

void Simulation::commit_plastic_step() {
    if (!plastic_) return;
    commit(grid_, *plastic_, fields_);
    persson_v_.reset();  // functions of the substrate, which has flattened
    substrate_q_.reset();
    refresh_forces();
}

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
    Body b = body_of(grid_, p);
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
    if (kind != GFMD_GREEN_HALFSPACE && free())
        fail(GFMD_ERR_STATE, "free boundaries are for the half-space only (a layer's free-space Green's function is "
                             "not implemented): set GFMD_BOUNDARY_PERIODIC first");
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
    // with hardness the new substrate is also the new step's (8 B/pt more for this call)
    RealBuffer hs(plastic_ ? h.size() : 0);
    std::copy(h.data(), h.data() + hs.size(), hs.data());
    double volume = 0.0;
    const auto swap_plastic = [&] {
        if (!plastic_) return;
        std::swap(plastic_->substrate, hs);
        std::swap(plastic_->committed_volume, volume);
    };
    undo_.save(fields_);
    change(
        "this substrate",
        [&] {
            std::swap(fields_.h, h);
            swap_plastic();
            persson_v_.reset();
            substrate_q_.reset();
            fields_.put_flat_at_rest(grid_);
            apply_control();
        },
        [&] {
            std::swap(fields_.h, h);
            swap_plastic();
            persson_v_.reset();
            substrate_q_.reset();
            undo_.restore(fields_);
        });
}

void Simulation::set_heights(const double *h) {
    const int64_t n = free() ? points() : grid_.local_points();
    grid_.on_all_ranks([&] {
        for (int64_t i = 0; i < n; ++i)
            if (!std::isfinite(h[i]) || std::fabs(h[i]) > kMaxHeight)
                fail(GFMD_ERR_INVALID_ARG, "height " + std::to_string(i + grid_.first_row() * grid_.nx()) + " = " +
                                               num(h[i]) + " is not finite or exceeds 1e100 in magnitude");
    });
    if (free()) return change_substrate(padded_substrate(h, params_.rho));
    RealBuffer nh;  // the new substrate, 8 B/pt for this call, allocated on every rank or none
    grid_.on_all_ranks([&] { nh = RealBuffer(static_cast<std::size_t>(n)); });
    std::copy(h, h + n, nh.data());
    change_substrate(std::move(nh));
}

// With free boundaries the surface is drawn on the padded cell, a periodic surface twice the
// region's size each way, and the region keeps its part, its highest point moved to zero: a
// non-periodic patch of a larger surface, as a measurement is.
void Simulation::generate_selfaffine(const SelfAffineParams &p) {
    validate_selfaffine(grid_, p);
    RealBuffer nh;  // the new substrate, 8 B/pt for this call, allocated on every rank or none
    grid_.on_all_ranks([&] { nh = RealBuffer(static_cast<std::size_t>(grid_.local_points())); });
    gfmd::generate_selfaffine(grid_, p, fields_.work.data(), nh.data());
    if (free()) {
        RealBuffer region(static_cast<std::size_t>(points()));
        crop(nh.data(), region.data());
        const double top = *std::max_element(region.data(), region.data() + region.size());
        for (std::size_t i = 0; i < region.size(); ++i) region[i] -= top;
        return change_substrate(padded_substrate(region.data(), params_.rho));
    }
    change_substrate(std::move(nh));
}

void Simulation::crop(const double *field, double *out) const {
    for (int64_t y = 0; y < ry_; ++y) std::copy(field + at(0, y), field + at(0, y) + rx_, out + y * rx_);
}

// The surface of a body pressed onto the region stays above the region's lowest point but for the
// discretization (the maximum principle of the Boussinesq potential: the displacement outside the
// loaded set is below its largest value on it): a depth of twice the region's height range, plus
// its size and 1000 adhesive ranges (the adhesive stress there is exp(-1000) = 0), clears it.
RealBuffer Simulation::padded_substrate(const double *h, double rho) const {
    RealBuffer nh(static_cast<std::size_t>(grid_.local_points()));
    double lo = h[0], hi = h[0];
    for (int64_t i = 0; i < points(); ++i) {
        lo = std::min(lo, h[i]);
        hi = std::max(hi, h[i]);
    }
    const double depth = 2.0 * (hi - lo) + lx() + ly() + 1000.0 * rho;
    const double pad = lo - depth;
    if (!std::isfinite(pad) || std::fabs(pad) > kMaxHeight)
        fail(GFMD_ERR_RANGE, "the padding below this substrate exceeds 1e100 in magnitude");
    std::fill(nh.data(), nh.data() + nh.size(), pad);
    for (int64_t y = 0; y < ry_; ++y) std::copy(h + y * rx_, h + (y + 1) * rx_, nh.data() + at(0, y));
    return nh;
}

void Simulation::require_periodic(const char *what) const {
    if (free())
        fail(GFMD_ERR_STATE, std::string(what) + " is not supported with free boundaries: set GFMD_BOUNDARY_PERIODIC first");
}

void Simulation::set_pressure(double sigma0) {
    require_finite(sigma0, "sigma0");
    if (sigma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "sigma0 must be >= 0, got " + num(sigma0));
    const Params old = params_;
    change(
        "sigma0",
        [&] {
            params_.sigma0 = sigma0 * load_fraction();  // exact: a power of 2
            params_.control = kPressureControl;
        },
        [&] { params_ = old; });    commit_plastic_step();
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
    require_periodic("displacement control");
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
        });    commit_plastic_step();
}

double Simulation::mean_displacement() const {
    const double mean = grid_.mean(fields_.z.data());
    return free() ? mean - params_.sigma0 * body_.compliance0 : mean;
}

double Simulation::elastic_energy() const {
    if (!free()) return forces_.u_el;
    // the uniform mode of the padded cell's pressure, sigma0 (the padded cell's) at every point,
    // holds (1/2) a^2 K(0) sigma0^2 N of the energy once the contacts carry the load
    const double s = params_.sigma0;
    return forces_.u_el + 0.5 * grid_.area_per_point() * body_.compliance0 * s * s * static_cast<double>(grid_.real_size());
}

void Simulation::set_adhesion(double gamma0, double rho) {
    require_finite(gamma0, "gamma0");
    require_finite(rho, "rho");
    if (gamma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "gamma0 must be >= 0, got " + num(gamma0));
    if (rho <= 0.0) fail(GFMD_ERR_INVALID_ARG, "rho must be > 0, got " + num(rho));
    if (!std::isfinite(gamma0 / (rho * rho)) || !std::isfinite(gamma0 / rho))
        fail(GFMD_ERR_RANGE, "the adhesive stiffness gamma0/rho^2 overflows");
    if (gamma0 > 0.0 && plastic_)
        fail(GFMD_ERR_STATE, "adhesion with a hardness (plasticity) is not supported: switch the hardness off first");
    Params asked = params_;
    asked.gamma0 = gamma0;
    require_solver_takes(grid_, asked, params_.solver);
    const Params old = params_;
    const Dynamics old_dynamics = dynamics_;
    // free boundaries: the padding sinks further if the new range needs it (never rises: the
    // surface stays above it)
    RealBuffer deeper;
    if (free()) {
        RealBuffer region(static_cast<std::size_t>(points()));
        crop(fields_.h.data(), region.data());
        deeper = padded_substrate(region.data(), rho);
        if (!(deeper[at(rx_, ry_)] < fields_.h[at(rx_, ry_)])) deeper = RealBuffer();
    }
    const auto swap_padding = [&] {
        if (deeper.size() > 0) std::swap(fields_.h, deeper);
    };
    change(
        "this adhesion",
        [&] {
            params_.gamma0 = gamma0;
            params_.rho = rho;
            dynamics_ = dynamics_for(params_, body_);
            swap_padding();
        },
        [&] {
            params_ = old;
            dynamics_ = old_dynamics;
            swap_padding();
        });
}

void Simulation::set_hardness(double hardness) {
    if (!(hardness > 0.0))
        fail(GFMD_ERR_INVALID_ARG, "the hardness must be > 0 (+infinity: no plasticity), got " + num(hardness));
    const bool on = std::isfinite(hardness);
    if (on) require_periodic("plasticity");
    if (on && grid_.ranks() > 1)
        fail(GFMD_ERR_STATE, "plasticity on a handle distributed over several ranks is not supported");
    if (on && params_.gamma0 > 0.0)
        fail(GFMD_ERR_STATE, "a hardness (plasticity) with adhesion is not supported: switch adhesion off first");
    Params asked = params_;
    asked.hardness = hardness;
    require_solver_takes(grid_, asked, params_.solver);
    if (on && plastic_) {  // a new hardness: the step made at the old one stands
        commit(grid_, *plastic_, fields_);
        persson_v_.reset();
        substrate_q_.reset();
        params_.hardness = hardness;
        refresh_forces();
        solver_->restart(dynamics_);
        return;
    }
    // on: the substrate now is the first step's; off: the substrate keeps its flattened shape
    std::unique_ptr<Plasticity> other;
    if (on) {
        check_memory(grid_.nx(), grid_.ny(), 9.0);
        other = std::make_unique<Plasticity>(grid_, fields_.h);
    }
    const Params old = params_;
    change(
        "this hardness",
        [&] {
            params_.hardness = hardness;
            std::swap(plastic_, other);
            persson_v_.reset();  // off: the flattened substrate is the substrate
            substrate_q_.reset();
        },
        [&] {
            params_ = old;
            std::swap(plastic_, other);
            persson_v_.reset();
            substrate_q_.reset();
        });
}

double Simulation::plastic_area() const {
    if (!plastic_) return 0.0;
    return static_cast<double>(plastic_->yielding_points) / static_cast<double>(grid_.real_size());
}

double Simulation::plastic_volume() const { return plastic_ ? gfmd::plastic_volume(grid_, *plastic_, fields_) : 0.0; }

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

int32_t Simulation::resolve_solver(int32_t requested) const {
    return requested == GFMD_SOLVER_AUTO ? choose_solver(choice_features()) : requested;
}

ChoiceFeatures Simulation::choice_features() const {
    ChoiceFeatures f;
    f.free_boundary = free();
    if (f.free_boundary) return f;  // the rule reads nothing else (solver_choice.cpp)
    f.body = params_.kind;
    f.adhesive = params_.gamma0 > 0.0;
    f.plastic = std::isfinite(params_.hardness);
    f.pressure_control = params_.control == kPressureControl;
    f.points = static_cast<double>(grid_.real_size());
    f.softness = long_wave_softness(grid_, body_, params_.e_star);
    f.longest_wave = longest_wave_softness(grid_, body_, params_.e_star);
    if (params_.kind == GFMD_GREEN_LAYER_FLUID) {  // what only the fluid layers' rules read
        f.flat = surface_flat();
        f.grid_thickness = shortest_wave_q(grid_) * params_.width;
        f.rough_thickness = roughness_thickness();
        f.newton_grid = *newton_grid_refusal(grid_) == '\0';
    }
    // (without load no contact, and Persson's variance, a transform of the substrate, not computed)
    if (f.pressure_control && params_.sigma0 > 0.0) f.persson_area = persson_contact_area(params_.sigma0);
    if (!f.pressure_control) f.overlap = overlap_fraction();
    return f;
}

// The shortest wave that matters to the adhesive sheets' rule: the grid's corner q_max = pi sqrt(2)/a
// where the substrate is rough down to lambda_s = 4a (q_max = 2 sqrt(2) q_s), smaller on a smoother one.
constexpr double kRuleWaveRatio = 2.0 * 1.4142135623730951;

double Simulation::roughness_thickness() const {
    if (!substrate_q_) substrate_q_ = substrate_shortest_wave(grid_, fields_, step_substrate());
    return kRuleWaveRatio * *substrate_q_ * params_.width;
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
    // make_solver may throw std::bad_alloc (CG's 16 B/pt): then nothing changed, on every rank
    std::unique_ptr<Solver> made;
    grid_.on_all_ranks([&] { made = make_solver(kind, grid_, dynamics_); });
    std::unique_ptr<Solver> replaced = std::exchange(solver_, std::move(made));
    active_solver_ = kind;
    return replaced;
}

void Simulation::set_solver(int32_t solver) {
    require_solver_takes(grid_, params_, solver);
    const int32_t kind = resolve_solver(solver);
    // a new, restarted solver, made on every rank or on none (its memory), then the old one freed
    std::unique_ptr<Solver> made;
    grid_.on_all_ranks([&] { made = make_solver(kind, grid_, dynamics_); });
    solver_ = std::move(made);
    active_solver_ = kind;
    params_.solver = solver;
}

std::unique_ptr<Simulation> Simulation::with_boundary(int32_t boundary) const {
    if (boundary == GFMD_BOUNDARY_FREE) {
        if (grid_.distribution() != nullptr)
            fail(GFMD_ERR_STATE, "free boundaries on a handle distributed over ranks are not supported");
        if (params_.kind != GFMD_GREEN_HALFSPACE)
            fail(GFMD_ERR_STATE, "free boundaries are for the half-space only (a layer's free-space Green's function "
                                 "is not implemented): set GFMD_GREEN_HALFSPACE first");
        if (params_.control == kDisplacementControl)
            fail(GFMD_ERR_STATE, "free boundaries take a prescribed pressure only: set a pressure first");
        if (std::isfinite(params_.hardness))
            fail(GFMD_ERR_STATE, "plasticity is not supported with free boundaries: switch the hardness off first");
        if (!takes_free_boundaries(params_.solver)) fail(GFMD_ERR_STATE, kFreeSolvers);
    }
    std::vector<double> h(static_cast<std::size_t>(points()));
    heights(h.data());
    auto s = std::make_unique<Simulation>(nx(), ny(), lx(), ly(), grid_.threads(), grid_.planner(),
                                          grid_.distribution(), boundary);
    if (!std::isnan(params_.nu)) s->set_poisson(params_.nu);
    s->set_modulus(params_.e_star);
    s->set_green(params_.kind, params_.width);
    s->set_adhesion(params_.gamma0, params_.rho);
    s->set_timestep(params_.dt_user);
    s->set_damping(params_.eta_user);
    s->set_solver(params_.solver);
    if (std::isfinite(params_.hardness)) s->set_hardness(params_.hardness);
    s->set_heights(h.data());
    if (params_.control == kDisplacementControl)
        s->set_mean_displacement(params_.mean_z);
    else
        s->set_pressure(params_.sigma0 / load_fraction());
    return s;
}

void Simulation::set_threads(int threads) { grid_.replan(threads, grid_.planner()); }

void Simulation::set_planner(int32_t planner) { grid_.replan(grid_.threads(), planner); }

void Simulation::reset() {
    // Even a flat surface can overflow: the FFT's rounding leaves modes of order eps * max h,
    // which an extreme E* turns into infinite stresses (a fuzz finding). Undo if so.
    // with hardness the substrate keeps the shape the body pressed into it
    if (plastic_) {
        commit(grid_, *plastic_, fields_);
        persson_v_.reset();
        substrate_q_.reset();
    }
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
    // The Newton method from a flat surface starts on coarser grids (newton_start_levels), before
    // its first step: a function of the state alone, so that a call in chunks, gfmd_step and one
    // call share the trajectory.
    bool started = call_start != nullptr;
    // The forces are evaluated after every step the solver asks the test for, and after the
    // last step of the call (between calls they always describe z); a solver that asks only
    // every few steps is tested only there, so one call and a relax in chunks stop alike.
    while (!solver_->at_check(params_) || forces_.residual > tol) {
        if (steps_taken == max_steps) return false;
        if (!started) {
            started = true;
            const int levels = newton_start_levels();
            int64_t coarse = 0;
            if (levels > 1) coarse_start(kNewtonStartTol, kNewtonStartSteps, levels, coarse);
        }
        if (plastic_) release(grid_, params_, *plastic_, fields_);
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

// With free boundaries the observables are the region's, its fields cropped.  Its contacts are
// counted in the region: the padding lies far below the surface, but a diverging run (a step too
// long for the body) can drive the surface through it, and the padded cell's count over the
// region's points then exceeded 1.
double Simulation::contact_area() const {
    if (!free()) return gfmd::contact_area(grid_, forces_);
    int64_t touching = 0;
    for (int64_t y = 0; y < ry_; ++y)
        for (int64_t x = 0; x < rx_; ++x) touching += fields_.z[at(x, y)] - fields_.h[at(x, y)] <= 0.0 ? 1 : 0;
    return static_cast<double>(touching) / static_cast<double>(points());
}
double Simulation::mean_gap() const {
    if (!free()) return gfmd::mean_gap(grid_, fields_);
    double sum = 0.0;
    for (int64_t y = 0; y < ry_; ++y)
        for (int64_t x = 0; x < rx_; ++x) sum += fields_.z[at(x, y)] - fields_.h[at(x, y)];
    return sum / static_cast<double>(points());
}
void Simulation::heights(double *out) const {
    if (free()) return crop(fields_.h.data(), out);
    std::copy(fields_.h.data(), fields_.h.data() + fields_.h.size(), out);
}
void Simulation::gap(double *out) const {
    if (!free()) return gfmd::gap(fields_, out);
    for (int64_t y = 0; y < ry_; ++y)
        for (int64_t x = 0; x < rx_; ++x) out[y * rx_ + x] = fields_.z[at(x, y)] - fields_.h[at(x, y)];
}
void Simulation::surface(double *out) const {
    if (free()) return crop(fields_.z.data(), out);
    std::copy(fields_.z.data(), fields_.z.data() + fields_.z.size(), out);
}
void Simulation::pressure(double *out) const {
    if (free()) {  // no hardness here (refused with free boundaries)
        std::vector<double> all(fields_.z.size());
        gfmd::pressure(params_, fields_, all.data());
        return crop(all.data(), out);
    }
    gfmd::pressure(params_, fields_, out);
    if (!plastic_ || plastic_->yielding_points == 0) return;
    for (std::size_t i = 0; i < fields_.z.size(); ++i)
        if (plastic_->yielding[i] != 0) out[i] = params_.hardness;  // the yielding substrate's pressure
}
void Simulation::contact_set(unsigned char *out) const {
    if (free()) {
        for (int64_t y = 0; y < ry_; ++y)
            for (int64_t x = 0; x < rx_; ++x) out[y * rx_ + x] = fields_.z[at(x, y)] <= fields_.h[at(x, y)] ? 1 : 0;
        return;
    }
    for (std::size_t i = 0; i < fields_.z.size(); ++i) out[i] = fields_.z[i] <= fields_.h[i] ? 1 : 0;
}
double Simulation::persson_variance() const {
    if (free())
        fail(GFMD_ERR_STATE, "Persson's theory of a simulation is that of its periodic cell: with free boundaries "
                             "evaluate it from the scan's spectrum (gfmd_topo_persson_contact_area)");
    if (!persson_v_) persson_v_ = gfmd::persson_variance(grid_, body_, fields_, step_substrate());
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
