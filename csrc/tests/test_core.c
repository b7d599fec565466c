/* SPDX-License-Identifier: MIT */
/*
 * Unit tests of the cranepredict C core (no framework). The last line of output is
 * "N passed, N failed"; the exit status is nonzero on any failure.
 *
 * Test-side arithmetic is done in double and compared with the core's crane_real results, so the
 * same file checks the double and the float build (with looser tolerances for float).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "crane.h"
#include "crane_internal.h"
#include "crane_patu655.h"
#include "golden.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

static int n_pass, n_fail;

#ifdef CRANE_FLOAT
static const int is_float = 1;
#else
static const int is_float = 0;
#endif

static void check(int ok, const char *what)
{
    if (ok) {
        ++n_pass;
    } else {
        ++n_fail;
        printf("FAIL: %s\n", what);
    }
}

static void check_status(crane_status got, crane_status want, const char *what)
{
    if (got != want)
        printf("  (%s: got status %d '%s', want %d)\n", what, (int)got, crane_status_message(got),
               (int)want);
    check(got == want, what);
}

static void check_close(double got, double want, double tol, const char *what)
{
    const int ok = fabs(got - want) <= tol;
    if (!ok)
        printf("  (%s: got %.17g, want %.17g, |diff| %.3g > %.3g)\n", what, got, want,
               fabs(got - want), tol);
    check(ok, what);
}

/* tolerance for the current precision */
static double tol(double dbl, double flt) { return is_float ? flt : dbl; }

static crane_real R(double x) { return (crane_real)x; }
static double D(crane_real x) { return (double)x; }

/* The PATU 655 of the crane file (src/cranepredict/cranes/patu655.toml), side links included,
 * from the generated header: one source of truth. A test that needs another crane copies this
 * and changes fields. */
static crane_params patu(void)
{
    static const crane_params p = CRANE_PATU655_INIT;
    return p;
}

/* The PATU 655 with massless side links: the open chain of the closed-form checks. */
static crane_params patu_no_links(void)
{
    crane_params p = patu();
    memset(&p.side_link1, 0, sizeof p.side_link1);
    memset(&p.side_link2, 0, sizeof p.side_link2);
    return p;
}

static crane_inputs constant_inputs(double pa0, double pb0, int mode1, double pa1, double pb1)
{
    crane_inputs in;
    memset(&in, 0, sizeof in);
    in.drive[0].mode = CRANE_DRIVE_PRESSURE;
    in.drive[0].p_a = R(pa0);
    in.drive[0].p_b = R(pb0);
    in.drive[1].mode = mode1;
    in.drive[1].p_a = R(pa1);
    in.drive[1].p_b = R(pb1);
    return in;
}

static crane_state state(double s0, double s1, double v0, double v1, double slew, double ext)
{
    crane_state s;
    memset(&s, 0, sizeof s);   /* the slew and extension rates, chambers and spools: 0 */
    s.stroke[0] = R(s0);
    s.stroke[1] = R(s1);
    s.stroke_rate[0] = R(v0);
    s.stroke_rate[1] = R(v1);
    s.slew = R(slew);
    s.extension = R(ext);
    return s;
}

/* ---------------------------------------------------------------------------------------------- */

#ifdef CRANE_FLOAT
/* The float build's own sin/cos (kinematics.c; internal, declared here to test it). */
void crane__sincosf(float x, float *s, float *c);

static void test_sincosf(void)
{
    double worst = 0;
    int k, ok = 1;
    static const float huge[] = {65.0f, -201.5f, 1e4f, -3.0e7f, 1e30f, -3.4e38f};

    for (k = -200000; k <= 200000; ++k) {
        const float x = (float)k * 3.2e-4f; /* [-64, 64] */
        float s, c;
        double e;
        crane__sincosf(x, &s, &c);
        e = fabs((double)s - sin((double)x)) + fabs((double)c - cos((double)x));
        if (e > worst)
            worst = e;
    }
    printf("  float sincos: largest |error| %.3g on [-64, 64]\n", worst);
    check_close(worst, 0, 3e-7, "float sincos vs double sin/cos on [-64, 64]");
    for (k = 0; k < (int)(sizeof huge / sizeof huge[0]); ++k) {
        float s, c;
        crane__sincosf(huge[k], &s, &c);
        if (!(fabs((double)s * (double)s + (double)c * (double)c - 1) < 1e-6))
            ok = 0;
    }
    check(ok, "float sincos: huge arguments give a point on the unit circle");
}
#else
static void test_sincosf(void) {}
#endif

static void test_model_init(void)
{
    const crane_params p = patu();
    crane_model m;
    crane_real th_lo, th_hi, ds;

    check_status(crane_model_init(&m, &p, R(0.5)), CRANE_OK, "model_init PATU 655");
    check(m.theta_min[0] < m.theta_max[0] && m.theta_min[1] < m.theta_max[1], "angle limits ordered");
    check(crane_joint_angle(&m, CRANE_TILT, R(0.78), &th_lo, &ds) == CRANE_OK &&
              th_lo == m.theta_min[1] && D(ds) < 0,
          "tilt: stroke_max is the lower angle limit, ds/dtheta1 < 0");
    check(crane_joint_angle(&m, CRANE_TILT, R(0), &th_hi, &ds) == CRANE_OK &&
              th_hi == m.theta_max[1],
          "tilt: stroke_min is the upper angle limit");
    check(crane_joint_angle(&m, CRANE_LIFT, R(0), &th_lo, &ds) == CRANE_OK &&
              th_lo == m.theta_min[0] && D(ds) > 0,
          "lift: stroke_min is the lower angle limit, ds/dtheta0 > 0");
    /* the tilt runs from about 0 to about -190 deg on the PATU 655 */
    check(D(m.theta_max[1]) < 0.5 && D(m.theta_min[1]) > -3.5, "tilt range plausible");
    {
        /* at rest the friction is 0: the force is the pressure on the bore area */
        crane_real f = 0;
        check_status(crane_cylinder_force(&m, CRANE_LIFT, R(175e5), 0, 0, &f), CRANE_OK,
                     "cylinder force at rest");
        check_close(D(f) / 175e5, 3.14159265358979 * 0.01 / 4, tol(1e-15, 1e-8), "bore area");
        check_close(D(f), 137445.0, 1.0, "175 bar on a 100 mm bore = 137,445 N");
    }
    check_close(D(m.m2), 141.943 + 15.928 + 200, tol(1e-12, 1e-4), "lumped m2");
}

static void test_round_trips(void)
{
    const crane_params p = patu();
    crane_model m;
    int j, k;

    crane_model_init(&m, &p, R(0));
    for (j = 0; j < 2; ++j) {
        const double smin = D(p.cylinder[j].stroke_min), smax = D(p.cylinder[j].stroke_max);
        double worst = 0;
        int all_ok = 1;
        for (k = 0; k <= 100; ++k) {
            const crane_real s = R(smin + (smax - smin) * k / 100.0);
            crane_real th, ds, s2;
            if (crane_joint_angle(&m, j, s, &th, &ds) != CRANE_OK) {
                all_ok = 0;
                continue;
            }
            /* the float angle can round a hair outside the limits at the ends */
            if (th < m.theta_min[j]) th = m.theta_min[j];
            if (th > m.theta_max[j]) th = m.theta_max[j];
            if (crane_joint_stroke(&m, j, th, &s2) != CRANE_OK) {
                all_ok = 0;
                continue;
            }
            if (fabs(D(s2) - D(s)) > worst)
                worst = fabs(D(s2) - D(s));
        }
        check(all_ok, j == 0 ? "lift round trip statuses" : "tilt round trip statuses");
        check_close(worst, 0, tol(1e-12, 2e-4), j == 0 ? "lift stroke->angle->stroke" :
                                                         "tilt stroke->angle->stroke");
    }
}

static void test_transmission(void)
{
    const crane_params p = patu();
    crane_model m;
    int j, k;

    crane_model_init(&m, &p, R(0));
    for (j = 0; j < 2; ++j) {
        const double smin = D(p.cylinder[j].stroke_min), smax = D(p.cylinder[j].stroke_max);
        const double d = tol(1e-6, 2e-3);
        double worst = 0;
        for (k = 0; k <= 20; ++k) {
            const crane_real s = R(smin + 0.02 + (smax - smin - 0.04) * k / 20.0);
            crane_real th, ds, sp, sm;
            double fd;
            crane_joint_angle(&m, j, s, &th, &ds);
            crane_joint_stroke(&m, j, R(D(th) + d), &sp);
            crane_joint_stroke(&m, j, R(D(th) - d), &sm);
            fd = (D(sp) - D(sm)) / (D(R(D(th) + d)) - D(R(D(th) - d)));
            if (fabs(fd - D(ds)) / fabs(D(ds)) > worst)
                worst = fabs(fd - D(ds)) / fabs(D(ds));
        }
        check_close(worst, 0, tol(1e-7, 2e-2), j == 0 ? "lift ds/dtheta vs finite differences" :
                                                        "tilt ds/dtheta vs finite differences");
    }
}

static void test_points(void)
{
    const crane_params p = patu();
    crane_model m;
    crane_real th[4], xyz[2 * CRANE_N_POINTS * 3], ds;
    const double psi = 0.7;
    double L;
    int ok;

    crane_model_init(&m, &p, R(0.3));
    crane_joint_angle(&m, CRANE_LIFT, R(0.2), &th[0], &ds);
    crane_joint_angle(&m, CRANE_TILT, R(0.5), &th[1], &ds);
    crane_joint_angle(&m, CRANE_LIFT, R(0.4), &th[2], &ds);
    crane_joint_angle(&m, CRANE_TILT, R(0.1), &th[3], &ds);
    check_status(crane_points(&m, R(psi), 2, th, xyz), CRANE_OK, "points OK");
    ok = xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0;
    check(ok, "pillar base at the origin");
    check_close(D(xyz[3]), -0.090 * cos(psi), 1e-6, "lift pivot world x");
    check_close(D(xyz[4]), -0.090 * sin(psi), 1e-6, "lift pivot world y");
    check_close(D(xyz[5]), 1.4261, 1e-6, "lift pivot world z");
    /* the cylinders' pin-to-pin lengths give back the strokes; side links keep their lengths */
    {
        const crane_real *P = xyz; /* pose 0 */
        double d2 = 0, e2 = 0, f2 = 0;
        int i;
        for (i = 0; i < 3; ++i) {
            d2 += pow(D(P[3 * 3 + i]) - D(P[2 * 3 + i]), 2);     /* rod eye - lift base */
            e2 += pow(D(P[6 * 3 + i]) - D(P[4 * 3 + i]), 2);     /* Q - tilt base */
            f2 += pow(D(P[6 * 3 + i]) - D(P[7 * 3 + i]), 2);     /* Q - A */
        }
        check_close(sqrt(d2) - 0.820, 0.2, tol(1e-12, 1e-5), "lift cylinder length from points");
        check_close(sqrt(e2) - 1.050, 0.5, tol(1e-12, 1e-5), "tilt cylinder length from points");
        L = sqrt(f2);
        check_close(L, 0.475, tol(1e-12, 1e-5), "side link 2 length from points");
    }
    /* nothing written on a bad pose */
    {
        crane_real buf[2 * CRANE_N_POINTS * 3], ref[2 * CRANE_N_POINTS * 3];
        crane_real bad[4];
        memset(buf, 0x5a, sizeof buf);
        memcpy(ref, buf, sizeof buf);
        memcpy(bad, th, sizeof bad);
        bad[3] = R(D(m.theta_max[1]) + 0.1);
        check_status(crane_points(&m, R(0), 2, bad, buf), CRANE_E_ANGLE, "points angle range");
        bad[3] = (crane_real)NAN;
        check_status(crane_points(&m, R(0), 2, bad, buf), CRANE_E_NONFINITE, "points NaN");
        check_status(crane_points(&m, R(0), 2, NULL, buf), CRANE_E_NULL, "points NULL");
        check_status(crane_points(NULL, R(0), 2, th, buf), CRANE_E_NULL, "points NULL model");
        check(memcmp(buf, ref, sizeof buf) == 0, "points: nothing written on bad input");
        check_status(crane_points(&m, R(0), 0, NULL, NULL), CRANE_OK, "points n = 0");
    }
}

/* ---- bad input ------------------------------------------------------------------------------ */

static void expect_init(crane_params p, double ext, crane_status want, const char *what)
{
    crane_model m, ref;
    memset(&m, 0x3c, sizeof m);
    memcpy(&ref, &m, sizeof m);
    check_status(crane_model_init(&m, &p, R(ext)), want, what);
    if (want != CRANE_OK)
        check(memcmp(&m, &ref, sizeof m) == 0, "model untouched on bad crane");
}

static void test_bad_params(void)
{
    const crane_params good = patu();
    crane_params p;
    crane_model m;

    check_status(crane_model_init(NULL, &good, R(0)), CRANE_E_NULL, "init NULL model");
    check_status(crane_model_init(&m, NULL, R(0)), CRANE_E_NULL, "init NULL params");
    p = good; p.lift_pivot.x = (crane_real)NAN; expect_init(p, 0, CRANE_E_NONFINITE, "NaN lift pivot");
    p = good; p.cylinder[1].friction.viscous = (crane_real)INFINITY;
    expect_init(p, 0, CRANE_E_NONFINITE, "inf viscous");
    expect_init(good, (double)NAN, CRANE_E_NONFINITE, "NaN extension");
    p = good; p.lift_boom.mass = 0; expect_init(p, 0, CRANE_E_BODY, "zero lift mass");
    p = good; p.outer_boom.izz = R(-1); expect_init(p, 0, CRANE_E_BODY, "negative Izz");
    p = good; p.extension_boom.mass = R(-1); expect_init(p, 0, CRANE_E_BODY, "negative ext mass");
    p = good; p.load_mass = R(-1); expect_init(p, 0, CRANE_E_BODY, "negative load");
    p = good; p.load_mass = 0; expect_init(p, 0, CRANE_OK, "zero load is fine");
    p = good; p.cylinder[0].rod = R(0.1); expect_init(p, 0, CRANE_E_CYLINDER, "bore <= rod");
    p = good; p.cylinder[1].rod = 0; expect_init(p, 0, CRANE_E_CYLINDER, "rod <= 0");
    p = good; p.cylinder[1].stroke_min = R(0.78);
    expect_init(p, 0, CRANE_E_CYLINDER, "stroke_min >= stroke_max");
    p = good; p.cylinder[0].friction.static_ = R(100);
    expect_init(p, 0, CRANE_E_FRICTION, "F_S < F_C");
    p = good; p.cylinder[0].friction.viscous = R(-1);
    expect_init(p, 0, CRANE_E_FRICTION, "negative viscous");
    p = good; p.cylinder[1].friction.stribeck_velocity = 0;
    expect_init(p, 0, CRANE_E_FRICTION, "v_S <= 0");
    p = good; p.cylinder[1].friction.factor = -1;
    expect_init(p, 0, CRANE_E_FRICTION, "factor < 0");
    p = good; p.gravity = R(-9.81); expect_init(p, 0, CRANE_E_GRAVITY, "negative gravity");
    expect_init(good, 1.5, CRANE_E_EXTENSION, "extension > max");
    expect_init(good, -0.1, CRANE_E_EXTENSION, "extension < min");
    p = good; p.cylinder[0].length_retracted = R(1.2);
    expect_init(p, 0, CRANE_E_GEOMETRY, "lift triangle cannot close");
    p = good; p.cylinder[1].stroke_max = R(3.0);
    expect_init(p, 0, CRANE_E_FOURBAR, "four-bar cannot close (tilt stroke_max 3.0)");
}

static void test_bad_small_calls(void)
{
    const crane_params p = patu();
    crane_model m;
    crane_real th = R(123), ds = R(456), s = R(789), f = R(1), tau[4] = {R(5), R(6), R(7), R(8)};
    const crane_real z[4] = {0, 0, 0, 0};
    crane_real nan4[4] = {0, 0, 0, 0};
    size_t count = 77;

    nan4[0] = (crane_real)NAN;
    crane_model_init(&m, &p, R(0));
    check_status(crane_joint_angle(&m, CRANE_LIFT, R(0.6), &th, &ds), CRANE_E_STROKE, "angle: stroke > max");
    check_status(crane_joint_angle(&m, CRANE_TILT, R(-0.01), &th, &ds), CRANE_E_STROKE, "angle: stroke < min");
    check_status(crane_joint_angle(&m, CRANE_TILT, (crane_real)NAN, &th, &ds), CRANE_E_NONFINITE, "angle: NaN");
    check_status(crane_joint_angle(&m, 2, R(0.1), &th, &ds), CRANE_E_CYLINDER, "angle: bad joint");
    check_status(crane_joint_angle(&m, 0, R(0.1), NULL, &ds), CRANE_E_NULL, "angle: NULL out");
    check_status(crane_joint_angle(NULL, 0, R(0.1), &th, &ds), CRANE_E_NULL, "angle: NULL model");
    check(D(th) == 123 && D(ds) == 456, "angle: nothing written on bad input");
    check_status(crane_joint_stroke(&m, CRANE_LIFT, R(D(m.theta_max[0]) + 0.01), &s), CRANE_E_ANGLE,
                 "stroke: angle above range");
    check_status(crane_joint_stroke(&m, CRANE_TILT, R(D(m.theta_min[1]) - 0.01), &s), CRANE_E_ANGLE,
                 "stroke: angle below range");
    check_status(crane_joint_stroke(&m, CRANE_TILT, (crane_real)INFINITY, &s), CRANE_E_NONFINITE, "stroke: inf");
    check_status(crane_joint_stroke(&m, -1, R(0), &s), CRANE_E_CYLINDER, "stroke: bad joint");
    check_status(crane_joint_stroke(&m, 0, R(0), NULL), CRANE_E_NULL, "stroke: NULL");
    check(D(s) == 789, "stroke: nothing written on bad input");
    check_status(crane_cylinder_force(&m, 0, R(-1), 0, 0, &f), CRANE_E_PRESSURE, "force: p_a < 0");
    check_status(crane_cylinder_force(&m, 1, 0, R(2e8), 0, &f), CRANE_E_PRESSURE, "force: p_b > max");
    check_status(crane_cylinder_force(&m, 1, 0, 0, (crane_real)NAN, &f), CRANE_E_NONFINITE, "force: NaN rate");
    check_status(crane_cylinder_force(&m, 3, 0, 0, 0, &f), CRANE_E_CYLINDER, "force: bad joint");
    check_status(crane_cylinder_force(&m, 0, 0, 0, 0, NULL), CRANE_E_NULL, "force: NULL");
    check(D(f) == 1, "force: nothing written on bad input");
    {
        /* F = p_a A_a - p_b A_b - friction */
        const double v = 0.01, Aa = 3.14159265358979 * 0.01 / 4,
                     Ab = 3.14159265358979 * (0.01 - 0.056 * 0.056) / 4;
        /* [S1]'s law at v = 2 v_S (x = 2): x / (x^2/4 + 3/4)^2 = 2 / (7/4)^2 = 32/49, so
         * k [210 tanh(8) + 90 * 32/49] + 330 tanh(4) v with k = 4 (lift) or 1 (tilt). */
        const double levels = 210 * tanh(8.0) + 90.0 * 32 / 49, viscous = 330 * tanh(4.0) * v;
        check_status(crane_cylinder_force(&m, 0, R(1e7), R(2e6), R(v), &f), CRANE_OK, "force OK");
        check_close(D(f), 1e7 * Aa - 2e6 * Ab - (4 * levels + viscous), tol(1e-8, 0.05), "force value");
        check_status(crane_cylinder_force(&m, 1, 0, 0, R(-v), &f), CRANE_OK, "force OK 2");
        check_close(D(f), levels + viscous, tol(1e-10, 1e-3), "friction is odd and opposes motion");
    }
    check_status(crane_inverse_dynamics(&m, nan4, z, z, tau), CRANE_E_NONFINITE, "ID: NaN");
    check_status(crane_inverse_dynamics(&m, z, z, z, NULL), CRANE_E_NULL, "ID: NULL");
    check(D(tau[0]) == 5 && D(tau[1]) == 6 && D(tau[2]) == 7 && D(tau[3]) == 8,
          "ID: nothing written on bad input");

    check_status(crane_sample_count(R(2), R(1e-3), &count), CRANE_OK, "count OK");
    check(count == 2001, "2 s at 1 ms: 2001 samples");
    check_status(crane_sample_count(R(0.3), R(0.1), &count), CRANE_OK, "count 0.3/0.1");
    check(count == 4, "0.3 s at 0.1 s: 4 samples (the 1e-9 tolerance)");
    check_status(crane_sample_count(R(1), R(0.3), &count), CRANE_OK, "count 1/0.3");
    check(count == 5, "1 s at 0.3 s: 5 samples (short last step)");
    count = 77;
    check_status(crane_sample_count(0, R(1e-3), &count), CRANE_E_HORIZON, "count: horizon 0");
    check_status(crane_sample_count(R(1), 0, &count), CRANE_E_DT, "count: dt 0");
    check_status(crane_sample_count(R(1), R(-1e-3), &count), CRANE_E_DT, "count: dt < 0");
    check_status(crane_sample_count(R(1), R(2), &count), CRANE_E_DT, "count: dt > horizon");
    check_status(crane_sample_count((crane_real)NAN, R(1e-3), &count), CRANE_E_NONFINITE, "count: NaN");
    check_status(crane_sample_count(R(1e30), R(1e-10), &count), CRANE_E_STEPS, "count: too many");
    check_status(crane_sample_count(R(1), R(1e-3), NULL), CRANE_E_NULL, "count: NULL");
    check(count == 77, "count: nothing written on bad input");
    check(strlen(crane_status_message(CRANE_E_FOURBAR)) > 0 &&
              strlen(crane_status_message((crane_status)99)) > 0,
          "status messages");
}

enum { BUF = 64 };

/* Runs crane_predict into a canary-filled buffer; checks the status and, on an error, that not a
 * byte of the buffer or of *n_written changed. */
static void expect_predict(const crane_params *p, const crane_state *s, const crane_inputs *in,
                           double horizon, double dt, size_t capacity, crane_status want,
                           const char *what)
{
    crane_sample buf[BUF], ref[BUF];
    size_t n = 12345;

    memset(buf, 0xa5, sizeof buf);
    memcpy(ref, buf, sizeof buf);
    check_status(crane_predict(p, s, in, R(horizon), R(dt), buf, capacity, &n, &work), want, what);
    if (want != CRANE_OK)
        check(memcmp(buf, ref, sizeof buf) == 0 && n == 12345, "predict: nothing written");
    else
        check(n <= capacity && memcmp(buf + n, ref + n, (BUF - n) * sizeof buf[0]) == 0,
              "predict: nothing written past the samples");
}

static void test_bad_predict(void)
{
    const crane_params good = patu();
    const crane_state s0 = state(0.2, 0.3, 0, 0, 0, 0);
    const crane_inputs in0 = constant_inputs(5e6, 1e6, CRANE_DRIVE_HOLD, 0, 0);
    crane_params p;
    crane_state s;
    crane_inputs in;
    crane_sample buf[BUF];
    size_t n;
    const crane_real ts[3] = {R(-0.1), R(0.05), R(0.2)};
    const crane_real tbad[3] = {R(0), R(0.05), R(0.05)};
    const crane_real tlate[3] = {R(0.01), R(0.05), R(0.2)};
    const crane_real tshort[3] = {R(0), R(0.05), R(0.09)};
    const crane_real pa[3] = {R(1e6), R(2e6), R(3e6)};
    const crane_real pbig[3] = {R(1e6), R(2e8), R(3e6)};
    const crane_real pnan[3] = {R(1e6), (crane_real)NAN, R(3e6)};

    expect_predict(&good, &s0, &in0, 0.1, 0.01, BUF, CRANE_OK, "predict OK (11 samples)");
    expect_predict(&good, &s0, &in0, 0.1, 0.01, 11, CRANE_OK, "predict OK, capacity exact");
    expect_predict(&good, &s0, &in0, 0.1, 0.01, 10, CRANE_E_CAPACITY, "capacity too small");
    check_status(crane_predict(NULL, &s0, &in0, R(0.1), R(0.01), buf, BUF, &n, &work), CRANE_E_NULL, "NULL params");
    check_status(crane_predict(&good, NULL, &in0, R(0.1), R(0.01), buf, BUF, &n, &work), CRANE_E_NULL, "NULL state");
    check_status(crane_predict(&good, &s0, NULL, R(0.1), R(0.01), buf, BUF, &n, &work), CRANE_E_NULL, "NULL inputs");
    check_status(crane_predict(&good, &s0, &in0, R(0.1), R(0.01), NULL, BUF, &n, &work), CRANE_E_NULL, "NULL out");
    check_status(crane_predict(&good, &s0, &in0, R(0.1), R(0.01), buf, BUF, NULL, &work), CRANE_E_NULL, "NULL n");
    check_status(crane_predict(&good, &s0, &in0, R(0.1), R(0.01), buf, BUF, &n, NULL), CRANE_E_NULL, "NULL work");
    {
        crane_model mw;
        size_t failed;
        check_status(crane_model_init(&mw, &good, s0.extension), CRANE_OK, "NULL work: the model");
        check_status(crane_predict_model(&mw, &s0, &in0, R(0.1), R(0.01), buf, BUF, &n, NULL), CRANE_E_NULL,
                     "predict_model: NULL work");
        check_status(crane_predict_many(&good, 1, 1, &s0, &in0, R(0.1), R(0.01), 1, buf, BUF, &failed, NULL),
                     CRANE_E_NULL, "predict_many: NULL work");
    }
    expect_predict(&good, &s0, &in0, 0.1, 0, BUF, CRANE_E_DT, "dt = 0");
    expect_predict(&good, &s0, &in0, 0.1, -0.01, BUF, CRANE_E_DT, "dt < 0");
    expect_predict(&good, &s0, &in0, 0.1, 0.2, BUF, CRANE_E_DT, "dt > horizon");
    expect_predict(&good, &s0, &in0, 0, 0.01, BUF, CRANE_E_HORIZON, "horizon = 0");
    expect_predict(&good, &s0, &in0, (double)NAN, 0.01, BUF, CRANE_E_NONFINITE, "horizon NaN");
    p = good; p.cylinder[1].stroke_max = R(3.0);
    expect_predict(&p, &s0, &in0, 0.1, 0.01, BUF, CRANE_E_FOURBAR, "predict: four-bar cannot close");
    p = good; p.outer_boom.com.y = (crane_real)NAN;
    expect_predict(&p, &s0, &in0, 0.1, 0.01, BUF, CRANE_E_NONFINITE, "predict: NaN in crane");
    s = s0; s.stroke[0] = (crane_real)NAN; expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_NONFINITE, "stroke NaN");
    s = s0; s.slew = (crane_real)INFINITY; expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_NONFINITE, "slew inf");
    s = s0; s.stroke[0] = R(0.6); expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_STROKE, "stroke > max");
    s = s0; s.stroke[1] = R(-0.001); expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_STROKE, "stroke < min");
    s = s0; s.extension = R(2); expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_EXTENSION, "extension");
    s = s0; s.stroke_rate[1] = R(0.01);
    expect_predict(&good, &s, &in0, 0.1, 0.01, BUF, CRANE_E_STROKE_RATE, "held cylinder with a rate");
    in = in0; in.drive[1].mode = 5; expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_DRIVE, "drive mode");
    in = in0; in.drive[0].p_a = R(-1); expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_PRESSURE, "p_a < 0");
    in = in0; in.drive[0].p_b = R(1.5e8); expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_PRESSURE, "p_b > max");
    in = in0; in.drive[0].p_a = (crane_real)NAN; expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_NONFINITE, "p_a NaN");

    in = in0;
    in.drive[0].n_samples = 3;
    in.drive[0].t = ts;
    in.drive[0].p_a_samples = pa;
    in.drive[0].p_b_samples = pa;
    expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_OK, "samples OK");
    in.drive[0].t = tbad; expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_SAMPLES, "samples not increasing");
    in.drive[0].t = tlate; expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_SAMPLES, "samples start after 0");
    in.drive[0].t = tshort; expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_SAMPLES, "samples end before horizon");
    in.drive[0].t = ts; in.drive[0].p_a_samples = pbig;
    expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_PRESSURE, "sample pressure > max");
    in.drive[0].p_a_samples = pnan;
    expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_NONFINITE, "sample pressure NaN");
    in.drive[0].p_a_samples = pa; in.drive[0].t = NULL;
    expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_NULL, "sample times NULL");
    in.drive[0].t = ts; in.drive[0].n_samples = 1;
    expect_predict(&good, &s0, &in, 0.1, 0.01, BUF, CRANE_E_SAMPLES, "one sample cannot cover");
}

/* ---- dynamics ------------------------------------------------------------------------------- */

/* The booms' torques of crane_inverse_dynamics at the extension e, with the slew and the
 * extension at rest. */
static void boom_torques(const crane_model *m, crane_real e, const crane_real th[2],
                         const crane_real w[2], const crane_real a[2], crane_real tau[2])
{
    const crane_real q[4] = {th[0], th[1], 0, e}, qd[4] = {w[0], w[1], 0, 0},
                     qdd[4] = {a[0], a[1], 0, 0};
    crane_real t[4];
    check_status(crane_inverse_dynamics(m, q, qd, qdd, t), CRANE_OK, "boom torques");
    tau[0] = t[0];
    tau[1] = t[1];
}

/* small deterministic generator for the random states */
static double rnd(unsigned long *seed)
{
    *seed = (*seed * 1103515245UL + 12345UL) & 0x7fffffffUL;
    return (double)*seed / 2147483648.0;
}

static void test_inverse_dynamics_lagrange(void)
{
    const crane_params p = patu_no_links();
    const double e = 0.37, g = 9.81;
    crane_model m;
    unsigned long seed = 42;
    double worst = 0;
    /* body 2 lumped independently: outer boom + extension boom at e + load at the tip */
    const double mob = 141.943, mex = 15.928, ml = 200;
    const double cob[2] = {0.643096, 0.247055};
    const double xex[2] = {-0.415 + e + 1.225, 0.287};
    const double xtp[2] = {-0.415 + e + 2.45, 0.287};
    const double m2 = mob + mex + ml;
    const double c2[2] = {(mob * cob[0] + mex * xex[0] + ml * xtp[0]) / m2,
                          (mob * cob[1] + mex * xex[1] + ml * xtp[1]) / m2};
    const double I2 = 58.6619 + mob * (pow(cob[0] - c2[0], 2) + pow(cob[1] - c2[1], 2)) + 7.97 +
                      mex * (pow(xex[0] - c2[0], 2) + pow(xex[1] - c2[1], 2)) +
                      ml * (pow(xtp[0] - c2[0], 2) + pow(xtp[1] - c2[1], 2));
    const double m1 = 143.66, c1[2] = {1.229248, 0.055596}, I1 = 67.0537;
    const double O2[2] = {2.881081, 0.021593};
    const double J1 = I1 + m1 * (c1[0] * c1[0] + c1[1] * c1[1]);
    const double J2 = I2 + m2 * (c2[0] * c2[0] + c2[1] * c2[1]);
    int k;

    crane_model_init(&m, &p, R(e));
    check_close(D(m.i2), I2, tol(1e-10, 1e-3), "lumped I2");
    check_close(D(m.c2.x), c2[0], tol(1e-13, 1e-5), "lumped c2.x");
    for (k = 0; k < 200; ++k) {
        /* across the angle limits (the model's domain: crane_inverse_dynamics rejects others) */
        const double th0 = D(m.theta_min[0]) + D(m.theta_max[0] - m.theta_min[0]) * rnd(&seed);
        const double th1 = D(m.theta_min[1]) + D(m.theta_max[1] - m.theta_min[1]) * rnd(&seed);
        const double w0 = 2 * rnd(&seed) - 1, w1 = 2 * rnd(&seed) - 1;
        const double a0 = 4 * rnd(&seed) - 2, a1 = 4 * rnd(&seed) - 2;
        const crane_real th[2] = {R(th0), R(th1)}, w[2] = {R(w0), R(w1)}, a[2] = {R(a0), R(a1)};
        crane_real tau[2];
        /* R(theta1) c2 and its derivative perp(R c2) */
        const double rc[2] = {cos(th1) * c2[0] - sin(th1) * c2[1], sin(th1) * c2[0] + cos(th1) * c2[1]};
        const double kk = O2[0] * rc[0] + O2[1] * rc[1];
        const double kp = O2[0] * -rc[1] + O2[1] * rc[0];
        const double M11 = J1 + m2 * (O2[0] * O2[0] + O2[1] * O2[1]) + J2 + 2 * m2 * kk;
        const double M12 = J2 + m2 * kk, M22 = J2;
        /* gravity: dV/dtheta = g m (R c).x for each rotated centre of mass */
        const double C1x = cos(th0) * c1[0] - sin(th0) * c1[1];
        const double r12x = cos(th0) * O2[0] - sin(th0) * O2[1];
        const double C2x = cos(th0 + th1) * c2[0] - sin(th0 + th1) * c2[1];
        const double G0 = g * (m1 * C1x + m2 * (r12x + C2x)), G1 = g * m2 * C2x;
        const double t0 = M11 * a0 + M12 * a1 + m2 * kp * w1 * (2 * w0 + w1) + G0;
        const double t1 = M12 * a0 + M22 * a1 - m2 * kp * w0 * w0 + G1;
        double err;

        boom_torques(&m, R(e), th, w, a, tau);
        err = (fabs(D(tau[0]) - t0) + fabs(D(tau[1]) - t1)) / (fabs(t0) + fabs(t1) + 1);
        if (err > worst)
            worst = err;
    }
    check_close(worst, 0, tol(1e-12, 1e-4), "Newton-Euler ID vs Lagrange closed form (200 states)");
}

/* The planar and the spatial dynamics kernels (dynamics.c) are one physics: at the model's
 * extension, with the slew and the extension at rest, the spatial kernel's boom torques and the
 * (lift, tilt) block of its mass matrix are the planar kernel's (which lumps the extension boom
 * and the load into the outer boom) to rounding, side links included. */
static void test_kernels_agree(void)
{
    const crane_params p = patu();
    crane_model m;
    crane__bodies b;
    unsigned long seed = 11;
    double worst_tau = 0, worst_m = 0;
    int k, i;

    crane_model_init(&m, &p, R(0.4));
    crane__bodies_init(&p, &b);
    for (k = 0; k < 100; ++k) {
        const double th0 = D(m.theta_min[0]) + D(m.theta_max[0] - m.theta_min[0]) * rnd(&seed);
        const double th1 = D(m.theta_min[1]) + D(m.theta_max[1] - m.theta_min[1]) * rnd(&seed);
        const crane_real w[4] = {R(2 * rnd(&seed) - 1), R(2 * rnd(&seed) - 1), 0, 0};
        const crane_real a[4] = {R(4 * rnd(&seed) - 2), R(4 * rnd(&seed) - 2), 0, 0};
        crane__conf cf;
        crane_real tp[2], ts[4], Mp[6], Ms[6];
        double e;

        crane__conf_at(&m, R(th0), R(th1), m.extension, &cf);
        crane__id_planar(&m, &cf, w, a, p.gravity, tp);
        crane__id_spatial(&m, &b, &cf, w, a, p.gravity, ts);
        crane__mass_planar(&m, &cf, Mp);
        crane__mass_spatial(&m, &b, &cf, Ms);
        e = (fabs(D(tp[0]) - D(ts[0])) + fabs(D(tp[1]) - D(ts[1]))) /
            (fabs(D(ts[0])) + fabs(D(ts[1])) + 1);
        if (e > worst_tau)
            worst_tau = e;
        for (i = 0; i < 4; i += i == 1 ? 2 : 1) {
            e = fabs(D(Mp[i]) - D(Ms[i])) / fabs(D(Ms[0]));
            if (e > worst_m)
                worst_m = e;
        }
    }
    check_close(worst_tau, 0, tol(1e-12, 1e-4), "planar vs spatial kernel: boom torques (100 states)");
    check_close(worst_m, 0, tol(1e-12, 1e-5), "planar vs spatial kernel: boom mass matrix");
}

/* 0.5 omega^T M omega, M from the core's inverse dynamics with g = 0 */
static double kinetic_energy(const crane_model *m, const crane_real th[2], const crane_real w[2])
{
    const crane_real z[2] = {0, 0}, e0[2] = {1, 0}, e1[2] = {0, 1};
    crane_real col0[2], col1[2];
    boom_torques(m, m->extension, th, z, e0, col0);
    boom_torques(m, m->extension, th, z, e1, col1);
    return 0.5 * (D(w[0]) * (D(col0[0]) * D(w[0]) + D(col1[0]) * D(w[1])) +
                  D(w[1]) * (D(col0[1]) * D(w[0]) + D(col1[1]) * D(w[1])));
}

static void test_energy(void)
{
    crane_params p = patu();
    const crane_state s0 = state(0.25, 0.40, 0.03, -0.04, 0.2, 0.5);
    /* RK4 at 1 ms: its truncation error is far below the 1e-9 asked (the error-controlled
     * method's, at its default tolerance, is 2e-8: tests/test_rosw.py holds it to its own) */
    crane_inputs in = constant_inputs(0, 0, CRANE_DRIVE_PRESSURE, 0, 0);
    crane_sample out[401];
    crane_model m;
    size_t n = 0, k;
    double E0, worst = 0;
    int i, no_stop = 1, moved;

    in.solver.method = CRANE_METHOD_RK4;
    p.gravity = 0;
    for (i = 0; i < 2; ++i) {
        p.cylinder[i].friction.coulomb = 0;
        p.cylinder[i].friction.static_ = 0;
        p.cylinder[i].friction.viscous = 0;
    }
    crane_model_init(&m, &p, R(0.5));
    check_status(crane_predict(&p, &s0, &in, R(0.4), R(1e-3), out, 401, &n, &work), CRANE_OK, "energy run");
    check(n == 401, "energy run: 401 samples");
    E0 = kinetic_energy(&m, out[0].theta, out[0].omega);
    for (k = 0; k < n; ++k) {
        const double E = kinetic_energy(&m, out[k].theta, out[k].omega);
        if (fabs(E - E0) / E0 > worst)
            worst = fabs(E - E0) / E0;
        if (out[k].stop[0] || out[k].stop[1])
            no_stop = 0;
    }
    moved = fabs(D(out[n - 1].stroke[0]) - 0.25) > 1e-3;
    check(no_stop && moved, "energy run stays free of the stops and moves");
    check_close(worst, 0, tol(1e-9, 1e-4), "frictionless, gravity-free: kinetic energy conserved");
}

/* ---- whole predictions ---------------------------------------------------------------------- */

static int strokes_in_range(const crane_params *p, const crane_sample *out, size_t n)
{
    size_t k;
    int j;
    for (k = 0; k < n; ++k)
        for (j = 0; j < 2; ++j)
            if (!(out[k].stroke[j] >= p->cylinder[j].stroke_min &&
                  out[k].stroke[j] <= p->cylinder[j].stroke_max))
                return 0;
    return 1;
}

enum { N_PAPER = 2001 };
static crane_sample paper_out[N_PAPER];

static void test_paper_scenario(void)
{
    crane_params p = patu();
    const crane_state s0 = CRANE_SCENARIO_PAPER_FIG4_STATE;
    const crane_inputs in = CRANE_SCENARIO_PAPER_FIG4_INPUTS;
    crane_model m;
    crane_real xyz[CRANE_N_POINTS * 3];
    size_t n = 0, k, first_stop = 0;
    int reached = 0, stays = 1, held = 1, mono = 1;

    p.load_mass = CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS;
    crane_model_init(&m, &p, R(0));
    check_status(crane_predict(&p, &s0, &in, CRANE_SCENARIO_PAPER_FIG4_HORIZON, R(1e-3), paper_out,
                               N_PAPER, &n, &work), CRANE_OK, "paper scenario runs");
    check(n == N_PAPER, "paper scenario: 2001 samples");
    check(D(paper_out[0].t) == 0 && D(paper_out[n - 1].t) == 2, "paper scenario: t from 0 to 2");
    for (k = 0; k < n; ++k) {
        if (paper_out[k].stop[0] == 1 && !reached) {
            reached = 1;
            first_stop = k;
        }
        if (reached && (paper_out[k].stop[0] != 1 || paper_out[k].stroke[0] != p.cylinder[0].stroke_max ||
                        paper_out[k].theta[0] != m.theta_max[0] || paper_out[k].omega[0] != 0))
            stays = 0;
        if (paper_out[k].stroke[1] != s0.stroke[1] || paper_out[k].omega[1] != 0 ||
            paper_out[k].stop[1] != 0)
            held = 0;
        if (k > 0 && !(paper_out[k].t > paper_out[k - 1].t))
            mono = 0;
    }
    check(reached && first_stop < n - 1, "paper scenario reaches the lift upper stop before 2 s");
    check(stays, "lift stays on its upper stop (stroke exactly stroke_max, omega 0)");
    check(held, "held tilt keeps its stroke, omega 0, no stop flag");
    check(mono, "sample times increase");
    check(strokes_in_range(&p, paper_out, n), "paper scenario: strokes never leave their range");
    printf("  paper scenario: lift upper stop at t = %.4f s (sample %lu)\n",
           D(paper_out[first_stop].t), (unsigned long)first_stop);
    /* the reported tip equals the tip of crane_points at the reported angles */
    check_status(crane_points(&m, 0, 1, paper_out[n / 2].theta, xyz), CRANE_OK, "points at a sample");
    check_close(D(xyz[30]), D(paper_out[n / 2].tip[0]), tol(1e-12, 1e-5), "sample tip x = points tip x");
    check_close(D(xyz[32]), D(paper_out[n / 2].tip[2]), tol(1e-12, 1e-5), "sample tip z = points tip z");
}

/* crane_step: 200 chained 10-ms periods continue the paper scenario's 2-s prediction (run by
 * test_paper_scenario into paper_out, dt = 1 ms: the same step grid), to the rounding of the
 * stroke -> angle conversion at each period's start (docs/model.md, "Continuing from a
 * prediction"), into the end stop; and its bad input. */
static void test_step(void)
{
    static crane_sample rk4_out[N_PAPER];
    crane_params p = patu();
    const crane_state s0 = CRANE_SCENARIO_PAPER_FIG4_STATE;
    crane_inputs in = CRANE_SCENARIO_PAPER_FIG4_INPUTS;
    crane_model m;
    crane_state s = s0, before;
    crane_sample ends[2];
    double worst = 0;
    size_t n = 0;
    int k, flags = 1;

    /* chained periods continue one prediction exactly with the fixed step (the error-controlled
     * method's steps depend on where the periods start: to its tolerance, tests/test_step.py) */
    in.solver.method = CRANE_METHOD_RK4;
    p.load_mass = CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS;
    check_status(crane_predict(&p, &s0, &in, CRANE_SCENARIO_PAPER_FIG4_HORIZON, R(1e-3), rk4_out,
                               N_PAPER, &n, &work), CRANE_OK, "step: the one-shot RK4 prediction");
    check_status(crane_model_init(&m, &p, R(0)), CRANE_OK, "step: model");
    for (k = 0; k < 200; ++k) {
        const crane_sample *want = &rk4_out[10 * (k + 1)];
        int i;
        if (crane_step(&m, &s, &in, R(0.01), R(1e-3), &s, ends, &work) != CRANE_OK)
            break;
        for (i = 0; i < 3; ++i) {
            const double e = fabs(D(ends[1].tip[i]) - D(want->tip[i]));
            worst = e > worst ? e : worst;
        }
        flags = flags && ends[1].stop[0] == want->stop[0] && ends[1].stop[1] == want->stop[1];
    }
    check(k == 200, "step: 200 chained periods run");
    /* float: each period's stroke carries 24 bits (6e-9 m on the lift's 0.1 m), an angle error of
     * about 1e-7 rad (ds/dtheta ~ 0.06 m/rad), 5e-7 m at the 5-m tip, over 200 periods */
    check(worst <= tol(1e-12, 1e-4), "step: chained periods = one prediction (tip)");
    check(flags && ends[1].stop[0] == 1, "step: the same stop flags, ending on the lift's stop");
    printf("  step: 200 chained 10-ms periods vs one 2-s prediction: tip within %.2g m\n", worst);

    before = s;
    check_status(crane_step(NULL, &s, &in, R(0.01), R(1e-3), &s, ends, &work), CRANE_E_NULL, "step: no model");
    check_status(crane_step(&m, &s, &in, R(0.01), R(1e-3), &s, NULL, &work), CRANE_E_NULL, "step: no out");
    check_status(crane_step(&m, &s, &in, R(0.01), R(1e-3), &s, ends, NULL), CRANE_E_NULL, "step: no work");
    check_status(crane_step(&m, &s, &in, R(0), R(1e-3), &s, ends, &work), CRANE_E_HORIZON, "step: period 0");
    check_status(crane_step(&m, &s, &in, R(0.01), R(0.02), &s, ends, &work), CRANE_E_DT, "step: dt > period");
    check(memcmp(&before, &s, sizeof s) == 0, "step: nothing written on an error");
}

static void test_stops_and_release(void)
{
    const crane_params p = patu();
    crane_model m;
    crane_sample out[301];
    size_t n = 0, k;
    int ok;

    crane_model_init(&m, &p, R(0));
    /* At rest on the lower angle stops with no pressure (tilt at stroke_max is its lower angle
     * limit, reported as stop +1 since the flags are in cylinder terms):
     * gravity keeps the lift on its stop and, in this pose, lifts the folded outer boom off its. */
    {
        const crane_state s0 = state(0, 0.78, 0, 0, 0, 0);
        const crane_inputs in = constant_inputs(0, 0, CRANE_DRIVE_PRESSURE, 0, 0);
        check_status(crane_predict(&p, &s0, &in, R(0.3), R(1e-3), out, 301, &n, &work), CRANE_OK, "rest on stops");
        ok = 1;
        for (k = 0; k < n; ++k)
            if (out[k].stop[0] != -1 || out[k].stroke[0] != 0 || out[k].theta[0] != m.theta_min[0])
                ok = 0;
        check(ok, "lift stays on its lower stop under gravity (stroke exactly stroke_min)");
        check(out[0].stop[1] == 1 && out[0].stroke[1] == p.cylinder[1].stroke_max &&
                  out[0].theta[1] == m.theta_min[1],
              "tilt at stroke_max starts on its lower angle stop, flagged +1 (cylinder terms)");
        check(out[1].stop[1] == 0 && out[n - 1].stroke[1] < out[1].stroke[1] &&
                  out[n - 1].theta[1] > out[1].theta[1],
              "tilt released from its lower stop when gravity pulls it into the range");
    }
    /* Lift on its lower stop, then pressurised: released at the first step and rising. */
    {
        const crane_state s0 = state(0, 0.3, 0, 0, 0, 0);
        const crane_inputs in = constant_inputs(100e5, 0, CRANE_DRIVE_HOLD, 0, 0);
        check_status(crane_predict(&p, &s0, &in, R(0.3), R(1e-3), out, 301, &n, &work), CRANE_OK, "release run");
        check(out[0].stop[0] == -1 && out[1].stop[0] == 0 && out[n - 1].stroke[0] > out[1].stroke[0],
              "lift released from its lower stop when pressurised");
    }
    /* Moving into a stop at t = 0: plastic impact takes the lift's rate to zero. */
    {
        const crane_state s0 = state(0.535, 0.3, 0.05, 0, 0, 0);
        const crane_inputs in = constant_inputs(175e5, 0, CRANE_DRIVE_PRESSURE, 30e5, 30e5);
        check_status(crane_predict(&p, &s0, &in, R(0.3), R(1e-3), out, 301, &n, &work), CRANE_OK, "impact at t=0");
        check(out[0].stop[0] == 1 && out[0].omega[0] == 0, "moving into the stop at t = 0: stopped, omega 0");
    }
    /* Both joints free, the lift hits its upper stop: the plastic impact must not add energy and
     * the strokes stay in range. */
    {
        const crane_state s0 = state(0.3, 0.3, 0.1, 0, 0, 0);
        const crane_inputs in = constant_inputs(175e5, 0, CRANE_DRIVE_PRESSURE, 60e5, 60e5);
        int hit = 0;
        check_status(crane_predict(&p, &s0, &in, R(1), R(5e-3), out, 301, &n, &work), CRANE_OK, "free-free run");
        for (k = 0; k < n; ++k)
            if (out[k].stop[0] == 1)
                hit = 1;
        check(hit, "free-free run hits the lift upper stop");
        check(strokes_in_range(&p, out, n), "free-free run: strokes stay in range");
    }
}

/* Both free, lift driven out hard: the lift hits stroke_max, the impact throws the outer boom down
 * and the tilt cylinder runs to stroke_max, its lower angle stop, flagged +1. */
static void test_tilt_flag(void)
{
    const crane_params p = patu();
    const crane_state s0 = state(0.116, 0.32, 0, 0, 0, 0);
    const crane_inputs in = constant_inputs(100e5, 0, CRANE_DRIVE_PRESSURE, 30e5, 20e5);
    crane_sample out[401];
    size_t n = 0;

    check_status(crane_predict(&p, &s0, &in, R(2), R(5e-3), out, 401, &n, &work), CRANE_OK, "tilt flag run");
    check(out[n - 1].stop[0] == 1 && out[n - 1].stroke[0] == p.cylinder[0].stroke_max,
          "lift ends on stroke_max (+1)");
    check(out[n - 1].stop[1] == 1 && out[n - 1].stroke[1] == p.cylinder[1].stroke_max,
          "tilt ends on stroke_max, flagged +1 in cylinder terms");
    check(strokes_in_range(&p, out, n), "tilt flag run: strokes stay in range");
}

static void test_samples_equal_constant(void)
{
    const crane_params p = patu();
    const crane_state s0 = state(0.2, 0.4, 0, 0, 0.3, 0.2);
    crane_inputs in = constant_inputs(120e5, 10e5, CRANE_DRIVE_PRESSURE, 40e5, 50e5);
    crane_sample a[101], b[101], c[101];
    const crane_real t[4] = {R(-1), R(0.03), R(0.07), R(0.5)};
    const crane_real pa[4] = {R(120e5), R(120e5), R(120e5), R(120e5)};
    const crane_real pb[4] = {R(10e5), R(10e5), R(10e5), R(10e5)};
    const crane_real ramp_a[4] = {R(0), R(40e5), R(200e5), R(10e5)};
    size_t na, nb, nc;

    /* RK4's steps (knots on its grid): the same bits; the default's explicit pair cuts its steps
     * at the knots, so within its tolerance */
    in.solver.method = CRANE_METHOD_RK4;
    crane_predict(&p, &s0, &in, R(0.5), R(5e-3), a, 101, &na, &work);
    in.drive[0].n_samples = 4;
    in.drive[0].t = t;
    in.drive[0].p_a_samples = pa;
    in.drive[0].p_b_samples = pb;
    crane_predict(&p, &s0, &in, R(0.5), R(5e-3), b, 101, &nb, &work);
    check(na == nb && memcmp(a, b, na * sizeof a[0]) == 0,
          "constant pressure samples give the same prediction as constant pressures");
    in.solver.method = CRANE_METHOD_DEFAULT;
    check_status(crane_predict(&p, &s0, &in, R(0.5), R(5e-3), b, 101, &nb, &work), CRANE_OK,
                 "constant samples run by default");
    check(nb == na && fabs(D(b[nb - 1].tip[2]) - D(a[na - 1].tip[2])) < 1e-4,
          "constant pressure samples by default: within 0.1 mm of RK4's constant pressures");
    in.solver.method = CRANE_METHOD_RK4;
    in.drive[0].p_a_samples = ramp_a;
    check_status(crane_predict(&p, &s0, &in, R(0.5), R(5e-3), c, 101, &nc, &work), CRANE_OK, "ramp samples run");
    check(strokes_in_range(&p, c, nc) && D(c[nc - 1].tip[2]) != D(a[na - 1].tip[2]),
          "ramp samples change the prediction");
}

/* Absurd gravity (validated only as >= 0): the state overflows; the prediction stops with
 * CRANE_E_DIVERGED, the samples written before are finite and nothing is written past them. */
static void test_diverged(void)
{
    crane_params p = patu();
    const crane_state s0 = state(0.116, 0.32, 0, 0, 0, 0);
    const crane_inputs in = constant_inputs(175e5, 0, CRANE_DRIVE_PRESSURE, 30e5, 20e5);
    static crane_sample out[201], ref[201];
    crane_model m;
    size_t n = 12345, k, failed = 77;
    int ok = 1;

    p.gravity = R(is_float ? 1e30 : 1e135);
    memset(out, 0xa5, sizeof out);
    memcpy(ref, out, sizeof out);
    check_status(crane_predict(&p, &s0, &in, R(0.2), R(1e-3), out, 201, &n, &work), CRANE_E_DIVERGED,
                 "gravity 1e135: CRANE_E_DIVERGED");
    check(n < 201, "diverged: fewer samples than asked for");
    for (k = 0; k < n; ++k)
        if (!isfinite(D(out[k].t)) || !isfinite(D(out[k].tip[0])) || !isfinite(D(out[k].tip[2])) ||
            !isfinite(D(out[k].theta[0])) || !isfinite(D(out[k].omega[1])))
            ok = 0;
    check(ok, "diverged: the samples written are finite");
    check(n < 201 && memcmp(out + n, ref + n, (201 - n) * sizeof out[0]) == 0,
          "diverged: nothing written past n_written");
    check(crane_model_init(&m, &p, R(0)) == CRANE_OK &&
              crane_predict_model(&m, &s0, &in, R(0.2), R(1e-3), out, 201, &k, &work) == CRANE_E_DIVERGED &&
              k == n,
          "diverged: crane_predict_model the same");
    check_status(crane_predict_many(&p, 1, 1, &s0, &in, R(0.2), R(1e-3), 1, out, 201, &failed, &work),
                 CRANE_E_DIVERGED, "diverged: crane_predict_many");
    check(failed == 0, "diverged: crane_predict_many names the future");
    check(strlen(crane_status_message(CRANE_E_DIVERGED)) > 0, "diverged: a message");
    printf("  diverged after %lu samples\n", (unsigned long)n);
}

/* A crane per future (n_params = n_futures): each future equals crane_predict with its own
 * crane; a count that is neither 1 nor n_futures, or a bad crane of one future, is refused
 * before anything is written, naming that future. */
static void test_params_per_future(void)
{
    crane_params p[3];
    crane_state s[3];
    crane_inputs in[3];
    static crane_sample out[3 * 101], ref[101], blank[3 * 101];
    size_t n, failed, k;
    int same = 1;

    for (k = 0; k < 3; ++k) {
        p[k] = patu();
        p[k].load_mass = R(100.0 + 150.0 * (double)k);
        s[k] = state(0.116, 0.20, 0, 0, 0, 0);
        in[k] = constant_inputs(175e5, 0, CRANE_DRIVE_HOLD, 0, 0);
    }
    p[1].cylinder[CRANE_LIFT].friction.factor = R(2.0);
    check_status(crane_predict_many(p, 3, 3, s, in, R(0.1), R(1e-3), 1, out, 101, &failed, &work),
                 CRANE_OK, "a crane per future");
    for (k = 0; k < 3; ++k) {
        check_status(crane_predict(&p[k], &s[k], &in[k], R(0.1), R(1e-3), ref, 101, &n, &work), CRANE_OK,
                     "a crane per future: crane_predict");
        same = same && n == 101 && memcmp(out + k * 101, ref, sizeof ref) == 0;
    }
    check(same, "a crane per future: each future is crane_predict's with its crane");
    check(D(out[100].tip[2]) > D(out[2 * 101 + 100].tip[2]),
          "a crane per future: the lighter load rises higher");

    memset(out, 0x5a, sizeof out);
    memcpy(blank, out, sizeof out);
    check_status(crane_predict_many(p, 2, 3, s, in, R(0.1), R(1e-3), 1, out, 101, &failed, &work),
                 CRANE_E_PARAMS, "n_params neither 1 nor n_futures");
    check(failed == 3, "n_params: a shared argument");
    check_status(crane_predict_many(p, 0, 3, s, in, R(0.1), R(1e-3), 1, out, 101, &failed, &work),
                 CRANE_E_PARAMS, "n_params 0");
    p[2].load_mass = R(-1.0);
    check_status(crane_predict_many(p, 3, 3, s, in, R(0.1), R(1e-3), 1, out, 101, &failed, &work),
                 CRANE_E_BODY, "a bad crane of future 2");
    check(failed == 2, "a bad crane: its future is named");
    check(memcmp(out, blank, sizeof out) == 0, "a bad crane: nothing written");
    check(strlen(crane_status_message(CRANE_E_PARAMS)) > 0, "n_params: a message");
}

/* CRANE_TEST_BENCH_REPS sets the repetitions (default 2000; 0 skips it: emulators, valgrind). */
static void benchmark(void)
{
    const crane_params p = patu();
    const crane_state s0 = state(0.116, 0.32, 0, 0, 0, 0);
    const crane_inputs in = constant_inputs(100e5, 0, CRANE_DRIVE_PRESSURE, 30e5, 20e5);
    static crane_sample out[401];
    size_t n;
    const char *env = getenv("CRANE_TEST_BENCH_REPS");
    const int reps = env ? atoi(env) : 2000;
    int r;
    clock_t c0, c1;

    if (reps <= 0)
        return;
    c0 = clock();
    for (r = 0; r < reps; ++r)
        crane_predict(&p, &s0, &in, R(2), R(5e-3), out, 401, &n, &work);
    c1 = clock();
    printf("  benchmark: 2 s at dt 5 ms (both joints free): %.1f us per prediction\n",
           1e6 * (double)(c1 - c0) / CLOCKS_PER_SEC / reps);
}

/* ---- golden vectors: the twin's trajectories of the named scenarios (tools/golden.py) ---- */

enum { N_GOLDEN_MAX = 4001 };
static crane_sample golden_out[N_GOLDEN_MAX];

static double max_abs_diff(const double *want, const crane_real *got, int n, double worst)
{
    int i;
    for (i = 0; i < n; ++i)
        if (!(fabs(D(got[i]) - want[i]) <= worst))
            worst = fabs(D(got[i]) - want[i]);
    return worst;
}

/* Joint j's position [lift stroke, tilt stroke, slew, extension] of a golden sample and of a core
 * sample, and the end of its range on side (-1: start, +1: end), m or rad. */
static double golden_position(const golden_sample *s, int j)
{
    return j < 2 ? s->stroke[j] : j == 2 ? s->slew : s->extension;
}

static double sample_position(const crane_sample *s, int j)
{
    return D(j < 2 ? s->stroke[j] : j == 2 ? s->slew : s->extension);
}

static double range_end(const crane_params *p, int j, int side)
{
    if (j < 2)
        return D(side < 0 ? p->cylinder[j].stroke_min : p->cylinder[j].stroke_max);
    if (j == 2)
        return D(side < 0 ? p->slew_drive.slew_min : p->slew_drive.slew_max);
    return D(side < 0 ? p->extension_min : p->extension_max);
}

static long first_stop(const crane_sample *out, size_t n, int joint)
{
    size_t k;
    for (k = 0; k < n; ++k)
        if (out[k].stop[joint] != 0)
            return (long)k;
    return -1;
}

/* Every named scenario against the twin (the spec), in whatever build this is: the double and the
 * float build, the cross builds under qemu, the sanitizers. All four joints are compared: the
 * spatial scenarios (golden_scenario.spatial) move the slew and the extension, the others hold
 * them (their slew and extension must stay as given, their rates 0). The tolerances are per
 * precision (double: the C-vs-twin agreement of tests/test_c_vs_twin.py; float: single-precision
 * round-off through 2000-3000 RK4 steps, measured, with a margin of about 10). In float an
 * end-stop event may land a few steps from the twin's, so flags are compared away from the twin's
 * first stop only; and a joint resting on its stop with (almost) no net force may leave it in one
 * precision and not in the other, without moving: in float a flag that differs while the core's
 * and the twin's positions are both within float resolution (4 FLT_EPSILON, relative) of that
 * stop is counted and printed, not failed (slew-stop-load-out: the telescope, at extension_max
 * since t = 0, is released at 1.808 s as in double (1.809 s), but double lands on the stop again
 * at 1.855 s while float's increments v h ~ 1e-8 m stay below its resolution at 1 m, 6e-8 m, so it
 * hovers within one ulp of the stop, flag 0, to the end). */
static void test_golden_vectors(void)
{
    /* Tolerances per precision and per class: [0] pressure-driven or held, [1] valve-driven (the oil
     * spring makes the chamber pressures stiff, so float round-off shows most there); a scenario is
     * valve-driven if any of its four actuators is. Quantities: [0] strokes, extension and tip, m;
     * [1] angles and slew, rad; [2] angular velocities and slew rate, rad/s; [3] chamber pressures
     * of all four actuators, Pa; [4] extension rate, m/s.
     * Measured (gcc 12, x86-64, all 26 scenarios, 7 of them spatial): double 5.3e-15 m, 2.2e-15 rad,
     * 4.9e-15 rad/s, 1.2e-8 Pa, 2.2e-16 m/s; float [0] 3.9e-5 m, 8.8e-6 rad, 9.7e-6 rad/s, 0.5 Pa
     * (slew-folded, slew-stretched: 1.1e-6 m, 1.4e-6 rad, 1.4e-6 rad/s; no scenario of this class
     * moves the extension, held it is exact); float [1] 6.1e-5 m, 3.1e-5 rad, 1.3e-3 rad/s, 1.3e4 Pa
     * (0.13 bar of about 100; the spatial ones: 6.1e-5 m, 1.1e-5 rad, 1.5e-5 rad/s, 5.6e3 Pa, and
     * 7e-6 m/s of extension rate in slew-stop-load-out); first stops on the twin's sample. The float
     * tolerances keep a margin of about 10 (the extension rate's, new with the four joints: 14 over
     * the valve class's 7e-6 m/s; the pressure class has no moving extension to measure, so it
     * takes the same). */
    static const double tol_f[2][5] = {{5e-4, 2.5e-4, 2e-4, 200, 1e-4},
                                       {5e-4, 2.5e-4, 1.5e-2, 1.5e5, 1e-4}};
    static const double tol_d[5] = {1e-9, 1e-9, 1e-7, 1e-3, 1e-7};
    static const char *const what_class[2] = {"pressure-driven", "valve-driven"};
    static const char *const what_qty[5] = {"strokes, extension and tip", "angles and slew",
                                             "angular velocities and slew rate",
                                             "chamber pressures", "extension rate"};
    const double tol_t = tol(1e-12, 1e-6);
    const long slack = is_float ? 2 : 0;
    double worst[2][5] = {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}};
    double worst_spatial[5] = {0, 0, 0, 0, 0};
    long worst_stop_shift = 0;
    int i, c, q, flags_ok = 1, counts_ok = 1, times_ok = 1, n_spatial = 0, n_run = 0;
    /* float resolution at a stop, relative (see above); double: none excused */
    const double at_stop = is_float ? 4.0 * 1.1920928955078125e-07 : -1.0;

    for (i = 0; i < GOLDEN_N_SCENARIOS; ++i) {
        const golden_scenario *g = &golden_scenarios[i];
        double *w = worst[g->valves ? 1 : 0];
        double ws[5] = {0, 0, 0, 0, 0};
        crane_params p = patu();
        size_t n = 0, k;
        int j, n_on_stop = 0;
        char what[96];

#if defined(CRANE_HYDRAULICS) && !CRANE_HYDRAULICS
        if (g->valves) {
            printf("  (golden %s: valve-driven, not in this build)\n", g->name);
            continue;
        }
#endif
        p.load_mass = g->load_mass;
        snprintf(what, sizeof what, "golden %s: prediction runs", g->name);
        check_status(crane_predict(&p, &g->state, &g->inputs, g->horizon, R(GOLDEN_DT), golden_out,
                                   N_GOLDEN_MAX, &n, &work), CRANE_OK, what);
        if (n != g->n_samples) {
            printf("  (golden %s: %lu samples, the twin %lu)\n", g->name, (unsigned long)n,
                   (unsigned long)g->n_samples);
            counts_ok = 0;
            continue;
        }
        ++n_run;
        n_spatial += g->spatial ? 1 : 0;
        for (k = 0; k < g->n_golden; ++k) {
            const golden_sample *want = &g->golden[k];
            const size_t idx = k * GOLDEN_EVERY < n - 1 ? k * GOLDEN_EVERY : n - 1;
            const crane_sample *got = &golden_out[idx];
            if (!(fabs(D(got->t) - want->t) <= tol_t))
                times_ok = 0;
            ws[0] = max_abs_diff(want->stroke, got->stroke, 2, ws[0]);
            ws[0] = max_abs_diff(&want->extension, &got->extension, 1, ws[0]);
            ws[0] = max_abs_diff(want->tip, got->tip, 3, ws[0]);
            ws[1] = max_abs_diff(want->theta, got->theta, 2, ws[1]);
            ws[1] = max_abs_diff(&want->slew, &got->slew, 1, ws[1]);
            ws[2] = max_abs_diff(want->omega, got->omega, 2, ws[2]);
            ws[2] = max_abs_diff(&want->slew_rate, &got->slew_rate, 1, ws[2]);
            ws[3] = max_abs_diff(want->p_a, got->p_a, 4, ws[3]);
            ws[3] = max_abs_diff(want->p_b, got->p_b, 4, ws[3]);
            ws[4] = max_abs_diff(&want->extension_rate, &got->extension_rate, 1, ws[4]);
            for (j = 0; j < 4; ++j) {
                const long near = g->first_stop[j] < 0 ? slack + 1 : labs((long)idx - g->first_stop[j]);
                if (got->stop[j] != want->stop[j] && near > slack) {
                    const double end = range_end(&p, j, want->stop[j] != 0 ? want->stop[j] : got->stop[j]);
                    const double res = at_stop * (fabs(end) > 1 ? fabs(end) : 1);
                    if (fabs(sample_position(got, j) - end) <= res
                        && fabs(golden_position(want, j) - end) <= res) {
                        ++n_on_stop;
                    } else {
                        printf("  (golden %s: stop[%d] %d at sample %lu, the twin %d)\n", g->name, j,
                               got->stop[j], (unsigned long)idx, want->stop[j]);
                        flags_ok = 0;
                    }
                }
            }
        }
        if (n_on_stop > 0)
            printf("  (golden %s: %d golden samples with a stop flag other than the twin's, the joint "
                   "within float resolution of that stop in both)\n", g->name, n_on_stop);
        for (q = 0; q < 5; ++q) {
            if (!(ws[q] <= w[q]))
                w[q] = ws[q];
            if (g->spatial && !(ws[q] <= worst_spatial[q]))
                worst_spatial[q] = ws[q];
        }
        for (j = 0; j < 4; ++j) {
            const long got = first_stop(golden_out, n, j), want = g->first_stop[j];
            const long shift = (got < 0) != (want < 0) ? 1000000 : labs(got - want);
            if (shift > worst_stop_shift)
                worst_stop_shift = shift;
        }
    }
    for (c = 0; c < 2; ++c) {
        printf("  golden vectors, %s: max |diff| %.2g m, %.2g rad, %.2g rad/s, %.2g Pa, %.2g m/s\n",
               what_class[c], worst[c][0], worst[c][1], worst[c][2], worst[c][3], worst[c][4]);
        for (q = 0; q < 5; ++q) {
            char what[96];
            snprintf(what, sizeof what, "golden, %s: %s within tolerance of the twin", what_class[c],
                     what_qty[q]);
            check(worst[c][q] <= (is_float ? tol_f[c][q] : tol_d[q]), what);
        }
    }
    printf("  golden vectors, the %d spatial scenarios (slew, extension moving): max |diff| %.2g m, "
           "%.2g rad, %.2g rad/s, %.2g Pa, %.2g m/s\n", n_spatial, worst_spatial[0],
           worst_spatial[1], worst_spatial[2], worst_spatial[3], worst_spatial[4]);
    printf("  golden vectors (%d of %d scenarios run): first stops shifted by <= %ld samples\n",
           n_run, GOLDEN_N_SCENARIOS, worst_stop_shift);
    check(counts_ok, "golden: as many samples as the twin");
    check(times_ok, "golden: sample times are the twin's");
    check(worst_stop_shift <= slack, "golden: first end-stop samples are the twin's");
    check(flags_ok, "golden: stop flags are the twin's");
}

/* The estimator on a held crane: the model keeps the positions and the pressures and zeroes the
 * rates, so a diagonal covariance stays diagonal and a measured field is the scalar Kalman filter
 * worked by hand: P- = P + q T, g = P- / (P- + r), x+ = x + g (z - x), P+ = P- r / (P- + r). Then
 * bad arguments leave it untouched. The estimator is large: static, not on the stack. */
/* crane_work needs no initialisation and carries nothing from one call to the next (crane.h):
 * every golden scenario over its first 0.5 s, by the default method and by RK4, gives the same
 * bytes with a zeroed work, with a work whose every byte is 0xFF (NaN in every real, a wild
 * pointer in every pointer: a field read before the call writes it would show) and with the
 * work that the previous call, another scenario, left. */
static void test_work_carries_nothing(void)
{
    enum { N_WORK = 128 };
    static crane_sample fresh[N_WORK], other[N_WORK];
    static crane_work used; /* the previous call's */
    static const int methods[2] = {CRANE_METHOD_DEFAULT, CRANE_METHOD_RK4};
    int i, k, runs = 0, same = 1, ok = 1;

    for (k = 0; k < 2; ++k) {
        for (i = 0; i < GOLDEN_N_SCENARIOS; ++i) {
            const golden_scenario *g = &golden_scenarios[i];
            const crane_real horizon = g->horizon < R(0.5) ? g->horizon : R(0.5);
            crane_params p = patu();
            crane_inputs in = g->inputs;
            size_t n0 = 0, n1 = 0, n2 = 0;
            crane_status s0, s1, s2;

#if defined(CRANE_HYDRAULICS) && !CRANE_HYDRAULICS
            if (g->valves) {
                continue;
            }
#endif
            p.load_mass = g->load_mass;
            in.solver.method = methods[k];
            memset(fresh, 0, sizeof fresh);
            memset(other, 0, sizeof other);
            memset(&work, 0, sizeof work);
            s0 = crane_predict(&p, &g->state, &in, horizon, R(5e-3), fresh, N_WORK, &n0, &work);
            memset(&work, 0xFF, sizeof work);
            s1 = crane_predict(&p, &g->state, &in, horizon, R(5e-3), other, N_WORK, &n1, &work);
            same = same && s1 == s0 && n1 == n0 && memcmp(fresh, other, sizeof fresh) == 0;
            memset(other, 0, sizeof other);
            s2 = crane_predict(&p, &g->state, &in, horizon, R(5e-3), other, N_WORK, &n2, &used);
            same = same && s2 == s0 && n2 == n0 && memcmp(fresh, other, sizeof fresh) == 0;
            ok = ok && s0 == CRANE_OK && n0 > 1;
            ++runs;
        }
    }
    check(ok && runs > 0, "work: every scenario predicts");
    check(same, "work: the same bytes from a zeroed, an all-ones and a used crane_work");
    printf("  work: %d predictions, each with a zeroed, an all-ones and a used crane_work\n", runs);
}

static void test_estimator(void)
{
    static crane_estimator est, before;
    crane_estimator_config c;
    crane_model m;
    crane_inputs held;
    const crane_params p = patu();
    crane_real x0[CRANE_EST_N], cov[CRANE_EST_N * CRANE_EST_N], z[CRANE_EST_N], var[CRANE_EST_N];
    const crane_real spool[4] = {0, 0, 0, 0};
    const double p0 = 1e-6, q = 1e-8, r = 4e-8, period = 0.01, dz = 2e-4;
    double pm, g;
    int i;

    memset(&c, 0, sizeof c);
    memset(&held, 0, sizeof held);
    memset(cov, 0, sizeof cov);
    for (i = 0; i < CRANE_EST_N; ++i) {
        c.lo[i] = R(-1e8);
        c.hi[i] = R(1e8);
        c.noise[i] = R(q);
        c.fd_step[i] = i < CRANE_EST_PRESSURES ? R(1e-4) : R(1e3);
        c.scale[i] = i < CRANE_EST_PRESSURES ? R(1e-3) : R(1e5);
        x0[i] = 0;
        z[i] = 0;
        var[i] = 0;
        cov[i * CRANE_EST_N + i] = i < CRANE_EST_PRESSURES ? R(p0) : R(1e10);
    }
    c.lo[0] = p.cylinder[CRANE_LIFT].stroke_min;
    c.hi[0] = p.cylinder[CRANE_LIFT].stroke_max;
    c.lo[1] = p.cylinder[CRANE_TILT].stroke_min;
    c.hi[1] = p.cylinder[CRANE_TILT].stroke_max;
    c.lo[3] = p.extension_min;
    c.hi[3] = p.extension_max;
    c.dt = R(0.005);
    x0[0] = R(0.15);
    x0[1] = R(0.3);
    x0[3] = p.extension_min;
    check_status(crane_model_init(&m, &p, x0[3]), CRANE_OK, "estimator: model");
    check_status(crane_estimator_init(&est, &c, x0, cov, spool), CRANE_OK, "estimator: init");
    z[0] = R(0.15 + dz);
    var[0] = R(r);
    check_status(crane_estimator_update(&est, &m, &held, R(period), z, var), CRANE_OK,
                 "estimator: update");
    pm = p0 + q * period;
    g = pm / (pm + r);
    check_close(D(est.x[0]), 0.15 + g * dz, tol(1e-12, 1e-6), "estimator: x+ = x + g (z - x)");
    check_close(D(est.covariance[0]), pm * r / (pm + r), pm * tol(1e-9, 1e-4),
                "estimator: P+ = P- r / (P- + r)");
    check_close(D(est.covariance[1]), 0, pm * tol(1e-9, 1e-4), "estimator: P stays diagonal");
    check_close(D(est.x[1]), 0.3, tol(1e-12, 1e-6), "estimator: an unmeasured position stays");
    check_close(D(est.nis), dz * dz / (pm + r), dz * dz / (pm + r) * tol(1e-9, 1e-3),
                "estimator: NIS");
    before = est;
    var[1] = R(-1);
    check_status(crane_estimator_update(&est, &m, &held, R(period), z, var), CRANE_E_ESTIMATOR,
                 "estimator: negative variance");
    var[1] = 0;
    check_status(crane_estimator_update(&est, &m, &held, 0, z, var), CRANE_E_HORIZON,
                 "estimator: period 0");
    check_status(crane_estimator_update(&est, NULL, &held, R(period), z, var), CRANE_E_NULL,
                 "estimator: NULL model");
    check(memcmp(&est, &before, sizeof est) == 0, "estimator: untouched by bad arguments");
    c.dt = 0;
    check_status(crane_estimator_init(&est, &c, x0, cov, spool), CRANE_E_ESTIMATOR,
                 "estimator: dt 0");
    check(memcmp(&est, &before, sizeof est) == 0, "estimator: untouched by a bad config");
}

int main(void)
{
    printf("cranepredict core tests (%s)\n", is_float ? "float" : "double");
    test_sincosf();
    test_model_init();
    test_round_trips();
    test_transmission();
    test_points();
    test_bad_params();
    test_bad_small_calls();
    test_bad_predict();
    test_inverse_dynamics_lagrange();
    test_kernels_agree();
    test_energy();
    test_paper_scenario();
    test_step();
    test_golden_vectors();
    test_stops_and_release();
    test_tilt_flag();
    test_samples_equal_constant();
    test_diverged();
    test_params_per_future();
    test_work_carries_nothing();
    test_estimator();
    benchmark();
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail ? 1 : 0;
}
