/* The network's rates driven by the caller's own rb_ode calls (as the detailed train model does):
 * restarting the solver in pieces gives what rb_network_simulate gives in one run, the rates
 * conserve mass exactly, and too small storage is refused. */
#include "rb_test.h"
#include "railbrake/rb_network.h"

static void two_volumes(rb_net_node nodes[2], rb_net_link *link)
{
    rb_net_node a = {RB_NODE_VOLUME, 7e5, 320, 1e-3, 0, 0, 0}, b = {RB_NODE_VOLUME, 1e5, 290, 5e-4, 0, 0, 0};
    nodes[0] = a;
    nodes[1] = b;
    *link = (rb_net_link){0};
    link->kind = RB_LINK_FIXED;
    link->from = 0;
    link->to = 1;
    link->orifice = (rb_orifice){5e-6, 0.8, 0.0, 0.528};
}

static void test_restarts_match_one_run(void)
{
    rb_net_node nodes[2];
    rb_net_link link;
    two_volumes(nodes, &link);
    rb_network net = {nodes, 2, &link, 1, NULL, 0, NULL, 0, NULL, 0};
    rb_error err;
    /* one run */
    double t_end = 0.2, p[2], T[2], m[2], mdot[1], work[256];
    int iwork[16];
    rb_ode_options opt = {1e-8, 1e-10, NULL, 0, 0, 100000};
    CHECK(rb_network_simulate(&net, &t_end, 1, &opt, work, 256, iwork, p, T, m, mdot, NULL, NULL, NULL, &err) == RB_OK);
    /* the same in 20 pieces of 10 ms */
    rb_network_eval ev;
    double eval_work[32], y[4], scale[4], y_out[4], dydt[4], ode_work[64];
    int eval_iwork[2], ode_iwork[4];
    CHECK(rb_network_state_count(&net) == 4);
    CHECK(rb_network_eval_size(&net, NULL) <= 32);
    CHECK(rb_network_eval_init(&net, &ev, eval_work, 32, eval_iwork, 2, y, scale, &err) == RB_OK);
    rb_ode_options o = opt;
    o.atol_scale = scale;
    for (int k = 0; k < 20; ++k) {
        double t0 = 0.01 * k, t1 = 0.01 * (k + 1);
        CHECK(rb_ode_solve(rb_network_rates, &ev, 4, t0, y, &t1, 1, y_out, NULL, &o, ode_work, 64, ode_iwork, NULL,
                           &err) == RB_OK);
    }
    CHECK_CLOSE(y[0], m[0], 1e-6, 0);
    CHECK_CLOSE(y[2], m[1], 1e-6, 0);
    CHECK_CLOSE(y[1], T[0], 1e-6, 0);
    rb_network_rates(0.2, y, dydt, &ev);
    CHECK_CLOSE(ev.p[1], p[1], 1e-6, 0);
    CHECK_CLOSE(dydt[0] + dydt[2], 0.0, 0, 1e-15);   /* what leaves one volume enters the other */
}

static void test_small_storage_refused(void)
{
    rb_net_node nodes[2];
    rb_net_link link;
    two_volumes(nodes, &link);
    rb_network net = {nodes, 2, &link, 1, NULL, 0, NULL, 0, NULL, 0};
    rb_network_eval ev;
    double work[4], y[4];
    int iwork[2];
    rb_error err;
    CHECK(rb_network_eval_init(&net, &ev, work, 4, iwork, 2, y, NULL, &err) == RB_ESIZE);
    CHECK(strstr(err.message, "storage") != NULL);
}

int main(void)
{
    test_restarts_match_one_run();
    test_small_storage_refused();
    return rb_test_summary("test_network_eval");
}
