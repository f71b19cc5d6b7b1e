/* compare.c: on random arguments over the ranges the scenes use, count how often glibc 2.36's fma and sse2
 * variants differ, and the largest error in ulps of each (and of SLEEF's Sleef_cinz_*_u10purec) against the
 * correctly rounded MPFR result. Usage: compare N (samples per range). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <math.h>
#include <mpfr.h>
#include <sleef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "offsets.h"

static uintptr_t base;
static uint64_t rng = 0x9E3779B97F4A7C15ull;
static double uni(double lo, double hi) {
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return lo + (hi - lo) * ((rng >> 11) * 0x1p-53);
}
static double ulps(double got, double want) { /* error in ulps of the correctly rounded value */
    if (got == want) return 0;
    double u = nextafter(fabs(want), INFINITY) - fabs(want);
    return fabs(got - want) / u;
}
static double cr1(int (*f)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t), double a) {
    mpfr_t x, z;
    mpfr_inits2(53, x, z, (mpfr_ptr)0);
    mpfr_set_d(x, a, MPFR_RNDN);
    f(z, x, MPFR_RNDN);
    double r = mpfr_get_d(z, MPFR_RNDN);
    mpfr_clears(x, z, (mpfr_ptr)0);
    return r;
}
static double cr_atan2(double y, double x) {
    mpfr_t a, b, z;
    mpfr_inits2(53, a, b, z, (mpfr_ptr)0);
    mpfr_set_d(a, y, MPFR_RNDN), mpfr_set_d(b, x, MPFR_RNDN);
    mpfr_atan2(z, a, b, MPFR_RNDN);
    double r = mpfr_get_d(z, MPFR_RNDN);
    mpfr_clears(a, b, z, (mpfr_ptr)0);
    return r;
}
typedef struct { long n, d_fs; double e_fma, e_sse2, e_sleef; long sleef_ne; } Acc;
static void acc(Acc *A, double fma, double sse2, double sleef, double cr) {
    A->n++;
    if (memcmp(&fma, &sse2, 8)) A->d_fs++;
    if (sleef != cr) A->sleef_ne++;
    double e;
    if ((e = ulps(fma, cr)) > A->e_fma) A->e_fma = e;
    if ((e = ulps(sse2, cr)) > A->e_sse2) A->e_sse2 = e;
    if ((e = ulps(sleef, cr)) > A->e_sleef) A->e_sleef = e;
}
static void show(const char *what, Acc *A) {
    printf("%-34s n=%ld fma!=sse2 %ld (%.3g%%)  max err ulp: fma %.3f sse2 %.3f | sleef_cinz_u10 %.3f (!=CR %.2g%%)\n",
           what, A->n, A->d_fs, 100.0 * A->d_fs / A->n, A->e_fma, A->e_sse2, A->e_sleef, 100.0 * A->sleef_ne / A->n);
}
int main(int argc, char **argv) {
    long N = argc > 1 ? atol(argv[1]) : 100000;
    struct link_map *lm;
    dlinfo(dlopen("libm.so.6", RTLD_NOLOAD | RTLD_LAZY), RTLD_DI_LINKMAP, &lm);
    base = lm->l_addr;
    double (*atan2_fma)(double, double) = (void *)(base + OFF_atan2_fma), (*atan2_sse2)(double, double) = (void *)(base + OFF_atan2_sse2);
    void (*sc_fma)(double, double *, double *) = (void *)(base + OFF_sincos_fma), (*sc_sse2)(double, double *, double *) = (void *)(base + OFF_sincos_sse2);
    double (*log_fma)(double) = (void *)(base + OFF_log_fma), (*log_sse2)(double) = (void *)(base + OFF_log_sse2);
    double (*cos_fma)(double) = (void *)(base + OFF_cos_fma), (*cos_sse2)(double) = (void *)(base + OFF_cos_sse2);
    double (*asin_fma)(double) = (void *)(base + OFF_asin_fma), (*asin_sse2)(double) = (void *)(base + OFF_asin_sse2);
    double (*acos_fma)(double) = (void *)(base + OFF_acos_fma), (*acos_sse2)(double) = (void *)(base + OFF_acos_sse2);
    struct { const char *name; double ylo, yhi, xlo, xhi; } at[] = {
        {"atan2 y,x in [-1,1]^2", -1, 1, -1, 1},
        {"atan2 y in [0,1], x in [0.5,1]", 0, 1, 0.5, 1},   /* ODE hinge / Eigen AngleAxis: half-angles */
        {"atan2 y in [0,0.25], x in [0.95,1]", 0, 0.25, 0.95, 1}};
    for (unsigned k = 0; k < 3; k++) {
        Acc A = {0};
        for (long i = 0; i < N; i++) {
            double y = uni(at[k].ylo, at[k].yhi), x = uni(at[k].xlo, at[k].xhi);
            acc(&A, atan2_fma(y, x), atan2_sse2(y, x), Sleef_cinz_atan2d1_u10purec(y, x), cr_atan2(y, x));
        }
        show(at[k].name, &A);
    }
    double sr[][2] = {{-0.05, 0.9}, {0, 2 * M_PI}, {0, 64}};
    for (unsigned k = 0; k < 3; k++) {
        Acc S = {0}, C = {0};
        for (long i = 0; i < N; i++) {
            double a = uni(sr[k][0], sr[k][1]), s1, c1, s2, c2;
            sc_fma(a, &s1, &c1), sc_sse2(a, &s2, &c2);
            Sleef_double_2 l = Sleef_cinz_sincosd1_u10purec(a);
            acc(&S, s1, s2, l.x, cr1(mpfr_sin, a));
            acc(&C, c1, c2, l.y, cr1(mpfr_cos, a));
        }
        char b[80];
        snprintf(b, sizeof b, "sincos->sin a in [%g,%g]", sr[k][0], sr[k][1]), show(b, &S);
        snprintf(b, sizeof b, "sincos->cos a in [%g,%g]", sr[k][0], sr[k][1]), show(b, &C);
    }
    {
        Acc A = {0};
        for (long i = 0; i < N; i++) {
            double a = uni(0, M_PI / 2);
            acc(&A, cos_fma(a), cos_sse2(a), Sleef_cinz_cosd1_u10purec(a), cr1(mpfr_cos, a));
        }
        show("cos a in [0,pi/2]", &A);
    }
    {
        Acc A = {0};
        for (long i = 0; i < N; i++) {
            double a = 1.0 - uni(0, 1); /* (0,1], as Random::normal */
            acc(&A, log_fma(a), log_sse2(a), Sleef_cinz_logd1_u10purec(a), cr1(mpfr_log, a));
        }
        show("log a in (0,1]", &A);
    }
    {
        Acc A = {0}, B = {0};
        for (long i = 0; i < N; i++) {
            double a = uni(-1, 1);
            acc(&A, asin_fma(a), asin_sse2(a), Sleef_cinz_asind1_u10purec(a), cr1(mpfr_asin, a));
            acc(&B, acos_fma(a), acos_sse2(a), Sleef_cinz_acosd1_u10purec(a), cr1(mpfr_acos, a));
        }
        show("asin a in [-1,1] (ODE, unused)", &A);
        show("acos a in [-1,1] (ODE, unused)", &B);
    }
    return 0;
}
