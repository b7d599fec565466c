/* SPDX-License-Identifier: MIT */
/*
 * Crane parameter checks and the derived model constants (docs/model.md, "Bad input", "Bodies and
 * the lumped outer boom", "End stops"), and the status messages.
 */
#include "crane_internal.h"
#include "guard_internal.h"

/* The first rule broken so far: every check below is one call that does nothing once a rule has
 * failed, so the checks read as a list, one line per field, in the order of the crane file. */
typedef struct {
    crane_status status;
    crane_field field;
} verdict;

/* x must be finite and keep its rule (ok, computed by the caller), else status `bad`. */
static void rule(verdict *v, crane_field f, crane_real x, int ok, crane_status bad)
{
    if (v->status != CRANE_OK) {
        return;
    }
    if (crane__finite(x) == 0) {
        v->status = CRANE_E_NONFINITE;
        v->field = f;
    } else if (ok == 0) {
        v->status = bad;
        v->field = f;
    } else {
        /* finite and keeps its rule */
    }
}

static void point_rule(verdict *v, crane_field f, crane_vec2 x)
{
    rule(v, f, x.x, 1, CRANE_OK);
    rule(v, f, x.y, 1, CRANE_OK);
}

/* A body's block of fields is MASS, COM, IZZ, IXX, IYY, IXY (crane.h). A side link or the pillar
 * may be massless (0 = neglected, the paper's model), never negative; every other body has mass
 * and inertia. Of the in-plane tensor the diagonal is >= 0; ixy is only finite, since a crane file
 * may give ixy and leave out ixx (taken as 0), and [S1]'s tensors are what they are. */
static void body_rules(verdict *v, crane_field mass, const crane_body *b, int massless_ok)
{
    rule(v, mass, b->mass, massless_ok != 0 ? b->mass >= 0 : b->mass > 0, CRANE_E_BODY);
    point_rule(v, (crane_field)(mass + 1), b->com);
    rule(v, (crane_field)(mass + 2), b->izz, massless_ok != 0 ? b->izz >= 0 : b->izz > 0,
         CRANE_E_BODY);
    rule(v, (crane_field)(mass + 3), b->ixx, b->ixx >= 0, CRANE_E_BODY);
    rule(v, (crane_field)(mass + 4), b->iyy, b->iyy >= 0, CRANE_E_BODY);
    rule(v, (crane_field)(mass + 5), b->ixy, 1, CRANE_OK);
}

/* The field of cylinder i from the lift cylinder's (the tilt block mirrors the lift block). */
static crane_field cylinder_field(int i, crane_field lift)
{
    return (crane_field)((int)lift + i * ((int)CRANE_FIELD_TILT_CYLINDER_BORE -
                                         (int)CRANE_FIELD_LIFT_CYLINDER_BORE));
}

/* In the FRICTION or HYDRAULICS block that starts at first, the field that is lift_field in the
 * lift cylinder's block starting at lift_first (every such block has the lift cylinder's order:
 * crane.h). */
static crane_field block_field(crane_field first, crane_field lift_first, crane_field lift_field)
{
    return (crane_field)((int)first + ((int)lift_field - (int)lift_first));
}

/* An actuator's circuit (docs/model.md, "Hydraulics"), if it has one (valve != NONE); first is
 * the block's HYDRAULICS_VALVE field. */
static void hydraulics_rules(verdict *v, crane_field first, const crane_hydraulics *h)
{
    const crane_real pmax = (crane_real)CRANE_PRESSURE_MAX;
    const int comp = h->valve == CRANE_VALVE_COMPENSATED;
    const crane_status bad = CRANE_E_HYDRAULICS;
    const crane_field lift = CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_VALVE;

    if (h->valve == CRANE_VALVE_NONE) {
        return;
    }
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_VALVE), 0,
         h->valve == CRANE_VALVE_ORIFICE || comp, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_TANK_PRESSURE), h->tank_pressure,
         h->tank_pressure >= 0 && h->tank_pressure <= pmax, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_SUPPLY_PRESSURE),
         h->supply_pressure, h->supply_pressure > h->tank_pressure && h->supply_pressure <= pmax, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_RELIEF_PRESSURE),
         h->relief_pressure, h->relief_pressure >= h->supply_pressure && h->relief_pressure <= pmax,
         bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_NOMINAL_FLOW), h->nominal_flow,
         h->nominal_flow > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_NOMINAL_PRESSURE_DROP),
         h->nominal_pressure_drop, h->nominal_pressure_drop > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_DEAD_BAND), h->dead_band,
         comp != 0 ? h->dead_band >= 0 && h->dead_band <= (crane_real)0.99 : h->dead_band == 0,
         bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_METER_OUT_FLOW),
         h->meter_out_flow, comp != 0 ? h->meter_out_flow > 0 : h->meter_out_flow >= 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_METER_OUT_PRESSURE_DROP),
         h->meter_out_pressure_drop,
         comp != 0 ? h->meter_out_pressure_drop > 0 : h->meter_out_pressure_drop >= 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_SPOOL_TIME_CONSTANT),
         h->spool_time_constant, h->spool_time_constant >= 0 && h->spool_time_constant <= 10, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_LAMINAR_PRESSURE_DROP),
         h->laminar_pressure_drop, h->laminar_pressure_drop > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_CAVITATION_PRESSURE),
         h->cavitation_pressure,
         h->cavitation_pressure >= (crane_real)CRANE_CHAMBER_PRESSURE_MIN &&
             h->cavitation_pressure <= h->tank_pressure,
         bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_VOLUME_A), h->hose_volume_a,
         h->hose_volume_a > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_VOLUME_B), h->hose_volume_b,
         h->hose_volume_b > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_OIL_BULK_MODULUS),
         h->oil_bulk_modulus, h->oil_bulk_modulus > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_HOSE_BULK_MODULUS),
         h->hose_bulk_modulus, h->hose_bulk_modulus > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_CYLINDER_BULK_MODULUS),
         h->cylinder_bulk_modulus, h->cylinder_bulk_modulus > 0, bad);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_LEAKAGE), h->leakage,
         h->leakage >= 0 && h->leakage <= (crane_real)1e-6, bad);
}

/* A friction block (first: its COULOMB field). */
static void friction_rules(verdict *v, crane_field first, const crane_friction *f)
{
    const crane_field lift = CRANE_FIELD_LIFT_CYLINDER_FRICTION_COULOMB;

    rule(v, first, f->coulomb, f->coulomb >= 0, CRANE_E_FRICTION);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_FRICTION_STATIC), f->static_,
         f->static_ >= f->coulomb, CRANE_E_FRICTION);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_FRICTION_VISCOUS), f->viscous,
         f->viscous >= 0, CRANE_E_FRICTION);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_FRICTION_STRIBECK_VELOCITY),
         f->stribeck_velocity, f->stribeck_velocity > 0, CRANE_E_FRICTION);
    rule(v, block_field(first, lift, CRANE_FIELD_LIFT_CYLINDER_FRICTION_FACTOR), f->factor,
         f->factor >= 0, CRANE_E_FRICTION);
}

static void cylinder_rules(verdict *v, int i, const crane_cylinder *c)
{
    /* stroke 0 is the fully retracted cylinder (length_retracted), so no stop lies below it; that
     * also keeps every pin-to-pin length positive, which the triangle and the four-bar need. */
    rule(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_ROD), c->rod, c->rod > 0, CRANE_E_CYLINDER);
    rule(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_BORE), c->bore, c->bore > c->rod,
         CRANE_E_CYLINDER);
    rule(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_LENGTH_RETRACTED), c->length_retracted,
         c->length_retracted > 0, CRANE_E_CYLINDER);
    rule(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_STROKE_MIN), c->stroke_min,
         c->stroke_min >= 0, CRANE_E_CYLINDER);
    rule(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_STROKE_MAX), c->stroke_max,
         c->stroke_max > c->stroke_min, CRANE_E_CYLINDER);
    friction_rules(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_FRICTION_COULOMB), &c->friction);
    hydraulics_rules(v, cylinder_field(i, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_VALVE), &c->hydraulics);
}

/* The slew drive and the extension cylinder, if the crane has them (docs/model.md, "Four joints"). */
static void actuator_rules(verdict *v, const crane_params *p)
{
    const crane_slew_drive *sd = &p->slew_drive;
    const crane_extension_cylinder *ec = &p->extension_cylinder;

    if (sd->present != 0) {
        rule(v, CRANE_FIELD_SLEW_DRIVE_BORE, sd->bore, sd->bore > 0, CRANE_E_CYLINDER);
        rule(v, CRANE_FIELD_SLEW_DRIVE_PINION_RADIUS, sd->pinion_radius, sd->pinion_radius > 0,
             CRANE_E_CYLINDER);
        rule(v, CRANE_FIELD_SLEW_DRIVE_SLEW_MIN, sd->slew_min, 1, CRANE_OK);
        rule(v, CRANE_FIELD_SLEW_DRIVE_SLEW_MAX, sd->slew_max, sd->slew_max > sd->slew_min,
             CRANE_E_CYLINDER);
        friction_rules(v, CRANE_FIELD_SLEW_DRIVE_FRICTION_COULOMB, &sd->friction);
        hydraulics_rules(v, CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_VALVE, &sd->hydraulics);
    }
    if (ec->present != 0) {
        rule(v, CRANE_FIELD_EXTENSION_CYLINDER_ROD, ec->rod, ec->rod > 0, CRANE_E_CYLINDER);
        rule(v, CRANE_FIELD_EXTENSION_CYLINDER_BORE, ec->bore, ec->bore > ec->rod, CRANE_E_CYLINDER);
        friction_rules(v, CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_COULOMB, &ec->friction);
        hydraulics_rules(v, CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_VALVE, &ec->hydraulics);
    }
}

crane_status crane__check_params(const crane_params *p, crane_field *field)
{
    verdict v = {CRANE_OK, CRANE_FIELD_NONE};
    int i;

    rule(&v, CRANE_FIELD_GRAVITY, p->gravity, p->gravity >= 0, CRANE_E_GRAVITY);
    rule(&v, CRANE_FIELD_LOAD_MASS, p->load_mass, p->load_mass >= 0, CRANE_E_BODY);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LIFT_PIVOT, p->lift_pivot);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_BASE, p->lift_cylinder_base);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_ROD, p->lift_cylinder_rod);
    point_rule(&v, CRANE_FIELD_GEOMETRY_TILT_CYLINDER_BASE, p->tilt_cylinder_base);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LINK1_PIVOT, p->link1_pivot);
    point_rule(&v, CRANE_FIELD_GEOMETRY_TILT_PIVOT, p->tilt_pivot);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LINK_PIN, p->link_pin);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LINK2_END, p->link2_end);
    point_rule(&v, CRANE_FIELD_GEOMETRY_LINK2_ATTACH, p->link2_attach);
    point_rule(&v, CRANE_FIELD_GEOMETRY_EXTENSION_MOUNT, p->extension_mount);
    /* The load point lies beyond the extension boom's mount, along its axis. */
    rule(&v, CRANE_FIELD_GEOMETRY_TIP_DISTANCE, p->tip_distance, p->tip_distance > 0, CRANE_E_FIELD);
    rule(&v, CRANE_FIELD_GEOMETRY_EXTENSION_MIN, p->extension_min, 1, CRANE_OK);
    rule(&v, CRANE_FIELD_GEOMETRY_EXTENSION_MAX, p->extension_max,
         p->extension_max >= p->extension_min, CRANE_E_FIELD);
    body_rules(&v, CRANE_FIELD_LIFT_BOOM_MASS, &p->lift_boom, 0);
    body_rules(&v, CRANE_FIELD_OUTER_BOOM_MASS, &p->outer_boom, 0);
    body_rules(&v, CRANE_FIELD_EXTENSION_BOOM_MASS, &p->extension_boom, 0);
    body_rules(&v, CRANE_FIELD_SIDE_LINK1_MASS, &p->side_link1, 1);
    body_rules(&v, CRANE_FIELD_SIDE_LINK2_MASS, &p->side_link2, 1);
    for (i = 0; i < 2; ++i) {
        cylinder_rules(&v, i, &p->cylinder[i]);
    }
    body_rules(&v, CRANE_FIELD_PILLAR_MASS, &p->pillar, 1);
    actuator_rules(&v, p);
    *field = v.field;
    return v.status;
}

/* The rules of a FRICTION block (coulomb .. factor) and a HYDRAULICS block (valve .. leakage), in
 * the order of their fields (crane.h). */
static const char *const FRICTION_RULES[] = {">= 0", ">= coulomb", ">= 0", "> 0", ">= 0"};
static const char *const HYDRAULICS_RULES[] = {
    "orifice or compensated", "> tank_pressure and <= 1e8", ">= 0 and <= 1e8",
    ">= supply_pressure and <= 1e8", "> 0", "> 0",
    "0 for an orifice valve, in [0, 0.99] for a compensated one",
    "> 0 for a compensated valve, >= 0 otherwise", "> 0 for a compensated valve, >= 0 otherwise",
    "in [0, 10]", "> 0", ">= -1e5 and <= tank_pressure", "> 0", "> 0", "> 0", "> 0", "> 0",
    "in [0, 1e-6]"};
enum model_rule_counts {
    N_FRICTION = (int)(sizeof FRICTION_RULES / sizeof FRICTION_RULES[0]),
    N_HYDRAULICS = (int)(sizeof HYDRAULICS_RULES / sizeof HYDRAULICS_RULES[0])
};

/* The rule of field f if it lies in the FRICTION or HYDRAULICS block that starts at the given
 * COULOMB or VALVE field, else NULL. */
static const char *block_rule(crane_field f, crane_field coulomb, crane_field valve)
{
    const int k = (int)f - (int)coulomb, j = (int)f - (int)valve;

    if (k >= 0 && k < N_FRICTION) {
        return FRICTION_RULES[k];
    }
    if (j >= 0 && j < N_HYDRAULICS) {
        return HYDRAULICS_RULES[j];
    }
    return NULL;
}

const char *crane_field_rule(crane_field field)
{
    static const crane_field blocks[4][2] = {
        {CRANE_FIELD_LIFT_CYLINDER_FRICTION_COULOMB, CRANE_FIELD_LIFT_CYLINDER_HYDRAULICS_VALVE},
        {CRANE_FIELD_TILT_CYLINDER_FRICTION_COULOMB, CRANE_FIELD_TILT_CYLINDER_HYDRAULICS_VALVE},
        {CRANE_FIELD_SLEW_DRIVE_FRICTION_COULOMB, CRANE_FIELD_SLEW_DRIVE_HYDRAULICS_VALVE},
        {CRANE_FIELD_EXTENSION_CYLINDER_FRICTION_COULOMB,
         CRANE_FIELD_EXTENSION_CYLINDER_HYDRAULICS_VALVE}};
    int k;

    for (k = 0; k < 4; ++k) {
        const char *r = block_rule(field, blocks[k][0], blocks[k][1]);
        if (r != NULL) {
            return r;
        }
    }
    switch (field) {
    case CRANE_FIELD_GRAVITY:
    case CRANE_FIELD_LOAD_MASS:
    case CRANE_FIELD_LIFT_CYLINDER_STROKE_MIN:
    case CRANE_FIELD_TILT_CYLINDER_STROKE_MIN:
        return ">= 0";
    case CRANE_FIELD_LIFT_CYLINDER_BORE:
    case CRANE_FIELD_TILT_CYLINDER_BORE:
    case CRANE_FIELD_EXTENSION_CYLINDER_BORE:
        return "> rod";
    case CRANE_FIELD_LIFT_CYLINDER_STROKE_MAX:
    case CRANE_FIELD_TILT_CYLINDER_STROKE_MAX:
        return "> stroke_min";
    case CRANE_FIELD_GEOMETRY_TIP_DISTANCE:
    case CRANE_FIELD_LIFT_BOOM_MASS:
    case CRANE_FIELD_LIFT_BOOM_IZZ:
    case CRANE_FIELD_OUTER_BOOM_MASS:
    case CRANE_FIELD_OUTER_BOOM_IZZ:
    case CRANE_FIELD_EXTENSION_BOOM_MASS:
    case CRANE_FIELD_EXTENSION_BOOM_IZZ:
    case CRANE_FIELD_LIFT_CYLINDER_ROD:
    case CRANE_FIELD_LIFT_CYLINDER_LENGTH_RETRACTED:
    case CRANE_FIELD_TILT_CYLINDER_ROD:
    case CRANE_FIELD_TILT_CYLINDER_LENGTH_RETRACTED:
    case CRANE_FIELD_SLEW_DRIVE_BORE:
    case CRANE_FIELD_SLEW_DRIVE_PINION_RADIUS:
    case CRANE_FIELD_EXTENSION_CYLINDER_ROD:
        return "> 0";
    case CRANE_FIELD_SIDE_LINK1_MASS:
    case CRANE_FIELD_SIDE_LINK1_IZZ:
    case CRANE_FIELD_SIDE_LINK2_MASS:
    case CRANE_FIELD_SIDE_LINK2_IZZ:
    case CRANE_FIELD_PILLAR_MASS:
    case CRANE_FIELD_PILLAR_IZZ:
        return ">= 0 (0 = neglected)";
    case CRANE_FIELD_LIFT_BOOM_IXX:
    case CRANE_FIELD_LIFT_BOOM_IYY:
    case CRANE_FIELD_OUTER_BOOM_IXX:
    case CRANE_FIELD_OUTER_BOOM_IYY:
    case CRANE_FIELD_EXTENSION_BOOM_IXX:
    case CRANE_FIELD_EXTENSION_BOOM_IYY:
    case CRANE_FIELD_SIDE_LINK1_IXX:
    case CRANE_FIELD_SIDE_LINK1_IYY:
    case CRANE_FIELD_SIDE_LINK2_IXX:
    case CRANE_FIELD_SIDE_LINK2_IYY:
    case CRANE_FIELD_PILLAR_IXX:
    case CRANE_FIELD_PILLAR_IYY:
        return ">= 0";
    case CRANE_FIELD_LIFT_BOOM_IXY:
    case CRANE_FIELD_OUTER_BOOM_IXY:
    case CRANE_FIELD_EXTENSION_BOOM_IXY:
    case CRANE_FIELD_SIDE_LINK1_IXY:
    case CRANE_FIELD_SIDE_LINK2_IXY:
    case CRANE_FIELD_PILLAR_IXY:
        return "finite";
    case CRANE_FIELD_GEOMETRY_EXTENSION_MIN:
    case CRANE_FIELD_SLEW_DRIVE_SLEW_MIN:
        return "finite";
    case CRANE_FIELD_GEOMETRY_EXTENSION_MAX:
        return ">= extension_min";
    case CRANE_FIELD_SLEW_DRIVE_SLEW_MAX:
        return "> slew_min";
    case CRANE_FIELD_NONE:
    case CRANE_FIELD_COUNT:
        return "";
    default:
        /* every point: pivots, pins, centres of mass */
        return field > CRANE_FIELD_NONE && field < CRANE_FIELD_COUNT ? "a finite pair [x, y]" : "";
    }
}

/* 0 < gamma < pi over the lift stroke. cos(gamma) is monotone in L, so the two ends decide
 * (exact). Returns the field at fault, CRANE_FIELD_NONE if the triangle is valid. */
static crane_field lift_triangle_check(const crane_model *m)
{
    const crane_real db = m->lift_db, dr = m->lift_dr;
    const crane_real l0 = m->params->cylinder[CRANE_LIFT].length_retracted;
    const crane_real ends[2] = {l0 + crane__stroke_min(m, CRANE_LIFT),
                                l0 + crane__stroke_max(m, CRANE_LIFT)};
    int k;

    if (!(db > 0)) {
        return CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_BASE;
    }
    if (!(dr > 0)) {
        return CRANE_FIELD_GEOMETRY_LIFT_CYLINDER_ROD;
    }
    for (k = 0; k < 2; ++k) {
        const crane_real cg = (db * db + dr * dr - ends[k] * ends[k]) / (2 * db * dr);
        if (!(cg > -1 && cg < 1)) {
            return k == 0 ? CRANE_FIELD_LIFT_CYLINDER_STROKE_MIN : CRANE_FIELD_LIFT_CYLINDER_STROKE_MAX;
        }
    }
    return CRANE_FIELD_NONE;
}

crane_status crane__model_derive(crane_model *m, const crane_params *params, crane_real extension,
                                 crane_field *field)
{
    const crane_params *p = params;
    crane_status st;
    crane_vec2 mount_e, x_ext, x_tip;
    crane_real m_ob, m_ext, m_load, th_lo, th_hi, ds;
    int i;

    st = crane__check_params(p, field);
    if (st != CRANE_OK) {
        return st;
    }
    if (crane__finite(extension) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (extension < p->extension_min || extension > p->extension_max) {
        return CRANE_E_EXTENSION;
    }

    m->params = p;
    m->extension = extension;

    {
        crane_real eps, beta;
        m->lift_db = crane__norm(crane__sub(p->lift_cylinder_base, p->lift_pivot));
        m->lift_dr = crane__norm(p->lift_cylinder_rod);
        crane__lift_offsets(p, &eps, &beta);
        crane__sincos(eps - beta, &m->lift_sin_off, &m->lift_cos_off);
    }
    m->tilt_l1 = crane__norm(p->link_pin);
    m->tilt_l2 = crane__norm(p->link2_end);

    /* Body 2: outer boom + extension boom at this extension + the load at the tip. */
    m_ob = p->outer_boom.mass;
    m_ext = p->extension_boom.mass;
    m_load = p->load_mass;
    mount_e = crane__add(p->extension_mount, crane__v2(extension, 0));
    x_ext = crane__add(mount_e, p->extension_boom.com);
    x_tip = crane__add(mount_e, crane__v2(p->tip_distance, 0));
    m->m2 = m_ob + m_ext + m_load;
    m->c2 = crane__scale(1 / m->m2,
                        crane__add(crane__add(crane__scale(m_ob, p->outer_boom.com),
                                              crane__scale(m_ext, x_ext)),
                                   crane__scale(m_load, x_tip)));
    m->i2 = p->outer_boom.izz + m_ob * crane__norm2(crane__sub(p->outer_boom.com, m->c2)) +
           p->extension_boom.izz + m_ext * crane__norm2(crane__sub(x_ext, m->c2)) +
           m_load * crane__norm2(crane__sub(x_tip, m->c2));
    m->j2 = m->i2 + m->m2 * crane__norm2(m->c2);

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
            m->link_ca[i] = n2 > 0 ? crane__dot(link[i]->com, v[i]) / n2 : 0;
            m->link_cb[i] = n2 > 0 ? crane__cross(v[i], link[i]->com) / n2 : 0;
            if (link[i]->mass > 0 || link[i]->izz > 0) {
                m->links = 1;
            }
        }
    }

    *field = lift_triangle_check(m);
    if (*field != CRANE_FIELD_NONE) {
        return CRANE_E_GEOMETRY;
    }
    *field = crane__fourbar_check(m);
    if (*field != CRANE_FIELD_NONE) {
        return CRANE_E_FOURBAR;
    }

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
    crane_field field;
    crane_status st;

    if (model == NULL || params == NULL) {
        return CRANE_E_NULL;
    }
    st = crane__model_derive(&m, params, extension, &field);
    if (st == CRANE_OK) {
        *model = m;
    }
    return st;
}

crane_status crane_params_check(const crane_params *params, crane_field *field)
{
    /* The kinematic rules need the derived lengths: derived at extension_min, which they do not
     * depend on (only the lumped outer boom does). */
    crane_model m;
    crane_field f = CRANE_FIELD_NONE;
    crane_status st;

    if (field != NULL) {
        *field = CRANE_FIELD_NONE;
    }
    if (params == NULL) {
        return CRANE_E_NULL;
    }
    st = crane__model_derive(&m, params, params->extension_min, &f);
    if (field != NULL) {
        *field = st == CRANE_OK ? CRANE_FIELD_NONE : f;
    }
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
    case CRANE_E_HORIZON: return "horizon <= 0";
    case CRANE_E_CAPACITY: return "the output buffer is smaller than the number of samples";
    case CRANE_E_ANGLE: return "an angle is outside the range reachable by the cylinder";
    case CRANE_E_SAMPLE_EVERY: return "sample_every must be in [1, CRANE_MAX_STEPS]";
    case CRANE_E_DIVERGED: return "the prediction diverged (a state not finite or out of range): the parameters are not physical";
    case CRANE_E_FIELD: return "a crane parameter is outside its range";
    case CRANE_E_OVERFLOW: return "an argument is too large: a result would not be finite or a size would overflow";
    case CRANE_E_STEPS: return "horizon / dt asks for more than CRANE_MAX_STEPS (1048576) steps, worst-case substeps included: raise dt or shorten the horizon";
    case CRANE_E_SAMPLE_COUNT: return "more than CRANE_MAX_SAMPLES (8388608) samples in one call: raise sample_every or dt, or split the futures";
    case CRANE_E_BATCH: return "futures x steps over CRANE_MAX_BATCH_STEPS (8388608) in one call: split the futures";
    case CRANE_E_HYDRAULICS: return "a hydraulic parameter is out of range (docs/model.md, Hydraulics)";
    case CRANE_E_VALVE: return "a valve drive is invalid: lever outside [-1, 1], no hydraulics, or a state's chamber pressure/spool out of range";
    case CRANE_E_ACTUATOR: return "a slew or extension drive on a crane without that actuator (its joint can only be held)";
    case CRANE_E_PARAMS: return "n_params must be 1 or n_futures";
    case CRANE_E_METHOD: return "solver: method unknown, or a tolerance outside tip [1e-9, 1] m, pressure [1, 1e7] Pa";
    case CRANE_E_TOLERANCE: return "the error control could not meet the tolerance (a step below the smallest, or the attempt cap)";
    case CRANE_E_SOLID:
    case CRANE_E_PART:
    case CRANE_E_GUARD:
    case CRANE_E_ESTIMATOR: /* the optional modules' messages: the guard's, then the estimator's */
        return crane__guard_status_message(status);
    default: /* not a crane_status: the fallback after the switch */
        break;
    }
    return crane__guard_status_message(status);
}
