/* Rail conditioning by dissipated friction energy (law and sources: rb_contact.h). */
#include "railbrake/rb_contact.h"

#include <math.h>

rb_status rb_conditioning_energy_check(const rb_conditioning_energy *c, rb_error *err)
{
    rb_status s;
    if (!c)
        return rb_fail(err, RB_EINVAL, "conditioning must not be NULL");
    if (!isfinite(c->leading_factor) || !(c->leading_factor > 0.0) || c->leading_factor > 1.0)
        return rb_fail(err, RB_EINVAL, "conditioning.leading_factor = %g: must lie in (0, 1]", c->leading_factor);
    if ((s = rb_check_positive(err, "conditioning.reference_energy", c->reference_energy)))
        return s;
    return RB_OK;
}

size_t rb_conditioning_energy_size(void) { return sizeof(rb_conditioning_energy); }

double rb_dissipated_energy_density(double creep_force, double slip_velocity, double speed,
                                    double contact_width)
{
    /* At standstill or without a contact no rail passes under the wheel: nothing is conditioned. */
    if (!(speed > 0.0) || !(contact_width > 0.0))
        return 0.0;
    return fabs(creep_force * slip_velocity) / (contact_width * speed);
}

double rb_conditioning_energy_factor(const rb_conditioning_energy *c, double energy_density)
{
    double e = energy_density > 0.0 ? energy_density : 0.0;
    return 1.0 - (1.0 - c->leading_factor) * exp(-e / c->reference_energy);
}
