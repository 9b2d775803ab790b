/* Rail conditioning by the energy the axles dissipate in the contact, cell by cell along the track.
 *
 * The rail under the train is a ring of cells of rail_cell_length; each carries a contamination
 * c (1: as laid, 0: cleaned). A cell enters the ring as laid when the leading axle reaches it. In
 * each step every axle on a conditioned condition (reference_energy > 0) leaves on the rail strip
 * its two contacts pass (each 2b wide, carrying half the axle's creep force) the energy density
 * e = |F/2 w| / (2 b v) over its travel v dt (rb_dissipated_energy_density); spread over its cell,
 * that is e v dt / cell_length, and the cell keeps
 *     c <- c exp(-e v dt / (cell_length reference_energy)),
 * so that after the energy E the cell's mu0 factor is 1 - (1 - leading_factor) exp(-E / E_ref):
 * the law of rb_conditioning_energy_factor (Allotta et al., Tribology International 69 (2014)
 * 128-140, there of the specific friction power; source and assumptions in rb_contact.h). With the
 * same e for every axle the axle-count law results, recovery_axles = E_ref / e. The axles behind
 * then see the cell their predecessors cleaned: the adhesion they find follows what the axles
 * ahead slid, not their index. An infinite reference_energy keeps the cells (sand conditions
 * them) without the sliding wheels cleaning them: a contaminant they do not remove.
 *
 * Sanders are a second source: the sand a sander drops lies loose on the cell ahead of its axle.
 * Each axle that meets a cell entrains the fraction sand_entrained of its loose sand into the
 * contact, where crushed it multiplies the cell's contamination by exp(-m / sand_reference) (m kg
 * per metre of track), and leaves the fraction sand_retention loose for the axles behind; the rest
 * is carried away. So the sander's axle and every axle behind brake on rail the sand improves
 * further with each passage (never less), by steps that shrink as the sand is used up. A fixed-rate sander drops R kg/s, R / v kg per
 * metre, more as the train slows; a variable-rate one R(v), a table over its car's speed (R = q v
 * lays q kg per metre at every speed). The law's form mirrors the energy law; its one
 * parameter has no published value (sand rates and their adhesion gain are not public in the
 * sources found, src/railbrake/data/references/sander_tests.yaml): an input [T], the one to
 * calibrate on a full-scale sander test. */
#include "plant_internal.h"
#include "railbrake/rb_bounds.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

static int condition_conditions(const rb_plant_condition *c) { return c->reference_energy > 0.0; }

static int rail_in_use(const rb_plant_params *p)
{
    for (int i = 0; i < p->n_conditions; ++i)
        if (condition_conditions(&p->condition[i])) return 1;
    return 0;
}

rb_status rb_rail_check(const rb_plant_params *p, rb_error *err)
{
    for (int i = 0; i < p->n_conditions; ++i) {
        const rb_plant_condition *c = &p->condition[i];
        if (isnan(c->reference_energy) || c->reference_energy < 0.0)
            return rb_fail(err, RB_EINVAL, "condition[%d].reference_energy = %g J/m2: must be >= 0 (0: no rail cells; "
                           "infinite: cells the sliding wheels do not clean)", i, c->reference_energy);
        if (c->reference_energy > 0.0 && isfinite(c->reference_energy)) {
            char name[48];
            snprintf(name, sizeof name, "condition[%d].reference_energy", i);
            rb_status st = rb_bound_check(err, "adhesion.reference_energy", name, c->reference_energy);
            if (st) return st;
        }
        if (c->reference_energy > 0.0 && c->recovery_axles > 0.0)
            return rb_fail(err, RB_EINVAL,
                           "condition[%d]: reference_energy = %g J/m2 and recovery_axles = %g both set: the rail is "
                           "conditioned by energy or by axle index, not both (set one to 0)",
                           i, c->reference_energy, c->recovery_axles);
        if (c->reference_energy > 0.0 && (!(c->leading_factor > 0.0) || c->leading_factor > 1.0))
            return rb_fail(err, RB_EINVAL, "condition[%d].leading_factor = %g: must lie in (0, 1]", i,
                           c->leading_factor);
    }
    if (p->n_sanders < 0 || p->n_sanders > RB_MAX_SANDERS)
        return rb_fail(err, RB_EINVAL, "n_sanders = %d: must be in [0, %d]", p->n_sanders, RB_MAX_SANDERS);
    if (p->n_sanders > 0 && !rail_in_use(p))
        return rb_fail(err, RB_EINVAL, "n_sanders = %d: sand conditions the rail cells, which no condition uses "
                       "(give a condition a reference_energy > 0)", p->n_sanders);
    for (int i = 0; i < p->n_sanders; ++i) {
        if (p->sander_axle[i] < 0 || p->sander_axle[i] >= p->n_cars * RB_AXLES_PER_CAR)
            return rb_fail(err, RB_EINVAL, "sander[%d].axle = %d: must be in [0, %d]", i, p->sander_axle[i],
                           p->n_cars * RB_AXLES_PER_CAR - 1);
        if (p->sander_trigger[i] != RB_SAND_DRIVER && p->sander_trigger[i] != RB_SAND_WSP)
            return rb_fail(err, RB_EINVAL, "sander[%d].trigger = %d: must be %d (driver) or %d (WSP)", i,
                           p->sander_trigger[i], RB_SAND_DRIVER, RB_SAND_WSP);
        char name[32];
        snprintf(name, sizeof name, "sander[%d].rate", i);
        const rb_bound *rate = rb_bound_find("train.sand_rate");
        rb_status st = rb_speed_table_check(&p->sander_rate[i], name, rate->min, rate->max, err);
        if (st) return st;
        double largest = 0.0;
        for (int k = 0; k < p->sander_rate[i].n; ++k) largest = fmax(largest, p->sander_rate[i].value[k]);
        if (!(largest > 0.0))
            return rb_fail(err, RB_EINVAL, "%s: every rate is 0 kg/s: the sander never sands", name);
        if (!(p->sander_start[i] >= 0.0 && isfinite(p->sander_start[i])))
            return rb_fail(err, RB_EINVAL, "sander[%d].start = %g s: must be >= 0", i, p->sander_start[i]);
    }
    if (p->n_sanders > 0 && !(p->sand_reference > 0.0 && p->sand_reference <= 10.0))
        return rb_fail(err, RB_EINVAL, "sand_reference = %g kg/m: must be in (0, 10] kg/m", p->sand_reference);
    if (p->n_sanders > 0 && !(p->sand_entrained > 0.0 && p->sand_entrained <= 1.0))
        return rb_fail(err, RB_EINVAL, "sand_entrained = %g: must be in (0, 1]", p->sand_entrained);
    if (p->n_sanders > 0 && !(p->sand_retention >= 0.0 && p->sand_retention + p->sand_entrained <= 1.0))
        return rb_fail(err, RB_EINVAL, "sand_retention = %g: must be in [0, 1 - sand_entrained = %g]",
                       p->sand_retention, 1.0 - p->sand_entrained);
    if (!rail_in_use(p)) return RB_OK;
    rb_status st;
    if ((st = rb_bound_check(err, "adhesion.rail_cell_length", "rail_cell_length", p->rail_cell_length))) return st;
    double length = 0.0;
    for (int c = 0; c < p->n_cars; ++c) length += p->car[c].length;
    /* the train's length (couplers stretch by millimetres) plus a cell at each end */
    double cells = length / p->rail_cell_length + 3.0;
    if (cells > RB_RAIL_MAX_CELLS)
        return rb_fail(err, RB_EINVAL,
                       "rail_cell_length = %g m: the train's %g m need %.0f cells, more than the %d the plant holds: "
                       "use cells of at least %g m",
                       p->rail_cell_length, length, ceil(cells), RB_RAIL_MAX_CELLS,
                       length / (RB_RAIL_MAX_CELLS - 3.0));
    return RB_OK;
}

static double axle_x(const rb_plant_params *p, const rb_plant_state *s, int axle)
{
    int c = axle / RB_AXLES_PER_CAR;
    return s->x[c] - p->car[c].axle_position[axle % RB_AXLES_PER_CAR];
}

static int64_t cell_of(const rb_plant_params *p, double x) { return (int64_t)floor(x / p->rail_cell_length); }

static int slot_of(int64_t cell)
{
    int64_t m = cell % RB_RAIL_MAX_CELLS;
    return (int)(m < 0 ? m + RB_RAIL_MAX_CELLS : m);
}

void rb_rail_init(const rb_plant_params *p, rb_plant_state *s)
{
    s->rail_active = rail_in_use(p);
    if (!s->rail_active) return;
    for (int i = 0; i < RB_RAIL_MAX_CELLS; ++i) s->rail_contamination[i] = 1.0, s->rail_sand[i] = 0.0;
    s->rail_front = cell_of(p, -p->car[0].axle_position[0]);   /* the leading axle; the train's front at 0 */
    for (int a = 0; a < RB_PLANT_MAX_AXLES; ++a) s->axle_cell[a] = INT64_MIN;   /* set at the first step */
}

double rb_rail_factor(const rb_plant_params *p, const rb_plant_state *s, int axle, double leading_factor)
{
    /* the cell ahead of the one the axle cleans: the rail as the axles ahead left it, which the
       contact meets (its own cell would count the axle's own sliding towards what it sees) */
    int64_t cell = cell_of(p, axle_x(p, s, axle)) + 1;
    double c = cell > s->rail_front ? 1.0 : s->rail_contamination[slot_of(cell)];   /* ahead: as laid */
    return 1.0 - (1.0 - leading_factor) * c;
}

/* Cells up to `cell` enter the ring as laid. */
static void enter_cells(rb_plant_state *s, int64_t cell)
{
    while (s->rail_front < cell) {
        int slot = slot_of(++s->rail_front);
        s->rail_contamination[slot] = 1.0;
        s->rail_sand[slot] = 0.0;
    }
}

/* An axle meets cell k: it crushes the part sand_entrained of the loose sand into the contact and
 * leaves the part sand_retention loose. */
static void pass_sand(const rb_plant_params *p, rb_plant_state *s, int64_t k)
{
    int slot = slot_of(k);
    double loose = s->rail_sand[slot];
    if (!(loose > 0.0)) return;
    s->rail_contamination[slot] *= exp(-p->sand_entrained * loose / p->sand_reference);
    s->rail_sand[slot] = p->sand_retention * loose;
}

/* Sander i's rate (kg/s) at its car's speed: a fixed-rate sander's table has one point. */
static double sander_rate(const rb_plant_params *p, const rb_plant_state *s, int i)
{
    return rb_speed_table_at(&p->sander_rate[i], s->v[p->sander_axle[i] / RB_AXLES_PER_CAR]);
}

/* Whether sander i drops sand in this step: the driver's from its start time, the WSP's while any
 * WSP valve is commanded. */
static int sander_on(const rb_plant_params *p, const rb_plant_state *s, const rb_plant_inputs *in, int i)
{
    if (p->sander_trigger[i] == RB_SAND_DRIVER) return s->time >= p->sander_start[i];
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a)
        if (in->hold[a] || in->vent[a]) return 1;
    return 0;
}

/* The sand of a step falls loose on the cell beyond the one the axle's contact meets now: the
 * axle meets it next (pass_sand). */
static void sand(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in, double dt)
{
    for (int i = 0; i < p->n_sanders; ++i) {
        if (!sander_on(p, s, in, i)) continue;
        double mass = sander_rate(p, s, i) * dt;
        int64_t cell = cell_of(p, axle_x(p, s, p->sander_axle[i])) + 2;
        enter_cells(s, cell);   /* the leading axle's sander sands the rail just ahead of the train */
        s->rail_sand[slot_of(cell)] += mass / p->rail_cell_length;
        s->sand_used += mass;
    }
}

/* Each axle that has come to new cells meets them (in order) and works their loose sand. */
static void axles_meet_sand(const rb_plant_params *p, rb_plant_state *s)
{
    if (p->n_sanders == 0) return;
    for (int a = 0; a < p->n_cars * RB_AXLES_PER_CAR; ++a) {
        int64_t met = cell_of(p, axle_x(p, s, a)) + 1;
        if (met > s->rail_front) met = s->rail_front;   /* beyond: rail as laid, no sand yet */
        if (s->axle_cell[a] == INT64_MIN) s->axle_cell[a] = met;   /* the cars' places are set after init */
        while (s->axle_cell[a] < met) pass_sand(p, s, ++s->axle_cell[a]);
    }
}

void rb_rail_step(const rb_plant_params *p, rb_plant_state *s, const rb_plant_inputs *in, double dt)
{
    const int n_axles = p->n_cars * RB_AXLES_PER_CAR;
    enter_cells(s, cell_of(p, axle_x(p, s, 0)));
    for (int a = 0; a < n_axles; ++a) {
        const rb_plant_condition *cond = &p->condition[s->zone_of[a]];
        if (!condition_conditions(cond)) continue;
        int c = a / RB_AXLES_PER_CAR;
        double v = s->v[c], slip = s->omega[a] * s->derived.axle_radius[a] - v;
        double e = rb_dissipated_energy_density(0.5 * s->force[a], slip, v, 2.0 * p->car[c].contact.b);
        double cleaned = e * v * dt / (p->rail_cell_length * cond->reference_energy);
        int64_t cell = cell_of(p, axle_x(p, s, a));
        if (cell <= s->rail_front) s->rail_contamination[slot_of(cell)] *= exp(-cleaned);
    }
    sand(p, s, in, dt);
    axles_meet_sand(p, s);
    for (int a = 0; a < n_axles; ++a)
        if (condition_conditions(&p->condition[s->zone_of[a]])) rb_plant_condition_axle(p, s, a);
}

/* ---- the adhesion each axle finds: its zone's condition, conditioned by axle index or by the
 * rail cell it stands on (here, below the plant's other parts, which call down into it) */

/* Polach parameters of the condition at axle index `axle` (0 = leading), with conditioning (by
 * axle index, or by the rail cell the axle stands on). */
static rb_polach_params condition_at_axle(const rb_plant_params *p, const rb_plant_state *s, int condition, int axle)
{
    const rb_plant_condition *c = &p->condition[condition];
    rb_polach_params q = c->polach;
    if (c->recovery_axles > 0.0)
        q.mu0 *= rb_conditioning_factor((double)axle, c->leading_factor, c->recovery_axles);
    if (c->reference_energy > 0.0)
        q.mu0 *= rb_rail_factor(p, s, axle, c->leading_factor);
    return q;
}

void rb_plant_set_axle_adhesion(rb_plant_state *s, int axle, const rb_polach_params *q)
{
    rb_plant_derived *d = &s->derived;
    s->polach[axle] = *q;
    d->mu_static[axle] = q->mu0 * q->A;
    d->mu_slip[axle] = q->mu0 * (1.0 - q->A);
    d->polach_v_ref_inv[axle] = q->v_ref_inv;
    d->polach_B[axle] = q->B;
    d->polach_kA_gain[axle] = q->kA * d->polach_gain[axle / RB_AXLES_PER_CAR];   /* derive_mechanics set the gain */
    d->polach_kS_gain[axle] = q->kS * d->polach_gain[axle / RB_AXLES_PER_CAR];
}

int rb_plant_zone_update(const rb_plant_params *p, rb_plant_state *s, int axle, double x)
{
    int condition = 0;
    for (int z = 0; z < p->n_zones; ++z)
        if (x >= p->zone[z].x_start && x < p->zone[z].x_end) condition = p->zone[z].condition;
    if (condition != s->zone_of[axle]) {
        s->zone_of[axle] = condition;
        rb_polach_params q = condition_at_axle(p, s, condition, axle);
        rb_plant_set_axle_adhesion(s, axle, &q);
    }
    return condition;
}

void rb_plant_condition_axle(const rb_plant_params *p, rb_plant_state *s, int axle)
{
    rb_polach_params q = condition_at_axle(p, s, s->zone_of[axle], axle);
    rb_plant_set_axle_adhesion(s, axle, &q);
}
