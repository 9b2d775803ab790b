/* Shared conventions of the railbrake C core.
 *
 * Every fallible function returns an rb_status and, when given a non-NULL rb_error,
 * writes a message naming the argument, its value and the allowed range. There is no
 * global state: the caller owns the error record. */
#ifndef RAILBRAKE_COMMON_H
#define RAILBRAKE_COMMON_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RB_OK = 0,
    RB_EINVAL = 1,   /* an argument is out of range, NaN or inconsistent */
    RB_ENOCONV = 2,  /* an iteration did not converge */
    RB_ESTATE = 3,   /* a call made in the wrong state */
    RB_ESIZE = 4     /* a buffer or array is too small */
} rb_status;

#define RB_ERROR_MESSAGE_SIZE 256

typedef struct {
    int code;
    char message[RB_ERROR_MESSAGE_SIZE];
} rb_error;

/* Records a formatted message in err (if not NULL) and returns code. */
rb_status rb_fail(rb_error *err, rb_status code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Clears err (if not NULL). */
void rb_error_clear(rb_error *err);

/* Argument checks: each returns RB_OK or fails with a message naming the argument. */
/* exp(x) for x <= 0, branch-free so that a loop of it vectorises (and every build computes it the
   same way, bit for bit). Cody and Waite's reduction x = n ln 2 + r, |r| <= ln 2 / 2, with fdlibm's
   split of ln 2 (n ln2_hi exact), exp(r) by its Taylor series to r^13 (truncation under
   0.3466^14 / 14! < 5e-18 relative, Estrin's scheme), 2^n put into the exponent bits. Below -708 it
   returns 0 (libm gives at most 3.3e-308 there). core/tests/test_fastmath.c checks it against libm's
   exp to 1e-15 relative over [-708, 0]. */
static inline double rb_exp_nonpos(double x)
{
    const double shifter = 6755399441055744.0;   /* 1.5 x 2^52: adding it rounds to an integer */
    double xc = x < -708.0 ? -708.0 : x;
    double t = xc * 1.4426950408889634074 + shifter;
    double n = t - shifter;
    double r = (xc - n * 6.93147180369123816490e-01) - n * 1.90821492927058770002e-10;
    double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
    double p01 = 1.0 + r, p23 = 1.0 / 2 + r * (1.0 / 6), p45 = 1.0 / 24 + r * (1.0 / 120);
    double p67 = 1.0 / 720 + r * (1.0 / 5040), p89 = 1.0 / 40320 + r * (1.0 / 362880);
    double p1011 = 1.0 / 3628800 + r * (1.0 / 39916800), p1213 = 1.0 / 479001600 + r * (1.0 / 6227020800.0);
    double e = ((p01 + r2 * p23) + r4 * (p45 + r2 * p67)) + r8 * ((p89 + r2 * p1011) + r4 * p1213);
    union { double d; int64_t i; } bits, scale;
    bits.d = t;                              /* its low bits hold n */
    scale.i = (bits.i - (int64_t)0x4338000000000000LL + 1023) << 52;
    double y = e * scale.d;
    return x < -708.0 ? 0.0 : y;
}

/* 1 - exp(-y) for y >= 0. Below 1/16 the Taylor series of (1 - exp(-y)) / y to y^7 (truncation
   under y^8 / 9! < 7e-16 relative), above it 1 - exp(-y) (cancellation costs at most ulp(1) /
   (1 - exp(-1/16)) < 4e-15 relative); core/tests/test_fastmath.c checks it against expm1 to 1e-14. */
static inline double rb_one_minus_exp_neg_series(double y)
{
    double y2 = y * y, y4 = y2 * y2;   /* Estrin's scheme: a short dependency chain */
    double a = 1.0 - y * (1.0 / 2), b = 1.0 / 6 - y * (1.0 / 24);
    double c = 1.0 / 120 - y * (1.0 / 720), d = 1.0 / 5040 - y * (1.0 / 40320);
    return y * ((a + y2 * b) + y4 * (c + y2 * d));
}

static inline double rb_one_minus_exp_neg(double y)
{
    if (y > 0.0625) return 1.0 - rb_exp_nonpos(-y);
    return rb_one_minus_exp_neg_series(y);
}

/* rb_one_minus_exp_neg with both arms computed and one selected: no branch, so that a loop of it
   vectorises; the same result for every y. The exponential's arm gets y only where it is taken
   (else 1: a NaN would overflow rb_exp_nonpos's integer shift, undefined behaviour). */
static inline double rb_one_minus_exp_neg_select(double y)
{
    double large = 1.0 - rb_exp_nonpos(-(y > 0.0625 ? y : 1.0)), small = rb_one_minus_exp_neg_series(y);
    return y > 0.0625 ? large : small;
}

/* atan(y / x) for y >= 0, x > 0 (y = +inf gives pi/2) in two parts, atan(y / x) = *base + *num / *den,
   so that a caller adding a fraction of its own to it needs one division for both, and none for y / x
   itself (the Polach coefficient, plant_kernel.c); branch-free so that a loop of it vectorises.
   Cephes' atan (S. L. Moshier, Cephes Math Library 2.8, atan.c: reduction to |r| <= 0.66 by pi/4 or
   pi/2 and a 4/5 rational; 2.2e-16 peak relative error quoted over the whole range), its reduction
   written in y and x: above tan(3 pi / 8) r = -x / y, above 0.66 r = (y - x) / (y + x), else y / x;
   *base = y0 + (r + extra), the rational's correction r z p(z) / q(z) left as num / den.
   core/tests/test_fastmath.c checks rb_atan_nonneg (x = 1) against libm's atan to 1e-15 relative
   over 0 to 1e300, and ratios y / x spread over 1e-12 to 1e12. */
static inline void rb_atan_ratio_parts(double y, double x, double *base, double *num, double *den)
{
    const double t3p8 = 2.41421356237309504880, morebits = 6.123233995736765886130e-17;
    int high = y > t3p8 * x, mid = y > 0.66 * x;
    double n0 = high ? -x : (mid ? y - x : y);
    double d0 = high ? y : (mid ? y + x : x);
    double y0 = high ? 1.57079632679489661923 : (mid ? 0.78539816339744830962 : 0.0);
    double extra = high ? morebits : (mid ? 0.5 * morebits : 0.0);
    double r = n0 / d0, z = r * r;
    double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z
                 - 7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z - 6.485021904942025371773e1;
    double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z
                 + 4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z + 1.945506571482613964425e2;
    *base = y0 + (r + extra);
    *num = r * z * p;
    *den = q;
}

/* atan(x) for x >= 0 in the two parts of rb_atan_ratio_parts (y = x over 1: the same operations as
   Cephes' reduction of x). */
static inline void rb_atan_nonneg_parts(double x, double *base, double *num, double *den)
{
    rb_atan_ratio_parts(x, 1.0, base, num, den);
}

/* atan(x) for x >= 0: rb_atan_nonneg_parts with its one division. */
static inline double rb_atan_nonneg(double x)
{
    double base, num, den;
    rb_atan_nonneg_parts(x, &base, &num, &den);
    return base + num / den;
}

rb_status rb_check_finite(rb_error *err, const char *name, double value);
rb_status rb_check_positive(rb_error *err, const char *name, double value);      /* finite and > 0 */
rb_status rb_check_nonnegative(rb_error *err, const char *name, double value);   /* finite and >= 0 */
rb_status rb_check_range(rb_error *err, const char *name, double value,
                         double lo, double hi);                                  /* finite, lo <= v <= hi */

/* Version of the C core, "MAJOR.MINOR.PATCH". */
const char *rb_version(void);

/* SHA-256 (hex) of the core's sources and headers when CMake configured the build; "unknown"
 * in a build without CMake (an exported FMU). */
const char *rb_build_hash(void);

#ifdef __cplusplus
}
#endif
#endif
