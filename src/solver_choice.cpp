#include "solver_choice.hpp"

#include <algorithm>
#include <cmath>

#include "gfmd.h"

namespace gfmd {

namespace {

// Displacement control: the surface CG where the long waves are stiff enough, else mass-weighted
// FIRE on a soft layer on a fluid foundation away from the substrate, FIRE otherwise.
int32_t under_displacement(const ChoiceFeatures &f, const ChoiceRule &r, double cg_cost) {
    if (!f.adhesive && cg_cost <= r.displacement_cg_cost) return GFMD_SOLVER_CG;
    if (f.body != GFMD_GREEN_LAYER_FLUID || f.longest_wave < r.displacement_mass_wave) return GFMD_SOLVER_FIRE;
    const bool near = f.overlap >= r.displacement_overlap ||
                      (f.overlap >= r.displacement_overlap_stiff && f.longest_wave < r.displacement_stiff_wave);
    return near ? GFMD_SOLVER_FIRE : GFMD_SOLVER_MASS_WEIGHTED_FIRE;
}

bool newton_takes(const ChoiceFeatures &f, const ChoiceRule &r) {
    return f.newton_grid && f.points >= r.newton_points && f.persson_area < r.newton_area;
}

// A thin sheet's first load from flat at few contacts: the Newton method, whose steps hardly grow
// in number as the contacts thin out, where the CG's and FIRE's do (from the grids on which the
// thin sheets leave the CG).
bool newton_from_flat(const ChoiceFeatures &f, const ChoiceRule &r) {
    return f.flat && f.newton_grid && f.points >= r.thin_soft_points && f.persson_area > 0.0 &&
           f.persson_area < r.newton_flat_area;
}

// A layer on a fluid foundation under pressure control without adhesion: the preconditioned
// surface CG, but on a thin sheet's first load at few contacts the Newton method, and on a load
// that continues from a deformed surface on large grids (and on thin soft sheets from 128^2 on)
// FIRE's family or the Newton method.
int32_t fluid_layer(const ChoiceFeatures &f, const ChoiceRule &r) {
    const bool thin = f.grid_thickness < r.thin;
    const bool thin_soft = thin && f.points >= r.thin_soft_points && f.longest_wave >= r.thin_soft_wave &&
                           f.rough_thickness < r.thin_soft_rough;
    if (thin && newton_from_flat(f, r)) return GFMD_SOLVER_NEWTON;
    if (!(f.points >= r.continue_points || thin_soft) || f.flat) return GFMD_SOLVER_CG;
    if (!thin) {
        if (f.longest_wave >= r.middle_wave) return GFMD_SOLVER_CG;
        return f.persson_area < r.continue_fire_area ? GFMD_SOLVER_CG : GFMD_SOLVER_FIRE;
    }
    if (newton_takes(f, r)) return GFMD_SOLVER_NEWTON;
    const double mass_area = r.mass_area / f.grid_thickness;
    if (f.persson_area < mass_area) return GFMD_SOLVER_MASS_WEIGHTED_FIRE;
    return f.persson_area < std::min(2.0 * mass_area, r.approach_area) ? GFMD_SOLVER_APPROACH_THEN_FIRE
                                                                        : GFMD_SOLVER_FIRE;
}

// The same with adhesion: the adhesive CG unless the sheet is thinner than the grid or the
// roughness resolves; those take the Newton method, mass weighting or the approach then FIRE at
// low loads where their longest wave is soft, FIRE otherwise.
int32_t adhesive_fluid_layer(const ChoiceFeatures &f, const ChoiceRule &r) {
    const double thickness = std::min(f.grid_thickness, f.rough_thickness);
    if (thickness >= r.adhesive_thin) return GFMD_SOLVER_CG;
    const bool soft = f.longest_wave >= r.adhesive_soft_wave;
    if (soft && (f.flat ? newton_from_flat(f, r) : newton_takes(f, r))) return GFMD_SOLVER_NEWTON;
    if (!soft || !(f.persson_area < r.adhesive_low_area)) return GFMD_SOLVER_FIRE;
    const bool mass = thickness < r.adhesive_thinner || f.persson_area < r.adhesive_mass_area;
    return mass ? GFMD_SOLVER_MASS_WEIGHTED_FIRE : GFMD_SOLVER_APPROACH_THEN_FIRE;
}

}  // namespace

int32_t choose_solver(const ChoiceFeatures &f, const ChoiceRule &r) {
    if (f.free_boundary) return GFMD_SOLVER_CG;  // Polonsky-Keer's CG (docs/decisions.md, "Free boundaries")
    if (f.plastic) return GFMD_SOLVER_FIRE;  // the one general solver that takes the yielding wall
    const double cg_cost = f.softness * std::sqrt(f.points);
    if (!f.pressure_control) return under_displacement(f, r, cg_cost);
    if (f.body == GFMD_GREEN_LAYER_FLUID) return f.adhesive ? adhesive_fluid_layer(f, r) : fluid_layer(f, r);
    // half-space and bonded layer: the adhesive surface CG, or Polonsky-Keer's CG within its cost
    // at sparse contacts and at low loads, FIRE otherwise
    if (f.adhesive || !(f.persson_area > 0.0)) return GFMD_SOLVER_CG;
    const double bound = (f.body == GFMD_GREEN_LAYER_BONDED) ? r.cg_cost_bonded : r.cg_cost;
    if (cg_cost <= bound && f.softness * f.persson_area < r.cg_dense) return GFMD_SOLVER_CG;
    return f.persson_area * std::sqrt(f.points) < r.cg_low_load ? GFMD_SOLVER_CG : GFMD_SOLVER_FIRE;
}

}  // namespace gfmd
