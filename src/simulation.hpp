// The GFMD simulation: state, elastic forces in Fourier space, damped dynamics with the
// non-penetration constraint in real space, and the observables.
#ifndef GFMD_SRC_SIMULATION_HPP
#define GFMD_SRC_SIMULATION_HPP

#include <cstdint>
#include <memory>

#include "buffer.hpp"
#include "fft_grid.hpp"
#include "substrate.hpp"

namespace gfmd {

// Heights and lengths are limited to 1e100 in magnitude so that no sum of squares of the fields
// (energies, FFT power) can overflow.
constexpr double kMaxHeight = 1e100;
constexpr double kMinLength = 1e-100, kMaxLength = 1e100;

class Simulation {
public:
    Simulation(int64_t nx, int64_t ny, double lx, double ly);
    // threads 0 = all cores; the FFT is planned once, with these settings.
    Simulation(int64_t nx, int64_t ny, double lx, double ly, int threads, int32_t planner);
    // Deep copy: an independent simulation in the same state (parameters, fields, solver state).
    std::unique_ptr<Simulation> clone() const;

    // Checkpoint and restart (checkpoint.cpp): the complete state in a portable binary file.
    void save(const char *path) const;
    static std::unique_ptr<Simulation> load(const char *path, bool (*fits_in_memory)(int64_t, int64_t));

    const FftGrid &grid() const { return grid_; }

    // Setters check everything before changing anything (a failed call changes nothing).
    void set_modulus(double e_star);
    void set_green(int32_t kind, double width);
    void set_poisson(double nu);
    void set_heights(const double *h);
    void generate_selfaffine(const SelfAffineParams &p);
    void set_pressure(double sigma0);
    void set_adhesion(double gamma0, double rho);
    void set_timestep(double dt);
    void set_damping(double eta);
    void set_solver(int32_t solver);
    void set_threads(int threads);  // 0 = all cores
    void set_planner(int32_t planner);
    int threads() const { return threads_; }
    void reset();

    double timestep() const { return dt_; }
    double damping() const { return eta_; }
    int32_t solver() const { return solver_; }

    // Dynamics.  Throw Error(GFMD_ERR_DIVERGED) after restoring the state of the call's start.
    void step(int64_t nsteps);
    // Returns true if converged; steps_taken receives the number of steps made.
    bool relax(double tol, int64_t max_steps, int64_t &steps_taken);
    double residual() const { return residual_; }

    // Observables of the current configuration.
    double contact_area() const;
    double mean_gap() const;
    double elastic_energy() const { return u_el_; }
    double adhesive_energy() const { return u_ad_; }
    void heights(double *out) const;
    void gap(double *out) const;
    void surface(double *out) const;
    void pressure(double *out) const;

    // Persson's theory (non-adhesive): the variance of the contact pressure the body would carry
    // in full contact, sum over q != 0 of (|h(q)| / G(q))^2 with this handle's substrate and body.
    double persson_variance() const;

private:
    // Stiffness 1/G(q) on the Hermitian half-spectrum for a candidate body; throws on overflow.
    RealBuffer stiffness_for(int32_t kind, double width, double e_star, double nu) const;
    void adopt_stiffness(RealBuffer &&k);  // commit and update the automatic dynamics
    double adhesive_stiffness() const;  // gamma0/rho^2, the stiffest point of the adhesive law
    bool state_finite() const;          // forces, energies and residual all finite
    void update_dynamics();
    void evaluate_forces();  // forces, energies and residual of the current z
    void advance();          // one step of the chosen solver followed by evaluate_forces()
    void advance_verlet();
    bool fire_control(double dt_max);  // FIRE's step and mixing from the power; true if uphill
    void advance_fire();
    void advance_fire_mass();
    void update_mass_floor();  // the mass floor for the current contact fraction
    void restart_fire();
    template <class Apply, class Undo>
    void change(const char *what, Apply &&apply, Undo &&undo);
    void change_body(const char *what, int32_t kind, double width, double e_star, double nu);
    template <class Fill>
    void change_substrate(Fill &&fill);
    void put_flat_at_rest();
    void save_state();
    void restore_state();
    [[noreturn]] void diverged(int64_t step);

    int threads_;
    int32_t planner_ = 1;  // GFMD_PLANNER_MEASURE
    FftGrid grid_;
    int64_t n_;
    int64_t rows_per_block_;
    double area_per_point_;

    // Parameters.
    double e_star_ = 1.0;
    int32_t kind_ = 0;  // GFMD_GREEN_HALFSPACE
    double width_ = 0.0;
    double nu_;         // NaN until set
    double sigma0_ = 0.0;
    double gamma0_ = 0.0, rho_ = 1.0;
    double dt_user_ = 0.0, eta_user_ = 0.0;
    int32_t solver_ = 1;  // GFMD_SOLVER_FIRE

    // Derived.
    double dt_ = 0.0, eta_ = 0.0, k_min_ = 0.0, k_max_ = 0.0;

    // Fields: substrate, surface, velocity, non-contact force per area, stiffness, FFT scratch,
    // and the state saved at the start of a dynamics call.
    RealBuffer h_, z_, v_, f_, stiff_;
    ComplexBuffer work_;
    RealBuffer saved_z_, saved_v_;
    ByteBuffer held_;  // mass-weighted FIRE only: 1 where the wall holds the body
    mutable RealBuffer sums_;  // per-block partial sums of the threaded reductions

    // Cached observables of the current z (kept in step with z by evaluate_forces()).
    double u_el_ = 0.0, u_ad_ = 0.0, residual_ = 0.0;
    // Sums over the projected force F (zero where the wall holds the body) for FIRE:
    // power F.v, |F|^2, |v|^2.
    double power_ = 0.0, f_norm2_ = 0.0, v_norm2_ = 0.0;
    int64_t contacts_ = 0;  // points with zero gap
    // Mass-weighted FIRE: masses m(q) = max(k(q), mass_floor_), chosen for the contact fraction
    // bucket mass_bucket_ (floor(log2(contacts)), -1 = not chosen yet); its time step.
    double mass_floor_ = 0.0, mass_dt_ = 0.0;
    int mass_bucket_ = -1;
    // FIRE's adaptive state (Bitzek et al., PRL 97, 170201 (2006)).
    double fire_dt_ = 0.0, fire_alpha_ = 0.0;
    int64_t fire_positive_ = 0;
};

}  // namespace gfmd

#endif
