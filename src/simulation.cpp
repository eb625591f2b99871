#include "simulation.hpp"

#include <algorithm>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "error.hpp"
#include "green.hpp"
#include "parallel.hpp"

namespace gfmd {

namespace {

// Automatic dynamics: dt = kDtFactor / omega_max (Verlet is stable up to 2/omega_max; 1 leaves
// room for the hard-wall collisions and the adhesive nonlinearity), damping eta = 2 kZeta
// omega_min: the slowest elastic mode slightly underdamped, every faster mode underdamped and
// decaying at the same rate eta/2.
constexpr double kDtFactor = 1.0;
constexpr double kZeta = 0.9;

// FIRE parameters (Bitzek et al. 2006; Guenole et al., Comput. Mater. Sci. 175, 109584 (2020)):
// the time step grows by kFireInc after kFireDelay downhill steps up to kFireDtMax/omega_max and is
// halved on an uphill step; the velocity mixing starts at kFireAlpha0 and decays by kFireAlphaDec.
constexpr double kFireDtMax = 1.0;
constexpr double kFireDtStart = 0.5;
constexpr double kFireInc = 1.1, kFireDec = 0.5;
constexpr double kFireAlpha0 = 0.1, kFireAlphaDec = 0.99;
constexpr int64_t kFireDelay = 5;

// Mass-weighted FIRE: the mass floor is the stiffness at kMassSpacing times the wave vector of the
// contact points' mean spacing (1 was best of 0.25 ... 4, docs/performance.md).
constexpr double kMassSpacing = 1.0;

std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

void require_finite(double x, const char *name) {
    if (!std::isfinite(x)) fail(GFMD_ERR_INVALID_ARG, std::string(name) + " must be finite, got " + num(x));
}

// "All cores": the machine's cores, unless the user limited OpenMP (OMP_NUM_THREADS), e.g. to
// run one process per core.
int all_cores() {
    const int n = omp_get_max_threads();
    return n > 0 ? n : 1;
}

}  // namespace

Simulation::Simulation(int64_t nx, int64_t ny, double lx, double ly)
    : Simulation(nx, ny, lx, ly, 0, GFMD_PLANNER_MEASURE) {}

Simulation::Simulation(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner)
    : threads_(threads > 0 ? threads : all_cores()),
      planner_(planner),
      grid_(nx, ny, lx, ly, threads_, planner_),
      n_(nx * ny),
      rows_per_block_(std::max<int64_t>(1, kBlock / (nx / 2 + 1))),
      area_per_point_(lx * ly / static_cast<double>(nx * ny)),
      nu_(std::numeric_limits<double>::quiet_NaN()),
      h_(static_cast<std::size_t>(n_)),
      z_(static_cast<std::size_t>(n_)),
      v_(static_cast<std::size_t>(n_)),
      f_(static_cast<std::size_t>(n_)),
      work_(static_cast<std::size_t>(grid_.complex_size())),
      saved_z_(static_cast<std::size_t>(n_)),
      saved_v_(static_cast<std::size_t>(n_)),
      sums_(static_cast<std::size_t>(6 * std::max(block_count(n_, kBlock), block_count(ny, rows_per_block_)))) {
    adopt_stiffness(stiffness_for(kind_, width_, e_star_, nu_));
    reset();
}

std::unique_ptr<Simulation> Simulation::clone() const {
    // planned once, with this handle's threads and planner
    auto c = std::unique_ptr<Simulation>(
        new Simulation(grid_.nx(), grid_.ny(), grid_.lx(), grid_.ly(), threads_, planner_));
    auto copy = [](const RealBuffer &from, RealBuffer &to) { std::copy(from.data(), from.data() + from.size(), to.data()); };
    c->e_star_ = e_star_;
    c->kind_ = kind_;
    c->width_ = width_;
    c->nu_ = nu_;
    c->sigma0_ = sigma0_;
    c->gamma0_ = gamma0_;
    c->rho_ = rho_;
    c->dt_user_ = dt_user_;
    c->eta_user_ = eta_user_;
    c->solver_ = solver_;
    if (solver_ == GFMD_SOLVER_FIRE_MASS) c->held_ = ByteBuffer(static_cast<std::size_t>(n_));
    copy(stiff_, c->stiff_);
    c->k_min_ = k_min_;
    c->k_max_ = k_max_;
    c->update_dynamics();
    copy(h_, c->h_);
    copy(z_, c->z_);
    copy(v_, c->v_);
    c->evaluate_forces();
    c->fire_dt_ = fire_dt_;
    c->fire_alpha_ = fire_alpha_;
    c->fire_positive_ = fire_positive_;
    return c;
}

RealBuffer Simulation::stiffness_for(int32_t kind, double width, double e_star, double nu) const {
    RealBuffer k(static_cast<std::size_t>(grid_.complex_size()));
    const int64_t nxh = grid_.nxh();
    for (int64_t ky = 0; ky < grid_.ny(); ++ky) {
        const double qy = grid_.qy(ky);
        for (int64_t kx = 0; kx < nxh; ++kx) {
            const double qx = grid_.qx(kx);
            const double q = std::sqrt(qx * qx + qy * qy);
            double kq = 0.0;  // the uniform mode has no elastic stiffness: force balance sets it
            if (q > 0.0) {
                const double g = (kind == GFMD_GREEN_HALFSPACE) ? 1.0 : green_inverse_factor(kind, q * width, nu);
                kq = 0.5 * q * e_star * g;  // 1/G(q) = q E* / (2 f(q w))
                if (!std::isfinite(kq))
                    fail(GFMD_ERR_RANGE, "the stiffness 1/G(q) overflows at q w = " + num(q * width) +
                                             ": the layer is too thin or too stiff for this grid");
            }
            k[static_cast<std::size_t>(ky * nxh + kx)] = kq;
        }
    }
    return k;
}

void Simulation::adopt_stiffness(RealBuffer &&k) {
    stiff_ = std::move(k);
    k_min_ = std::numeric_limits<double>::infinity();
    k_max_ = 0.0;
    for (std::size_t c = 1; c < stiff_.size(); ++c) {
        if (stiff_[c] > 0.0) k_min_ = std::min(k_min_, stiff_[c]);
        k_max_ = std::max(k_max_, stiff_[c]);
    }
    if (k_max_ == 0.0) {  // a single grid point, or every mode underflowed: use the cell's scale
        k_max_ = e_star_ * 3.141592653589793 / std::sqrt(grid_.cell_area());
        k_min_ = k_max_;
    }
    update_dynamics();
}

double Simulation::adhesive_stiffness() const { return (gamma0_ > 0.0) ? gamma0_ / (rho_ * rho_) : 0.0; }

bool Simulation::state_finite() const {
    return std::isfinite(u_el_) && std::isfinite(u_ad_) && std::isfinite(residual_);
}

void Simulation::update_dynamics() {
    dt_ = (dt_user_ > 0.0) ? dt_user_ : kDtFactor / std::sqrt(k_max_ + adhesive_stiffness());
    eta_ = (eta_user_ > 0.0) ? eta_user_ : 2.0 * kZeta * std::sqrt(k_min_);
    restart_fire();
}

// Applies a change, then checks that the forces and energies of the new state are finite; if
// they overflow (extreme but individually valid values, e.g. E* = 1e300 with unit heights), the
// change is undone and the call fails with nothing changed.
template <class Apply, class Undo>
void Simulation::change(const char *what, Apply &&apply, Undo &&undo) {
    apply();
    evaluate_forces();
    if (state_finite()) return;
    undo();
    evaluate_forces();
    fail(GFMD_ERR_RANGE, std::string(what) + " would make the forces or energies overflow double precision; "
                                             "nothing was changed");
}

// A new Green's function, modulus or Poisson ratio: new stiffness, kept only if finite.
void Simulation::change_body(const char *what, int32_t kind, double width, double e_star, double nu) {
    RealBuffer k = stiffness_for(kind, width, e_star, nu);
    RealBuffer old;
    const int32_t old_kind = kind_;
    const double old_width = width_, old_e = e_star_, old_nu = nu_;
    change(
        what,
        [&] {
            old = std::move(stiff_);
            kind_ = kind;
            width_ = width;
            e_star_ = e_star;
            nu_ = nu;
            adopt_stiffness(std::move(k));
        },
        [&] {
            kind_ = old_kind;
            width_ = old_width;
            e_star_ = old_e;
            nu_ = old_nu;
            adopt_stiffness(std::move(old));
        });
}

void Simulation::set_modulus(double e_star) {
    require_finite(e_star, "E*");
    if (e_star <= 0.0) fail(GFMD_ERR_INVALID_ARG, "E* must be > 0, got " + num(e_star));
    change_body("E*", kind_, width_, e_star, nu_);
}

void Simulation::set_green(int32_t kind, double width) {
    if (kind != GFMD_GREEN_HALFSPACE && kind != GFMD_GREEN_LAYER_FLUID && kind != GFMD_GREEN_LAYER_BONDED)
        fail(GFMD_ERR_BAD_ENUM, "unknown Green's function kind " + std::to_string(kind));
    if (kind == GFMD_GREEN_HALFSPACE) {
        width = 0.0;
    } else {
        require_finite(width, "layer width");
        if (width <= 0.0) fail(GFMD_ERR_INVALID_ARG, "layer width must be > 0, got " + num(width));
    }
    if (kind == GFMD_GREEN_LAYER_BONDED && std::isnan(nu_))
        fail(GFMD_ERR_STATE, "the bonded layer needs Poisson's ratio: call gfmd_set_poisson first");
    change_body("this Green's function", kind, width, e_star_, nu_);
}

void Simulation::set_poisson(double nu) {
    require_finite(nu, "Poisson's ratio");
    if (nu <= -1.0 || nu > 0.5) fail(GFMD_ERR_INVALID_ARG, "Poisson's ratio must be in (-1, 0.5], got " + num(nu));
    if (kind_ == GFMD_GREEN_LAYER_BONDED)
        change_body("this Poisson ratio", kind_, width_, e_star_, nu);
    else
        nu_ = nu;
}

// A new substrate resets the body; the old substrate, surface and velocities are kept in the
// scratch buffers (the force buffer is recomputed anyway) until the new state is known finite.
template <class Fill>
void Simulation::change_substrate(Fill &&fill) {
    change(
        "this substrate",
        [&] {
            std::copy(h_.data(), h_.data() + n_, saved_z_.data());
            std::copy(z_.data(), z_.data() + n_, saved_v_.data());
            std::copy(v_.data(), v_.data() + n_, f_.data());
            fill();
            put_flat_at_rest();
        },
        [&] {
            std::copy(saved_z_.data(), saved_z_.data() + n_, h_.data());
            std::copy(saved_v_.data(), saved_v_.data() + n_, z_.data());
            std::copy(f_.data(), f_.data() + n_, v_.data());
        });
}

// The body flat at the highest substrate point, at rest (new substrate, reset).
void Simulation::put_flat_at_rest() {
    const double top = *std::max_element(h_.data(), h_.data() + n_);
    std::fill(z_.data(), z_.data() + n_, top);
    std::fill(v_.data(), v_.data() + n_, 0.0);
}

void Simulation::set_heights(const double *h) {
    for (int64_t i = 0; i < n_; ++i)
        if (!std::isfinite(h[i]) || std::fabs(h[i]) > kMaxHeight)
            fail(GFMD_ERR_INVALID_ARG, "height " + std::to_string(i) + " = " + num(h[i]) +
                                           " is not finite or exceeds 1e100 in magnitude");
    change_substrate([&] { std::copy(h, h + n_, h_.data()); });
}

void Simulation::generate_selfaffine(const SelfAffineParams &p) {
    validate_selfaffine(grid_, p);  // before h_ is overwritten
    change_substrate([&] { gfmd::generate_selfaffine(grid_, p, work_.data(), h_.data()); });
}

void Simulation::set_pressure(double sigma0) {
    require_finite(sigma0, "sigma0");
    if (sigma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "sigma0 must be >= 0, got " + num(sigma0));
    const double old = sigma0_;
    change("sigma0", [&] { sigma0_ = sigma0; }, [&] { sigma0_ = old; });
}

void Simulation::set_adhesion(double gamma0, double rho) {
    require_finite(gamma0, "gamma0");
    require_finite(rho, "rho");
    if (gamma0 < 0.0) fail(GFMD_ERR_INVALID_ARG, "gamma0 must be >= 0, got " + num(gamma0));
    if (rho <= 0.0) fail(GFMD_ERR_INVALID_ARG, "rho must be > 0, got " + num(rho));
    const double k_adh = gamma0 / (rho * rho);
    if (!std::isfinite(k_adh) || !std::isfinite(gamma0 / rho))
        fail(GFMD_ERR_RANGE, "the adhesive stiffness gamma0/rho^2 overflows");
    const double old_gamma0 = gamma0_, old_rho = rho_;
    change(
        "this adhesion",
        [&] {
            gamma0_ = gamma0;
            rho_ = rho;
            update_dynamics();
        },
        [&] {
            gamma0_ = old_gamma0;
            rho_ = old_rho;
            update_dynamics();
        });
}

void Simulation::set_timestep(double dt) {
    require_finite(dt, "dt");
    if (dt < 0.0) fail(GFMD_ERR_INVALID_ARG, "dt must be >= 0 (0 = automatic), got " + num(dt));
    dt_user_ = dt;
    update_dynamics();
}

void Simulation::set_damping(double eta) {
    require_finite(eta, "damping");
    if (eta < 0.0) fail(GFMD_ERR_INVALID_ARG, "damping must be >= 0 (0 = automatic), got " + num(eta));
    eta_user_ = eta;
    update_dynamics();
}

void Simulation::set_solver(int32_t solver) {
    if (solver != GFMD_SOLVER_VERLET && solver != GFMD_SOLVER_FIRE && solver != GFMD_SOLVER_FIRE_MASS)
        fail(GFMD_ERR_BAD_ENUM, "unknown solver " + std::to_string(solver));
    // Mass weighting needs one byte per point more; allocated first, so that a failure changes
    // nothing, and released when another solver is chosen.
    if (solver == GFMD_SOLVER_FIRE_MASS && held_.size() == 0) held_ = ByteBuffer(static_cast<std::size_t>(n_));
    if (solver != GFMD_SOLVER_FIRE_MASS) held_ = ByteBuffer();
    solver_ = solver;
    restart_fire();
}

void Simulation::set_threads(int threads) {
    if (threads < 0 || threads > 4096)
        fail(GFMD_ERR_INVALID_ARG, "threads must be in [0, 4096] (0 = all cores), got " + std::to_string(threads));
    const int t = (threads == 0) ? all_cores() : threads;
    grid_.replan(t, planner_);
    threads_ = t;
}

void Simulation::set_planner(int32_t planner) {
    if (planner != GFMD_PLANNER_ESTIMATE && planner != GFMD_PLANNER_MEASURE && planner != GFMD_PLANNER_PATIENT)
        fail(GFMD_ERR_BAD_ENUM, "unknown FFT planner " + std::to_string(planner));
    grid_.replan(threads_, planner);
    planner_ = planner;
}

void Simulation::restart_fire() {
    // Mass-weighted FIRE keeps its step as a fraction of its own time step mass_dt_.
    fire_dt_ = kFireDtStart * ((solver_ == GFMD_SOLVER_FIRE_MASS) ? 1.0 : dt_ / kDtFactor);
    mass_bucket_ = -1;
    fire_alpha_ = kFireAlpha0;
    fire_positive_ = 0;
}

void Simulation::reset() {
    // Even a flat surface can overflow: the FFT's rounding leaves modes of order eps * max h,
    // which an extreme E* turns into infinite stresses (a fuzz finding). Undo if so.
    change(
        "resetting the surface",
        [&] {
            std::copy(z_.data(), z_.data() + n_, saved_z_.data());
            std::copy(v_.data(), v_.data() + n_, saved_v_.data());
            put_flat_at_rest();
        },
        [&] {
            std::copy(saved_z_.data(), saved_z_.data() + n_, z_.data());
            std::copy(saved_v_.data(), saved_v_.data() + n_, v_.data());
        });
}

void Simulation::evaluate_forces() {
    // Elastic stress in Fourier space: sigma(q) = -u(q)/G(q); U_el = (A/2) sum_q |u(q)|^2/G(q)
    // with u(q) = Z(q)/N the normalized coefficients (seed paper, Eqs. 1-3).
    grid_.forward(z_.data(), work_.data());
    const int64_t nxh = grid_.nxh();
    const double inv_n = 1.0 / static_cast<double>(n_);
    const double w_last = grid_.weight(nxh - 1);  // 1 if the last column is the Nyquist one
    std::complex<double> *work = work_.data();
    const double *stiff = stiff_.data();
    const auto energy = parallel_sums<1>(threads_, grid_.ny(), rows_per_block_, sums_.data(),
                                         [&](int64_t y0, int64_t y1, double *acc) {
        for (int64_t ky = y0; ky < y1; ++ky) {
            std::complex<double> *row = work + ky * nxh;
            const double *krow = stiff + ky * nxh;
            // column 0 (and a Nyquist column) count once in the full-plane sum, the others twice
            double e = krow[0] * std::norm(row[0]);
            if (nxh > 1) e += (w_last - 2.0) * krow[nxh - 1] * std::norm(row[nxh - 1]);
            row[0] *= -krow[0] * inv_n;
            for (int64_t kx = 1; kx < nxh; ++kx) {
                e += 2.0 * krow[kx] * std::norm(row[kx]);
                row[kx] *= -krow[kx] * inv_n;
            }
            acc[0] += e;
        }
    });
    u_el_ = 0.5 * grid_.cell_area() * energy[0] * inv_n * inv_n;
    grid_.backward(work_.data(), f_.data());

    // Real space: external pressure, adhesion, the residual of the constrained problem, and the
    // sums FIRE needs (power F.v, |F|^2, |v|^2 of the projected force F).
    const bool adhesive = gamma0_ > 0.0;
    const double adh_coef = adhesive ? gamma0_ / rho_ : 0.0, inv_rho = 1.0 / rho_, sigma0 = sigma0_;
    double ref = sigma0_ + adh_coef;
    if (ref <= 0.0) ref = e_star_;
    const double inv_ref = 1.0 / ref;
    double *f = f_.data();
    const double *z = z_.data(), *h = h_.data(), *v = v_.data();
    const auto sums = parallel_sums<6>(threads_, n_, kBlock, sums_.data(), [&](int64_t i0, int64_t i1, double *acc) {
        double adh_sum = 0.0, res2 = 0.0, power = 0.0, v2 = 0.0, rel2 = 0.0;
        int64_t touching = 0;
        // Vectorized: the block's partial sums are split over SIMD lanes, in a fixed order, so
        // results stay independent of the thread count.
#pragma omp simd reduction(+ : adh_sum, res2, power, v2, rel2, touching)
        for (int64_t i = i0; i < i1; ++i) {
            const double g = z[i] - h[i];
            double fi = f[i] - sigma0;
            if (adhesive) {
                const double w = std::exp(-g * inv_rho);
                adh_sum += w;
                fi -= adh_coef * w;
            }
            f[i] = fi;
            touching += (g <= 0.0) ? 1 : 0;
            const double r = (g <= 0.0) ? std::max(fi, 0.0) : fi;  // in contact only pulling away counts
            res2 += r * r;
            rel2 += (r * inv_ref) * (r * inv_ref);  // the residual, scaled first: no overflow
            power += r * v[i];
            v2 += v[i] * v[i];
        }
        acc[0] += adh_sum;
        acc[1] += res2;
        acc[2] += power;
        acc[3] += v2;
        acc[4] += rel2;
        acc[5] += static_cast<double>(touching);
    });
    contacts_ = static_cast<int64_t>(sums[5]);
    u_ad_ = gamma0_ * area_per_point_ * sums[0];
    f_norm2_ = sums[1];
    power_ = sums[2];
    v_norm2_ = sums[3];
    residual_ = std::sqrt(sums[4] * inv_n);
}

void Simulation::advance() {
    if (solver_ == GFMD_SOLVER_FIRE)
        advance_fire();
    else if (solver_ == GFMD_SOLVER_FIRE_MASS)
        advance_fire_mass();
    else
        advance_verlet();
    evaluate_forces();
}

// FIRE's adaptive control from the power F.v of the last force evaluation: downhill -> after
// kFireDelay such steps grow the step (up to dt_max) and decay the mixing; uphill -> halve the
// step and reset the mixing.  Returns true if uphill.
bool Simulation::fire_control(double dt_max) {
    if (power_ > 0.0) {
        if (++fire_positive_ > kFireDelay) {
            fire_dt_ = std::min(fire_dt_ * kFireInc, dt_max);
            fire_alpha_ *= kFireAlphaDec;
        }
        return false;
    }
    fire_positive_ = 0;
    fire_dt_ *= kFireDec;
    fire_alpha_ = kFireAlpha0;
    return true;
}

void Simulation::advance_fire() {
    // FIRE 2.0 (Guenole et al. 2020, Algorithm 2) on the real-space field, unit mass per area:
    // uphill (F.v <= 0) -> stop and shrink the step; downhill -> grow it and steer v along F.
    // The wall is handled as in the damped dynamics: forces into the substrate at points in
    // contact are taken by the wall (projected out of F) and a point that hits it stops.
    const bool uphill = fire_control(kFireDtMax * dt_ / kDtFactor);
    const double dt = fire_dt_;
    // Mixing after the velocity update: v <- (1-a) v + a |v| F/|F|, with |v| of the updated v.
    // |v + dt F|^2 follows from the sums of the last force evaluation.
    double vn2 = 0.0;
    if (!uphill) vn2 = v_norm2_ + 2.0 * dt * power_ + dt * dt * f_norm2_;
    const double mix = (f_norm2_ > 0.0) ? fire_alpha_ * std::sqrt(std::max(vn2, 0.0) / f_norm2_) : 0.0;
    const double keep = 1.0 - fire_alpha_;
    // Uphill: step back half a step (FIRE 2.0), then restart from rest.
    const double back = uphill ? 0.5 * dt : 0.0;
    double *__restrict z = z_.data(), *__restrict v = v_.data();
    const double *__restrict h = h_.data(), *__restrict f = f_.data();
    parallel_for(threads_, n_, kBlock, [&](int64_t i0, int64_t i1) {
        // Branch-free (selects), so that scattered contact points cost no mispredictions and
        // the loop vectorizes.
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) {
            const double zo = z[i], vo = v[i], hi = h[i], fo = f[i];
            const double fi = (zo <= hi) ? std::max(fo, 0.0) : fo;
            double vi = uphill ? 0.0 : vo;
            vi += dt * fi;
            vi = keep * vi + mix * fi;
            const double zn = zo - back * vo + dt * vi;
            const bool hit = zn < hi;  // the wall stops a point that reaches it
            v[i] = hit ? 0.0 : vi;
            z[i] = hit ? hi : zn;
        }
    });
}

// The mass floor of mass-weighted FIRE.  A body pressed onto a substrate at contact fraction phi
// is held at points about sqrt(1/phi) cells apart; modes longer than that spacing are pinned by the
// contacts and do not relax on their own (soft) elastic time scale.  Their masses are therefore
// raised to the stiffness k_c at the contact spacing, the largest 1/G(q) over the fraction phi of
// modes with the smallest |q| (|q|^2 <= 4 pi phi / cell).  The floor depends only on the bucket
// floor(log2(contacts)), so it is a function of the state (a checkpoint resumes bit for bit).
void Simulation::update_mass_floor() {
    const int bucket = (contacts_ > 0) ? static_cast<int>(std::floor(std::log2(static_cast<double>(contacts_)))) : 0;
    if (bucket == mass_bucket_) return;
    const double phi = std::ldexp(1.0, bucket) / static_cast<double>(n_);
    const double qc2 = kMassSpacing * kMassSpacing * 4.0 * 3.141592653589793 * phi / area_per_point_;
    const int64_t nxh = grid_.nxh();
    double kc = 0.0;
    for (int64_t ky = 0; ky < grid_.ny(); ++ky) {
        const double qy = grid_.qy(ky);
        for (int64_t kx = 0; kx < nxh; ++kx) {
            const double qx = grid_.qx(kx);
            if (qx * qx + qy * qy <= qc2) kc = std::max(kc, stiff_[static_cast<std::size_t>(ky * nxh + kx)]);
        }
    }
    mass_floor_ = std::min(std::max(kc, k_min_), k_max_);
    // omega^2 = k(q)/m(q) <= 1 for the elastic modes.  The adhesive law's stiffness is local: a
    // single point's acceleration per unit force is the real-space diagonal of M^-1, the mean of
    // 1/m(q) over all modes (translation invariance), so it adds k_adh <1/m>.
    double inv_m = 0.0;
    for (int64_t ky = 0; ky < grid_.ny(); ++ky)
        for (int64_t kx = 0; kx < nxh; ++kx)
            inv_m += grid_.weight(kx) / std::max(stiff_[static_cast<std::size_t>(ky * nxh + kx)], mass_floor_);
    inv_m /= static_cast<double>(n_);
    mass_dt_ = kDtFactor / std::sqrt(1.0 + adhesive_stiffness() * inv_m);
    mass_bucket_ = bucket;
}

void Simulation::advance_fire_mass() {
    // FIRE with mass weighting (after Zhou, Moseler & Mueser, PRB 99, 144103 (2019)): each Fourier
    // mode has the inertia m(q) = max(k(q), k_c), so every mode stiffer than the contact spacing's
    // k_c oscillates with the same frequency.  The wall stays a real-space constraint, treated so
    // that it cannot feed the mass metric: (1) the force is projected before it is preconditioned,
    // so the wall's reaction never enters M^-1; (2) the points the wall holds are masked after it
    // (below); (3) the masses are bounded below by k_c, so M^-1 is bounded and the pinned long
    // modes are not accelerated beyond what the contacts let them move; (4) a point that hits the
    // wall stops, and FIRE's power test uses the true derivative of the energy, F.v, so any energy
    // a clamp puts in is caught as an uphill step.
    update_mass_floor();
    const bool uphill = fire_control(kFireDtMax);  // the step as a fraction of mass_dt_
    const double dt = std::min(fire_dt_, kFireDtMax) * mass_dt_;

    // a = M^-1 F_projected, one more r2c/c2r pair, computed in place of F (evaluate_forces()
    // recomputes F after the step); |a|^2 by Parseval in the same pass.  Points held by the wall
    // (in contact, pushed into it) are marked first: their acceleration is masked after the
    // preconditioning, so that only the free points move, with the preconditioner restricted to
    // them (a principal block of M^-1, still positive definite).  Without the mask the wall's
    // held points are lifted by their neighbours' preconditioned pull and clamped back every
    // step: the run bounces and never converges (measured; see docs/performance.md).
    double *z = z_.data(), *v = v_.data(), *a = f_.data();
    const double *h = h_.data();
    unsigned char *held = held_.data();
    parallel_for(threads_, n_, kBlock, [&](int64_t i0, int64_t i1) {
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) {
            const double fo = a[i];
            const bool contact = z[i] <= h[i];
            held[i] = (contact && fo <= 0.0) ? 1 : 0;
            a[i] = contact ? std::max(fo, 0.0) : fo;
        }
    });
    grid_.forward(a, work_.data());
    const int64_t nxh = grid_.nxh();
    const double inv_n = 1.0 / static_cast<double>(n_), floor = mass_floor_;
    std::complex<double> *work = work_.data();
    const double *stiff = stiff_.data();
    const auto a2 = parallel_sums<1>(threads_, grid_.ny(), rows_per_block_, sums_.data(),
                                     [&](int64_t y0, int64_t y1, double *acc) {
        for (int64_t ky = y0; ky < y1; ++ky) {
            std::complex<double> *row = work + ky * nxh;
            const double *krow = stiff + ky * nxh;
            for (int64_t kx = 0; kx < nxh; ++kx) {
                row[kx] *= inv_n / std::max(krow[kx], floor);
                acc[0] += grid_.weight(kx) * std::norm(row[kx]);
            }
        }
    });
    grid_.backward(work_.data(), a);
    const double a_norm = std::sqrt(a2[0] * static_cast<double>(n_));

    // FIRE 1.0 order (Bitzek et al. 2006): mix v towards a with the current |v| (|a| before the
    // mask: steering slightly weaker than FIRE's), then a semi-implicit Euler step; uphill: step
    // back half a step and restart from rest.
    const double mix = (a_norm > 0.0 && !uphill) ? fire_alpha_ * std::sqrt(v_norm2_) / a_norm : 0.0;
    const double keep = uphill ? 0.0 : 1.0 - fire_alpha_;
    const double back = uphill ? 0.5 * dt : 0.0;
    parallel_for(threads_, n_, kBlock, [&](int64_t i0, int64_t i1) {
#pragma omp simd
        for (int64_t i = i0; i < i1; ++i) {  // branch-free, as in advance_fire()
            const double zo = z[i], vo = v[i], hi = h[i], ao = a[i];
            const double ai = held[i] ? 0.0 : ao;
            const double vi = keep * vo + (mix + dt) * ai;
            const double zn = zo - back * vo + dt * vi;
            const bool hit = zn < hi;
            v[i] = hit ? 0.0 : vi;
            z[i] = hit ? hi : zn;
        }
    });
}

void Simulation::advance_verlet() {
    // Damped leapfrog: v(t+dt/2) = [(1 - eta dt/2) v(t-dt/2) + dt F(t)] / (1 + eta dt/2),
    // z(t+dt) = z(t) + dt v(t+dt/2), then the hard wall z >= h with the velocity of a point that
    // hits it set to zero (seed paper, Sec. 2.2).
    const double c1 = 1.0 - 0.5 * eta_ * dt_, c2 = 1.0 / (1.0 + 0.5 * eta_ * dt_), dt = dt_;
    double *z = z_.data(), *v = v_.data();
    const double *h = h_.data(), *f = f_.data();
    parallel_for(threads_, n_, kBlock, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            double vi = (c1 * v[i] + dt * f[i]) * c2;
            double zi = z[i] + dt * vi;
            if (zi < h[i]) {
                zi = h[i];
                vi = 0.0;
            }
            v[i] = vi;
            z[i] = zi;
        }
    });
}

void Simulation::save_state() {
    std::copy(z_.data(), z_.data() + n_, saved_z_.data());
    std::copy(v_.data(), v_.data() + n_, saved_v_.data());
}

void Simulation::restore_state() {
    std::copy(saved_z_.data(), saved_z_.data() + n_, z_.data());
    std::copy(saved_v_.data(), saved_v_.data() + n_, v_.data());
    evaluate_forces();
}

void Simulation::diverged(int64_t step) {
    restore_state();
    fail(GFMD_ERR_DIVERGED, "a non-finite value appeared at step " + std::to_string(step) + " (dt = " + num(dt_) +
                                ", stability limit 2/omega_max = " + num(2.0 / std::sqrt(k_max_ + adhesive_stiffness())) +
                                "); the state before the call was restored");
}

void Simulation::step(int64_t nsteps) {
    save_state();
    for (int64_t s = 0; s < nsteps; ++s) {
        advance();
        if (!state_finite()) diverged(s + 1);
    }
}

bool Simulation::relax(double tol, int64_t max_steps, int64_t &steps_taken) {
    save_state();
    restart_fire();
    steps_taken = 0;
    while (residual_ > tol) {
        if (steps_taken == max_steps) return false;
        advance();
        ++steps_taken;
        if (!state_finite()) diverged(steps_taken);
    }
    return true;
}

double Simulation::contact_area() const {
    const double *z = z_.data(), *h = h_.data();
    const auto c = parallel_sums<1>(threads_, n_, kBlock, sums_.data(), [&](int64_t i0, int64_t i1, double *acc) {
        int64_t k = 0;
        for (int64_t i = i0; i < i1; ++i) k += (z[i] <= h[i]) ? 1 : 0;
        acc[0] += static_cast<double>(k);
    });
    return c[0] / static_cast<double>(n_);
}

double Simulation::mean_gap() const {
    const double *z = z_.data(), *h = h_.data();
    const auto s = parallel_sums<1>(threads_, n_, kBlock, sums_.data(), [&](int64_t i0, int64_t i1, double *acc) {
        double t = 0.0;
        for (int64_t i = i0; i < i1; ++i) t += z[i] - h[i];
        acc[0] += t;
    });
    return s[0] / static_cast<double>(n_);
}

void Simulation::heights(double *out) const { std::copy(h_.data(), h_.data() + n_, out); }

void Simulation::gap(double *out) const {
    for (int64_t i = 0; i < n_; ++i) out[i] = z_[i] - h_[i];
}

void Simulation::surface(double *out) const { std::copy(z_.data(), z_.data() + n_, out); }

void Simulation::pressure(double *out) const {
    // Substrate on body: contact pressure max(0, -F) where the gap is zero, minus the adhesive pull.
    const double adh_coef = (gamma0_ > 0.0) ? gamma0_ / rho_ : 0.0;
    for (int64_t i = 0; i < n_; ++i) {
        const double g = z_[i] - h_[i];
        const double pull = (adh_coef > 0.0) ? adh_coef * std::exp(-g / rho_) : 0.0;
        const double contact = (g <= 0.0) ? std::max(-f_[i], 0.0) : 0.0;
        out[i] = contact - pull;
    }
}

double Simulation::persson_variance() const {
    // In full contact the surface follows the substrate, so the stress modes are sigma(q) =
    // h(q)/G(q) with h(q) the normalized Fourier coefficients; their variance (q != 0, full plane,
    // Parseval) is the width of Persson's pressure distribution at full magnification.
    ComplexBuffer hq(static_cast<std::size_t>(grid_.complex_size()));  // not the solver's scratch
    grid_.forward(h_.data(), hq.data());
    const int64_t nxh = grid_.nxh();
    const double inv_n = 1.0 / static_cast<double>(n_);
    double v = 0.0;
    for (int64_t ky = 0; ky < grid_.ny(); ++ky)
        for (int64_t kx = 0; kx < nxh; ++kx) {
            const std::size_t c = static_cast<std::size_t>(ky * nxh + kx);
            const double s = stiff_[c] * (std::abs(hq[c]) * inv_n);  // scaled first: no overflow
            v += grid_.weight(kx) * s * s;
        }
    if (!std::isfinite(v))
        fail(GFMD_ERR_RANGE, "the full-contact pressure variance overflows double precision");
    return v;
}

}  // namespace gfmd
