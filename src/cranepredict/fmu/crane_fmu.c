/* SPDX-License-Identifier: MIT */
/*
 * The crane as a co-simulation unit (crane_fmu.h): the state at rest at the initial pose, one
 * crane_step per communication step, the variables by value reference. No globals: several
 * instances run side by side in one process.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "crane_fmu.h"

static int fail(cfmu_instance *f, const char *what, crane_status st)
{
    char msg[256];
    snprintf(msg, sizeof msg, "%s: %s (crane status %d)", what, crane_status_message(st), (int)st);
    if (f->log)
        f->log(f->log_env, 1, msg);
    return 1;
}

static int refuse(cfmu_instance *f, const char *msg)
{
    if (f->log)
        f->log(f->log_env, 1, msg);
    return 1;
}

void cfmu_free(cfmu_instance *f)
{
    free(f->future);
    free(f->work);
    free(f->part_clearance);
    f->future = NULL;
    f->work = f->part_clearance = NULL;
    f->future_capacity = 0;
}

void cfmu_init(cfmu_instance *f, cfmu_logger log, void *env)
{
    memset(f, 0, sizeof *f);
    f->log = log;
    f->log_env = env;
    f->s.magic = CFMU_MAGIC;
    f->s.size = (unsigned)sizeof(cfmu_snapshot);
    cfmu_defaults(&f->params, f->s.value);
}

/* The model at the current load and extension (made again when either has changed). */
static int ensure_model(cfmu_instance *f)
{
    crane_status st;

    f->params.load_mass = f->s.value[Q_LOAD_MASS];
    if (f->model_valid && f->model.extension == f->s.state.extension)
        return 0;
    st = crane_model_init(&f->model, &f->params, f->s.state.extension);
    if (st != CRANE_OK)
        return fail(f, "the crane at this load_mass and extension", st);
    f->model_valid = 1;
    return 0;
}

static int valve_driven(int j)
{
    return cfmu_drive == CRANE_DRIVE_VALVE && cfmu_levered[j];
}

/* The drives of one communication step: constant over it (the importer holds its inputs). */
static void drives(const cfmu_instance *f, crane_inputs *in)
{
    static const cfmu_quantity lever[4] = {Q_LIFT_LEVER, Q_TILT_LEVER, Q_SLEW_LEVER,
                                           Q_EXTENSION_LEVER};
    int j;

    memset(in, 0, sizeof *in);
    /* fixed RK4 steps: a fixed cost per communication step, and chained steps that continue one
     * prediction exactly (docs/fmu.md) */
    in->solver.method = CRANE_METHOD_RK4;
    for (j = 0; j < 4; ++j) {
        crane_drive *d = &in->drive[j];
        if (valve_driven(j)) {
            d->mode = CRANE_DRIVE_VALVE;
            d->u = f->s.value[lever[j]];
        } else if (cfmu_drive == CRANE_DRIVE_PRESSURE && j < 2 &&
                   f->s.value[j == 0 ? Q_LIFT_HOLD : Q_TILT_HOLD] == 0) {
            d->mode = CRANE_DRIVE_PRESSURE;
            d->p_a = f->s.value[j == 0 ? Q_LIFT_P_A_IN : Q_TILT_P_A_IN];
            d->p_b = f->s.value[j == 0 ? Q_LIFT_P_B_IN : Q_TILT_P_B_IN];
        } else {
            d->mode = CRANE_DRIVE_HOLD;
        }
    }
}

/* The chamber pressures that hold actuator j still against the force (N, positive extends) with
 * the spool closed (docs/model.md, "Static state at rest"; cranepredict.state_at_rest): the
 * chamber that does not carry the load at the tank pressure. */
static int holding_pressures(cfmu_instance *f, int j, crane_real force)
{
    static const char *const names[4] = {"lift", "tilt", "slew", "extension"};
    const crane_hydraulics *h = j < 2 ? &f->params.cylinder[j].hydraulics
                                : j == CRANE_SLEW ? &f->params.slew_drive.hydraulics
                                                  : &f->params.extension_cylinder.hydraulics;
    const double pi = 3.14159265358979323846;
    crane_real bore, rod, a_a, a_b, p_a, p_b;
    char msg[256];

    if (j < 2) {
        bore = f->params.cylinder[j].bore;
        rod = f->params.cylinder[j].rod;
    } else if (j == CRANE_SLEW) {
        bore = f->params.slew_drive.bore;
        rod = 0;   /* the rack's two bores: A_a = A_b */
    } else {
        bore = f->params.extension_cylinder.bore;
        rod = f->params.extension_cylinder.rod;
    }
    a_a = (crane_real)(pi * bore * bore / 4);
    a_b = j == CRANE_SLEW ? a_a : (crane_real)(pi * (bore * bore - rod * rod) / 4);
    if (force >= 0) {
        p_b = h->tank_pressure;
        p_a = (force + p_b * a_b) / a_a;
    } else {
        p_a = h->tank_pressure;
        p_b = (p_a * a_a - force) / a_b;
    }
    if (!(p_a <= h->relief_pressure && p_b <= h->relief_pressure &&
          p_a >= (crane_real)CRANE_CHAMBER_PRESSURE_MIN && p_b >= (crane_real)CRANE_CHAMBER_PRESSURE_MIN)) {
        snprintf(msg, sizeof msg, "holding the crane at the initial pose with load_mass = %g kg "
                 "needs %s chamber pressures %g / %g bar, outside [%g, %g] bar (the relief "
                 "setting): lighten the load or choose another pose", (double)f->params.load_mass,
                 names[j], (double)p_a / 1e5, (double)p_b / 1e5,
                 (double)CRANE_CHAMBER_PRESSURE_MIN / 1e5, (double)h->relief_pressure / 1e5);
        return refuse(f, msg);
    }
    f->s.state.p_a[j] = p_a;
    f->s.state.p_b[j] = p_b;
    f->s.state.spool[j] = 0;
    return 0;
}

/* The state at rest at the initial pose: the valve-driven actuators' chambers hold the crane
 * (gravity torques from the core's inverse dynamics at zero rates over each cylinder's
 * ds/dtheta; the extension's gravity force along the boom; the slew carries none). */
static int state_at_rest(cfmu_instance *f)
{
    crane_state *s = &f->s.state;
    crane_real theta[2], ds[2], zero[4] = {0, 0, 0, 0}, tau[4], q[4];
    crane_status st;
    int j;

    memset(s, 0, sizeof *s);
    s->stroke[0] = f->s.value[Q_LIFT_STROKE_START];
    s->stroke[1] = f->s.value[Q_TILT_STROKE_START];
    s->slew = f->s.value[Q_SLEW_START];
    s->extension = f->s.value[Q_EXTENSION_START];
    f->model_valid = 0;
    if (ensure_model(f))
        return 1;
    for (j = 0; j < 2; ++j) {
        st = crane_joint_angle(&f->model, j, s->stroke[j], &theta[j], &ds[j]);
        if (st != CRANE_OK)
            return fail(f, j == 0 ? "lift_stroke_start" : "tilt_stroke_start", st);
    }
    q[0] = theta[0];
    q[1] = theta[1];
    q[2] = s->slew;
    q[3] = s->extension;
    st = crane_inverse_dynamics(&f->model, q, zero, zero, tau);
    if (st != CRANE_OK)
        return fail(f, "the holding forces at the initial pose", st);
    for (j = 0; j < 2; ++j)
        if (valve_driven(j) && holding_pressures(f, j, tau[j] / ds[j]))
            return 1;
    if (valve_driven(CRANE_SLEW) && holding_pressures(f, CRANE_SLEW, 0))
        return 1;
    if (valve_driven(CRANE_EXTENSION)) {
        if (holding_pressures(f, CRANE_EXTENSION, tau[3]))
            return 1;
    }
    return 0;
}

/* One period from the current state: the state and the sample at its end; on an error nothing
 * changes. at_start: keep the sample at the period's start instead (the outputs at t0). */
static int advance(cfmu_instance *f, double h, int at_start)
{
    crane_inputs in;
    crane_state next;
    crane_sample out[2];
    crane_status st;
    const double step = f->s.value[Q_STEP];

    if (ensure_model(f))
        return 1;
    drives(f, &in);
    st = crane_step(&f->model, &f->s.state, &in, h, step < h ? step : h, &next, out,
                    &f->prediction);
    if (st != CRANE_OK)
        return fail(f, at_start ? "the initial state" : "doStep", st);
    if (at_start) {
        f->s.sample = out[0];
        return 0;
    }
    f->s.state = next;
    f->s.sample = out[1];
    f->s.time += h;
    return 0;
}

/* The guard's verdict on the future from the current state under the current inputs (held
 * over the guard horizon): a prediction sampled about every 10 ms, judged by crane_guard
 * (docs/guard.md) with its stop that freezes the crane after the reaction time; the signal is
 * STOP for any contact within the horizon. */
static int judge(cfmu_instance *f)
{
    const double horizon = f->s.value[Q_GUARD_HORIZON], step = f->s.value[Q_STEP];
    const double dt = step < horizon ? step : horizon;
    const size_t every = dt < 0.01 ? (size_t)(0.01 / dt + 0.5) : 1;
    crane_inputs in;
    crane_guard_result r;
    crane_status st;
    size_t count, failed, k;
    double least;

    if (cfmu_n_obstacles == 0)
        return 0;
    st = crane_sample_count_every(horizon, dt, every, &count);
    if (st != CRANE_OK)
        return fail(f, "guard_horizon and step", st);
    if (count > f->future_capacity) {
        crane_sample *grown = (crane_sample *)realloc(f->future, count * sizeof *grown);
        if (!grown)
            return refuse(f, "out of memory for the guard's prediction");
        f->future = grown;
        f->future_capacity = count;
    }
    if (!f->work) {
        f->work = (crane_real *)malloc(cfmu_n_parts * (cfmu_n_obstacles + CRANE_GUARD_PART_WORK) *
                                       sizeof(crane_real));
        f->part_clearance = (crane_real *)malloc(cfmu_n_parts * sizeof(crane_real));
        if (!f->work || !f->part_clearance)
            return refuse(f, "out of memory for the guard");
    }
    drives(f, &in);
    f->params.load_mass = f->s.value[Q_LOAD_MASS];
    st = crane_predict_many(&f->params, 1, 1, &f->s.state, &in, horizon, dt, every, f->future, count,
                            &failed, &f->prediction);
    if (st != CRANE_OK)
        return fail(f, "the guard's prediction", st);
    if (ensure_model(f))
        return 1;
    st = crane_guard(&f->model, cfmu_parts, cfmu_n_parts, cfmu_obstacles, cfmu_n_obstacles,
                     f->future, count, &cfmu_guard_config, f->part_clearance, f->work,
                     cfmu_n_parts * (cfmu_n_obstacles + CRANE_GUARD_PART_WORK), &r);
    if (st != CRANE_OK)
        return fail(f, "the guard", st);
    least = f->part_clearance[0];
    for (k = 1; k < cfmu_n_parts; ++k)
        least = f->part_clearance[k] < least ? f->part_clearance[k] : least;
    /* crane_guard's stop freezes the crane after the reaction time; a real stop (valves to
     * neutral, the oil and the inertia carrying on) takes longer, so a WARN by that stop could
     * be optimistic: any predicted contact is a STOP here (conservative, never optimistic). */
    f->s.signal = r.contact ? CRANE_STOP : r.signal;
    f->s.time_to_contact = r.contact ? r.t : horizon;
    f->s.stop_latest = r.contact ? r.stop_latest : horizon;
    f->s.min_clearance = least;
    return 0;
}

/* The state at rest, the outputs at the start and the verdict, from the parameters and inputs
 * as set: at the end of the initialization, and for an output asked for during it. */
static int prepare(cfmu_instance *f)
{
    if (state_at_rest(f))
        return 1;
    if (advance(f, f->s.value[Q_STEP], 1))
        return 1;
    if (judge(f))
        return 1;
    f->s.sample.t = 0;
    return 0;
}

int cfmu_exit_initialization(cfmu_instance *f)
{
    if (prepare(f))
        return 1;
    f->s.initialized = 1;
    return 0;
}

int cfmu_do_step(cfmu_instance *f, double h)
{
    char msg[128];

    if (!f->s.initialized)
        return refuse(f, "doStep before the initialization has ended");
    if (!(h > 0) || !isfinite(h)) {
        snprintf(msg, sizeof msg, "the communication step must be > 0 and finite, got %g", h);
        return refuse(f, msg);
    }
    {
        /* the step and the verdict at its end, or nothing changed */
        const cfmu_snapshot before = f->s;
        if (advance(f, h, 0))
            return 1;
        if (judge(f)) {
            f->s = before;
            return 1;
        }
    }
    return 0;
}

static double output(const cfmu_instance *f, cfmu_quantity q)
{
    const crane_sample *o = &f->s.sample;
    const crane_state *s = &f->s.state;

    switch (q) {
    case Q_TIP_X: return o->tip[0];
    case Q_TIP_Y: return o->tip[1];
    case Q_TIP_Z: return o->tip[2];
    case Q_LIFT_STROKE: return o->stroke[0];
    case Q_TILT_STROKE: return o->stroke[1];
    case Q_LIFT_STROKE_RATE: return s->stroke_rate[0];
    case Q_TILT_STROKE_RATE: return s->stroke_rate[1];
    case Q_LIFT_ANGLE: return o->theta[0];
    case Q_TILT_ANGLE: return o->theta[1];
    case Q_LIFT_ANGLE_RATE: return o->omega[0];
    case Q_TILT_ANGLE_RATE: return o->omega[1];
    case Q_SLEW: return o->slew;
    case Q_SLEW_RATE: return o->slew_rate;
    case Q_EXTENSION: return o->extension;
    case Q_EXTENSION_RATE: return o->extension_rate;
    case Q_LIFT_P_A: return o->p_a[0];
    case Q_LIFT_P_B: return o->p_b[0];
    case Q_TILT_P_A: return o->p_a[1];
    case Q_TILT_P_B: return o->p_b[1];
    case Q_SLEW_P_A: return o->p_a[2];
    case Q_SLEW_P_B: return o->p_b[2];
    case Q_EXTENSION_P_A: return o->p_a[3];
    case Q_EXTENSION_P_B: return o->p_b[3];
    case Q_LIFT_STOP: return o->stop[0];
    case Q_TILT_STOP: return o->stop[1];
    case Q_SLEW_STOP: return o->stop[2];
    case Q_EXTENSION_STOP: return o->stop[3];
    case Q_TIME: return f->s.time;
    case Q_GUARD_SIGNAL: return f->s.signal;
    case Q_TIME_TO_CONTACT: return f->s.time_to_contact;
    case Q_MIN_CLEARANCE: return f->s.min_clearance;
    case Q_STOP_LATEST: return f->s.stop_latest;
    default: return f->s.value[q];
    }
}

static int lookup(cfmu_instance *f, unsigned vr, int type, const cfmu_variable **v)
{
    char msg[128];

    if (vr >= cfmu_n_variables) {
        snprintf(msg, sizeof msg, "no variable has value reference %u", vr);
        return refuse(f, msg);
    }
    *v = &cfmu_variables[vr];
    if ((*v)->type != type) {
        snprintf(msg, sizeof msg, "value reference %u is not of the type asked for", vr);
        return refuse(f, msg);
    }
    return 0;
}

int cfmu_get(cfmu_instance *f, unsigned vr, int type, double *value)
{
    const cfmu_variable *v;

    if (lookup(f, vr, type, &v))
        return 1;
    /* an output during the initialization: computed from what has been set so far */
    if (v->set == CFMU_OUTPUT && !f->s.initialized && v->quantity != Q_TIME && prepare(f))
        return 1;
    *value = output(f, v->quantity);
    return 0;
}

/* The range of a value that can be set, with its name for the message. */
static int in_range(cfmu_quantity q, double x, const char **name, const char **rule)
{
    switch (q) {
    case Q_LIFT_LEVER: *name = "lift_lever"; break;
    case Q_TILT_LEVER: *name = "tilt_lever"; break;
    case Q_SLEW_LEVER: *name = "slew_lever"; break;
    case Q_EXTENSION_LEVER: *name = "extension_lever"; break;
    case Q_STEP: *name = "step"; *rule = "> 0 and finite"; return x > 0 && isfinite(x);
    case Q_GUARD_HORIZON:
        *name = "guard_horizon";
        *rule = "> 0 and finite";
        return x > 0 && isfinite(x);
    case Q_LOAD_MASS: *name = "load_mass"; *rule = ">= 0 and finite"; return x >= 0 && isfinite(x);
    default: *name = "the value"; *rule = "finite"; return isfinite(x);
    }
    *rule = "in [-1, 1]";
    return x >= -1 && x <= 1;
}

int cfmu_set(cfmu_instance *f, unsigned vr, int type, double value)
{
    const cfmu_variable *v;
    const char *name, *rule;
    char msg[160];

    if (lookup(f, vr, type, &v))
        return 1;
    if (v->set == CFMU_OUTPUT || (v->set == CFMU_FIXED && f->s.initialized)) {
        snprintf(msg, sizeof msg, "value reference %u cannot be set %s", vr,
                 v->set == CFMU_OUTPUT ? "(an output)" : "after the initialization");
        return refuse(f, msg);
    }
    if (!in_range(v->quantity, value, &name, &rule)) {
        snprintf(msg, sizeof msg, "%s must be %s, got %g", name, rule, value);
        return refuse(f, msg);
    }
    if (v->quantity == Q_LOAD_MASS && value != f->s.value[Q_LOAD_MASS])
        f->model_valid = 0;
    f->s.value[v->quantity] = value;
    return 0;
}

int cfmu_restore(cfmu_instance *f, const cfmu_snapshot *snap)
{
    if (snap->magic != CFMU_MAGIC || snap->size != (unsigned)sizeof(cfmu_snapshot))
        return refuse(f, "not a state of this FMU (or of another build of it)");
    f->s = *snap;
    f->model_valid = 0;
    return f->s.initialized ? ensure_model(f) : 0;
}

const char *cfmu_serialize(const void *state, unsigned char *serialized, size_t size)
{
    if (size < sizeof(cfmu_snapshot))
        return "serializing a state into a buffer too small";
    memcpy(serialized, state, sizeof(cfmu_snapshot));
    return NULL;
}

const char *cfmu_deserialize(const unsigned char *serialized, size_t size, void **state)
{
    cfmu_snapshot snap;
    if (size != sizeof snap)
        return "a serialized state of another size than this FMU's";
    memcpy(&snap, serialized, sizeof snap);
    if (snap.magic != CFMU_MAGIC || snap.size != (unsigned)sizeof snap)
        return "a serialized state of another FMU";
    if (!*state) {
        *state = malloc(sizeof snap);
        if (!*state)
            return "deserializing a state (out of memory)";
    }
    memcpy(*state, &snap, sizeof snap);
    return NULL;
}
