/* SPDX-License-Identifier: MIT */
/*
 * cranepredict C core: faster-than-real-time prediction of a hydraulic loader crane: lift, tilt
 * (planar Newton-Euler), and with a slew or extension drive also the slew and the telescope
 * (four-joint spatial dynamics), with end stops and valve-driven hydraulics; integrated with error
 * control (ROS34PW2, DOPRI5(4)) or fixed-step RK4 (crane_solver). The model and the methods are
 * specified in docs/model.md.
 *
 * C99, libm only, no heap, no mutable globals, no I/O. The caller owns every struct and buffer.
 * Every entry point returns a crane_status and never aborts; on an error nothing is written to
 * the outputs beyond what the status says. SI units throughout: m, s, rad, kg, N, Pa.
 *
 * Build with -DCRANE_FLOAT to compute in float instead of double.
 *
 * The declarations between CRANE_CDEF_BEGIN and CRANE_CDEF_END are read verbatim by the Python
 * build (cffi cdef), so they must stay plain declarations: no macros, no preprocessor lines.
 */
#ifndef CRANE_H
#define CRANE_H

#include <stddef.h>

#ifdef CRANE_FLOAT
typedef float crane_real;
#else
typedef double crane_real;
#endif

/* CRANE_CDEF_BEGIN */
typedef enum {
    CRANE_OK = 0,
    CRANE_E_NULL = 1,           /* a required pointer is NULL */
    CRANE_E_NONFINITE = 2,      /* a NaN or infinity in the inputs */
    CRANE_E_BODY = 3,           /* a mass, centre of mass or inertia is not physical */
    CRANE_E_CYLINDER = 4,       /* bore/rod/length/stroke range not physical */
    CRANE_E_FRICTION = 5,       /* friction coefficients not physical */
    CRANE_E_GEOMETRY = 6,       /* lift triangle leaves 0 < gamma < pi over the lift stroke */
    CRANE_E_FOURBAR = 7,        /* the tilt four-bar cannot close over the tilt stroke */
    CRANE_E_GRAVITY = 8,        /* gravity < 0 */
    CRANE_E_STROKE = 9,         /* an initial stroke outside [stroke_min, stroke_max] */
    CRANE_E_EXTENSION = 10,     /* extension outside [extension_min, extension_max] */
    CRANE_E_STROKE_RATE = 11,   /* a held cylinder given a nonzero stroke rate */
    CRANE_E_DRIVE = 12,         /* drive mode unknown */
    CRANE_E_PRESSURE = 13,      /* a pressure outside [0, CRANE_PRESSURE_MAX] */
    CRANE_E_SAMPLES = 14,       /* pressure sample times not increasing or not covering [0, horizon] */
    CRANE_E_DT = 15,            /* dt <= 0 or dt > horizon */
    CRANE_E_HORIZON = 16,       /* horizon <= 0 */
    CRANE_E_CAPACITY = 17,      /* output buffer smaller than the number of samples */
    CRANE_E_ANGLE = 18,         /* an angle outside the range reachable by the cylinder */
    CRANE_E_SAMPLE_EVERY = 19,  /* sample_every is 0 (or over LONG_MAX) */
    CRANE_E_DIVERGED = 20,      /* the state stopped being finite or physical (absurd parameters) */
    CRANE_E_FIELD = 21,         /* a crane parameter outside its range (crane_params_check names it) */
    CRANE_E_OVERFLOW = 22,      /* an argument so large that a result is not finite or a size overflows */
    CRANE_E_STEPS = 23,         /* horizon / dt asks for more than CRANE_MAX_STEPS steps */
    CRANE_E_SAMPLE_COUNT = 24,  /* more than CRANE_MAX_SAMPLES samples in one call (horizon, dt,
                                   sample_every, n_futures) */
    CRANE_E_BATCH = 25,         /* n_futures x steps over CRANE_MAX_BATCH_STEPS in one call */
    CRANE_E_HYDRAULICS = 26,    /* a hydraulic parameter out of range (docs/model.md, Hydraulics) */
    CRANE_E_VALVE = 27,         /* a lever outside [-1, 1], a valve drive without hydraulics (or
                                 * in a build without CRANE_HYDRAULICS), or a chamber pressure /
                                 * spool of the state out of range */
    CRANE_E_ACTUATOR = 28,      /* a slew or extension drive (not a hold) on a crane without a
                                 * slew drive / extension cylinder */
    CRANE_E_PARAMS = 29,        /* crane_predict_many: n_params neither 1 nor n_futures */
    CRANE_E_METHOD = 30,        /* crane_solver: a method unknown or a tolerance out of range */
    CRANE_E_TOLERANCE = 31,     /* the error control could not meet the tolerance: a step below
                                 * CRANE_MIN_STEP or more attempts than the cap (docs/model.md,
                                 * "Integration"); samples before it are written, as DIVERGED */
    /* the collision guard (docs/guard.md) */
    CRANE_E_SOLID = 40,         /* a solid (obstacle) is not valid, or a pair of two planes */
    CRANE_E_PART = 41,          /* a crane part is not valid */
    CRANE_E_GUARD = 42,         /* a guard setting (margin, reaction, cycle, tolerances) out of range */
    CRANE_E_ESTIMATOR = 50      /* an estimator setting, estimate or measurement variance out of
                                 * range, or a covariance that cannot be kept positive definite */
} crane_status;

/* The joints (docs/model.md, "Four joints"): four-entry arrays are [lift, tilt, slew, extension],
 * two-entry arrays [lift, tilt]. */
enum { CRANE_LIFT = 0, CRANE_TILT = 1, CRANE_SLEW = 2, CRANE_EXTENSION = 3 };
/* A drive left zero is a hold: a caller that fills only the lift and tilt drives (or none) holds
 * the slew and the extension, as docs/model.md says of a drive left out. */
enum { CRANE_DRIVE_HOLD = 0, CRANE_DRIVE_PRESSURE = 1, CRANE_DRIVE_VALVE = 2 };
enum { CRANE_VALVE_NONE = 0, CRANE_VALVE_ORIFICE = 1, CRANE_VALVE_COMPENSATED = 2 };
enum { CRANE_N_POINTS = 11 };
enum { CRANE_METHOD_DEFAULT = 0, CRANE_METHOD_ROSW = 1, CRANE_METHOD_RK4 = 2, CRANE_METHOD_DOPRI5 = 3 };
enum { CRANE_PRESSURE_MAX = 100000000 };   /* Pa (1000 bar): the largest pressure accepted */
enum { CRANE_CHAMBER_PRESSURE_MIN = -100000 };  /* Pa gauge (vacuum): the lowest chamber pressure */

/* Bounded work and memory: checked before anything runs or is written (CRANE_E_STEPS,
 * CRANE_E_SAMPLE_COUNT, CRANE_E_BATCH), so that no accepted call runs for more than seconds
 * (measured on the project's shared 2-core CI machine, both cylinders driven: 1.0 s for one
 * prediction of CRANE_MAX_STEPS, 0.5 us a step; a PC core is about twice as fast).
 *   CRANE_MAX_STEPS: sample intervals per prediction (one future), n = ceil(horizon/dt - 1e-9):
 *     2^20; with RK4 these are its steps. The error-controlled methods' work is their cap on step
 *     attempts (64 + 4096 a second of horizon + one per sample of a sampled drive inside), which
 *     counts against it in place of the RK4 work: 2^20 is 17 min of crane time at dt = 1 ms.
 *     With RK4 the work counted against it is n plus one step per
 *     sample of a sampled drive inside (0, horizon) (steps are cut there), times the most
 *     substeps a step of valve-driven cylinders or a moving extension can take.
 *     Why 2^20: the step times are t_k = k dt in every build (never accumulated), and in the float
 *     build horizon/dt is uncertain by about 4 eps n steps (both operands rounded to 24 bits; the
 *     step count allows for it): up to 2^20 steps that stays under a quarter step, so the last
 *     step is at most 1.25 dt long, and k dt is within dt/8 of its exact value, so the sample times
 *     stay strictly increasing.
 *   CRANE_MAX_SAMPLES: samples written by one call (all futures of crane_predict_many): 2^23,
 *     2.4 GB of crane_sample in double (288 bytes each); a single prediction (n + 1 <= 2^20 + 1)
 *     never reaches it.
 *   CRANE_MAX_BATCH_STEPS: steps of one crane_predict_many call, n_futures x n: 2^23, about 4 s;
 *     split larger batches into several calls (they may run on several threads). */
enum { CRANE_MAX_STEPS = 1048576, CRANE_MAX_SAMPLES = 8388608, CRANE_MAX_BATCH_STEPS = 8388608 };

typedef struct {
    crane_real x, y;
} crane_vec2;

typedef struct {
    crane_real mass;     /* kg */
    crane_vec2 com;      /* centre of mass in the body's frame, m */
    crane_real izz;      /* moment of inertia about the centre of mass, kg m^2 */
    /* The in-plane entries of the inertia tensor about the centre of mass, in the body's frame
     * (kg m^2; [S1]'s convention ixy = -integral(x y dm)): the slew inertia needs them (docs/model.md,
     * "Four joints"). A body known only by izz: ixx = 0, iyy = izz, ixy = 0 (slender along x). */
    crane_real ixx, iyy, ixy;
} crane_body;

typedef struct {
    crane_real coulomb;            /* F_C, N */
    crane_real static_;            /* F_S >= F_C, N */
    crane_real viscous;            /* sigma, N s/m */
    crane_real stribeck_velocity;  /* v_S > 0, m/s */
    crane_real factor;             /* k >= 0: multiplies F_C and F_S, not sigma ([S1]: 4 on the lift) */
} crane_friction;

/* A cylinder's valve and oil (docs/model.md, "Hydraulics"); SI: Pa, m^3, m^3/s, s. */
typedef struct {
    int valve;                       /* CRANE_VALVE_NONE (no circuit: cannot be valve-driven),
                                      * CRANE_VALVE_ORIFICE or CRANE_VALVE_COMPENSATED */
    crane_real supply_pressure;      /* p_S */
    crane_real tank_pressure;        /* p_T */
    crane_real relief_pressure;      /* port relief setting p_R */
    crane_real nominal_flow;         /* orifice: at full opening and nominal_pressure_drop;
                                      * compensated: the meter-in flow at full opening */
    crane_real nominal_pressure_drop;
    crane_real dead_band;            /* compensated: u0 in [0, 0.99]; orifice: 0 */
    crane_real meter_out_flow;       /* compensated: meter-out orifice, flow at ... */
    crane_real meter_out_pressure_drop;   /* ... this pressure drop */
    crane_real spool_time_constant;  /* s; 0 = no spool lag */
    crane_real laminar_pressure_drop;     /* d_l > 0: width of the laminar region */
    crane_real cavitation_pressure;  /* anti-cavitation valve opens below this */
    crane_real hose_volume_a, hose_volume_b;   /* dead volumes, m^3 */
    crane_real oil_bulk_modulus, hose_bulk_modulus, cylinder_bulk_modulus;
    crane_real leakage;              /* m^3/(s Pa) across the piston; 0 = none */
} crane_hydraulics;

typedef struct {
    crane_real bore;               /* piston diameter, m */
    crane_real rod;                /* rod diameter, m */
    crane_real length_retracted;   /* pin-to-pin length at stroke 0, m */
    crane_real stroke_min;         /* end stops, m */
    crane_real stroke_max;
    crane_friction friction;
    crane_hydraulics hydraulics;   /* .valve = CRANE_VALVE_NONE when the crane file has none */
} crane_cylinder;

/* The slew actuator (docs/model.md, "Four joints"): two cylinders of one bore on a rack turning a
 * pinion on the pillar, the equivalent cylinder with A_a = A_b = pi bore^2 / 4 and the rack travel
 * s = pinion_radius (psi - slew_min) as its stroke. */
typedef struct {
    int present;                   /* 1: the crane has one; 0: its slew can only be held (the
                                      other fields are then not read) */
    crane_real bore;               /* each rack cylinder's bore, m */
    crane_real pinion_radius;      /* pitch radius, m: ds/dpsi */
    crane_real slew_min, slew_max; /* the slew range, rad (the rack's travel) */
    crane_friction friction;       /* at the rack's speed */
    crane_hydraulics hydraulics;   /* chamber a turns towards +psi; .valve = CRANE_VALVE_NONE: none */
} crane_slew_drive;

/* The telescope's cylinder (docs/model.md, "Four joints"): bore side extending, its stroke is
 * extension - extension_min, its range [0, extension_max - extension_min]. */
typedef struct {
    int present;                   /* 1: the crane has one; 0: its extension can only be held */
    crane_real bore, rod;          /* m */
    crane_friction friction;
    crane_hydraulics hydraulics;   /* .valve = CRANE_VALVE_NONE: none */
} crane_extension_cylinder;

typedef struct {
    crane_real gravity;              /* m/s^2, along -y of the boom plane */
    crane_vec2 lift_pivot;           /* O1, boom plane */
    crane_vec2 lift_cylinder_base;   /* boom plane */
    crane_vec2 lift_cylinder_rod;    /* lift boom frame */
    crane_vec2 tilt_cylinder_base;   /* lift boom frame */
    crane_vec2 link1_pivot;          /* P1, lift boom frame */
    crane_vec2 tilt_pivot;           /* O2, lift boom frame */
    crane_vec2 link_pin;             /* Q in side link 1's frame (origin P1) */
    crane_vec2 link2_end;            /* A in side link 2's frame (origin Q) */
    crane_vec2 link2_attach;         /* A in the outer boom frame */
    crane_vec2 extension_mount;      /* outer boom frame */
    crane_real tip_distance;         /* load point along the extension boom's x axis, m */
    crane_real extension_min;        /* m */
    crane_real extension_max;
    crane_body lift_boom;            /* lift boom frame */
    crane_body outer_boom;           /* outer boom frame */
    crane_body extension_boom;       /* extension boom frame */
    crane_real load_mass;            /* kg, point mass at the tip, >= 0 */
    crane_cylinder cylinder[2];      /* [CRANE_LIFT], [CRANE_TILT] */
    crane_body side_link1;           /* side link 1 frame (origin P1) */
    crane_body side_link2;           /* side link 2 frame (origin Q) */
    crane_body pillar;               /* boom plane; turns with the slew only (all 0: none) */
    crane_slew_drive slew_drive;
    crane_extension_cylinder extension_cylinder;
} crane_params;

/* The crane file's fields, for crane_params_check to say which one breaks a rule. Each name is the
 * crane file's dotted name in capitals with '.' -> '_' (cylinder i = lift_cylinder, tilt_cylinder;
 * the Python layer maps the codes back to dotted names by that rule). A body's block is MASS, COM,
 * IZZ, IXX, IYY, IXY; the tilt cylinder's block mirrors the lift cylinder's, in the same order, and
 * every FRICTION and HYDRAULICS block (the cylinders', the slew drive's, the extension cylinder's)
 * has the lift cylinder's order (model.c counts on all three). To add a field: an enumerator here (in both cylinder blocks for a cylinder
 * field), its check in model.c (crane__check_params) and its rule in crane_field_rule. */
typedef enum {
    CRANE_FIELD_NONE = 0,
    CRANE_FIELD_GRAVITY,
    CRANE_FIELD_LOAD_MASS,
    CRANE_FIELD_GEOMETRY_LIFT_PIVOT,
    CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_BASE,
    CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_ROD,
    CRANE_FIELD_GEOMETRY_TILT_CYLINDER_BASE,
    CRANE_FIELD_GEOMETRY_LINK1_PIVOT,
    CRANE_FIELD_GEOMETRY_TILT_PIVOT,
    CRANE_FIELD_GEOMETRY_LINK_PIN,
    CRANE_FIELD_GEOMETRY_LINK2_END,
    CRANE_FIELD_GEOMETRY_LINK2_ATTACH,
    CRANE_FIELD_GEOMETRY_EXTENSION_MOUNT,
    CRANE_FIELD_GEOMETRY_TIP_DISTANCE,
    CRANE_FIELD_GEOMETRY_EXTENSION_MIN,
    CRANE_FIELD_GEOMETRY_EXTENSION_MAX,
    CRANE_FIELD_LIFT_BOOM_MASS,
    CRANE_FIELD_LIFT_BOOM_COM,
    CRANE_FIELD_LIFT_BOOM_IZZ,
    CRANE_FIELD_LIFT_BOOM_IXX,
    CRANE_FIELD_LIFT_BOOM_IYY,
    CRANE_FIELD_LIFT_BOOM_IXY,
    CRANE_FIELD_OUTER_BOOM_MASS,
    CRANE_FIELD_OUTER_BOOM_COM,
    CRANE_FIELD_OUTER_BOOM_IZZ,
    CRANE_FIELD_OUTER_BOOM_IXX,
    CRANE_FIELD_OUTER_BOOM_IYY,
    CRANE_FIELD_OUTER_BOOM_IXY,
    CRANE_FIELD_EXTENSION_BOOM_MASS,
    CRANE_FIELD_EXTENSION_BOOM_COM,
    CRANE_FIELD_EXTENSION_BOOM_IZZ,
    CRANE_FIELD_EXTENSION_BOOM_IXX,
    CRANE_FIELD_EXTENSION_BOOM_IYY,
    CRANE_FIELD_EXTENSION_BOOM_IXY,
    CRANE_FIELD_SIDE_LINK1_MASS,
    CRANE_FIELD_SIDE_LINK1_COM,
    CRANE_FIELD_SIDE_LINK1_IZZ,
    CRANE_FIELD_SIDE_LINK1_IXX,
    CRANE_FIELD_SIDE_LINK1_IYY,
    CRANE_FIELD_SIDE_LINK1_IXY,
    CRANE_FIELD_SIDE_LINK2_MASS,
    CRANE_FIELD_SIDE_LINK2_COM,
    CRANE_FIELD_SIDE_LINK2_IZZ,
    CRANE_FIELD_SIDE_LINK2_IXX,
    CRANE_FIELD_SIDE_LINK2_IYY,
    CRANE_FIELD_SIDE_LINK2_IXY,
    CRANE_FIELD_PILLAR_MASS,
    CRANE_FIELD_PILLAR_COM,
    CRANE_FIELD_PILLAR_IZZ,
    CRANE_FIELD_PILLAR_IXX,
    CRANE_FIELD_PILLAR_IYY,
    CRANE_FIELD_PILLAR_IXY,
    CRANE_FIELD_LIFT_CYLINDER_BORE,
    CRANE_FIELD_LIFT_CYLINDER_ROD,
    CRANE_FIELD_LIFT_CYLINDER_LENGTH_RETRACTED,
    CRANE_FIELD_LIFT_CYLINDER_STROKE_MIN,
    CRANE_FIELD_LIFT_CYLINDER_STROKE_MAX,
    CRANE_FIELD_LIFT_CYLINDER_FRICTION_COULOMB,
    CRANE_FIELD_LIFT_CYLINDER_FRICTION_STATIC,
    CRANE_FIELD_LIFT_CYLINDER_FRICTION_VISCOUS,
    CRANE_FIELD_LIFT_CYLINDER_FRICTION_STRIBECK_VELOCITY,
    CRANE_FIELD_LIFT_CYLINDER_FRICTION_FACTOR,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_VALVE,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_SUPPLY_PRESSURE,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_TANK_PRESSURE,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_RELIEF_PRESSURE,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_NOMINAL_FLOW,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_NOMINAL_PRESSURE_DROP,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_DEAD_BAND,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_METER_OUT_FLOW,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_METER_OUT_PRESSURE_DROP,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_SPOOL_TIME_CONSTANT,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_LAMINAR_PRESSURE_DROP,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_CAVITATION_PRESSURE,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_VOLUME_A,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_VOLUME_B,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_OIL_BULK_MODULUS,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_BULK_MODULUS,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_CYLINDER_BULK_MODULUS,
    CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_LEAKAGE,
    CRANE_FIELD_TILT_CYLINDER_BORE,
    CRANE_FIELD_TILT_CYLINDER_ROD,
    CRANE_FIELD_TILT_CYLINDER_LENGTH_RETRACTED,
    CRANE_FIELD_TILT_CYLINDER_STROKE_MIN,
    CRANE_FIELD_TILT_CYLINDER_STROKE_MAX,
    CRANE_FIELD_TILT_CYLINDER_FRICTION_COULOMB,
    CRANE_FIELD_TILT_CYLINDER_FRICTION_STATIC,
    CRANE_FIELD_TILT_CYLINDER_FRICTION_VISCOUS,
    CRANE_FIELD_TILT_CYLINDER_FRICTION_STRIBECK_VELOCITY,
    CRANE_FIELD_TILT_CYLINDER_FRICTION_FACTOR,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_VALVE,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_SUPPLY_PRESSURE,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_TANK_PRESSURE,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_RELIEF_PRESSURE,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_NOMINAL_FLOW,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_NOMINAL_PRESSURE_DROP,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_DEAD_BAND,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_METER_OUT_FLOW,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_METER_OUT_PRESSURE_DROP,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_SPOOL_TIME_CONSTANT,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_LAMINAR_PRESSURE_DROP,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_CAVITATION_PRESSURE,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_HOSE_VOLUME_A,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_HOSE_VOLUME_B,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_OIL_BULK_MODULUS,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_HOSE_BULK_MODULUS,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_CYLINDER_BULK_MODULUS,
    CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_LEAKAGE,
    CRANE_FIELD_SLEW_DRIVE_BORE,
    CRANE_FIELD_SLEW_DRIVE_PINION_RADIUS,
    CRANE_FIELD_SLEW_DRIVE_SLEW_MIN,
    CRANE_FIELD_SLEW_DRIVE_SLEW_MAX,
    CRANE_FIELD_SLEW_DRIVE_FRICTION_COULOMB,
    CRANE_FIELD_SLEW_DRIVE_FRICTION_STATIC,
    CRANE_FIELD_SLEW_DRIVE_FRICTION_VISCOUS,
    CRANE_FIELD_SLEW_DRIVE_FRICTION_STRIBECK_VELOCITY,
    CRANE_FIELD_SLEW_DRIVE_FRICTION_FACTOR,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_VALVE,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_SUPPLY_PRESSURE,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_TANK_PRESSURE,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_RELIEF_PRESSURE,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_NOMINAL_FLOW,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_NOMINAL_PRESSURE_DROP,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_DEAD_BAND,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_METER_OUT_FLOW,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_METER_OUT_PRESSURE_DROP,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_SPOOL_TIME_CONSTANT,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_LAMINAR_PRESSURE_DROP,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_CAVITATION_PRESSURE,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_HOSE_VOLUME_A,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_HOSE_VOLUME_B,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_OIL_BULK_MODULUS,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_HOSE_BULK_MODULUS,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_CYLINDER_BULK_MODULUS,
    CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_LEAKAGE,
    CRANE_FIELD_EXTENSION_CYLINDER_BORE,
    CRANE_FIELD_EXTENSION_CYLINDER_ROD,
    CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_COULOMB,
    CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_STATIC,
    CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_VISCOUS,
    CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_STRIBECK_VELOCITY,
    CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_FACTOR,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_VALVE,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_SUPPLY_PRESSURE,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_TANK_PRESSURE,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_RELIEF_PRESSURE,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_NOMINAL_FLOW,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_NOMINAL_PRESSURE_DROP,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_DEAD_BAND,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_METER_OUT_FLOW,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_METER_OUT_PRESSURE_DROP,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_SPOOL_TIME_CONSTANT,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_LAMINAR_PRESSURE_DROP,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_CAVITATION_PRESSURE,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_HOSE_VOLUME_A,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_HOSE_VOLUME_B,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_OIL_BULK_MODULUS,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_HOSE_BULK_MODULUS,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_CYLINDER_BULK_MODULUS,
    CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_LEAKAGE,
    CRANE_FIELD_COUNT
} crane_field;

typedef struct {
    crane_real stroke[2];        /* m: [lift, tilt] */
    crane_real stroke_rate[2];   /* m/s; 0 = at rest; must be 0 for a held cylinder */
    crane_real slew;             /* psi, rad, about the vertical axis */
    crane_real extension;        /* e, m */
    crane_real slew_rate;        /* rad/s; must be 0 when the slew is held */
    crane_real extension_rate;   /* m/s; must be 0 when the extension is held */
    /* A valve-driven actuator's chamber pressures (Pa gauge, in [CRANE_CHAMBER_PRESSURE_MIN,
     * CRANE_PRESSURE_MAX]) and spool position (in [-1, 1]; read only with a spool lag), per joint
     * [lift, tilt, slew, extension]. */
    crane_real p_a[4], p_b[4], spool[4];
} crane_state;

typedef struct {
    int mode;                    /* CRANE_DRIVE_HOLD (0), _PRESSURE or _VALVE */
    crane_real p_a;              /* bore-side pressure, Pa (used when n_samples == 0) */
    crane_real p_b;              /* rod-side pressure, Pa */
    const crane_real *t;         /* n_samples sample times, s, strictly increasing */
    const crane_real *p_a_samples;
    const crane_real *p_b_samples;
    size_t n_samples;            /* 0: constant pressures (or lever) */
    crane_real u;                /* CRANE_DRIVE_VALVE: the lever in [-1, 1] (n_samples == 0) */
    const crane_real *u_samples; /* CRANE_DRIVE_VALVE: the lever at the times t */
} crane_drive;

/* How a future is integrated (docs/model.md, "Integration"). All zero is the default: error
 * control at the default tolerances, dt the sample interval, with the ROS34PW2 Rosenbrock-W
 * method for a stiff future (a valve drive, a moving telescope) and the explicit pair DOPRI5(4)
 * for the others (in a build with -DCRANE_ROSW=0: RK4). CRANE_METHOD_ROSW and
 * CRANE_METHOD_DOPRI5 ask for one of the two by name. CRANE_METHOD_RK4 is fixed-step RK4 with step
 * dt (the fixed cost per call that the embedded worst case is stated for); the tolerances are not
 * read then. */
typedef struct {
    int method;                  /* CRANE_METHOD_DEFAULT (0), CRANE_METHOD_ROSW, CRANE_METHOD_RK4,
                                    CRANE_METHOD_DOPRI5 (no valve drive: else CRANE_E_METHOD) */
    crane_real tip_tolerance;    /* m of tip position per step; 0: CRANE_TIP_TOLERANCE; else in
                                    [1e-9, 1] */
    crane_real pressure_tolerance; /* Pa of chamber pressure per step; 0: CRANE_PRESSURE_TOLERANCE;
                                    else in [1, 1e7] */
} crane_solver;

typedef struct {
    crane_drive drive[4];        /* [CRANE_LIFT], [CRANE_TILT], [CRANE_SLEW], [CRANE_EXTENSION];
                                    a zero drive is a hold */
    crane_solver solver;         /* zero: the default method and tolerances */
} crane_inputs;

typedef struct {
    crane_real t;                /* s */
    crane_real stroke[2];        /* m */
    crane_real theta[2];         /* rad: lift angle, tilt angle relative to the lift boom */
    crane_real omega[2];         /* rad/s */
    crane_real slew;             /* psi, rad */
    crane_real extension;        /* e, m */
    crane_real slew_rate;        /* rad/s */
    crane_real extension_rate;   /* m/s */
    crane_real tip[3];           /* world, m */
    /* Per joint [lift, tilt, slew, extension]: */
    int stop[4];                 /* -1 at the start of the actuator's range (stroke_min; slew_min;
                                    extension_min), +1 at its end, 0 otherwise; held: 0 */
    crane_real p_a[4], p_b[4];   /* Pa: valve: the chamber pressures; pressure drive: the given
                                  * ones at t; held: 0 */
    crane_real flow_a[4];        /* m^3/s: the valve's flow into the bore side (0 unless valve) */
    crane_real flow_b[4];        /* m^3/s: the valve's flow out of the rod side (0 unless valve) */
    crane_real spool[4];         /* the spool position (0 unless valve-driven) */
} crane_sample;

/* Derived constants of one crane at one extension e (docs/model.md's symbols): filled by
 * crane_model_init, read-only after. The struct is public so that a C caller can own it (on the
 * stack, in static memory); its fields are the core's, not an interface: the Python binding
 * declares it opaque (only its size is known there), so its layout may change. It keeps only the
 * parameters that predictions and the queries read (not a copy of crane_params), and refers to
 * the params for those it reads unchanged: keep params alive and unchanged while the model is used
 * (crane_model_init). A model is held on the stack by crane_predict and crane_predict_many, whose
 * budget on a small target (docs/embedding.md) is why it refers rather than copies. */
typedef struct {
    const crane_params *params;            /* p: gravity, the points O1, B1, E1, B2, P1, O2, the
                                              link2_attach A, extension_mount and tip_distance
                                              (the tip), each cylinder's length_retracted, stroke
                                              range, friction and circuit, the lift boom's inertia
                                              are read from it */
    crane_real extension;                  /* e, the argument of crane_model_init */
    /* Lift triangle: */
    crane_real lift_db;                    /* db = |B1 - O1| */
    crane_real lift_dr;                    /* dr = |E1| */
    /* Tilt four-bar: */
    crane_real tilt_l1;                    /* l1 = |p.link_pin| */
    crane_real tilt_l2;                    /* l2 = |p.link2_end| */
    crane_real tilt_branch;                /* -sign(cross(Q - P1, A - Q)), constant over the
                                              stroke: the side of P1 -> A on which angle ->
                                              stroke finds Q (+1 left, the PATU's) */
    /* Bodies (body 2 lumped at e: docs/model.md, "Bodies and the lumped outer boom"): */
    crane_real m2;                         /* m2 = m_ob + m_ext + m_load (m1 = p.lift_boom.mass) */
    crane_real i2;                         /* I2 about c2, parallel axes (I1 = p.lift_boom.izz) */
    crane_vec2 c2;                         /* c2 = (m_ob c_ob + m_ext x_ext + m_load x_tip) / m2,
                                              outer boom frame (c1 = p.lift_boom.com) */
    crane_real theta_min[2], theta_max[2]; /* angle limits: theta at the two stroke limits,
                                              ordered (docs/model.md, "End stops") */
    crane_real lift_cos_off, lift_sin_off; /* cos, sin of (eps - beta) */
    crane_real j2;                         /* I2 + m2 |c2|^2 */
    int links;                             /* 1 if a side link has mass or inertia, else 0 */
    crane_real link_ca[2], link_cb[2];     /* side links 1, 2 (their mass and Izz: p.side_link1,
                                              p.side_link2): com = ca v + cb perp(v) with
                                              v = link_pin (link 1),
                                              link2_end (link 2): ca = com.v / |v|^2,
                                              cb = cross(v, com) / |v|^2 */
} crane_model;

/* The crane's rules, the one validator of a crane (the Python layer and tools/crane2header.py call
 * it too): every field's range, then the lift triangle and the tilt four-bar over their whole
 * stroke ranges (docs/model.md, "Bad input"). Returns CRANE_OK or the status of the first rule
 * broken; then, if field is not NULL, *field names the field at fault: the field itself for a
 * range, for the lift triangle or the four-bar the point or stroke limit at which it fails.
 * CRANE_FIELD_NONE only with CRANE_OK or CRANE_E_NULL. */
crane_status crane_params_check(const crane_params *params, crane_field *field);

/* The rule a field must keep, in the crane file's terms (e.g. "> 0", "> rod"; a static string;
 * "" for CRANE_FIELD_NONE or an unknown code). */
const char *crane_field_rule(crane_field field);

/* crane_params_check, then the extension against [extension_min, extension_max], then derives
 * the model constants. On an error *model is left untouched. */
/* The model refers to *params (the parameters it reads unchanged, the cylinders' hydraulics),
 * so that a model on a small stack stays small: keep params alive and unchanged while the model is
 * used. */
crane_status crane_model_init(crane_model *model, const crane_params *params, crane_real extension);

/* The default solver with its numbers filled in: CRANE_METHOD_DEFAULT (CRANE_METHOD_RK4 in a
 * build without the error-controlled methods) at the default tip and pressure tolerances (what a
 * zero crane_solver means). */
crane_status crane_solver_default(crane_solver *solver);

/* Number of samples a prediction writes: ceil(horizon/dt - 1e-9) + 1. */
crane_status crane_sample_count(crane_real horizon, crane_real dt, size_t *count);

/* ---- The core's working storage ----
 * A prediction's working data (crane_work): the integrator's context and the state vectors of its
 * steps (the float build on a Cortex-M4F: 1,248 bytes, 304 with RK4 only), in the caller's memory
 * (static, a task's data, the heap of a desktop program), not on the stack: a controller's task
 * stack is small (docs/embedding.md, "Footprint"). One crane_work per concurrent call, apart
 * from the call's other arguments; a call writes everything it reads of it, so it needs no
 * initialisation and carries nothing from one call to the next. Its fields are the core's, not
 * an interface: the Python binding declares it opaque (only its size is known there), so its
 * layout may change. The types below are its parts, named as the core's (crane__). */
/* CRANE_WORK_BEGIN */
/* The error-controlled method (ROS34PW2, docs/model.md "Integration") is compiled in unless
 * CRANE_ROSW is defined to 0: a build for a controller that needs the fixed cost and the smaller
 * code and working storage of RK4 (docs/embedding.md); there the default method is RK4 and
 * CRANE_METHOD_ROSW is refused (CRANE_E_METHOD). Define it alike for the core and its callers:
 * crane_work's size depends on it. */
#ifndef CRANE_ROSW
#define CRANE_ROSW 1
#endif

/* The state's entries: q[4], qd[4] (lift, tilt, slew, extension), then with valve-driven
 * actuators joint j's p_a, p_b and spool at CRANE__NMECH + 3j (integrator.c). */
enum { CRANE__NX = 20, CRANE__NMECH = 8 };

typedef struct {
    crane_real v[CRANE__NX];
} crane__vector;

/* The four-bar at one tilt angle (docs/model.md, "Tilt kinematics", "Side links"), in the lift
 * boom frame: the pins Q and A, the stroke and ds/dtheta1, and the side links' terms of ID reduced
 * to what depends on theta1 alone. Per link (mass m, Izz I), with its centre of mass d, its velocity
 * relative to the lift boom per unit tilt rate v, its relative acceleration per unit squared tilt
 * rate at zero tilt acceleration w (so the relative acceleration is alpha1 v + omega1^2 w), k =
 * dphi/dtheta1 and g = ddphi per unit squared tilt rate (ddphi = k alpha1 + g omega1^2), the sums
 * over both links are: M (their share of M00, M01, M11), md = sum m d, mv = sum m v,
 * huu = (sum m cross(d, w) + I g, sum m w.v + I g k), dv = sum m d.v. The links' torques are then
 * (gl = gravity in the lift boom frame, w1 = omega0, u = omega1)
 *   tau0 = M00 alpha0 + M01 alpha1 + cross(md, gl) + huu0 u^2 + 2 dv w1 u,
 *   tau1 = M01 alpha0 + M11 alpha1 + mv.gl + huu1 u^2 - dv w1^2. */
typedef struct {
    crane_vec2 q, a;
    crane_real stroke, ds;
    crane_real M[3];
    crane_vec2 md, mv;
    crane_real huu[2], dv;
} crane__tilt_kin;

/* The spatial kernel's constants of one crane (independent of the extension): body 3 = the
 * extension boom + the load, lumped in the extension boom frame (mass, centre, izz, in-plane tensor
 * ixx, iyy, ixy), and the pillar's share of the slew inertia m com.x^2 + iyy. */
typedef struct {
    crane_real m3, izz3, t3[3], jp;
    crane_vec2 c3;
} crane__bodies;

/* What the kernels read of one configuration (theta0, theta1, e), computed once for all of them:
 * trig of theta0, theta1 and theta0 + theta1, the extension and the four-bar (which the planar
 * kernel reads only with side links). The rotated arms (C1 = R(th0) c1 and the like) and the
 * side links one by one are each reader's to work (dynamics.c): this struct is in every
 * crane_work (the caller's memory): its size is the caller's RAM. */
typedef struct {
    crane_real c0, s0, c1, s1, c01, s01, e;
    crane__tilt_kin tk;
} crane__conf;

/* The relief and anti-cavitation valves of a prediction: its model, the valve-driven actuators
 * (bit j: actuator j) and their chambers' rates G_lim/C(V) at the current substep's start
 * (crane__substeps; coef[2j], coef[2j + 1]). In each integrator's context. */
typedef struct {
    const crane_model *m;
    crane_real coef[8];
    unsigned valves;
} crane__limits;

/* Everything the accelerations need at (t, x): the configuration (the mass matrix is worked from
 * it where it is solved), J_z and the net generalized forces b = tau - h; and what the
 * configuration was worked at, so that the next evaluation at the same angles (a sample, the next
 * step's release check and first RK4 stage) or the same tilt angle (a tilt held or stopped) reuses
 * it instead of evaluating the same trig and four-bar again. */
typedef struct {
    crane__conf cf;
    crane_real jz, b[4];
    crane_real key_th[2];
} crane__dyn;

#if CRANE_ROSW
/* The Jacobian J of the W-method at a step's start: the stiff parts of f exactly, the rest left
 * out (a W-method keeps its order with any J): the chambers' slopes (crane__chamber_jacobian),
 * the oil spring's coupling of the pressures and the joint rates, the friction's damping, the
 * spool's pole and the valve's gain. Not the slopes through the configuration (gravity,
 * volumes, the mass matrix's change), which are slow. */
typedef struct {
    crane_real mp[6], jz;     /* the kernel's mass matrix (mass) and J_z */
    crane_real ds[4];         /* ds/dq */
    crane_real fr[4];         /* ds^2 max(dF/dv, 0): the friction's damping of the joint */
    crane_real ch[4][8];      /* each valve-driven actuator's crane__chamber_jacobian */
    crane_real area[4][2];    /* A_a ds, -A_b ds: its force's slopes in the pressures, in q terms */
    crane_real spool[4];      /* 1 / tau of its spool (0 without a lag) */
} crane__wjac;
#endif

/* The integrator's context of one prediction (integrator.c) and its steps' vectors. */
typedef struct {
    const crane_inputs *in;
    const crane_state *s0;      /* held joints report their initial strokes */
    /* the model (lim.m) and the relief and anti-cavitation valves (crane__limit_valves);
     * lim.valves bit j: joint j is valve-driven (some is: the state carries pressures and
     * spools) */
    crane__limits lim;
    crane__bodies b;            /* the spatial kernel's constants */
    size_t cursor[4];           /* sample segment last used, per joint */
    /* The one scratch of every evaluation of the dynamics (RK4's stages, the release rule, the
     * impacts, the substep count), which never overlap. */
    crane__dyn d;
    signed char mode[4];        /* CRANE__FREE, _HELD, _STOP_LO, _STOP_HI (in q terms) */
    /* Bit j: joint j's lower limit of q is its actuator's stroke_max (stop flag +1 there; else
     * -1). */
    unsigned char lo_is_max;
    unsigned char planar;       /* the planar kernel: slew and extension held */
    unsigned char cache;        /* which of d is valid (integrator.c) */
    /* The last step ended with the release rule run at its end (the next step's start time and
     * state) releasing nothing: the release at the next step's start would repeat it exactly. */
    unsigned char release_clear;
    crane__vector x;            /* the state */
#if CRANE_ROSW
    /* The error-controlled method (ROS34PW2): the relief and anti-cavitation valves are rates
     * (crane__limit_rates) instead of RK4's implicit update. */
    unsigned char rosw;
    /* ... with the explicit pair DOPRI5(4) instead of ROS34PW2 (a future without valve drives:
     * no oil, no chambers) */
    unsigned char dopri;
    /* bit 2j + side: that chamber's relief or anti-cavitation valve is open over the step
     * (limits_open) */
    unsigned char open;
    /* bit 2j + side: that chamber's vacuum floor is in J over the step (floors_in) */
    unsigned char floor;
    /* its tolerances: tip metres over the crane's reach (angles), tip metres (the extension),
     * Pa (the pressures) */
    crane_real tol_q, tol_tip, tol_p;
    /* the rates at the step's start, the step's end and its rates, the rates at a stage's point
     * (the explicit pair's last stage) */
    crane__vector f0, x1, f1, fs;
    crane__vector stage[4];     /* ROS34PW2's stages */
    /* A prediction runs one method: their working data share the storage. */
    union {
        crane__wjac J; /* ROS34PW2's matrix at the step's start (w_matrix) */
        struct {
            /* the explicit pair's stages k1..k6 of the step last taken (k7 is its end's rates),
             * for its dense output */
            crane_real k[6][CRANE__NMECH];
            /* and its dense output's coefficients over the step last taken
             * (dense_coefficients) */
            crane_real d[3][CRANE__NMECH];
        } dp;
    } work;
#endif
} crane_work;
/* CRANE_WORK_END */

/* Predicts the motion from state0 under the inputs over [0, horizon] and samples it every dt
 * (the last sample at the horizon), integrated by inputs->solver: by default with error control
 * to its tolerances, its steps independent of dt (the samples by dense output); with
 * CRANE_METHOD_RK4 by fixed RK4 steps of dt; in the caller's working storage *work (crane_work:
 * one per concurrent call; what it holds on return is not a result). Writes *n_written samples
 * (t = 0 first) into out[0..capacity).
 * CRANE_E_DIVERGED is the one error after which samples have been written: if the state stops
 * being finite or a valve-driven actuator leaves the physical domain (a spool beyond [-1, 1], a
 * chamber above CRANE_PRESSURE_MAX: possible only with absurd parameters, e.g. gravity 1e135) the
 * prediction stops there, *n_written is the number of samples before it (all finite and
 * physical; may be 0); nothing non-finite is ever written and what lies beyond *n_written is not
 * a result. Every other error writes nothing. */
crane_status crane_predict(const crane_params *params, const crane_state *state0,
                           const crane_inputs *inputs, crane_real horizon, crane_real dt,
                           crane_sample *out, size_t capacity, size_t *n_written,
                           crane_work *work);

/* crane_predict with a model from crane_model_init: the crane's checks and derived constants
 * (which depend only on the crane file and the extension) are done once by the caller instead of
 * on every call. state0->extension must equal the model's extension (else CRANE_E_EXTENSION).
 * The results are identical to crane_predict's. */
crane_status crane_predict_model(const crane_model *model, const crane_state *state0,
                                 const crane_inputs *inputs, crane_real horizon, crane_real dt,
                                 crane_sample *out, size_t capacity, size_t *n_written,
                                 crane_work *work);

/* One control period: advances *state by period (s) under the inputs with crane_predict_model's
 * integration (inputs->solver: with RK4, steps of dt <= period, the last step of the period up to
 * 1.25 dt long; with error control, steps of its own from the period's start; end stops,
 * valves), writes the samples at the period's start and end to out[0] and out[1] (t = 0 and
 * t = period) and the state at its end to *next (which may be state): the strokes, slew, extension
 * and their rates (a boom cylinder's stroke rate is omega ds/dtheta at its stroke, 0 on a stop or
 * held), every actuator's chamber pressures and spool (docs/model.md, "Continuing from a
 * prediction"). Chained under constant drives, the calls continue one prediction: with RK4 the
 * samples at the periods' ends are those of one prediction over their sum, to the rounding of the
 * stroke <-> angle conversion; with error control each period steps from its own start, so they
 * agree with it to the method's accuracy. As crane_predict_model, the model must be the one at
 * state->extension (a telescope that has moved needs a model made at its new extension:
 * crane_model_init); sampled drives' times count from the period's start. Every error of
 * crane_predict_model with period as the horizon (CRANE_E_HORIZON if period <= 0, CRANE_E_DT if
 * dt <= 0 or dt > period, ...); on an error nothing is written, except CRANE_E_DIVERGED (out[0]
 * may have been written, *next not). */
crane_status crane_step(const crane_model *model, const crane_state *state,
                        const crane_inputs *inputs, crane_real period, crane_real dt,
                        crane_state *next, crane_sample out[2], crane_work *work);

/* Number of samples a prediction writes when it keeps only the sample at t = 0, the one after
 * every sample_every-th step (sample_every >= 1) and the one after the last step: with
 * n = ceil(horizon/dt - 1e-9) steps, floor(n / sample_every) + (n % sample_every != 0) + 1. */
crane_status crane_sample_count_every(crane_real horizon, crane_real dt, size_t sample_every,
                                      size_t *count);

/* Many futures in one call: future k starts from states[k] under inputs[k] with the crane
 * params[0] (n_params = 1: one crane for all) or params[k] (n_params = n_futures: a crane per
 * future, e.g. the load, friction or pressures of a parameter sweep; each is checked with its
 * future); any other n_params is CRANE_E_PARAMS. All share horizon, dt and sample_every (1 = every
 * step, as crane_predict). Its samples go to
 * out[k * stride .. k * stride + count), count = crane_sample_count_every(horizon, dt,
 * sample_every), which must be <= stride. Every future is validated before anything is written;
 * on an error *failed is the index of the first bad future (n_futures for an error in the shared
 * arguments) and nothing is written; except CRANE_E_DIVERGED (see crane_predict): then futures
 * 0 .. *failed - 1 are complete, future *failed holds some finite samples and the rest nothing.
 * No heap, no threads: to use several cores, call it on disjoint slices of the batch from several
 * threads, each with its own crane_work (it touches nothing but its arguments).
 * The samples of each future are identical to crane_predict's (at the kept steps). */
crane_status crane_predict_many(const crane_params *params, size_t n_params, size_t n_futures,
                                const crane_state *states, const crane_inputs *inputs,
                                crane_real horizon, crane_real dt, size_t sample_every,
                                crane_sample *out, size_t stride, size_t *failed,
                                crane_work *work);

/* Kinematics of one joint (joint = CRANE_LIFT or CRANE_TILT). */
crane_status crane_joint_angle(const crane_model *model, int joint, crane_real stroke,
                               crane_real *theta, crane_real *dstroke_dtheta);
crane_status crane_joint_stroke(const crane_model *model, int joint, crane_real theta,
                                crane_real *stroke);

/* World positions (x, y, z) of the crane's points for n poses: theta is n x 2, xyz is
 * n x CRANE_N_POINTS x 3, in the order: pillar_base, lift_pivot, lift_cylinder_base,
 * lift_cylinder_rod, tilt_cylinder_base, link1_pivot, link_pin, link2_attach, tilt_pivot,
 * extension_mount, tip. Every angle must lie within its limits (CRANE_E_ANGLE); an n whose arrays
 * would not fit a size_t gives CRANE_E_OVERFLOW. */
crane_status crane_points(const crane_model *model, crane_real slew, size_t n,
                          const crane_real *theta, crane_real *xyz);

/* Newton-Euler inverse dynamics (docs/model.md, "Dynamics", "Four joints"): the generalized
 * forces over [lift, tilt, slew, extension] (N m, N m, N m, N) for q = (theta0, theta1, psi, e),
 * rates qd and accelerations qdd, gravity included; the slew's row is J_z qdd_s + Jdot_z omega_s
 * (the mass matrix is block diagonal). The model's own extension is not used: e is q[3]. theta within the angle
 * limits (CRANE_E_ANGLE), e within [extension_min, extension_max] (CRANE_E_EXTENSION); psi any
 * finite value (nothing depends on it); forces too large to be finite give CRANE_E_OVERFLOW. */
crane_status crane_inverse_dynamics(const crane_model *model, const crane_real q[4],
                                    const crane_real qd[4], const crane_real qdd[4],
                                    crane_real tau[4]);

/* Cylinder force along its axis (positive extends) at pressures p_a, p_b and stroke rate v;
 * CRANE_E_OVERFLOW if it is not finite (a stroke rate near the largest real). */
crane_status crane_cylinder_force(const crane_model *model, int joint, crane_real p_a,
                                  crane_real p_b, crane_real stroke_rate, crane_real *force);

/* A short English description of a status code (a static string). */
const char *crane_status_message(crane_status status);
/* ---- Collision guard (docs/guard.md): solids, exact distances, the crane's shape, the verdict ----
 * A solid is a half-space, an oriented box or a segment grown by a radius (capsule, sphere, and a
 * cylinder, whose distances are those of its capsule: conservative, never larger than the true
 * one). Distances are between surfaces, 0 when solids touch or overlap. */
enum { CRANE_SOLID_PLANE = 0, CRANE_SOLID_BOX = 1, CRANE_SOLID_CAPSULE = 2, CRANE_SOLID_SPHERE = 3,
       CRANE_SOLID_CYLINDER = 4 };
/* The field of a solid or part at fault (crane_solid_check, crane_guard_check). */
enum { CRANE_GUARD_FIELD_KIND = 1, CRANE_GUARD_FIELD_A = 2, CRANE_GUARD_FIELD_B = 3,
       CRANE_GUARD_FIELD_RADIUS = 4, CRANE_GUARD_FIELD_AXES = 5, CRANE_GUARD_FIELD_HALF = 6,
       CRANE_GUARD_FIELD_DROP = 7 };
/* Frames a part's points are given in (docs/model.md "Frames"): the boom plane, the lift boom,
 * the pin Q of the side links (a point given relative to Q, in lift boom axes), the outer boom, the
 * extension boom. */
enum { CRANE_FRAME_BASE = 0, CRANE_FRAME_LIFT = 1, CRANE_FRAME_LINK_PIN = 2, CRANE_FRAME_OUTER = 3,
       CRANE_FRAME_EXTENSION = 4 };
enum { CRANE_GO = 0, CRANE_WARN = 1, CRANE_STOP = 2 };
/* The largest coordinate or size a solid or part may have, m: a site, not the globe (squares of
 * lengths stay far from overflow in float). */
enum { CRANE_GUARD_LENGTH_MAX = 1000000 };

typedef struct {
    int kind;                    /* CRANE_SOLID_* */
    crane_real a[3];             /* plane: a point of it; box, sphere: centre; capsule, cylinder: axis end */
    crane_real b[3];             /* plane: unit normal out of the solid; capsule, cylinder: other axis end */
    crane_real radius;           /* capsule (>= 0), sphere and cylinder (> 0), m */
    crane_real axes[9];          /* box: rows are its unit axes (orthonormal) in the world frame */
    crane_real half[3];          /* box: half extents along its axes, > 0, m */
} crane_solid;

typedef struct {
    int frame;                   /* CRANE_FRAME_* */
    crane_vec2 at;               /* m, in that frame */
} crane_anchor;

typedef struct {
    int kind;                    /* CRANE_SOLID_CAPSULE, CRANE_SOLID_SPHERE or CRANE_SOLID_BOX */
    crane_anchor a, b;           /* capsule: axis ends; sphere, box: a is where it hangs (b unused) */
    crane_real radius;           /* capsule (>= 0), sphere (> 0), m */
    crane_real drop;             /* sphere, box: centre this far below a (world vertical), m */
    crane_real half[3];          /* box: half extents (outward in the boom plane, lateral, up), m */
} crane_part;

typedef struct {
    crane_real margin;           /* clearance below which the guard calls it a contact, m, >= 0 */
    crane_real reaction;         /* delay from the stop decision to the stop, s, >= 0 */
    crane_real cycle;            /* control cycle, s, > 0: STOP if stopping cannot wait one more */
    crane_real time_tolerance;   /* the first contact is located within this, s, > 0 (at least
                                    1e-3 of the samples' spacing is used) */
    crane_real clearance_tolerance; /* per-part minima may be this much too large, m, >= 0 */
} crane_guard_config;

typedef struct {
    int signal;                  /* CRANE_GO, CRANE_WARN or CRANE_STOP */
    int contact;                 /* 1: the clearance falls below the margin within the horizon */
    int at_start;                /* 1: it is below the margin at t = 0 already */
    crane_real t;                /* first contact, s: the clearance is >= margin on [0, t) */
    int part, obstacle;          /* the pair at the first contact */
    crane_real clearance;        /* their clearance at t, m */
    crane_real on_part[3];       /* the closest points at t, world, m */
    crane_real on_obstacle[3];
    crane_real theta[2];         /* joint angles at t, rad */
    crane_real slew, extension;  /* at t, rad and m */
    crane_real gradient[4];      /* d clearance / d q_j of the pair at t, q = [lift angle, tilt
                                    angle, slew, extension]: m/rad (m/m for the extension) */
    crane_real approach[4];      /* gradient_j * dq_j/dt at t, m/s: < 0 = joint j closes the gap */
    crane_real stop_latest;      /* latest time to begin stopping, s (t - reaction; < 0: too late) */
    size_t evaluations;          /* pair distances computed */
} crane_guard_result;

/* The checks of one solid: CRANE_E_SOLID with *field = the CRANE_GUARD_FIELD_* at fault, else 0. */
crane_status crane_solid_check(const crane_solid *solid, int *field);

/* Exact distance between two solids (any pair but two planes) and the closest points. */
crane_status crane_solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                                  crane_real on_a[3], crane_real on_b[3]);

/* Checks the parts and the obstacles; on an error *which is the index of the bad part (CRANE_E_PART)
 * or obstacle (CRANE_E_SOLID) and *field its CRANE_GUARD_FIELD_*. */
crane_status crane_guard_check(const crane_part *parts, size_t n_parts, const crane_solid *obstacles,
                               size_t n_obstacles, size_t *which, int *field);

/* The parts as world solids at one pose (for drawing and tests): out[n_parts]. The extension
 * (m, within the crane's range) places the parts in the extension boom frame. */
crane_status crane_part_solids(const crane_model *model, const crane_part *parts, size_t n_parts,
                               crane_real slew, crane_real extension, const crane_real theta[2],
                               crane_solid *out);

/* Scratch reals per part of crane_guard, beyond one per obstacle. */
enum { CRANE_GUARD_PART_WORK = 7 };

/* The verdict on a predicted future (samples from crane_predict_model of the same crane: each
 * sample's joint angles, slew, extension and their rates pose the parts): per-part minimum
 * clearance over the samples (part_clearance[n_parts]), the first contact, between samples too
 * (docs/guard.md, "Nothing is missed"), the stop analysis for a stop that freezes the crane after
 * config->reaction, and the signal. work is scratch of n_parts * (n_obstacles +
 * CRANE_GUARD_PART_WORK) reals (CRANE_E_CAPACITY if work_capacity is smaller). Nothing is written
 * on an error. */
crane_status crane_guard(const crane_model *model, const crane_part *parts, size_t n_parts,
                         const crane_solid *obstacles, size_t n_obstacles,
                         const crane_sample *samples, size_t n_samples,
                         const crane_guard_config *config, crane_real *part_clearance,
                         crane_real *work, size_t work_capacity, crane_guard_result *result);
/* ---- State estimation (docs/live.md, "The estimator"): an extended Kalman filter ----
 * The estimated fields, in this order: the positions (lift stroke, tilt stroke, slew, extension),
 * their rates (CRANE_EST_RATES + joint), the chamber pressures (CRANE_EST_PRESSURES + 2 joint for
 * the bore side p_a, + 1 for the rod side p_b). SI units: m, rad, m/s, rad/s, Pa. */
enum { CRANE_EST_N = 16, CRANE_EST_LIFT_STROKE = 0, CRANE_EST_TILT_STROKE = 1, CRANE_EST_SLEW = 2,
       CRANE_EST_EXTENSION = 3, CRANE_EST_RATES = 4, CRANE_EST_PRESSURES = 8 };

typedef struct {
    crane_real lo[CRANE_EST_N], hi[CRANE_EST_N]; /* each field's valid domain, lo < hi */
    crane_real noise[CRANE_EST_N];   /* process noise density, (unit)^2 / s, >= 0 */
    crane_real fd_step[CRANE_EST_N]; /* the Jacobian's finite-difference step, unit, > 0 */
    crane_real scale[CRANE_EST_N];   /* the field's scale, > 0: the covariance's eigenvalues are
                                        floored at 1e-12 in these units */
    crane_real dt;                   /* the model's RK4 step, s, > 0 (the period if shorter) */
    int jacobian_columns;            /* the Jacobian's columns renewed per update, in turn, 1 to
                                        CRANE_EST_N (0: all of them, every update); the first
                                        update after init renews all */
} crane_estimator_config;

/* The estimator and its scratch, caller-owned (no heap; sizeof: docs/embedding.md). After an
 * error of crane_estimator_update other than a bad argument, initialise it again. */
typedef struct {
    crane_estimator_config config;
    crane_real x[CRANE_EST_N];       /* the estimate */
    crane_real covariance[CRANE_EST_N * CRANE_EST_N]; /* row-major */
    crane_real spool[4];             /* the spools the model carries (not estimated) */
    crane_real nis;                  /* the last update's normalised innovation squared */
    crane_real field_nis[CRANE_EST_N]; /* per measured field, innovation^2 / S_ii (else 0) */
    int n_measured;                  /* fields measured in the last update */
    int projected;                   /* 1: the last estimate was projected into the domain */
    crane_real jacobian[CRANE_EST_N * CRANE_EST_N]; /* the model's Jacobian, row-major: each
                                        column as of the update that last renewed it */
    int next_column;                 /* the first column the next update renews */
    int jacobian_ready;              /* 1 once every column has been computed */
    /* scratch of an update */
    crane_real step[CRANE_EST_N], y0[CRANE_EST_N];
    int rows[CRANE_EST_N];
    crane_state futures[CRANE_EST_N + 1];
    crane_inputs inputs[CRANE_EST_N + 1];
    crane_sample samples[2 * (CRANE_EST_N + 1)];
    crane_real a[CRANE_EST_N * CRANE_EST_N], b[CRANE_EST_N * CRANE_EST_N],
        k[CRANE_EST_N * CRANE_EST_N];
    crane_work work;                 /* its predictions' working storage */
} crane_estimator;

/* Starts the estimator at x0 (inside the config's domain) with covariance0 (made symmetric
 * positive definite as after every update) and the spools spool0 (in [-1, 1]). */
crane_status crane_estimator_init(crane_estimator *est, const crane_estimator_config *config,
                                  const crane_real x0[CRANE_EST_N],
                                  const crane_real covariance0[CRANE_EST_N * CRANE_EST_N],
                                  const crane_real spool0[4]);

/* One cycle: the estimate predicted over period (s, > 0) under inputs (the levers of the period;
 * a held joint's rate is 0 and its pressures are kept), its covariance by the model's Jacobian,
 * then updated with the measured fields: z[i] with variance[i] > 0 (Pa^2, m^2, ...); variance 0 =
 * not measured. model: the crane's (crane_model_init at any extension); its params predict. */
crane_status crane_estimator_update(crane_estimator *est, const crane_model *model,
                                    const crane_inputs *inputs, crane_real period,
                                    const crane_real z[CRANE_EST_N],
                                    const crane_real variance[CRANE_EST_N]);
/* CRANE_CDEF_END */

#endif /* CRANE_H */
