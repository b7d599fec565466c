/* SPDX-License-Identifier: MIT */
/*
 * The board program's host twin: the same scenarios (scenarios.c), the same calls and the same
 * output lines for the samples, built for the host in float against the host's float library
 * (csrc/build-float). board_check.py compares the two outputs.
 */
#include <stdio.h>
#include "crane.h"
#include "scenarios.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

static crane_params crane;
enum { CAPACITY = 2001 };
static crane_sample out[CAPACITY];

int main(void)
{
    const board_scenario *sc;
    char line[BOARD_LINE_MAX];
    size_t n_sc, i, k, n;
    crane_status st;

    sc = board_scenarios(&n_sc);
    for (i = 0; i < n_sc; ++i) {
        n = 0;
        board_crane(&sc[i], &crane);
        st = crane_predict(&crane, &sc[i].state0, &sc[i].inputs, sc[i].horizon, sc[i].dt, out,
                           CAPACITY, &n, &work);
        if (st != CRANE_OK) {
            fprintf(stderr, "%s: %s\n", sc[i].name, crane_status_message(st));
            return 1;
        }
        printf("samples %s %lu\n", sc[i].name, (unsigned long)n);
        for (k = 0; k < n; ++k) {
            board_format_sample(line, sc[i].name, k, &out[k]);
            fputs(line, stdout);
        }
    }
#ifdef BOARD_VALVES
    {
        /* The estimator's run, as the board's run_estimator makes it. */
        static crane_estimator est;
        static crane_estimator_config config;
        static crane_model model;
        static crane_real x0[CRANE_EST_N], cov0[CRANE_EST_N * CRANE_EST_N], spool0[4];
        static crane_real z[CRANE_EST_N], variance[CRANE_EST_N];
        const board_scenario *e =
            board_estimator_prepare(&crane, &model, out, CAPACITY, &config, x0, cov0, spool0);

        if (e == NULL) {
            fprintf(stderr, "estimator: its measurements could not be predicted\n");
            return 1;
        }
        st = crane_estimator_init(&est, &config, x0, cov0, spool0);
        for (k = 1; k <= BOARD_ESTIMATOR_CYCLES && st == CRANE_OK; ++k) {
            board_measurement(&out[k], z, variance);
            st = crane_estimator_update(&est, &model, &e->inputs, BOARD_ESTIMATOR_PERIOD, z,
                                        variance);
            board_format_estimate(line, k, &est);
            fputs(line, stdout);
        }
        if (st != CRANE_OK) {
            fprintf(stderr, "estimator: %s\n", crane_status_message(st));
            return 1;
        }
    }
#endif
    return 0;
}
