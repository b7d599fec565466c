/* SPDX-License-Identifier: MIT */
/*
 * Fuzz target of the collision guard (libFuzzer entry point LLVMFuzzerTestOneInput; also driven
 * by replay.c over fuzz/corpus-guard/ in `make test`). The input decides two solids, two crane
 * parts and the guard's settings, as raw reals (NaN, infinities, huge values) or as bounded ones.
 * The contract checked (abort on a violation; the sanitizers catch the rest):
 *   - crane_solid_distance returns CRANE_OK exactly when both solids pass crane_solid_check and
 *     they are not two planes, else CRANE_E_SOLID and writes nothing; on CRANE_OK the distance is
 *     finite, >= 0, the same both ways round, and the closest points are finite and that far apart;
 *   - crane_guard on a fixed prediction, slewing from and at rates of the input's (raw: NaN,
 *     infinities), returns CRANE_OK or a documented error, writes nothing on an error, and on
 *     CRANE_OK gives a signal, clearances >= 0 and a contact inside the horizon.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "crane.h"
#include "crane_patu655.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work prediction_work;

typedef struct {
    const uint8_t *p;
    size_t n;
    int raw;
} input;

static double next_real(input *in)
{
    if (in->raw) {
        double x = 0;
        if (in->n >= sizeof x) {
            memcpy(&x, in->p, sizeof x);
            in->p += sizeof x;
            in->n -= sizeof x;
        }
        return x;
    }
    if (in->n >= 2) {
        const int v = (int)in->p[0] | ((int)in->p[1] << 8);
        in->p += 2;
        in->n -= 2;
        return (v - 32768) / 4096.0; /* +-8 m in steps of 1/4096 */
    }
    return 0;
}

static int next_byte(input *in)
{
    int b = 0;
    if (in->n) {
        b = in->p[0];
        in->p++;
        in->n--;
    }
    return b;
}

static void solid(input *in, crane_solid *s)
{
    int i;
    memset(s, 0, sizeof *s);
    s->kind = next_byte(in) % 6; /* 5 is not a kind */
    for (i = 0; i < 3; ++i)
        s->a[i] = (crane_real)next_real(in);
    for (i = 0; i < 3; ++i)
        s->b[i] = (crane_real)next_real(in);
    s->radius = (crane_real)fabs(next_real(in));
    if (next_byte(in) & 1) {
        const double yaw = next_real(in);
        s->axes[0] = (crane_real)cos(yaw);
        s->axes[1] = (crane_real)sin(yaw);
        s->axes[3] = (crane_real)-sin(yaw);
        s->axes[4] = (crane_real)cos(yaw);
        s->axes[8] = 1;
    } else {
        for (i = 0; i < 9; ++i)
            s->axes[i] = (crane_real)next_real(in);
    }
    for (i = 0; i < 3; ++i)
        s->half[i] = (crane_real)fabs(next_real(in));
    if (s->kind == CRANE_SOLID_PLANE && (next_byte(in) & 1)) {
        /* a unit normal, so that planes get past the check too */
        const double n = sqrt((double)(s->b[0] * s->b[0] + s->b[1] * s->b[1] + s->b[2] * s->b[2]));
        if (n > 0 && isfinite(n))
            for (i = 0; i < 3; ++i)
                s->b[i] = (crane_real)((double)s->b[i] / n);
    }
}

static void check(int ok)
{
    if (!ok)
        abort();
}

static double tolerance(double scale)
{
    return (sizeof(crane_real) < sizeof(double) ? 1e-3 : 1e-8) * (1 + scale);
}

static void fuzz_distance(const crane_solid *a, const crane_solid *b)
{
    crane_real d = 123, e = 123, pa[3] = {7, 7, 7}, pb[3] = {7, 7, 7}, qa[3], qb[3];
    int fa, fb;
    const int valid = crane_solid_check(a, &fa) == CRANE_OK && crane_solid_check(b, &fb) == CRANE_OK &&
                      !(a->kind == CRANE_SOLID_PLANE && b->kind == CRANE_SOLID_PLANE);
    const crane_status st = crane_solid_distance(a, b, &d, pa, pb);
    int i;
    if (!valid) {
        check(st == CRANE_E_SOLID && d == 123 && pa[0] == 7 && pb[2] == 7);
        return;
    }
    check(st == CRANE_OK && isfinite((double)d) && d >= 0);
    check(crane_solid_distance(b, a, &e, qb, qa) == CRANE_OK);
    {
        double gap = 0, scale = (double)d;
        for (i = 0; i < 3; ++i) {
            check(isfinite((double)pa[i]) && isfinite((double)pb[i]));
            gap += ((double)pa[i] - (double)pb[i]) * ((double)pa[i] - (double)pb[i]);
            scale += fabs((double)pa[i]) + fabs((double)pb[i]);
        }
        check(fabs((double)d - (double)e) <= tolerance(scale));
        if (d > 0)
            check(fabs(sqrt(gap) - (double)d) <= tolerance(scale));
    }
}

/* A fixed prediction: the paper's scenario, 0.5 s at 10 ms. */
static crane_sample samples[51], slewing[51];
static crane_model model;
static size_t n_samples;

static void predict_once(void)
{
    static const crane_params params = CRANE_PATU655_INIT;
    crane_state st;
    crane_inputs in;
    if (n_samples)
        return;
    memset(&st, 0, sizeof st);
    memset(&in, 0, sizeof in);
    st.stroke[CRANE_LIFT] = (crane_real)0.116;
    st.stroke[CRANE_TILT] = (crane_real)0.20;
    in.drive[CRANE_LIFT].mode = CRANE_DRIVE_PRESSURE;
    in.drive[CRANE_LIFT].p_a = (crane_real)175e5;
    in.drive[CRANE_TILT].mode = CRANE_DRIVE_HOLD;
    check(crane_model_init(&model, &params, 0) == CRANE_OK);
    check(crane_predict_model(&model, &st, &in, (crane_real)0.5, (crane_real)0.01, samples, 51,
                              &n_samples, &prediction_work) == CRANE_OK);
}

static void fuzz_guard(input *in, const crane_solid obstacles[2])
{
    crane_part parts[2];
    crane_guard_config cfg;
    crane_guard_result res;
    crane_real clearance[2] = {77, 77}, work[2 * (2 + CRANE_GUARD_PART_WORK)];
    crane_real slew0, slew_rate;
    crane_status st;
    size_t k;
    int i;

    predict_once();
    for (i = 0; i < 2; ++i) {
        memset(&parts[i], 0, sizeof parts[i]);
        parts[i].kind = next_byte(in) % 4; /* 0 = plane: not a part */
        parts[i].a.frame = next_byte(in) % 6;
        parts[i].b.frame = next_byte(in) % 6;
        parts[i].a.at.x = (crane_real)next_real(in);
        parts[i].a.at.y = (crane_real)next_real(in);
        parts[i].b.at.x = (crane_real)next_real(in);
        parts[i].b.at.y = (crane_real)next_real(in);
        parts[i].radius = (crane_real)next_real(in);
        parts[i].drop = (crane_real)next_real(in);
        parts[i].half[0] = parts[i].half[1] = parts[i].half[2] = (crane_real)next_real(in);
    }
    cfg.margin = (crane_real)next_real(in);
    cfg.reaction = (crane_real)next_real(in);
    cfg.cycle = (crane_real)next_real(in);
    cfg.time_tolerance = (crane_real)fabs(next_real(in));
    cfg.clearance_tolerance = (crane_real)next_real(in);
    /* the prediction with a slew of the input's: start and rate (raw: NaN, infinities) */
    slew0 = (crane_real)next_real(in);
    slew_rate = (crane_real)next_real(in);
    for (k = 0; k < n_samples; ++k) {
        slewing[k] = samples[k];
        slewing[k].slew = slew0 + slew_rate * samples[k].t;
        slewing[k].slew_rate = slew_rate;
    }
    memset(&res, 0x5a, sizeof res);
    st = crane_guard(&model, parts, 2, obstacles, 2, slewing, n_samples,
                     &cfg, clearance, work, sizeof work / sizeof work[0], &res);
    if (st != CRANE_OK) {
        check(st == CRANE_E_PART || st == CRANE_E_SOLID || st == CRANE_E_GUARD ||
              st == CRANE_E_NONFINITE);
        check(clearance[0] == 77 && clearance[1] == 77 && res.signal == 0x5a5a5a5a);
        return;
    }
    check(res.signal == CRANE_GO || res.signal == CRANE_WARN || res.signal == CRANE_STOP);
    check(clearance[0] >= 0 && clearance[1] >= 0);
    if (res.contact) {
        check(res.t >= slewing[0].t && res.t <= slewing[n_samples - 1].t);
        check(res.part >= 0 && res.part < 2 && res.obstacle >= 0 && res.obstacle < 2);
        check(isfinite((double)res.clearance) && res.clearance >= 0 && res.signal != CRANE_GO);
    } else {
        check(res.signal == CRANE_GO);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input in;
    crane_solid s[2];
    in.p = data;
    in.n = size;
    in.raw = next_byte(&in) & 1;
    solid(&in, &s[0]);
    solid(&in, &s[1]);
    fuzz_distance(&s[0], &s[1]);
    fuzz_guard(&in, s);
    return 0;
}
