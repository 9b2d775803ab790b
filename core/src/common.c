#include "railbrake/rb_common.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

rb_status rb_fail(rb_error *err, rb_status code, const char *fmt, ...)
{
    if (err) {
        va_list args;
        va_start(args, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, args);
        va_end(args);
        err->code = (int)code;
    }
    return code;
}

void rb_error_clear(rb_error *err)
{
    if (err) {
        err->code = RB_OK;
        err->message[0] = '\0';
    }
}

rb_status rb_check_finite(rb_error *err, const char *name, double value)
{
    if (!isfinite(value))
        return rb_fail(err, RB_EINVAL, "%s = %g: must be a finite number", name, value);
    return RB_OK;
}

rb_status rb_check_positive(rb_error *err, const char *name, double value)
{
    if (!isfinite(value) || !(value > 0.0))
        return rb_fail(err, RB_EINVAL, "%s = %g: must be finite and > 0", name, value);
    return RB_OK;
}

rb_status rb_check_nonnegative(rb_error *err, const char *name, double value)
{
    if (!isfinite(value) || !(value >= 0.0))
        return rb_fail(err, RB_EINVAL, "%s = %g: must be finite and >= 0", name, value);
    return RB_OK;
}

rb_status rb_check_range(rb_error *err, const char *name, double value, double lo, double hi)
{
    if (!isfinite(value) || value < lo || value > hi)
        return rb_fail(err, RB_EINVAL, "%s = %g: must lie in [%g, %g]", name, value, lo, hi);
    return RB_OK;
}

const char *rb_version(void) { return "0.1.0"; }
