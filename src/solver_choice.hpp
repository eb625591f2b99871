// GFMD_SOLVER_AUTO's rule: a pure function from a few named features of the problem to the solver
// that relaxes it fastest, as measured with gfmd_bench (docs/decisions.md, "The default solver").
// The simulation computes the features (Simulation::choice_features) and follows the choice.
#ifndef GFMD_SRC_SOLVER_CHOICE_HPP
#define GFMD_SRC_SOLVER_CHOICE_HPP

#include <cstdint>

namespace gfmd {

struct ChoiceFeatures {
    bool free_boundary = false;      // free boundaries (the padded cell): only CG, FIRE and Verlet step there
    int32_t body = 0;                // GFMD_GREEN_*
    bool adhesive = false;           // gamma0 > 0
    bool plastic = false;            // a finite hardness: only FIRE and Verlet take its yielding wall
    bool pressure_control = true;    // false: the mean position is prescribed
    double points = 0.0;             // nx ny
    double softness = 0.0;           // S = k_halfspace(q_max) / k_min: the long waves' softness
    double longest_wave = 1.0;       // f(q_min w) = k_halfspace(q_min) / k(q_min)
    double grid_thickness = 0.0;     // q_max w, q_max = pi sqrt(2)/a: the width against the grid
    double rough_thickness = 0.0;    // 2 sqrt(2) q_s w: the width against the substrate's shortest wave
    double persson_area = 0.0;       // Persson's A/A0 at sigma0 (pressure control; 0 without load)
    double overlap = 0.0;            // displacement control: the fraction of h above the mean position
    bool flat = true;                // the surface is flat (no load carried yet: a first load; fluid layers)
    bool newton_grid = false;        // the Newton method takes this grid (square, power of 2, one rank)
};

// The thresholds, one line each: what is compared, and why the bound lies there (the measured
// crossover of the two solvers it separates; docs/decisions.md has the figures).
struct ChoiceRule {
    // pressure control, no adhesion, half-space and bonded layer: Polonsky-Keer CG or FIRE
    double cg_cost = 4e4;              // S sqrt(N): CG's iterations grow with it; faster below
    double cg_cost_bonded = 8e4;       // S sqrt(N) on a bonded layer: its iterations grow less
    double cg_dense = 14.0;            // S A/A0: CG's iterations grow with the contact set
    double cg_low_load = 20.0;         // A/A0 sqrt(N): at few contacts CG wins beyond its cost bound
    // pressure control, no adhesion, layer on a fluid foundation: surface CG unless a deformed start
    double continue_points = 2048.0 * 2048.0;  // N from which a continuing load leaves the CG
    double thin = 6.0;                 // q_max w below which the sheet is thinner than the grid resolves
    double thin_soft_points = 128.0 * 128.0;   // N from which the thin soft sheets leave the CG
    double thin_soft_wave = 1e6;       // f(q_min w) of those sheets
    double thin_soft_rough = 4.5;      // 2 sqrt(2) q_s w of those sheets
    double middle_wave = 1e4;          // f(q_min w) from which a resolved layer keeps the CG
    double continue_fire_area = 0.04;  // A/A0 from which a thick layer's continuing load takes FIRE
    double mass_area = 0.15;           // A/A0 q_max w below which a thin sheet takes mass-weighted FIRE
    double approach_area = 0.15;       // A/A0 above which the approach then FIRE no longer pays
    // the Newton method, with and without adhesion
    double newton_points = 1024.0 * 1024.0;  // N from which it beats FIRE on the thin sheets
    double newton_area = 0.45;         // A/A0 below which it does (the last measured load, 0.4, and a margin)
    double newton_flat_area = 0.05;    // A/A0 below which it wins a thin sheet's first load from flat
    // pressure control with adhesion, layer on a fluid foundation
    double adhesive_thin = 6.0;        // min(q_max w, 2 sqrt(2) q_s w) below which the adhesive CG loses
    double adhesive_thinner = 4.0;     // the same, below which mass weighting wins at every low load
    double adhesive_soft_wave = 2e4;   // f(q_min w) from which the approach (and Newton) pay
    double adhesive_low_area = 0.1;    // A/A0 below which they do
    double adhesive_mass_area = 0.02;  // A/A0 below which mass weighting beats the approach
    // displacement control
    double displacement_cg_cost = 2e5;  // S sqrt(N) below which the surface CG wins (no adhesion)
    double displacement_mass_wave = 2.0;  // f(q_min w) from which mass weighting beats FIRE
    double displacement_overlap = 0.35;   // overlap from which FIRE wins again (contacts pin the waves)
    double displacement_overlap_stiff = 0.25;  // the same where f(q_min w) < 1e4
    double displacement_stiff_wave = 1e4;      // that f(q_min w)
};

inline constexpr ChoiceRule kChoiceRule{};

// The solver GFMD_SOLVER_AUTO takes for a problem with these features (never GFMD_SOLVER_AUTO).
int32_t choose_solver(const ChoiceFeatures &f, const ChoiceRule &rule = kChoiceRule);

}  // namespace gfmd

#endif
