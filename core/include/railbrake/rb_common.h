/* Shared conventions of the railbrake C core.
 *
 * Every fallible function returns an rb_status and, when given a non-NULL rb_error,
 * writes a message naming the argument, its value and the allowed range. There is no
 * global state: the caller owns the error record. */
#ifndef RAILBRAKE_COMMON_H
#define RAILBRAKE_COMMON_H

#include <math.h>
#include <stddef.h>

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
/* 1 - exp(-y) for y >= 0. Below 1/16 the Taylor series of (1 - exp(-y)) / y to y^7 (truncation
   under y^8 / 9! < 7e-16 relative; core/tests/test_common.c checks it against expm1 to 1e-14), above
   it -expm1(-y): cheaper than libm where most calls are small. */
static inline double rb_one_minus_exp_neg(double y)
{
    if (y > 0.0625) return -expm1(-y);
    return y * (1.0 - y * (1.0 / 2 - y * (1.0 / 6 - y * (1.0 / 24 - y * (1.0 / 120 - y * (1.0 / 720
                - y * (1.0 / 5040 - y * (1.0 / 40320))))))));
}

rb_status rb_check_finite(rb_error *err, const char *name, double value);
rb_status rb_check_positive(rb_error *err, const char *name, double value);      /* finite and > 0 */
rb_status rb_check_nonnegative(rb_error *err, const char *name, double value);   /* finite and >= 0 */
rb_status rb_check_range(rb_error *err, const char *name, double value,
                         double lo, double hi);                                  /* finite, lo <= v <= hi */

/* Version of the C core, "MAJOR.MINOR.PATCH". */
const char *rb_version(void);

#ifdef __cplusplus
}
#endif
#endif
