/**
 * @file gfmd.h
 * @brief gfmd: Green's function molecular dynamics (GFMD) for the contact between a rigid, rough
 *        substrate and an elastic half-space or thin elastic layer.
 *
 * Model (Putignano, Dapp & Müser, Biomimetics 1, 7 (2016)):
 * a periodic grid of nx x ny points on a cell lx x ly (spacing lx/nx, ly/ny) holds the rigid
 * substrate heights h(r) and the elastic body's surface z(r) = h(r) + gap(r), gap >= 0.  A uniform
 * external pressure sigma0 pushes the body down onto the substrate; an optional adhesive stress
 * (gamma0/rho) exp(-gap/rho) pulls it down as well.  Elasticity acts in Fourier space: the stress
 * of mode q is -u(q)/G(q), G(q) = 2 f(q w) / (q E*), with f = 1 for the half-space.
 * Units are the user's: any consistent length and pressure units (E* = 1 and a = 1 are typical).
 *
 * @par Array layout (all fields of nx*ny values)
 * x runs fastest.  In C a field is `double field[ny][nx]`, point (ix, iy) at index ix + nx*iy.
 * In Fortran the same memory is `real(dp) :: field(nx, ny)`, point (ix+1, iy+1).  No transposes.
 *
 * @par Error model
 * Every call that can fail returns an int32_t status, GFMD_OK (0) on success.  A failed call leaves
 * the handle usable and its state unchanged (GFMD_ERR_NOT_CONVERGED keeps the progress made, as
 * documented at gfmd_relax()).  The message of the last failure on a handle is kept in the handle:
 * gfmd_last_error(), until the next failure.  The library never aborts or exits on user input.
 *
 * @par Thread contract
 * Distinct handles are independent and may be used from different threads at the same time.  One
 * handle must be used by one thread at a time (including the const getters, which may record an
 * error message, and Persson's, which transform the substrate in the handle's FFT scratch).  FFTW
 * planning, which is not thread-safe, is serialized inside the library.  The library installs
 * FFTW's spawn-loop callback (fftw_threads_set_callback) so that its own transforms run on the
 * handle's threads; other threaded FFTW plans of the process run as with FFTW's OpenMP backend.
 */
#ifndef GFMD_H
#define GFMD_H

#include <stdint.h>

#include "gfmd/gfmd_export.h"
#include "gfmd/gfmd_constants.h"
#include "gfmd/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque simulation handle. */
typedef struct gfmd_sim gfmd_sim;

/* The enums (status codes, Green kinds, distributions, solvers, planners) and GFMD_DEFAULT_TOL
 * are generated from include/gfmd/constants.tbl into gfmd/gfmd_constants.h. */

/* ---------------------------------------------------------------- version and status */

/** Runtime version string, e.g. "0.1.0" (compare with GFMD_VERSION_STRING). */
GFMD_API const char *gfmd_version(void);

/** Static description of a status code; never NULL (unknown codes give "unknown status"). */
GFMD_API const char *gfmd_status_string(int32_t status);

/**
 * Copy the message of the last failed call on @p s into @p buf (capacity @p len bytes).
 * The copy is always NUL-terminated when len >= 1 (with s == NULL too: then "" and GFMD_ERR_NULL).  Returns GFMD_OK, or GFMD_ERR_TRUNCATED when
 * the message did not fit (use gfmd_last_error_length()).  The message is "" if no call on the
 * handle has failed yet; a successful call does not clear it.
 */
GFMD_API int32_t gfmd_last_error(const gfmd_sim *s, char *buf, int64_t len);

/** Buffer size (message length + 1 for the NUL) that gfmd_last_error() needs. */
GFMD_API int32_t gfmd_last_error_length(const gfmd_sim *s, int64_t *needed);

/* ---------------------------------------------------------------- lifetime */

/**
 * Create a simulation of nx x ny points on a periodic cell lx x ly.  The body starts as a
 * half-space with E* = 1, flat substrate h = 0, no load, no adhesion.
 * @param out receives the handle; set to NULL on failure.
 * @return GFMD_ERR_INVALID_ARG for non-positive sizes, nx or ny above 2^30, or lengths that are not
 *         within [1e-100, 1e100] (NaN, inf), GFMD_ERR_NOMEM if the grid does not fit in the
 *         memory available (82 bytes per point, above the measured peak) or allocation fails.
 */
GFMD_API int32_t gfmd_sim_create(int64_t nx, int64_t ny, double lx, double ly, gfmd_sim **out);

/**
 * gfmd_sim_create() with the thread count and the FFT planner fixed before the first FFT plan is
 * made, so that the handle plans exactly once and an ESTIMATE handle never meets a measured plan
 * (FFTW reuses wisdom of a more rigorous planner: a MEASURE plan made first would change the
 * transforms' bits from one process to the next).
 * @param nthreads threads as in gfmd_set_threads() (0 = the default).
 * @param planner  GFMD_PLANNER_* as in gfmd_set_fft_planner().
 * @return as gfmd_sim_create(), and GFMD_ERR_INVALID_ARG for nthreads outside [0, 4096],
 *         GFMD_ERR_BAD_ENUM for an unknown planner.
 */
GFMD_API int32_t gfmd_sim_create_ex(int64_t nx, int64_t ny, double lx, double ly, int32_t nthreads,
                                    int32_t planner, gfmd_sim **out);

/**
 * Deep copy: *out receives a new, independent handle in the same state as @p s (substrate,
 * configuration, parameters, solver state; not the last error message).  *out is NULL on failure.
 */
GFMD_API int32_t gfmd_sim_clone(const gfmd_sim *s, gfmd_sim **out);

/** Destroy the handle in *sim and set *sim = NULL.  Accepts sim == NULL and *sim == NULL. */
GFMD_API void gfmd_sim_destroy(gfmd_sim **sim);

/**
 * Checkpoint: save the complete state (grid, parameters, substrate, surface, velocities, solver
 * state, thread and planner settings) to @p path, in the portable, versioned format of
 * docs/guarantees.md.  Written to "<path>.tmp" and renamed, so a crash while saving never
 * leaves a damaged file under @p path.  GFMD_ERR_IO if it cannot be written.
 */
GFMD_API int32_t gfmd_sim_save(const gfmd_sim *s, const char *path);

/**
 * Restart: create *out from a checkpoint.  A run continued from it repeats the saved run bit for
 * bit when the FFT plans are the same (same process, imported wisdom, or GFMD_PLANNER_ESTIMATE).
 * Refuses, with *out = NULL: GFMD_ERR_IO (cannot open), GFMD_ERR_FORMAT (not a checkpoint,
 * truncated, checksum mismatch, invalid content), GFMD_ERR_VERSION (unknown format version),
 * GFMD_ERR_NOMEM.  As there is no handle yet, the message goes to @p errbuf (capacity @p errlen,
 * always NUL-terminated; errbuf may be NULL).
 */
GFMD_API int32_t gfmd_sim_load(const char *path, gfmd_sim **out, char *errbuf, int64_t errlen);

/** Grid size and cell lengths given at creation.  Any output pointer may be NULL. */
GFMD_API int32_t gfmd_get_grid(const gfmd_sim *s, int64_t *nx, int64_t *ny, double *lx, double *ly);

/* ---------------------------------------------------------------- the elastic body */

/**
 * The body's lateral boundary.  GFMD_BOUNDARY_PERIODIC (the default): the grid is one cell of a
 * periodic surface.  GFMD_BOUNDARY_FREE: the grid is the whole region of a half-space whose
 * surface beyond it carries no load -- a measured, non-periodic scan -- solved on the zero-padded
 * 2nx x 2ny cell with the free-space Boussinesq response of each grid cell, exact for a pressure
 * constant on each cell; the load sigma0 is a total force sigma0 lx ly on the body, and every
 * field, A/A0 and the mean gap are the region's.  gfmd_get_mean_displacement() then gives the
 * level of the surface far from the region (the body's rigid position), gfmd_get_energies() the
 * elastic energy (1/2) sum p u of the contact pressure and its free-space displacement.
 * Free boundaries take the half-space under pressure control, with or without adhesion, the
 * solvers GFMD_SOLVER_CG, FIRE, VERLET and AUTO (which takes CG), and not layers, displacement
 * control, plasticity, the multilevel start, Persson's theory of the handle (use
 * gfmd_topo_persson_contact_area()) or a distributed handle: those calls, or this one in those
 * states, return GFMD_ERR_STATE.  A change of boundary keeps the parameters and the substrate
 * and puts the body flat, at rest; it needs the memory of the new grid (4x with free
 * boundaries).  GFMD_ERR_BAD_ENUM for another value.  Checkpoints keep the boundary.
 */
GFMD_API int32_t gfmd_set_boundary(gfmd_sim *s, int32_t boundary);

/** The boundary set (GFMD_BOUNDARY_*). */
GFMD_API int32_t gfmd_get_boundary(const gfmd_sim *s, int32_t *boundary);

/** Contact modulus E* = E/(1 - nu^2) > 0 (default 1).  Keeps the configuration. */
GFMD_API int32_t gfmd_set_modulus(gfmd_sim *s, double e_star);

/**
 * Choose the elastic body: GFMD_GREEN_HALFSPACE (width ignored), GFMD_GREEN_LAYER_FLUID or
 * GFMD_GREEN_LAYER_BONDED with layer width > 0.  The bonded layer needs Poisson's ratio set first
 * (gfmd_set_poisson), otherwise GFMD_ERR_STATE.  Keeps the current configuration.
 */
GFMD_API int32_t gfmd_set_green(gfmd_sim *s, int32_t kind, double width);

/** Poisson's ratio, -1 < nu <= 0.5 (used by the bonded layer only).  Keeps the configuration. */
GFMD_API int32_t gfmd_set_poisson(gfmd_sim *s, double nu);

/**
 * The dimensionless factor f(t), t = q w, of G(q) = 2 f(q w)/(q E*) for a kind of body
 * (1 for the half-space).  Accurate to a few ulps for all t > 0: the closed forms are evaluated by
 * series where they cancel and in exponentially scaled form where they overflow.
 * @param nu Poisson's ratio, used by GFMD_GREEN_LAYER_BONDED only.
 * @return GFMD_ERR_INVALID_ARG for t <= 0 or non-finite, GFMD_ERR_RANGE if f over- or underflows
 *         (t below about 1e-103 for the fluid foundation or the incompressible bonded layer).
 */
GFMD_API int32_t gfmd_green_factor(int32_t kind, double t, double nu, double *f);

/* ---------------------------------------------------------------- the substrate */

/**
 * Set the nx*ny substrate heights (x fastest), all finite and at most 1e100 in magnitude.  The
 * body is reset to flat at the highest substrate point, at rest.
 */
GFMD_API int32_t gfmd_set_heights(gfmd_sim *s, const double *h);

/** Copy the nx*ny substrate heights into @p h. */
GFMD_API int32_t gfmd_get_heights(const gfmd_sim *s, double *h);

/**
 * Generate a self-affine substrate: spectrum C(q) = 1 for 0 < q < q_r = 2 pi/lambda_r,
 * (q/q_r)^(-2(1+H)) for q_r <= q <= q_s = 2 pi/lambda_s, 0 above (and on the Nyquist lines);
 * real and imaginary parts of each Fourier amplitude drawn independently (uniform or Gaussian with
 * equal second moment) from a portable generator seeded by @p seed, so a seed gives the same
 * surface on every machine.  Scaled so that the spectral rms gradient sqrt(<|grad h|^2>) equals
 * @p rms_gradient, shifted so that max h = 0.  Resets the body like gfmd_set_heights().
 * Requires 0 <= hurst <= 1, lambda_r >= lambda_s >= 2 grid spacings (the larger spacing if the
 * cells are not square), lambda_s <= the cell, 0 < rms_gradient with rms_gradient * L <= 1e100.
 */
GFMD_API int32_t gfmd_generate_selfaffine(gfmd_sim *s, double hurst, double lambda_r, double lambda_s,
                                          double rms_gradient, uint64_t seed, int32_t distribution);

/* ---------------------------------------------------------------- loads */

/** Pressure control (the default): an external pressure sigma0 >= 0 pushes the body onto the
 *  substrate, and its mean position follows.  Keeps the configuration. */
GFMD_API int32_t gfmd_set_pressure(gfmd_sim *s, double sigma0);

/**
 * Displacement control: prescribe the mean position of the body's surface, mean(z) = @p d (in the
 * substrate's height units; z = h + gap), so that the mean pressure the body carries follows —
 * also when it is tensile, as on the unstable branch of an adhesive contact and at pull-off.  The
 * configuration is moved to the nearest one with that mean (every free point shifted alike, points
 * reaching the substrate stopped) and every step keeps it.  A smaller d presses harder.
 * GFMD_ERR_INVALID_ARG if d is not finite or below the substrate's mean height (a body with z >= h
 * cannot have a smaller mean).  gfmd_set_pressure() returns to pressure control.  Works with
 * every solver (GFMD_SOLVER_CG without adhesion); GFMD_SOLVER_MASS_WEIGHTED_FIRE then holds the mean in
 * its preconditioned step, one FFT pair more per step (see gfmd_set_solver()).  Checkpoints keep
 * the mode.
 */
GFMD_API int32_t gfmd_set_mean_displacement(gfmd_sim *s, double d);

/** The mean position of the body's surface, mean(z), under either control. */
GFMD_API int32_t gfmd_get_mean_displacement(const gfmd_sim *s, double *d);

/**
 * The mean pressure the body carries (compressive > 0): sigma0 under pressure control; under
 * displacement control the pressure that balances the body at its prescribed position (the mean
 * elastic and adhesive stress of the points out of contact: at equilibrium, the mean contact
 * pressure minus the mean adhesive pull).  With no point out of contact (the position at the
 * substrate's mean: full contact) the least pressure that keeps every point on the substrate, the
 * limit of the pressure as the last gap closes.
 */
GFMD_API int32_t gfmd_get_mean_pressure(const gfmd_sim *s, double *p);

/**
 * Adhesion: stress (gamma0/rho) exp(-gap/rho) pulling the body down; gamma0 >= 0 is the surface
 * energy (gamma0 = 0 switches adhesion off), rho > 0 the range.  Keeps the configuration.
 */
GFMD_API int32_t gfmd_set_adhesion(gfmd_sim *s, double gamma0, double rho);

/* ---------------------------------------------------------------- dynamics */

/**
 * Time step of the damped dynamics (unit mass per unit area).  0 (the default) chooses it from
 * the Green's function: dt = 1/omega_max, omega_max^2 the largest stiffness (elastic + adhesive).
 * GFMD_SOLVER_FIRE grows its own step up to 1.3 dt (see gfmd_set_solver()).
 */
GFMD_API int32_t gfmd_set_timestep(gfmd_sim *s, double dt);

/**
 * Damping rate eta >= 0 of every mode's velocity.  0 (the default) chooses it so that the slowest
 * elastic mode is slightly underdamped: eta = 1.8 omega_min.
 */
GFMD_API int32_t gfmd_set_damping(gfmd_sim *s, double eta);

/**
 * Method used by gfmd_step() and gfmd_relax().  All share the forces, the wall and the convergence
 * criterion and reach the same equilibrium (with adhesion, a minimum of a non-convex energy that
 * may differ between solvers).  The solver restarts at every change listed under *Continuing a
 * trajectory*; its state is in checkpoints.
 *
 * - GFMD_SOLVER_AUTO (the default): the fastest of the others for the problem, from a few features
 *   of it -- the body, adhesion, the load control, the grid's points, the long waves' softness
 *   S = k_halfspace(q_max)/k_min and f(q_min w), the layer's width against the grid and the
 *   roughness, Persson's A/A0 at the load, whether the surface is still flat (a first load) and
 *   the substrate's overlap with a prescribed mean position.  In short: the CG on half-spaces,
 *   bonded layers and layers on a fluid foundation wherever it is fastest (most problems below
 *   2048^2, first loads, low loads, and with adhesion all but the thinnest sheets); FIRE at dense
 *   contacts; the Newton method on thin sheets' continuing loads from 1024^2 on; mass-weighted
 *   FIRE or the approach then FIRE on thin sheets at low loads and on soft layers under
 *   displacement control.  The rule is one table of thresholds (src/solver_choice.hpp, each with
 *   its reason; docs/decisions.md has the measurements); it is applied again whenever the body,
 *   the substrate, the adhesion, the load or its control changes, at gfmd_reset() and on each grid
 *   of gfmd_relax_multilevel().  gfmd_get_solver() tells the choice.
 * - GFMD_SOLVER_CG: constrained conjugate gradients; one "step" is one iteration.  Under pressure
 *   control on a half-space or bonded layer without adhesion Polonsky & Keer's iteration on the
 *   contact pressure (two FFT pairs an iteration, the convergence test, one pair more, every
 *   third iteration since the restart: gfmd_relax() stops at most two iterations after the first
 *   that meets tol, and a call that reaches max_steps between two tests returns
 *   GFMD_ERR_NOT_CONVERGED); otherwise a projected CG on the surface, tested every iteration,
 *   preconditioned by the inverse mode stiffness (floored at the contact spacing's) under pressure
 *   control, with a line search along the adhesive energy and every step checked against it when
 *   adhesive.  It takes adhesion under pressure control only: GFMD_ERR_STATE, nothing changed, for
 *   a call that would bring adhesion, CG and displacement control together.  16 bytes per point.
 * - GFMD_SOLVER_FIRE: FIRE, its step adapted up to 1.3 times the time step, no damping needed.
 * - GFMD_SOLVER_MASS_WEIGHTED_FIRE (deprecated name GFMD_SOLVER_FIRE_MASS): FIRE with each Fourier
 *   mode's inertia taken from its stiffness, floored at the stiffness of the contact spacing, the
 *   points the wall holds kept still, its own time step (gfmd_set_timestep() does not apply).  Two
 *   FFT pairs a step (a third under displacement control when the held set changed); one byte per
 *   point.  Fast on thin sheets and at low loads.
 * - GFMD_SOLVER_APPROACH_THEN_FIRE (deprecated name GFMD_SOLVER_MASS_FIRE): after every restart at
 *   most 100 mass-weighted steps (at the unmasked modes' time step), then GFMD_SOLVER_FIRE from
 *   where they got, the motion kept (rescaled so that the results do not depend on the units).
 *   The count of approach steps is solver state.  One byte per point.
 * - GFMD_SOLVER_NEWTON: the active-set Newton method for thin sheets on a fluid foundation.  A step
 *   holds the points the wall holds and solves for the others by CG preconditioned with a
 *   multigrid cycle of the thin-plate stencil, then moves to max(h, z + alpha d), alpha halved
 *   until the energy falls enough; one "step" is one Newton step (at most 10 CG iterations, each
 *   an FFT pair and a cycle, and a forward transform per halving).  From a flat surface (a first
 *   load) a call that steps first relaxes the body on coarser grids, as gfmd_relax_multilevel()
 *   does: the grid halved while it keeps 64 points a side, at most 3 times, each grid to 1e-6 in
 *   at most 1000 steps; steps_taken counts this grid's steps only.  gfmd_step() and a relax in
 *   chunks make the same start and steps as one call; the coarse grids (a third of this grid's
 *   points together) are freed when the start ends (GFMD_ERR_NOMEM, nothing changed, if they
 *   cannot be had).  An adhesive sheet with several equilibria may end in another one than
 *   without the start.  With adhesion its CG adds the adhesive law's curvature within a trust
 *   region |d| <= R (Steihaug), R = rho after a restart, doubled after a full step to its edge,
 *   set to the step taken after a shortened one, never below 0.3 rho; R is
 *   solver state.  Results do not depend on the thread count.  It takes a layer on a fluid
 *   foundation under pressure control on one process, on a square grid of square cells whose side
 *   is a power of 2 >= 32: GFMD_ERR_STATE, nothing changed, otherwise (and for a later call that
 *   would bring it another body or displacement control); gfmd_relax_multilevel() takes the
 *   default's choice on its grids below 32^2.  About 80 bytes per point.  Fast where the stencil
 *   stands for the stiffness, q_max w < 6.
 * - GFMD_SOLVER_VERLET: the seed paper's damped dynamics (gfmd_set_timestep(), gfmd_set_damping()).
 *
 * A solver's extra memory that cannot be had gives GFMD_ERR_NOMEM with nothing changed.
 */
GFMD_API int32_t gfmd_set_solver(gfmd_sim *s, int32_t solver);

/** The solver that steps now: the one set, or the one GFMD_SOLVER_AUTO chose (never AUTO). */
GFMD_API int32_t gfmd_get_solver(const gfmd_sim *s, int32_t *solver);

/**
 * Threads used by this handle: FFTW's transforms and the library's own loops, on a pool of threads
 * the handle owns (threads that wait yield their core, so a core shared with another process does
 * not stall the others).  0 (the default) uses OMP_NUM_THREADS if that is set (e.g. to 1 when
 * running one process per core), otherwise the CPUs the process may run on (its affinity mask),
 * bounded by a cgroup CPU quota.  Results do not depend on the thread count of the library's loops
 * (sums are formed in fixed blocks); FFTW may round differently with threads.  Re-plans the
 * transforms: to plan once, give the threads to gfmd_sim_create_ex().
 */
GFMD_API int32_t gfmd_set_threads(gfmd_sim *s, int32_t nthreads);

/** Threads in effect for this handle. */
GFMD_API int32_t gfmd_get_threads(const gfmd_sim *s, int32_t *nthreads);

/** FFTW planner rigour (GFMD_PLANNER_*) for this handle's transforms; re-plans them. */
GFMD_API int32_t gfmd_set_fft_planner(gfmd_sim *s, int32_t planner);

/**
 * Load FFTW wisdom from a file (process-wide, as FFTW's wisdom is), so that later plans of the
 * same sizes are made without measuring.  GFMD_ERR_IO if the file cannot be read or parsed.
 */
GFMD_API int32_t gfmd_import_wisdom(const char *path);

/** Save the process's FFTW wisdom to a file.  GFMD_ERR_IO if it cannot be written. */
GFMD_API int32_t gfmd_export_wisdom(const char *path);

/** The time step and damping rate in effect (automatic or user-set). Either pointer may be NULL. */
GFMD_API int32_t gfmd_get_dynamics(const gfmd_sim *s, double *dt, double *eta);

/**
 * @par Continuing a trajectory
 * The solver's adaptive state (FIRE's step and mixing) lives in the handle: gfmd_step() and
 * gfmd_relax() continue where the last call stopped, so gfmd_relax(N) then gfmd_relax(M), or any
 * chunks of gfmd_step(), follow exactly the trajectory of one call (same steps, same bits), and a
 * checkpoint taken between chunks resumes it.  The solver restarts only when the energy landscape
 * or the dynamics change: gfmd_set_pressure, gfmd_set_adhesion, gfmd_set_green, gfmd_set_modulus,
 * gfmd_set_poisson (bonded layer), a new substrate, gfmd_set_solver, gfmd_set_timestep,
 * gfmd_set_damping, gfmd_reset, or gfmd_restart_solver().
 */

/**
 * Advance @p nsteps >= 0 steps of the chosen solver (elastic forces in Fourier space,
 * non-penetration z >= h enforced in real space after each step).
 * GFMD_ERR_DIVERGED if a non-finite value appears; the state before the call (configuration and
 * solver state) is then restored.
 */
GFMD_API int32_t gfmd_step(gfmd_sim *s, int64_t nsteps);

/** Restart the solver's adaptive state as a change of the landscape would (e.g. after the user
 *  moved the configuration by other means); the configuration stays. */
GFMD_API int32_t gfmd_restart_solver(gfmd_sim *s);

/**
 * Step until the relative force residual (see gfmd_get_residual) is <= tol (tol <= 0: the
 * default GFMD_DEFAULT_TOL), at most @p max_steps > 0 steps.  @p steps_taken (may be NULL)
 * receives the steps made.  GFMD_ERR_NOT_CONVERGED if the limit is reached; the progress and the
 * solver's state are kept, so that another call continues the same trajectory.
 * GFMD_ERR_DIVERGED restores the state before the call.
 */
GFMD_API int32_t gfmd_relax(gfmd_sim *s, double tol, int64_t max_steps, int64_t *steps_taken);

/**
 * gfmd_relax() from a start made on coarser grids: the same body relaxed on the grid coarsened
 * @p levels - 1 times by 2 (nx/2^k x ny/2^k points, same cell; the substrate and the current
 * surface filtered to each grid by dropping the modes it cannot hold; the solver the handle's
 * setting gives on that grid), each coarse surface interpolated to the next finer grid (zero-padded
 * spectrum, then lifted onto the substrate where it would penetrate), and relaxed there in turn
 * (GFMD_SOLVER_AUTO chooses again for that deformed start, as for a load that continues; a failed
 * call restores the solver of its start), to the same tol and at most @p max_steps steps per grid;
 * then this grid as gfmd_relax() does.  The long waves relax where steps are cheap; whether that
 * pays depends on the body (docs/performance.md).  levels = 1 is gfmd_relax().  An adhesive body
 * with several equilibria may end in another one than from flat.
 * @p steps_taken (may be NULL) receives this grid's steps, @p coarse_steps (may be NULL) those of
 * all coarser grids together.  GFMD_ERR_INVALID_ARG, nothing
 * changed, unless levels = 1 (on any grid) or levels > 1 and nx, ny are divisible by 2^(levels-1)
 * with at least 8 points a side on the coarsest grid; statuses otherwise as gfmd_relax() (a coarse grid that does not
 * converge is still used as the start).  Deterministic: coarse grids are planned with
 * GFMD_PLANNER_ESTIMATE and use the handle's threads.
 */
GFMD_API int32_t gfmd_relax_multilevel(gfmd_sim *s, double tol, int64_t max_steps, int32_t levels,
                                       int64_t *steps_taken, int64_t *coarse_steps);

/**
 * Relative force residual of the current configuration: the rms over all points of the net
 * non-contact stress (elastic + adhesive - sigma0; at points in contact only its part pulling
 * away from the substrate), divided by sigma0 + gamma0/rho (or by E* when both are zero).
 */
GFMD_API int32_t gfmd_get_residual(const gfmd_sim *s, double *residual);

/** Put the body back to flat at the highest substrate point, at rest. */
GFMD_API int32_t gfmd_reset(gfmd_sim *s);

/* ---------------------------------------------------------------- observables */

/** Relative contact area A/A0: the fraction of points whose gap is zero. */
GFMD_API int32_t gfmd_get_contact_area(const gfmd_sim *s, double *rel_area);

/** Mean gap <z - h> over the cell. */
GFMD_API int32_t gfmd_get_mean_gap(const gfmd_sim *s, double *mean_gap);

/**
 * Elastic energy U_el = (A/2) sum_q |u(q)|^2 / G(q) and adhesive energy
 * U_ad = integral of gamma0 exp(-gap/rho) dA (energy gained, >= 0), both for the whole cell.
 */
GFMD_API int32_t gfmd_get_energies(const gfmd_sim *s, double *elastic, double *adhesive);

/** Gap field z - h (nx*ny, x fastest, >= 0). */
GFMD_API int32_t gfmd_get_gap(const gfmd_sim *s, double *gap);

/** Elastic body's surface z = h + gap (nx*ny, x fastest). */
GFMD_API int32_t gfmd_get_surface(const gfmd_sim *s, double *z);

/**
 * Normal stress exerted by the substrate on the body (nx*ny): contact pressure (>= 0, at points
 * in contact) minus the adhesive pull.  At equilibrium its mean equals sigma0.
 */
GFMD_API int32_t gfmd_get_pressure(const gfmd_sim *s, double *p);

/* ---------------------------------------------------------------- plasticity */

/**
 * Perfect plasticity of the substrate at hardness @p hardness (docs/model.md, "Plasticity"): the
 * contact pressure never exceeds H; where the body would press harder the substrate yields and its
 * height is lowered to the body's surface, for good.  A load step (the relaxation at one load) is
 * the minimum of U_el - (work of the load) + H V, V the volume by which the body's surface lies
 * below the substrate as the step began; each change of load (gfmd_set_pressure(),
 * gfmd_set_mean_displacement()) and gfmd_reset() begin a new step from the substrate as it is then,
 * so loading and unloading in steps leave the plastic deformation in place.  gfmd_get_heights()
 * returns the substrate as deformed now; a new substrate (gfmd_set_heights(),
 * gfmd_generate_selfaffine()) starts without deformation.  A change of a finite H ends the step
 * made at the old one.  @p hardness = +INFINITY (the default) switches plasticity off; the
 * substrate keeps the shape it has.  Steps with FIRE or Verlet; GFMD_SOLVER_AUTO takes FIRE.
 * Kept by checkpoints.  Needs 16 B/pt more.
 * @return GFMD_ERR_INVALID_ARG for hardness <= 0 or NaN; GFMD_ERR_STATE with adhesion, with a
 *         solver other than FIRE, Verlet and AUTO, or on a handle distributed over several ranks;
 *         GFMD_ERR_NOMEM if the plastic state does not fit.
 */
GFMD_API int32_t gfmd_set_hardness(gfmd_sim *s, double hardness);

/** The hardness (+INFINITY without plasticity). */
GFMD_API int32_t gfmd_get_hardness(const gfmd_sim *s, double *hardness);

/**
 * The plastic state: @p plastic_area receives the fraction of the points yielding now (at the
 * hardness: their pressure is H), @p plastic_volume the volume the substrate has lost to plastic
 * flow since it was set (the sum of the original minus the current heights times the area per
 * point).  Both 0 without hardness.  Either pointer may be NULL.
 */
GFMD_API int32_t gfmd_get_plasticity(const gfmd_sim *s, double *plastic_area, double *plastic_volume);

/* ---------------------------------------------------------------- how the contact is made */

/**
 * Connected-component labelling of a set of grid points: the points with mask[i] != 0 on an
 * nx x ny grid (x fastest).  labels[i] receives 0 outside the set and 1..npatches inside,
 * numbered in the order of each patch's first point (index ix + nx*iy ascending): the labels are
 * a function of the set alone.  @p connectivity 4 joins points that share an edge, 8 also the
 * diagonal neighbours; @p periodic nonzero wraps the grid around in both directions (a patch
 * across the border is one patch).  A pure function of its arguments, no handle.
 * @return GFMD_ERR_NULL for a NULL mask, labels or npatches; GFMD_ERR_INVALID_ARG for nx, ny < 1
 *         or a connectivity other than 4 and 8; GFMD_ERR_NOMEM if the search does not fit.
 */
GFMD_API int32_t gfmd_label_patches(int64_t nx, int64_t ny, const int32_t *mask, int32_t connectivity,
                                    int32_t periodic, int64_t *labels, int64_t *npatches);

/**
 * The contact patches of the current configuration: gfmd_label_patches() of the points in contact
 * (zero gap, those gfmd_get_contact_area() counts), periodic.  @p labels (nx*ny) may be NULL to
 * count only.  On a handle distributed over several ranks labels must be NULL (each rank's rows:
 * gfmd_mpi_get_local_contact_patches()); the count, gfmd_get_patch_property() and
 * gfmd_get_pressure_histogram() work there, the same on every rank and at any number of ranks
 * (the contact set is gathered on every rank: 9 B per point of the whole grid, 17 B with the
 * pressure; GFMD_ERR_NOMEM on every rank if that does not fit on one).
 */
GFMD_API int32_t gfmd_get_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels,
                                          int64_t *npatches);

/**
 * One property (GFMD_PATCH_*) of every contact patch, in label order (values[k] for label k+1):
 * points, area, edge count (the lattice perimeter: edges between a patch point and an edge
 * neighbour out of contact), perimeter (the edges' length times pi/4, the mean ratio of a randomly
 * oriented curve's length to its staircase's on a square grid), centroid x / y (the mean of the
 * patch's positions unwrapped across the periodic border, folded into [0, lx) x [0, ly); a patch
 * that wraps around the whole cell gets the mean of one unwrapping, from its first point), load
 * (the pressure of gfmd_get_pressure() summed over the patch, times the area per point).
 * @p values has room for @p capacity patches (NULL with capacity 0 to count only).
 * @param npatches receives the number of patches.
 * @return GFMD_ERR_TRUNCATED if npatches > capacity (the first capacity values written).
 */
GFMD_API int32_t gfmd_get_patch_property(const gfmd_sim *s, int32_t connectivity, int32_t property, int64_t capacity,
                                         double *values, int64_t *npatches);

/**
 * The distribution of the contact pressure: the points in contact binned by their pressure
 * (gfmd_get_pressure()) into @p nbins equal bins on [range[0], range[1]] (pressures beyond it in
 * the end bins).  fraction[b] = the bin's points / (nx ny), mean[b] = the mean pressure of its
 * points (0 for an empty bin): sum fraction = A/A0 and sum fraction[b] mean[b] = the mean of the
 * pressure over the contact, which equals sigma0 at equilibrium without adhesion.  The density
 * of P(p) is fraction[b] / bin width.
 * @param range in: [lo, hi], finite with lo < hi, or {0, 0} for the contact's own range; out: the
 *        range used.
 */
GFMD_API int32_t gfmd_get_pressure_histogram(const gfmd_sim *s, int64_t nbins, double *range, double *fraction,
                                             double *mean);

/**
 * Persson's distribution of the contact pressure at external pressure @p sigma0, per unit area
 * of the cell (J. Chem. Phys. 115, 3840 (2001), the diffusion in p with the absorbing boundary
 * P(0) = 0 of the non-adhesive contact): P(p) = N(p - sigma0) - N(p + sigma0) for p >= 0, 0 below,
 * N the normal density of variance V (gfmd_persson_variance(), the handle's body).  It integrates
 * to gfmd_persson_contact_area(sigma0) and its first moment is sigma0.  Evaluated at the @p n
 * pressures @p p into @p density.
 * @param sigma0 finite and >= 0; p finite.
 */
GFMD_API int32_t gfmd_persson_pressure_distribution(const gfmd_sim *s, double sigma0, int64_t n, const double *p,
                                                    double *density);

/* ---------------------------------------------------------------- theory and analysis */

/**
 * Persson's contact mechanics theory (non-adhesive) for this handle's substrate and body: the
 * variance V of the pressure the body would carry in full contact,
 * V = sum over q != 0 of |h(q)|^2 / G(q)^2 (full plane, h(q) the Fourier coefficients normalized so
 * that sum_q |h(q)|^2 = <h^2>), with the handle's G(q) (half-space or layer).  For a half-space,
 * V = (E* g / 2)^2 with g the rms gradient.  Does not change the handle's state; V is computed
 * at the first call after the substrate or the body changed (one FFT, into the handle's own
 * transform scratch: no memory is allocated, so it cannot fail for want of memory) and kept with
 * them, so later calls -- and the automatic solver choice at each change of load -- reuse it.
 * @return GFMD_ERR_RANGE if V overflows double precision.
 */
GFMD_API int32_t gfmd_persson_variance(const gfmd_sim *s, double *variance);

/**
 * Persson's relative contact area at external pressure @p sigma0 (not the handle's own load, so a
 * whole theory curve can be drawn without touching the simulation):
 * A/A0 = erf(sigma0 / sqrt(2 V)), V from gfmd_persson_variance(); 1 for a flat substrate (V = 0)
 * under a positive load.  Small loads give A/A0 = sqrt(8/pi) sigma0/(E* g) for the half-space.
 * @param sigma0 finite and >= 0.
 */
GFMD_API int32_t gfmd_persson_contact_area(const gfmd_sim *s, double sigma0, double *rel_area);

/**
 * The inverse of gfmd_persson_contact_area(): the external pressure at which Persson's relative
 * contact area is @p rel_area, sigma0 = sqrt(2 V) x with erf(x) = rel_area (x by bisection to
 * the last bit: erf for rel_area <= 1/2, erfc(x) = 1 - rel_area above, so that areas near 1 keep
 * their digits).  A load sweep at chosen Persson areas (as the study's) takes its loads from here.
 * Does not change the handle's state; V as in gfmd_persson_variance().
 * @param rel_area finite, in [0, 1) (0 gives 0).
 * @return GFMD_ERR_INVALID_ARG for rel_area outside [0, 1) or not finite, GFMD_ERR_STATE for a
 *         flat substrate (V = 0: full contact under any positive load) with rel_area > 0.
 */
GFMD_API int32_t gfmd_persson_load(const gfmd_sim *s, double rel_area, double *sigma0);

/**
 * Linear least squares: the x (n values) minimizing ||A x - b||_2 for an m x n matrix A of full
 * column rank, m >= n >= 1, solved by QR (LAPACKE_dgels).  @p a is column major (element (i, j) at
 * a[i + j*m]) and, like @p b, is not modified.  Fits of a line or a power law are one column of
 * ones and one of x (or ln x) values.
 * @param rss receives the residual sum of squares ||A x - b||^2 (may be NULL).
 * @return GFMD_ERR_NULL for a NULL a, b or x; GFMD_ERR_INVALID_ARG if m < n, n < 1, m beyond
 *         LAPACK's 32-bit index, an entry is NaN or infinite, or A is rank deficient (x unchanged
 *         then); GFMD_ERR_NOMEM if the work copies cannot be allocated.
 */
GFMD_API int32_t gfmd_least_squares(int64_t m, int64_t n, const double *a, const double *b, double *x, double *rss);

/* ---------------------------------------------------------------- measured topographies */

/** Opaque topography handle: a grid of heights read from an instrument's file (or given). */
typedef struct gfmd_topo gfmd_topo;

/** 1 if this build reads files of @p format (GFMD_TOPO_*), 0 if not: GFMD_TOPO_X3P needs a build
 *  with libzip and libxml2 (docs/topography.md); unknown formats 0. */
GFMD_API int32_t gfmd_topo_format_supported(int32_t format);

/**
 * Read a topography from @p path: a text matrix or x y z listing, a Gwyddion simple field (.gsf),
 * an ISO 25178-71 / BCR surface data file (.sdf, text or binary) or a numpy .npy array
 * (GFMD_TOPO_*; GFMD_TOPO_AUTO detects the format from the content, docs/topography.md).  The
 * heights are nx x ny, x fastest (a scan's rows along x), NaN at missing points.  Lengths in
 * physical units (SDF, GSF with units, a text matrix with Gwyddion's "# Width:" header) are
 * converted to the caller's unit, @p unit metres long (1e-6: micrometres); a file without units
 * (.npy, a bare matrix, x y z) keeps its numbers and has a spacing of 1 (see
 * gfmd_topo_get_info(), gfmd_topo_set_physical_size()).  The caller's buffer receives the message
 * of a failure.
 * @return GFMD_ERR_IO if the file cannot be read; GFMD_ERR_FORMAT with what was expected and where
 *         (line, byte offset) if its content is not valid in the format (truncated, a header that
 *         declares more data than the file holds, wrong magic, an infinite value); nothing is
 *         allocated beyond what the file's length holds.  GFMD_ERR_INVALID_ARG for a bad unit.
 */
GFMD_API int32_t gfmd_topo_read(const char *path, int32_t format, double unit, gfmd_topo **out, char *errbuf,
                                int64_t errlen);

/** A topography of the caller's heights (nx x ny, x fastest, NaN = missing) on lx x ly. */
GFMD_API int32_t gfmd_topo_from_heights(int64_t nx, int64_t ny, double lx, double ly, const double *h,
                                        gfmd_topo **out);

/** Free a topography and set *t to NULL; NULL and *t == NULL are no-ops. */
GFMD_API void gfmd_topo_destroy(gfmd_topo **t);

/** The message of the last failed call on @p t, as gfmd_last_error(). */
GFMD_API int32_t gfmd_topo_last_error(const gfmd_topo *t, char *buf, int64_t len);

/** Grid size and physical size (the caller's unit).  Any output pointer may be NULL. */
GFMD_API int32_t gfmd_topo_get_grid(const gfmd_topo *t, int64_t *nx, int64_t *ny, double *lx, double *ly);

/**
 * Where the topography came from: @p format the GFMD_TOPO_* read (GFMD_TOPO_AUTO: given by the
 * caller), @p has_units 1 if the file gave physical units (converted to the caller's), 0 if its
 * numbers were taken as they are; @p missing the count of missing (NaN) points.  Any output
 * pointer may be NULL.
 */
GFMD_API int32_t gfmd_topo_get_info(const gfmd_topo *t, int32_t *format, int32_t *has_units, int64_t *missing);

/** Set the physical size (a file without units); finite and > 0. */
GFMD_API int32_t gfmd_topo_set_physical_size(gfmd_topo *t, double lx, double ly);

/** Copy the nx x ny heights (x fastest, NaN at missing points) into @p h. */
GFMD_API int32_t gfmd_topo_get_heights(const gfmd_topo *t, double *h);

/**
 * Fill the missing points (GFMD_FILL_NEAREST: the nearest measured point's value;
 * GFMD_FILL_LAPLACE: the harmonic interpolation, the measured points fixed and no flux through the
 * scan's border).  @return GFMD_ERR_STATE if every point is missing.
 */
GFMD_API int32_t gfmd_topo_fill_missing(gfmd_topo *t, int32_t method);

/**
 * Subtract the least-squares fit of the measured points by a constant (GFMD_DETREND_HEIGHT), a
 * plane (GFMD_DETREND_PLANE) or a second-order polynomial (GFMD_DETREND_CURVATURE); missing
 * points stay missing.
 */
GFMD_API int32_t gfmd_topo_detrend(gfmd_topo *t, int32_t mode);

/**
 * Resample onto nx x ny points (>= 2 a side) by Keys' cubic convolution (a = -1/2, separable: exact
 * for polynomials up to second order away from the border, whose samples are continued as
 * constants).  The new samples span the old ones' extent, first to last: the spacing becomes
 * (n_old - 1)/(n_new - 1) of the old, and lx = nx times it.  The grid a solver wants (a power of
 * two, a finer one) from a scan's.  @return GFMD_ERR_STATE if points are missing (fill them first).
 */
GFMD_API int32_t gfmd_topo_resample(gfmd_topo *t, int64_t nx, int64_t ny);

/**
 * The radially averaged power spectral density C(q) = lx ly / (2 pi)^2 <|h_q|^2> (h_q the
 * normalized Fourier coefficients, h(r) = sum_q h_q e^{iqr}, of the mean-free heights, after the
 * window), averaged over @p nbins bins of |q| spaced evenly in ln q from the smallest to the
 * largest nonzero wavevector of the grid: q[k] the modes' mean |q|, c[k] their mean C(q), count[k]
 * how many modes of the full plane fell in the bin (an empty bin: its centre, C = 0, count 0).
 * Parseval: sum_k count[k] c[k] (2 pi)^2 / (lx ly) is the variance of the (windowed) heights.
 * @p count may be NULL.  @return GFMD_ERR_STATE if points are missing (fill them first).
 */
GFMD_API int32_t gfmd_topo_psd(const gfmd_topo *t, int32_t window, int64_t nbins, double *q, double *c,
                               int64_t *count);

/**
 * The profiles' PSD along x, averaged over the ny rows: C1(q) = lx / (2 pi) <|h_k|^2> at
 * q = 2 pi k / lx, k = 0..nx/2 (nx/2 + 1 values; @p capacity room for them), each row mean-free
 * (and windowed along x): sum over k of w_k C1 (2 pi / lx) is the profiles' mean variance, w_k = 2
 * but for k = 0 and the Nyquist mode (1).  @param n receives nx/2 + 1.
 * @return GFMD_ERR_TRUNCATED if capacity < nx/2 + 1 (the first capacity values written).
 */
GFMD_API int32_t gfmd_topo_profile_psd(const gfmd_topo *t, int32_t window, int64_t capacity, double *q, double *c,
                                       int64_t *n);

/**
 * The spectrum's moments (every mode, not the bins): rms height sqrt(sum |h_q|^2), rms slope
 * sqrt(sum q^2 |h_q|^2) and rms curvature sqrt(sum q^4 |h_q|^2) / 2 (of the mean curvature
 * laplacian(h) / 2), of the mean-free, windowed heights.  Any output pointer may be NULL.
 */
GFMD_API int32_t gfmd_topo_moments(const gfmd_topo *t, int32_t window, double *rms_height, double *rms_slope,
                                   double *rms_curvature);

/**
 * Persson's relative contact area erf(sigma0 / sqrt(2 V)) of the topography pressed on a body
 * (GFMD_GREEN_*, with its width and nu as gfmd_set_green() / gfmd_set_poisson(), contact modulus
 * e_star), V = sum_q |h_q|^2 (q E* / (2 f(q w)))^2 from the topography's own spectrum (windowed);
 * @p variance (may be NULL) receives V.  The same as gfmd_persson_contact_area() of a simulation
 * whose heights are the topography's (periodic scans, GFMD_WINDOW_NONE).
 */
GFMD_API int32_t gfmd_topo_persson_contact_area(const gfmd_topo *t, int32_t window, int32_t kind, double width,
                                                double nu, double e_star, double sigma0, double *rel_area,
                                                double *variance);

/**
 * Persson's mean gap u(sigma0) of the topography pressed on a body (the arguments as
 * gfmd_topo_persson_contact_area(), sigma0 > 0): Yang & Persson's theory (J. Phys.: Condens.
 * Matter 20, 215214 (2008), Eq. 2), u = sum_q |h_q|^2 k(q) J(sigma0 / sqrt(2 V(q))) / (2 sqrt(2 V(q))) with
 * k(q) = q E* / (2 f(q w)), V(q) the full-contact pressure variance of the modes up to |q| and
 * J(s) = (2/sqrt(pi)) int_s^inf dt/t [gamma + 3 (1 - gamma) erf(t)^2] exp(-t^2); on a half-space
 * the paper's integrals become the grid's sums.  @p gamma in [0, 1] is the theory's
 * elastic-energy factor (< 0: the paper's 0.45).  The mean gap grows as -ln(sigma0) at low loads
 * and vanishes at high ones (docs/topography.md).
 */
GFMD_API int32_t gfmd_topo_persson_mean_gap(const gfmd_topo *t, int32_t window, int32_t kind, double width,
                                            double nu, double e_star, double sigma0, double gamma, double *mean_gap);

#ifdef __cplusplus
}
#endif

#endif /* GFMD_H */
