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

crane_real crane__cylinder_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v)
{
    return p_a * m->area_a[joint] - p_b * m->area_b[joint] -
           crane__friction(&m->params->cylinder[joint].friction, v);
}

crane_status crane_cylinder_force(const crane_model *model, int joint, crane_real p_a,
                                  crane_real p_b, crane_real stroke_rate, crane_real *force)
{
    const crane_real pmax = (crane_real)CRANE_PRESSURE_MAX;
    crane_real f;

    if (!model || !force)
        return CRANE_E_NULL;
    if (joint != CRANE_LIFT && joint != CRANE_TILT)
        return CRANE_E_CYLINDER;
    if (!crane__finite(p_a) || !crane__finite(p_b) || !crane__finite(stroke_rate))
        return CRANE_E_NONFINITE;
    if (p_a < 0 || p_a > pmax || p_b < 0 || p_b > pmax)
        return CRANE_E_PRESSURE;
    /* The viscous term overflows for stroke rates near the largest real (1e307 m/s). */
    f = crane__cylinder_force(model, joint, p_a, p_b, stroke_rate);
    if (!crane__finite(f))
        return CRANE_E_OVERFLOW;
    *force = f;
    return CRANE_OK;
}
