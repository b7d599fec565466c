/* SPDX-License-Identifier: MIT */
/*
 * Hydraulic cylinder force: chamber pressures on the piston areas minus smooth Stribeck friction
 * (docs/model.md, "Cylinders").
 */
#include "crane_internal.h"

/* Beyond these arguments exp(-r^2) is below 1e-35 and tanh is +-1 to the last bit, so skipping
 * the libm calls (and exp's slow underflow path) changes nothing but the run time. */
static const crane_real EXP_CUTOFF = 80;
static const crane_real TANH_CUTOFF = 22;

crane_real crane__friction(const crane_friction *f, crane_real v)
{
    const crane_real r = v / f->stribeck_velocity;
    const crane_real x = v / f->tanh_velocity;
    const crane_real r2 = r * r;
    const crane_real stribeck = r2 < EXP_CUTOFF ? (f->static_ - f->coulomb) * crane__exp(-r2) : 0;
    /* tanh instead of sign(v) keeps the right-hand side smooth for RK4. */
    const crane_real smooth_sign = x > TANH_CUTOFF ? 1 : x < -TANH_CUTOFF ? -1 : crane__tanh(x);
    return (f->coulomb + stribeck) * smooth_sign + f->viscous * v;
}

crane_real crane__cylinder_force(const crane_model *m, int joint, crane_real p_a, crane_real p_b,
                                 crane_real v)
{
    return p_a * m->area_a[joint] - p_b * m->area_b[joint] -
           crane__friction(&m->friction[joint], v);
}

crane_status crane_cylinder_force(const crane_model *model, int joint, crane_real p_a,
                                  crane_real p_b, crane_real stroke_rate, crane_real *force)
{
    const crane_real pmax = (crane_real)CRANE_PRESSURE_MAX;

    if (!model || !force)
        return CRANE_E_NULL;
    if (joint != CRANE_LIFT && joint != CRANE_TILT)
        return CRANE_E_CYLINDER;
    if (!crane__finite(p_a) || !crane__finite(p_b) || !crane__finite(stroke_rate))
        return CRANE_E_NONFINITE;
    if (p_a < 0 || p_a > pmax || p_b < 0 || p_b > pmax)
        return CRANE_E_PRESSURE;
    *force = crane__cylinder_force(model, joint, p_a, p_b, stroke_rate);
    return CRANE_OK;
}
