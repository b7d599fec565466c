/* SPDX-License-Identifier: MIT */
/*
 * Hydraulic cylinder force: chamber pressures on the piston areas minus [S1]'s smooth Stribeck friction
 * (docs/model.md, "Cylinders").
 */
#include "crane_internal.h"

/* tanh(4), the factor [S1]'s friction law puts on the viscous term. */
static const crane_real TANH_4 = (crane_real)0.999329299739067;
/* Beyond these arguments tanh is +-1 to the last bit and the Stribeck term x / (x^2/4 + 3/4)^2
 * (16 / x^3 for large x) is below 2e-17 of F_S - F_C, so skipping them changes nothing but the
 * run time, and x^2 cannot overflow. */
static const crane_real TANH_CUTOFF = 22;
static const crane_real STRIBECK_CUTOFF = 1000000;

crane_real crane__friction(const crane_friction *f, crane_real v)
{
    /* [S1]'s law, F = k [F_C tanh(4x) + (F_S - F_C) x / (x^2/4 + 3/4)^2] sign(v) + sigma tanh(4) v
     * with x = |v| / v_S, written with the signed r = v / v_S (both odd terms are smooth in r):
     * no separate smoothing velocity, the right-hand side stays smooth for RK4. */
    const crane_real r = v / f->stribeck_velocity;
    const crane_real r4 = 4 * r;
    const crane_real coulomb = r4 > TANH_CUTOFF ? 1 : r4 < -TANH_CUTOFF ? -1 : crane__tanh(r4);
    crane_real stribeck = 0;

    if (crane__fabs(r) < STRIBECK_CUTOFF) {
        const crane_real q = r * r / 4 + (crane_real)0.75;
        stribeck = r / (q * q);
    }
    return f->factor * (f->coulomb * coulomb + (f->static_ - f->coulomb) * stribeck) +
           f->viscous * TANH_4 * v;
}

#if CRANE_ROSW
crane_real crane__friction_slope(const crane_friction *f, crane_real v)
{
    /* dF/dv of crane__friction, term by term: d tanh(4r)/dr = 4 (1 - tanh^2), and
     * d/dr r / q^2 = (q - r^2) / q^3 with q = r^2/4 + 3/4; over v_S for dr/dv. */
    const crane_real r = v / f->stribeck_velocity;
    const crane_real r4 = 4 * r;
    crane_real coulomb = 0, stribeck = 0;

    if (crane__fabs(r4) < TANH_CUTOFF) {
        const crane_real th = crane__tanh(r4);
        coulomb = 4 * (1 - th * th);
    }
    if (crane__fabs(r) < STRIBECK_CUTOFF) {
        const crane_real q = r * r / 4 + (crane_real)0.75;
        stribeck = (q - r * r) / (q * q * q);
    }
    return f->factor * (f->coulomb * coulomb + (f->static_ - f->coulomb) * stribeck) /
               f->stribeck_velocity +
           f->viscous * TANH_4;
}
#endif /* CRANE_ROSW */

/* A cylinder's piston areas: pi bore^2 / 4 (bore side) and pi (bore^2 - rod^2) / 4 (rod side),
 * worked where needed rather than kept in the model (the stack). */
static void piston_areas(crane_real bore, crane_real rod, crane_real *area_a, crane_real *area_b)
{
    *area_a = crane__pi() * bore * bore / 4;
    *area_b = crane__pi() * (bore * bore - rod * rod) / 4;
}

crane_real crane__cylinder_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v)
{
    const crane_cylinder *c = &m->params->cylinder[joint];
    crane_real a_a, a_b;

    piston_areas(c->bore, c->rod, &a_a, &a_b);
    return p_a * a_a - p_b * a_b - crane__friction(&c->friction, v);
}

void crane__actuator_areas(const crane_model *m, int joint, crane_real *area_a, crane_real *area_b)
{
    const crane_params *p = m->params;

    if (joint < 2) {
        piston_areas(p->cylinder[joint].bore, p->cylinder[joint].rod, area_a, area_b);
    } else if (joint == CRANE_SLEW) {
        /* the rack's two bores push against each other: the equivalent cylinder has A_a = A_b */
        *area_a = crane__pi() * p->slew_drive.bore * p->slew_drive.bore / 4;
        *area_b = *area_a;
    } else {
        piston_areas(p->extension_cylinder.bore, p->extension_cylinder.rod, area_a, area_b);
    }
}

void crane__actuator_range(const crane_model *m, int joint, crane_real *stroke_min,
                           crane_real *stroke_max)
{
    const crane_params *p = m->params;

    if (joint < 2) {
        *stroke_min = crane__stroke_min(m, joint);
        *stroke_max = crane__stroke_max(m, joint);
    } else {
        *stroke_min = 0;
        *stroke_max = joint == CRANE_SLEW
                          ? p->slew_drive.pinion_radius * (p->slew_drive.slew_max - p->slew_drive.slew_min)
                          : p->extension_max - p->extension_min;
    }
}

crane_real crane__actuator_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v)
{
    const crane_params *p = m->params;
    crane_real a_a, a_b;

    if (joint < 2) {
        return crane__cylinder_force(m, joint, p_a, p_b, v);
    }
    crane__actuator_areas(m, joint, &a_a, &a_b);
    return p_a * a_a - p_b * a_b -
           crane__friction(joint == CRANE_SLEW ? &p->slew_drive.friction
                                               : &p->extension_cylinder.friction, v);
}

const crane_friction *crane__actuator_friction(const crane_model *m, int joint)
{
    const crane_params *p = m->params;

    if (joint < 2) {
        return &p->cylinder[joint].friction;
    }
    return joint == CRANE_SLEW ? &p->slew_drive.friction : &p->extension_cylinder.friction;
}

crane_status crane_cylinder_force(const crane_model *model, int joint, crane_real p_a,
                                  crane_real p_b, crane_real stroke_rate, crane_real *force)
{
    const crane_real pmax = (crane_real)CRANE_PRESSURE_MAX;
    crane_real f;

    if (model == NULL || force == NULL) {
        return CRANE_E_NULL;
    }
    if (joint != CRANE_LIFT && joint != CRANE_TILT) {
        return CRANE_E_CYLINDER;
    }
    if (crane__finite(p_a) == 0 || crane__finite(p_b) == 0 || crane__finite(stroke_rate) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (p_a < 0 || p_a > pmax || p_b < 0 || p_b > pmax) {
        return CRANE_E_PRESSURE;
    }
    /* The viscous term overflows for stroke rates near the largest real (1e307 m/s). */
    f = crane__cylinder_force(model, joint, p_a, p_b, stroke_rate);
    if (crane__finite(f) == 0) {
        return CRANE_E_OVERFLOW;
    }
    *force = f;
    return CRANE_OK;
}
