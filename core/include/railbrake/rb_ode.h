/* A small variable-step stiff ODE integrator for whole simulations inside the core.
 *
 * Method: the L-stable Rosenbrock (W-) pair of order 2(3) of Shampine & Reichelt, "The MATLAB ODE
 * Suite", SIAM J. Sci. Comput. 18 (1997) 1-22 (the formula behind ode23s), with its continuous
 * extension for output at requested times. The Jacobian and df/dt are taken by forward finite
 * differences every step; the linear systems are solved by dense LU with partial pivoting.
 * SUNDIALS is not among the project's dependencies, hence this solver; it suits the small stiff
 * systems of pneumatic circuits and valves (up to some tens of states).
 *
 * No allocation: the caller provides work (rb_ode_workspace_size(n) doubles) and iwork (n ints). */
#ifndef RAILBRAKE_ODE_H
#define RAILBRAKE_ODE_H

#include "railbrake/rb_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* dy/dt = f(t, y). */
typedef void (*rb_ode_rhs)(double t, const double *y, double *dydt, void *user);
/* Called after every accepted step (may be NULL). */
typedef void (*rb_ode_step_output)(double t, const double *y, void *user);

typedef struct {
    double rtol;       /* relative tolerance, > 0 */
    double atol;       /* absolute tolerance, > 0: atol * atol_scale[i] for component i */
    const double *atol_scale; /* n positive scales, or NULL for 1 */
    double h_initial;  /* first step, s; 0 = chosen automatically */
    double h_max;      /* largest step, s; 0 = no limit */
    long max_steps;    /* accepted + rejected steps before giving up */
} rb_ode_options;

typedef struct {
    long steps;      /* accepted */
    long rejected;
    long rhs_calls;
} rb_ode_stats;

size_t rb_ode_workspace_size(size_t n);

/* Integrates from t0 (y holds y(t0) on entry, y(t_end) on exit, t_end = t_out[n_out - 1]).
   t_out: n_out increasing times >= t0 where y is written (row-major, n_out x n) into y_out.
   step_output: optional callback after each accepted step. stats may be NULL. */
rb_status rb_ode_solve(rb_ode_rhs rhs, void *user, size_t n, double t0, double *y,
                       const double *t_out, size_t n_out, double *y_out,
                       rb_ode_step_output step_output, const rb_ode_options *opt,
                       double *work, size_t work_size, int *iwork, rb_ode_stats *stats,
                       rb_error *err);

/* Dense LU with partial pivoting of the n x n row-major matrix a (in place); 0 if singular. */
int rb_lu_factor(double *a, size_t n, int *pivot);
void rb_lu_solve(const double *lu, size_t n, const int *pivot, double *b);

#ifdef __cplusplus
}
#endif
#endif
