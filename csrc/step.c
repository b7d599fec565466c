/* SPDX-License-Identifier: MIT */
/*
 * One control period: a state in, the state at the period's end out (docs/model.md, "Continuing
 * from a prediction"), so that a controller, an estimator or a co-simulation unit can run the
 * model cycle by cycle on caller-owned structs.
 */
#include <limits.h>
#include "crane_internal.h"

/* The state a prediction continues from at a sample (the rule of Trajectory.state in the Python
 * layer): the sample's strokes, slew, extension and their rates, every actuator's chamber
 * pressures and spool, and each boom cylinder's stroke rate omega ds/dtheta at the sample's
 * stroke (0 when omega is 0: a held or stopped joint). */
static void state_at(const crane_model *m, const crane_sample *o, crane_state *s)
{
    int i;

    for (i = 0; i < 2; ++i) {
        crane_real theta, ds = 0;
        s->stroke[i] = o->stroke[i];
        if (o->omega[i] != 0) {
            (void)crane_joint_angle(m, i, o->stroke[i], &theta, &ds);
        }
        s->stroke_rate[i] = o->omega[i] != 0 ? o->omega[i] * ds : 0;
    }
    s->slew = o->slew;
    s->extension = o->extension;
    s->slew_rate = o->slew_rate;
    s->extension_rate = o->extension_rate;
    for (i = 0; i < 4; ++i) {
        s->p_a[i] = o->p_a[i];
        s->p_b[i] = o->p_b[i];
        s->spool[i] = o->spool[i];
    }
}

crane_status crane_step(const crane_model *model, const crane_state *state,
                        const crane_inputs *inputs, crane_real period, crane_real dt,
                        crane_state *next, crane_sample out[2], crane_work *work)
{
    crane_status st;
    size_t n_written;

    if (model == NULL || state == NULL || inputs == NULL || next == NULL || out == NULL ||
        work == NULL) {
        return CRANE_E_NULL;
    }
    /* LONG_MAX: no step but the last is kept, so out[2] holds the period's two ends */
    st = crane__predict_every(model, state, inputs, period, dt, LONG_MAX, out, 2, &n_written, work);
    if (st != CRANE_OK) {
        return st;
    }
    state_at(model, &out[1], next);
    return CRANE_OK;
}
