/*
 * Crane parameter checks and the derived model constants (docs/model.md, "Bad input", "Bodies and
 * the lumped outer boom", "End stops"), and the status messages.
 */
#include "crane_internal.h"

enum { FOURBAR_POINTS = 101 };

static int body_finite(const crane_body *b)
{
    return crane__finite(b->mass) && crane__finite_vec(b->com) && crane__finite(b->izz);
}

static int cylinder_finite(const crane_cylinder *c)
{
    const crane_friction *f = &c->friction;
    return crane__finite(c->bore) && crane__finite(c->rod) && crane__finite(c->length_retracted) &&
           crane__finite(c->stroke_min) && crane__finite(c->stroke_max) &&
           crane__finite(f->coulomb) && crane__finite(f->static_) && crane__finite(f->viscous) &&
           crane__finite(f->stribeck_velocity) && crane__finite(f->tanh_velocity);
}

static int params_finite(const crane_params *p)
{
    return crane__finite(p->gravity) && crane__finite_vec(p->lift_pivot) &&
           crane__finite_vec(p->lift_cylinder_base) && crane__finite_vec(p->lift_cylinder_rod) &&
           crane__finite_vec(p->tilt_cylinder_base) && crane__finite_vec(p->link1_pivot) &&
           crane__finite_vec(p->tilt_pivot) && crane__finite_vec(p->link_pin) &&
           crane__finite_vec(p->link2_end) && crane__finite_vec(p->link2_attach) &&
           crane__finite_vec(p->extension_mount) && crane__finite(p->tip_distance) &&
           crane__finite(p->extension_min) && crane__finite(p->extension_max) &&
           body_finite(&p->lift_boom) && body_finite(&p->outer_boom) &&
           body_finite(&p->extension_boom) && crane__finite(p->load_mass) &&
           body_finite(&p->side_link1) && body_finite(&p->side_link2) &&
           cylinder_finite(&p->cylinder[0]) && cylinder_finite(&p->cylinder[1]);
}

static int body_ok(const crane_body *b) { return b->mass > 0 && b->izz > 0; }

/* A side link may be massless (0 = neglected, the paper's model), never negative. */
static int link_ok(const crane_body *b) { return b->mass >= 0 && b->izz >= 0; }

static int cylinder_ok(const crane_cylinder *c)
{
    /* A pin-to-pin length must stay positive for the triangle and the four-bar to mean anything. */
    return c->rod > 0 && c->bore > c->rod && c->length_retracted > 0 &&
           c->stroke_min < c->stroke_max && c->length_retracted + c->stroke_min > 0;
}

static int friction_ok(const crane_friction *f)
{
    return f->coulomb >= 0 && f->static_ >= f->coulomb && f->viscous >= 0 &&
           f->stribeck_velocity > 0 && f->tanh_velocity > 0;
}

crane_status crane__check_params(const crane_params *p)
{
    int i;

    if (!params_finite(p))
        return CRANE_E_NONFINITE;
    if (!body_ok(&p->lift_boom) || !body_ok(&p->outer_boom) || !body_ok(&p->extension_boom) ||
        !(p->load_mass >= 0) || !link_ok(&p->side_link1) || !link_ok(&p->side_link2))
        return CRANE_E_BODY;
    for (i = 0; i < 2; ++i)
        if (!cylinder_ok(&p->cylinder[i]))
            return CRANE_E_CYLINDER;
    for (i = 0; i < 2; ++i)
        if (!friction_ok(&p->cylinder[i].friction))
            return CRANE_E_FRICTION;
    if (!(p->gravity >= 0))
        return CRANE_E_GRAVITY;
    for (i = 0; i < 2; ++i)
        if (!crane__hydraulics_ok(&p->cylinder[i].hydraulics))
            return CRANE_E_HYDRAULICS;
    return CRANE_OK;
}

/* 0 < gamma < pi over the lift stroke. cos(gamma) is monotone in L, so the two ends decide. */
static int lift_triangle_ok(const crane_model *m)
{
    const crane_real db = m->lift_db, dr = m->lift_dr;
    const crane_real ends[2] = {m->length_retracted[CRANE_LIFT] + m->stroke_min[CRANE_LIFT],
                                m->length_retracted[CRANE_LIFT] + m->stroke_max[CRANE_LIFT]};
    int k;

    if (!(db > 0) || !(dr > 0))
        return 0;
    for (k = 0; k < 2; ++k) {
        const crane_real cg = (db * db + dr * dr - ends[k] * ends[k]) / (2 * db * dr);
        if (!(cg > -1 && cg < 1))
            return 0;
    }
    return 1;
}

/* The four-bar closes with finite, nonzero ds/dtheta1 of one sign and theta1 inside
 * (-3pi/2, pi/2) at 101 strokes. Beyond docs/model.md, theta1 must also move monotonically in the
 * direction that sign says: otherwise the wrap cuts the stroke range and the limits are wrong. */
static int fourbar_ok(const crane_model *m)
{
    const crane_real lo = -3 * crane__pi() / 2, hi = crane__pi() / 2;
    crane_real prev_theta = 0, sign = 0;
    int k;

    if (!(m->tilt_l1 > 0) || !(m->tilt_l2 > 0) || !(m->tilt_ra > 0))
        return 0;
    for (k = 0; k < FOURBAR_POINTS; ++k) {
        const crane_real s = m->stroke_min[CRANE_TILT] +
                             (m->stroke_max[CRANE_TILT] - m->stroke_min[CRANE_TILT]) * (crane_real)k /
                                                 (crane_real)(FOURBAR_POINTS - 1);
        crane_real theta, ds;
        if (!crane__tilt_from_stroke(m, s, &theta, &ds, NULL, NULL))
            return 0;
        if (!crane__finite(theta) || !crane__finite(ds) || ds == 0 || !(theta > lo && theta < hi))
            return 0;
        if (k == 0) {
            sign = ds > 0 ? 1 : -1;
        } else {
            if ((ds > 0 ? 1 : -1) != sign)
                return 0;
            if (!((theta - prev_theta) * sign > 0))
                return 0;
        }
        prev_theta = theta;
    }
    return 1;
}

crane_status crane__model_derive(crane_model *m, const crane_params *params, crane_real extension)
{
    const crane_params *p = params;
    crane_status st;
    crane_vec2 mount_e, x_ext, x_tip;
    crane_real m_ob, m_ext, m_load, th_lo, th_hi, ds;
    int i;

    st = crane__check_params(p);
    if (st != CRANE_OK)
        return st;
    if (!crane__finite(extension))
        return CRANE_E_NONFINITE;
    if (extension < p->extension_min || extension > p->extension_max)
        return CRANE_E_EXTENSION;

    m->gravity = p->gravity;
    m->lift_pivot = p->lift_pivot;
    m->lift_cylinder_base = p->lift_cylinder_base;
    m->lift_cylinder_rod = p->lift_cylinder_rod;
    m->tilt_cylinder_base = p->tilt_cylinder_base;
    m->link1_pivot = p->link1_pivot;
    m->tilt_pivot = p->tilt_pivot;
    m->link2_attach = p->link2_attach;
    m->extension_mount = p->extension_mount;
    for (i = 0; i < 2; ++i) {
        m->length_retracted[i] = p->cylinder[i].length_retracted;
        m->stroke_min[i] = p->cylinder[i].stroke_min;
        m->stroke_max[i] = p->cylinder[i].stroke_max;
        m->friction[i] = p->cylinder[i].friction;
        m->hyd[i] = p->cylinder[i].hydraulics.valve != CRANE_VALVE_NONE
                        ? &p->cylinder[i].hydraulics
                        : NULL;
    }
    m->extension = extension;

    {
        const crane_vec2 b = crane__sub(p->lift_cylinder_base, p->lift_pivot);
        const crane_vec2 e = p->lift_cylinder_rod;
        m->lift_db = crane__norm(b);
        m->lift_dr = crane__norm(e);
        m->lift_beta = crane__atan2(b.y, b.x);
        m->lift_eps = crane__atan2(e.y, e.x);
        crane__sincos(m->lift_eps - m->lift_beta, &m->lift_sin_off, &m->lift_cos_off);
    }
    m->tilt_l1 = crane__norm(p->link_pin);
    m->tilt_l2 = crane__norm(p->link2_end);
    m->tilt_ra = crane__norm(p->link2_attach);
    m->tilt_alpha_a = crane__atan2(p->link2_attach.y, p->link2_attach.x);

    for (i = 0; i < 2; ++i) {
        const crane_real bore = p->cylinder[i].bore, rod = p->cylinder[i].rod;
        m->area_a[i] = crane__pi() * bore * bore / 4;
        m->area_b[i] = crane__pi() * (bore * bore - rod * rod) / 4;
    }

    /* Body 2: outer boom + extension boom at this extension + the load at the tip. */
    m_ob = p->outer_boom.mass;
    m_ext = p->extension_boom.mass;
    m_load = p->load_mass;
    mount_e = crane__add(p->extension_mount, crane__v2(extension, 0));
    x_ext = crane__add(mount_e, p->extension_boom.com);
    x_tip = crane__add(mount_e, crane__v2(p->tip_distance, 0));
    m->m1 = p->lift_boom.mass;
    m->c1 = p->lift_boom.com;
    m->i1 = p->lift_boom.izz;
    m->m2 = m_ob + m_ext + m_load;
    m->c2 = crane__scale(1 / m->m2,
                        crane__add(crane__add(crane__scale(m_ob, p->outer_boom.com),
                                              crane__scale(m_ext, x_ext)),
                                   crane__scale(m_load, x_tip)));
    m->i2 = p->outer_boom.izz + m_ob * crane__norm2(crane__sub(p->outer_boom.com, m->c2)) +
           p->extension_boom.izz + m_ext * crane__norm2(crane__sub(x_ext, m->c2)) +
           m_load * crane__norm2(crane__sub(x_tip, m->c2));
    m->tip = x_tip;
    m->j1 = m->i1 + m->m1 * crane__norm2(m->c1);
    m->j2 = m->i2 + m->m2 * crane__norm2(m->c2);
    m->m2_o2sq = m->m2 * crane__norm2(p->tilt_pivot);

    /* Side links: each centre of mass in the basis (v, perp v) of its link's vector, v = link_pin
     * (P1 to Q) or link2_end (Q to A), so that R(phi) cL = ca v' + cb perp(v') with v' = R(phi) v
     * (Q - P1 or A - Q) needs no trig. Zero lengths are rejected below (four-bar check). */
    {
        const crane_body *link[2];
        const crane_vec2 v[2] = {p->link_pin, p->link2_end};
        link[0] = &p->side_link1;
        link[1] = &p->side_link2;
        m->links = 0;
        for (i = 0; i < 2; ++i) {
            const crane_real n2 = crane__norm2(v[i]);
            m->link_m[i] = link[i]->mass;
            m->link_i[i] = link[i]->izz;
            m->link_ca[i] = n2 > 0 ? crane__dot(link[i]->com, v[i]) / n2 : 0;
            m->link_cb[i] = n2 > 0 ? crane__cross(v[i], link[i]->com) / n2 : 0;
            if (link[i]->mass > 0 || link[i]->izz > 0)
                m->links = 1;
        }
    }

    if (!lift_triangle_ok(m))
        return CRANE_E_GEOMETRY;
    if (!fourbar_ok(m))
        return CRANE_E_FOURBAR;

    /* Angle limits from the stroke limits; the smaller angle is the lower limit whatever the
     * sign of ds/dtheta (on the PATU the tilt's lower limit is at stroke_max). */
    for (i = 0; i < 2; ++i) {
        const crane_cylinder *c = &p->cylinder[i];
        if (i == CRANE_LIFT) {
            crane__lift_from_stroke(m, c->stroke_min, &th_lo, &ds);
            crane__lift_from_stroke(m, c->stroke_max, &th_hi, &ds);
        } else {
            (void)crane__tilt_from_stroke(m, c->stroke_min, &th_lo, &ds, NULL, NULL);
            (void)crane__tilt_from_stroke(m, c->stroke_max, &th_hi, &ds, NULL, NULL);
        }
        m->theta_min[i] = th_lo < th_hi ? th_lo : th_hi;
        m->theta_max[i] = th_lo < th_hi ? th_hi : th_lo;
    }

    return CRANE_OK;
}

crane_status crane_model_init(crane_model *model, const crane_params *params, crane_real extension)
{
    /* Derived into a local copy so that a rejected crane leaves *model untouched. */
    crane_model m;
    crane_status st;

    if (!model || !params)
        return CRANE_E_NULL;
    st = crane__model_derive(&m, params, extension);
    if (st == CRANE_OK)
        *model = m;
    return st;
}

const char *crane_status_message(crane_status status)
{
    switch (status) {
    case CRANE_OK: return "ok";
    case CRANE_E_NULL: return "a required pointer is NULL";
    case CRANE_E_NONFINITE: return "a NaN or infinity in the inputs";
    case CRANE_E_BODY: return "a mass, centre of mass or inertia is not physical";
    case CRANE_E_CYLINDER: return "cylinder bore/rod/length/stroke range not physical (or no such cylinder)";
    case CRANE_E_FRICTION: return "friction coefficients not physical";
    case CRANE_E_GEOMETRY: return "the lift triangle leaves 0 < gamma < pi over the lift stroke";
    case CRANE_E_FOURBAR: return "the tilt four-bar cannot close over the tilt stroke";
    case CRANE_E_GRAVITY: return "gravity is negative";
    case CRANE_E_STROKE: return "an initial stroke is outside [stroke_min, stroke_max]";
    case CRANE_E_EXTENSION: return "the extension is outside [extension_min, extension_max]";
    case CRANE_E_STROKE_RATE: return "a held cylinder was given a nonzero stroke rate";
    case CRANE_E_DRIVE: return "unknown drive mode";
    case CRANE_E_PRESSURE: return "a pressure is outside [0, 1e8] Pa";
    case CRANE_E_SAMPLES: return "pressure sample times are not strictly increasing or do not cover [0, horizon]";
    case CRANE_E_DT: return "dt <= 0 or dt > horizon";
    case CRANE_E_HORIZON: return "horizon <= 0, or too many steps";
    case CRANE_E_CAPACITY: return "the output buffer is smaller than the number of samples";
    case CRANE_E_ANGLE: return "an angle is outside the range reachable by the cylinder";
    case CRANE_E_SAMPLE_EVERY: return "sample_every must be >= 1";
    case CRANE_E_DIVERGED: return "the prediction diverged (the state stopped being finite): the parameters are not physical";
    case CRANE_E_HYDRAULICS: return "a hydraulic parameter is out of range (docs/model.md, Hydraulics)";
    case CRANE_E_VALVE: return "a valve drive is invalid: lever outside [-1, 1], no hydraulics for the cylinder, or a chamber pressure/spool of the state out of range";
    }
    return "unknown status";
}
