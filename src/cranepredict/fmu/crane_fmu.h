/* SPDX-License-Identifier: MIT */
/*
 * The crane as a co-simulation unit, independent of the FMI version: an instance owns its crane
 * parameters, its model and its snapshot (time, state, last sample, the values set), and advances
 * with crane_step. fmi3_crane.c and fmi2_crane.c put the FMI 3.0 and 2.0 interfaces over it.
 * The exported FMU's variables, drive and crane come from crane_fmu_config.h, which
 * cranepredict.fmu writes at export (docs/fmu.md).
 */
#ifndef CRANE_FMU_H
#define CRANE_FMU_H

#include <stddef.h>
#include "crane.h"

/* What a variable is (the export's table maps each value reference to one of these). */
typedef enum {
    /* inputs */
    Q_LIFT_LEVER, Q_TILT_LEVER, Q_SLEW_LEVER, Q_EXTENSION_LEVER,
    Q_LIFT_P_A_IN, Q_LIFT_P_B_IN, Q_TILT_P_A_IN, Q_TILT_P_B_IN,
    /* parameters */
    Q_LOAD_MASS, Q_LIFT_STROKE_START, Q_TILT_STROKE_START, Q_SLEW_START, Q_EXTENSION_START,
    Q_STEP, Q_LIFT_HOLD, Q_TILT_HOLD, Q_GUARD_HORIZON,
    /* outputs */
    Q_TIP_X, Q_TIP_Y, Q_TIP_Z,
    Q_LIFT_STROKE, Q_TILT_STROKE, Q_LIFT_STROKE_RATE, Q_TILT_STROKE_RATE,
    Q_LIFT_ANGLE, Q_TILT_ANGLE, Q_LIFT_ANGLE_RATE, Q_TILT_ANGLE_RATE,
    Q_SLEW, Q_SLEW_RATE, Q_EXTENSION, Q_EXTENSION_RATE,
    Q_LIFT_P_A, Q_LIFT_P_B, Q_TILT_P_A, Q_TILT_P_B,
    Q_SLEW_P_A, Q_SLEW_P_B, Q_EXTENSION_P_A, Q_EXTENSION_P_B,
    Q_LIFT_STOP, Q_TILT_STOP, Q_SLEW_STOP, Q_EXTENSION_STOP,
    Q_GUARD_SIGNAL, Q_TIME_TO_CONTACT, Q_MIN_CLEARANCE, Q_STOP_LATEST,   /* with a world */
    Q_TIME,        /* the independent variable */
    Q_COUNT
} cfmu_quantity;

enum { CFMU_FLOAT64 = 0, CFMU_INT32 = 1, CFMU_BOOLEAN = 2 };
/* How a variable may be set: never (an output), any time (an input, a tunable parameter), or
 * only before the initialization ends (a fixed parameter). */
enum { CFMU_OUTPUT = 0, CFMU_INPUT = 1, CFMU_TUNABLE = 2, CFMU_FIXED = 3 };

typedef struct {
    cfmu_quantity quantity;
    int type;      /* CFMU_FLOAT64, _INT32, _BOOLEAN */
    int set;       /* CFMU_OUTPUT, _INPUT, _TUNABLE, _FIXED */
} cfmu_variable;

/* Everything a run depends on, plain data (get/set state, serialization: a copy of it). */
typedef struct {
    unsigned magic;            /* CFMU_MAGIC: a serialized snapshot of this FMU */
    unsigned size;             /* sizeof(cfmu_snapshot) */
    double time;
    int initialized;           /* the initialization has ended: state and sample hold values */
    double value[Q_COUNT];     /* the inputs and parameters as set (outputs unused) */
    crane_state state;
    crane_sample sample;       /* at time: the outputs */
    /* with a world: the guard's verdict on the future from time under the inputs then */
    int signal;                /* CRANE_GO, CRANE_WARN, CRANE_STOP */
    double time_to_contact;    /* s from time; the guard horizon if no contact */
    double min_clearance;      /* m, over the parts and the horizon */
    double stop_latest;        /* s from time: the latest time to begin stopping; the horizon if
                                  no contact */
} cfmu_snapshot;

enum { CFMU_MAGIC = 0x43524e46u };

typedef void (*cfmu_logger)(void *env, int error, const char *message);

typedef struct {
    cfmu_snapshot s;
    crane_params params;
    crane_model model;
    int model_valid;           /* model is at params (load_mass) and s.state.extension */
    cfmu_logger log;
    void *log_env;
    /* the guard's scratch (heap, made at the end of the initialization; not state) */
    crane_sample *future;
    size_t future_capacity;
    crane_real *work, *part_clearance;
    crane_work prediction;     /* the predictions' working storage (not state) */
} cfmu_instance;

/* The export's configuration (crane_fmu_config.h, written by cranepredict.fmu). */
extern const cfmu_variable cfmu_variables[];
extern const size_t cfmu_n_variables;
extern const char cfmu_token[];
extern const int cfmu_drive;           /* CRANE_DRIVE_VALVE (levers) or CRANE_DRIVE_PRESSURE */
extern const int cfmu_levered[4];      /* joint j has a lever (valve drive); else it is held */
/* With a world (cfmu_n_obstacles > 0): the guard's crane parts, obstacles and settings. */
extern const crane_part cfmu_parts[];
extern const size_t cfmu_n_parts;
extern const crane_solid cfmu_obstacles[];
extern const size_t cfmu_n_obstacles;
extern const crane_guard_config cfmu_guard_config;
/* The crane file's parameters and every variable's start value. */
void cfmu_defaults(crane_params *params, double value[Q_COUNT]);

/* Status of the functions below: 0 = ok, 1 = error (logged). */
void cfmu_init(cfmu_instance *f, cfmu_logger log, void *env);
void cfmu_free(cfmu_instance *f);     /* the guard's scratch */
int cfmu_exit_initialization(cfmu_instance *f);
int cfmu_do_step(cfmu_instance *f, double h);
int cfmu_get(cfmu_instance *f, unsigned vr, int type, double *value);
int cfmu_set(cfmu_instance *f, unsigned vr, int type, double value);
/* A snapshot read back (get/set state, deserialization): checked, then the model re-made. */
int cfmu_restore(cfmu_instance *f, const cfmu_snapshot *snap);
/* The serialization both FMI versions share: a snapshot into bytes, and bytes (checked: size, magic)
 * into a snapshot allocated if *state is NULL. NULL on success, else what went wrong. */
const char *cfmu_serialize(const void *state, unsigned char *serialized, size_t size);
const char *cfmu_deserialize(const unsigned char *serialized, size_t size, void **state);

#endif /* CRANE_FMU_H */
