/* SPDX-License-Identifier: MIT */
/*
 * The board's scenarios (csrc/board): GENERATED from the scenario files in
 * src/cranepredict/scenarios by csrc/board/scenarios2header.py -- do not edit. Regenerate:
 *   python3 csrc/board/scenarios2header.py   (csrc/ci-embedded.sh checks it with --check)
 *
 *   paper-dt2ms: paper-fig4.toml at dt = 0.002 s (cranepredict.DEFAULT_DT)
 *   paper-dt1ms: paper-fig4.toml at dt = 0.001 s
 */
#ifndef BOARD_SCENARIOS_GENERATED_H
#define BOARD_SCENARIOS_GENERATED_H

#include "crane.h"

#ifndef CRANE_R
#define CRANE_R(x) ((crane_real)(x))
#endif

/* board_scenario initializers, in the order the board runs them. */
#define BOARD_SCENARIOS_INIT { \
    {.name = "paper-dt2ms", .horizon = CRANE_R(2.0), .dt = CRANE_R(0.002), .load_mass = CRANE_R(200.0), \
     .state0 = {.stroke = {CRANE_R(0.116), CRANE_R(0.2)}, .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
                .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}, \
     .inputs = {.drive = {{.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(17500000.0), .p_b = CRANE_R(0.0)}, \
                          {.mode = CRANE_DRIVE_HOLD}}}}, \
    {.name = "paper-dt1ms", .horizon = CRANE_R(2.0), .dt = CRANE_R(0.001), .load_mass = CRANE_R(200.0), \
     .state0 = {.stroke = {CRANE_R(0.116), CRANE_R(0.2)}, .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
                .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}, \
     .inputs = {.drive = {{.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(17500000.0), .p_b = CRANE_R(0.0)}, \
                          {.mode = CRANE_DRIVE_HOLD}}}}, \
}

#endif
