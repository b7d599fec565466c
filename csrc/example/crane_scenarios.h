/* SPDX-License-Identifier: MIT */
/*
 * The named scenarios of cranepredict (src/cranepredict/scenarios) for the C core.
 *
 * GENERATED from the TOML files in src/cranepredict/scenarios by tools/golden.py -- do not edit.
 * Regenerate:  python3 tools/golden.py   (tests/test_golden.py checks it is current)
 *
 * For scenario X (the file's name in capitals, '-' -> '_'):
 *   CRANE_SCENARIO_X_LOAD_MASS   the load, kg: set crane_params.load_mass of CRANE_PATU655_INIT
 *   CRANE_SCENARIO_X_STATE       a crane_state initializer
 *   CRANE_SCENARIO_X_INPUTS      a crane_inputs initializer: the four drives [lift, tilt, slew,
 *                                extension] (sampled drives as compound literals)
 *   CRANE_SCENARIO_X_HORIZON     s
 * CRANE_SCENARIO_LIST(ENTRY) calls ENTRY("name", X) for every scenario X, in the order of the
 * names (csrc/bench/bench_core.c picks one by name through it).
 * Every scenario uses the PATU 655 (crane_patu655.h).
 */

#ifndef CRANE_SCENARIOS_H
#define CRANE_SCENARIOS_H

#include "crane.h"

#ifndef CRANE_R
#define CRANE_R(x) ((crane_real)(x))
#endif


/* both-driven: Both cylinders driven: lift at 80 bar raises the boom while the tilt cylinder (rod side 30 bar) unfolds the outer boom, 200 kg. */
#define CRANE_SCENARIO_BOTH_DRIVEN_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_BOTH_DRIVEN_STATE { \
    .stroke = {CRANE_R(0.15), CRANE_R(0.45)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_BOTH_DRIVEN_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(8000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(3000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_BOTH_DRIVEN_HORIZON CRANE_R(2.0)

/* end-stop-lift-lower: Lift lower end stop: the rod side at 60 bar pulls the booms down until the lift cylinder is fully retracted; tilt held, 200 kg. */
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(6000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_HORIZON CRANE_R(2.0)

/* end-stop-tilt: Tilt end stop: 120 bar on the tilt cylinder's rod side unfolds the outer boom until the tilt cylinder is fully retracted (stroke_min); lift held, 200 kg. */
#define CRANE_SCENARIO_END_STOP_TILT_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_END_STOP_TILT_STATE { \
    .stroke = {CRANE_R(0.3), CRANE_R(0.25)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_END_STOP_TILT_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(12000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_END_STOP_TILT_HORIZON CRANE_R(2.0)

/* extend-while-slewing: Extending while slewing: from rest on closed valves (200 kg, outer boom near horizontal), the slew lever at -0.7 and the telescope lever fully open at t = 0, the booms' valves closed; the extension running out brakes the slew (Coriolis) and raises its inertia. */
#define CRANE_SCENARIO_EXTEND_WHILE_SLEWING_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_EXTEND_WHILE_SLEWING_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.05)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.5), .extension = CRANE_R(0.1), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(6818184.960655069), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(112373.36320531779)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(3325773.0566978203), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_EXTEND_WHILE_SLEWING_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(-0.7)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}}}
#define CRANE_SCENARIO_EXTEND_WHILE_SLEWING_HORIZON CRANE_R(2.0)

/* lever-open: The operator's version of the paper's experiment: the crane at rest on closed valves (paper-fig4's pose, 200 kg), the lift lever pushed fully open at t = 0, the tilt valve closed; the chamber pressures follow from the oil flows (orifice valve of [S1], 80 bar supply). */
#define CRANE_SCENARIO_LEVER_OPEN_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LEVER_OPEN_STATE { \
    .stroke = {CRANE_R(0.116), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(7086013.880115141), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2670549.5117333727), CRANE_R(100000.0), CRANE_R(641899.8157514883)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_LEVER_OPEN_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LEVER_OPEN_HORIZON CRANE_R(2.0)

/* load-0: Lift without load: 30 bar on the bore side, tilt held; just above the 29.68 bar that holds the booms at the start, so they rise slowly; 0 kg. */
#define CRANE_SCENARIO_LOAD_0_LOAD_MASS CRANE_R(0.0)
#define CRANE_SCENARIO_LOAD_0_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_0_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(3000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_0_HORIZON CRANE_R(2.0)

/* load-200: Lift with the load: 65 bar on the bore side, tilt held; just below the 65.04 bar that holds this load at the start, so the booms sink slowly; 200 kg. */
#define CRANE_SCENARIO_LOAD_200_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LOAD_200_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_200_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(6500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_200_HORIZON CRANE_R(2.0)

/* load-500: Lift with the load: 118 bar on the bore side, tilt held; just below the 118.08 bar that holds this load at the start, so the booms sink slowly; 500 kg. */
#define CRANE_SCENARIO_LOAD_500_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_LOAD_500_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_500_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(11800000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_500_HORIZON CRANE_R(2.0)

/* lower-gravity: Lowering under gravity: the lift cylinder's bore side at a low 40 bar, below the 54.33 bar that holds the booms with 200 kg at the start: they sink slowly (friction and the low pressure brake them); tilt held. */
#define CRANE_SCENARIO_LOWER_GRAVITY_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LOWER_GRAVITY_STATE { \
    .stroke = {CRANE_R(0.45), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOWER_GRAVITY_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(4000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOWER_GRAVITY_HORIZON CRANE_R(2.0)

/* paper-fig4: The paper's Figure 4: lift cylinder at 175 bar on the bore side (137,445 N), tilt cylinder held, 200 kg, lift boom starting near horizontal; it reaches the upper end stop within 2 s. */
#define CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_PAPER_FIG4_STATE { \
    .stroke = {CRANE_R(0.116), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_PAPER_FIG4_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(17500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_PAPER_FIG4_HORIZON CRANE_R(2.0)

/* pressure-ramps: Pressure ramps (sampled inputs): lift bore side ramps 40 -> 90 bar over 0.2-1.2 s; the tilt rod side rises 20 -> 50 bar over 0.5-1.5 s, 200 kg. */
#define CRANE_SCENARIO_PRESSURE_RAMPS_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_PRESSURE_RAMPS_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_PRESSURE_RAMPS_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.2), CRANE_R(1.2), CRANE_R(2.0)}, .p_a_samples = (const crane_real[]){CRANE_R(4000000.0), CRANE_R(4000000.0), CRANE_R(9000000.0), CRANE_R(9000000.0)}, .p_b_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_PRESSURE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.5), CRANE_R(1.5), CRANE_R(2.0)}, .p_a_samples = (const crane_real[]){CRANE_R(1000000.0), CRANE_R(1000000.0), CRANE_R(1000000.0), CRANE_R(1000000.0)}, .p_b_samples = (const crane_real[]){CRANE_R(2000000.0), CRANE_R(2000000.0), CRANE_R(5000000.0), CRANE_R(5000000.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_PRESSURE_RAMPS_HORIZON CRANE_R(2.0)

/* slew-folded: Slewing with the boom folded (compare slew-stretched): 20 bar on the slew drive's chamber a, the booms and telescope held folded in (lift 0.05 m, tilt 0.75 m, extension 0), 200 kg; the slew inertia is about 6x smaller than stretched, so it turns about 7x as far in 2 s (1.43 rad against 0.19 rad). */
#define CRANE_SCENARIO_SLEW_FOLDED_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_SLEW_FOLDED_STATE { \
    .stroke = {CRANE_R(0.05), CRANE_R(0.75)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_SLEW_FOLDED_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(2000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_SLEW_FOLDED_HORIZON CRANE_R(2.0)

/* slew-stop-load-out: Stopping a slew with the load out: 500 kg at full reach (boom stretched, telescope out), the slew lever fully open for 1 s and then back to neutral within 0.2 s; the closed valve and the oil brake the slewing load, the chamber pressures peak at the relief. */
#define CRANE_SCENARIO_SLEW_STOP_LOAD_OUT_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_SLEW_STOP_LOAD_OUT_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.05)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(-1.0), .extension = CRANE_R(1.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(14332452.625685323), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(174930.91631997767)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(10031808.243325733), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_SLEW_STOP_LOAD_OUT_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(1.0), CRANE_R(1.2), CRANE_R(2.5)}, .u_samples = (const crane_real[]){CRANE_R(1.0), CRANE_R(1.0), CRANE_R(0.0), CRANE_R(0.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_SLEW_STOP_LOAD_OUT_HORIZON CRANE_R(2.5)

/* slew-stretched: Slewing with the boom stretched (compare slew-folded): 20 bar on the slew drive's chamber a, the booms and telescope held stretched out (lift 0.05 m, tilt 0.0 m, extension 1.0 m), 200 kg. */
#define CRANE_SCENARIO_SLEW_STRETCHED_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_SLEW_STRETCHED_STATE { \
    .stroke = {CRANE_R(0.05), CRANE_R(0.0)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(1.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_SLEW_STRETCHED_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(2000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_SLEW_STRETCHED_HORIZON CRANE_R(2.0)

/* slew-while-lifting: Slewing while lifting: from rest on closed valves (200 kg, boom out), the slew lever at 0.8 and the lift lever at 0.6 at t = 0, the tilt and telescope valves closed; the rising boom changes the slew inertia and the slew rate loads the booms. */
#define CRANE_SCENARIO_SLEW_WHILE_LIFTING_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_SLEW_WHILE_LIFTING_STATE { \
    .stroke = {CRANE_R(0.1), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.3), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(7371446.176554987), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2871255.427821799), CRANE_R(100000.0), CRANE_R(675475.5281161432)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_SLEW_WHILE_LIFTING_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.6)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.8)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_SLEW_WHILE_LIFTING_HORIZON CRANE_R(2.0)

/* slewed-extended: Slewed (60 deg) and extended (0.8 m) pose: lift 85 bar with the tilt at 30/40 bar (bore/rod), 300 kg; tests the world mapping and the lumped extension. */
#define CRANE_SCENARIO_SLEWED_EXTENDED_LOAD_MASS CRANE_R(300.0)
#define CRANE_SCENARIO_SLEWED_EXTENDED_STATE { \
    .stroke = {CRANE_R(0.25), CRANE_R(0.35)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(1.0471975511965976), .extension = CRANE_R(0.8), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_SLEWED_EXTENDED_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(8500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(3000000.0), .p_b = CRANE_R(4000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_SLEWED_EXTENDED_HORIZON CRANE_R(2.0)

/* telescope-end-stop: The telescope into its end stop: from rest on closed valves (200 kg, outer boom near horizontal), the telescope lever fully open from 0.7 m; the extension reaches extension_max (1.0 m) and stops there, the oil pressure rising to the supply. */
#define CRANE_SCENARIO_TELESCOPE_END_STOP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_TELESCOPE_END_STOP_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.05)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.7), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(7321886.204681705), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(112373.36320531779)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(4117208.333435491), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_TELESCOPE_END_STOP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}}}
#define CRANE_SCENARIO_TELESCOPE_END_STOP_HORIZON CRANE_R(3.0)

/* tilt-alone: Tilt cylinder driven alone: rod side 30 bar, above the 28.59 bar that holds the outer boom at the start, so it unfolds slowly against its weight; lift held, 200 kg. */
#define CRANE_SCENARIO_TILT_ALONE_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_TILT_ALONE_STATE { \
    .stroke = {CRANE_R(0.3), CRANE_R(0.35)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0)}
#define CRANE_SCENARIO_TILT_ALONE_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(3000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_TILT_ALONE_HORIZON CRANE_R(2.0)

/* valve-all-four: All four levers at once from rest on closed valves, 300 kg: lift 0.5, tilt -0.4, slew 0.6, telescope -0.8 (retracting from 0.8 m). */
#define CRANE_SCENARIO_VALVE_ALL_FOUR_LOAD_MASS CRANE_R(300.0)
#define CRANE_SCENARIO_VALVE_ALL_FOUR_STATE { \
    .stroke = {CRANE_R(0.15), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.3), .extension = CRANE_R(0.8), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(9072670.918308826), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(4295840.218154502), CRANE_R(100000.0), CRANE_R(1040039.0358562216)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_ALL_FOUR_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.5)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(-0.4)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.6)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(-0.8)}}}
#define CRANE_SCENARIO_VALVE_ALL_FOUR_HORIZON CRANE_R(2.0)

/* valve-both-levers: Both levers: the lift lever at 0.7 (extend) and the tilt lever at -0.6 (retract) from rest at once, 200 kg. */
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(6178987.191041452), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2333301.3827653592), CRANE_R(100000.0), CRANE_R(839174.8498331379)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.7)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(-0.6)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_HORIZON CRANE_R(2.0)

/* valve-closed-500: The lift valve closed holding 500 kg on its oil spring while the tilt lever is opened to 0.5 (retract) between 0.2 and 0.7 s and closed again: the lift's trapped oil carries the changing load and rings. */
#define CRANE_SCENARIO_VALVE_CLOSED_500_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_CLOSED_500_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(10982290.630781185), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(4793972.433945876), CRANE_R(100000.0), CRANE_R(1798786.3888854461)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_CLOSED_500_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.2), CRANE_R(0.25), CRANE_R(0.65), CRANE_R(0.7), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(-0.5), CRANE_R(-0.5), CRANE_R(0.0), CRANE_R(0.0)}, .n_samples = 6}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_CLOSED_500_HORIZON CRANE_R(2.0)

/* valve-end-stop: Driving into an end stop: the lift lever fully open (extend) from rest near the top of the stroke; the piston reaches its upper stop and the bore-side pressure builds towards the supply pressure (the PATU's relief setting is above its supply, so the relief stays shut), 200 kg. */
#define CRANE_SCENARIO_VALVE_END_STOP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_END_STOP_STATE { \
    .stroke = {CRANE_R(0.47), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(5206049.449543527), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(215646.39045977846)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2745699.107438475), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_END_STOP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_END_STOP_HORIZON CRANE_R(2.0)

/* valve-lift-reverse: Reversing the lever: the lift lever fully open (extend) from rest, then pulled through to fully reversed (lower) over 0.1 s at 0.8 s, 500 kg; the tilt valve stays closed. */
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_STATE { \
    .stroke = {CRANE_R(0.25), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(11841609.066659464), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(6105370.016371044), CRANE_R(100000.0), CRANE_R(1131961.448418028)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.8), CRANE_R(0.9), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(1.0), CRANE_R(1.0), CRANE_R(-1.0), CRANE_R(-1.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_HORIZON CRANE_R(2.0)

/* valve-lift-step: Lever step from rest: the lift lever goes from closed to fully open (extend) at 0.1 s; the tilt valve stays closed (its oil spring carries the outer boom), 200 kg, starting at rest. */
#define CRANE_SCENARIO_VALVE_LIFT_STEP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_LIFT_STEP_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(6572430.490678125), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2710935.7983335913), CRANE_R(100000.0), CRANE_R(665215.213013518)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LIFT_STEP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.1), CRANE_R(0.11), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(1.0), CRANE_R(1.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_LIFT_STEP_HORIZON CRANE_R(2.0)

/* valve-lower-heavy: Lowering a heavy load: 500 kg with the outer boom folded in, where the tilt cylinder holds it in tension on the rod side; the tilt lever fully open (extend) lets the load run ahead of the oil, so the bore side falls to the cavitation floor while the rod side meters it out. */
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_STATE { \
    .stroke = {CRANE_R(0.35), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(11435648.948466873), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(201663.69871383518)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(6086345.682005782), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_HORIZON CRANE_R(2.0)

/* valve-slow-ramp: Slow ramp: the lift lever opens linearly from closed to fully open (extend) over 2 s, 200 kg; the tilt valve stays closed. */
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_STATE { \
    .stroke = {CRANE_R(0.15), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .slew_rate = CRANE_R(0.0), .extension_rate = CRANE_R(0.0), \
    .p_a = {CRANE_R(6651622.511669743), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .p_b = {CRANE_R(100000.0), CRANE_R(2464712.0845374228), CRANE_R(100000.0), CRANE_R(757837.3356677694)}, \
    .spool = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(1.0)}, .n_samples = 2}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_HORIZON CRANE_R(2.0)

/* The state estimator (cp.EKF, docs/live.md) for lever-open's crane, measuring
 * lift_stroke, tilt_stroke, slew, extension, lift_p_a, lift_p_b, tilt_p_a, tilt_p_b:
 *   CRANE_EXAMPLE_ESTIMATOR_CONFIG       a crane_estimator_config initializer
 *   CRANE_EXAMPLE_ESTIMATOR_VARIANCE     each estimated field's sensor variance (SI units^2; 0: not measured)
 *   CRANE_EXAMPLE_ESTIMATOR_X0, CRANE_EXAMPLE_ESTIMATOR_COVARIANCE0_DIAGONAL, CRANE_EXAMPLE_ESTIMATOR_SPOOL0
 *                    the filter after its first measurement, the scenario's initial state
 *                    (crane_estimator_init's; the covariance is diagonal) */
#define CRANE_EXAMPLE_ESTIMATOR_CONFIG { \
    .lo = {CRANE_R(0.0), CRANE_R(0.0), CRANE_R(-3.316126), CRANE_R(0.0), CRANE_R(-10.0), CRANE_R(-10.0), CRANE_R(-10.0), CRANE_R(-10.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0), CRANE_R(-100000.0)}, \
    .hi = {CRANE_R(0.535), CRANE_R(0.78), CRANE_R(3.316126), CRANE_R(1.0), CRANE_R(10.0), CRANE_R(10.0), CRANE_R(10.0), CRANE_R(10.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0), CRANE_R(100000000.0)}, \
    .noise = {CRANE_R(1e-08), CRANE_R(1e-08), CRANE_R(1e-08), CRANE_R(1e-08), CRANE_R(0.004), CRANE_R(0.004), CRANE_R(0.004), CRANE_R(0.04), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0), CRANE_R(500000000000.0)}, \
    .fd_step = {CRANE_R(1e-05), CRANE_R(1e-05), CRANE_R(1e-05), CRANE_R(1e-05), CRANE_R(0.0001), CRANE_R(0.0001), CRANE_R(0.0001), CRANE_R(0.0001), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0), CRANE_R(1000.0)}, \
    .scale = {CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(0.001), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0)}, \
    .dt = CRANE_R(0.005), .jacobian_columns = 4}
#define CRANE_EXAMPLE_ESTIMATOR_VARIANCE {CRANE_R(4e-08), CRANE_R(4e-08), CRANE_R(2.5e-07), CRANE_R(2.5e-07), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}
#define CRANE_EXAMPLE_ESTIMATOR_X0 {CRANE_R(0.116), CRANE_R(0.2), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(7086013.880115141), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(2670549.5117333727), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(100000.0), CRANE_R(641899.8157514883)}
#define CRANE_EXAMPLE_ESTIMATOR_COVARIANCE0_DIAGONAL {CRANE_R(4e-08), CRANE_R(4e-08), CRANE_R(2.5e-07), CRANE_R(2.5e-07), CRANE_R(0.0025000000000000005), CRANE_R(0.0025000000000000005), CRANE_R(0.0025000000000000005), CRANE_R(0.0025000000000000005), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(40000000000.0), CRANE_R(4000000000000.0), CRANE_R(4000000000000.0), CRANE_R(4000000000000.0), CRANE_R(4000000000000.0)}
#define CRANE_EXAMPLE_ESTIMATOR_SPOOL0 {CRANE_R(1.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}

/* Every scenario above: ENTRY("name", X) */
#define CRANE_SCENARIO_LIST(ENTRY) \
    ENTRY("both-driven", BOTH_DRIVEN) \
    ENTRY("end-stop-lift-lower", END_STOP_LIFT_LOWER) \
    ENTRY("end-stop-tilt", END_STOP_TILT) \
    ENTRY("extend-while-slewing", EXTEND_WHILE_SLEWING) \
    ENTRY("lever-open", LEVER_OPEN) \
    ENTRY("load-0", LOAD_0) \
    ENTRY("load-200", LOAD_200) \
    ENTRY("load-500", LOAD_500) \
    ENTRY("lower-gravity", LOWER_GRAVITY) \
    ENTRY("paper-fig4", PAPER_FIG4) \
    ENTRY("pressure-ramps", PRESSURE_RAMPS) \
    ENTRY("slew-folded", SLEW_FOLDED) \
    ENTRY("slew-stop-load-out", SLEW_STOP_LOAD_OUT) \
    ENTRY("slew-stretched", SLEW_STRETCHED) \
    ENTRY("slew-while-lifting", SLEW_WHILE_LIFTING) \
    ENTRY("slewed-extended", SLEWED_EXTENDED) \
    ENTRY("telescope-end-stop", TELESCOPE_END_STOP) \
    ENTRY("tilt-alone", TILT_ALONE) \
    ENTRY("valve-all-four", VALVE_ALL_FOUR) \
    ENTRY("valve-both-levers", VALVE_BOTH_LEVERS) \
    ENTRY("valve-closed-500", VALVE_CLOSED_500) \
    ENTRY("valve-end-stop", VALVE_END_STOP) \
    ENTRY("valve-lift-reverse", VALVE_LIFT_REVERSE) \
    ENTRY("valve-lift-step", VALVE_LIFT_STEP) \
    ENTRY("valve-lower-heavy", VALVE_LOWER_HEAVY) \
    ENTRY("valve-slow-ramp", VALVE_SLOW_RAMP)

#endif
