/* The study's fits, all by least squares through gfmd_least_squares (LAPACKE_dgels):
 *   kappa   A/A0 = kappa sigma0/(E* g) over the half-space points with A/A0 <= KAPPA_MAX_AREA
 *   c(W)    A_W(sigma0) = A_hs(c(W) sigma0): the mean log-shift of each layer's points onto the
 *           half-space curve, then c ~ W^alpha for W <= SMALL_W_C
 *   theta   U_el/U_ad at three contact areas with adhesion, theta ~ W^beta for W <= SMALL_W_THETA,
 *           per area and with one common exponent */
#include <math.h>
#include <stdio.h>

#include "study.h"

const double TARGETS[N_TARGETS] = {0.05, 0.1, 0.2};

/* Too few points (a reduced --widths list) leave the result NaN, reported as such. */
static void fit(int m, int n, const double *a, const double *b, double *x, const char *what) {
    if (m < n + 1) {
        printf("  (%s: %d points for %d parameters, not fitted)\n", what, m, n);
        for (int j = 0; j < n; ++j) x[j] = NAN;
        return;
    }
    CHECK(NULL, gfmd_least_squares(m, n, a, b, x, NULL));
}

/* Fit y = exp(x0) W^x1 over the given points (log-log line). */
static void power_law(int m, const double *w, const double *y, double *x, const char *what) {
    double a[2 * MAX_BODIES * N_TARGETS], b[MAX_BODIES * N_TARGETS];
    for (int i = 0; i < m; ++i) {
        a[i] = 1.0;
        a[m + i] = log(w[i]);
        b[i] = log(y[i]);
    }
    fit(m, 2, a, b, x, what);
}

double at_area(const sweep *c, double area, size_t field) {
    for (int k = 0; k + 1 < c->n; ++k) {
        const double a0 = c->p[k].area, a1 = c->p[k + 1].area;
        if (a0 > 0.0 && area >= a0 && area <= a1 && a1 > a0) {
            const double t = (log(area) - log(a0)) / (log(a1) - log(a0));
            const double y0 = *(const double *)((const char *)&c->p[k] + field);
            const double y1 = *(const double *)((const char *)&c->p[k + 1] + field);
            return exp((1.0 - t) * log(y0) + t * log(y1));
        }
    }
    return NAN;
}

void fit_kappa(const sweep *halfspace, fits *f) {
    double a[MAX_LOADS], b[MAX_LOADS];
    int m = 0;
    for (int k = 0; k < halfspace->n; ++k)
        if (halfspace->p[k].area <= KAPPA_MAX_AREA) {
            a[m] = halfspace->p[k].sigma0 / (E_STAR * GRADIENT);
            b[m++] = halfspace->p[k].area;
        }
    fit(m, 1, a, b, &f->kappa, "kappa");
}

void fit_collapse(const sweep *sw, const options *o, fits *f) {
    f->cw[0] = 1.0;
    for (int b = 1; b < o->n_widths; ++b) {
        double ones[MAX_LOADS], shift[MAX_LOADS], lnc = 0.0;
        int m = 0;
        for (int k = 0; k < sw[b].n; ++k) {
            const double ls = log(at_area(&sw[0], sw[b].p[k].area, offsetof(point, sigma0)));
            if (sw[b].p[k].area <= COLLAPSE_MAX_AREA && isfinite(ls)) {
                ones[m] = 1.0;
                shift[m++] = ls - log(sw[b].p[k].sigma0);
            }
        }
        fit(m, 1, ones, shift, &lnc, "c(W)");
        f->cw[b] = exp(lnc);
    }
    double wv[MAX_BODIES], cv[MAX_BODIES];
    int m = 0;
    for (int b = 1; b < o->n_widths; ++b)
        if (o->widths[b] <= SMALL_W_C) wv[m] = o->widths[b], cv[m++] = f->cw[b];
    power_law(m, wv, cv, f->cfit, "c(W) exponent");
}

void fit_theta(const sweep *ad, const options *o, fits *f) {
    /* common exponent: one intercept per area, one slope (columns: area indicators, ln W) */
    double ac[(N_TARGETS + 1) * MAX_BODIES * N_TARGETS], bc[MAX_BODIES * N_TARGETS], lw[MAX_BODIES * N_TARGETS];
    int rows[MAX_BODIES * N_TARGETS] = {0}, mc = 0;
    for (int t = 0; t < N_TARGETS; ++t) {
        double w[MAX_BODIES], th[MAX_BODIES];
        int mt = 0;
        f->tfit[t][0] = f->tfit[t][1] = NAN;
        for (int b = 0; b < o->n_adh; ++b) {
            const double ue = at_area(&ad[b], TARGETS[t], offsetof(point, u_el));
            const double ua = at_area(&ad[b], TARGETS[t], offsetof(point, u_ad));
            if (!isfinite(ue) || !isfinite(ua)) continue; /* the area is outside this sweep */
            if (o->adh_widths[b] > 0.0 && o->adh_widths[b] <= SMALL_W_THETA) {
                w[mt] = o->adh_widths[b], th[mt++] = ue / ua;
                rows[mc] = t, lw[mc] = log(o->adh_widths[b]), bc[mc++] = log(ue / ua);
            }
        }
        if (mt >= 3) power_law(mt, w, th, f->tfit[t], "theta exponent");
    }
    int used[N_TARGETS] = {0}, ncol = 0, col[N_TARGETS];
    for (int i = 0; i < mc; ++i) used[rows[i]] = 1;
    for (int t = 0; t < N_TARGETS; ++t) col[t] = used[t] ? ncol++ : -1;
    f->theta_common = NAN;
    if (mc >= ncol + 2) {
        for (int i = 0; i < (ncol + 1) * mc; ++i) ac[i] = 0.0;
        for (int i = 0; i < mc; ++i) {
            ac[col[rows[i]] * mc + i] = 1.0;
            ac[ncol * mc + i] = lw[i];
        }
        double x[N_TARGETS + 1];
        fit(mc, ncol + 1, ac, bc, x, "common theta exponent");
        f->theta_common = x[ncol];
    }
}
