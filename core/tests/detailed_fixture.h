/* A detailed model's valve design for the C tests: the packaged design's values (the EP valve,
 * relay valve and solver settings that railbrake.simulation.detailed.detailed_params() reads from
 * src/railbrake/data/valves/epv.yaml, relay.yaml, epv_solenoid_force.csv and
 * src/railbrake/data/detailed/valves.yaml, whose sources those files name), written out once. A
 * test design: the defaults live in those files. */
#ifndef RB_DETAILED_FIXTURE_H
#define RB_DETAILED_FIXTURE_H

#include <string.h>

#include "railbrake/rb_detailed.h"

static inline void fill_detailed(rb_detailed_params *d)
{
    memset(d, 0, sizeof *d);
    d->pilot_volume = 2e-06;
    d->pilot_orifice_area = 7.068583470577033e-08;
    d->nozzle_diameter = 0.002;
    d->armature_mass = 0.005;
    d->armature_spring_rate = 3500.0;
    d->armature_preload = 0.02;
    d->armature_damping = 20.0;
    d->airgap_open = 0.00045000000000000004;
    d->flapper_travel = 0.00015;
    d->solenoid.n_gap = 11; d->solenoid.n_current = 13;
    static const double gap[] = {0.00015, 0.0002, 0.00025, 0.0003, 0.00035, 0.0004, 0.00045000000000000004, 0.0005, 0.00055, 0.0006500000000000001, 0.00075};
    static const double current[] = {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2};
    static const double force[] = {
        0.0, 0.02958, 0.11832, 0.26722, 0.47695, 0.74703, 1.07678, 1.4633, 1.90898, 2.40057, 2.94356, 3.53216, 4.13953,
        0.0, 0.02737, 0.10947, 0.24713, 0.4411, 0.69088, 0.99622, 1.35383, 1.76617, 2.22381, 2.72682, 3.28025, 3.8443,
        0.0, 0.02539, 0.10155, 0.22918, 0.40906, 0.64068, 0.92406, 1.25591, 1.63843, 2.06541, 2.53259, 3.04735, 3.57876,
        0.0, 0.02361, 0.09444, 0.21306, 0.38029, 0.59563, 0.85908, 1.16798, 1.52372, 1.92292, 2.35786, 2.83711, 3.33904,
        0.0, 0.02201, 0.08804, 0.19854, 0.35438, 0.55505, 0.80054, 1.08873, 1.42033, 1.79427, 2.20012, 2.6473, 3.12192,
        0.0, 0.02056, 0.08224, 0.18542, 0.33095, 0.51835, 0.74762, 1.01704, 1.32681, 1.67769, 2.05722, 2.47536, 2.92465,
        0.0, 0.01924, 0.07698, 0.17351, 0.3097, 0.48507, 0.69962, 0.95199, 1.24195, 1.57039, 1.92736, 2.31911, 2.74487,
        0.0, 0.01805, 0.07219, 0.16268, 0.29037, 0.45479, 0.65595, 0.89279, 1.16471, 1.47273, 1.80901, 2.1767, 2.57839,
        0.0, 0.01696, 0.06782, 0.1528, 0.27273, 0.42716, 0.6161, 0.83875, 1.09421, 1.38358, 1.70084, 2.04655, 2.42422,
        0.0, 0.01504, 0.06015, 0.13546, 0.24179, 0.3787, 0.5462, 0.7439, 0.97048, 1.22713, 1.51069, 1.81774, 2.15319,
        0.0, 0.01342, 0.05367, 0.12081, 0.21563, 0.33774, 0.48712, 0.66369, 0.86583, 1.09481, 1.34951, 1.62381, 1.92346,
    };
    for (int i = 0; i < d->solenoid.n_gap; ++i) d->solenoid.gap[i] = gap[i];
    for (int j = 0; j < d->solenoid.n_current; ++j) d->solenoid.current[j] = current[j];
    for (int k = 0; k < d->solenoid.n_gap * d->solenoid.n_current; ++k) d->solenoid.force[k] = force[k];
    d->current_max = 1.0;
    d->piston_area = 0.0003141592653589793;
    d->piston_mass = 0.03;
    d->piston_spring_rate = 6400.0;
    d->piston_preload = 8.0;
    d->piston_damping = 100.0;
    d->piston_friction = 0.2;
    d->piston_friction_velocity = 0.0001;
    d->piston_travel = 0.001;
    d->seat_lap = 2e-05;
    d->epv_inlet_diameter = 0.00195;
    d->epv_exhaust_diameter = 0.00195;
    d->membrane_points = 5;
    { static const double v[] = {-0.003, -0.0015, 0.0, 0.0015, 0.003}; for (int i = 0; i < 5; ++i) d->membrane_x[i] = v[i]; }
    { static const double v[] = {-2.4e-05, -1.1599999999999999e-05, 0.0, 1.09e-05, 2.1e-05}; for (int i = 0; i < 5; ++i) d->membrane_volume[i] = v[i]; }
    d->membrane_mass = 0.2;
    d->membrane_spring_rate = 58000.0;
    d->membrane_preload = 0.0;
    d->membrane_damping = 150.0;
    d->membrane_travel = 0.003;
    d->relay_inlet_diameter = 0.00505;
    d->relay_exhaust_diameter = 0.00505;
    d->thermal_time = 1.5;
    d->trim_time = 0.5;
    d->rtol = 0.0001;
    d->atol = 0.0001;
    d->mechanics_dt = 0.0001;
}

#endif
