/* SPDX-License-Identifier: MIT */
/*
 * The scenarios the board runs, shared by the board program (main.c) and its host twin (host.c)
 * so that both run exactly the same calls, and the one output format both print.
 */
#ifndef BOARD_SCENARIOS_H
#define BOARD_SCENARIOS_H

#include <stddef.h>
#include "crane.h"

typedef struct {
    const char *name;
    crane_real horizon, dt; /* s */
    crane_real load_mass;   /* kg: the scenario's load on the crane of crane_patu655.h */
    crane_state state0;
    crane_inputs inputs;
} board_scenario;

/* The scenarios, in the order both programs run them; *count is their number. */
const board_scenario *board_scenarios(size_t *count);

/* The crane of crane_patu655.h with the scenario's load. */
void board_crane(const board_scenario *sc, crane_params *params);

#ifdef BOARD_VALVES
/* The state estimator's run (make HYD=1): the filter of example/crane_scenarios.h
 * (CRANE_EXAMPLE_ESTIMATOR_*, the live twin's cp.EKF) on lever-open, BOARD_ESTIMATOR_CYCLES
 * updates of BOARD_ESTIMATOR_PERIOD, each measuring the scenario's own prediction at its time. */
enum { BOARD_ESTIMATOR_CYCLES = 10 };
#define BOARD_ESTIMATOR_PERIOD ((crane_real)0.01)

/* The estimator's run before its first update: the scenario's crane into *params and *model,
 * its own prediction (the measurements, one sample per period) into out[0..capacity), the
 * filter's configuration and first state. The scenario, or NULL if anything failed. */
const board_scenario *board_estimator_prepare(crane_params *params, crane_model *model,
                                              crane_sample *out, size_t capacity,
                                              crane_estimator_config *config,
                                              crane_real x0[CRANE_EST_N],
                                              crane_real covariance0[CRANE_EST_N * CRANE_EST_N],
                                              crane_real spool0[4]);

/* The measurement of a sample: z and each field's variance (0: not measured). */
void board_measurement(const crane_sample *s, crane_real z[CRANE_EST_N],
                       crane_real variance[CRANE_EST_N]);

/* "estimate K x[0] ... x[15]\n": the estimate after update K, each as the hex digits of its bits. */
void board_format_estimate(char *line, size_t k, const crane_estimator *est);
#endif

/* Longest line board_format_sample or board_format_estimate writes, NUL included. */
enum { BOARD_LINE_MAX = 320 };

/* "sample NAME K t tip_x tip_y tip_z stroke_lift stroke_tilt theta_lift theta_tilt p_a_lift
 * p_b_lift p_a_tilt p_b_tilt stop_lift stop_tilt\n": every crane_real as the hex digits of its bits (exact, and needs no printf with
 * floating point on the board), the stop flags as -1, 0 or 1. */
void board_format_sample(char *line, const char *name, size_t k, const crane_sample *s);

/* Appends the decimal digits of v to the string at p; returns the new end (the NUL). */
char *board_put_u32(char *p, unsigned long v);

/* Appends s; returns the new end (the NUL). */
char *board_put_str(char *p, const char *s);

#endif
