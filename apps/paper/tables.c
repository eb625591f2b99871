/* The study's CSV tables (one per figure, docs/paper/README.md) and its printed report. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"

static FILE *open_csv(const char *dir, const char *name, const char *header) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "gfmd_paper: cannot write %s: %s\n", path, strerror(errno));
        exit(1);
    }
    fprintf(f, "%s\n", header);
    return f;
}

static const char *body_name(double W) { return W > 0.0 ? "layer" : "halfspace"; }

/* Figs. 3, 4, 6: area, area complement and separation against load. */
void write_load_tables(const sweep *sw, const options *o) {
    FILE *f3 = open_csv(o->dir, "fig3_area.csv",
                        "body,W,sigma0,sigma0_over_Eg,rel_area,persson_area,mean_gap,separation,u_el,steps,seconds");
    FILE *f4 = open_csv(o->dir, "fig4_area_complement.csv", "body,W,sigma0_over_Eg,rel_area,a_times_complement");
    FILE *f6 = open_csv(o->dir, "fig6_separation.csv", "body,W,sigma0_over_Estar,mean_gap,separation");
    for (int b = 0; b < o->n_widths; ++b)
        for (int k = 0; k < sw[b].n; ++k) {
            const point *p = &sw[b].p[k];
            const double load = p->sigma0 / (E_STAR * GRADIENT);
            fprintf(f3, "%s,%g,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%lld,%.4f\n", body_name(p->W), p->W, p->sigma0,
                    load, p->area, p->persson, p->gap, p->sep, p->u_el, p->steps, p->seconds);
            fprintf(f4, "%s,%g,%.10e,%.10e,%.10e\n", body_name(p->W), p->W, load, p->area, p->area * (1.0 - p->area));
            fprintf(f6, "%s,%g,%.10e,%.10e,%.10e\n", body_name(p->W), p->W, p->sigma0 / E_STAR, p->gap, p->sep);
        }
    fclose(f3);
    fclose(f4);
    fclose(f6);
}

/* Persson's curves, smooth, for the plots (same substrate, each body's G(q)). */
void write_persson_curves(const gfmd_sim *surface, const options *o) {
    FILE *fp = open_csv(o->dir, "persson_curves.csv", "body,W,sigma0_over_Eg,persson_area");
    for (int b = 0; b < o->n_widths; ++b) {
        gfmd_sim *s = make_body(surface, o->widths[b], o->solver);
        double first = 0.0, last = 0.0; /* the sweep's loads (sweep.c), a factor 3 beyond */
        sweep_load_range(s, &first, &last);
        const double lo = first / 3.0, hi = last * 3.0;
        for (int k = 0; k <= 60; ++k) {
            const double sig = lo * pow(hi / lo, k / 60.0);
            double a = 0.0;
            CHECK(s, gfmd_persson_contact_area(s, sig, &a));
            fprintf(fp, "%s,%g,%.10e,%.10e\n", body_name(o->widths[b]), o->widths[b], sig / (E_STAR * GRADIENT), a);
        }
        gfmd_sim_destroy(&s);
    }
    fclose(fp);
}

/* Fig. 5: the collapse onto the half-space curve and c(W) with its fit. */
void write_collapse_tables(const sweep *sw, const options *o, const fits *f) {
    FILE *f5a = open_csv(o->dir, "fig5a_collapse.csv", "body,W,c,scaled_load,rel_area");
    FILE *f5b = open_csv(o->dir, "fig5b_cW.csv", "W,c,c_fit");
    for (int b = 0; b < o->n_widths; ++b) {
        const double W = o->widths[b];
        for (int k = 0; k < sw[b].n; ++k)
            fprintf(f5a, "%s,%g,%.10e,%.10e,%.10e\n", body_name(W), W, f->cw[b],
                    f->cw[b] * sw[b].p[k].sigma0 / (E_STAR * GRADIENT), sw[b].p[k].area);
        if (b > 0) fprintf(f5b, "%g,%.10e,%.10e\n", W, f->cw[b], exp(f->cfit[0]) * pow(W, f->cfit[1]));
    }
    fclose(f5a);
    fclose(f5b);
}

/* Fig. 7: the adhesive sweeps and theta = U_el/U_ad at the target areas. */
void write_theta_tables(const sweep *ad, const options *o) {
    FILE *fa = open_csv(o->dir, "fig7_adhesion_sweep.csv", "body,W,sigma0,rel_area,u_el,u_ad,steps");
    for (int b = 0; b < o->n_adh; ++b)
        for (int k = 0; k < ad[b].n; ++k) {
            const point *p = &ad[b].p[k];
            fprintf(fa, "%s,%g,%.10e,%.10e,%.10e,%.10e,%lld\n", body_name(p->W), p->W, p->sigma0, p->area, p->u_el,
                    p->u_ad, p->steps);
        }
    fclose(fa);
    FILE *f7 = open_csv(o->dir, "fig7_theta.csv", "W,target_area,u_el,u_ad,theta");
    for (int t = 0; t < N_TARGETS; ++t)
        for (int b = 0; b < o->n_adh; ++b) {
            const double ue = at_area(&ad[b], TARGETS[t], offsetof(point, u_el));
            const double ua = at_area(&ad[b], TARGETS[t], offsetof(point, u_ad));
            if (isfinite(ue) && isfinite(ua))
                fprintf(f7, "%g,%g,%.10e,%.10e,%.10e\n", o->adh_widths[b], TARGETS[t], ue, ua, ue / ua);
        }
    fclose(f7);
}

void write_fits(const options *o, const fits *f) {
    /* only the fits of the sweeps that ran (--adhesion-only, --no-adhesion): no rows of NaN */
    FILE *ff = open_csv(o->dir, "fits.csv", "quantity,value,detail");
    if (o->n_widths > 0) {
        fprintf(ff, "kappa_halfspace,%.6f,A/A0 = kappa sigma0/(E* g) for A/A0 <= %g\n", f->kappa, KAPPA_MAX_AREA);
        fprintf(ff, "persson_kappa,%.6f,sqrt(8/pi) (small-load slope of erf)\n", sqrt(8.0 / 3.14159265358979323846));
        fprintf(ff, "c_exponent,%.6f,c(W) ~ W^alpha for W <= 0.125\n", f->cfit[1]);
        fprintf(ff, "c_prefactor,%.6e,c(W) = prefactor W^alpha for W <= 0.125\n", exp(f->cfit[0]));
    }
    if (o->adhesion) {
        for (int t = 0; t < N_TARGETS; ++t)
            fprintf(ff, "theta_exponent_A%g,%.6f,theta ~ W^beta at A/A0 = %g for W <= 0.25\n", TARGETS[t],
                    f->tfit[t][1], TARGETS[t]);
        fprintf(ff, "theta_exponent,%.6f,common beta of the three areas (one intercept each)\n", f->theta_common);
    }
    fclose(ff);
}

void report_fits(const options *o, const fits *f) {
    printf("\nFits (gfmd_least_squares):\n");
    if (o->n_widths > 0) {
        printf("  kappa (half-space, A/A0 <= %g)  = %.3f   (Persson: sqrt(8/pi) = %.3f)\n", KAPPA_MAX_AREA, f->kappa,
               sqrt(8.0 / 3.14159265358979323846));
        printf("  c(W) ~ W^alpha, W <= 0.125      : alpha = %.3f (paper: -3)\n", f->cfit[1]);
    }
    for (int b = 1; b < o->n_widths; ++b) {
        printf("    W = %-7g c = %-10.4g", o->widths[b], f->cw[b]);
        if (b > 1)
            printf(" local exponent to the previous W: %.2f",
                   log(f->cw[b] / f->cw[b - 1]) / log(o->widths[b] / o->widths[b - 1]));
        printf("\n");
    }
    if (o->adhesion) {
        for (int t = 0; t < N_TARGETS; ++t)
            printf("  theta ~ W^beta at A/A0 = %-5g : beta = %.3f\n", TARGETS[t], f->tfit[t][1]);
        printf("  theta, common exponent          : beta = %.3f (paper: +3)\n", f->theta_common);
    }
}

/* Fig. 8: the pull-off stress of each adhesive sheet, in E* and in units of the adhesive stress
 * gamma0/rho. */
void write_pulloff_table(const pulloff *p, int n, const options *o) {
    FILE *f8 = open_csv(o->dir, "fig8_pulloff.csv",
                        "W,pull_off_over_Estar,pull_off_over_gamma0_rho,max_area,detached,lift,steps,seconds");
    printf("\nFig. 8: pull-off stress against W (gamma0 = %g, rho = %g)\n", GAMMA0, RHO);
    printf("%8s %14s %14s %10s %9s %9s\n", "W", "sigma_po/E*", "/(gamma0/rho)", "max A/A0", "came off", "seconds");
    for (int b = 0; b < n; ++b) {
        fprintf(f8, "%g,%.8e,%.8e,%.6f,%d,%.4f,%lld,%.3f\n", p[b].W, p[b].pull_off, p[b].pull_off / (GAMMA0 / RHO),
                p[b].area_max, p[b].detached, p[b].lift, p[b].steps, p[b].seconds);
        printf("%8g %14.5e %14.5f %10.5f %9s %9.1f\n", p[b].W, p[b].pull_off, p[b].pull_off / (GAMMA0 / RHO),
               p[b].area_max, p[b].detached ? "yes" : "no", p[b].seconds);
    }
    fclose(f8);
}
