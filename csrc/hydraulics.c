/* SPDX-License-Identifier: MIT */
/*
 * Valve-driven cylinders: the valve's flows, the chamber equations and the stiffness bound that
 * sets the substeps (docs/model.md, "Hydraulics"). Everything here runs on validated inputs.
 */
#include "crane_internal.h"

#if CRANE_HYDRAULICS
#define LIMIT_OVERRIDE CRANE__LIMIT_OVERRIDE

/* The vacuum floor (docs/model.md, "Relief, cavitation floor, leakage"): a chamber more than
 * FLOOR_MARGIN below its cavitation pressure is one that the anti-cavitation valve cannot fill
 * (an impact empties it at several times the valve's nominal flow); the oil would cavitate. A
 * make-up flow FLOOR_GAIN times the valve's gradient holds it there, within FLOOR_MARGIN +
 * Q / (FLOOR_GAIN G_lim) of the cavitation pressure, above vacuum. */
static const crane_real FLOOR_MARGIN = (crane_real)8e3;
static const crane_real FLOOR_GAIN = 100;


/* Substeps keep lambda h / n below this: RK4 is stable on the negative real axis up to 2.785,
 * and the 10 % margin covers the chamber volumes changing within a step. */
static const crane_real SUBSTEP_STABILITY = (crane_real)2.5;

/* g(dp): the signed square root of the orifice law, replaced for |dp| < d_l by the odd cubic
 * that meets it with the same value and slope, so that the flows stay Lipschitz at dp = 0. */
static CRANE__ALWAYS_INLINE crane_real orifice(crane_real dp, crane_real dl)
{
    crane_real x;

    if (dp >= dl) {
        return crane__sqrt(dp);
    }
    if (dp <= -dl) {
        return -crane__sqrt(-dp);
    }
    x = dp / dl;
    return crane__sqrt(dl) * x * (5 - x * x) * (crane_real)0.25;
}

/* phi(x) of the compensated valve's meter-in edge: the compensator cannot push oil into a
 * chamber above the supply pressure; C1 between 0 and 1. */
static CRANE__ALWAYS_INLINE crane_real saturation(crane_real x)
{
    if (x <= 0) {
        return 0;
    }
    if (x >= 1) {
        return 1;
    }
    return x * (3 - x * x) * (crane_real)0.5;
}

/* d g(dp) / d dp of orifice (the root's slope, the cubic's inside d_l). */
static CRANE__ALWAYS_INLINE crane_real orifice_slope(crane_real dp, crane_real dl)
{
    crane_real x;

    if (dp >= dl) {
        return (crane_real)0.5 / crane__sqrt(dp);
    }
    if (dp <= -dl) {
        return (crane_real)0.5 / crane__sqrt(-dp);
    }
    x = dp / dl;
    return crane__sqrt(dl) * (5 - 3 * x * x) * (crane_real)0.25 / dl;
}

/* d phi(x) / dx of saturation. */
static CRANE__ALWAYS_INLINE crane_real saturation_slope(crane_real x)
{
    return x <= 0 || x >= 1 ? 0 : (1 - x * x) * (crane_real)1.5;
}

static CRANE__ALWAYS_INLINE crane_real gain(const crane_hydraulics *h)
{
    return h->nominal_flow / crane__sqrt(h->nominal_pressure_drop);
}

/* The steepest pressure-flow slope of the valve; the relief and anti-cavitation valves open with
 * it too, so that they add no stiffness of their own. */
static CRANE__ALWAYS_INLINE crane_real gradient(const crane_hydraulics *h)
{
    if (h->valve == CRANE_VALVE_COMPENSATED) {
        const crane_real km = h->meter_out_flow / crane__sqrt(h->meter_out_pressure_drop);
        const crane_real g_out = (crane_real)1.25 * km / crane__sqrt(h->laminar_pressure_drop);
        const crane_real g_in = (crane_real)1.5 * h->nominal_flow / h->laminar_pressure_drop;
        return g_out > g_in ? g_out : g_in;
    }
    return (crane_real)1.25 * gain(h) / crane__sqrt(h->laminar_pressure_drop);
}

/* The valve at spool y on the branch y takes, where each flow is an opening o(y) times a flow per
 * unit opening (Q_a = o w_a into the bore side, Q_b = o w_b out of the rod side): the orifice
 * valve's o = K y, the compensated valve's (y -+ u0) / (1 - u0) beyond its dead band (0 inside,
 * both edges closed). Returns do/dy: the flows' gain in the spool is (do/dy) w. With slope not
 * NULL it also gets dw_a/dp_a and dw_b/dp_b: the flows' slopes in their own chambers' pressures
 * are o times them (w_a does not depend on p_b, nor w_b on p_a). One function for the flows, their
 * gains and their slopes, so that the three keep one branch. */
static crane_real valve_branch(const crane_hydraulics *h, crane_real y, crane_real p_a,
                               crane_real p_b, crane_real *o, crane_real *w_a, crane_real *w_b,
                               crane_real slope[2])
{
    const crane_real dl = h->laminar_pressure_drop;

    if (h->valve != CRANE_VALVE_COMPENSATED) {
        /* the pressure drops before the square roots: fewer values are held across the calls,
         * which keeps this frame (on the stack budget's deepest path) smaller */
        const crane_real dp_a = y >= 0 ? h->supply_pressure - p_a : p_a - h->tank_pressure;
        const crane_real dp_b = y >= 0 ? p_b - h->tank_pressure : h->supply_pressure - p_b;
        const crane_real k = gain(h);
        *o = y * k;
        *w_a = orifice(dp_a, dl);
        *w_b = orifice(dp_b, dl);
        if (slope != NULL) {
            /* dp_a falls with p_a on the supply side (y >= 0), rises on the tank side; dp_b the
             * other way round */
            slope[0] = y >= 0 ? -orifice_slope(dp_a, dl) : orifice_slope(dp_a, dl);
            slope[1] = y >= 0 ? orifice_slope(dp_b, dl) : -orifice_slope(dp_b, dl);
        }
        return k;
    }
    {
        const crane_real u0 = h->dead_band;
        const crane_real km = h->meter_out_flow / crane__sqrt(h->meter_out_pressure_drop);
        if (y > u0) {
            const crane_real x = (h->supply_pressure - p_a) / dl;
            *o = (y - u0) / (1 - u0);
            *w_a = h->nominal_flow * saturation(x);
            *w_b = km * orifice(p_b - h->tank_pressure, dl);
            if (slope != NULL) {
                slope[0] = -h->nominal_flow * saturation_slope(x) / dl;
                slope[1] = km * orifice_slope(p_b - h->tank_pressure, dl);
            }
        } else if (y < -u0) {
            const crane_real x = (h->supply_pressure - p_b) / dl;
            *o = (y + u0) / (1 - u0);
            *w_a = km * orifice(p_a - h->tank_pressure, dl);
            *w_b = h->nominal_flow * saturation(x);
            if (slope != NULL) {
                slope[0] = km * orifice_slope(p_a - h->tank_pressure, dl);
                slope[1] = -h->nominal_flow * saturation_slope(x) / dl;
            }
        } else {
            *o = 0;
            *w_a = 0;
            *w_b = 0;
            if (slope != NULL) {
                slope[0] = 0;
                slope[1] = 0;
            }
            return 0;
        }
        return 1 / (1 - u0);
    }
}

void crane__valve_flows(const crane_hydraulics *h, crane_real y, crane_real p_a, crane_real p_b,
                        crane_real *q_a, crane_real *q_b)
{
    crane_real o, w_a, w_b;

    (void)valve_branch(h, y, p_a, p_b, &o, &w_a, &w_b, NULL);
    *q_a = o * w_a;
    *q_b = o * w_b;
}

/* C(V) = V / Be: the oil, the cylinder wall and the hose in series. */
static CRANE__ALWAYS_INLINE crane_real compliance(const crane_hydraulics *h, crane_real v, crane_real v_hose)
{
    return v / h->oil_bulk_modulus + (v - v_hose) / h->cylinder_bulk_modulus +
           v_hose / h->hose_bulk_modulus;
}

const crane_hydraulics *crane__circuit(const crane_model *m, int joint)
{
    const crane_params *p = m->params;
    const crane_hydraulics *h;

    if (joint < 2) {
        h = &p->cylinder[joint].hydraulics;
    } else if (joint == CRANE_SLEW) {
        h = p->slew_drive.present != 0 ? &p->slew_drive.hydraulics : NULL;
    } else {
        h = p->extension_cylinder.present != 0 ? &p->extension_cylinder.hydraulics : NULL;
    }
    return h != NULL && h->valve != CRANE_VALVE_NONE ? h : NULL;
}

/* The chamber volumes of actuator j at a stroke, V_a = V_hose,a + A_a (s - s_min) and
 * V_b = V_hose,b + A_b (s_max - s); ab gets (A_a, A_b, s_min, s_max). Inlined: no frame of its
 * own on the stack budget's deepest path. */
static CRANE__ALWAYS_INLINE void volumes(const crane_model *m, int joint, const crane_hydraulics *h,
                                         crane_real stroke, crane_real ab[4], crane_real *v_a,
                                         crane_real *v_b)
{
    crane__actuator_areas(m, joint, &ab[0], &ab[1]);
    crane__actuator_range(m, joint, &ab[2], &ab[3]);
    *v_a = h->hose_volume_a + ab[0] * (stroke - ab[2]);
    *v_b = h->hose_volume_b + ab[1] * (ab[3] - stroke);
}

void crane__chamber_rates(const crane_model *m, int joint, crane_real lever, crane_real stroke,
                          crane_real v, const crane_real p[2], crane_real y, crane_real rate[3])
{
    const crane_hydraulics *const h = crane__circuit(m, joint);
    crane_real q_l, q_a, q_b, v_a, v_b;
    crane_real spool = y; /* the spool the valve's flows see: the lever itself without a lag */
    crane_real ab[4];     /* the piston areas and the stroke range */

    /* the valve (the call) first, the chambers after: fewer values are held
     * across the calls, which keeps this frame, on the stack budget's deepest path, smaller */
    if (h->spool_time_constant > 0) {
        rate[2] = (lever - y) / h->spool_time_constant;
    } else {
        spool = lever;
        rate[2] = 0;
    }
    crane__valve_flows(h, spool, p[0], p[1], &q_a, &q_b);
    volumes(m, joint, h, stroke, ab, &v_a, &v_b);
    q_l = h->leakage * (p[0] - p[1]);
    /* the relief and anti-cavitation valves are not here: crane__limit_valves, implicitly */
    rate[0] = (q_a - ab[0] * v - q_l) / compliance(h, v_a, h->hose_volume_a);
    rate[1] = (ab[1] * v - q_b + q_l) / compliance(h, v_b, h->hose_volume_b);
}

#if CRANE_ROSW
/* The flow out of a chamber at p through its open limit valve (setting: the valve's): G_lim
 * (p - setting), and with its vacuum floor held in (floor != 0: ROS34PW2's mode over the step)
 * FLOOR_GAIN G_lim (p - knee) more. */
static crane_real limit_outflow(const crane_hydraulics *h, crane_real g, crane_real p,
                                crane_real setting, unsigned floor)
{
    crane_real q = g * (p - setting);

    if (floor != 0u) {
        q += FLOOR_GAIN * g * (p - (h->cavitation_pressure - FLOOR_MARGIN));
    }
    return q;
}

void crane__limit_rates(const crane_model *m, int joint, crane_real stroke, const crane_real p[2],
                        unsigned open, crane_real rate[2])
{
    const crane_hydraulics *const h = crane__circuit(m, joint);
    const crane_real g = h->nominal_flow / LIMIT_OVERRIDE;   /* G_lim */
    crane_real v_a, v_b, set, ab[4];

    if ((open & 3u) == 0u) {
        return;
    }
    volumes(m, joint, h, stroke, ab, &v_a, &v_b);
    if ((open & 1u) != 0u) {
        (void)crane__limit_side(m, joint, p[0], &set);
        rate[0] -= limit_outflow(h, g, p[0], set, open & 4u) / compliance(h, v_a, h->hose_volume_a);
    }
    if ((open & 2u) != 0u) {
        (void)crane__limit_side(m, joint, p[1], &set);
        rate[1] -= limit_outflow(h, g, p[1], set, open & 8u) / compliance(h, v_b, h->hose_volume_b);
    }
}

int crane__limit_side(const crane_model *m, int joint, crane_real p, crane_real *setting)
{
    const crane_hydraulics *const h = crane__circuit(m, joint);

    if (p <= h->cavitation_pressure + (h->relief_pressure - h->cavitation_pressure) / 2) {
        *setting = h->cavitation_pressure;
        return p < h->cavitation_pressure ? -1 : 0;
    }
    *setting = h->relief_pressure;
    return p > h->relief_pressure ? 1 : 0;
}

crane_real crane__floor_knee(const crane_model *m, int joint)
{
    return crane__circuit(m, joint)->cavitation_pressure - FLOOR_MARGIN;
}

void crane__chamber_jacobian(const crane_model *m, int joint, crane_real y, crane_real stroke,
                             const crane_real p[2], unsigned open, crane_real jac[8])
{
    const crane_hydraulics *const h = crane__circuit(m, joint);
    const crane_real g = h->nominal_flow / LIMIT_OVERRIDE;   /* G_lim */
    const crane_real l = h->leakage;
    crane_real v_a, v_b, c_a, c_b, da, db, ab[4], o, w_a, w_b, slope[2];
    const crane_real g_y = valve_branch(h, y, p[0], p[1], &o, &w_a, &w_b, slope);

    volumes(m, joint, h, stroke, ab, &v_a, &v_b);
    c_a = compliance(h, v_a, h->hose_volume_a);
    c_b = compliance(h, v_b, h->hose_volume_b);
    /* the flows' slopes in the chambers' pressures, dQ_a/dp_a and dQ_b/dp_b */
    da = o * slope[0];
    db = o * slope[1];
    /* an open limit valve adds its slope G_lim (open: the caller's judgement, bit 0 the a side,
     * bit 1 the b side; crane__limit_side), and its vacuum floor's where the caller holds it in
     * (bits 2 and 3: the chamber below the floor's knee over the step) */
    if ((open & 1u) != 0u) {
        da -= (open & 4u) != 0u ? (1 + FLOOR_GAIN) * g : g;
    }
    if ((open & 2u) != 0u) {
        db += (open & 8u) != 0u ? (1 + FLOOR_GAIN) * g : g;
    }
    jac[0] = (da - l) / c_a;
    jac[1] = l / c_a;
    jac[2] = l / c_b;
    jac[3] = (-db - l) / c_b;
    jac[4] = -ab[0] / c_a;
    jac[5] = ab[1] / c_b;
    /* the valve's gain: a spool opening or closing over the step moves the flows in proportion;
     * left out, ROS34PW2's error estimate of a chamber draining as its spool opens cancelled
     * (docs/model.md, "The matrix J") */
    jac[6] = 0;
    jac[7] = 0;
    if (h->spool_time_constant > 0) {
        jac[6] = g_y * w_a / c_a;
        jac[7] = -g_y * w_b / c_b;
    }
}
#endif /* CRANE_ROSW */

void crane__limit_valves(const crane__limits *l, crane_real dt, crane_real *p, int stride)
{
    int i;

    /* chamber i: actuator i / 2, a side (even) or b side (odd) */
    for (i = 0; i < 8; ++i) {
        if (((l->valves >> (i >> 1)) & 1u) != 0u) {
            const crane_hydraulics *const h = crane__circuit(l->m, i >> 1);
            crane_real *const pk = &p[stride * (i >> 1) + (i & 1)];
            /* the setting the pressure is beyond (none: ref = p, which leaves p exactly) */
            const crane_real p0 = *pk, a = dt * l->coef[i];
            const crane_real knee = h->cavitation_pressure - FLOOR_MARGIN;
            crane_real ref = h->cavitation_pressure;
            if (*pk > ref) {
                ref = h->relief_pressure;
                if (*pk < ref) {
                    ref = *pk;
                }
            }
            *pk = ref + (*pk - ref) / (1 + dt * l->coef[i]);
            if (*pk < knee) {
                /* beyond the vacuum floor's knee: implicit Euler with the floor's flow as well
                 * (piecewise linear, so the end below the knee is the one solution) */
                *pk = (p0 + a * h->cavitation_pressure + FLOOR_GAIN * a * knee) /
                      (1 + a + FLOOR_GAIN * a);
            }
        }
    }
}

static crane_real substep_count(crane_real lam, crane_real h)
{
    const crane_real n = crane__ceil(h * lam / SUBSTEP_STABILITY);
    /* Bounded so that a long fits: a prediction that would need more substeps than
     * CRANE_MAX_STEPS is refused before it runs (predict.c, check_work), so this never binds
     * while integrating. */
    if (!(n <= (crane_real)CRANE_MAX_STEPS)) {
        return (crane_real)CRANE_MAX_STEPS + 1;
    }
    return n < 1 ? 1 : n;
}

/* lambda of docs/model.md, "Hydraulics": the bound of the actuator's pressure and spool rates at
 * a stroke. A chamber's self-feedback (one valve edge, at most the gradient G, and G again: room
 * kept for a limit valve, although they are implicit now) plus the leakage twice: it couples the
 * pair, whose difference relaxes at leakage (1/C_a + 1/C_b) (Gershgorin: each row's diagonal and
 * off-diagonal); and the spool's pole 1/tau. coef gets the rates G_lim/C(V) of the relief and
 * anti-cavitation valves (crane__limit_valves). */
static crane_real stiffness(const crane_model *m, int joint, crane_real stroke, crane_real coef[2])
{
    const crane_hydraulics *const h = crane__circuit(m, joint);
    crane_real g, la, lb, c_a, c_b, v_a, v_b, ab[4];

    volumes(m, joint, h, stroke, ab, &v_a, &v_b);
    c_a = compliance(h, v_a, h->hose_volume_a);
    c_b = compliance(h, v_b, h->hose_volume_b);
    g = h->nominal_flow / LIMIT_OVERRIDE;   /* G_lim */
    coef[0] = g / c_a;
    coef[1] = g / c_b;
    g = 2 * (gradient(h) + h->leakage);
    la = g / c_a;
    lb = g / c_b;
    if (lb > la) {
        la = lb;
    }
    if (h->spool_time_constant > 0 && 1 / h->spool_time_constant > la) {
        la = 1 / h->spool_time_constant;
    }
    return la;
}

long crane__substeps(const crane_model *m, const crane_real stroke[4], const int valve[4],
                     crane_real h, crane_real *coef)
{
    crane_real lam = 0;
    int j;

    for (j = 0; j < 4; ++j) {
        if (valve[j] != 0) {
            const crane_real l = stiffness(m, j, stroke[j], &coef[2 * j]);
            if (l > lam) {
                lam = l;
            }
        }
    }
    return (long)substep_count(lam, h);
}

long crane__substeps_bound(const crane_model *m, const int valve[4], crane_real h)
{
    crane_real lam = 0;
    int j;

    for (j = 0; j < 4; ++j) {
        if (valve[j] != 0) {
            crane_real s_min, s_max, l, coef[2];
            crane__actuator_range(m, j, &s_min, &s_max);
            l = stiffness(m, j, s_min, coef);
            if (l > lam) {
                lam = l;
            }
            l = stiffness(m, j, s_max, coef);
            if (l > lam) {
                lam = l;
            }
        }
    }
    return (long)substep_count(lam, h);
}
#endif /* CRANE_HYDRAULICS */
