/* SPDX-License-Identifier: MIT */
/*
 * Bounded work and arguments that overflow: the limits of crane.h
 * (CRANE_MAX_STEPS, CRANE_MAX_SAMPLES, CRANE_MAX_BATCH_STEPS) are checked before anything runs,
 * with a status that names what to change; the entry points that answered CRANE_OK with an
 * infinite result or read past an array now return a status. Double and float builds. The last
 * line is "N passed, N failed"; the exit status is nonzero on any failure.
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "crane.h"
#include "crane_patu655.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

static int n_pass, n_fail;

static void check_status(crane_status got, crane_status want, const char *what)
{
    if (got == want) {
        ++n_pass;
    } else {
        ++n_fail;
        printf("FAIL: %s: got %d '%s', want %d\n", what, (int)got, crane_status_message(got),
               (int)want);
    }
}

static void check(int ok, const char *what)
{
    if (ok)
        ++n_pass;
    else {
        ++n_fail;
        printf("FAIL: %s\n", what);
    }
}

static const crane_params params = CRANE_PATU655_INIT;

static void held(crane_inputs *in)
{
    memset(in, 0, sizeof *in);   /* all four drives (slew and extension too): holds */
    in->drive[0].mode = CRANE_DRIVE_HOLD;
    in->drive[1].mode = CRANE_DRIVE_HOLD;
}

/* Finding 3: horizon = 1e9 s (or dt = 1e-12 s) was accepted; sample_every = 10^12 ran for hours. */
static void test_limits(void)
{
    crane_state s = {{(crane_real)0.1, (crane_real)0.2}, {0, 0}, 0, 0, 0, 0, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
    crane_inputs in[2];
    crane_sample out[2];
    size_t n = 0, failed = 0;
    const crane_real dt = (crane_real)1e-3;

    held(&in[0]);
    held(&in[1]);
    check_status(crane_sample_count((crane_real)1e9, dt, &n), CRANE_E_STEPS, "horizon 1e9: steps");
    check_status(crane_sample_count((crane_real)1.0, (crane_real)1e-12, &n), CRANE_E_STEPS,
                 "dt 1e-12: steps");
    /* 10^12 where size_t holds it; on a 32-bit target the largest sample_every accepted */
    check_status(crane_sample_count_every((crane_real)1e9, dt,
                                          SIZE_MAX > 0xFFFFFFFFu ? (size_t)1000000000000ULL
                                                                 : (size_t)LONG_MAX,
                                          &n),
                 CRANE_E_STEPS, "horizon 1e9, sample_every 10^12: steps");
    check_status(crane_predict(&params, &s, &in[0], (crane_real)1e9, dt, out, 2, &n, &work),
                 CRANE_E_STEPS, "crane_predict horizon 1e9");
    check_status(crane_predict_many(&params, 1, 1, &s, in, (crane_real)1e9, dt, 1000000, out, 2,
                                    &failed, &work),
                 CRANE_E_STEPS, "crane_predict_many horizon 1e9");
    check(failed == 1, "crane_predict_many horizon 1e9: a shared argument");
    /* at the limit: accepted by the count (not run here) */
    check_status(crane_sample_count((crane_real)CRANE_MAX_STEPS * dt, dt, &n), CRANE_OK,
                 "CRANE_MAX_STEPS steps are accepted");
    check(n == (size_t)CRANE_MAX_STEPS + 1, "CRANE_MAX_STEPS steps: that many samples + 1");
    {
        /* the last step of the longest prediction: at most 1.25 dt (float: horizon/dt rounded) */
        const crane_real horizon = (crane_real)CRANE_MAX_STEPS * dt;
        const crane_real last = horizon - (crane_real)(long)(n - 2) * dt;
        check(last > 0 && last <= (crane_real)1.25 * dt, "the longest prediction's last step <= 1.25 dt");
    }
    check_status(crane_sample_count((crane_real)(CRANE_MAX_STEPS + 2) * dt, dt, &n),
                 CRANE_E_STEPS, "CRANE_MAX_STEPS + 2 steps are not");
    /* one call's samples: 9 futures of 1,000,001 samples */
    check_status(crane_predict_many(&params, 1, 9, &s, in, (crane_real)1000, dt, 1, out, 2, &failed, &work),
                 CRANE_E_SAMPLE_COUNT, "9 x 1,000,001 samples: over CRANE_MAX_SAMPLES");
    /* one call's work: 34 futures of 1,000,000 steps, 11 samples each */
    check_status(crane_predict_many(&params, 1, 34, &s, in, (crane_real)1000, dt, 100000, out, 2,
                                    &failed, &work),
                 CRANE_E_BATCH, "34 x 1,000,000 steps: over CRANE_MAX_BATCH_STEPS");
}

/* Time is k dt in every build, and CRANE_MAX_STEPS keeps it exact enough in float: the step
 * times up to the limit are strictly increasing, within dt/8 of k dt, and the samples of a run
 * carry exactly (crane_real)k * dt. */
static void test_time_is_k_dt(void)
{
    const crane_real dt = (crane_real)1e-3;
    crane_state s = {{(crane_real)0.1, (crane_real)0.2}, {0, 0}, 0, 0, 0, 0, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
    crane_inputs in[1];
    static crane_sample out[20];
    size_t failed = 0;
    long k, worst_k = 0;
    double worst = 0;
    int increasing = 1, exact = 1;

    for (k = CRANE_MAX_STEPS - 65536; k <= CRANE_MAX_STEPS; ++k) {
        const crane_real t = (crane_real)k * dt, t1 = (crane_real)(k + 1) * dt;
        const double err = fabs((double)t - (double)k * (double)dt);
        increasing &= t1 > t;
        if (err > worst) {
            worst = err;
            worst_k = k;
        }
    }
    check(increasing, "step times strictly increasing up to CRANE_MAX_STEPS");
    check(worst <= (double)dt / 8, "step times within dt/8 of k dt up to CRANE_MAX_STEPS");
    (void)worst_k;

    held(&in[0]);
    check_status(crane_predict_many(&params, 1, 1, &s, in, (crane_real)65.536, dt, 4096, out, 20,
                                    &failed, &work),
                 CRANE_OK, "65,536 held steps, every 4096th kept");
    for (k = 0; k <= 16; ++k)
        exact &= out[k].t == (k == 16 ? (crane_real)65.536 : (crane_real)(k * 4096) * dt);
    check(exact, "sample times are (crane_real)k * dt, the last one the horizon");
}

/* Finding 5: entry points that answered CRANE_OK to bad input. */
static void test_overflowing_arguments(void)
{
    crane_model m;
    crane_real force = 7, tau[4] = {7, 7, 7, 7}, stroke, th[4], w[4] = {0, 0, 0, 0},
               a[4] = {0, 0, 0, 0};
    crane_real xyz[3 * CRANE_N_POINTS];
    const int dbl = sizeof(crane_real) == sizeof(double);
    /* a rate whose viscous force, or a joint rate whose square, is beyond the largest real */
    const crane_real big_rate = dbl ? (crane_real)1e307 : (crane_real)1e37;
    const crane_real big_omega = dbl ? (crane_real)1e160 : (crane_real)1e20;

    check_status(crane_model_init(&m, &params, 0), CRANE_OK, "PATU model");
    check_status(crane_cylinder_force(&m, CRANE_LIFT, 0, 0, big_rate, &force), CRANE_E_OVERFLOW,
                 "crane_cylinder_force, stroke rate 1e307");
    check(force == 7, "crane_cylinder_force, stroke rate 1e307: nothing written");
    check_status(crane_cylinder_force(&m, CRANE_LIFT, 0, 0, (crane_real)0.1, &force), CRANE_OK,
                 "crane_cylinder_force, stroke rate 0.1");

    th[0] = (m.theta_min[0] + m.theta_max[0]) / 2;
    th[1] = (m.theta_min[1] + m.theta_max[1]) / 2;
    th[2] = 0;
    th[3] = m.extension;
    w[1] = big_omega;
    check_status(crane_inverse_dynamics(&m, th, w, a, tau), CRANE_E_OVERFLOW,
                 "crane_inverse_dynamics, omega 1e160");
    check(tau[0] == 7 && tau[1] == 7, "crane_inverse_dynamics, omega 1e160: nothing written");
    w[1] = 0;
    check_status(crane_inverse_dynamics(&m, th, w, a, tau), CRANE_OK,
                 "crane_inverse_dynamics in range");

    /* a tilt angle 0.3 rad beyond the limit, where crane_joint_stroke already said no */
    th[1] = m.theta_min[1] - (crane_real)0.3;
    check_status(crane_joint_stroke(&m, CRANE_TILT, th[1], &stroke), CRANE_E_ANGLE,
                 "crane_joint_stroke beyond the tilt limit");
    tau[0] = tau[1] = 7;
    check_status(crane_inverse_dynamics(&m, th, w, a, tau), CRANE_E_ANGLE,
                 "crane_inverse_dynamics beyond the tilt limit (four-bar open)");
    check(tau[0] == 7 && tau[1] == 7, "crane_inverse_dynamics beyond the limit: nothing written");

    /* n = SIZE_MAX/2 + 1: 2 n wraps to 0 and the pose loop read past the caller's array */
    th[1] = (m.theta_min[1] + m.theta_max[1]) / 2;
    check_status(crane_points(&m, 0, SIZE_MAX / 2 + 1, th, xyz), CRANE_E_OVERFLOW,
                 "crane_points, n = SIZE_MAX/2 + 1");
    check_status(crane_points(&m, 0, 1, th, xyz), CRANE_OK, "crane_points, n = 1");
}

int main(void)
{
    printf("cranepredict bounds tests (%s)\n", sizeof(crane_real) == sizeof(double) ? "double" : "float");
    test_limits();
    test_time_is_k_dt();
    test_overflowing_arguments();
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail ? 1 : 0;
}
