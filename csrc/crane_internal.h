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
static inline crane_real crane__cbrt(crane_real x) { return cbrtf(x); }
static inline crane_real crane__pow(crane_real x, crane_real y) { return powf(x, y); }
static inline crane_real crane__floor(crane_real x) { return floorf(x); }
static inline crane_real crane__frexp(crane_real x, int *e) { return frexpf(x, e); }
static inline crane_real crane__ldexp(crane_real x, int e) { return ldexpf(x, e); }
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
static inline crane_real crane__cbrt(crane_real x) { return cbrt(x); }
static inline crane_real crane__pow(crane_real x, crane_real y) { return pow(x, y); }
static inline crane_real crane__floor(crane_real x) { return floor(x); }
static inline crane_real crane__frexp(crane_real x, int *e) { return frexp(x, e); }
static inline crane_real crane__ldexp(crane_real x, int e) { return ldexp(x, e); }
#endif

/* isfinite is a type-generic macro; wrapping it keeps the call sites typed. */
static inline int crane__finite(crane_real x) { return isfinite(x) != 0; }
/* lo <= x <= hi (false for NaN) */
static inline int crane__in_range(crane_real x, crane_real lo, crane_real hi) { return x >= lo && x <= hi; }

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

/* ---- what crane_model refers to in crane_params rather than keeps (crane.h) ---- */

/* Stroke limits of boom cylinder i (0, 1). */
static inline crane_real crane__stroke_min(const crane_model *m, int i)
{
    return m->params->cylinder[i].stroke_min;
}

static inline crane_real crane__stroke_max(const crane_model *m, int i)
{
    return m->params->cylinder[i].stroke_max;
}

/* The tip in the outer boom frame at the model's extension: x_tip = extension_mount + (e, 0)
 * + (tip_distance, 0) (the same sums as the lumped body's in crane__model_derive). */
static inline crane_vec2 crane__tip(const crane_model *m)
{
    const crane_params *p = m->params;
    return crane__add(crane__add(p->extension_mount, crane__v2(m->extension, 0)),
                      crane__v2(p->tip_distance, 0));
}

/* The lift triangle's angles: eps = atan2(E1.y, E1.x) of the rod eye in the lift boom frame and
 * beta = atan2 of B1 - O1 (docs/model.md, "Lift kinematics"). */
static inline void crane__lift_offsets(const crane_params *p, crane_real *eps, crane_real *beta)
{
    const crane_vec2 b = crane__sub(p->lift_cylinder_base, p->lift_pivot);
    *eps = crane__atan2(p->lift_cylinder_rod.y, p->lift_cylinder_rod.x);
    *beta = crane__atan2(b.y, b.x);
}

/* ---- joint modes of the integrator ---- */

enum { CRANE__FREE = 0, CRANE__HELD = 1, CRANE__STOP_LO = 2, CRANE__STOP_HI = 3 };

/* ---- drives and events of the integrator ---- */

enum { CRANE__BISECTIONS = 60, CRANE__RELEASE_BISECTIONS = 40, CRANE__MAX_PIECES = 8 };

/* The segment [t_j, t_j+1] of a sampled drive that holds time t, and t's fraction of it in [0, 1]:
 * the last j (at most n - 2) with t_j <= t, so that a time on a knot reads the segment that starts
 * there (s = 0: the knot's value exactly), whichever segment the cursor came from (the samples of
 * crane_predict_many and the dense output move it differently; the twin's rule, bisect_right).
 * The cursor walks from the last segment: RK4 stage times move forward, redone event steps go back
 * a little. Validation guarantees n >= 2 and t[0] <= 0 < horizon <= t[n-1]. */
static CRANE__ALWAYS_INLINE crane_real crane__drive_segment(const crane_drive *d, size_t *cursor,
                                                            crane_real t, size_t *jp)
{
    size_t j = *cursor, n = d->n_samples;
    crane_real s;

    while (j + 2 < n && t >= d->t[j + 1])
        ++j;
    while (j > 0 && t < d->t[j])
        --j;
    *cursor = j;
    *jp = j;
    s = (t - d->t[j]) / (d->t[j + 1] - d->t[j]);
    return s < 0 ? 0 : s > 1 ? 1 : s;
}

/* Pressures of a pressure drive at time t: constant, or linear interpolation of the samples. */
static CRANE__ALWAYS_INLINE void crane__drive_pressures(const crane_drive *d, size_t *cursor,
                                                        crane_real t, crane_real *p_a,
                                                        crane_real *p_b)
{
    size_t j;
    crane_real s;

    if (d->n_samples == 0) {
        *p_a = d->p_a;
        *p_b = d->p_b;
        return;
    }
    s = crane__drive_segment(d, cursor, t, &j);
    *p_a = d->p_a_samples[j] + s * (d->p_a_samples[j + 1] - d->p_a_samples[j]);
    *p_b = d->p_b_samples[j] + s * (d->p_b_samples[j + 1] - d->p_b_samples[j]);
}

/* The lever of a valve drive at time t (the same interpolation). */
static CRANE__ALWAYS_INLINE crane_real crane__drive_lever(const crane_drive *d, size_t *cursor,
                                                          crane_real t)
{
    size_t j;
    crane_real s;

    if (d->n_samples == 0)
        return d->u;
    s = crane__drive_segment(d, cursor, t, &j);
    return d->u_samples[j] + s * (d->u_samples[j + 1] - d->u_samples[j]);
}

/* Time in (0, h] at which the cubic Hermite interpolant of a joint coordinate on a step (q and
 * its rate at both ends) first reaches the limit (docs/model.md, "End stops"): 60 bisections
 * keeping lo inside and hi outside; the answer is hi. Bisecting s = tau/h in [0, 1] is the same
 * search without a division in the loop (its dependency chain is the cost of an event). */
static inline crane_real crane__crossing_time(crane_real th0, crane_real w0, crane_real th1,
                                              crane_real w1, crane_real h, crane_real limit,
                                              int upper)
{
    const crane_real hw0 = h * w0, hw1 = h * w1;
    crane_real lo = 0, hi = 1;
    int k;

    for (k = 0; k < CRANE__BISECTIONS; ++k) {
        const crane_real s = (lo + hi) / 2, s2 = s * s, s3 = s2 * s;
        const crane_real H = (2 * s3 - 3 * s2 + 1) * th0 + (s3 - 2 * s2 + s) * hw0 +
                             (-2 * s3 + 3 * s2) * th1 + (s3 - s2) * hw1;
        const int outside = upper != 0 ? H > limit : H < limit;
        if (outside != 0)
            hi = s;
        else
            lo = s;
    }
    return hi * h;
}

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

/* The four-bar's terms at one tilt angle: crane__tilt_kin, with the other parts of a prediction's
 * working storage in crane.h (crane_work). Fills *tk at cos/sin of theta1; the side-link sums
 * only if m->links (else they are unset). */
void crane__tilt_kinematics(const crane_model *m, crane_real c1, crane_real s1,
                            crane__tilt_kin *tk);

/* Side links by velocity ratios (docs/model.md, "Side links"). With qp = Q - P1, aq = A - Q,
 * ra = A - O2 and D = cross(qp, aq) = perp(qp).aq: k1 = perp(ra).aq / D, k2 = perp(ra).qp / -D;
 * at alpha1 = 0 and omega1 = 1 the closure's acceleration gives rhs = -ra + k1^2 qp + k2^2 aq,
 * g1 = rhs.aq / D, g2 = rhs.qp / -D (ddphi_i = k_i alpha1 + g_i omega1^2). The centres of mass
 * relative to their link's origin are e1 = R(phi1) cL1 = ca1 qp + cb1 perp(qp) and
 * e2 = ca2 aq + cb2 perp(aq) (R(phi1) takes link_pin to qp, R(phi2) link2_end to aq; ca, cb are
 * cL's coordinates in those bases, from crane_model). Then each link's d, v, w (as defined at
 * crane__tilt_kin) and the sums over both links that the inverse dynamics needs
 * (kinematics.c); the spatial kernel's slew inertia takes the links one by one from the same
 * vectors (dynamics.c). Inline in both, so that neither adds a frame to the stack budget's
 * deepest path. */
typedef struct {
    crane_vec2 qp, aq, e1, e2, d1, d2, v1, v2;
    crane_real inv_d, k1, k2;
} crane__link_vec;

static CRANE__ALWAYS_INLINE void crane__link_vectors(const crane_model *m,
                                                     const crane__tilt_kin *tk, crane__link_vec *l)
{
    const crane_params *p = m->params;
    const crane_vec2 ra = crane__sub(tk->a, p->tilt_pivot);

    l->qp = crane__sub(tk->q, p->link1_pivot);
    l->aq = crane__sub(tk->a, tk->q);
    l->inv_d = 1 / crane__cross(l->qp, l->aq);
    l->k1 = crane__cross(ra, l->aq) * l->inv_d;
    l->k2 = -crane__cross(ra, l->qp) * l->inv_d;
    l->e1 = crane__add(crane__scale(m->link_ca[0], l->qp),
                       crane__scale(m->link_cb[0], crane__perp(l->qp)));
    l->e2 = crane__add(crane__scale(m->link_ca[1], l->aq),
                       crane__scale(m->link_cb[1], crane__perp(l->aq)));
    /* Link 1 turns about P1: d1 = P1 + e1. */
    l->d1 = crane__add(p->link1_pivot, l->e1);
    l->v1 = crane__scale(l->k1, crane__perp(l->e1));
    /* Link 2 rides on Q (dQ = k1 perp(qp) per unit tilt rate) and turns: d2 = Q + e2. */
    l->d2 = crane__add(tk->q, l->e2);
    l->v2 = crane__add(crane__scale(l->k1, crane__perp(l->qp)),
                       crane__scale(l->k2, crane__perp(l->e2)));
}

/* The exact validity of the tilt four-bar over the tilt stroke (docs/model.md, "Tilt kinematics")
 * on a model whose lengths are derived: the field at fault, or CRANE_FIELD_NONE; sets tilt_branch. */
crane_field crane__fourbar_check(crane_model *m);

/* theta wrapped into (-3pi/2, pi/2]. */
crane_real crane__wrap_tilt(crane_real theta);

/* ---- dynamics.c: the dynamics kernels (docs/model.md, "Dynamics", "Four joints") ---- */

/* The spatial kernel's constants (crane__bodies, crane.h) of the crane p. */
void crane__bodies_init(const crane_params *p, crane__bodies *b);

/* The configuration (crane__conf, crane.h) at theta0, theta1 and e. */
void crane__conf_at(const crane_model *m, crane_real th0, crane_real th1, crane_real e,
                    crane__conf *cf);

/* The planar kernel: Newton-Euler inverse dynamics of the two booms (the extension boom and the
 * load lumped into the outer boom at the model's extension: m2, c2, i2) at cf's trig (and its
 * four-bar, with side links), for rates omega, accelerations alpha and gravity g. */
void crane__id_planar(const crane_model *m, const crane__conf *cf, const crane_real omega[2],
                      const crane_real alpha[2], crane_real g, crane_real tau[2]);

/* Its mass matrix (M00, M01, M11) in crane__mass_spatial's layout Mp = (M00, M01, 0, M11, 0, 1)
 * (the extension, held, with a unit mass that decouples it), from cos/sin of theta1 alone (it
 * does not depend on theta0) and the four-bar's side links. */
void crane__mass_planar(const crane_model *m, const crane__conf *cf, crane_real Mp[6]);

/* The spatial kernel: generalized forces [lift, tilt, slew, extension] for rates qd and
 * accelerations qdd, gravity g, but for what crane__slew_inertia adds: the slew's own inertial
 * term (tau[2] is 0 here; the caller adds crane__slew_torque, having J_z for the mass matrix
 * anyway, so that it is worked once) and the slew's loads on the side links. */
void crane__id_spatial(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                       const crane_real qd[4], const crane_real qdd[4], crane_real g,
                       crane_real tau[4]);

/* The slew inertia J_z and its rate of change Jdot_z at the rates qd; and the slew's loads on the
 * side links (their centripetal force and gyroscopic moment at omega_s = qd[2]) added to tau[0],
 * tau[1], which complete crane__id_spatial's. */
void crane__slew_inertia(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                         const crane_real qd[4], crane_real *jz, crane_real *jdot,
                         crane_real tau[2]);

/* The slew equation's inertial term J_z alpha_s + Jdot_z omega_s (exactly 0 at rest without
 * acceleration, whatever J_z). */
static inline crane_real crane__slew_torque(crane_real jz, crane_real jdot, crane_real ws,
                                            crane_real as)
{
    return ws != 0 || as != 0 ? jz * as + jdot * ws : 0;
}

/* The spatial kernel's in-plane mass matrix over (lift, tilt, extension), symmetric, row-major
 * upper triangle Mp = (M00, M01, M0e, M11, M1e, Mee), in closed form (the columns
 * ID(q, 0, e_j, 0) of crane__id_spatial worked by hand; tests compare them); the slew's entry is
 * J_z alone (block diagonal). */
void crane__mass_spatial(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                         crane_real Mp[6]);

/* ---- cylinder.c ---- */

crane_real crane__friction(const crane_friction *f, crane_real v);
/* dF/dv of crane__friction. */
crane_real crane__friction_slope(const crane_friction *f, crane_real v);
/* The friction of actuator joint (a boom cylinder, the slew rack, the extension cylinder). */
const crane_friction *crane__actuator_friction(const crane_model *m, int joint);
crane_real crane__cylinder_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v);
/* Actuator j of [lift, tilt, slew, extension] (docs/model.md, "Four joints", "Actuators"): the
 * boom cylinders, the slew drive as its equivalent cylinder (the rack: A_a = A_b, stroke
 * r_p (psi - slew_min)) and the extension cylinder (stroke e - extension_min). Its piston areas,
 * its stroke range and its force along the stroke at stroke rate v. */
void crane__actuator_areas(const crane_model *m, int joint, crane_real *area_a, crane_real *area_b);
void crane__actuator_range(const crane_model *m, int joint, crane_real *stroke_min,
                           crane_real *stroke_max);
crane_real crane__actuator_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v);

/* ---- hydraulics.c (docs/model.md, "Hydraulics") ---- */

/* Valve-driven cylinders are compiled in unless CRANE_HYDRAULICS is defined to 0: a build
 * without them refuses valve drives (CRANE_E_VALVE) and is smaller, for a controller that drives
 * by pressures only (docs/embedding.md: on the Cortex-M4F about 4.5 kB less code and 24 bytes
 * less stack; the budgeted build has them). */
#ifndef CRANE_HYDRAULICS
#define CRANE_HYDRAULICS 1
#endif

/* The valve's flows at spool y: q_a into the bore side, q_b out of the rod side. */
void crane__valve_flows(const crane_hydraulics *h, crane_real y, crane_real p_a, crane_real p_b,
                        crane_real *q_a, crane_real *q_b);
/* The circuit of actuator j (0..3), NULL when it has none. */
const crane_hydraulics *crane__circuit(const crane_model *m, int joint);
/* Valve-driven actuator j (0..3) at the lever command `lever`, stroke, stroke rate v, pressures p
 * (p_a, p_b) and spool y: rate = (dp_a/dt, dp_b/dt, dy/dt). */
void crane__chamber_rates(const crane_model *m, int joint, crane_real lever, crane_real stroke,
                          crane_real v, const crane_real p[2], crane_real y, crane_real rate[3]);

/* The relief and anti-cavitation valves over dt, implicitly (docs/model.md, "Integration
 * (stiffness and substeps)"): the chamber pressures of each valve-driven actuator j at
 * p[stride j], p[stride j + 1]. */
void crane__limit_valves(const crane__limits *l, crane_real dt, crane_real *p, int stride);
/* The substep count of a step of size h from the strokes of the valve-driven actuators (valve[j],
 * j over [lift, tilt, slew, extension]); coef gets each one's two rates G_lim/C(V) at its
 * stroke for crane__limit_valves (coef[2j], coef[2j + 1]). */
/* The relief and anti-cavitation valves' flows as rates (the error-controlled method integrates
 * them with the chamber equations, docs/model.md "Integration"): subtracts G_lim (p - setting) /
 * C(V) from each chamber whose valve is open (bit 0 the a side, bit 1 the b side; the setting the
 * nearer one, crane__limit_side), and the vacuum floor's FLOOR_GAIN G_lim (p - knee) / C(V) where
 * it is held in (bit 2 the a side, bit 3 the b side). A valve's opening and closing and a floor's
 * knee are events of the integrator: a step keeps each mode as it was at its start, so that its
 * rates stay smooth over the step. */
void crane__limit_rates(const crane_model *m, int joint, crane_real stroke, const crane_real p[2],
                        unsigned open, crane_real rate[2]);
/* The chamber equations' Jacobian of actuator joint at spool y, the stroke and pressures p:
 * jac = (dpa'/dpa, dpa'/dpb, dpb'/dpa, dpb'/dpb, dpa'/dv, dpb'/dv, dpa'/dy, dpb'/dy), v the stroke
 * rate; the valve's pressure slopes, the leakage and the slopes of the limit valves open (bit 0:
 * the a side's, bit 1 the b side's) and of the vacuum floors held in (bit 2: the a side's, bit 3
 * the b side's); the valve's gains in the spool where the spool is a state (a lag), else 0. */
void crane__chamber_jacobian(const crane_model *m, int joint, crane_real y, crane_real stroke,
                             const crane_real p[2], unsigned open, crane_real jac[8]);
/* Which limit valve a chamber of actuator joint at p is beyond: -1 the anti-cavitation valve, +1
 * the relief valve, 0 neither; *setting gets the setting of the nearer one. */
int crane__limit_side(const crane_model *m, int joint, crane_real p, crane_real *setting);
/* The vacuum floor's knee of actuator joint's chambers, Pa: the cavitation pressure less the
 * floor's margin (docs/model.md, "The vacuum floor"). */
crane_real crane__floor_knee(const crane_model *m, int joint);
/* The relief and anti-cavitation valves pass the valve's nominal flow at this much beyond their
 * settings, Pa (docs/model.md, "Relief, cavitation floor, leakage"). */
static const crane_real CRANE__LIMIT_OVERRIDE = (crane_real)5e3;
long crane__substeps(const crane_model *m, const crane_real stroke[4], const int valve[4],
                     crane_real h, crane_real *coef);
/* Its largest value over every stroke (at the stroke ends, where the chambers are smallest). */
long crane__substeps_bound(const crane_model *m, const int valve[4], crane_real h);

/* ---- model.c ---- */

/* The field rules of crane_params_check (not the kinematic ones); *field names the first broken. */
crane_status crane__check_params(const crane_params *p, crane_field *field);

/* crane_model_init without its NULL checks, deriving straight into *m (which is left partly
 * written on an error): for callers that own a scratch model, like crane_predict. On an error
 * *field is the crane field at fault (CRANE_FIELD_NONE for the extension, which is not one). */
crane_status crane__model_derive(crane_model *m, const crane_params *params, crane_real extension,
                                 crane_field *field);

/* ---- predict.c, for the integrator ---- */

/* The first sample time of a sampled drive (pressures or lever) of joints 0..n_joints-1 that lies
 * in (t, t_end), farther than a thousandth of dt from both ends; t_end if there is none. Steps
 * are cut there (docs/model.md, "Integration and samples"): the drive is linear between its
 * samples, smooth only inside a segment, and RK4 across a kink is first order. */
crane_real crane__next_knot(const crane_inputs *in, int n_joints, crane_real t, crane_real t_end,
                            crane_real dt);
/* The sample times of the sampled drives inside (0, horizon), counted per drive: the steps that
 * the knots may cut (RK4's, DOPRI5's) on top of the work bound without them. */
long crane__knot_count(const crane_inputs *in, crane_real horizon);
#if CRANE_ROSW
/* Where a ROS34PW2 step from t to t_end ends (docs/model.md, "Integration": the drives' rule): at
 * the first sample inside of a sampled pressure drive (farther than a thousandth of dt from both
 * ends, as crane__next_knot); for a sampled valve drive, at t_end if the spool error that its
 * stages' view of the lever can leave is within tolerance, else at the farthest sample inside
 * where it is (the lever is linear up to the first). t_end if nothing cuts the step. */
crane_real crane__rosw_step_end(const crane_model *m, const crane_inputs *in, crane_real t,
                                crane_real t_end, crane_real dt, crane_real tolerance);
#endif

/* ---- integrator.c ---- */

/* The default tolerances of the error-controlled method (crane_solver; docs/model.md,
 * "Integration"): per step, m of tip and Pa of chamber pressure. */
static const crane_real CRANE__TIP_TOLERANCE = (crane_real)5e-5;
static const crane_real CRANE__PRESSURE_TOLERANCE = (crane_real)1e4;
/* Its cap on step attempts over a horizon (docs/model.md, "Integration"): 64 plus 4096 a second
 * (as many as steps of 0.24 ms), plus one a knot inside the horizon (crane__knot_count: DOPRI5
 * cuts its steps there), so that the work of a call is bounded before it runs. A horizon
 * whose cap is beyond CRANE_MAX_STEPS gets 64 + CRANE_MAX_STEPS (refused as CRANE_E_STEPS): the
 * conversion of a larger count to long would overflow. */
static inline long crane__attempt_cap(crane_real horizon)
{
    const crane_real n = crane__ceil(horizon * 4096);
    return n < (crane_real)CRANE_MAX_STEPS ? 64 + (long)n : 64 + (long)CRANE_MAX_STEPS;
}

/* Runs a validated prediction (docs/model.md, "Integration and samples", "Four joints"): the
 * model, state, inputs, horizon, dt, step count and capacity have all been checked by
 * crane_predict. Writes the sample at t = 0, one after every sample_every-th step (>= 1) and one
 * after the last step: crane__decimated_count samples, and returns CRANE_OK; or, if the state
 * stops being finite (or its chambers and spools leave their domain), CRANE_E_DIVERGED with the
 * samples written before that (all finite). *n_written is set either way. work: the caller's. */
crane_status crane__integrate(const crane_model *m, const crane_state *s0, const crane_inputs *in,
                              crane_real horizon, crane_real dt, long n_steps, long sample_every,
                              crane_sample *out, size_t *n_written, crane_work *work);

/* The extension's friction rate bound of docs/model.md ("Four joints", substeps), 1/s:
 * lambda_e = G_f (M^-1)_ee with (M^-1)_ee taken at most 4 / m_ext (the extension boom's own mass;
 * the PATU 655 stays below 1.1 / m_ext unloaded and 0.25 / m_ext with 500 kg), so that the work
 * of a call has a bound (crane.h): G_f = k (4 F_C + 16/9 (F_S - F_C)) / v_S + sigma tanh(4), the
 * friction law's steepest slope. Returns 0 for a crane without an extension cylinder. */
static inline crane_real crane__extension_friction_slope(const crane_params *p)
{
    const crane_friction *f = &p->extension_cylinder.friction;
    if (p->extension_cylinder.present == 0)
        return 0;
    return f->factor * (4 * f->coulomb + (crane_real)16 / 9 * (f->static_ - f->coulomb)) /
               f->stribeck_velocity +
           f->viscous * crane__tanh(4);
}

static inline crane_real crane__extension_rate_bound(const crane_params *p)
{
    return crane__extension_friction_slope(p) * 4 / p->extension_boom.mass;
}

/* crane_predict_model after its NULL checks, keeping the sample at t = 0, one after every
 * sample_every-th step (>= 1) and one after the last (crane__decimated_count samples): the one
 * copy of the checks and the prediction that crane_predict_model and crane_step share. */
crane_status crane__predict_every(const crane_model *model, const crane_state *state0,
                                  const crane_inputs *inputs, crane_real horizon, crane_real dt,
                                  long sample_every, crane_sample *out, size_t capacity,
                                  size_t *n_written, crane_work *work);

/* Samples written for n_steps steps, keeping every sample_every-th step and the last. */
static inline size_t crane__decimated_count(long n_steps, long sample_every)
{
    return (size_t)(n_steps / sample_every) + (n_steps % sample_every != 0) + 1;
}

/* The estimator's status messages (estimator.c: its text stays in the estimator's module); "unknown
 * status" for a status that is not the estimator's. */
const char *crane__estimator_status_message(crane_status status);

#endif /* CRANE_INTERNAL_H */
