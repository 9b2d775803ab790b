/* Parameters changed during a scenario run (rb_run_retune, rb_run.h): the native counterpart of
 * the FMU's tunable parameters. */
#include "railbrake/rb_bounds.h"
#include "railbrake/rb_run.h"

rb_status rb_run_retune(const rb_plant_params *plant, const rb_wsp_params *wsp, rb_run_state *run, rb_error *err)
{
    rb_status s;
    if (!run) return rb_fail(err, RB_EINVAL, "run = NULL: a run state is required");
    /* both checked before either changes: a refused call changes nothing */
    if ((s = rb_wsp_check(wsp, err)) || (s = rb_plant_retune_adhesion(plant, &run->plant, err))) return s;
    return rb_bcu_retune_wsp(&run->bcu, wsp, err);
}
