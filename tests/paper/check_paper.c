/* Checks the tables of gfmd_paper (run in its --quick mode by ctest) against the physics the seed
 * paper reports, not against stored numbers:
 *   - every CSV has its documented header;
 *   - A/A0 rises with the load for every body, and with decreasing W at equal load;
 *   - kappa of the half-space (recomputed here by the closed-form least squares through the
 *     origin, and equal to the program's LAPACKE fit) lies in [1.6, 2.6];
 *   - Persson's small-load slope sqrt(8/pi) is within a factor 1.5 of the GFMD kappa, and
 *     Persson's area (its own column) within a factor 1.5 of GFMD at the small-load points;
 *   - c(W) grows as W shrinks; its small-W exponent lies in [-3.5, -2.5];
 *   - theta's small-W exponents lie in [2.5, 3.5].
 * Usage: check_paper DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_ROWS = 4096, MAX_COLS = 16, LINE = 1024 };

typedef struct {
    int rows, cols;
    char body[MAX_ROWS][16];
    double v[MAX_ROWS][MAX_COLS]; /* numeric columns (column 0 is text in most tables) */
} table;

static int failures = 0;

#define EXPECT(cond, ...)                              \
    do {                                               \
        if (!(cond)) {                                 \
            fprintf(stderr, "FAIL: " __VA_ARGS__);     \
            fprintf(stderr, "\n");                     \
            ++failures;                                \
        }                                              \
    } while (0)

static table *read_table(const char *dir, const char *name, const char *header) {
    static table tables[12];
    static int used = 0;
    char path[4096], line[LINE];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "FAIL: cannot open %s\n", path);
        exit(1);
    }
    if (used == 12) {
        fprintf(stderr, "FAIL: too many tables\n");
        exit(1);
    }
    table *t = &tables[used++];
    t->rows = 0;
    if (!fgets(line, sizeof line, f)) line[0] = 0;
    line[strcspn(line, "\r\n")] = 0;
    EXPECT(!strcmp(line, header), "%s: header '%s', documented '%s'", name, line, header);
    t->cols = 1;
    for (const char *c = header; *c; ++c) t->cols += (*c == ',');
    while (fgets(line, sizeof line, f) && t->rows < MAX_ROWS) {
        int col = 0;
        char *save = NULL;
        for (char *tok = strtok_r(line, ",\r\n", &save); tok; tok = strtok_r(NULL, ",\r\n", &save), ++col) {
            if (col >= MAX_COLS) break;
            char *end = NULL;
            t->v[t->rows][col] = strtod(tok, &end);
            if (end == tok) {
                t->v[t->rows][col] = NAN;
                if (col == 0) snprintf(t->body[t->rows], sizeof t->body[0], "%s", tok);
            }
        }
        EXPECT(col == t->cols, "%s row %d: %d fields, expected %d", name, t->rows + 1, col, t->cols);
        t->rows++;
    }
    fclose(f);
    EXPECT(t->rows > 0, "%s has no rows", name);
    return t;
}

static double fit_value(const char *dir, const char *quantity) {
    char path[4096], line[LINE];
    snprintf(path, sizeof path, "%s/fits.csv", dir);
    FILE *f = fopen(path, "r");
    double v = NAN;
    while (f && fgets(line, sizeof line, f)) {
        char *comma = strchr(line, ',');
        if (comma && (size_t)(comma - line) == strlen(quantity) && !strncmp(line, quantity, strlen(quantity)))
            v = strtod(comma + 1, NULL);
    }
    if (f) fclose(f);
    EXPECT(isfinite(v), "fits.csv has no finite '%s'", quantity);
    return v;
}

/* log-log interpolation of area(load) along rows [r0, r1) of fig3; NAN outside */
static double area_at(const table *t, int r0, int r1, double load) {
    for (int r = r0; r + 1 < r1; ++r) {
        const double x0 = t->v[r][3], x1 = t->v[r + 1][3];
        if (load >= x0 && load <= x1) {
            const double s = (log(load) - log(x0)) / (log(x1) - log(x0));
            return exp((1 - s) * log(t->v[r][4]) + s * log(t->v[r + 1][4]));
        }
    }
    return NAN;
}

/* --same-equilibrium A B: two runs of the study that differ only in how each load was relaxed
 * (gfmd_paper --multilevel, --approach): every load's A/A0 within one grid point and mean gap within 1e-4
 * relative (both relax to the default tolerance, 1e-6 in the residual, from other starts), and
 * the first load of at least one body took another number of steps (the other start did run). */
static int same_equilibrium(const char *a_dir, const char *b_dir, double points) {
    const char *header = "body,W,sigma0,sigma0_over_Eg,rel_area,persson_area,mean_gap,separation,u_el,steps,seconds";
    const table *a = read_table(a_dir, "fig3_area.csv", header), *b = read_table(b_dir, "fig3_area.csv", header);
    EXPECT(a->rows == b->rows && a->rows > 0, "fig3_area.csv: %d and %d rows", a->rows, b->rows);
    int other_start = 0;
    for (int r = 0; r < a->rows && r < b->rows; ++r) {
        EXPECT(fabs(a->v[r][4] - b->v[r][4]) <= 1.0 / points + 1e-12, "row %d: A/A0 %.6g and %.6g", r + 1, a->v[r][4],
               b->v[r][4]);
        EXPECT(fabs(a->v[r][6] - b->v[r][6]) <= 1e-4 * fabs(a->v[r][6]), "row %d: mean gap %.8g and %.8g", r + 1,
               a->v[r][6], b->v[r][6]);
        if ((r == 0 || a->v[r][1] != a->v[r - 1][1]) && a->v[r][9] != b->v[r][9]) other_start = 1;
    }
    EXPECT(other_start, "no body's first load took another number of steps: the multilevel start did not run");
    printf("%d loads: the same equilibrium from both starts\n", a->rows);
    return failures ? 1 : 0;
}

int main(int argc, char **argv) {
    if (argc == 5 && !strcmp(argv[1], "--same-equilibrium")) return same_equilibrium(argv[2], argv[3], atof(argv[4]));
    if (argc != 2) {
        fprintf(stderr, "usage: %s DIR | --same-equilibrium DIR_A DIR_B GRID_POINTS\n", argv[0]);
        return 2;
    }
    const char *dir = argv[1];
    const table *f3 = read_table(dir, "fig3_area.csv",
                                 "body,W,sigma0,sigma0_over_Eg,rel_area,persson_area,mean_gap,separation,u_el,steps,seconds");
    read_table(dir, "fig4_area_complement.csv", "body,W,sigma0_over_Eg,rel_area,a_times_complement");
    read_table(dir, "fig5a_collapse.csv", "body,W,c,scaled_load,rel_area");
    const table *f5b = read_table(dir, "fig5b_cW.csv", "W,c,c_fit");
    read_table(dir, "fig6_separation.csv", "body,W,sigma0_over_Estar,mean_gap,separation");
    read_table(dir, "fig7_adhesion_sweep.csv", "body,W,sigma0,rel_area,u_el,u_ad,steps");
    read_table(dir, "fig7_theta.csv", "W,target_area,u_el,u_ad,theta");
    read_table(dir, "persson_curves.csv", "body,W,sigma0_over_Eg,persson_area");
    read_table(dir, "fits.csv", "quantity,value,detail");

    /* bodies: consecutive row blocks of equal W, listed half-space first, then W decreasing */
    int start[64], nb = 0;
    for (int r = 0; r < f3->rows; ++r)
        if (r == 0 || f3->v[r][1] != f3->v[r - 1][1]) start[nb++] = r;
    start[nb] = f3->rows;
    EXPECT(nb >= 4 && !strcmp(f3->body[0], "halfspace"), "fig3: the half-space first and at least 3 layers");
    for (int b = 0; b < nb; ++b) {
        for (int r = start[b] + 1; r < start[b + 1]; ++r)
            EXPECT(f3->v[r][3] > f3->v[r - 1][3] && f3->v[r][4] > f3->v[r - 1][4],
                   "fig3 W = %g: A/A0 must rise with the load (rows %d, %d)", f3->v[r][1], r, r + 1);
        for (int r = start[b]; r < start[b + 1]; ++r)
            EXPECT(f3->v[r][4] > 0.0 && f3->v[r][4] <= 1.0, "fig3 row %d: A/A0 outside (0, 1]", r + 1);
        if (b >= 2) EXPECT(f3->v[start[b]][1] < f3->v[start[b - 1]][1], "fig3: layers must come in decreasing W");
    }
    /* thinner is softer: at each load of a thinner body inside the thicker one's range, the area
     * is at least the thicker one's, allowing one grid point of the quick mode's 128^2 grid and
     * the interpolation error of the log-log curve (both < 1e-3 relative at these areas) */
    int compared = 0;
    for (int b = 1; b < nb; ++b)
        for (int r = start[b]; r < start[b + 1]; ++r) {
            const double thick = area_at(f3, start[b - 1], start[b], f3->v[r][3]);
            if (!isfinite(thick)) continue;
            ++compared;
            EXPECT(f3->v[r][4] >= thick * (1.0 - 2e-3) - 1.0 / 16384.0,
                   "A/A0 must grow as W shrinks: W = %g has %g at load %g, the thicker body %g", f3->v[r][1],
                   f3->v[r][4], f3->v[r][3], thick);
        }
    EXPECT(compared >= 3, "too few overlapping loads to compare bodies (%d)", compared);

    /* kappa: least squares through the origin over the half-space's rows with A/A0 <= 0.1 */
    double spa = 0.0, spp = 0.0, persson_max = 0.0, persson_min = 1e300;
    for (int r = start[0]; r < start[1]; ++r)
        if (f3->v[r][4] <= 0.1) {
            spa += f3->v[r][3] * f3->v[r][4];
            spp += f3->v[r][3] * f3->v[r][3];
            const double ratio = f3->v[r][4] / f3->v[r][5];
            persson_max = fmax(persson_max, ratio);
            persson_min = fmin(persson_min, ratio);
        }
    const double kappa = spa / spp, kappa_fit = fit_value(dir, "kappa_halfspace");
    printf("kappa = %.4f (program's fit %.4f)\n", kappa, kappa_fit);
    EXPECT(fabs(kappa - kappa_fit) < 1e-5 * kappa, "kappa: closed form %g vs LAPACKE fit %g", kappa, kappa_fit);
    EXPECT(kappa >= 1.6 && kappa <= 2.6, "kappa = %g outside [1.6, 2.6]", kappa);
    const double kp = sqrt(8.0 / 3.14159265358979323846);
    printf("Persson: slope ratio %.3f, pointwise GFMD/Persson %.3f..%.3f (A/A0 <= 0.1)\n", kappa / kp, persson_min,
           persson_max);
    EXPECT(kappa / kp <= 1.5 && kappa / kp >= 1.0 / 1.5, "Persson's slope %g not within 1.5 of kappa %g", kp, kappa);

    /* c(W) */
    for (int r = 1; r < f5b->rows; ++r)
        EXPECT(f5b->v[r][1] >= f5b->v[r - 1][1] * (1.0 - 1e-3), "c(W) must grow as W shrinks (W = %g)", f5b->v[r][0]);
    const double alpha = fit_value(dir, "c_exponent");
    printf("c(W) exponent = %.3f\n", alpha);
    EXPECT(alpha >= -3.5 && alpha <= -2.5, "c(W) exponent %g outside [-3.5, -2.5]", alpha);

    const double beta = fit_value(dir, "theta_exponent");
    printf("theta exponent = %.3f\n", beta);
    EXPECT(beta >= 2.5 && beta <= 3.5, "theta exponent %g outside [2.5, 3.5]", beta);

    if (failures) fprintf(stderr, "%d check(s) failed\n", failures);
    else printf("all checks passed\n");
    return failures ? 1 : 0;
}
