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

/* Longest line board_format_sample writes, NUL included. */
enum { BOARD_LINE_MAX = 200 };

/* "sample NAME K t tip_x tip_y tip_z stroke_lift stroke_tilt theta_lift theta_tilt p_a_lift
 * p_b_lift p_a_tilt p_b_tilt stop_lift stop_tilt\n": every crane_real as the hex digits of its bits (exact, and needs no printf with
 * floating point on the board), the stop flags as -1, 0 or 1. */
void board_format_sample(char *line, const char *name, size_t k, const crane_sample *s);

/* Appends the decimal digits of v to the string at p; returns the new end (the NUL). */
char *board_put_u32(char *p, unsigned long v);

/* Appends s; returns the new end (the NUL). */
char *board_put_str(char *p, const char *s);

#endif
