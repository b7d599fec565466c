/* SPDX-License-Identifier: MIT */
/*
 * The named scenarios of cranepredict (src/cranepredict/scenarios) for the C core.
 *
 * GENERATED from the TOML files in src/cranepredict/scenarios by tools/golden.py -- do not edit.
 * Regenerate:  python3 tools/golden.py   (tests/test_golden.py checks it is current)
 * Left out until the C core moves the slew and the extension (issue 11): extend-while-slewing, slew-folded, slew-stop-load-out, slew-stretched, slew-while-lifting, telescope-end-stop, valve-all-four
 *
 * For scenario X (the file's name in capitals, '-' -> '_'):
 *   CRANE_SCENARIO_X_LOAD_MASS   the load, kg: set crane_params.load_mass of CRANE_PATU655_INIT
 *   CRANE_SCENARIO_X_STATE       a crane_state initializer
 *   CRANE_SCENARIO_X_INPUTS      a crane_inputs initializer (sampled drives as compound literals)
 *   CRANE_SCENARIO_X_HORIZON     s
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
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_BOTH_DRIVEN_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(8000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(3000000.0)}}}
#define CRANE_SCENARIO_BOTH_DRIVEN_HORIZON CRANE_R(2.0)

/* end-stop-lift-lower: Lift lower end stop: the rod side at 60 bar pulls the booms down until the lift cylinder is fully retracted; tilt held, 200 kg. */
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(6000000.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_END_STOP_LIFT_LOWER_HORIZON CRANE_R(2.0)

/* end-stop-tilt: Tilt end stop: 120 bar on the tilt cylinder's rod side unfolds the outer boom until the tilt cylinder is fully retracted (stroke_min); lift held, 200 kg. */
#define CRANE_SCENARIO_END_STOP_TILT_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_END_STOP_TILT_STATE { \
    .stroke = {CRANE_R(0.3), CRANE_R(0.25)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_END_STOP_TILT_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(12000000.0)}}}
#define CRANE_SCENARIO_END_STOP_TILT_HORIZON CRANE_R(2.0)

/* lever-open: The operator's version of the paper's experiment: the crane at rest on closed valves (paper-fig4's pose, 200 kg), the lift lever pushed fully open at t = 0, the tilt valve closed; the chamber pressures follow from the oil flows (orifice valve of [S1], 80 bar supply). */
#define CRANE_SCENARIO_LEVER_OPEN_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LEVER_OPEN_STATE { \
    .stroke = {CRANE_R(0.116), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(7086013.880115141), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(2670549.511733372)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_LEVER_OPEN_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_LEVER_OPEN_HORIZON CRANE_R(2.0)

/* load-0: Lift without load: 30 bar on the bore side, tilt held; just above the 29.68 bar that holds the booms at the start, so they rise slowly; 0 kg. */
#define CRANE_SCENARIO_LOAD_0_LOAD_MASS CRANE_R(0.0)
#define CRANE_SCENARIO_LOAD_0_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_0_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(3000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_0_HORIZON CRANE_R(2.0)

/* load-200: Lift with the load: 65 bar on the bore side, tilt held; just below the 65.04 bar that holds this load at the start, so the booms sink slowly; 200 kg. */
#define CRANE_SCENARIO_LOAD_200_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LOAD_200_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_200_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(6500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_200_HORIZON CRANE_R(2.0)

/* load-500: Lift with the load: 118 bar on the bore side, tilt held; just below the 118.08 bar that holds this load at the start, so the booms sink slowly; 500 kg. */
#define CRANE_SCENARIO_LOAD_500_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_LOAD_500_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOAD_500_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(11800000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOAD_500_HORIZON CRANE_R(2.0)

/* lower-gravity: Lowering under gravity: the lift cylinder's bore side at a low 40 bar, below the 54.33 bar that holds the booms with 200 kg at the start: they sink slowly (friction and the low pressure brake them); tilt held. */
#define CRANE_SCENARIO_LOWER_GRAVITY_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_LOWER_GRAVITY_STATE { \
    .stroke = {CRANE_R(0.45), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_LOWER_GRAVITY_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(4000000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_LOWER_GRAVITY_HORIZON CRANE_R(2.0)

/* paper-fig4: The paper's Figure 4: lift cylinder at 175 bar on the bore side (137,445 N), tilt cylinder held, 200 kg, lift boom starting near horizontal; it reaches the upper end stop within 2 s. */
#define CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_PAPER_FIG4_STATE { \
    .stroke = {CRANE_R(0.116), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_PAPER_FIG4_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(17500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_HOLD}}}
#define CRANE_SCENARIO_PAPER_FIG4_HORIZON CRANE_R(2.0)

/* pressure-ramps: Pressure ramps (sampled inputs): lift bore side ramps 40 -> 90 bar over 0.2-1.2 s; the tilt rod side rises 20 -> 50 bar over 0.5-1.5 s, 200 kg. */
#define CRANE_SCENARIO_PRESSURE_RAMPS_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_PRESSURE_RAMPS_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_PRESSURE_RAMPS_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.2), CRANE_R(1.2), CRANE_R(2.0)}, .p_a_samples = (const crane_real[]){CRANE_R(4000000.0), CRANE_R(4000000.0), CRANE_R(9000000.0), CRANE_R(9000000.0)}, .p_b_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0), CRANE_R(0.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_PRESSURE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.5), CRANE_R(1.5), CRANE_R(2.0)}, .p_a_samples = (const crane_real[]){CRANE_R(1000000.0), CRANE_R(1000000.0), CRANE_R(1000000.0), CRANE_R(1000000.0)}, .p_b_samples = (const crane_real[]){CRANE_R(2000000.0), CRANE_R(2000000.0), CRANE_R(5000000.0), CRANE_R(5000000.0)}, .n_samples = 4}}}
#define CRANE_SCENARIO_PRESSURE_RAMPS_HORIZON CRANE_R(2.0)

/* slewed-extended: Slewed (60 deg) and extended (0.8 m) pose: lift 85 bar with the tilt at 30/40 bar (bore/rod), 300 kg; tests the world mapping and the lumped extension. */
#define CRANE_SCENARIO_SLEWED_EXTENDED_LOAD_MASS CRANE_R(300.0)
#define CRANE_SCENARIO_SLEWED_EXTENDED_STATE { \
    .stroke = {CRANE_R(0.25), CRANE_R(0.35)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(1.0471975511965976), .extension = CRANE_R(0.8)}
#define CRANE_SCENARIO_SLEWED_EXTENDED_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(8500000.0), .p_b = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(3000000.0), .p_b = CRANE_R(4000000.0)}}}
#define CRANE_SCENARIO_SLEWED_EXTENDED_HORIZON CRANE_R(2.0)

/* tilt-alone: Tilt cylinder driven alone: rod side 30 bar, above the 28.59 bar that holds the outer boom at the start, so it unfolds slowly against its weight; lift held, 200 kg. */
#define CRANE_SCENARIO_TILT_ALONE_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_TILT_ALONE_STATE { \
    .stroke = {CRANE_R(0.3), CRANE_R(0.35)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0)}
#define CRANE_SCENARIO_TILT_ALONE_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_HOLD}, \
    {.mode = CRANE_DRIVE_PRESSURE, .p_a = CRANE_R(0.0), .p_b = CRANE_R(3000000.0)}}}
#define CRANE_SCENARIO_TILT_ALONE_HORIZON CRANE_R(2.0)

/* valve-both-levers: Both levers: the lift lever at 0.7 (extend) and the tilt lever at -0.6 (retract) from rest at once, 200 kg. */
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(6178987.191041451), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(2333301.3827653583)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.7)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(-0.6)}}}
#define CRANE_SCENARIO_VALVE_BOTH_LEVERS_HORIZON CRANE_R(2.0)

/* valve-closed-500: The lift valve closed holding 500 kg on its oil spring while the tilt lever is opened to 0.5 (retract) between 0.2 and 0.7 s and closed again: the lift's trapped oil carries the changing load and rings. */
#define CRANE_SCENARIO_VALVE_CLOSED_500_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_CLOSED_500_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.4)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(10982290.630781185), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(4793972.433945875)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_CLOSED_500_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.2), CRANE_R(0.25), CRANE_R(0.65), CRANE_R(0.7), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(-0.5), CRANE_R(-0.5), CRANE_R(0.0), CRANE_R(0.0)}, .n_samples = 6}}}
#define CRANE_SCENARIO_VALVE_CLOSED_500_HORIZON CRANE_R(2.0)

/* valve-end-stop: Driving into an end stop: the lift lever fully open (extend) from rest near the top of the stroke; the piston reaches its upper stop and the bore-side pressure builds towards the supply pressure (the PATU's relief setting is above its supply, so the relief stays shut), 200 kg. */
#define CRANE_SCENARIO_VALVE_END_STOP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_END_STOP_STATE { \
    .stroke = {CRANE_R(0.47), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(5206049.449543527), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(2745699.1074384744)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_END_STOP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_VALVE_END_STOP_HORIZON CRANE_R(2.0)

/* valve-lift-reverse: Reversing the lever: the lift lever fully open (extend) from rest, then pulled through to fully reversed (lower) over 0.1 s at 0.8 s, 500 kg; the tilt valve stays closed. */
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_STATE { \
    .stroke = {CRANE_R(0.25), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(11841609.066659465), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(6105370.016371044)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.8), CRANE_R(0.9), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(1.0), CRANE_R(1.0), CRANE_R(-1.0), CRANE_R(-1.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_VALVE_LIFT_REVERSE_HORIZON CRANE_R(2.0)

/* valve-lift-step: Lever step from rest: the lift lever goes from closed to fully open (extend) at 0.1 s; the tilt valve stays closed (its oil spring carries the outer boom), 200 kg, starting at rest. */
#define CRANE_SCENARIO_VALVE_LIFT_STEP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_LIFT_STEP_STATE { \
    .stroke = {CRANE_R(0.2), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(6572430.490678124), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(2710935.798333591)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LIFT_STEP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.1), CRANE_R(0.11), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(0.0), CRANE_R(1.0), CRANE_R(1.0)}, .n_samples = 4}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_VALVE_LIFT_STEP_HORIZON CRANE_R(2.0)

/* valve-lower-heavy: Lowering a heavy load: 500 kg with the outer boom folded in, where the tilt cylinder holds it in tension on the rod side; the tilt lever fully open (extend) lets the load run ahead of the oil, so the bore side falls to the cavitation floor while the rod side meters it out. */
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_LOAD_MASS CRANE_R(500.0)
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_STATE { \
    .stroke = {CRANE_R(0.35), CRANE_R(0.2)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(11435648.948466873), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(6086345.682005781)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(1.0)}}}
#define CRANE_SCENARIO_VALVE_LOWER_HEAVY_HORIZON CRANE_R(2.0)

/* valve-slow-ramp: Slow ramp: the lift lever opens linearly from closed to fully open (extend) over 2 s, 200 kg; the tilt valve stays closed. */
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_LOAD_MASS CRANE_R(200.0)
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_STATE { \
    .stroke = {CRANE_R(0.15), CRANE_R(0.3)}, \
    .stroke_rate = {CRANE_R(0.0), CRANE_R(0.0)}, \
    .slew = CRANE_R(0.0), .extension = CRANE_R(0.0), \
    .p_a = {CRANE_R(6651622.511669741), CRANE_R(100000.0)}, .p_b = {CRANE_R(100000.0), CRANE_R(2464712.0845374214)}, .spool = {CRANE_R(0.0), CRANE_R(0.0)}}
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_INPUTS {.drive = { \
    {.mode = CRANE_DRIVE_VALVE, .t = (const crane_real[]){CRANE_R(0.0), CRANE_R(2.0)}, .u_samples = (const crane_real[]){CRANE_R(0.0), CRANE_R(1.0)}, .n_samples = 2}, \
    {.mode = CRANE_DRIVE_VALVE, .u = CRANE_R(0.0)}}}
#define CRANE_SCENARIO_VALVE_SLOW_RAMP_HORIZON CRANE_R(2.0)

#endif
