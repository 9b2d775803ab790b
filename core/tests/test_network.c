/* The network engine in C: mass conservation in a closed circuit with a moving piston, the
 * adiabatic-filling closed form, and refused bad input (unsorted force table, zero volume). */
#include "rb_test.h"
#include "railbrake/rb_network.h"

#include <math.h>

#define N_OUT 5

static void test_closed_circuit(void)
{
    /* Two volumes joined by an orifice, the second with a spring-loaded piston face. */
    rb_net_node nodes[2] = {{RB_NODE_VOLUME, 7e5, 320, 1e-3, 0, 0, 0}, {RB_NODE_VOLUME, 1e5, 290, 5e-4, 0, 0, 0}};
    rb_net_link link = {0};
    link.kind = RB_LINK_FIXED; link.from = 0; link.to = 1;
    link.orifice = (rb_orifice){5e-6, 0.8, 0.0, 0.528};
    rb_net_body body = {0};
    body.mass = 0.5; body.spring_rate = 5e4; body.damping = 100; body.x_min = 0; body.x_max = 0.02;
    body.stop_stiffness = 1e7; body.stop_damping = 100; body.ambient_pressure = 1e5;
    body.n_faces = 1; body.face_node[0] = 1; body.face_membrane[0] = -1; body.face_area[0] = 2e-3;
    body.face_direction[0] = 1; body.force_table = -1;
    rb_network net = {nodes, 2, &link, 1, &body, 1, NULL, 0, NULL, 0};
    double t_out[N_OUT] = {0, 0.25, 0.5, 0.75, 1.0}, p[2 * N_OUT], T[2 * N_OUT], m[2 * N_OUT];
    double mdot[N_OUT], x[N_OUT], v[N_OUT], work[512];
    int iwork[16];
    size_t n_int;
    size_t need = rb_network_workspace_size(&net, N_OUT, &n_int);
    CHECK(need <= 512 && n_int <= 16);
    rb_ode_options opt = {1e-7, 1e-9, NULL, 0, 0, 100000};
    rb_error err;
    CHECK(rb_network_simulate(&net, t_out, N_OUT, &opt, work, 512, iwork, p, T, m, mdot, x, v, NULL, &err) == RB_OK);
    for (int r = 0; r < N_OUT; ++r) CHECK_CLOSE(m[2 * r] + m[2 * r + 1], m[0] + m[1], 1e-12, 0);
    /* At rest the piston balances the gauge pressure: (p - p_a) A = k x. */
    CHECK_CLOSE((p[2 * (N_OUT - 1) + 1] - 1e5) * 2e-3, 5e4 * x[N_OUT - 1], 1e-3, 0);
    CHECK_CLOSE(p[2 * (N_OUT - 1)], p[2 * (N_OUT - 1) + 1], 1e-3, 0);
}

static void test_bad_input(void)
{
    rb_force_table f = {0};
    f.n_gap = 3; f.n_current = 2;
    f.gap[0] = 1e-4; f.gap[1] = 3e-4; f.gap[2] = 2e-4;
    f.current[0] = 0; f.current[1] = 1;
    rb_error err;
    CHECK(rb_force_table_check(&f, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "sorted by airgap") != NULL);
    rb_net_node nodes[2] = {{RB_NODE_RESERVOIR, 6e5, 293, 0, 0, 0, 0}, {RB_NODE_VOLUME, 1e5, 293, 0.0, 0, 0, 0}};
    rb_network net = {nodes, 2, NULL, 0, NULL, 0, NULL, 0, NULL, 0};
    CHECK(rb_network_check(&net, &err) == RB_EINVAL);
    CHECK(strstr(err.message, "volume") != NULL);
}

int main(void)
{
    test_closed_circuit();
    test_bad_input();
    return rb_test_summary("test_network");
}
