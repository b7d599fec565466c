/* SPDX-License-Identifier: MIT */
/*
 * Internal helpers of the cranepredict C core: precision-neutral math wrappers, 2-D vector
 * algebra and the prototypes shared between the core's source files. Not part of the public API.
 */
#ifndef CRANE_INTERNAL_H
#define CRANE_INTERNAL_H

#include <math.h>
#include "crane.h"

/* Inlines a static helper into every caller, so that its frame is not stacked on theirs (the
 * stack budget of docs/embedding.md). A plain hint for compilers other than gcc and clang. */
#if defined(__GNUC__)
#define CRANE__ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define CRANE__ALWAYS_INLINE inline
#endif

/* Keeps a static helper out of line (gcc inlines a helper with one call site), so that its locals
 * are not in its caller's frame while the caller calls something deep (the stack budget). */
#if defined(__GNUC__)
#define CRANE__NOINLINE __attribute__((noinline))
#else
#define CRANE__NOINLINE
#endif

/* ---- math wrappers: one spelling for both precisions, so no call promotes float to double ---- */

#ifdef CRANE_FLOAT
static inline crane_real crane__sqrt(crane_real x) { return sqrtf(x); }
/* sin and cos in float are the core's own (kinematics.c), not newlib's sinf/cosf: those enter a
 * 416-byte large-argument reduction for |x| > 201 rad, which the stack budget cannot afford and a
 * static call graph cannot rule out. Arguments beyond 64 rad are first reduced exactly by fmodf. */
void crane__sincosf(float x, float *s, float *c);
static inline void crane__sincos(crane_real x, crane_real *s, crane_real *c) { crane__sincosf(x, s, c); }
static inline crane_real crane__sin(crane_real x) { crane_real s, c; crane__sincosf(x, &s, &c); return s; }
static inline crane_real crane__cos(crane_real x) { crane_real s, c; crane__sincosf(x, &s, &c); return c; }
static inline crane_real crane__acos(crane_real x) { return acosf(x); }
static inline crane_real crane__atan2(crane_real y, crane_real x) { return atan2f(y, x); }
static inline crane_real crane__tanh(crane_real x) { return tanhf(x); }
static inline crane_real crane__fabs(crane_real x) { return fabsf(x); }
static inline crane_real crane__ceil(crane_real x) { return ceilf(x); }
#else
static inline crane_real crane__sqrt(crane_real x) { return sqrt(x); }
static inline crane_real crane__sin(crane_real x) { return sin(x); }
static inline crane_real crane__cos(crane_real x) { return cos(x); }
static inline void crane__sincos(crane_real x, crane_real *s, crane_real *c) { *s = sin(x); *c = cos(x); }
static inline crane_real crane__acos(crane_real x) { return acos(x); }
static inline crane_real crane__atan2(crane_real y, crane_real x) { return atan2(y, x); }
static inline crane_real crane__tanh(crane_real x) { return tanh(x); }
static inline crane_real crane__fabs(crane_real x) { return fabs(x); }
static inline crane_real crane__ceil(crane_real x) { return ceil(x); }
#endif

/* isfinite is a type-generic macro; wrapping it keeps the call sites typed. */
static inline int crane__finite(crane_real x) { return isfinite(x) != 0; }

static inline int crane__finite_vec(crane_vec2 v) { return crane__finite(v.x) && crane__finite(v.y); }

/* pi rounded to the working precision (the cast folds at compile time). */
static inline crane_real crane__pi(void) { return (crane_real)3.14159265358979323846; }

/* ---- 2-D vectors ---- */

static inline crane_vec2 crane__v2(crane_real x, crane_real y)
{
    crane_vec2 v;
    v.x = x;
    v.y = y;
    return v;
}

static inline crane_vec2 crane__add(crane_vec2 a, crane_vec2 b) { return crane__v2(a.x + b.x, a.y + b.y); }
static inline crane_vec2 crane__sub(crane_vec2 a, crane_vec2 b) { return crane__v2(a.x - b.x, a.y - b.y); }
static inline crane_vec2 crane__scale(crane_real s, crane_vec2 a) { return crane__v2(s * a.x, s * a.y); }
static inline crane_real crane__dot(crane_vec2 a, crane_vec2 b) { return a.x * b.x + a.y * b.y; }
static inline crane_real crane__cross(crane_vec2 a, crane_vec2 b) { return a.x * b.y - a.y * b.x; }
static inline crane_vec2 crane__perp(crane_vec2 a) { return crane__v2(-a.y, a.x); }
static inline crane_real crane__norm2(crane_vec2 a) { return crane__dot(a, a); }
static CRANE__ALWAYS_INLINE crane_real crane__norm(crane_vec2 a) { return crane__sqrt(crane__dot(a, a)); }

/* R(a) v, with the caller's cos/sin so that each angle's trig is evaluated once. */
static CRANE__ALWAYS_INLINE crane_vec2 crane__rot(crane_real c, crane_real s, crane_vec2 v)
{
    return crane__v2(c * v.x - s * v.y, s * v.x + c * v.y);
}

/* ---- joint modes of the integrator ---- */

enum { CRANE__FREE = 0, CRANE__HELD = 1, CRANE__STOP_LO = 2, CRANE__STOP_HI = 3 };

/* ---- kinematics.c ---- */

/* Lift: stroke -> (theta0, ds/dtheta0); the stroke must be in range (or the acos is clamped). */
void crane__lift_from_stroke(const crane_model *m, crane_real stroke, crane_real *theta,
                             crane_real *ds);
/* Lift from cos/sin of theta0: stroke and ds/dtheta0 (either pointer may be NULL). */
void crane__lift_from_angle(const crane_model *m, crane_real c0, crane_real s0,
                            crane_real *stroke, crane_real *ds);

/* Tilt: stroke -> theta1, ds/dtheta1, Q and A (lift boom frame); returns 0 if it cannot close. */
int crane__tilt_from_stroke(const crane_model *m, crane_real stroke, crane_real *theta,
                            crane_real *ds, crane_vec2 *q, crane_vec2 *a);
/* Tilt from cos/sin of theta1: stroke, ds/dtheta1, Q and A (any output pointer may be NULL). */
void crane__tilt_from_angle(const crane_model *m, crane_real c1, crane_real s1,
                            crane_real *stroke, crane_real *ds, crane_vec2 *q, crane_vec2 *a);

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

/* Fills *tk at cos/sin of theta1; the side-link sums only if m->links (else they are unset). */
void crane__tilt_kinematics(const crane_model *m, crane_real c1, crane_real s1,
                            crane__tilt_kin *tk);

/* The exact validity of the tilt four-bar over the tilt stroke (docs/model.md, "Tilt kinematics")
 * on a model whose lengths are derived: the field at fault, or CRANE_FIELD_NONE; sets tilt_branch. */
crane_field crane__fourbar_check(crane_model *m);

/* theta wrapped into (-3pi/2, pi/2]. */
crane_real crane__wrap_tilt(crane_real theta);

/* ---- dynamics.c ---- */

/* Newton-Euler inverse dynamics from the rotated vectors C1 = R(th0) c1, C2 = R(th0+th1) c2,
 * r12 = R(th0) O2 (computed once by the caller), with the side links' terms from tk (the four-bar
 * at theta1; NULL when the model has no side links) and c0, s0 = cos, sin of theta0. */
void crane__inverse_dynamics(const crane_model *m, crane_vec2 C1, crane_vec2 C2, crane_vec2 r12,
                             crane_real c0, crane_real s0, const crane__tilt_kin *tk,
                             const crane_real omega[2], const crane_real alpha[2], crane_real g,
                             crane_real tau[2]);

/* Mass matrix (M00, M01, M11) from cos/sin of theta1 alone (it does not depend on theta0), with
 * the side links' share from tk (NULL when the model has no side links). */
void crane__mass_matrix(const crane_model *m, crane_real c1, crane_real s1,
                        const crane__tilt_kin *tk, crane_real M[3]);

/* ---- cylinder.c ---- */

crane_real crane__friction(const crane_friction *f, crane_real v);
crane_real crane__cylinder_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v);

/* ---- hydraulics.c (docs/model.md, "Hydraulics") ---- */

/* Valve-driven cylinders are compiled in unless CRANE_HYDRAULICS is defined to 0: a build
 * without them refuses valve drives (CRANE_E_VALVE) and is smaller, for a controller that drives
 * by pressures only (docs/embedding.md: on the Cortex-M4F about 3.7 kB less code and 160 bytes
 * less stack; the budgeted build has them). */
#ifndef CRANE_HYDRAULICS
#define CRANE_HYDRAULICS 1
#endif

/* The valve's flows at spool y: q_a into the bore side, q_b out of the rod side. */
void crane__valve_flows(const crane_hydraulics *h, crane_real y, crane_real p_a, crane_real p_b,
                        crane_real *q_a, crane_real *q_b);
/* Valve-driven cylinder i at the lever command `lever`, stroke, stroke rate v, pressures p
 * (p_a, p_b) and spool y: rate = (dp_a/dt, dp_b/dt, dy/dt). */
void crane__chamber_rates(const crane_model *m, int i, crane_real lever, crane_real stroke,
                          crane_real v, const crane_real p[2], crane_real y, crane_real rate[3]);
/* The substep count of a step of size h from the strokes of the valve-driven joints (valve[i]). */
long crane__substeps(const crane_model *m, const crane_real stroke[2], const int valve[2],
                     crane_real h);

/* ---- model.c ---- */

/* The field rules of crane_params_check (not the kinematic ones); *field names the first broken. */
crane_status crane__check_params(const crane_params *p, crane_field *field);

/* crane_model_init without its NULL checks, deriving straight into *m (which is left partly
 * written on an error): for callers that own a scratch model, like crane_predict. On an error
 * *field is the crane field at fault (CRANE_FIELD_NONE for the extension, which is not one). */
crane_status crane__model_derive(crane_model *m, const crane_params *params, crane_real extension,
                                 crane_field *field);

/* ---- integrator.c ---- */

/* Runs a validated prediction: the model, state, inputs, horizon, dt, step count and capacity
 * have all been checked by crane_predict. Writes the sample at t = 0, one after every
 * sample_every-th step (>= 1) and one after the last step: crane__decimated_count samples, and
 * returns CRANE_OK; or, if theta or omega stop being finite, CRANE_E_DIVERGED with the samples
 * written before that (all finite). *n_written is set either way. */
crane_status crane__integrate(const crane_model *m, const crane_state *s0, const crane_inputs *in,
                              crane_real horizon, crane_real dt, long n_steps, long sample_every,
                              crane_sample *out, size_t *n_written);

/* Samples written for n_steps steps, keeping every sample_every-th step and the last. */
static inline size_t crane__decimated_count(long n_steps, long sample_every)
{
    return (size_t)(n_steps / sample_every) + (n_steps % sample_every != 0) + 1;
}

#endif /* CRANE_INTERNAL_H */
