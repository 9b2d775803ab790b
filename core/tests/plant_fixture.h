/* A plausible high-speed train for the C tests (values as in docs/simulation.md). */
#ifndef RB_PLANT_FIXTURE_H
#define RB_PLANT_FIXTURE_H

#include <string.h>

#include "railbrake/rb_plant.h"

/* A plausible high-speed car (values as in docs/simulation.md). */
static inline void fill_car(rb_plant_car *c)
{
    memset(c, 0, sizeof *c);
    rb_car *v = &c->vehicle;
    v->motor = 0;
    v->axles = 4;
    v->mass = 50e3;
    v->wheelset = (rb_wheelset){0.43, 120.0, 50e3 / 4};
    v->brake.discs = 3;
    v->brake.mean_radius = 0.247;
    v->brake.caliper = (rb_caliper){0.0314, 1500.0, 3.0, 0.92, 1.01325e5};
    rb_pad_friction_sintered(0.42, &v->brake.pad, NULL);
    v->supply_pressure = 1.01325e5 + 4.5e5;
    c->length = 25.0;
    c->axle_position[0] = 3.0; c->axle_position[1] = 5.5;
    c->axle_position[2] = 19.5; c->axle_position[3] = 22.0;
    c->contact = (rb_creep_contact){6.0e-3, 5.0e-3, 4.5, 8.1e10};
    c->ed_tau = 0.3;
    c->supply_volume = 0.1; c->pilot_volume = 0.5e-3; c->relay_volume = 1.0e-3;
    c->cylinder_volume = 1.5e-3; c->pipe_volume = 0.0123;
    c->charge_area = 7e-6; c->ep_area = 3e-6; c->ep_tau = 0.1; c->ep_band = 0.1e5;
    c->relay_supply_area = 20e-6; c->relay_exhaust_area = 20e-6; c->relay_band = 0.1e5; c->relay_travel = 1.0;
    c->hold_area = 20e-6; c->vent_area = 20e-6; c->valve_delay = 0.015; c->pipe_area = 100e-6;
}

static inline void fill_plant(rb_plant_params *p, int n_cars, double speed)
{
    memset(p, 0, sizeof *p);
    p->n_cars = n_cars; p->dt = 1e-3; p->substeps = 1; p->temperature = 293.15; p->ambient_temperature = 293.15; p->atmosphere = 1.01325e5;
    p->discharge_coefficient = 0.8; p->critical_ratio = 0.528;
    for (int i = 0; i < n_cars; ++i) fill_car(&p->car[i]);
    p->coupler = (rb_coupler){0.01, 1e7, 0.0, 2e5};
    p->main_reservoir_volume = 0.5; p->main_reservoir_area = 100e-6;
    p->compressor_flow = 0.03; p->governor_on = 8.5e5; p->governor_off = 10e5;
    p->initial_pressure = 9.5e5; p->initial_speed = speed;
    p->n_conditions = 1;
    p->condition[0] = (rb_plant_condition){{0.55, 0.40, 0.60, 1.0, 0.4, 0.0}, 1.0, 0.0, 0.0};  /* Polach dry */
    p->creep_speed_min = 1.0;
}

#endif
