/* SPDX-License-Identifier: MIT */
/*
 * C tests of the collision guard (geometry.c, guard.c) in the precision of the build (double or
 * float): distances with answers derived on paper, bad solids and buffers (nothing written), and
 * a guarded prediction whose first contact is checked against the clearance at every sample.
 * The thorough checks (coal oracle, brute force) are in tests/test_guard*.py; these make the
 * float, sanitizer, valgrind and cross builds run the guard too.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "crane.h"
#include "crane_patu655.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work prediction_work;

static int failures;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            printf("FAIL %s:%d: %s\n", __FILE__, __LINE__, #cond);                   \
            failures++;                                                              \
        }                                                                            \
    } while (0)

static const double EPS = sizeof(crane_real) < sizeof(double) ? 1e-5 : 1e-12;

static crane_solid capsule(double ax, double ay, double az, double bx, double by, double bz,
                           double r)
{
    crane_solid s;
    memset(&s, 0, sizeof s);
    s.kind = CRANE_SOLID_CAPSULE;
    s.a[0] = (crane_real)ax;
    s.a[1] = (crane_real)ay;
    s.a[2] = (crane_real)az;
    s.b[0] = (crane_real)bx;
    s.b[1] = (crane_real)by;
    s.b[2] = (crane_real)bz;
    s.radius = (crane_real)r;
    return s;
}

static crane_solid box(double cx, double cy, double cz, double yaw, double h)
{
    crane_solid s;
    const double c = cos(yaw), sn = sin(yaw);
    memset(&s, 0, sizeof s);
    s.kind = CRANE_SOLID_BOX;
    s.a[0] = (crane_real)cx;
    s.a[1] = (crane_real)cy;
    s.a[2] = (crane_real)cz;
    s.axes[0] = (crane_real)c;
    s.axes[1] = (crane_real)sn;
    s.axes[3] = (crane_real)-sn;
    s.axes[4] = (crane_real)c;
    s.axes[8] = 1;
    s.half[0] = s.half[1] = s.half[2] = (crane_real)h;
    return s;
}

static crane_solid ground(double z)
{
    crane_solid s;
    memset(&s, 0, sizeof s);
    s.kind = CRANE_SOLID_PLANE;
    s.a[2] = (crane_real)z;
    s.b[2] = 1;
    return s;
}

static double dist(const crane_solid *a, const crane_solid *b)
{
    crane_real d = -1, pa[3], pb[3];
    CHECK(crane_solid_distance(a, b, &d, pa, pb) == CRANE_OK);
    return (double)d;
}

static void test_paper_distances(void)
{
    /* a rod past a unit box's edge x = 1.5, y = 0.5: |1.5 - 0.5| / sqrt 2 */
    const crane_solid rod = capsule(0, 0, 0, 2, 2, 0, 0), cube = box(2, 0, 0, 0, 0.5);
    const crane_solid a = capsule(0, 0, 0, 0, 0, 2, 0.1), b = capsule(0.5, 0, 1, 0.5, 0, 3, 0.15);
    const crane_solid turned = box(0, 0, 2, atan(1.0), 0.5), floor0 = ground(0);
    const crane_solid inside = capsule(1.9, 0, 0, 2.1, 0, 0, 0.01);
    CHECK(fabs(dist(&rod, &cube) - 1 / sqrt(2.0)) < EPS);
    CHECK(fabs(dist(&a, &b) - 0.25) < EPS);
    CHECK(fabs(dist(&turned, &floor0) - 1.5) < EPS);
    CHECK(dist(&inside, &cube) == 0);
}

static void test_bad_input_writes_nothing(void)
{
    crane_solid bad = box(0, 0, 0, 0, 0.5), good = capsule(0, 0, 0, 1, 0, 0, 0.1);
    crane_real d = 7, pa[3] = {7, 7, 7}, pb[3] = {7, 7, 7};
    int field = 0;
    bad.half[1] = 0;
    CHECK(crane_solid_check(&bad, &field) == CRANE_E_SOLID && field == CRANE_GUARD_FIELD_HALF);
    CHECK(crane_solid_distance(&good, &bad, &d, pa, pb) == CRANE_E_SOLID);
    CHECK(d == 7 && pa[0] == 7 && pb[2] == 7);
    bad = good;
    bad.a[1] = (crane_real)NAN;
    CHECK(crane_solid_check(&bad, &field) == CRANE_E_SOLID && field == CRANE_GUARD_FIELD_A);
    bad = ground(0);
    CHECK(crane_solid_distance(&bad, &bad, &d, pa, pb) == CRANE_E_SOLID && d == 7);
    CHECK(crane_solid_distance(NULL, &good, &d, pa, pb) == CRANE_E_NULL);
}

/* The paper's scenario (lift 175 bar, tilt held) against a power-line conductor. */
static crane_sample samples[1001];

static void test_guarded_prediction(void)
{
    static const crane_params params = CRANE_PATU655_INIT;
    crane_model model;
    crane_state st;
    crane_inputs in;
    crane_part parts[2];
    crane_solid obstacles[2];
    crane_guard_config cfg;
    crane_guard_result res;
    crane_real clearance[2] = {77, 77}, work[2 * (2 + CRANE_GUARD_PART_WORK)];
    size_t n = 0, k;

    memset(&st, 0, sizeof st);
    memset(&in, 0, sizeof in);
    memset(parts, 0, sizeof parts);
    st.stroke[CRANE_LIFT] = (crane_real)0.116;
    st.stroke[CRANE_TILT] = (crane_real)0.20;
    in.drive[CRANE_LIFT].mode = CRANE_DRIVE_PRESSURE;
    in.drive[CRANE_LIFT].p_a = (crane_real)175e5;
    in.drive[CRANE_TILT].mode = CRANE_DRIVE_HOLD;
    CHECK(crane_model_init(&model, &params, 0) == CRANE_OK);
    CHECK(crane_predict_model(&model, &st, &in, 2, (crane_real)0.002, samples, 1001, &n, &prediction_work) == CRANE_OK);
    CHECK(n == 1001);

    /* the pillar (base to lift pivot, boom plane) and the extension boom's outer part */
    parts[0].kind = CRANE_SOLID_CAPSULE;
    parts[0].a.frame = parts[0].b.frame = CRANE_FRAME_BASE;
    parts[0].b.at = params.lift_pivot;
    parts[0].radius = (crane_real)0.2;
    parts[1].kind = CRANE_SOLID_CAPSULE;
    parts[1].a.frame = parts[1].b.frame = CRANE_FRAME_EXTENSION;
    parts[1].a.at.x = (crane_real)1.6;
    parts[1].b.at.x = params.tip_distance;
    parts[1].radius = (crane_real)0.09;
    obstacles[0] = ground(-1.5);
    obstacles[1] = capsule(3.3, -30, 6, 3.3, 30, 6, 0.015);
    cfg.margin = 1;
    cfg.reaction = (crane_real)0.2;
    cfg.cycle = (crane_real)0.01;
    cfg.time_tolerance = (crane_real)1e-4;
    cfg.clearance_tolerance = 0;

    /* a buffer too small: nothing written */
    memset(&res, 0x5a, sizeof res);
    CHECK(crane_guard(&model, parts, 2, obstacles, 2, samples, n, &cfg, clearance, work,
                      sizeof work / sizeof work[0] - 1, &res) == CRANE_E_CAPACITY);
    CHECK(clearance[0] == 77 && res.signal == 0x5a5a5a5a);
    cfg.cycle = 0;
    CHECK(crane_guard(&model, parts, 2, obstacles, 2, samples, n, &cfg, clearance, work,
                      sizeof work / sizeof work[0], &res) == CRANE_E_GUARD);
    cfg.cycle = (crane_real)0.01;

    CHECK(crane_guard(&model, parts, 2, obstacles, 2, samples, n, &cfg, clearance, work,
                      sizeof work / sizeof work[0], &res) == CRANE_OK);
    /* the pillar stands 1.5 m over the ground, radius 0.2: 1.3 m, and never moves */
    CHECK(fabs((double)clearance[0] - 1.3) < EPS);
    CHECK(res.contact == 1 && res.at_start == 0 && res.part == 1 && res.obstacle == 1);
    CHECK(res.t > (crane_real)0.7 && res.t < (crane_real)0.8);
    CHECK(fabs((double)(res.stop_latest - (res.t - cfg.reaction))) < EPS);
    CHECK(res.signal == CRANE_WARN);
    CHECK(res.approach[CRANE_LIFT] < 0 && res.approach[CRANE_TILT] == 0);
    CHECK(res.approach[CRANE_SLEW] == 0 && res.approach[CRANE_EXTENSION] == 0);
    /* every sample before the contact is clear of the margin, the first after it is not far off */
    for (k = 0; k < n && samples[k].t < res.t; ++k) {
        crane_solid posed[2];
        CHECK(crane_part_solids(&model, parts, 2, 0, 0, samples[k].theta, posed) == CRANE_OK);
        CHECK(dist(&posed[1], &obstacles[1]) > 1.0);
    }
    printf("guard: contact at t = %.4f s, stop by %.4f s, %lu distances\n", (double)res.t,
           (double)res.stop_latest, (unsigned long)res.evaluations);
}

/* The load (a sphere r = 0.3 m hanging 0.6 m below the tip) moved by the slew alone or by the
 * telescope alone, in hand-made samples 0.5 s apart (constant rates: the Hermite motion is the
 * exact one), toward a ball (r = 0.25 m) that no sample comes within the margin (0.1 m) of: the
 * contact lies between two samples, at the time derived on paper. */
static crane_sample hand[5];

static void guard_load_vs_ball(const crane_model *model, const crane_part *load, size_t n,
                               const crane_solid *ball, crane_guard_result *res)
{
    crane_guard_config cfg;
    crane_real clearance[1], work[1 + CRANE_GUARD_PART_WORK];
    size_t k;
    cfg.margin = (crane_real)0.1;
    cfg.reaction = (crane_real)0.2;
    cfg.cycle = (crane_real)0.01;
    cfg.time_tolerance = (crane_real)1e-4;
    cfg.clearance_tolerance = 0;
    for (k = 0; k < n; ++k) {
        crane_solid posed;
        CHECK(crane_part_solids(model, load, 1, hand[k].slew, hand[k].extension, hand[k].theta,
                                &posed) == CRANE_OK);
        CHECK(dist(&posed, ball) > 0.1); /* the contact is only between samples */
    }
    CHECK(crane_guard(model, load, 1, ball, 1, hand, n, &cfg, clearance, work,
                      sizeof work / sizeof work[0], res) == CRANE_OK);
    CHECK(res->contact == 1 && res->at_start == 0);
}

static void test_slew_and_telescope_alone(void)
{
    static const crane_params params = CRANE_PATU655_INIT;
    /* 5 x the time tolerance used, 1e-3 of the samples' 0.5-s spacing (above the asked 1e-4 s):
     * the advancement stops early, never late */
    const double tol = 5 * 1e-3 * 0.5;
    crane_model model;
    crane_part load;
    crane_solid at0, ball;
    crane_guard_result res;
    crane_real theta[2], ds;
    double rho, beta = 1.0, w = 0.8, t_star, u[3], len, lateral[3], big_l = 0.75, side = 0.62;
    size_t k;
    int i;

    CHECK(crane_model_init(&model, &params, 0) == CRANE_OK);
    CHECK(crane_joint_angle(&model, CRANE_LIFT, (crane_real)0.3, &theta[0], &ds) == CRANE_OK);
    CHECK(crane_joint_angle(&model, CRANE_TILT, (crane_real)0.2, &theta[1], &ds) == CRANE_OK);
    memset(&load, 0, sizeof load);
    load.kind = CRANE_SOLID_SPHERE;
    load.a.frame = CRANE_FRAME_EXTENSION;
    load.a.at.x = params.tip_distance;
    load.radius = (crane_real)0.3;
    load.drop = (crane_real)0.6;
    memset(hand, 0, sizeof hand);
    for (k = 0; k < 5; ++k) {
        hand[k].t = (crane_real)(0.5 * (double)k);
        hand[k].theta[0] = theta[0];
        hand[k].theta[1] = theta[1];
    }

    /* Slewing at w with the boom held: the load's centre circles the slew axis at its horizontal
     * distance rho; a ball at the same height and distance, beta ahead, is at the chord
     * 2 rho sin((beta - w t) / 2), so the clearance reaches the margin at
     * t* = (beta - 2 asin((0.1 + 0.3 + 0.25) / (2 rho))) / w. */
    CHECK(crane_part_solids(&model, &load, 1, 0, 0, theta, &at0) == CRANE_OK);
    rho = (double)at0.a[0];
    CHECK(rho > 3 && fabs((double)at0.a[1]) < EPS);
    memset(&ball, 0, sizeof ball);
    ball.kind = CRANE_SOLID_SPHERE;
    ball.radius = (crane_real)0.25;
    ball.a[0] = (crane_real)(rho * cos(beta));
    ball.a[1] = (crane_real)(rho * sin(beta));
    ball.a[2] = at0.a[2];
    for (k = 0; k < 5; ++k) {
        hand[k].slew = (crane_real)(w * (double)hand[k].t);
        hand[k].slew_rate = (crane_real)w;
    }
    guard_load_vs_ball(&model, &load, 5, &ball, &res);
    t_star = (beta - 2 * asin(0.65 / (2 * rho))) / w;
    CHECK((double)res.t <= t_star + 1e-6 && (double)res.t > t_star - tol);
    CHECK(fabs((double)res.slew - w * (double)res.t) < EPS * 10);
    CHECK(res.approach[CRANE_SLEW] < 0 && res.gradient[CRANE_SLEW] < 0);
    CHECK(res.approach[CRANE_LIFT] == 0 && res.approach[CRANE_EXTENSION] == 0);
    printf("guard, slew alone: contact at %.5f s, on paper %.5f s\n", (double)res.t, t_star);

    /* Telescoping at 1 m/s with slew 0.3 held: the load moves along the outer boom's axis u; a
     * ball L = 0.75 m ahead along u and D = 0.62 m aside (horizontal, across the boom plane) is at
     * sqrt((L - e)^2 + D^2), the margin reached at e* = L - sqrt(0.65^2 - D^2) = t* x 1 m/s. */
    for (k = 0; k < 5; ++k) {
        hand[k].slew = (crane_real)0.3;
        hand[k].slew_rate = 0;
        hand[k].extension = (crane_real)(double)hand[k].t;
        hand[k].extension_rate = 1;
    }
    CHECK(crane_part_solids(&model, &load, 1, (crane_real)0.3, 0, theta, &at0) == CRANE_OK);
    CHECK(crane_part_solids(&model, &load, 1, (crane_real)0.3, 1, theta, &ball) == CRANE_OK);
    for (i = 0, len = 0; i < 3; ++i) {
        u[i] = (double)(ball.a[i] - at0.a[i]);
        len += u[i] * u[i];
    }
    CHECK(fabs(len - 1) < EPS * 10); /* one metre of extension moves the load one metre */
    lateral[0] = -sin(0.3);
    lateral[1] = cos(0.3);
    lateral[2] = 0;
    memset(&ball, 0, sizeof ball);
    ball.kind = CRANE_SOLID_SPHERE;
    ball.radius = (crane_real)0.25;
    for (i = 0; i < 3; ++i)
        ball.a[i] = (crane_real)((double)at0.a[i] + big_l * u[i] + side * lateral[i]);
    guard_load_vs_ball(&model, &load, 3, &ball, &res);
    t_star = big_l - sqrt(0.65 * 0.65 - side * side);
    CHECK((double)res.t <= t_star + 1e-6 && (double)res.t > t_star - tol);
    CHECK(fabs((double)res.extension - (double)res.t) < EPS * 10);
    CHECK(res.approach[CRANE_EXTENSION] < 0 && res.gradient[CRANE_EXTENSION] < 0);
    CHECK(res.approach[CRANE_SLEW] == 0 && res.approach[CRANE_LIFT] == 0);
    printf("guard, telescope alone: contact at %.5f s, on paper %.5f s\n", (double)res.t, t_star);

    /* a sample beyond the telescope's range, a slew rate that is not finite: nothing written */
    {
        crane_guard_config cfg;
        crane_real clearance[1] = {77}, work[1 + CRANE_GUARD_PART_WORK];
        memset(&cfg, 0, sizeof cfg);
        cfg.cycle = (crane_real)0.01;
        cfg.time_tolerance = (crane_real)1e-4;
        memset(&res, 0x5a, sizeof res);
        hand[1].extension = params.extension_max + (crane_real)0.01;
        CHECK(crane_guard(&model, &load, 1, &ball, 1, hand, 3, &cfg, clearance, work,
                          sizeof work / sizeof work[0], &res) == CRANE_E_EXTENSION);
        hand[1].extension = (crane_real)0.5;
        hand[1].slew_rate = (crane_real)NAN;
        CHECK(crane_guard(&model, &load, 1, &ball, 1, hand, 3, &cfg, clearance, work,
                          sizeof work / sizeof work[0], &res) == CRANE_E_NONFINITE);
        CHECK(clearance[0] == 77 && res.signal == 0x5a5a5a5a);
        CHECK(crane_part_solids(&model, &load, 1, 0, params.extension_max + 1, theta, &at0) ==
              CRANE_E_EXTENSION);
    }
}

int main(void)
{
    test_paper_distances();
    test_bad_input_writes_nothing();
    test_guarded_prediction();
    test_slew_and_telescope_alone();
    if (failures) {
        printf("test_guard: %d failures\n", failures);
        return 1;
    }
    printf("test_guard: all passed\n");
    return 0;
}
