/* LD_PRELOAD shim for studying which libm calls change Plausible's physics bits.
 *
 * Interposes the floating-point libm functions imported by plausible and libode.so.8. For each, it can
 *   - route the call to one of glibc 2.36's internal ifunc variants (fma, avx, sse2; located through the
 *     libc6-dbg symbol offsets in offsets.h) or to a correctly rounded MPFR result (cr), instead of the
 *     variant glibc chose for this CPU (sys);
 *   - perturb the result by one ulp (nextafter towards +inf);
 *   - record statistics per call site (return address): calls, argument min/max, and on how many calls
 *     the fma and sse2 variants (and avx vs sse2, sys vs cr) give different bits for the same argument.
 *
 * Environment:
 *   SHIM_ROUTE=all=sse2|all=avx|all=fma|all=cr|name=variant,...   (all=avx: avx where glibc has one,
 *              else sse2, i.e. what GLIBC_TUNABLES=glibc.cpu.hwcaps=-FMA,-AVX2 selects on an AVX CPU)
 *   SHIM_PERTURB=name,...        SHIM_STATS=path (report written at exit)   SHIM_QUIET=1
 *   SHIM_CALLER=exe|libode|exe,libode: route and perturb only calls whose return address lies in those
 *              objects (the executable, libode.so.8); other callers get glibc's own variant
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <math.h>
#include <mpfr.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "offsets.h"

enum { V_SYS, V_FMA, V_AVX, V_SSE2, V_CR, V_SLEEF, NV };
static const char *vname[NV] = {"sys", "fma", "avx", "sse2", "cr", "sleef"};
/* sleef: SLEEF 3.5.1 Sleef_cinz_<f>{d1,f1}_u10purec, documented as bit-wise consistent on all platforms */
typedef struct { double x, y; } D2;
typedef struct { float x, y; } F2s;
enum { K_D1, K_D2, K_SC, K_F1, K_F2, K_SCF };

#define MAXSITES 128
typedef struct {
    void *ra;
    unsigned long calls, d_fs, d_as, d_sc, d_lc;
    double lo[2], hi[2], ex[2];
    int has_ex;
} Site;

typedef int (*mpfr1)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);
typedef int (*mpfr2)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t);

typedef struct {
    const char *name;
    int kind;
    uintptr_t off[NV];
    void *mp; /* mpfr function */
    void *ptr[NV];
    int route, perturb;
    Site sites[MAXSITES];
    int nsites;
    unsigned long calls, overflow;
} Fn;

#define O(f, v) OFF_##f##_##v
enum { F_sin, F_cos, F_sincos, F_atan2, F_asin, F_acos, F_exp, F_log, F_pow, F_log10,
       F_sincosf, F_powf, F_logf, F_asinf, F_acosf, F_atan2f, F_tanf, NF };
static Fn fns[NF] = {
    [F_sin] = {"sin", K_D1, {0, O(sin, fma), O(sin, avx), O(sin, sse2)}, mpfr_sin},
    [F_cos] = {"cos", K_D1, {0, O(cos, fma), O(cos, avx), O(cos, sse2)}, mpfr_cos},
    [F_sincos] = {"sincos", K_SC, {0, O(sincos, fma), O(sincos, avx), O(sincos, sse2)}, NULL},
    [F_atan2] = {"atan2", K_D2, {0, O(atan2, fma), O(atan2, avx), O(atan2, sse2)}, mpfr_atan2},
    [F_asin] = {"asin", K_D1, {0, O(asin, fma), 0, O(asin, sse2)}, mpfr_asin},
    [F_acos] = {"acos", K_D1, {0, O(acos, fma), 0, O(acos, sse2)}, mpfr_acos},
    [F_exp] = {"exp", K_D1, {0, O(exp, fma), O(exp, avx), O(exp, sse2)}, mpfr_exp},
    [F_log] = {"log", K_D1, {0, O(log, fma), O(log, avx), O(log, sse2)}, mpfr_log},
    [F_pow] = {"pow", K_D2, {0, O(pow, fma), 0, O(pow, sse2)}, mpfr_pow},
    [F_log10] = {"log10", K_D1, {0}, mpfr_log10},
    [F_sincosf] = {"sincosf", K_SCF, {0, O(sincosf, fma), 0, O(sincosf, sse2)}, NULL},
    [F_powf] = {"powf", K_F2, {0, O(powf, fma), 0, O(powf, sse2)}, mpfr_pow},
    [F_logf] = {"logf", K_F1, {0, O(logf, fma), 0, O(logf, sse2)}, mpfr_log},
    [F_asinf] = {"asinf", K_F1, {0}, mpfr_asin},
    [F_acosf] = {"acosf", K_F1, {0}, mpfr_acos},
    [F_atan2f] = {"atan2f", K_F2, {0}, mpfr_atan2},
    [F_tanf] = {"tanf", K_F1, {0}, mpfr_tan},
};

static pthread_once_t once = PTHREAD_ONCE_INIT;
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static __thread int busy;
static const char *stats_path;
static uintptr_t lo_obj[4], hi_obj[4];
static int nobj = -1; /* -1: no caller filter */

static int phdr_cb(struct dl_phdr_info *info, size_t size, void *data) {
    (void)size;
    const char *want = data, *n = info->dlpi_name;
    int exe = n[0] == 0, ode = strstr(n, "libode.so") != NULL;
    if (!((exe && strstr(want, "exe")) || (ode && strstr(want, "libode")))) return 0;
    uintptr_t lo = UINTPTR_MAX, hi = 0;
    for (int i = 0; i < info->dlpi_phnum; i++) {
        const ElfW(Phdr) *ph = &info->dlpi_phdr[i];
        if (ph->p_type != PT_LOAD) continue;
        uintptr_t a = info->dlpi_addr + ph->p_vaddr;
        if (a < lo) lo = a;
        if (a + ph->p_memsz > hi) hi = a + ph->p_memsz;
    }
    if (nobj < 4) lo_obj[nobj] = lo, hi_obj[nobj] = hi, nobj++;
    return 0;
}

static int caller_selected(void *ra) {
    if (nobj < 0) return 1;
    for (int i = 0; i < nobj; i++)
        if ((uintptr_t)ra >= lo_obj[i] && (uintptr_t)ra < hi_obj[i]) return 1;
    return 0;
}

static void init(void) {
    void *h = dlopen("libm.so.6", RTLD_NOLOAD | RTLD_LAZY);
    struct link_map *lm = NULL;
    if (!h || dlinfo(h, RTLD_DI_LINKMAP, &lm) != 0 || !lm) {
        fprintf(stderr, "shim: cannot find libm.so.6\n");
        abort();
    }
    const char *route = getenv("SHIM_ROUTE"), *perturb = getenv("SHIM_PERTURB");
    stats_path = getenv("SHIM_STATS");
    const char *caller = getenv("SHIM_CALLER");
    if (caller) {
        nobj = 0;
        dl_iterate_phdr(phdr_cb, (void *)caller);
        if (!getenv("SHIM_QUIET")) fprintf(stderr, "shim: caller filter %s: %d objects\n", caller, nobj);
    }
    for (int i = 0; i < NF; i++) {
        Fn *f = &fns[i];
        f->ptr[V_SYS] = dlsym(RTLD_NEXT, f->name);
        for (int v = V_FMA; v <= V_SSE2; v++)
            f->ptr[v] = f->off[v] ? (void *)(lm->l_addr + f->off[v]) : NULL;
        f->ptr[V_CR] = (void *)1;
        static void *sl;
        if (!sl) sl = dlopen("libsleef.so.3", RTLD_NOW | RTLD_LOCAL);
        if (sl) {
            char sym[64];
            snprintf(sym, sizeof sym, "Sleef_cinz_%.*s%s_u10purec", (int)(strlen(f->name) - (f->kind >= K_F1)),
                     f->name, f->kind >= K_F1 ? "f1" : "d1");
            f->ptr[V_SLEEF] = dlsym(sl, sym);
        }
        if (route) {
            char key[64];
            for (int v = 0; v < NV; v++) {
                snprintf(key, sizeof key, "all=%s", vname[v]);
                if (strstr(route, key)) f->route = v;
                snprintf(key, sizeof key, "%s=%s", f->name, vname[v]);
                const char *p = strstr(route, key);
                if (p && (p == route || p[-1] == ',') && (p[strlen(key)] == 0 || p[strlen(key)] == ','))
                    f->route = v;
            }
            if (strstr(route, "all=avx") && !f->ptr[V_AVX]) f->route = V_SSE2;
            if (!f->ptr[f->route]) f->route = V_SYS; /* no such variant: libm's own (no ifunc) */
        }
        if (perturb) {
            char key[64];
            snprintf(key, sizeof key, ",%s,", f->name);
            char buf[512];
            snprintf(buf, sizeof buf, ",%s,", perturb);
            f->perturb = strstr(buf, key) != NULL;
        }
        if (!getenv("SHIM_QUIET") && (f->route || f->perturb))
            fprintf(stderr, "shim: %s -> %s%s\n", f->name, vname[f->route], f->perturb ? " +1ulp" : "");
    }
}

/* Correctly rounded result of f through MPFR, in double (prec 53) or float (prec 24) format. */
static void cr_eval(Fn *f, double a, double b, double *r0, double *r1) {
    int flt = f->kind >= K_F1;
    mpfr_prec_t prec = flt ? 24 : 53;
    mpfr_exp_t emin = mpfr_get_emin(), emax = mpfr_get_emax();
    mpfr_set_emin(flt ? -148 : -1073);
    mpfr_set_emax(flt ? 128 : 1024);
    mpfr_t x, y, z, w;
    mpfr_inits2(prec, z, w, (mpfr_ptr)0);
    mpfr_inits2(53, x, y, (mpfr_ptr)0);
    mpfr_set_d(x, a, MPFR_RNDN);
    mpfr_set_d(y, b, MPFR_RNDN);
    int t;
    if (f->kind == K_SC || f->kind == K_SCF) {
        t = mpfr_sin_cos(z, w, x, MPFR_RNDN);
        /* mpfr_sin_cos returns a combined ternary: sin's in the low bits, cos's shifted */
        int ts = t & 3, tc = (t >> 2) & 3;
        mpfr_subnormalize(z, ts == 1 ? 1 : ts == 2 ? -1 : 0, MPFR_RNDN);
        mpfr_subnormalize(w, tc == 1 ? 1 : tc == 2 ? -1 : 0, MPFR_RNDN);
        *r0 = mpfr_get_d(z, MPFR_RNDN);
        *r1 = mpfr_get_d(w, MPFR_RNDN);
    } else {
        if (f->kind == K_D2 || f->kind == K_F2)
            t = ((mpfr2)f->mp)(z, x, y, MPFR_RNDN);
        else
            t = ((mpfr1)f->mp)(z, x, MPFR_RNDN);
        t = mpfr_subnormalize(z, t, MPFR_RNDN);
        *r0 = mpfr_get_d(z, MPFR_RNDN);
        *r1 = 0;
    }
    mpfr_clears(x, y, z, w, (mpfr_ptr)0);
    mpfr_set_emin(emin);
    mpfr_set_emax(emax);
}

static void eval(Fn *f, int v, double a, double b, double *r0, double *r1) {
    if (v == V_CR) {
        cr_eval(f, a, b, r0, r1);
        return;
    }
    void *p = f->ptr[v];
    *r1 = 0;
    if (v == V_SLEEF && f->kind == K_SC) {
        D2 r = ((D2(*)(double))p)(a);
        *r0 = r.x, *r1 = r.y;
        return;
    }
    if (v == V_SLEEF && f->kind == K_SCF) {
        F2s r = ((F2s(*)(float))p)((float)a);
        *r0 = r.x, *r1 = r.y;
        return;
    }
    switch (f->kind) {
    case K_D1: *r0 = ((double (*)(double))p)(a); break;
    case K_D2: *r0 = ((double (*)(double, double))p)(a, b); break;
    case K_SC: ((void (*)(double, double *, double *))p)(a, r0, r1); break;
    case K_F1: *r0 = ((float (*)(float))p)((float)a); break;
    case K_F2: *r0 = ((float (*)(float, float))p)((float)a, (float)b); break;
    case K_SCF: {
        float s, c;
        ((void (*)(float, float *, float *))p)((float)a, &s, &c);
        *r0 = s;
        *r1 = c;
    } break;
    }
}

static int differ(double a0, double a1, double b0, double b1) {
    return memcmp(&a0, &b0, 8) != 0 || memcmp(&a1, &b1, 8) != 0;
}

static void record(Fn *f, void *ra, double a, double b) {
    double r[NV][2];
    for (int v = 0; v < NV; v++)
        if (f->ptr[v]) eval(f, v, a, b, &r[v][0], &r[v][1]);
    pthread_mutex_lock(&mu);
    f->calls++;
    Site *s = NULL;
    for (int i = 0; i < f->nsites; i++)
        if (f->sites[i].ra == ra) s = &f->sites[i];
    if (!s && f->nsites < MAXSITES) {
        s = &f->sites[f->nsites++];
        s->ra = ra;
        s->lo[0] = s->lo[1] = INFINITY;
        s->hi[0] = s->hi[1] = -INFINITY;
    }
    if (!s) {
        f->overflow++;
        pthread_mutex_unlock(&mu);
        return;
    }
    s->calls++;
    double ab[2] = {a, b};
    for (int k = 0; k < 2; k++) {
        if (ab[k] < s->lo[k]) s->lo[k] = ab[k];
        if (ab[k] > s->hi[k]) s->hi[k] = ab[k];
    }
    if (f->ptr[V_FMA] && differ(r[V_FMA][0], r[V_FMA][1], r[V_SSE2][0], r[V_SSE2][1])) {
        s->d_fs++;
        if (!s->has_ex) s->ex[0] = a, s->ex[1] = b, s->has_ex = 1;
    }
    if (f->ptr[V_AVX] && differ(r[V_AVX][0], r[V_AVX][1], r[V_SSE2][0], r[V_SSE2][1])) s->d_as++;
    if (differ(r[V_SYS][0], r[V_SYS][1], r[V_CR][0], r[V_CR][1])) s->d_sc++;
    if (f->ptr[V_SLEEF] && differ(r[V_SLEEF][0], r[V_SLEEF][1], r[V_CR][0], r[V_CR][1])) s->d_lc++;
    pthread_mutex_unlock(&mu);
}

static void call(Fn *f, void *ra, double a, double b, double *r0, double *r1) {
    pthread_once(&once, init);
    if (busy) {
        eval(f, V_SYS, a, b, r0, r1);
        return;
    }
    busy = 1;
    if (stats_path) record(f, ra, a, b);
    int sel = caller_selected(ra);
    eval(f, sel ? f->route : V_SYS, a, b, r0, r1);
    if (f->perturb && sel) {
        if (f->kind >= K_F1) {
            *r0 = nextafterf((float)*r0, INFINITY);
            *r1 = nextafterf((float)*r1, INFINITY);
        } else {
            *r0 = nextafter(*r0, INFINITY);
            *r1 = nextafter(*r1, INFINITY);
        }
    }
    busy = 0;
}

#define RA __builtin_return_address(0)
#define D1(fn)                                                                                               \
    double fn(double x) {                                                                                    \
        double r0, r1;                                                                                       \
        call(&fns[F_##fn], RA, x, 0, &r0, &r1);                                                              \
        return r0;                                                                                           \
    }
#define D2(fn)                                                                                               \
    double fn(double x, double y) {                                                                          \
        double r0, r1;                                                                                       \
        call(&fns[F_##fn], RA, x, y, &r0, &r1);                                                              \
        return r0;                                                                                           \
    }
#define F1(fn)                                                                                               \
    float fn(float x) {                                                                                      \
        double r0, r1;                                                                                       \
        call(&fns[F_##fn], RA, x, 0, &r0, &r1);                                                              \
        return (float)r0;                                                                                    \
    }
#define F2(fn)                                                                                               \
    float fn(float x, float y) {                                                                             \
        double r0, r1;                                                                                       \
        call(&fns[F_##fn], RA, x, y, &r0, &r1);                                                              \
        return (float)r0;                                                                                    \
    }
D1(sin) D1(cos) D1(asin) D1(acos) D1(exp) D1(log) D1(log10) D2(atan2) D2(pow)
F1(logf) F1(asinf) F1(acosf) F1(tanf) F2(powf) F2(atan2f)
void sincos(double x, double *s, double *c) { call(&fns[F_sincos], RA, x, 0, s, c); }
void sincosf(float x, float *s, float *c) {
    double r0, r1;
    call(&fns[F_sincosf], RA, x, 0, &r0, &r1);
    *s = (float)r0;
    *c = (float)r1;
}

__attribute__((destructor)) static void report(void) {
    if (!stats_path) return;
    char path[512];
    snprintf(path, sizeof path, "%s", stats_path);
    FILE *o = fopen(path, "w");
    if (!o) return;
    fprintf(o, "# fn caller+offset symbol calls fma!=sse2 avx!=sse2 sys!=cr sleef!=cr arg0[min,max] arg1[min,max] "
               "first_fma!=sse2_arg\n");
    for (int i = 0; i < NF; i++) {
        Fn *f = &fns[i];
        for (int k = 0; k < f->nsites; k++) {
            Site *s = &f->sites[k];
            Dl_info di;
            memset(&di, 0, sizeof di);
            dladdr(s->ra, &di);
            const char *obj = di.dli_fname ? strrchr(di.dli_fname, '/') : NULL;
            obj = obj ? obj + 1 : (di.dli_fname ? di.dli_fname : "?");
            fprintf(o, "%s %s+0x%lx %s %lu %lu %lu %lu %lu [%.17g,%.17g] [%.17g,%.17g]", f->name, obj,
                    (unsigned long)((char *)s->ra - (char *)di.dli_fbase), di.dli_sname ? di.dli_sname : "-",
                    s->calls, s->d_fs, s->d_as, s->d_sc, s->d_lc, s->lo[0], s->hi[0], s->lo[1], s->hi[1]);
            if (s->has_ex) fprintf(o, " (%a,%a)", s->ex[0], s->ex[1]);
            fputc('\n', o);
        }
        if (f->overflow) fprintf(o, "%s overflow %lu\n", f->name, f->overflow);
    }
    fclose(o);
}
