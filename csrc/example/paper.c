/* SPDX-License-Identifier: MIT */
/*
 * The paper's experiment (Figure 4) on the C core alone, with the crane compiled in from the
 * generated header crane_patu655.h (source: src/cranepredict/cranes/patu655.toml).
 *
 * Lift cylinder at 175e5 Pa bore side, 0 rod side; tilt cylinder held; 200 kg at the tip;
 * lift stroke 0.116 m, tilt stroke 0.20 m (src/cranepredict/scenarios/paper-fig4.toml), at rest;
 * 2 s at dt = 1e-3 s.
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

#define HORIZON 2.0
#define DT 1e-3
#define N_SAMPLES 2001 /* ceil(HORIZON / DT) + 1 */

static const crane_params crane = CRANE_PATU655_INIT;
static crane_sample out[N_SAMPLES];

int main(int argc, char **argv)
{
    crane_state s0;
    crane_inputs in;
    crane_status st;
    size_t n = 0, k;
    const int all = argc > 1 && strcmp(argv[1], "--all") == 0;
    double t_stop = -1;

    memset(&s0, 0, sizeof s0);
    s0.stroke[CRANE_LIFT] = (crane_real)0.116;
    s0.stroke[CRANE_TILT] = (crane_real)0.20;
    memset(&in, 0, sizeof in);
    in.drive[CRANE_LIFT].mode = CRANE_DRIVE_PRESSURE;
    in.drive[CRANE_LIFT].p_a = (crane_real)175e5;
    in.drive[CRANE_LIFT].p_b = 0;
    in.drive[CRANE_TILT].mode = CRANE_DRIVE_HOLD;

    st = crane_predict(&crane, &s0, &in, (crane_real)HORIZON, (crane_real)DT, out, N_SAMPLES, &n);
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
