/* SPDX-License-Identifier: MIT */
/*
 * Fuzz target of the cranepredict C core (libFuzzer entry point LLVMFuzzerTestOneInput; also
 * driven without libFuzzer by replay.c over the files of fuzz/corpus/).
 *
 * The bytes become the values of the public structs and arguments; the pointers in them are built
 * here and are always valid for their stated sizes (the API contract): every buffer is malloc'd at
 * exactly its stated size, so ASan catches any access outside it. The checks, each an abort():
 *   - every call returns a status in [CRANE_OK, CRANE_STATUS_LAST] with a non-empty message;
 *   - on an error nothing is written to the outputs (canary-filled buffers stay as they were),
 *     except CRANE_E_DIVERGED and CRANE_E_TOLERANCE (the error control gave up), which write
 *     fewer than crane_sample_count() samples;
 *   - on success crane_predict writes exactly crane_sample_count() samples, none past them,
 *     with times 0 .. horizon; every sample written (on success or CRANE_E_DIVERGED) is finite
 *     (FUZZ_STRICT_FINITE, on by default), with increasing times, stop flags in {-1, 0, 1} and
 *     strokes inside [stroke_min, stroke_max];
 *   - crane_predict_model with a model from crane_model_init gives crane_predict's status and
 *     the same bytes; crane_sample_count_every agrees with crane_sample_count at 1 and never
 *     asks for more samples than it;
 *   - crane_predict_many over two futures (the state and inputs twice) writes nothing on an error
 *     (but CRANE_E_DIVERGED), sets *failed in [0, 2], and on success gives each future
 *     crane_predict's samples at the kept steps, bit for bit; it runs only when the step count is
 *     small (MAX_CAPACITY), else a short stride stops it before any work;
 *   - crane_step with the horizon as its period gives crane_predict's status (but for its
 *     capacity), its first and last samples bit for bit, and writes no next state on an error;
 *   - calls run only up to FUZZ_MAX_HORIZON s (beyond it they get no room for samples and are
 *     refused after validation): a call's work is bounded by its horizon, not by the harness;
 *   - crane_params_check names a field exactly when it fails, agrees with crane_model_init at
 *     extension_min, and every field has a rule;
 *   - the inputs (const) are not modified.
 * Crashes, out-of-bounds accesses and undefined behaviour are caught by the sanitizers.
 *
 * Input format. Byte 0 bit 0 selects how the rest is read:
 *   0 (patch):  start from the paper's scenario on the PATU 655 (short horizon) and apply records
 *               [field index: 1 byte][value: sizeof(crane_real) bytes, native]: index < N_REAL
 *               sets a real field (table below), index >= N_REAL sets an integer field from the
 *               first value byte(s). Short inputs stay close to valid ones.
 *   1 (raw):    the bytes are copied over crane_params, crane_state, crane_inputs (pointers then
 *               replaced by our buffers, n_samples capped), then horizon, dt, extension, slew,
 *               the sample arrays and the poses, then the integers; missing bytes are zero.
 */
#include <float.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "crane.h"
#include "crane_patu655.h"
#include "crane_scenarios.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

#define CRANE_STATUS_LAST CRANE_E_TOLERANCE
#define MAX_SAMPLES 16   /* pressure samples per cylinder */
#define MAX_CAPACITY 600 /* output samples (bounds the work per input) */
#define MAX_POSES 4      /* crane_points poses */
/* The longest horizon that runs (s): beyond it the calls get no room for their samples, so they
 * are refused after validation (CRANE_E_CAPACITY). A call's work is bounded by the horizon too
 * (the error-controlled method's attempt cap, 64 + 4096 per second; RK4's substeps per step), and
 * a stiff input at the cap of a 200-s horizon takes seconds under the sanitizers. */
#define FUZZ_MAX_HORIZON 5.0

/* How far (in units of the working precision's epsilon times the cylinder's length scale) a
 * reported stroke may lie outside [stroke_min, stroke_max]. The core clamps the reported stroke of
 * a free joint (docs/model.md, "End stops"), so the range is exact; before that, the stroke ->
 * angle -> stroke round trip put one 8.9e-16 m below stroke_min
 * (fuzz/corpus/crash-stroke-rounds-below-min). */
#ifndef FUZZ_STROKE_ULPS
#define FUZZ_STROKE_ULPS 0
#endif

/* 1: CRANE_OK (or the samples before CRANE_E_DIVERGED) with a non-finite output is a violation. */
#ifndef FUZZ_STRICT_FINITE
#define FUZZ_STRICT_FINITE 1
#endif

typedef struct {
    crane_params params;
    crane_state state;
    crane_inputs inputs;
    crane_real horizon, dt, extension, slew;
    crane_real t[2][MAX_SAMPLES], pa[2][MAX_SAMPLES], pb[2][MAX_SAMPLES];
    crane_real theta[MAX_POSES * 2];
    crane_real omega[2], alpha[2], stroke_arg, theta_arg, rate_arg, p_a_arg, p_b_arg;
    unsigned capacity, n_poses;
    int joint;
    unsigned sample_every; /* last, so that the raw inputs of the corpus keep their meaning */
} universe;

/* mode[0], mode[1], n_samples[0], n_samples[1], capacity, n_poses, joint, sample_every */
enum { N_INT = 8 };

static void fail(const char *what)
{
    fprintf(stderr, "fuzz_core: contract violated: %s\n", what);
    abort();
}

static void check_status(crane_status st, const char *what)
{
    const char *msg;
    if ((int)st < (int)CRANE_OK || (int)st > (int)CRANE_STATUS_LAST)
        fail(what);
    msg = crane_status_message(st);
    if (!msg || !msg[0])
        fail("empty status message");
}

static int finite_r(crane_real x) { return x - x == 0; }

/* The two errors after which the samples before them are written (and valid). */
static int partial(crane_status st) { return st == CRANE_E_DIVERGED || st == CRANE_E_TOLERANCE; }

static double eps_r(void) { return sizeof(crane_real) < sizeof(double) ? (double)FLT_EPSILON : DBL_EPSILON; }

static int stroke_ok(const crane_cylinder *c, crane_real s)
{
    const double scale = fabs((double)c->length_retracted) + fabs((double)c->stroke_min) +
                         fabs((double)c->stroke_max);
    const double tol = FUZZ_STROKE_ULPS * eps_r() * scale;
    return (double)s >= (double)c->stroke_min - tol && (double)s <= (double)c->stroke_max + tol;
}

/* The real-valued fields that patch records address, in a fixed order. */
static size_t real_fields(universe *u, crane_real **f)
{
    crane_params *p = &u->params;
    size_t n = 0;
    int i, k;
    f[n++] = &p->gravity;
#define V2(v) (f[n++] = &(v).x, f[n++] = &(v).y)
    V2(p->lift_pivot); V2(p->lift_cylinder_base); V2(p->lift_cylinder_rod);
    V2(p->tilt_cylinder_base); V2(p->link1_pivot); V2(p->tilt_pivot); V2(p->link_pin);
    V2(p->link2_end); V2(p->link2_attach); V2(p->extension_mount);
    f[n++] = &p->tip_distance; f[n++] = &p->extension_min; f[n++] = &p->extension_max;
#define BODY(b) (f[n++] = &(b).mass, V2((b).com), f[n++] = &(b).izz)
    BODY(p->lift_boom); BODY(p->outer_boom); BODY(p->extension_boom);
    f[n++] = &p->load_mass;
    for (i = 0; i < 2; ++i) {
        crane_cylinder *c = &p->cylinder[i];
        f[n++] = &c->bore; f[n++] = &c->rod; f[n++] = &c->length_retracted;
        f[n++] = &c->stroke_min; f[n++] = &c->stroke_max;
        f[n++] = &c->friction.coulomb; f[n++] = &c->friction.static_;
        f[n++] = &c->friction.viscous; f[n++] = &c->friction.stribeck_velocity;
        f[n++] = &c->friction.factor;
    }
    for (i = 0; i < 2; ++i) {
        f[n++] = &u->state.stroke[i]; f[n++] = &u->state.stroke_rate[i];
        f[n++] = &u->inputs.drive[i].p_a; f[n++] = &u->inputs.drive[i].p_b;
    }
    f[n++] = &u->state.slew; f[n++] = &u->state.extension;
    f[n++] = &u->horizon; f[n++] = &u->dt; f[n++] = &u->extension; f[n++] = &u->slew;
    for (i = 0; i < 2; ++i)
        for (k = 0; k < MAX_SAMPLES; ++k) {
            f[n++] = &u->t[i][k]; f[n++] = &u->pa[i][k]; f[n++] = &u->pb[i][k];
        }
    for (k = 0; k < MAX_POSES * 2; ++k)
        f[n++] = &u->theta[k];
    f[n++] = &u->omega[0]; f[n++] = &u->omega[1]; f[n++] = &u->alpha[0]; f[n++] = &u->alpha[1];
    f[n++] = &u->stroke_arg; f[n++] = &u->theta_arg; f[n++] = &u->rate_arg;
    f[n++] = &u->p_a_arg; f[n++] = &u->p_b_arg;
    /* appended, so that the corpus's patch records keep their meaning */
    BODY(p->side_link1); BODY(p->side_link2);
#undef V2
#undef BODY
    return n;
}

enum { MAX_FIELDS = 256 };

static void set_int(universe *u, unsigned which, const uint8_t *v)
{
    const int8_t s = (int8_t)v[0];
    const unsigned w = (unsigned)v[0] | ((unsigned)v[1] << 8);
    switch (which % N_INT) {
    case 0: u->inputs.drive[0].mode = s; break;
    case 1: u->inputs.drive[1].mode = s; break;
    case 2: u->inputs.drive[0].n_samples = (size_t)(v[0] % (MAX_SAMPLES + 1)); break;
    case 3: u->inputs.drive[1].n_samples = (size_t)(v[0] % (MAX_SAMPLES + 1)); break;
    case 4: u->capacity = w % (MAX_CAPACITY + 1); break;
    case 5: u->n_poses = v[0] % (MAX_POSES + 1); break;
    case 6: u->joint = s; break;
    default: u->sample_every = w; break;
    }
}

/* The paper's scenario (generated header example/crane_scenarios.h), 0.2 s at 1 ms; the samples a
 * ramp over [-0.1, 0.2 + ...]. */
static void defaults(universe *u)
{
    static const crane_params patu = CRANE_PATU655_INIT;
    static const crane_state paper_state = CRANE_SCENARIO_PAPER_FIG4_STATE;
    static const crane_inputs paper_inputs = CRANE_SCENARIO_PAPER_FIG4_INPUTS;
    int i, k;

    memset(u, 0, sizeof *u);
    u->params = patu;
    u->params.load_mass = CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS;
    u->state = paper_state;
    u->inputs = paper_inputs;
    u->horizon = (crane_real)0.2;
    u->dt = (crane_real)1e-3;
    u->capacity = 201;
    u->n_poses = 1;
    u->sample_every = 1;
    for (i = 0; i < 2; ++i)
        for (k = 0; k < MAX_SAMPLES; ++k) {
            u->t[i][k] = (crane_real)(-0.1 + 0.05 * k);
            u->pa[i][k] = (crane_real)(1e6 * (k % 5));
            u->pb[i][k] = (crane_real)(5e5 * (k % 3));
        }
    for (k = 0; k < MAX_POSES * 2; ++k)
        u->theta[k] = (crane_real)(k % 2 ? -1.0 : 0.5);
    u->stroke_arg = (crane_real)0.2;
    u->theta_arg = (crane_real)0.3;
    u->rate_arg = (crane_real)0.01;
    u->p_a_arg = (crane_real)1e7;
    u->p_b_arg = (crane_real)1e6;
}

static void decode(universe *u, const uint8_t *data, size_t size)
{
    defaults(u);
    if (size == 0)
        return;
    if ((data[0] & 1) == 0) {
        crane_real *f[MAX_FIELDS];
        const size_t nf = real_fields(u, f);
        size_t pos = 1;
        while (pos + 1 + sizeof(crane_real) <= size) {
            const unsigned idx = data[pos];
            const uint8_t *v = data + pos + 1;
            if (idx < nf)
                memcpy(f[idx], v, sizeof(crane_real));
            else
                set_int(u, idx - (unsigned)nf, v);
            pos += 1 + sizeof(crane_real);
        }
    } else {
        /* raw: arbitrary bytes over the structs, in order; missing bytes are zero */
        uint8_t *buf = (uint8_t *)calloc(1, sizeof *u + 16);
        size_t n = size - 1;
        if (!buf)
            abort();
        if (n > sizeof *u + 16)
            n = sizeof *u + 16;
        memcpy(buf, data + 1, n);
        memcpy(u, buf, sizeof *u);
        free(buf);
        /* the pointers are ours (set in run_predict); the sizes are capped */
        for (n = 0; n < 2; ++n) {
            u->inputs.drive[n].n_samples %= (MAX_SAMPLES + 1);
            u->inputs.drive[n].t = NULL;
            u->inputs.drive[n].p_a_samples = NULL;
            u->inputs.drive[n].p_b_samples = NULL;
            u->inputs.drive[n].u_samples = NULL;
        }
        u->capacity %= (MAX_CAPACITY + 1);
        u->n_poses %= (MAX_POSES + 1);
    }
}

/* a malloc'd copy of n reals (n may be 0: a 1-byte block, never dereferenced as a real) */
static crane_real *copy_reals(const crane_real *src, size_t n)
{
    crane_real *p = (crane_real *)malloc(n ? n * sizeof *p : 1);
    if (!p)
        abort();
    if (n)
        memcpy(p, src, n * sizeof *p);
    return p;
}

/* The outputs of crane_predict(_model) with status st; count = crane_sample_count(). */
static void check_samples(const universe *u, const crane_params *params, crane_status st,
                          size_t count, const crane_sample *out, const crane_sample *ref,
                          size_t cap, size_t n_written)
{
    size_t k;
    int i;

    if (st != CRANE_OK && !partial(st)) {
        if (n_written != 0xdeadbeef || memcmp(out, ref, cap ? cap * sizeof *out : 1))
            fail("crane_predict wrote outputs on an error");
        return;
    }
    if (st == CRANE_OK && (count == 0 || n_written != count || n_written > cap || n_written < 2))
        fail("crane_predict: sample count");
    if (partial(st) && (count == 0 || n_written >= count || n_written > cap))
        fail("crane_predict: sample count on CRANE_E_DIVERGED or CRANE_E_TOLERANCE");
    if (memcmp(out + n_written, ref + n_written, (cap - n_written) * sizeof *out))
        fail("crane_predict wrote past n_written");
    if (n_written > 0 && out[0].t != 0)
        fail("crane_predict: the first sample is not at t = 0");
    if (st == CRANE_OK && out[n_written - 1].t != u->horizon)
        fail("crane_predict: the last sample is not at horizon");
    for (k = 0; k < n_written; ++k) {
        const crane_sample *s = &out[k];
        int finite = finite_r(s->t);
        if (k > 0 && !(s->t > out[k - 1].t))
            fail("crane_predict: sample times not increasing");
        for (i = 0; i < 2; ++i) {
            if (s->stop[i] < -1 || s->stop[i] > 1)
                fail("crane_predict: stop flag");
            if (!finite_r(s->stroke[i]) || !finite_r(s->theta[i]) || !finite_r(s->omega[i]))
                finite = 0;
        }
        for (i = 0; i < 3; ++i)
            if (!finite_r(s->tip[i]))
                finite = 0;
        if (!finite) {
            if (FUZZ_STRICT_FINITE)
                fail("crane_predict: a non-finite sample written");
            continue;
        }
        for (i = 0; i < 2; ++i)
            if (!stroke_ok(&params->cylinder[i], s->stroke[i]))
                fail("crane_predict: a stroke left [stroke_min, stroke_max]");
    }
}

/* crane_predict_many over two futures (state and inputs twice), against crane_predict's output
 * (status st_one, n_one samples in one[]; count = crane_sample_count(), 0 if it failed). */
static void run_many(const universe *u, const crane_params *params, const crane_state *state,
                     const crane_inputs *inputs, crane_status st_one, const crane_sample *one,
                     size_t n_one, size_t count)
{
    enum { F = 2 };
    crane_state states[F];
    crane_inputs ins[F];
    crane_sample *out, *ref;
    size_t every = 0, stride, total, failed = 0xdeadbeef, k, j;
    crane_status st, se;

    for (k = 0; k < F; ++k) {
        states[k] = *state;
        ins[k] = *inputs;
    }
    se = crane_sample_count_every(u->horizon, u->dt, u->sample_every, &every);
    /* bounded work: a real run only for a short prediction; else a stride of 1 sample, which
     * every call refuses (CRANE_E_CAPACITY or an earlier error) before running anything */
    stride = se == CRANE_OK && count > 0 && count <= MAX_CAPACITY ? every : 1;
    total = F * stride;
    out = (crane_sample *)malloc(total * sizeof *out);
    ref = (crane_sample *)malloc(total * sizeof *out);
    if (!out || !ref)
        abort();
    memset(out, 0x5a, total * sizeof *out);
    memcpy(ref, out, total * sizeof *out);
    st = crane_predict_many(params, 1, F, states, ins, u->horizon, u->dt, u->sample_every, out, stride,
                            &failed, &work);
    check_status(st, "crane_predict_many status");
    if (failed > F)
        fail("crane_predict_many: *failed out of range");
    if (st == CRANE_OK && failed != F)
        fail("crane_predict_many: *failed not n_futures on success");
    if (st != CRANE_OK && !partial(st) && memcmp(out, ref, total * sizeof *out))
        fail("crane_predict_many wrote outputs on an error");
    if (st == CRANE_OK && stride == 1)
        fail("crane_predict_many ran with a stride below its sample count");
    if (st == CRANE_OK && st_one == CRANE_OK) {
        /* each future: crane_predict's samples at t = 0, every sample_every-th step and the last */
        for (k = 0; k < F; ++k)
            for (j = 0; j < every; ++j) {
                const size_t step = j + 1 == every ? n_one - 1 : j * u->sample_every;
                if (step >= n_one || memcmp(&out[k * stride + j], &one[step], sizeof *one))
                    fail("crane_predict_many differs from crane_predict");
            }
    }
    if (st == CRANE_OK && st_one != CRANE_OK && st_one != CRANE_E_CAPACITY)
        fail("crane_predict_many accepted what crane_predict refused");
    free(out);
    free(ref);
}

/* crane_params_check: a field exactly on an error, its rule, and crane_model_init's verdict. */
static void run_check(const universe *u)
{
    const crane_params params = u->params;
    crane_field field = (crane_field)77;
    crane_model model;
    const crane_status st = crane_params_check(&params, &field);

    check_status(st, "crane_params_check status");
    if ((int)field < 0 || (int)field >= (int)CRANE_FIELD_COUNT)
        fail("crane_params_check: field out of range");
    if ((st == CRANE_OK) != (field == CRANE_FIELD_NONE))
        fail("crane_params_check: a field without an error or an error without a field");
    if (st != CRANE_OK && !crane_field_rule(field))
        fail("crane_params_check: no rule for the field");
    if (crane_model_init(&model, &params, params.extension_min) != st)
        fail("crane_params_check differs from crane_model_init at extension_min");
}

static void run_predict(const universe *u)
{
    crane_params params = u->params;
    crane_state state = u->state;
    crane_inputs inputs = u->inputs;
    crane_real *ts[2], *pas[2], *pbs[2];
    crane_sample *out, *ref;
    const int long_run = (double)u->horizon > FUZZ_MAX_HORIZON;
    const size_t cap = long_run ? 0 : u->capacity;
    size_t n_written = 0xdeadbeef, count = 0;
    crane_status st, stc;
    unsigned char pcopy[sizeof params], scopy[sizeof state], icopy[sizeof inputs];
    int i;

    for (i = 0; i < 2; ++i) {
        const size_t ns = inputs.drive[i].n_samples;
        ts[i] = copy_reals(u->t[i], ns);
        pas[i] = copy_reals(u->pa[i], ns);
        pbs[i] = copy_reals(u->pb[i], ns);
        inputs.drive[i].t = ts[i];
        inputs.drive[i].p_a_samples = pas[i];
        inputs.drive[i].p_b_samples = pbs[i];
        /* a valve drive's lever samples (mostly outside [-1, 1]: CRANE_E_VALVE; the pointer is ours) */
        inputs.drive[i].u_samples = pas[i];
    }
    /* exactly cap samples (one byte if cap is 0), canary-filled */
    out = (crane_sample *)malloc(cap ? cap * sizeof *out : 1);
    ref = (crane_sample *)malloc(cap ? cap * sizeof *out : 1);
    if (!out || !ref)
        abort();
    memset(out, 0xa5, cap ? cap * sizeof *out : 1);
    memcpy(ref, out, cap ? cap * sizeof *out : 1);
    memcpy(pcopy, &params, sizeof params);
    memcpy(scopy, &state, sizeof state);
    memcpy(icopy, &inputs, sizeof inputs);

    st = crane_predict(&params, &state, &inputs, u->horizon, u->dt, out, cap, &n_written, &work);
    check_status(st, "crane_predict status");
    if (memcmp(pcopy, &params, sizeof params) || memcmp(scopy, &state, sizeof state) ||
        memcmp(icopy, &inputs, sizeof inputs))
        fail("crane_predict modified its inputs");
    stc = crane_sample_count(u->horizon, u->dt, &count);
    check_status(stc, "crane_sample_count status");
    check_samples(u, &params, st, stc == CRANE_OK ? count : 0, out, ref, cap, n_written);

    /* crane_predict_model with the model of the same crane: the same status and bytes */
    {
        crane_model model;
        crane_sample *out2 = (crane_sample *)malloc(cap ? cap * sizeof *out : 1);
        size_t n2 = 0xdeadbeef;
        crane_status st2;
        if (!out2)
            abort();
        memcpy(out2, ref, cap ? cap * sizeof *out : 1);
        if (crane_model_init(&model, &params, state.extension) == CRANE_OK) {
            st2 = crane_predict_model(&model, &state, &inputs, u->horizon, u->dt, out2, cap, &n2, &work);
            check_status(st2, "crane_predict_model status");
            if (memcmp(scopy, &state, sizeof state) || memcmp(icopy, &inputs, sizeof inputs))
                fail("crane_predict_model modified its inputs");
            check_samples(u, &params, st2, stc == CRANE_OK ? count : 0, out2, ref, cap, n2);
            if (st2 != st || n2 != n_written ||
                memcmp(out2, out, cap ? cap * sizeof *out : 1))
                fail("crane_predict_model differs from crane_predict");
        }
        free(out2);
    }

    /* crane_step over the horizon as its period: crane_predict's status (but for its capacity),
     * its first and last samples bit for bit, nothing written to the next state on an error */
    {
        crane_model model;
        crane_state next, canary;
        crane_sample ends[2];
        crane_status st3;
        if (!long_run && crane_model_init(&model, &params, state.extension) == CRANE_OK) {
            memset(&next, 0xa5, sizeof next);
            memcpy(&canary, &next, sizeof next);
            st3 = crane_step(&model, &state, &inputs, u->horizon, u->dt, &next, ends, &work);
            check_status(st3, "crane_step status");
            if (memcmp(scopy, &state, sizeof state) || memcmp(icopy, &inputs, sizeof inputs))
                fail("crane_step modified its inputs");
            if (st3 != CRANE_OK && memcmp(&next, &canary, sizeof next))
                fail("crane_step wrote its next state on an error");
            if (st != CRANE_E_CAPACITY && st3 != st)
                fail("crane_step's status differs from crane_predict's");
            if (st == CRANE_OK && st3 == CRANE_OK &&
                (memcmp(&ends[0], &out[0], sizeof ends[0]) ||
                 memcmp(&ends[1], &out[n_written - 1], sizeof ends[1]) ||
                 memcmp(next.stroke, out[n_written - 1].stroke, sizeof next.stroke)))
                fail("crane_step's samples differ from crane_predict's");
        }
    }

    run_many(u, &params, &state, &inputs, st, out, n_written,
             stc == CRANE_OK && !long_run ? count : 0);

    /* crane_sample_count_every */
    {
        size_t ce = 0xdeadbeef, c1 = 0xdeadbeef;
        const crane_status se = crane_sample_count_every(u->horizon, u->dt, u->sample_every, &ce);
        const crane_status s1 = crane_sample_count_every(u->horizon, u->dt, 1, &c1);
        check_status(se, "crane_sample_count_every status");
        check_status(s1, "crane_sample_count_every status");
        if (s1 != stc || (s1 == CRANE_OK && c1 != count))
            fail("crane_sample_count_every(1) differs from crane_sample_count");
        if (se != CRANE_OK && ce != 0xdeadbeef)
            fail("crane_sample_count_every wrote on an error");
        if (u->sample_every == 0 && se != CRANE_E_SAMPLE_EVERY)
            fail("crane_sample_count_every accepted sample_every 0");
        if (se == CRANE_OK && (s1 != CRANE_OK || ce < 2 || ce > c1))
            fail("crane_sample_count_every: count out of range");
    }
    for (i = 0; i < 2; ++i) {
        free(ts[i]);
        free(pas[i]);
        free(pbs[i]);
    }
    free(out);
    free(ref);
}

static void run_model(const universe *u)
{
    const crane_params params = u->params;
    crane_model model, mref;
    crane_status st;
    int j;

    memset(&model, 0x3c, sizeof model);
    memcpy(&mref, &model, sizeof model);
    st = crane_model_init(&model, &params, u->extension);
    check_status(st, "crane_model_init status");
    if (st != CRANE_OK) {
        if (memcmp(&model, &mref, sizeof model))
            fail("crane_model_init wrote the model on an error");
        return;
    }
    {
        /* crane_points: n poses, buffers of exactly the stated sizes */
        const size_t n = u->n_poses;
        const size_t nxyz = n * CRANE_N_POINTS * 3;
        crane_real *theta = copy_reals(u->theta, 2 * n);
        crane_real *xyz = (crane_real *)malloc(nxyz ? nxyz * sizeof *xyz : 1);
        crane_real *xref = (crane_real *)malloc(nxyz ? nxyz * sizeof *xyz : 1);
        if (!xyz || !xref)
            abort();
        memset(xyz, 0x77, nxyz ? nxyz * sizeof *xyz : 1);
        memcpy(xref, xyz, nxyz ? nxyz * sizeof *xyz : 1);
        st = crane_points(&model, u->slew, n, theta, xyz);
        check_status(st, "crane_points status");
        if (st != CRANE_OK && memcmp(xyz, xref, nxyz ? nxyz * sizeof *xyz : 1))
            fail("crane_points wrote on an error");
        free(theta);
        free(xyz);
        free(xref);
    }
    for (j = -1; j <= 2; ++j) {
        const int joint = j == 2 ? u->joint : j;
        crane_real th = (crane_real)11, ds = (crane_real)12, s = (crane_real)13, f = (crane_real)14;
        st = crane_joint_angle(&model, joint, u->stroke_arg, &th, &ds);
        check_status(st, "crane_joint_angle status");
        if (st != CRANE_OK && (th != 11 || ds != 12))
            fail("crane_joint_angle wrote on an error");
        st = crane_joint_stroke(&model, joint, u->theta_arg, &s);
        check_status(st, "crane_joint_stroke status");
        if (st != CRANE_OK && s != 13)
            fail("crane_joint_stroke wrote on an error");
        st = crane_cylinder_force(&model, joint, u->p_a_arg, u->p_b_arg, u->rate_arg, &f);
        check_status(st, "crane_cylinder_force status");
        if (st != CRANE_OK && f != 14)
            fail("crane_cylinder_force wrote on an error");
    }
    {
        crane_real tau[4] = {(crane_real)21, (crane_real)22, (crane_real)23, (crane_real)24};
        const crane_real q[4] = {u->theta[0], u->theta[1], u->slew, u->extension};
        const crane_real qd[4] = {u->omega[0], u->omega[1], 0, 0};
        const crane_real qdd[4] = {u->alpha[0], u->alpha[1], 0, 0};
        st = crane_inverse_dynamics(&model, q, qd, qdd, tau);
        check_status(st, "crane_inverse_dynamics status");
        if (st != CRANE_OK && (tau[0] != 21 || tau[1] != 22 || tau[2] != 23 || tau[3] != 24))
            fail("crane_inverse_dynamics wrote on an error");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    universe *u = (universe *)malloc(sizeof *u);
    if (!u)
        abort();
    decode(u, data, size);
    if (!crane_status_message((crane_status)(12345 + (size ? data[0] : 0))))
        fail("no status message for an unknown code");
    run_predict(u);
    run_model(u);
    run_check(u);
    free(u);
    return 0;
}
