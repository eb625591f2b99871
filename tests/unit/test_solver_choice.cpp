// GFMD_SOLVER_AUTO's rule (src/solver_choice.cpp) as a function: a table of feature sets and the
// solver each must get, with every threshold of ChoiceRule met from both sides.  Each row starts
// from a base problem of its region and moves one feature across one bound, so that a rule whose
// bound moved, or whose comparison flipped (< for <=), fails the row on one side.  "Just below" and
// "just above" are the bound times (1 -+ 1e-9): the features are measured doubles, and the rule
// compares them with its bounds directly.  The choices on real problems (features computed by the
// library from its fields) are test_api's automatic_choice_* and the benchmark's --choices.
#include <cmath>
#include <cstdio>
#include <vector>

#include "gfmd.h"
#include "solver_choice.hpp"

namespace {

using gfmd::ChoiceFeatures;
using gfmd::kChoiceRule;
const gfmd::ChoiceRule &R = kChoiceRule;

double below(double bound) { return bound * (1.0 - 1e-9); }
double above(double bound) { return bound * (1.0 + 1e-9); }

const char *name(int32_t s) {
    switch (s) {
    case GFMD_SOLVER_VERLET: return "VERLET";
    case GFMD_SOLVER_FIRE: return "FIRE";
    case GFMD_SOLVER_MASS_WEIGHTED_FIRE: return "MASS_WEIGHTED_FIRE";
    case GFMD_SOLVER_CG: return "CG";
    case GFMD_SOLVER_APPROACH_THEN_FIRE: return "APPROACH_THEN_FIRE";
    case GFMD_SOLVER_NEWTON: return "NEWTON";
    default: return "?";
    }
}

struct Row {
    const char *what;
    ChoiceFeatures f;
    int32_t expected;
};

// softness S for a given S sqrt(N)
double softness_for(double cg_cost, double points) { return cg_cost / std::sqrt(points); }

// A half-space at 256^2 under pressure control, no adhesion, a light load.
ChoiceFeatures halfspace(double points = 256.0 * 256.0) {
    ChoiceFeatures f;
    f.body = GFMD_GREEN_HALFSPACE;
    f.points = points;
    f.softness = 0.7 * std::sqrt(points);
    f.persson_area = 0.01;
    f.flat = false;
    return f;
}

// A thin sheet on a fluid foundation at 2048^2, deformed (a continuing load), no adhesion.
ChoiceFeatures thin_sheet() {
    ChoiceFeatures f;
    f.body = GFMD_GREEN_LAYER_FLUID;
    f.points = 2048.0 * 2048.0;
    f.softness = 1e9;
    f.longest_wave = 1e8;
    f.grid_thickness = 1.0;
    f.rough_thickness = 1.0;
    f.persson_area = 0.1;
    f.flat = false;
    f.newton_grid = true;
    return f;
}

// A thick layer (resolved by the grid) on a fluid foundation, stiff long wave, deformed, 2048^2.
ChoiceFeatures thick_layer() {
    ChoiceFeatures f = thin_sheet();
    f.grid_thickness = 100.0;
    f.rough_thickness = 100.0;
    f.longest_wave = 4.0;
    f.persson_area = 0.01;
    return f;
}

// An adhesive thin sheet at 2048^2 on a grid the Newton method does not take, low load.
ChoiceFeatures adhesive_sheet() {
    ChoiceFeatures f = thin_sheet();
    f.adhesive = true;
    f.newton_grid = false;
    f.grid_thickness = 5.0;
    f.rough_thickness = 5.0;
    f.persson_area = 0.05;
    return f;
}

// A layer on a fluid foundation under displacement control, soft, far from the substrate.
ChoiceFeatures displaced_layer() {
    ChoiceFeatures f;
    f.body = GFMD_GREEN_LAYER_FLUID;
    f.pressure_control = false;
    f.points = 256.0 * 256.0;
    f.softness = 1e6;
    f.longest_wave = 1e3;
    f.grid_thickness = 20.0;
    f.rough_thickness = 20.0;
    f.overlap = 0.1;
    return f;
}

template <class Change>
ChoiceFeatures with(ChoiceFeatures f, Change &&change) {
    change(f);
    return f;
}

std::vector<Row> rows() {
    const double n256 = 256.0 * 256.0, n1024 = 1024.0 * 1024.0;
    std::vector<Row> t;
    auto add = [&](const char *what, ChoiceFeatures f, int32_t s) { t.push_back({what, f, s}); };

    // half-space and bonded layer, no adhesion
    add("half-space without load", with(halfspace(), [](ChoiceFeatures &f) { f.persson_area = 0.0; }), GFMD_SOLVER_CG);
    add("half-space adhesive", with(halfspace(), [](ChoiceFeatures &f) { f.adhesive = true; f.persson_area = 0.5; }),
        GFMD_SOLVER_CG);
    // a hardness: FIRE, whatever else (the CG's row above without it)
    add("half-space without load, plastic", with(halfspace(), [](ChoiceFeatures &f) {
            f.persson_area = 0.0; f.plastic = true; }), GFMD_SOLVER_FIRE);
    // cg_cost: within it CG (S A/A0 small); beyond it and at many contacts FIRE
    // (A/A0 sqrt(N) just beyond cg_low_load, S A/A0 below cg_dense: the cost bound decides)
    const auto dense_load = [&](ChoiceFeatures &f) { f.persson_area = 1.05 * R.cg_low_load / std::sqrt(f.points); };
    add("cg_cost: just below", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            dense_load(f); f.softness = softness_for(below(R.cg_cost), f.points); }), GFMD_SOLVER_CG);
    add("cg_cost: just above", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            dense_load(f); f.softness = softness_for(above(R.cg_cost), f.points); }), GFMD_SOLVER_FIRE);
    add("cg_cost_bonded: just below", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            f.body = GFMD_GREEN_LAYER_BONDED; dense_load(f);
            f.softness = softness_for(below(R.cg_cost_bonded), f.points); }), GFMD_SOLVER_CG);
    add("cg_cost_bonded: just above", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            f.body = GFMD_GREEN_LAYER_BONDED; dense_load(f);
            f.softness = softness_for(above(R.cg_cost_bonded), f.points); }), GFMD_SOLVER_FIRE);
    // cg_dense: S A/A0 within the cost bound (S = 100 at 256^2: S sqrt(N) = 2.56e4)
    add("cg_dense: just below", with(halfspace(), [&](ChoiceFeatures &f) {
            f.softness = 100.0; f.persson_area = below(R.cg_dense) / 100.0; }), GFMD_SOLVER_CG);
    add("cg_dense: just above", with(halfspace(), [&](ChoiceFeatures &f) {
            f.softness = 100.0; f.persson_area = above(R.cg_dense) / 100.0; }), GFMD_SOLVER_FIRE);
    // cg_low_load: beyond the cost bound, A/A0 sqrt(N)
    add("cg_low_load: just below", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            f.persson_area = below(R.cg_low_load) / 1024.0; }), GFMD_SOLVER_CG);
    add("cg_low_load: just above", with(halfspace(n1024), [&](ChoiceFeatures &f) {
            f.persson_area = above(R.cg_low_load) / 1024.0; }), GFMD_SOLVER_FIRE);

    // layer on a fluid foundation, no adhesion
    add("fluid layer, first load", with(thin_sheet(), [](ChoiceFeatures &f) { f.flat = true; }), GFMD_SOLVER_CG);
    // newton_flat_area: a thin sheet's first load at few contacts, from thin_soft_points on
    const auto few = [&](ChoiceFeatures &f) { f.flat = true; f.persson_area = below(R.newton_flat_area); };
    add("newton_flat_area: just below", with(thin_sheet(), few), GFMD_SOLVER_NEWTON);
    add("newton_flat_area: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.flat = true; f.persson_area = R.newton_flat_area; }), GFMD_SOLVER_CG);
    add("newton_flat_area: no load", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.flat = true; f.persson_area = 0.0; }), GFMD_SOLVER_CG);
    add("newton_flat_area: below thin_soft_points", with(with(thin_sheet(), few), [&](ChoiceFeatures &f) {
            f.points = below(R.thin_soft_points); }), GFMD_SOLVER_CG);
    add("newton_flat_area: a grid Newton does not take", with(with(thin_sheet(), few), [](ChoiceFeatures &f) {
            f.newton_grid = false; }), GFMD_SOLVER_CG);
    add("newton_flat_area: not thin", with(with(thin_sheet(), few), [&](ChoiceFeatures &f) {
            f.grid_thickness = R.thin; }), GFMD_SOLVER_CG);
    add("thin sheet below continue_points, not soft", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.points = below(R.continue_points); f.longest_wave = below(R.thin_soft_wave); }), GFMD_SOLVER_CG);
    // thin soft sheets below continue_points: each of the four conditions on its own
    const auto small_soft = [&](ChoiceFeatures &f) {
        f.points = n256; f.longest_wave = R.thin_soft_wave; f.persson_area = 0.01; };
    add("thin_soft: all met", with(thin_sheet(), small_soft), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("thin_soft_points: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.points = below(R.thin_soft_points); }), GFMD_SOLVER_CG);
    add("thin_soft_points: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.points = R.thin_soft_points; }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("thin_soft_wave: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.longest_wave = below(R.thin_soft_wave); }), GFMD_SOLVER_CG);
    add("thin_soft_rough: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.rough_thickness = below(R.thin_soft_rough); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("thin_soft_rough: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.rough_thickness = R.thin_soft_rough; }), GFMD_SOLVER_CG);
    add("continue_points: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.points = R.continue_points; f.longest_wave = 1.0; f.newton_grid = false; f.persson_area = 0.01; }),
        GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    // thin: q_max w on either side (a light continuing load: mass weighting on a thin sheet, CG on a thick layer)
    add("thin: just below, light load", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.grid_thickness = below(R.thin); f.persson_area = 0.01; f.newton_grid = false; }),
        GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("thin: at it, light load", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.grid_thickness = R.thin; f.persson_area = 0.01; }), GFMD_SOLVER_CG);
    add("middle_wave: just below", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = below(R.middle_wave); f.persson_area = 0.3; }), GFMD_SOLVER_FIRE);
    add("middle_wave: at it", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = R.middle_wave; f.persson_area = 0.3; }), GFMD_SOLVER_CG);
    add("continue_fire_area: just below", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.persson_area = below(R.continue_fire_area); }), GFMD_SOLVER_CG);
    add("continue_fire_area: at it", with(thick_layer(), [&](ChoiceFeatures &f) {
            f.persson_area = R.continue_fire_area; }), GFMD_SOLVER_FIRE);
    // the Newton method on the thin sheets: its grid, its points, its area
    add("newton_area: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = below(R.newton_area); }), GFMD_SOLVER_NEWTON);
    add("newton_area: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = R.newton_area; }), GFMD_SOLVER_FIRE);
    add("newton_points: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.points = R.newton_points; }), GFMD_SOLVER_NEWTON);
    add("newton_points: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            small_soft(f); f.points = below(R.newton_points); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("newton grid refused", with(thin_sheet(), [](ChoiceFeatures &f) { f.newton_grid = false; }),
        GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    // mass_area / q_max w, then the approach below min(2 mass_area / q_max w, approach_area)
    const auto no_newton = [](ChoiceFeatures &f) { f.newton_grid = false; f.grid_thickness = 2.0; };
    add("mass_area: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.persson_area = below(R.mass_area / 2.0); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("mass_area: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.persson_area = R.mass_area / 2.0; }), GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("twice mass_area: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.grid_thickness = 4.0; f.persson_area = below(2.0 * R.mass_area / 4.0); }),
        GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("twice mass_area: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.grid_thickness = 4.0; f.persson_area = 2.0 * R.mass_area / 4.0; }), GFMD_SOLVER_FIRE);
    add("approach_area: just below", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.grid_thickness = 1.5; f.persson_area = below(R.approach_area); }),
        GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("approach_area: at it", with(thin_sheet(), [&](ChoiceFeatures &f) {
            no_newton(f); f.grid_thickness = 1.5; f.persson_area = R.approach_area; }), GFMD_SOLVER_FIRE);

    // layer on a fluid foundation with adhesion
    add("adhesive_thin: at it (grid)", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.grid_thickness = R.adhesive_thin; f.rough_thickness = 2.0 * R.adhesive_thin; }), GFMD_SOLVER_CG);
    add("adhesive_thin: at it (roughness)", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.rough_thickness = R.adhesive_thin; f.grid_thickness = 2.0 * R.adhesive_thin; }), GFMD_SOLVER_CG);
    add("adhesive_thin: just below (roughness)", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.rough_thickness = below(R.adhesive_thin); f.grid_thickness = 2.0 * R.adhesive_thin; }),
        GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive_thinner: just below", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.grid_thickness = below(R.adhesive_thinner); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("adhesive_thinner: at it", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.grid_thickness = R.adhesive_thinner; f.rough_thickness = R.adhesive_thinner; }),
        GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive_soft_wave: just below", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.longest_wave = below(R.adhesive_soft_wave); }), GFMD_SOLVER_FIRE);
    add("adhesive_soft_wave: at it", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.longest_wave = R.adhesive_soft_wave; }), GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive_low_area: just below", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = below(R.adhesive_low_area); }), GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive_low_area: at it", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = R.adhesive_low_area; }), GFMD_SOLVER_FIRE);
    add("adhesive_mass_area: just below", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = below(R.adhesive_mass_area); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("adhesive_mass_area: at it", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.persson_area = R.adhesive_mass_area; }), GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive Newton: deformed", with(adhesive_sheet(), [](ChoiceFeatures &f) { f.newton_grid = true; }),
        GFMD_SOLVER_NEWTON);
    add("adhesive Newton: flat start", with(adhesive_sheet(), [](ChoiceFeatures &f) {
            f.newton_grid = true; f.flat = true; }), GFMD_SOLVER_APPROACH_THEN_FIRE);
    add("adhesive Newton: flat start below newton_flat_area", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.newton_grid = true; f.flat = true; f.persson_area = below(R.newton_flat_area); }), GFMD_SOLVER_NEWTON);
    add("adhesive Newton: flat start below newton_flat_area, stiff long wave", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.newton_grid = true; f.flat = true; f.persson_area = below(R.newton_flat_area);
            f.longest_wave = below(R.adhesive_soft_wave); }), GFMD_SOLVER_FIRE);
    add("adhesive Newton: newton_area at it", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.newton_grid = true; f.persson_area = R.newton_area; }), GFMD_SOLVER_FIRE);
    add("adhesive Newton: stiff long wave", with(adhesive_sheet(), [&](ChoiceFeatures &f) {
            f.newton_grid = true; f.longest_wave = below(R.adhesive_soft_wave); }), GFMD_SOLVER_FIRE);

    // displacement control
    const auto stiff = [&](ChoiceFeatures &f) { f.body = GFMD_GREEN_HALFSPACE; f.longest_wave = 1.0; };
    add("displacement_cg_cost: at it", with(displaced_layer(), [&](ChoiceFeatures &f) {
            stiff(f); f.softness = softness_for(R.displacement_cg_cost, f.points); }), GFMD_SOLVER_CG);
    add("displacement_cg_cost: just above", with(displaced_layer(), [&](ChoiceFeatures &f) {
            stiff(f); f.softness = softness_for(above(R.displacement_cg_cost), f.points); }), GFMD_SOLVER_FIRE);
    add("displacement CG: adhesive", with(displaced_layer(), [&](ChoiceFeatures &f) {
            stiff(f); f.adhesive = true; f.softness = 1.0; }), GFMD_SOLVER_FIRE);
    add("displacement, bonded layer, soft", with(displaced_layer(), [](ChoiceFeatures &f) {
            f.body = GFMD_GREEN_LAYER_BONDED; }), GFMD_SOLVER_FIRE);
    add("displacement_mass_wave: just below", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = below(R.displacement_mass_wave); }), GFMD_SOLVER_FIRE);
    add("displacement_mass_wave: at it", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = R.displacement_mass_wave; }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("displacement_overlap_stiff: just below", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.overlap = below(R.displacement_overlap_stiff); }), GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("displacement_overlap_stiff: at it", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.overlap = R.displacement_overlap_stiff; }), GFMD_SOLVER_FIRE);
    add("displacement_stiff_wave: at it", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.overlap = R.displacement_overlap_stiff; f.longest_wave = R.displacement_stiff_wave; }),
        GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("displacement_overlap: just below (soft)", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = R.displacement_stiff_wave; f.overlap = below(R.displacement_overlap); }),
        GFMD_SOLVER_MASS_WEIGHTED_FIRE);
    add("displacement_overlap: at it (soft)", with(displaced_layer(), [&](ChoiceFeatures &f) {
            f.longest_wave = R.displacement_stiff_wave; f.overlap = R.displacement_overlap; }), GFMD_SOLVER_FIRE);
    return t;
}

}  // namespace

int main() {
    int failures = 0, checked = 0;
    for (const Row &r : rows()) {
        const int32_t got = gfmd::choose_solver(r.f);
        ++checked;
        if (got != r.expected) {
            ++failures;
            std::printf("FAIL %s: %s, expected %s\n", r.what, name(got), name(r.expected));
        } else {
            std::printf("ok   %s: %s\n", r.what, name(got));
        }
    }
    // The rule is a function of its argument: a different table moves the choice (the default
    // argument is not read behind the caller's back).
    gfmd::ChoiceRule never_cg = kChoiceRule;
    never_cg.cg_cost = 0.0;
    never_cg.cg_low_load = 0.0;
    ChoiceFeatures f = halfspace();
    ++checked;
    if (gfmd::choose_solver(f) != GFMD_SOLVER_CG || gfmd::choose_solver(f, never_cg) != GFMD_SOLVER_FIRE) {
        ++failures;
        std::printf("FAIL a rule passed as argument is not the one applied\n");
    }
    std::printf("%d passed, %d failed\n", checked - failures, failures);
    return failures == 0 ? 0 : 1;
}
