/* SPDX-License-Identifier: MIT */
/*
 * The prediction entry point: validates every input before anything is written, then hands over
 * to the integrator (docs/model.md, "Integration and samples", "Bad input").
 */
#include <float.h>
#include <limits.h>
#include <stdint.h>
#include "crane_internal.h"

/* The step count is worked out in double even in the float build. The 1e-9 tolerance of the
 * specification is for double; in the float build horizon/dt carries the float rounding of both
 * operands, so the tolerance grows by a few float epsilons of the quotient (else 0.1f/0.01f would
 * ask for an 11th step of 4e-9 s). */
static crane_status step_count(crane_real horizon, crane_real dt, long *n_steps)
{
    double q, n;

    if (crane__finite(horizon) == 0 || crane__finite(dt) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (!(horizon > 0)) {
        return CRANE_E_HORIZON;
    }
    if (!(dt > 0) || dt > horizon) {
        return CRANE_E_DT;
    }
    q = (double)horizon / (double)dt;
    q -= 1e-9 + (sizeof(crane_real) < sizeof(double) ? q * 4.0 * (double)FLT_EPSILON : 0.0);
    n = ceil(q);
    if (n < 1) {
        n = 1;
    }
    /* Bounded work (crane.h); it also keeps the step index exact in a float and in a 32-bit long. */
    if (!(n <= (double)CRANE_MAX_STEPS)) {
        return CRANE_E_STEPS;
    }
    *n_steps = (long)n;
    return CRANE_OK;
}

crane_status crane_solver_default(crane_solver *solver)
{
    if (solver == NULL) {
        return CRANE_E_NULL;
    }
    solver->method = CRANE_ROSW != 0 ? CRANE_METHOD_DEFAULT : CRANE_METHOD_RK4;
    solver->tip_tolerance = CRANE__TIP_TOLERANCE;
    solver->pressure_tolerance = CRANE__PRESSURE_TOLERANCE;
    return CRANE_OK;
}

crane_status crane_sample_count(crane_real horizon, crane_real dt, size_t *count)
{
    long n;
    crane_status st;

    if (count == NULL) {
        return CRANE_E_NULL;
    }
    st = step_count(horizon, dt, &n);
    if (st != CRANE_OK) {
        return st;
    }
    *count = (size_t)n + 1;
    return CRANE_OK;
}

static int pressure_ok(crane_real p)
{
    return p >= 0 && p <= (crane_real)CRANE_PRESSURE_MAX;
}

static int lever_ok(crane_real u) { return u >= -1 && u <= 1; }

/* The sample times of a sampled drive (pressures or a lever): strictly increasing, covering
 * [0, horizon], so that interpolation never extrapolates. */
static crane_status check_times(const crane_real *t, size_t n, crane_real horizon)
{
    size_t k;

    if (n < 2) {
        return CRANE_E_SAMPLES;
    }
    for (k = 1; k < n; ++k) {
        if (!(t[k] > t[k - 1])) {
            return CRANE_E_SAMPLES;
        }
    }
    return t[0] <= 0 && t[n - 1] >= horizon ? CRANE_OK : CRANE_E_SAMPLES;
}

static int chamber_ok(crane_real p)
{
    return p >= (crane_real)CRANE_CHAMBER_PRESSURE_MIN && p <= (crane_real)CRANE_PRESSURE_MAX;
}

/* A valve drive of joint i (docs/model.md, "Hydraulics", "Bad input"): the actuator has a circuit,
 * the lever (or its samples) is in [-1, 1] and covers the horizon, the state's chamber pressures
 * and spool are in range. */
static crane_status check_valve(const crane_model *model, int i, const crane_state *s,
                                const crane_drive *d, crane_real horizon)
{
    size_t k;

#if CRANE_HYDRAULICS
    if (crane__circuit(model, i) == NULL) {
        return CRANE_E_VALVE;
    }
#else
    (void)model;
    return CRANE_E_VALVE;
#endif
    if (crane__finite(s->p_a[i]) == 0 || crane__finite(s->p_b[i]) == 0 ||
        crane__finite(s->spool[i]) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (chamber_ok(s->p_a[i]) == 0 || chamber_ok(s->p_b[i]) == 0 || lever_ok(s->spool[i]) == 0) {
        return CRANE_E_VALVE;
    }
    if (d->n_samples == 0) {
        if (crane__finite(d->u) == 0) {
            return CRANE_E_NONFINITE;
        }
        return lever_ok(d->u) != 0 ? CRANE_OK : CRANE_E_VALVE;
    }
    if (d->t == NULL || d->u_samples == NULL) {
        return CRANE_E_NULL;
    }
    for (k = 0; k < d->n_samples; ++k) {
        if (crane__finite(d->t[k]) == 0 || crane__finite(d->u_samples[k]) == 0) {
            return CRANE_E_NONFINITE;
        }
    }
    for (k = 0; k < d->n_samples; ++k) {
        if (lever_ok(d->u_samples[k]) == 0) {
            return CRANE_E_VALVE;
        }
    }
    return check_times(d->t, d->n_samples, horizon);
}

static crane_status check_drive(const crane_drive *d, crane_real stroke_rate, crane_real horizon)
{
    size_t k;

    if (d->mode != CRANE_DRIVE_PRESSURE && d->mode != CRANE_DRIVE_HOLD) {
        return CRANE_E_DRIVE;
    }
    if (crane__finite(d->p_a) == 0 || crane__finite(d->p_b) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (d->mode == CRANE_DRIVE_HOLD) {
        /* A closed valve ignores the pressures and samples. */
        return stroke_rate != 0 ? CRANE_E_STROKE_RATE : CRANE_OK;
    }
    if (d->n_samples == 0) {
        return pressure_ok(d->p_a) != 0 && pressure_ok(d->p_b) != 0 ? CRANE_OK : CRANE_E_PRESSURE;
    }

    if (d->t == NULL || d->p_a_samples == NULL || d->p_b_samples == NULL) {
        return CRANE_E_NULL;
    }
    for (k = 0; k < d->n_samples; ++k) {
        if (crane__finite(d->t[k]) == 0 || crane__finite(d->p_a_samples[k]) == 0 ||
            crane__finite(d->p_b_samples[k]) == 0) {
            return CRANE_E_NONFINITE;
            }
    }
    for (k = 0; k < d->n_samples; ++k) {
        if (pressure_ok(d->p_a_samples[k]) == 0 || pressure_ok(d->p_b_samples[k]) == 0) {
            return CRANE_E_PRESSURE;
        }
    }
    return check_times(d->t, d->n_samples, horizon);
}

/* The slew's or the extension's drive (docs/model.md, "Four joints", "Bad input"): a hold, or a
 * pressure or valve drive on a crane that has the actuator; the slew within its range when the crane
 * has a slew drive (the extension's range is the model's check). */
static crane_status check_joint4(const crane_model *model, int j, const crane_state *s,
                                 const crane_drive *d, crane_real horizon)
{
    const crane_params *p = model->params;
    const crane_real rate = j == CRANE_SLEW ? s->slew_rate : s->extension_rate;
    const int present = j == CRANE_SLEW ? p->slew_drive.present : p->extension_cylinder.present;

    if (j == CRANE_SLEW && present != 0 &&
        (s->slew < p->slew_drive.slew_min || s->slew > p->slew_drive.slew_max)) {
        return CRANE_E_ANGLE;
        }
    if (d->mode == CRANE_DRIVE_HOLD) {
        return rate != 0 ? CRANE_E_STROKE_RATE : CRANE_OK;
    }
    if (d->mode != CRANE_DRIVE_PRESSURE && d->mode != CRANE_DRIVE_VALVE) {
        return CRANE_E_DRIVE;
    }
    if (present == 0) {
        return CRANE_E_ACTUATOR;
    }
    if (d->mode == CRANE_DRIVE_VALVE) {
        return check_valve(model, j, s, d, horizon);
    }
    return check_drive(d, rate, horizon);
}

/* The checks of one future against a model that holds its extension (docs/model.md, "Bad input"),
 * in the order crane_predict has always made them. */
static crane_status check_future(const crane_model *model, const crane_state *state0,
                                 const crane_inputs *inputs, crane_real horizon)
{
    const crane_solver *sv = &inputs->solver;
    crane_status st;
    int i;

    /* the solver (a zero tolerance is the default; NaN fails every range) */
    if (sv->method != CRANE_METHOD_DEFAULT && sv->method != CRANE_METHOD_ROSW &&
        sv->method != CRANE_METHOD_RK4 && sv->method != CRANE_METHOD_DOPRI5) {
        return CRANE_E_METHOD;
    }
    if (CRANE_ROSW == 0 && (sv->method == CRANE_METHOD_ROSW || sv->method == CRANE_METHOD_DOPRI5)) {
        return CRANE_E_METHOD;
    }
    /* the explicit pair is for futures without oil: a valve drive's chambers are stiff */
    if (sv->method == CRANE_METHOD_DOPRI5) {
        for (i = 0; i < 4; ++i) {
            if (inputs->drive[i].mode == CRANE_DRIVE_VALVE) {
                return CRANE_E_METHOD;
            }
        }
    }
    if (sv->method != CRANE_METHOD_RK4 &&
        ((sv->tip_tolerance != 0 &&
          crane__in_range(sv->tip_tolerance, (crane_real)1e-9, 1) == 0) ||
         (sv->pressure_tolerance != 0 &&
          crane__in_range(sv->pressure_tolerance, 1, (crane_real)1e7) == 0))) {
        return CRANE_E_METHOD;
    }
    for (i = 0; i < 2; ++i) {
        if (crane__finite(state0->stroke[i]) == 0 || crane__finite(state0->stroke_rate[i]) == 0) {
            return CRANE_E_NONFINITE;
        }
    }
    if (crane__finite(state0->slew) == 0 || crane__finite(state0->slew_rate) == 0 ||
        crane__finite(state0->extension_rate) == 0) {
        return CRANE_E_NONFINITE;
        }
    for (i = 0; i < 2; ++i) {
        if (state0->stroke[i] < crane__stroke_min(model, i) ||
            state0->stroke[i] > crane__stroke_max(model, i)) {
            return CRANE_E_STROKE;
            }
    }
    for (i = 0; i < 2; ++i) {
        st = inputs->drive[i].mode == CRANE_DRIVE_VALVE
                 ? check_valve(model, i, state0, &inputs->drive[i], horizon)
                 : check_drive(&inputs->drive[i], state0->stroke_rate[i], horizon);
        if (st != CRANE_OK) {
            return st;
        }
    }
    for (i = CRANE_SLEW; i <= CRANE_EXTENSION; ++i) {
        st = check_joint4(model, i, state0, &inputs->drive[i], horizon);
        if (st != CRANE_OK) {
            return st;
        }
    }
    return CRANE_OK;
}

/* A knot this close to a step's start or end, as a fraction of dt, does not cut the step: the
 * step grid's own rounding (and the float build's) must not make slivers of a step, and the kink
 * it leaves out costs O((margin dt)^2). */
static const crane_real KNOT_MARGIN = (crane_real)1e-3;

/* The first sample of drive d after time a (bisection: long lever records cost log n). */
static size_t first_after(const crane_drive *d, crane_real a)
{
    size_t lo = 0, hi = d->n_samples;

    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (d->t[mid] > a) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

crane_real crane__next_knot(const crane_inputs *in, int n_joints, crane_real t, crane_real t_end,
                            crane_real dt)
{
    const crane_real lo = t + KNOT_MARGIN * dt, hi = t_end - KNOT_MARGIN * dt;
    crane_real knot = t_end;
    int j;

    for (j = 0; j < n_joints; ++j) {
        const crane_drive *d = &in->drive[j];
        size_t a;
        if (d->mode == CRANE_DRIVE_HOLD) {
            continue;
        }
        a = first_after(d, lo);
        if (a < d->n_samples && d->t[a] < hi && d->t[a] < knot) {
            knot = d->t[a];
        }
    }
    return knot;
}

long crane__knot_count(const crane_inputs *in, crane_real horizon)
{
    long n = 0;
    int j;

    for (j = 0; j < 4; ++j) {
        const crane_drive *d = &in->drive[j];
        size_t k;
        if (d->mode == CRANE_DRIVE_HOLD) {
            continue;
        }
        for (k = 0; k < d->n_samples; ++k) {
            if (d->t[k] > 0 && d->t[k] < horizon) {
                ++n;
            }
        }
    }
    return n;
}

#if CRANE_ROSW
#if CRANE_HYDRAULICS
/* The spool error that a step over [a, b] can leave by seeing valve drive d's lever only at its
 * stages (the lever rule, docs/model.md "Integration"): the stages see the lever as if it were
 * its chord over the step; the lever's samples inside depart from that chord by delta(t), and a
 * spool of lag tau follows delta by at most min(max |delta|, integral |delta| dt / tau) (tau = 0:
 * the spool is the lever). delta is linear between the samples and 0 at a and b. */
static crane_real chord_error(const crane_drive *d, crane_real tau, crane_real a, crane_real b)
{
    size_t k = first_after(d, a), cursor = k > 0 ? k - 1 : 0;
    const crane_real u_a = crane__drive_lever(d, &cursor, a);
    const crane_real slope = (crane__drive_lever(d, &cursor, b) - u_a) / (b - a);
    crane_real t0 = a, d0 = 0, peak = 0, area = 0;
    int more = 1;

    while (more != 0) {
        const crane_real t1 = k < d->n_samples && d->t[k] < b ? d->t[k] : b;
        const crane_real d1 = t1 < b ? d->u_samples[k] - (u_a + slope * (t1 - a)) : 0;
        const crane_real m0 = crane__fabs(d0), m1 = crane__fabs(d1);
        if (m0 + m1 > 0) {
            /* |delta| integrated over the piece: a trapezoid, or two triangles where delta
             * changes sign */
            area += (t1 - t0) * (d0 * d1 >= 0 ? (m0 + m1) / 2 : (d0 * d0 + d1 * d1) / (2 * (m0 + m1)));
        }
        if (m1 > peak) {
            peak = m1;
        }
        more = t1 < b;
        t0 = t1;
        d0 = d1;
        ++k;
    }
    return tau > 0 && area < tau * peak ? area / tau : peak;
}
#endif

crane_real crane__rosw_step_end(const crane_model *m, const crane_inputs *in, crane_real t,
                                crane_real t_end, crane_real dt, crane_real tolerance)
{
    const crane_real lo_t = t + KNOT_MARGIN * dt;
    crane_real end = t_end;
    int j;

    for (j = 0; j < 4; ++j) {
        const crane_drive *d = &in->drive[j];
        if (d->mode == CRANE_DRIVE_HOLD || d->n_samples == 0) {
            continue;
        }
#if CRANE_HYDRAULICS
        if (d->mode == CRANE_DRIVE_VALVE) {
            const crane_real tau = crane__circuit(m, j)->spool_time_constant;
            size_t lo = first_after(d, lo_t), hi;
            if (chord_error(d, tau, t, end) <= tolerance) {
                continue;
            }
            /* the farthest sample inside whose chord keeps the rule (a bisection over the
             * samples; the first one always ends the step: the lever is linear before it) */
            hi = first_after(d, end - KNOT_MARGIN * dt);
            if (lo >= hi || d->t[lo] >= end - KNOT_MARGIN * dt) {
                continue;
            }
            --hi;
            while (lo < hi) {
                const size_t mid = lo + (hi - lo + 1) / 2;
                if (chord_error(d, tau, t, d->t[mid]) <= tolerance) {
                    lo = mid;
                } else {
                    hi = mid - 1;
                }
            }
            end = d->t[lo];
            continue;
        }
#else
        (void)m;
        (void)tolerance;
#endif
        {
            /* a pressure drive's first sample inside: its pressures act on the booms at once */
            const size_t k = first_after(d, lo_t);
            if (k < d->n_samples && d->t[k] < end - KNOT_MARGIN * dt) {
                end = d->t[k];
            }
        }
    }
    return end;
}
#endif

/* Bounded work with valve-driven cylinders or a moving extension (docs/model.md, "Hydraulics",
 * "Four joints", "Bad input"): every step may be cut into substeps, at most as many as at the
 * stroke ends (where the chambers are smallest; the last step may be up to 1.25 dt long) or at
 * the extension friction's rate bound, one more for each knot, and those count against CRANE_MAX_STEPS
 * (CRANE_E_STEPS) and, with total (the batch's RK4 steps so far, updated), against
 * CRANE_MAX_BATCH_STEPS (CRANE_E_BATCH). Integer arithmetic without overflow on a 32-bit long. */
static crane_status check_work(const crane_model *m, const crane_inputs *in, crane_real horizon,
                               crane_real dt, long n_steps, long *total)
{
    const crane_real h = dt * (crane_real)1.25;
    const long knots = crane__knot_count(in, horizon);
    long n_max = 1, work;

    /* the error-controlled method: its attempt cap (docs/model.md, "Integration") */
    if (CRANE_ROSW != 0 && in->solver.method != CRANE_METHOD_RK4) {
        work = crane__attempt_cap(horizon);
        if (work > (long)CRANE_MAX_STEPS || knots > (long)CRANE_MAX_STEPS - work) {
            return CRANE_E_STEPS;
        }
        work += knots;
        if (total != NULL) {
            if (work > (long)CRANE_MAX_BATCH_STEPS - *total) {
                return CRANE_E_BATCH;
            }
            *total += work;
        }
        return CRANE_OK;
    }
#if CRANE_HYDRAULICS
    int valve[4], j, any = 0;

    for (j = 0; j < 4; ++j) {
        valve[j] = in->drive[j].mode == CRANE_DRIVE_VALVE;
        any = any || valve[j];
    }
    if (any != 0) {
        n_max = crane__substeps_bound(m, valve, h);
    }
#endif
    /* docs/model.md "Four joints": a moving extension's friction substeps, at their bound */
    if (in->drive[CRANE_EXTENSION].mode != CRANE_DRIVE_HOLD) {
        const crane_real ne = crane__ceil(h * crane__extension_rate_bound(m->params) / (crane_real)2.5);
        if (!(ne <= (crane_real)CRANE_MAX_STEPS)) {
            return CRANE_E_STEPS;
        }
        if ((long)ne > n_max) {
            n_max = (long)ne;
        }
    }
    /* Every knot cuts a step into one more piece, with its own substeps; a step's pieces sum to
     * its length, so their counts ceil(h_i c) sum to at most the whole step's ceil(h c) plus one
     * per knot (ceil(a) + ceil(b) <= ceil(a + b) + 1): a dense lever log costs a substep a knot,
     * not a step's worth. */
    if (n_max > (long)CRANE_MAX_STEPS / n_steps) {
        return CRANE_E_STEPS;
    }
    work = n_steps * n_max;
    if (knots > (long)CRANE_MAX_STEPS - work) {
        return CRANE_E_STEPS;
    }
    work += knots;
    if (total != NULL) {
        if (work > (long)CRANE_MAX_BATCH_STEPS - *total) {
            return CRANE_E_BATCH;
        }
        *total += work;
    }
    return CRANE_OK;
}

/* A validated prediction: the integrator (which picks the planar dynamics kernel when the slew
 * and the extension are held). */
static CRANE__ALWAYS_INLINE crane_status integrate(const crane_model *m, const crane_state *s0,
                                                   const crane_inputs *in, crane_real horizon,
                                                   crane_real dt, long n_steps, long sample_every,
                                                   crane_sample *out, size_t *n_written,
                                                   crane_work *work)
{
    return crane__integrate(m, s0, in, horizon, dt, n_steps, sample_every, out, n_written, work);
}

/* crane_predict_model after its NULL checks, keeping every sample_every-th sample (and the
 * last). The entry points call it, so that crane_predict does not add crane_predict_model's frame
 * to its stack. */
static CRANE__ALWAYS_INLINE crane_status predict(const crane_model *model,
                                                 const crane_state *state0,
                                                 const crane_inputs *inputs, crane_real horizon,
                                                 crane_real dt, long sample_every,
                                                 crane_sample *out, size_t capacity,
                                                 size_t *n_written, crane_work *work)
{
    crane_status st;
    long n_steps;

    if (crane__finite(state0->extension) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (state0->extension != model->extension) {
        return CRANE_E_EXTENSION;
    }
    st = step_count(horizon, dt, &n_steps);
    if (st != CRANE_OK) {
        return st;
    }
    st = check_future(model, state0, inputs, horizon);
    if (st != CRANE_OK) {
        return st;
    }
    st = check_work(model, inputs, horizon, dt, n_steps, NULL);
    if (st != CRANE_OK) {
        return st;
    }
    if (crane__decimated_count(n_steps, sample_every) > capacity) {
        return CRANE_E_CAPACITY;
    }

    return integrate(model, state0, inputs, horizon, dt, n_steps, sample_every, out, n_written,
                     work);
}

crane_status crane_predict(const crane_params *params, const crane_state *state0,
                           const crane_inputs *inputs, crane_real horizon, crane_real dt,
                           crane_sample *out, size_t capacity, size_t *n_written,
                           crane_work *work)
{
    crane_model model;
    crane_field field;
    crane_status st;

    if (params == NULL || state0 == NULL || inputs == NULL || out == NULL || n_written == NULL ||
        work == NULL) {
        return CRANE_E_NULL;
    }
    st = crane__model_derive(&model, params, state0->extension, &field);
    if (st != CRANE_OK) {
        return st;
    }
    return predict(&model, state0, inputs, horizon, dt, 1, out, capacity, n_written, work);
}

crane_status crane_predict_model(const crane_model *model, const crane_state *state0,
                                 const crane_inputs *inputs, crane_real horizon, crane_real dt,
                                 crane_sample *out, size_t capacity, size_t *n_written,
                                 crane_work *work)
{
    if (model == NULL || state0 == NULL || inputs == NULL || out == NULL || n_written == NULL ||
        work == NULL) {
        return CRANE_E_NULL;
    }
    return crane__predict_every(model, state0, inputs, horizon, dt, 1, out, capacity, n_written,
                                work);
}

crane_status crane__predict_every(const crane_model *model, const crane_state *state0,
                                  const crane_inputs *inputs, crane_real horizon, crane_real dt,
                                  long sample_every, crane_sample *out, size_t capacity,
                                  size_t *n_written, crane_work *work)
{
    return predict(model, state0, inputs, horizon, dt, sample_every, out, capacity, n_written,
                   work);
}

crane_status crane_sample_count_every(crane_real horizon, crane_real dt, size_t sample_every,
                                      size_t *count)
{
    long n;
    crane_status st;

    if (count == NULL) {
        return CRANE_E_NULL;
    }
    if (sample_every == 0 || sample_every > (size_t)LONG_MAX) {
        return CRANE_E_SAMPLE_EVERY;
    }
    st = step_count(horizon, dt, &n);
    if (st != CRANE_OK) {
        return st;
    }
    *count = crane__decimated_count(n, (long)sample_every);
    return CRANE_OK;
}

/* The checks of crane_predict_many's futures, every one before the first is integrated, with
 * *model as scratch (out of line, so that the checks' locals are not in the entry point's frame
 * during the integration: the stack budget of docs/embedding.md). The model depends on the
 * extension only through the lumped outer boom, so with one crane for all futures it is derived
 * again only when the extension changes; with a crane per future (each = 1) for every future,
 * which checks that crane too. On an error *failed is the future at fault. */
static CRANE__NOINLINE crane_status check_futures(crane_model *model, const crane_params *params,
                                                  size_t each, size_t n_futures,
                                                  const crane_state *states,
                                                  const crane_inputs *inputs, crane_real horizon,
                                                  crane_real dt, long n_steps, size_t *failed)
{
    crane_field field;
    crane_status st;
    size_t k;
    long total = 0;   /* RK4 steps of the futures validated so far, their substeps included */

    for (k = 0; k < n_futures; ++k) {
        const crane_state *s = &states[k];
        if (k == 0 || each != 0u || !(s->extension == states[k - 1].extension)) {
            /* straight into the caller's model: crane_model_init's own copy would add its size
             * to the entry point's stack */
            st = crane__model_derive(model, params + k * each, s->extension, &field);
            if (st != CRANE_OK) {
                *failed = k;
                return st;
            }
        }
        st = check_future(model, s, &inputs[k], horizon);
        /* the substeps of valve-driven and extension-driven futures count against the bounds too (CRANE_E_BATCH
         * here names the future that takes the batch over) */
        if (st == CRANE_OK) {
            st = check_work(model, &inputs[k], horizon, dt, n_steps, &total);
        }
        if (st != CRANE_OK) {
            *failed = k;
            return st;
        }
    }
    return CRANE_OK;
}

crane_status crane_predict_many(const crane_params *params, size_t n_params, size_t n_futures,
                                const crane_state *states, const crane_inputs *inputs,
                                crane_real horizon, crane_real dt, size_t sample_every,
                                crane_sample *out, size_t stride, size_t *failed,
                                crane_work *work)
{
    crane_model model;
    crane_field field;
    crane_status st;
    size_t k, count;
    long n_steps;
    /* 1: params[k] is future k's crane; 0: params[0] is every future's */
    const size_t each = n_params != 1;

    if (failed == NULL) {
        return CRANE_E_NULL;
    }
    *failed = n_futures;
    if (params == NULL || work == NULL ||
        (n_futures > 0 && (states == NULL || inputs == NULL || out == NULL))) {
        return CRANE_E_NULL;
    }
    if (each != 0u && n_params != n_futures) {
        return CRANE_E_PARAMS;
    }
    /* one crane for all: checked as a shared argument; a crane per future: with its future */
    st = each != 0u ? CRANE_OK : crane__check_params(params, &field);
    if (st != CRANE_OK) {
        return st;
    }
    st = crane_sample_count_every(horizon, dt, sample_every, &count);
    if (st != CRANE_OK) {
        return st;
    }
    (void)step_count(horizon, dt, &n_steps);
    /* Bounded work and memory of the whole call (crane.h), before the buffers are looked at. */
    if (n_futures > 0 && count > (size_t)CRANE_MAX_SAMPLES / n_futures) {
        return CRANE_E_SAMPLE_COUNT;
    }
    if (n_futures > 0 && (size_t)n_steps > (size_t)CRANE_MAX_BATCH_STEPS / n_futures) {
        return CRANE_E_BATCH;
    }
    if (count > stride || (n_futures > 0 && stride > SIZE_MAX / n_futures)) {
        return CRANE_E_CAPACITY;
    }

    /* Validate every future before the first write. */
    st = check_futures(&model, params, each, n_futures, states, inputs, horizon, dt, n_steps,
                       failed);
    if (st != CRANE_OK) {
        return st;
    }
    for (k = 0; k < n_futures; ++k) {
        if (k == 0 || each != 0u || !(states[k].extension == states[k - 1].extension)) {
            (void)crane__model_derive(&model, params + k * each, states[k].extension, &field);
        }
        st = integrate(&model, &states[k], &inputs[k], horizon, dt, n_steps, (long)sample_every,
                       out + k * stride, &count, work);
        if (st != CRANE_OK) {
            *failed = k;
            return st;
        }
    }
    return CRANE_OK;
}
