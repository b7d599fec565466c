/* SPDX-License-Identifier: MIT */
/*
 * Bare C benchmark of the prediction core: no Python, the same crane as the pytest benchmarks
 * (benchmarks/), timed with the monotonic clock.
 *
 *   bench_core [dt horizon lift_stroke tilt_stroke lift_drive tilt_drive [min_seconds [load]]]
 *     dt, horizon: s; strokes: m (at rest); drive: "hold" or "p_a,p_b" in Pa;
 *     min_seconds: repeat the prediction for at least this long (default 0.5); load: kg (200).
 *   Without arguments: paper-fig4 at dt = 1e-3 s (the scenario from the generated header
 *   example/crane_scenarios.h: 2 s, 0.116 0.20, 175 bar on the lift's bore side, tilt held, 200 kg).
 *
 *   bench_core --scenario NAME [dt [min_seconds]] [--substeps]
 *     any named scenario of example/crane_scenarios.h (its load, initial state, all four drives
 *     and horizon; tools/golden.py generates it from src/cranepredict/scenarios), default dt 2e-3 s.
 *     --substeps also prints, over the steps of one prediction at dt, the RK4 substeps per step
 *     that each source of stiffness asks for (docs/model.md, "Hydraulics" and "Four joints"):
 *     the valve-driven actuators' chambers (crane__substeps at the step's start) and the moving
 *     extension's friction (ceil(h G_f min((M^-1)_ee, 4 / m_ext) / 2.5), M over the joints not
 *     held and not the slew), and the count the integrator takes, the larger of the two (steps
 *     split by an end-stop event are counted as one step of dt).
 *
 * Prints one line of key=value pairs: the wall time of the best and the mean prediction, the
 * faster-than-real-time ratios (simulated s / wall s) and the final tip, which the pytest
 * benchmark compares with predict() to make sure both ran the same model. The crane is
 * src/cranepredict/cranes/patu655.toml, through the generated header example/crane_patu655.h.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "crane.h"
#include "crane_internal.h"
#include "crane_patu655.h"
#include "crane_scenarios.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

#define R(x) ((crane_real)(x))

enum { MAX_SAMPLES = 200001 };
static crane_sample out[MAX_SAMPLES];

/* PATU 655 from the generated header (src/cranepredict/cranes/patu655.toml), 200 kg load. */
static const crane_params patu655 = CRANE_PATU655_INIT;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The named scenarios of the generated header. */
typedef struct {
    const char *name;
    crane_real load_mass;
    crane_state state;
    crane_inputs inputs;
    crane_real horizon;
} scenario;

#define SCENARIO_ENTRY(name, X)                                                                  \
    {name, CRANE_SCENARIO_##X##_LOAD_MASS, CRANE_SCENARIO_##X##_STATE,                          \
     CRANE_SCENARIO_##X##_INPUTS, CRANE_SCENARIO_##X##_HORIZON},
static const scenario scenarios[] = {CRANE_SCENARIO_LIST(SCENARIO_ENTRY)};

static const scenario *find_scenario(const char *name)
{
    size_t i;
    for (i = 0; i < sizeof scenarios / sizeof scenarios[0]; ++i)
        if (strcmp(scenarios[i].name, name) == 0)
            return &scenarios[i];
    fprintf(stderr, "bench_core: no scenario %s; known:", name);
    for (i = 0; i < sizeof scenarios / sizeof scenarios[0]; ++i)
        fprintf(stderr, " %s", scenarios[i].name);
    fprintf(stderr, "\n");
    return NULL;
}

/* (M^-1)_ee of the in-plane mass matrix Mp = (M00, M01, M0e, M11, M1e, Mee) over the joints of
 * (lift, tilt, extension) that are free (free[k]), by Gaussian elimination on that block. */
static double minv_ee(const crane_real Mp[6], const int free3[3])
{
    const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    double a[3][4];
    int map[3], n = 0, i, j, k;
    for (i = 0; i < 3; ++i)
        if (free3[i])
            map[n++] = i;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j)
            a[i][j] = (double)Mp[idx[map[i]][map[j]]];
        a[i][n] = map[i] == 2 ? 1.0 : 0.0;
    }
    for (k = 0; k < n; ++k)
        for (i = k + 1; i < n; ++i) {
            const double f = a[i][k] / a[k][k];
            for (j = k; j <= n; ++j)
                a[i][j] -= f * a[k][j];
        }
    for (i = n - 1; i >= 0; --i) {
        for (j = i + 1; j < n; ++j)
            a[i][n] -= a[i][j] * a[j][n];
        a[i][n] /= a[i][i];
    }
    return a[n - 1][n];   /* the extension is the last free joint */
}

/* The substeps of every step of the prediction in out (n samples at dt, sample_every 1), by
 * source: see the header. */
static int print_substeps(const crane_params *p, const crane_inputs *in, const crane_sample *o,
                          size_t n, double dt)
{
    crane_model m;
    crane__bodies b;
    int valve[4], j, any_valve = 0;
    const int ext_moves = in->drive[CRANE_EXTENSION].mode != CRANE_DRIVE_HOLD;
    const double gf = (double)crane__extension_friction_slope(p);
    const double m_ext = (double)p->extension_boom.mass;
    long by_joint[4] = {0, 0, 0, 0}, steps = 0, sum_v = 0, sum_f = 0, sum_n = 0, max_v = 0,
         max_f = 0, bind_v = 0, bind_f = 0, tie = 0;
    size_t k;

    if (crane_model_init(&m, p, o[0].extension) != CRANE_OK)
        return 1;
    crane__bodies_init(p, &b);
    for (j = 0; j < 4; ++j) {
        valve[j] = in->drive[j].mode == CRANE_DRIVE_VALVE;
        any_valve |= valve[j];
    }
    for (k = 0; k + 1 < n; ++k) {
        const crane_sample *x = &o[k];
        const crane_real h = o[k + 1].t - x->t;
        long nv = 1, nf = 1, nn;
        if (any_valve) {
            const crane_real stroke[4] = {
                x->stroke[0], x->stroke[1],
                p->slew_drive.pinion_radius * (x->slew - p->slew_drive.slew_min),
                x->extension - p->extension_min};
            crane_real coef[8];   /* the limit valves' rates: not needed here */
            nv = crane__substeps(&m, stroke, valve, h, coef);
            for (j = 0; j < 4; ++j) {   /* each valve-driven actuator's chambers alone */
                int one[4] = {0, 0, 0, 0};
                one[j] = valve[j];
                by_joint[j] += valve[j] ? crane__substeps(&m, stroke, one, h, coef) : 1;
            }
        }
        if (ext_moves) {
            crane__conf cf;
            crane_real Mp[6];
            const int free3[3] = {in->drive[0].mode != CRANE_DRIVE_HOLD,
                                  in->drive[1].mode != CRANE_DRIVE_HOLD, 1};
            double minv;
            crane__conf_at(&m, x->theta[0], x->theta[1], x->extension, &cf);
            crane__mass_spatial(&m, &b, &cf, Mp);
            minv = minv_ee(Mp, free3);
            if (minv > 4 / m_ext)
                minv = 4 / m_ext;
            nf = (long)ceil((double)h * gf * minv / 2.5);
            if (nf < 1)
                nf = 1;
        }
        nn = nv > nf ? nv : nf;
        ++steps;
        sum_v += nv;
        sum_f += nf;
        sum_n += nn;
        max_v = nv > max_v ? nv : max_v;
        max_f = nf > max_f ? nf : max_f;
        if (nv > nf)
            ++bind_v;
        else if (nf > nv)
            ++bind_f;
        else
            ++tie;
    }
    printf("substeps dt=%.9g steps=%ld valves=%d%d%d%d extension_moves=%d "
           "valve_mean=%.3f valve_max=%ld valve_mean_by_joint=%.3f,%.3f,%.3f,%.3f "
           "friction_mean=%.3f friction_max=%ld taken_mean=%.3f "
           "taken_total=%ld valve_binds=%ld friction_binds=%ld tie=%ld\n",
           dt, steps, valve[0], valve[1], valve[2], valve[3], ext_moves,
           (double)sum_v / (double)steps, max_v, (double)by_joint[0] / (double)steps,
           (double)by_joint[1] / (double)steps, (double)by_joint[2] / (double)steps,
           (double)by_joint[3] / (double)steps, (double)sum_f / (double)steps, max_f,
           (double)sum_n / (double)steps, sum_n, bind_v, bind_f, tie);
    return 0;
}

static int parse_drive(const char *arg, crane_drive *d)
{
    char *end;
    d->mode = CRANE_DRIVE_PRESSURE;
    if (strcmp(arg, "hold") == 0) {
        d->mode = CRANE_DRIVE_HOLD;
        return 1;
    }
    d->p_a = R(strtod(arg, &end));
    if (*end != ',')
        return 0;
    d->p_b = R(strtod(end + 1, &end));
    return *end == '\0';
}

int main(int argc, char **argv)
{
    static const crane_state paper_state = CRANE_SCENARIO_PAPER_FIG4_STATE;
    static const crane_inputs paper_inputs = CRANE_SCENARIO_PAPER_FIG4_INPUTS;
    int named = argc >= 3 && strcmp(argv[1], "--scenario") == 0, want_substeps = 0;
    const scenario *sc = NULL;
    int given;
    double dt, horizon, min_seconds;
    crane_params p = patu655;
    crane_state s = paper_state;
    crane_inputs in = paper_inputs;
    size_t n = 0, need = 0;
    long reps = 0;
    double t0, wall, best = 1e30;
    crane_status st;

    if (named) {   /* --scenario NAME [dt [min_seconds]] [--substeps] */
        if (argc >= 4 && strcmp(argv[argc - 1], "--substeps") == 0) {
            want_substeps = 1;
            --argc;
        }
        sc = find_scenario(argv[2]);
        if (sc == NULL)
            return 2;
        s = sc->state;
        in = sc->inputs;
        p.load_mass = sc->load_mass;
        dt = argc >= 4 ? atof(argv[3]) : 2e-3;
        horizon = (double)sc->horizon;
        min_seconds = argc >= 5 ? atof(argv[4]) : 0.5;
        given = 0;
    } else {
        given = argc >= 7;
        dt = given ? atof(argv[1]) : 1e-3;
        horizon = given ? atof(argv[2]) : (double)CRANE_SCENARIO_PAPER_FIG4_HORIZON;
        min_seconds = argc >= 8 ? atof(argv[7]) : 0.5;
        p.load_mass = argc >= 9 ? R(atof(argv[8])) : CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS;
    }
    if (given) {
        memset(&s, 0, sizeof s);
        memset(&in, 0, sizeof in);
        s.stroke[CRANE_LIFT] = R(atof(argv[3]));
        s.stroke[CRANE_TILT] = R(atof(argv[4]));
        if (!parse_drive(argv[5], &in.drive[CRANE_LIFT]) ||
            !parse_drive(argv[6], &in.drive[CRANE_TILT])) {
            fprintf(stderr, "bench_core: a drive is \"hold\" or \"p_a,p_b\" (Pa)\n");
            return 2;
        }
    }
    /* CRANE_BENCH_METHOD=rosw|dopri5|rk4 picks the method (crane_solver); unset: the default */
    if (getenv("CRANE_BENCH_METHOD") != NULL) {
        const char *name = getenv("CRANE_BENCH_METHOD");
        in.solver.method = strcmp(name, "rk4") == 0      ? CRANE_METHOD_RK4
                           : strcmp(name, "rosw") == 0   ? CRANE_METHOD_ROSW
                           : strcmp(name, "dopri5") == 0 ? CRANE_METHOD_DOPRI5
                                                         : CRANE_METHOD_DEFAULT;
    }
    st = crane_sample_count(R(horizon), R(dt), &need);
    if (st != CRANE_OK || need > MAX_SAMPLES) {
        fprintf(stderr, "bench_core: bad horizon/dt (%s)\n", crane_status_message(st));
        return 2;
    }

    /* Repeat until min_seconds have passed; report the best single call (the machine is shared:
     * the minimum is the least disturbed figure) and the mean. */
    t0 = now();
    do {
        const double t1 = now();
        double w;
        st = crane_predict(&p, &s, &in, R(horizon), R(dt), out, MAX_SAMPLES, &n, &work);
        w = now() - t1;
        if (st != CRANE_OK) {
            fprintf(stderr, "bench_core: %s\n", crane_status_message(st));
            return 1;
        }
        if (w < best)
            best = w;
        ++reps;
    } while (now() - t0 < min_seconds);
    wall = (now() - t0) / (double)reps;

    if (sc != NULL)
        printf("scenario=%s ", sc->name);
    printf("dt=%.9g samples=%lu reps=%ld best_s=%.9g mean_s=%.9g ratio_best=%.1f "
           "ratio_mean=%.1f tip_x=%.17g tip_y=%.17g tip_z=%.17g\n",
           dt, (unsigned long)n, reps, best, wall, horizon / best, horizon / wall,
           (double)out[n - 1].tip[0], (double)out[n - 1].tip[1], (double)out[n - 1].tip[2]);
    if (want_substeps && print_substeps(&p, &in, out, n, dt) != 0)
        return 1;
    return 0;
}
