/* Scenario runner: BCU + plant, decimated time series, KPIs (the plant benchmark: plant_bench.c). */
#include "run_internal.h"
#include "railbrake/rb_bounds.h"
#include "channels_internal.h"
#include "plant_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define LOCK_SPEED (10.0 / 3.6)   /* m/s: locks count above 10 km/h */
#define SLIDE_SLIP 0.02           /* |slip| above which an axle slid (worst_axle) [T] */

size_t rb_run_state_size(void) { return sizeof(rb_run_state); }
size_t rb_kpis_size(void) { return sizeof(rb_kpis); }

enum { GLOBAL_CHANNELS = 10, CAR_CHANNELS = 4, AXLE_CHANNELS = 9 };
static const rb_channel_name global_names[GLOBAL_CHANNELS] = {
    {"time", "s"}, {"speed", "m/s"}, {"position", "m"}, {"deceleration", "m/s^2"},
    {"demand_deceleration", "m/s^2"}, {"main_reservoir", "Pa"}, {"pipe_end", "Pa"},
    {"compressor_on", "1"}, {"air_vented", "kg"}, {"air_drawn", "kg"}};
static const rb_channel_name car_names[CAR_CHANNELS] = {
    {"supply", "Pa"}, {"pilot", "Pa"}, {"relay", "Pa"}, {"ed_force", "N"}};
static const rb_channel_name axle_names[AXLE_CHANNELS] = {
    {"wheel_speed", "m/s"}, {"slip", "1"}, {"cylinder", "Pa"}, {"hold", "1"}, {"vent", "1"},
    {"adhesion", "1"}, {"disc_temperature", "K"}, {"brake_energy", "J"},
    {"wsp_mode", "1"}};

static const rb_channel_layout layout = {global_names, car_names, axle_names,
                                         GLOBAL_CHANNELS, CAR_CHANNELS, AXLE_CHANNELS};

int rb_run_channel_count(int n_cars) { return rb_channel_count(&layout, n_cars); }

rb_status rb_run_channel_info(int index, int n_cars, char *name, size_t name_size, char *unit,
                              size_t unit_size, rb_error *err)
{
    return rb_channel_info(&layout, index, n_cars, name, name_size, unit, unit_size, err);
}

rb_brake_demand rb_scenario_demand(const rb_scenario *sc, double t)
{
    rb_brake_demand d = {0.0, 0.0};
    for (int i = 0; i < sc->n_demand && sc->demand_time[i] <= t + 1e-12; ++i) {
        d.service = sc->demand_service[i];
        d.emergency = sc->demand_emergency[i];
    }
    return d;
}

rb_status rb_run_check_scenario(const rb_scenario *sc, rb_error *err)
{
    rb_status s;
    if (sc->n_demand < 1 || sc->n_demand > RB_MAX_DEMAND_STEPS)
        return rb_fail(err, RB_EINVAL, "n_demand = %d: must be in [1, %d]", sc->n_demand, RB_MAX_DEMAND_STEPS);
    for (int i = 0; i < sc->n_demand; ++i) {
        if ((s = rb_check_nonnegative(err, "demand_time", sc->demand_time[i]))) return s;
        if (i > 0 && !(sc->demand_time[i] > sc->demand_time[i - 1]))
            return rb_fail(err, RB_EINVAL, "demand_time[%d] = %g: times must increase", i, sc->demand_time[i]);
        if ((s = rb_check_range(err, "demand_service", sc->demand_service[i], 0.0, 1.0))) return s;
    }
    if ((s = rb_check_range(err, "max_time", sc->max_time, 0.0, 3600.0))) return s;
    if ((s = rb_check_nonnegative(err, "stop_speed", sc->stop_speed))) return s;
    if ((s = rb_check_positive(err, "record_interval", sc->record_interval))) return s;
    if ((s = rb_check_positive(err, "adhesion_interval", sc->adhesion_interval))) return s;
    if (sc->n_speed_marks < 0 || sc->n_speed_marks > RB_MAX_SPEED_MARKS)
        return rb_fail(err, RB_EINVAL, "n_speed_marks = %d: must be in [0, %d]", sc->n_speed_marks, RB_MAX_SPEED_MARKS);
    for (int i = 0; i < sc->n_speed_marks; ++i) {
        if ((s = rb_check_nonnegative(err, "speed_mark", sc->speed_mark[i]))) return s;
        if (i > 0 && !(sc->speed_mark[i] < sc->speed_mark[i - 1]))
            return rb_fail(err, RB_EINVAL, "speed_mark[%d] = %g m/s: the marks must decrease", i, sc->speed_mark[i]);
    }
    return RB_OK;
}

rb_status rb_run_init(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_wsp_params *wsp,
                      const rb_scenario *scenario, rb_run_state *run, rb_error *err)
{
    rb_status s;
    if (!run || !scenario) return rb_fail(err, RB_EINVAL, "run and scenario must not be NULL");
    if ((s = rb_run_check_scenario(scenario, err))) return s;
    memset(run, 0, sizeof *run);
    if ((s = rb_plant_init(plant, &run->plant, err))) return s;
    if ((s = rb_plant_bounds_check(plant, err))) return s;
    if ((s = rb_bcu_init(bcu, wsp, &run->bcu, err))) return s;
    if (bcu->n_cars != plant->n_cars)
        return rb_fail(err, RB_EINVAL, "bcu.n_cars = %d: must equal the plant's n_cars = %d", bcu->n_cars, plant->n_cars);
    rb_plant_get_outputs(plant, &run->plant, &run->out);
    rb_run_start_kpis(plant, run);
    return RB_OK;
}

void rb_run_start_kpis(const rb_plant_params *plant, rb_run_state *run)
{
    run->min_main_reservoir = run->out.main_reservoir;
    run->total_mass = 0.0;
    for (int c = 0; c < plant->n_cars; ++c) {
        run->car_min_supply[c] = run->out.supply[c];
        run->car_min_supply_margin[c] = HUGE_VAL;
        run->total_mass += plant->car[c].vehicle.mass;
    }
    for (int a = 0; a < plant->n_cars * RB_AXLES_PER_CAR; ++a) {
        run->axle_max_disc_temperature[a] = run->axle_max_disc_surface_temperature[a] = plant->ambient_temperature;
        run->axle_pad_distance[a] = run->axle_pad_friction_distance[a] = 0.0;
        run->adhesion_axle[a] = !rb_run_car_isolated(plant, a / RB_AXLES_PER_CAR);
        run->peak_log_creep[a] = NAN;
        run->peak_zone[a] = -1;
        run->peak_maxima[a] = 0;
        run->last_hold[a] = run->out.hold[a];
        run->last_vent[a] = run->out.vent[a];
    }
}

void rb_run_record_row(const rb_plant_params *p, const rb_plant_outputs *o, const rb_bcu_params *bcu,
                       const rb_bcu_state *bs, const rb_scenario *sc, double *row)
{
    int n = p->n_cars, na = n * RB_AXLES_PER_CAR;
    rb_brake_demand d = rb_scenario_demand(sc, o->time);
    double g[GLOBAL_CHANNELS] = {o->time, o->speed, o->position, o->deceleration,
                                 rb_bcu_demand_deceleration(bcu, &d, rb_bcu_speed(o, n)),
                                 o->main_reservoir, o->pipe_end, (double)o->compressor_on, o->air_vented,
                                 o->air_drawn};
    memcpy(row, g, sizeof g);
    row += GLOBAL_CHANNELS;
    for (int c = 0; c < n; ++c) {
        row[c] = o->supply[c];
        row[n + c] = o->pilot[c];
        row[2 * n + c] = o->relay[c];
        row[3 * n + c] = o->ed_force[c];
    }
    row += CAR_CHANNELS * n;
    for (int a = 0; a < na; ++a) {
        row[a] = o->wheel_speed[a];
        row[na + a] = o->slip[a];
        row[2 * na + a] = o->cylinder[a];
        row[3 * na + a] = o->hold[a];
        row[4 * na + a] = o->vent[a];
        row[5 * na + a] = o->adhesion[a];
        row[6 * na + a] = o->disc_temperature[a];
        row[7 * na + a] = o->brake_energy[a];
        row[8 * na + a] = (double)rb_bcu_wsp_mode(bcu, bs, a);
    }
}

int rb_run_car_isolated(const rb_plant_params *p, int car)
{
    for (int i = 0; i < p->n_faults; ++i)
        if (p->fault[i].kind == RB_FAULT_CAR_ISOLATED && p->fault[i].car == car) return 1;
    return 0;
}

/* The available peak adhesion, mean over the axles of the cars not isolated (< 0: none). Each
 * axle's peak is followed from its last sample (about 5 evaluations of Polach's law, against some
 * 200 for a search of the whole curve). The whole curve is searched at the first sample, after a
 * change of adhesion condition, and at every sample while it has more than one inner maximum
 * (another branch could rise above the followed one). Such a branch can form as the train slows,
 * as a shallow hump a few tenths of a decade of creep beside the other: one axle in turn is
 * searched every RESCAN_EVERY samples to see it form. */
#define RESCAN_EVERY 4

static double mean_peak_adhesion(const rb_plant_params *p, rb_run_state *r)
{
    int n_axles = p->n_cars * RB_AXLES_PER_CAR, n = 0, tracked[RB_PLANT_MAX_AXLES], n_tracked = 0;
    int rescan_axle = r->peak_samples % RESCAN_EVERY == 0 ? (int)(r->peak_rescans++ % n_axles) : -1;
    double peak[RB_PLANT_MAX_AXLES], log_creep[RB_PLANT_MAX_AXLES], followed[RB_PLANT_MAX_AXLES], sum = 0.0;
    for (int a = 0; a < n_axles; ++a) {
        if (!r->adhesion_axle[a]) continue;
        if (r->plant.zone_of[a] != r->peak_zone[a]) {   /* another condition */
            r->peak_zone[a] = r->plant.zone_of[a];
            r->peak_log_creep[a] = NAN;
        }
        if (a == rescan_axle || r->peak_maxima[a] != 1 || isnan(r->peak_log_creep[a])) {
            peak[a] = rb_plant_peak_adhesion_track(p, &r->plant, a, &r->peak_log_creep[a], &r->peak_maxima[a]);
        } else {   /* followed, all together (rb_plant_peaks_track: their evaluations side by side) */
            tracked[n_tracked] = a;
            log_creep[n_tracked++] = r->peak_log_creep[a];
        }
    }
    if (n_tracked > 0) rb_plant_peaks_track(p, &r->plant, tracked, n_tracked, log_creep, followed);
    for (int i = 0; i < n_tracked; ++i) {
        peak[tracked[i]] = followed[i];
        r->peak_log_creep[tracked[i]] = log_creep[i];
    }
    for (int a = 0; a < n_axles; ++a) {   /* summed in the axles' order */
        if (!r->adhesion_axle[a]) continue;
        sum += peak[a];
        ++n;
    }
    return n > 0 ? sum / n : -1.0;
}

static inline double larger(double x, double y) { return x > y ? x : y; }
static inline double smaller(double x, double y) { return x < y ? x : y; }

/* The axles after a braking step, over the train in simple loops (vectors; the cars' figures
 * repeated per axle first): slips above 10 km/h, locks, cylinder shortfalls (a cylinder short of
 * its car's demand with the WSP valves at rest: the air did not get there); each axle's extremes,
 * the train's taken at the end. The lock events that began in the step are returned. */
static inline int accumulate_axles(const rb_plant_params *p, rb_run_state *r)
{
    const rb_plant_outputs *o = &r->out;
    /* flags as wide as the doubles they select between: no packing between lane widths */
    double demand[RB_PLANT_MAX_AXLES], lock_speed[RB_PLANT_MAX_AXLES], dt = p->dt;
    int64_t counts[RB_PLANT_MAX_AXLES], events = 0;
    int n = p->n_cars * RB_AXLES_PER_CAR;
    for (int c = 0; c < p->n_cars; ++c)
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            demand[a] = r->in.pressure_demand[c];
            lock_speed[a] = 0.1 * o->car_speed[c];
            counts[a] = o->car_speed[c] > LOCK_SPEED;
        }
    for (int a = 0; a < n; ++a) {
        int64_t short_of = ((o->hold[a] | o->vent[a]) == 0) & (demand[a] - o->cylinder[a] > RB_SHORTFALL_PA);
        r->shortfall_time[a] = short_of ? r->shortfall_time[a] + dt : 0.0;
        r->axle_max_shortfall[a] = larger(r->shortfall_time[a], r->axle_max_shortfall[a]);
    }
    for (int a = 0; a < n; ++a) {
        double slip = fabs(o->slip[a]);
        r->axle_max_slip[a] = counts[a] ? larger(slip, r->axle_max_slip[a]) : r->axle_max_slip[a];
    }
    for (int a = 0; a < n; ++a) {
        int64_t locked = counts[a] & (o->wheel_speed[a] < lock_speed[a]);
        int64_t begins = locked & (r->lock_time[a] == 0.0);
        events += begins;
        r->axle_locks[a] += begins ? 1.0 : 0.0;
        r->lock_time[a] = locked ? r->lock_time[a] + dt : (counts[a] ? 0.0 : r->lock_time[a]);
        r->axle_max_lock[a] = larger(r->lock_time[a], r->axle_max_lock[a]);
    }
    return (int)events;
}

/* The WSP's effort and the wheel-flat risk after a braking step: the valves' changes of state
 * (the outputs are the valves' actual states, after their response delays), and each axle's
 * sliding energy, the work of its creep force F on the slip velocity w = omega r - v (both of the
 * same sign: F w >= 0 is the power the contact dissipates). */
static inline void accumulate_effort(const rb_plant_params *p, rb_run_state *r)
{
    const rb_plant_outputs *o = &r->out;
    const rb_plant_state *s = &r->plant;
    long switches = 0;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        switches += (o->hold[a] != r->last_hold[a]) + (o->vent[a] != r->last_vent[a]);
        r->last_hold[a] = o->hold[a];
        r->last_vent[a] = o->vent[a];
    }
    r->valve_switchings += switches;
    for (int c = 0; c < p->n_cars; ++c)
        for (int a = c * RB_AXLES_PER_CAR; a < (c + 1) * RB_AXLES_PER_CAR; ++a) {
            double wheel = s->omega[a] * s->derived.axle_radius[a], w = wheel - s->v[c];
            r->axle_sliding_energy[a] += s->force[a] * w * p->dt;
            double ds = s->brake_torque[a] > 0.0 ? wheel * p->dt : 0.0;   /* the pads slide while they press */
            r->axle_pad_distance[a] += ds;
            r->axle_pad_friction_distance[a] += s->pad_friction[a] * ds;
        }
}

/* The speed marks the train passed in this step, each placed linearly between the last step's
 * speed and this one's (the step is 1 ms: the error is a fraction of a millimetre). */
static void pass_marks(const rb_scenario *sc, rb_run_state *r)
{
    const rb_plant_outputs *o = &r->out;
    while (r->marks_passed < sc->n_speed_marks && o->speed <= sc->speed_mark[r->marks_passed]) {
        int i = r->marks_passed++;
        double drop = r->last_speed - o->speed, above = r->last_speed - sc->speed_mark[i];
        /* a mark at or above the last speed (the speed at the demand): passed then */
        double f = above <= 0.0 ? 0.0 : above / drop;
        r->mark_time[i] = r->last_time + f * (o->time - r->last_time);
        r->mark_position[i] = r->last_position + f * (o->position - r->last_position);
    }
    r->last_time = o->time;
    r->last_speed = o->speed;
    r->last_position = o->position;
}

/* KPI accumulation after one step: air supply minima and the hottest disc always; while
 * braking, the supply margin, the axles and the sampled available adhesion. */
static inline void accumulate(const rb_plant_params *p, const rb_scenario *sc, rb_run_state *r)
{
    const rb_plant_outputs *o = &r->out;
    int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    /* summed axle by axle, in the train's order: a chain of subtractions, begun first so that the
       extremes below fill its waits */
    double rail = 0.0;
    if (r->braking)
        for (int a = 0; a < n_axles; ++a) rail -= r->plant.force[a];
    r->min_main_reservoir = smaller(o->main_reservoir, r->min_main_reservoir);
    for (int c = 0; c < p->n_cars; ++c) r->car_min_supply[c] = smaller(o->supply[c], r->car_min_supply[c]);
    for (int a = 0; a < n_axles; ++a)
        r->axle_max_disc_temperature[a] = larger(o->disc_temperature[a], r->axle_max_disc_temperature[a]);
    for (int a = 0; a < n_axles; ++a)
        r->axle_max_disc_surface_temperature[a] = larger(o->disc_surface_temperature[a],
                                                         r->axle_max_disc_surface_temperature[a]);
    if (!r->braking) return;   /* before braking every shortfall, slip and lock is 0 */
    pass_marks(sc, r);
    for (int c = 0; c < p->n_cars; ++c) {
        double demand = r->in.pressure_demand[c], margin = o->supply[c] - demand;
        r->car_min_supply_margin[c] = demand > p->atmosphere ? smaller(margin, r->car_min_supply_margin[c])
                                                            : r->car_min_supply_margin[c];
    }
    r->lock_events += accumulate_axles(p, r);
    accumulate_effort(p, r);
    r->rail_decel_sum += rail / r->total_mass * p->dt;
    r->rail_decel_time += p->dt;
    if (o->time >= r->next_adhesion - 1e-9 && o->speed > LOCK_SPEED) {
        double peak = mean_peak_adhesion(p, r);
        if (peak >= 0.0) { r->peak_sum += peak; r->peak_samples++; }
        r->next_adhesion += sc->adhesion_interval;
    }
}

/* accumulate, flattened and built for the plant's kernel (as the plant's step, plant_step.c) */
RB_FLATTEN static void accumulate_portable(const rb_plant_params *p, const rb_scenario *sc, rb_run_state *r)
{
    accumulate(p, sc, r);
}

#if RB_PLANT_HAVE_AVX2
__attribute__((target("avx2"), flatten))
static void accumulate_avx2(const rb_plant_params *p, const rb_scenario *sc, rb_run_state *r)
{
    accumulate(p, sc, r);
}
#endif

static void accumulate_step(const rb_plant_params *p, const rb_scenario *sc, rb_run_state *r)
{
#if RB_PLANT_HAVE_AVX2
    if (r->plant.kernel == RB_PLANT_KERNEL_AVX2) {
        accumulate_avx2(p, sc, r);
        return;
    }
#endif
    accumulate_portable(p, sc, r);
}

rb_status rb_run_advance(const rb_plant_params *plant, const rb_bcu_params *bcu, const rb_scenario *sc,
                         rb_run_state *r, double t_until, double *series, size_t max_rows, int *finished,
                         rb_error *err)
{
    int nch = rb_run_channel_count(plant->n_cars);
    while (!r->finished && r->out.time < t_until - 1e-9) {
        if (series && r->out.time >= r->next_record - 1e-9) {
            if (r->rows >= max_rows)
                return rb_fail(err, RB_ESIZE, "max_rows = %zu: the series needs more rows", max_rows);
            rb_run_record_row(plant, &r->out, bcu, &r->bcu, sc, series + r->rows * (size_t)nch);
            r->rows++;
            r->next_record += sc->record_interval;
        }
        rb_brake_demand d = rb_scenario_demand(sc, r->out.time);
        if (!r->braking && (d.emergency > 0.5 || d.service > 0.0)) {
            r->braking = 1;
            r->brake_time = r->out.time;
            r->brake_position = r->out.position;
            r->brake_speed = r->out.speed;
            r->next_adhesion = r->out.time;
            r->last_time = r->out.time, r->last_speed = r->out.speed, r->last_position = r->out.position;
        }
        if (rb_bcu_update(bcu, &r->bcu, &d, &r->out)) r->in = r->bcu.command;   /* held between cycles */
        rb_plant_step(plant, &r->plant, &r->in);
        rb_plant_update_step_outputs(plant, &r->plant, &r->out);
        accumulate_step(plant, sc, r);
        r->stopped = r->braking && r->out.speed <= sc->stop_speed;
        r->finished = r->stopped || r->out.time >= sc->max_time - 1e-9;
        /* the rest of the outputs where they are read: by the next BCU cycle, a record, the end */
        int read = r->finished || r->out.time >= r->bcu.next_cycle - 1e-9 || r->out.time >= t_until - 1e-9 ||
                   (series && r->out.time >= r->next_record - 1e-9);
        if (read) rb_plant_update_outputs(plant, &r->plant, &r->out);
        if (r->finished) {
            if (series && r->rows < max_rows) {
                rb_run_record_row(plant, &r->out, bcu, &r->bcu, sc, series + r->rows * (size_t)nch);
                r->rows++;
            }
        }
    }
    if (finished) *finished = r->finished;
    return RB_OK;
}

void rb_run_accumulate(const rb_plant_params *plant, const rb_scenario *scenario, rb_run_state *run)
{
    accumulate_step(plant, scenario, run);
}

void rb_run_kpis(const rb_plant_params *plant, const rb_run_state *r, rb_kpis *k)
{
    const rb_plant_outputs *o = &r->out;
    memset(k, 0, sizeof *k);
    k->stopped = r->stopped;
    if (r->braking) {
        k->stopping_distance_m = o->position - r->brake_position;
        k->stopping_time_s = o->time - r->brake_time;
        k->mean_deceleration = k->stopping_time_s > 0.0 ? (r->brake_speed - o->speed) / k->stopping_time_s : 0.0;
    }
    int n_axles = plant->n_cars * RB_AXLES_PER_CAR;
    double max_lock = 0.0, max_shortfall = 0.0;   /* the largest of the axles' */
    k->max_slip = 0.0;
    k->max_disc_temperature = plant->ambient_temperature;
    for (int a = 0; a < n_axles; ++a) {
        k->max_slip = larger(r->axle_max_slip[a], k->max_slip);
        max_lock = larger(r->axle_max_lock[a], max_lock);
        max_shortfall = larger(r->axle_max_shortfall[a], max_shortfall);
        k->max_disc_temperature = larger(r->axle_max_disc_temperature[a], k->max_disc_temperature);
    }
    k->wheel_lock_events = r->lock_events;
    k->max_lock_duration_s = max_lock;
    k->air_consumed_kg = o->air_vented;
    double peak = r->peak_samples ? r->peak_sum / r->peak_samples : 0.0;
    double rail = r->rail_decel_time > 0.0 ? r->rail_decel_sum / r->rail_decel_time : 0.0;
    k->adhesion_utilisation = peak > 0.0 ? rail / (RB_G * peak) : 0.0;
    k->safety_timer_trips = r->bcu.wsp_default.trips;
    double m0 = r->plant.m_initial;
    k->air_balance_error = fabs(o->air_in_system + o->air_vented - o->air_compressed - m0) / m0;
    k->min_main_reservoir = r->min_main_reservoir;
    k->min_supply = HUGE_VAL;
    double min_margin = HUGE_VAL;
    for (int c = 0; c < plant->n_cars; ++c) {
        k->min_supply = smaller(r->car_min_supply[c], k->min_supply);
        min_margin = smaller(r->car_min_supply_margin[c], min_margin);
    }
    k->air_drawn_kg = o->air_drawn;
    k->air_vented_kg = o->air_vented;
    k->cylinder_shortfall_s = max_shortfall;
    k->worst_axle = -1.0;
    double worst_locks = 0.0, worst_slip = 0.0;
    for (int a = 0; a < n_axles; ++a) {
        k->brake_energy += o->brake_energy[a];
        int worse = r->axle_locks[a] > worst_locks ||
                    (r->axle_locks[a] == worst_locks && r->axle_max_slip[a] > worst_slip);
        if (worse && (r->axle_locks[a] > 0 || r->axle_max_slip[a] > SLIDE_SLIP)) {
            k->worst_axle = a;
            worst_locks = r->axle_locks[a];
            worst_slip = r->axle_max_slip[a];
        }
    }
    k->valve_switchings = (double)r->valve_switchings;
    for (int a = 0; a < n_axles; ++a) {
        k->sliding_energy += r->axle_sliding_energy[a];
        k->max_sliding_energy = larger(r->axle_sliding_energy[a], k->max_sliding_energy);
    }
    double pad_distance = 0.0, pad_friction_distance = 0.0;
    k->max_disc_surface_temperature = plant->ambient_temperature;
    for (int a = 0; a < n_axles; ++a) {
        pad_distance += r->axle_pad_distance[a];
        pad_friction_distance += r->axle_pad_friction_distance[a];
        k->max_disc_surface_temperature = larger(r->axle_max_disc_surface_temperature[a], k->max_disc_surface_temperature);
    }
    k->mean_pad_friction = pad_distance > 0.0 ? pad_friction_distance / pad_distance : 0.0;
    for (int i = 0; i < RB_MAX_SPEED_MARKS; ++i) {
        int passed = i < r->marks_passed;
        k->mark_time_s[i] = passed ? r->mark_time[i] - r->brake_time : -1.0;
        k->mark_distance_m[i] = passed ? r->mark_position[i] - r->brake_position : -1.0;
    }
    k->min_supply_margin = min_margin == HUGE_VAL ? 0.0 : min_margin;
}
