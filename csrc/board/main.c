/* SPDX-License-Identifier: MIT */
/*
 * The cranepredict core on a Cortex-M4F without an OS (Arm MPS2 AN386, as QEMU's mps2-an386
 * models it). The crane is compiled in from the generated header crane_patu655.h (const: in
 * flash; each scenario's copy with its load is in RAM), the scenarios from example/crane_scenarios.h (tools/golden.py). For each scenario of scenarios.c it prints every sample over semihosting, the timer
 * ticks of the crane_predict call, and the stack that call used; then it calls every other entry
 * point once with its stack measured the same way. The host checks the output
 * (csrc/board/board_check.py): samples against the host float build, instructions, stack
 * against tools/footprint.py.
 *
 * Instructions: QEMU's -icount shift=0 advances the virtual clock by exactly 1 ns per executed
 * instruction, and the CMSDK APB timer 0 counts down at the 25 MHz system clock of that virtual
 * time. The timer is calibrated here against a loop of known length, so the host can turn ticks
 * into instructions (and notice when -icount is off). On a real board build with -DBOARD_DWT:
 * the clock is then the DWT cycle counter and the ticks are CPU cycles (QEMU does not model the
 * DWT: it reads 0 there).
 *
 * Stack: everything below the caller's stack pointer is painted with a pattern just before the
 * call, and the lowest word that no longer holds it after the call is the call's depth.
 *
 * Exit status 0 if every call returned what it should, 1 otherwise.
 */
#include <stdint.h>
#include <string.h>
#include "crane.h"
#include "scenarios.h"
#include "semihost.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work prediction_work;

#define PAINT 0xC5A3C5A3u
#define CALIBRATION_LOOPS 1000000u /* two instructions each */

extern uint32_t __stack_limit[];

static crane_params crane; /* the scenario's: crane_patu655.h with its load (board_crane) */
enum { CAPACITY = 2001 };           /* the largest scenario: 2 s at 1 ms */
static crane_sample out[CAPACITY];  /* 48 B a sample in float: static memory, not the stack */

#ifdef BOARD_PROFILE
/* The profile build (board_profile.py): one prediction of scenario BOARD_PROFILE_SCENARIO (an
 * index into scenarios.c's list), nothing else, so that QEMU's execution log stays small; sampled
 * every BOARD_PROFILE_DT s if that is defined (make profile PROFILE_DT=...), else at the
 * scenario's dt. */
#ifndef BOARD_PROFILE_SCENARIO
#define BOARD_PROFILE_SCENARIO 0
#endif
int main(void)
{
    size_t n_sc, n = 0;
    const board_scenario *sc = board_scenarios(&n_sc) + BOARD_PROFILE_SCENARIO;
#ifdef BOARD_PROFILE_DT
    const crane_real dt = (crane_real)BOARD_PROFILE_DT;
#else
    const crane_real dt = sc->dt;
#endif

    board_crane(sc, &crane);
    return crane_predict(&crane, &sc->state0, &sc->inputs, sc->horizon, dt, out, CAPACITY,
                         &n, &prediction_work) == CRANE_OK ? 0 : 1;
}
#else

#ifdef BOARD_DWT
/* ARMv7-M debug: DEMCR.TRCENA powers the DWT, DWT_CTRL.CYCCNTENA starts its cycle counter. */
#define DEMCR (*(volatile uint32_t *)0xE000EDFCu)
#define DWT_CTRL (*(volatile uint32_t *)0xE0001000u)
#define DWT_CYCCNT (*(volatile uint32_t *)0xE0001004u)
static void clock_start(void)
{
    DEMCR |= 1u << 24;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= 1u;
}
static inline uint32_t clock_now(void)
{
    return DWT_CYCCNT;
}
#else
/* CMSDK APB timer 0 of the MPS2 (AN386 application note): a 32-bit down counter at 25 MHz. */
#define TIMER0_CTRL (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)
static void clock_start(void)
{
    TIMER0_RELOAD = 0xFFFFFFFFu;
    TIMER0_VALUE = 0xFFFFFFFFu;
    TIMER0_CTRL = 1u;
}
/* Complemented, so that it counts up like the DWT's. */
static inline uint32_t clock_now(void)
{
    return ~TIMER0_VALUE;
}
#endif

static crane_sample out2[CAPACITY]; /* crane_predict_model's, to compare with crane_predict's */
static char line[BOARD_LINE_MAX];
static int failures;

static inline uint32_t stack_pointer(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp)::"memory");
    return sp;
}

/* Paints [__stack_limit, caller's sp). Naked and stackless, so that nothing of the pattern
 * below the caller is overwritten before the measured call. */
__attribute__((naked, noinline)) static void paint_below_sp(uint32_t *limit)
{
    __asm__ volatile("    ldr r1, =0xC5A3C5A3\n"
                     "    mov r2, sp\n"
                     "1:  cmp r0, r2\n"
                     "    bhs 2f\n"
                     "    str r1, [r0], #4\n"
                     "    b 1b\n"
                     "2:  bx lr\n");
    (void)limit;
}

/* Bytes between sp0 and the lowest word that lost the pattern. */
static inline uint32_t stack_used(uint32_t sp0)
{
    const volatile uint32_t *p = __stack_limit;

    while (*p == PAINT)
        ++p;
    return sp0 - (uint32_t)(uintptr_t)p;
}

/* The painting's own test: a frame of at least PROBE_BYTES that it must see. */
enum { PROBE_BYTES = 256 };
__attribute__((noinline)) static uint8_t stack_probe(void)
{
    volatile uint8_t buf[PROBE_BYTES];
    size_t i;

    for (i = 0; i < PROBE_BYTES; ++i)
        buf[i] = (uint8_t)i;
    return buf[0];
}

static void spin(uint32_t n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n)::"cc");
}

/* One output line: "KEY NAME VALUE" (or "KEY VALUE" when name is NULL). */
static void report(const char *key, const char *name, unsigned long v)
{
    char *p = board_put_str(line, key);

    if (name != NULL) {
        p = board_put_str(p, " ");
        p = board_put_str(p, name);
    }
    p = board_put_str(p, " ");
    p = board_put_u32(p, v);
    (void)board_put_str(p, "\n");
    semihost_write(line);
}

/* A call that did not do what it should: "error WHAT VALUE", and the exit status becomes 1. */
static void fail(const char *what, unsigned long value)
{
    report("error", what, value);
    ++failures;
}

static void expect(crane_status st, crane_status want, const char *what)
{
    if (st != want)
        fail(what, (unsigned long)st);
}

/* Runs CALL with the stack painted below this function's frame; prints the depth and the timer
 * ticks of the call under NAME. A macro so that the call is made from the frame whose stack
 * pointer is read. */
#define MEASURED(name, call)                                                                       \
    do {                                                                                           \
        uint32_t sp0_ = stack_pointer(), t0_, t1_;                                                 \
        paint_below_sp(__stack_limit);                                                             \
        t0_ = clock_now();                                                                         \
        call;                                                                                      \
        t1_ = clock_now();                                                                         \
        report("stack", (name), (unsigned long)stack_used(sp0_));                                  \
        report("ticks", (name), (unsigned long)(t1_ - t0_));                                       \
    } while (0)

static void run_scenario(const board_scenario *sc)
{
    crane_status st = CRANE_OK;
    size_t n = 0, count = 0, k;

    board_crane(sc, &crane);
    expect(crane_sample_count(sc->horizon, sc->dt, &count), CRANE_OK, "crane_sample_count");
    report("scenario", sc->name, (unsigned long)count);
    MEASURED("crane_predict", st = crane_predict(&crane, &sc->state0, &sc->inputs, sc->horizon,
                                                 sc->dt, out, CAPACITY, &n, &prediction_work));
    expect(st, CRANE_OK, sc->name);
    if (n != count)
        fail("sample_count", (unsigned long)n);
    report("samples", sc->name, (unsigned long)n);
    for (k = 0; k < n; ++k) {
        board_format_sample(line, sc->name, k, &out[k]);
        semihost_write(line);
    }
}

/* The collision guard's entry points, with the stack measured, on the paper prediction in
 * samples[0..n). The parts and obstacles are the harness's own, not a crane file's shape: two
 * capsules along the lift and outer booms and a load sphere, against a ceiling (a plane 5 m up,
 * which the rising tip reaches) and a wall (a box). */
static void run_guard(const crane_model *model, const crane_sample *samples, size_t n)
{
    static const crane_part parts[3] = {
        {.kind = CRANE_SOLID_CAPSULE, .a = {CRANE_FRAME_LIFT, {0, 0}},
         .b = {CRANE_FRAME_LIFT, {(crane_real)2.9, 0}}, .radius = (crane_real)0.12},
        {.kind = CRANE_SOLID_CAPSULE, .a = {CRANE_FRAME_OUTER, {0, 0}},
         .b = {CRANE_FRAME_OUTER, {(crane_real)2.0, 0}}, .radius = (crane_real)0.1},
        {.kind = CRANE_SOLID_SPHERE, .a = {CRANE_FRAME_OUTER, {(crane_real)2.0, 0}},
         .radius = (crane_real)0.25, .drop = (crane_real)0.4},
    };
    static const crane_solid obstacles[2] = {
        {.kind = CRANE_SOLID_PLANE, .a = {0, 0, 5}, .b = {0, 0, -1}},
        {.kind = CRANE_SOLID_BOX, .a = {(crane_real)5.5, 0, 2}, .axes = {1, 0, 0, 0, 1, 0, 0, 0, 1},
         .half = {(crane_real)0.25, 2, 2}},
    };
    static const crane_guard_config config = {
        .margin = (crane_real)0.1, .reaction = (crane_real)0.2, .cycle = (crane_real)0.01,
        .time_tolerance = (crane_real)1e-3, .clearance_tolerance = (crane_real)1e-3};
    static crane_solid posed[3];
    static crane_real clearance[3], work[3 * (2 + CRANE_GUARD_PART_WORK)];
    static crane_guard_result result;
    const crane_real theta[2] = {samples[0].theta[0], samples[0].theta[1]};
    crane_real d = 0, on_a[3], on_b[3];
    size_t which = 0;
    int field = 0;
    crane_status st = CRANE_OK;

    MEASURED("crane_solid_check", st = crane_solid_check(&obstacles[1], &field));
    expect(st, CRANE_OK, "crane_solid_check");
    MEASURED("crane_guard_check", st = crane_guard_check(parts, 3, obstacles, 2, &which, &field));
    expect(st, CRANE_OK, "crane_guard_check");
    MEASURED("crane_part_solids", st = crane_part_solids(model, parts, 3, 0, 0, theta, posed));
    expect(st, CRANE_OK, "crane_part_solids");
    MEASURED("crane_solid_distance",
             st = crane_solid_distance(&obstacles[1], &posed[0], &d, on_a, on_b));
    expect(st, CRANE_OK, "crane_solid_distance");
    MEASURED("crane_guard", st = crane_guard(model, parts, 3, obstacles, 2, samples, n, &config,
                                             clearance, work, sizeof work / sizeof work[0],
                                             &result));
    expect(st, CRANE_OK, "crane_guard");
    /* The rising tip must reach the ceiling: a guard that saw nothing would not test much. */
    if (!result.contact || result.obstacle != 0)
        fail("crane_guard_contact", (unsigned long)result.contact);
    report("guard_signal", NULL, (unsigned long)result.signal);
    report("guard_evaluations", NULL, (unsigned long)result.evaluations);
}

/* Every other entry point once, with the stack measured; values from the paper scenario. */
static void run_entry_points(const board_scenario *sc)
{
    static crane_model model;
    static crane_state states[2];
    static crane_inputs inputs[2];
    static crane_real xyz[2 * CRANE_N_POINTS * 3];
    crane_real theta[4] = {(crane_real)0.1, (crane_real)-0.6, (crane_real)0.2, (crane_real)-0.4};
    crane_real q[4] = {(crane_real)0.1, (crane_real)-0.6, (crane_real)0.2, (crane_real)0};
    crane_real qd[4] = {(crane_real)0.3, (crane_real)-0.2, (crane_real)0.1, (crane_real)0.05};
    crane_real qdd[4] = {(crane_real)1.0, (crane_real)0.5, (crane_real)0.2, (crane_real)0.1};
    crane_real tau[4], th = 0, ds = 0, stroke = 0, force = 0;
    size_t n = 0, count = 0, failed = 0;
    const char *msg = NULL;
    crane_field field = CRANE_FIELD_NONE;
    crane_status st = CRANE_OK;

    semihost_write("entry_points\n");
    board_crane(sc, &crane);
    MEASURED("probe_256", (void)stack_probe());
    MEASURED("crane_params_check", st = crane_params_check(&crane, &field));
    expect(st, CRANE_OK, "crane_params_check");
    if (field != CRANE_FIELD_NONE)
        fail("crane_params_check_field", (unsigned long)field);
    MEASURED("crane_field_rule", msg = crane_field_rule(CRANE_FIELD_GRAVITY));
    if (msg == NULL || msg[0] == '\0')
        fail("crane_field_rule", 0);
    MEASURED("crane_model_init", st = crane_model_init(&model, &crane, sc->state0.extension));
    expect(st, CRANE_OK, "crane_model_init");
    MEASURED("crane_sample_count", st = crane_sample_count(sc->horizon, sc->dt, &count));
    expect(st, CRANE_OK, "crane_sample_count");
    MEASURED("crane_sample_count_every",
             st = crane_sample_count_every(sc->horizon, sc->dt, 10, &count));
    expect(st, CRANE_OK, "crane_sample_count_every");
    MEASURED("crane_predict_model",
             st = crane_predict_model(&model, &sc->state0, &sc->inputs, sc->horizon, sc->dt,
                                      out2, CAPACITY, &n, &prediction_work));
    expect(st, CRANE_OK, "crane_predict_model");
    (void)crane_predict(&crane, &sc->state0, &sc->inputs, sc->horizon, sc->dt, out, CAPACITY, &n, &prediction_work);
    if (memcmp(out, out2, n * sizeof out[0]) != 0)
        fail("crane_predict_model_differs_from_crane_predict", (unsigned long)n);
    states[0] = states[1] = sc->state0;
    states[1].stroke[CRANE_LIFT] = (crane_real)0.2;
    inputs[0] = inputs[1] = sc->inputs;
    MEASURED("crane_predict_many",
             st = crane_predict_many(&crane, 1, 2, states, inputs, sc->horizon, sc->dt, 10, out2,
                                     count, &failed, &prediction_work));
    expect(st, CRANE_OK, "crane_predict_many");
    MEASURED("crane_joint_angle",
             st = crane_joint_angle(&model, CRANE_TILT, (crane_real)0.2, &th, &ds));
    expect(st, CRANE_OK, "crane_joint_angle");
    MEASURED("crane_joint_stroke", st = crane_joint_stroke(&model, CRANE_TILT, th, &stroke));
    expect(st, CRANE_OK, "crane_joint_stroke");
    MEASURED("crane_points", st = crane_points(&model, (crane_real)0.5, 2, theta, xyz));
    expect(st, CRANE_OK, "crane_points");
    q[3] = sc->state0.extension;
    MEASURED("crane_inverse_dynamics",
             st = crane_inverse_dynamics(&model, q, qd, qdd, tau));
    expect(st, CRANE_OK, "crane_inverse_dynamics");
    MEASURED("crane_cylinder_force",
             st = crane_cylinder_force(&model, CRANE_LIFT, (crane_real)175e5, (crane_real)0,
                                       (crane_real)0.05, &force));
    expect(st, CRANE_OK, "crane_cylinder_force");
    MEASURED("crane_status_message", msg = crane_status_message(CRANE_E_DIVERGED));
    if (msg == NULL || msg[0] == '\0')
        fail("crane_status_message", 0);
    run_guard(&model, out, n);
}

#ifdef BOARD_VALVES
/* The state estimator (make HYD=1): crane_estimator_init, then BOARD_ESTIMATOR_CYCLES updates,
 * each with its stack and ticks measured and the estimate printed (the host prints the same). The
 * measurements are lever-open's own prediction, one sample per period. */
static void run_estimator(void)
{
    static crane_estimator est; /* 14,984 B in float: static memory, not the stack */
    static crane_estimator_config config;
    static crane_model model;
    static crane_real x0[CRANE_EST_N], covariance0[CRANE_EST_N * CRANE_EST_N], spool0[4];
    static crane_real z[CRANE_EST_N], variance[CRANE_EST_N];
    const board_scenario *sc;
    crane_status st = CRANE_OK;
    size_t k;

    semihost_write("estimator\n");
    sc = board_estimator_prepare(&crane, &model, out, CAPACITY, &config, x0, covariance0, spool0);
    if (sc == NULL) {
        fail("board_estimator_prepare", 0);
        return;
    }
    MEASURED("crane_estimator_init",
             st = crane_estimator_init(&est, &config, x0, covariance0, spool0));
    expect(st, CRANE_OK, "crane_estimator_init");
    for (k = 1; k <= BOARD_ESTIMATOR_CYCLES; ++k) {
        board_measurement(&out[k], z, variance);
        MEASURED("crane_estimator_update",
                 st = crane_estimator_update(&est, &model, &sc->inputs, BOARD_ESTIMATOR_PERIOD, z,
                                             variance));
        expect(st, CRANE_OK, "crane_estimator_update");
        board_format_estimate(line, k, &est);
        semihost_write(line);
    }
}
#endif

int main(void)
{
    const board_scenario *sc;
    size_t n_sc, k;
    uint32_t t0, t1;

    semihost_write("board mps2-an386 cortex-m4f\n");
    clock_start();
    t0 = clock_now();
    spin(CALIBRATION_LOOPS);
    t1 = clock_now();
    report("calibration", NULL, (unsigned long)CALIBRATION_LOOPS);
    report("calibration_ticks", NULL, (unsigned long)(t1 - t0));
    report("stack_region", NULL,
           (unsigned long)(stack_pointer() - (uint32_t)(uintptr_t)__stack_limit));

    sc = board_scenarios(&n_sc);
    for (k = 0; k < n_sc; ++k)
        run_scenario(&sc[k]);
    run_entry_points(&sc[0]);
#ifdef BOARD_VALVES
    run_estimator();
#endif
    report("failures", NULL, (unsigned long)failures);
    return failures == 0 ? 0 : 1;
}

#endif /* BOARD_PROFILE */
