#include "green.hpp"

#include <cmath>
#include <limits>

#include "gfmd.h"

namespace gfmd {

namespace {

// The closed forms below are written with x = 2t.  For x < 2 they cancel (fluid denominator,
// bonded numerator at nu -> 1/2), so they are summed as power series with the leading powers
// factored out; for x >= 2 they are divided by e^x/2 so that nothing overflows up to t = 1e308.
constexpr double kSeriesLimit = 2.0;

// (sinh x - x)/x^3 = sum_{k>=1} x^(2k-2)/(2k+1)!  ->  returns sum_{k>=1} x^(2k)/(2k+1)!
double sinh_tail(double x2) {
    double term = x2 / 6.0, sum = 0.0;
    for (int k = 1; k < 40 && term > 1e-18 * (sum + 1e-300); ++k) {
        sum += term;
        term *= x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    }
    return sum;
}

// (cosh x - 1 - x^2/2)/x^4 = sum_{k>=2} x^(2k-4)/(2k)!
double cosh_tail_over_x4(double x2) {
    double term = 1.0 / 24.0, sum = 0.0;
    for (int k = 2; k < 40 && term > 1e-18 * sum; ++k) {
        sum += term;
        term *= x2 / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
    }
    return sum;
}

// Layer on a fluid foundation (the seed paper, Putignano, Dapp & Müser 2016, Eq. 4):
// f(t) = (sinh 2t + 2t) / (cosh 2t - 1 - 2t^2).  Returns numerator and denominator scaled alike.
void fluid_parts(double t, double &num, double &den) {
    const double x = 2.0 * t;
    if (x < kSeriesLimit) {
        const double x2 = x * x;
        num = 2.0 + sinh_tail(x2);               // (sinh x + x)/x
        den = x * x * x * cosh_tail_over_x4(x2);  // (cosh x - 1 - x^2/2)/x
    } else {
        const double e = std::exp(-x);
        num = 1.0 - e * e + 2.0 * x * e;          // (sinh x + x) 2 e^-x
        den = 1.0 + e * e - (2.0 + x * x) * e;    // (cosh x - 1 - x^2/2) 2 e^-x
    }
}

// Layer bonded to a rigid foundation, kappa = 3 - 4 nu (Carbone & Mangialardi, JMPS 56, 684 (2008)):
// f_b(t) = (kappa sinh 2t - 2t) / (kappa cosh 2t + 2t^2 + (1 + kappa^2)/2).
void bonded_parts(double t, double nu, double &num, double &den) {
    const double x = 2.0 * t;
    const double kappa = 3.0 - 4.0 * nu;
    const double kappa_m1 = 2.0 - 4.0 * nu;  // exact where kappa -> 1 (incompressible)
    if (x < kSeriesLimit) {
        num = x * (kappa_m1 + kappa * sinh_tail(x * x));
        den = kappa * std::cosh(x) + 0.5 * x * x + 0.5 * (1.0 + kappa * kappa);
    } else {
        const double e = std::exp(-x);
        num = kappa * (1.0 - e * e) - 2.0 * x * e;
        den = kappa * (1.0 + e * e) + (x * x + 1.0 + kappa * kappa) * e;
    }
}

void parts(int32_t kind, double t, double nu, double &num, double &den) {
    if (kind == GFMD_GREEN_LAYER_FLUID) {
        fluid_parts(t, num, den);
    } else if (kind == GFMD_GREEN_LAYER_BONDED) {
        bonded_parts(t, nu, num, den);
    } else {
        num = 1.0;
        den = 1.0;
    }
}

}  // namespace

double green_inverse_factor(int32_t kind, double t, double nu) {
    double num = 1.0, den = 1.0;
    parts(kind, t, nu, num, den);
    return den / num;
}

double green_factor(int32_t kind, double t, double nu) {
    double num = 1.0, den = 1.0;
    parts(kind, t, nu, num, den);
    if (den == 0.0) return std::numeric_limits<double>::infinity();
    return num / den;
}

}  // namespace gfmd
