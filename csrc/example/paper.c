/* SPDX-License-Identifier: MIT */
/*
 * The paper's experiment (Figure 4) on the C core alone, with the crane and the scenario compiled
 * in from the generated headers crane_patu655.h (src/cranepredict/cranes/patu655.toml) and
 * crane_scenarios.h (src/cranepredict/scenarios/paper-fig4.toml: lift cylinder at 175 bar on the
 * bore side, tilt held, 200 kg, from rest), 2 s at dt = 1e-3 s.
 *
 *   paper          prints the final tip position (world, m) and when the lift reached its stop
 *   paper --all    also prints every sample: "t tip_x tip_y tip_z" (for the precision checks)
 *
 * Exit status 0 on success, 1 if the core returned an error.
 */
#include <stdio.h>
#include <string.h>
#include "crane.h"
#include "crane_patu655.h"
#include "crane_scenarios.h"

/* the predictions' working storage (crane.h): one, these calls never run at once */
static crane_work work;

#define DT 1e-3
#define N_SAMPLES 2001 /* ceil(horizon / DT) + 1 for the scenario's 2 s */

static const crane_params patu655 = CRANE_PATU655_INIT;
static crane_sample out[N_SAMPLES];

int main(int argc, char **argv)
{
    crane_params crane = patu655;
    const crane_state s0 = CRANE_SCENARIO_PAPER_FIG4_STATE;
    const crane_inputs in = CRANE_SCENARIO_PAPER_FIG4_INPUTS;
    crane_status st;
    size_t n = 0, k;
    const int all = argc > 1 && strcmp(argv[1], "--all") == 0;
    double t_stop = -1;

    crane.load_mass = CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS;
    st = crane_predict(&crane, &s0, &in, CRANE_SCENARIO_PAPER_FIG4_HORIZON, (crane_real)DT, out,
                       N_SAMPLES, &n, &work);
    if (st != CRANE_OK) {
        fprintf(stderr, "crane_predict: %s (status %d)\n", crane_status_message(st), (int)st);
        return 1;
    }
    for (k = 0; k < n; ++k) {
        if (all)
            printf("sample %.17g %.17g %.17g %.17g\n", (double)out[k].t, (double)out[k].tip[0],
                   (double)out[k].tip[1], (double)out[k].tip[2]);
        if (t_stop < 0 && out[k].stop[CRANE_LIFT] == 1)
            t_stop = (double)out[k].t;
    }
    printf("precision %s\n", sizeof(crane_real) == sizeof(float) ? "float" : "double");
    printf("samples %lu\n", (unsigned long)n);
    printf("start %.17g %.17g %.17g\n", (double)out[0].tip[0], (double)out[0].tip[1],
           (double)out[0].tip[2]);
    printf("tip %.17g %.17g %.17g\n", (double)out[n - 1].tip[0], (double)out[n - 1].tip[1],
           (double)out[n - 1].tip[2]);
    printf("lift_stop_t %.17g\n", t_stop);
    return 0;
}
