/* Many runs in one call: each variant's own plant, BCU and scenario, run to its end without
 * recording, its KPIs (or its error) into the caller's arrays. A study's worker hands a batch of
 * variants to C at once (railbrake.simulation.run_batch). */
#include "railbrake/rb_run.h"

#include <stdio.h>
#include <string.h>

rb_status rb_run_batch(int n, const rb_plant_params *plants, const rb_bcu_params *bcus, const rb_wsp_params *wsps,
                       const rb_scenario *scenarios, rb_run_state *run, rb_kpis *kpis, int *status,
                       rb_error *errors, rb_error *err)
{
    if (n < 0 || n > RB_MAX_BATCH) return rb_fail(err, RB_EINVAL, "n = %d: must be in [0, %d]", n, RB_MAX_BATCH);
    if (n > 0 && (!plants || !bcus || !scenarios || !run || !kpis || !status))
        return rb_fail(err, RB_EINVAL, "plants, bcus, scenarios, run, kpis and status must not be NULL");
    for (int i = 0; i < n; ++i) {
        rb_error *e = errors ? &errors[i] : NULL;
        int finished = 0;
        const rb_wsp_params *wsp = wsps ? &wsps[i] : NULL;
        memset(&kpis[i], 0, sizeof kpis[i]);
        status[i] = rb_run_init(&plants[i], &bcus[i], wsp, &scenarios[i], run, e);
        if (status[i] == RB_OK)
            status[i] = rb_run_advance(&plants[i], &bcus[i], &scenarios[i], run, scenarios[i].max_time, NULL, 0,
                                       &finished, e);
        if (status[i] == RB_OK) rb_run_kpis(&plants[i], run, &kpis[i]);
    }
    return RB_OK;
}
