/* SPDX-License-Identifier: MIT */
/*
 * The collision guard's verdict on a predicted future (docs/guard.md): the crane's parts posed
 * along the samples, their clearance to every obstacle, the first contact found between samples
 * by conservative advancement, the stop analysis and the signal.
 */
#include "guard_internal.h"

/* The crane at one pose: its joint coordinates q = [theta0, theta1, slew, extension] (the
 * CRANE_LIFT .. CRANE_EXTENSION order), their trig and the pin Q of the side links (lift boom
 * frame). */
typedef struct {
    crane_real q[4], c0, s0, c1, s1, cpsi, spsi;
    crane_vec2 pin;
} pose;

/* Joint j's coordinate and rate in a sample. */
static crane_real coord(const crane_sample *s, int j)
{
    return j < 2 ? s->theta[j] : j == CRANE_SLEW ? s->slew : s->extension;
}

static crane_real coord_rate(const crane_sample *s, int j)
{
    return j < 2 ? s->omega[j] : j == CRANE_SLEW ? s->slew_rate : s->extension_rate;
}

static void pose_at(const crane_model *m, const crane_real q[4], pose *p)
{
    int j;
    for (j = 0; j < 4; ++j) {
        p->q[j] = q[j];
    }
    crane__sincos(q[0], &p->s0, &p->c0);
    crane__sincos(q[1], &p->s1, &p->c1);
    crane__sincos(q[CRANE_SLEW], &p->spsi, &p->cpsi);
    crane__tilt_from_angle(m, p->c1, p->s1, NULL, NULL, &p->pin, NULL);
}

static void pose_sample(const crane_model *m, const crane_sample *s, pose *p)
{
    crane_real q[4];
    int j;
    for (j = 0; j < 4; ++j) {
        q[j] = coord(s, j);
    }
    pose_at(m, q, p);
}

/* The pose at sample s, p holding the pose at the sample before: a coordinate that has not
 * changed keeps its trig and pin (a held joint costs nothing per sample; the same values). */
static void pose_next(const crane_model *m, const crane_sample *s, pose *p)
{
    if (s->theta[0] != p->q[0]) {
        p->q[0] = s->theta[0];
        crane__sincos(p->q[0], &p->s0, &p->c0);
    }
    if (s->theta[1] != p->q[1]) {
        p->q[1] = s->theta[1];
        crane__sincos(p->q[1], &p->s1, &p->c1);
        crane__tilt_from_angle(m, p->c1, p->s1, NULL, NULL, &p->pin, NULL);
    }
    if (s->slew != p->q[CRANE_SLEW]) {
        p->q[CRANE_SLEW] = s->slew;
        crane__sincos(p->q[CRANE_SLEW], &p->spsi, &p->cpsi);
    }
    p->q[CRANE_EXTENSION] = s->extension;
}

/* Where the extension frame's origin is in the outer boom frame at extension e. */
static crane_vec2 extension_origin(const crane_model *m, crane_real e)
{
    return crane__add(m->params->extension_mount, crane__v2(e, 0));
}

/* An anchor in the boom plane at a pose. */
static crane_vec2 plane_point(const crane_model *m, const pose *p, crane_anchor an)
{
    crane_vec2 v = an.at;
    switch (an.frame) {
    case CRANE_FRAME_BASE:
        return v;
    case CRANE_FRAME_LINK_PIN:
        v = crane__add(p->pin, v);
        break;
    case CRANE_FRAME_OUTER:
        v = crane__add(m->params->tilt_pivot, crane__rot(p->c1, p->s1, v));
        break;
    case CRANE_FRAME_EXTENSION:
        v = crane__add(extension_origin(m, p->q[CRANE_EXTENSION]), v);
        v = crane__add(m->params->tilt_pivot, crane__rot(p->c1, p->s1, v));
        break;
    default: /* CRANE_FRAME_LIFT */
        break;
    }
    return crane__add(m->params->lift_pivot, crane__rot(p->c0, p->s0, v));
}

static crane__v3 to_world(crane_vec2 v, const pose *p)
{
    return crane__v3_make(v.x * p->cpsi, v.x * p->spsi, v.y);
}

static void part_solid(const crane_model *m, const crane_part *pt, const pose *p, crane_solid *s)
{
    const crane__v3 a = to_world(plane_point(m, p, pt->a), p);
    int i;

    s->kind = pt->kind;
    s->radius = pt->radius;
    for (i = 0; i < 9; ++i) {
        s->axes[i] = 0;
    }
    for (i = 0; i < 3; ++i) {
        s->half[i] = pt->half[i];
    }
    if (pt->kind == CRANE_SOLID_CAPSULE) {
        crane__v3_store(s->a, a);
        crane__v3_store(s->b, to_world(plane_point(m, p, pt->b), p));
        return;
    }
    /* sphere or box: hangs below its anchor; the box turns with the slew */
    crane__v3_store(s->a, crane__v3_make(a.x, a.y, a.z - pt->drop));
    crane__v3_store(s->b, crane__v3_make(a.x, a.y, a.z - pt->drop));
    s->axes[0] = p->cpsi;
    s->axes[1] = p->spsi;
    s->axes[3] = -p->spsi;
    s->axes[4] = p->cpsi;
    s->axes[8] = 1;
}

/* The index of side link 1's angle phi in a part's rates (after the four joints). */
enum guard_slot { LINK = 4, RATES = 5 };

static crane_real larger(crane_real a, crane_real b)
{
    return a > b ? a : b;
}

/* How far a point of an anchor can move per unit change of each joint coordinate (theta0,
 * theta1, slew, extension) and of phi, side link 1's angle (Q turns about P1 at radius l1), with
 * the extension anywhere in [e_lo, e_hi]: a point moves at most sum_j k[j] d_j, each d_j the
 * largest excursion of that coordinate (motion_bound; docs/guard.md, "Nothing is missed").
 * Move one coordinate at a time: the extension shifts the extension frame by d_e along the outer
 * boom; theta1 and phi, theta0 turn a point about the tilt pivot, P1, the lift pivot (chords are
 * no longer than arcs, |R(a') v' - R(a) v| <= |a' - a| max|v| + |v' - v|); the slew turns it about
 * the vertical axis at its horizontal distance, at most |O1.x| + its distance from the lift pivot. */
static void anchor_rates(const crane_model *m, crane_anchor an, crane_real e_lo, crane_real e_hi,
                         crane_real k[RATES])
{
    const crane_real r = crane__norm(an.at);
    int j;
    for (j = 0; j < RATES; ++j) {
        k[j] = 0;
    }
    switch (an.frame) {
    case CRANE_FRAME_BASE:
        k[CRANE_SLEW] = crane__fabs(an.at.x);
        return;
    case CRANE_FRAME_LINK_PIN:
        k[0] = crane__norm(m->params->link1_pivot) + m->tilt_l1 + r;
        k[LINK] = m->tilt_l1;
        break;
    case CRANE_FRAME_OUTER:
        k[0] = crane__norm(m->params->tilt_pivot) + r;
        k[1] = r;
        break;
    case CRANE_FRAME_EXTENSION: {
        /* |origin(e) + at| is convex in e: largest at an end of the range */
        const crane_real re = larger(crane__norm(crane__add(extension_origin(m, e_lo), an.at)),
                                     crane__norm(crane__add(extension_origin(m, e_hi), an.at)));
        k[0] = crane__norm(m->params->tilt_pivot) + re;
        k[1] = re;
        k[CRANE_EXTENSION] = 1;
        break;
    }
    default: /* CRANE_FRAME_LIFT */
        k[0] = r;
        break;
    }
    k[CRANE_SLEW] = crane__fabs(m->params->lift_pivot.x) + k[0];
}

static void part_rates(const crane_model *m, const crane_part *pt, crane_real e_lo, crane_real e_hi,
                       crane_real k[RATES])
{
    int i;
    anchor_rates(m, pt->a, e_lo, e_hi, k);
    if (pt->kind == CRANE_SOLID_CAPSULE) {
        crane_real kb[RATES];
        /* every point of the segment is a convex combination of its ends */
        anchor_rates(m, pt->b, e_lo, e_hi, kb);
        for (i = 0; i < RATES; ++i) {
            k[i] = larger(k[i], kb[i]);
        }
    } else if (pt->kind == CRANE_SOLID_BOX) {
        /* the box turns with the slew about the vertical axis: its corners lie up to its
         * horizontal half diagonal further out than its centre */
        k[CRANE_SLEW] += crane__sqrt(pt->half[0] * pt->half[0] + pt->half[1] * pt->half[1]);
    } else {
        /* a sphere: its centre's rates bound every point of it */
    }
}

/* The angle side link 1 turns between two pins Q. */
static crane_real link_turn(const crane_model *m, crane_vec2 a, crane_vec2 b)
{
    const crane_vec2 u = crane__sub(a, m->params->link1_pivot), v = crane__sub(b, m->params->link1_pivot);
    return crane__fabs(crane__atan2(crane__cross(u, v), crane__dot(u, v)));
}

/* The angle side link 1 turns from the pin Q at a to where it is at tilt angle theta1. */
static CRANE__NOINLINE crane_real link_turn_to(const crane_model *m, crane_vec2 a, crane_real theta1)
{
    crane_real c, sn;
    crane_vec2 b;
    crane__sincos(theta1, &sn, &c);
    crane__tilt_from_angle(m, c, sn, NULL, NULL, &b, NULL);
    return link_turn(m, a, b);
}

/* q_j(u) over one step, u = (t - s0.t) / (s1.t - s0.t) in [0, 1]: the cubic Hermite interpolant
 * of the samples' coordinates and rates, c[0] + c[1] u + c[2] u^2 + c[3] u^3. It matches the
 * model's motion to O(h^4) (docs/guard.md, "Nothing is missed"). */
static void hermite(const crane_sample *s0, const crane_sample *s1, int j, crane_real c[4])
{
    const crane_real h = s1->t - s0->t, d = coord(s1, j) - coord(s0, j);
    const crane_real m0 = h * coord_rate(s0, j), m1 = h * coord_rate(s1, j);
    c[0] = coord(s0, j);
    c[1] = m0;
    c[2] = 3 * d - 2 * m0 - m1;
    c[3] = -2 * d + m0 + m1;
}

static crane_real cubic_at(const crane_real c[4], crane_real u)
{
    return c[0] + u * (c[1] + u * (c[2] + u * c[3]));
}

static void widen(crane_real v, crane_real *lo, crane_real *hi)
{
    if (v < *lo) {
        *lo = v;
    }
    if (v > *hi) {
        *hi = v;
    }
}

/* The range [lo, hi] of q_j over [ua, ub]: its values at the ends and at the cubic's
 * stationary points between them (roots of c1 + 2 c2 u + 3 c3 u^2). */
static void coord_range(const crane_sample *s0, const crane_sample *s1, int j, crane_real ua,
                        crane_real ub, crane_real *lo, crane_real *hi)
{
    crane_real c[4], qa, qb, qc;
    hermite(s0, s1, j, c);
    *lo = *hi = cubic_at(c, ua);
    widen(cubic_at(c, ub), lo, hi);
    qa = 3 * c[3];
    qb = 2 * c[2];
    qc = c[1];
    if (qa != 0) {
        const crane_real disc = qb * qb - 4 * qa * qc;
        if (disc >= 0) {
            const crane_real sq = crane__sqrt(disc);
            const crane_real r0 = (-qb - sq) / (2 * qa), r1 = (-qb + sq) / (2 * qa);
            if (r0 > ua && r0 < ub) {
                widen(cubic_at(c, r0), lo, hi);
            }
            if (r1 > ua && r1 < ub) {
                widen(cubic_at(c, r1), lo, hi);
            }
        }
    } else if (qb != 0) {
        const crane_real r = -qc / qb;
        if (r > ua && r < ub) {
            widen(cubic_at(c, r), lo, hi);
        }
    } else {
        /* at most linear: its ends bound it */
    }
}

/* How far any point of a part (rates k, anchor_rates) can get, at any u in [ua, ub] of the step
 * s0 -> s1, from where it is at ua (pose *a): each coordinate's largest excursion from its value
 * at ua, and side link 1's, which is monotone in theta1 (one sign of ds/dtheta1 over the stroke,
 * the crane check), so its extremes are at theta1's. Coordinates a part does not move with are
 * skipped. */
static CRANE__NOINLINE crane_real motion_bound(const crane_real k[RATES], const crane_model *m,
                                               const crane_sample *s0, const crane_sample *s1,
                                               crane_real ua, crane_real ub, const pose *a)
{
    crane_real lo, hi, d = 0;
    int j;
    for (j = 0; j < 4; ++j) {
        /* a coordinate at rest over the step (the same value, no rate at either end) stays put */
        const int still = coord(s0, j) == coord(s1, j) && coord_rate(s0, j) == 0 &&
                          coord_rate(s1, j) == 0;
        if (still == 0 && (k[j] > 0 || (j == CRANE_TILT && k[LINK] > 0))) {
            coord_range(s0, s1, j, ua, ub, &lo, &hi);
            d += k[j] * larger(hi - a->q[j], a->q[j] - lo);
            if (j == CRANE_TILT && k[LINK] > 0) {
                d += k[LINK] * larger(link_turn_to(m, a->pin, lo), link_turn_to(m, a->pin, hi));
            }
        }
    }
    return d;
}

/* Everything the search needs that stays fixed during one call. */
typedef struct {
    const crane_model *m;
    const crane_part *parts;
    const crane_solid *obstacles;
    crane_solid *posed;          /* the caller's one posed part: shared to keep frames small */
    size_t evaluations;
} scene;

/* The clearance of the posed part (sc->posed) to obstacle j; the closest points if pa, pb. */
static crane_real clearance(scene *sc, size_t j, crane__v3 *pa, crane__v3 *pb)
{
    crane__v3 qa, qb;
    crane_real d = 0;
    (void)crane__solid_distance(sc->posed, &sc->obstacles[j], &d, pa != NULL ? pa : &qa,
                                pb != NULL ? pb : &qb);
    sc->evaluations++;
    return d;
}

/* Poses part i at p into sc->posed and measures it against obstacle j. */
static crane_real pair_distance(scene *sc, size_t i, size_t j, const pose *p, crane__v3 *pa,
                                crane__v3 *pb)
{
    part_solid(sc->m, &sc->parts[i], p, sc->posed);
    return clearance(sc, j, pa, pb);
}

/* The pose at u of the step s0 -> s1 (Hermite coordinates). */
static void pose_between(const crane_model *m, const crane_sample *s0, const crane_sample *s1,
                         crane_real u, pose *p)
{
    crane_real c[4], q[4];
    int j;
    for (j = 0; j < 4; ++j) {
        hermite(s0, s1, j, c);
        q[j] = cubic_at(c, u);
    }
    pose_at(m, q, p);
}

/* Conservative advancement of one pair over one step, from the sample s0 to s1: from a time with
 * clearance d > margin, jump ahead as far as the motion bound lets the clearance drop by less
 * than d - margin (halving the jump until it does), evaluate there, repeat. Returns 1 with
 * *u_hit (the fraction of the step) if the clearance is <= margin there, or cannot be shown to
 * stay above it beyond (the jump shrank below tol, a fraction of the step); 0 if it stays above
 * over the whole step, with *d_end the clearance at s1. */
static CRANE__NOINLINE int advance(scene *sc, size_t i, size_t j, const crane_real k[RATES],
                                   const crane_sample *s0, const crane_sample *s1,
                                   crane_real margin, crane_real tol, crane_real *u_hit,
                                   crane_real *d_end)
{
    pose a;
    crane_real ua = 0, d;

    pose_sample(sc->m, s0, &a);
    d = pair_distance(sc, i, j, &a, NULL, NULL);
    for (;;) {
        crane_real ub = 1;
        if (d <= margin) {
            *u_hit = ua;
            return 1;
        }
        while (motion_bound(k, sc->m, s0, s1, ua, ub, &a) > d - margin) {
            if (ub - ua <= tol) {
                *u_hit = ua;
                return 1;
            }
            ub = ua + (ub - ua) / 2;
        }
        if (!(ub > ua)) { /* no progress left in this precision: cannot exclude the contact */
            *u_hit = ua;
            return 1;
        }
        if (ub >= 1) {
            pose_sample(sc->m, s1, &a);
            *d_end = pair_distance(sc, i, j, &a, NULL, NULL);
            return 0;
        }
        ua = ub;
        pose_between(sc->m, s0, s1, ua, &a);
        d = pair_distance(sc, i, j, &a, NULL, NULL);
    }
}

static crane_status check_config(const crane_guard_config *c)
{
    if (crane__finite(c->margin) == 0 || crane__finite(c->reaction) == 0 ||
        crane__finite(c->cycle) == 0 || crane__finite(c->time_tolerance) == 0 ||
        crane__finite(c->clearance_tolerance) == 0) {
        return CRANE_E_NONFINITE;
        }
    if (c->margin < 0 || c->reaction < 0 || !(c->cycle > 0) || !(c->time_tolerance > 0) ||
        c->clearance_tolerance < 0) {
        return CRANE_E_GUARD;
        }
    return CRANE_OK;
}

static int anchor_ok(crane_anchor an)
{
    return an.frame >= CRANE_FRAME_BASE && an.frame <= CRANE_FRAME_EXTENSION &&
           crane__length_ok(an.at.x) && crane__length_ok(an.at.y);
}

static int part_field(const crane_part *p)
{
    int i;
    if (p->kind != CRANE_SOLID_CAPSULE && p->kind != CRANE_SOLID_SPHERE && p->kind != CRANE_SOLID_BOX) {
        return CRANE_GUARD_FIELD_KIND;
    }
    if (anchor_ok(p->a) == 0) {
        return CRANE_GUARD_FIELD_A;
    }
    if (p->kind == CRANE_SOLID_CAPSULE) {
        if (anchor_ok(p->b) == 0) {
            return CRANE_GUARD_FIELD_B;
        }
        if (!(crane__length_ok(p->radius) != 0 && p->radius >= 0)) {
            return CRANE_GUARD_FIELD_RADIUS;
        }
        return 0;
    }
    if (crane__length_ok(p->drop) == 0) {
        return CRANE_GUARD_FIELD_DROP;
    }
    if (p->kind == CRANE_SOLID_SPHERE) {
        return crane__length_ok(p->radius) != 0 && p->radius > 0 ? 0 : CRANE_GUARD_FIELD_RADIUS;
    }
    for (i = 0; i < 3; ++i) {
        if (!(crane__length_ok(p->half[i]) != 0 && p->half[i] > 0)) {
            return CRANE_GUARD_FIELD_HALF;
        }
    }
    return 0;
}

crane_status crane_guard_check(const crane_part *parts, size_t n_parts, const crane_solid *obstacles,
                               size_t n_obstacles, size_t *which, int *field)
{
    size_t i;
    if ((n_parts != 0u && parts == NULL) || (n_obstacles != 0u && obstacles == NULL) ||
        which == NULL || field == NULL) {
        return CRANE_E_NULL;
    }
    for (i = 0; i < n_parts; ++i) {
        const int f = part_field(&parts[i]);
        if (f != 0) {
            *which = i;
            *field = f;
            return CRANE_E_PART;
        }
    }
    for (i = 0; i < n_obstacles; ++i) {
        const int f = crane__solid_field(&obstacles[i]);
        if (f != 0) {
            *which = i;
            *field = f;
            return CRANE_E_SOLID;
        }
    }
    return CRANE_OK;
}

crane_status crane_part_solids(const crane_model *model, const crane_part *parts, size_t n_parts,
                               crane_real slew, crane_real extension, const crane_real theta[2],
                               crane_solid *out)
{
    size_t i, which;
    int field;
    crane_real q[4];
    pose p;
    crane_status st;

    if (model == NULL || theta == NULL || (n_parts != 0u && (parts == NULL || out == NULL))) {
        return CRANE_E_NULL;
    }
    st = crane_guard_check(parts, n_parts, NULL, 0, &which, &field);
    if (st != CRANE_OK) {
        return st;
    }
    if (crane__finite(slew) == 0 || crane__finite(extension) == 0 || crane__finite(theta[0]) == 0 ||
        crane__finite(theta[1]) == 0) {
        return CRANE_E_NONFINITE;
        }
    if (extension < model->params->extension_min || extension > model->params->extension_max) {
        return CRANE_E_EXTENSION;
    }
    q[0] = theta[0];
    q[1] = theta[1];
    q[CRANE_SLEW] = slew;
    q[CRANE_EXTENSION] = extension;
    pose_at(model, q, &p);
    for (i = 0; i < n_parts; ++i) {
        part_solid(model, &parts[i], &p, &out[i]);
    }
    return CRANE_OK;
}

static crane_status check_samples(const crane_model *m, const crane_sample *s, size_t n)
{
    size_t k;
    int j;
    for (k = 0; k < n; ++k) {
        if (crane__finite(s[k].t) == 0) {
            return CRANE_E_NONFINITE;
        }
        if (k > 0 && !(s[k].t > s[k - 1].t)) {
            return CRANE_E_SAMPLES;
        }
        for (j = 0; j < 4; ++j) {
            if (crane__finite(coord(&s[k], j)) == 0 || crane__finite(coord_rate(&s[k], j)) == 0) {
                return CRANE_E_NONFINITE;
            }
        }
        for (j = 0; j < 2; ++j) {
            if (s[k].theta[j] < m->theta_min[j] || s[k].theta[j] > m->theta_max[j]) {
                return CRANE_E_ANGLE;
            }
        }
        if (s[k].extension < m->params->extension_min || s[k].extension > m->params->extension_max) {
            return CRANE_E_EXTENSION;
        }
    }
    return CRANE_OK;
}

/* The pair's clearance gradient in the four joint coordinates (central differences) and its
 * rate from each joint's motion (rate[j]). */
static CRANE__NOINLINE void approach(scene *sc, crane_guard_result *r, const crane_real rate[4])
{
    const crane_real h = sizeof(crane_real) < sizeof(double) ? (crane_real)1e-3 : (crane_real)1e-6;
    int j;
    for (j = 0; j < 4; ++j) {
        crane_real q[4], dp;
        pose p;
        q[0] = r->theta[0];
        q[1] = r->theta[1];
        q[CRANE_SLEW] = r->slew;
        q[CRANE_EXTENSION] = r->extension;
        q[j] += h;
        pose_at(sc->m, q, &p);
        dp = pair_distance(sc, (size_t)r->part, (size_t)r->obstacle, &p, NULL, NULL);
        q[j] -= 2 * h;
        pose_at(sc->m, q, &p);
        r->gradient[j] = (dp - pair_distance(sc, (size_t)r->part, (size_t)r->obstacle, &p, NULL, NULL)) / (2 * h);
        r->approach[j] = r->gradient[j] * rate[j];
    }
}
static CRANE__NOINLINE void record_contact(scene *sc, crane_guard_result *r, size_t i, size_t j,
                                           crane_real t, const pose *p)
{
    crane__v3 pa, pb;
    r->contact = 1;
    r->t = t;
    r->part = (int)i;
    r->obstacle = (int)j;
    r->theta[0] = p->q[0];
    r->theta[1] = p->q[1];
    r->slew = p->q[CRANE_SLEW];
    r->extension = p->q[CRANE_EXTENSION];
    r->clearance = pair_distance(sc, i, j, p, &pa, &pb);
    crane__v3_store(r->on_part, pa);
    crane__v3_store(r->on_obstacle, pb);
}

/* The time tolerance as a fraction of a step, at least 1e-3: each jump of the advancement is
 * longer than half of it, so one pair takes at most 2,000 jumps over one step (a pair of boxes
 * about 14,000 x86 instructions a jump; the worst case of a call is that times the pairs and the
 * steps: a samples' slew rate of 1e7 rad/s with a tolerance of 1e-4 of a step took 31 G). */
static crane_real u_tolerance(crane_real time_tolerance, crane_real h)
{
    const crane_real u = time_tolerance / h, u_min = (crane_real)1e-3;
    return u > u_min ? u : u_min;
}

/* dq_j/dt at the fraction u of the step s0 -> s1 (the Hermite coordinates' derivatives). */
static CRANE__NOINLINE void rates_at(const crane_sample *s0, const crane_sample *s1, crane_real u,
                                     crane_real rate[4])
{
    int k;
    for (k = 0; k < 4; ++k) {
        crane_real c[4];
        hermite(s0, s1, k, c);
        rate[k] = (c[1] + u * (2 * c[2] + u * 3 * c[3])) / (s1->t - s0->t);
    }
}

/* A contact of pair (i, j) at the fraction u of the step s0 -> s1: its time, pose, points and the
 * joint rates there. */
static CRANE__NOINLINE void note_contact(scene *sc, crane_guard_result *r, size_t i, size_t j,
                                         const crane_sample *s0, const crane_sample *s1,
                                         crane_real u, crane_real rate[4])
{
    pose p;
    rates_at(s0, s1, u, rate);
    pose_between(sc->m, s0, s1, u, &p);
    record_contact(sc, r, i, j, s0->t + u * (s1->t - s0->t), &p);
}

/* The range [lo, hi] of the extension over the whole future (the Hermite motion between samples
 * included): it bounds the distance of the extension boom's points from the tilt pivot. */
static CRANE__NOINLINE void extension_range(const crane_sample *s, size_t n, crane_real *lo,
                                            crane_real *hi)
{
    size_t k;
    *lo = *hi = s[0].extension;
    for (k = 1; k < n; ++k) {
        crane_real a, b;
        coord_range(&s[k - 1], &s[k], CRANE_EXTENSION, 0, 1, &a, &b);
        widen(a, lo, hi);
        widen(b, lo, hi);
    }
}

/* A part's bound accumulated over the step s0 -> s1 (pose *p0 at s0): sum_j k_j times the
 * largest excursion of coordinate j, as in motion_bound, but for all parts at once: the
 * excursions are computed once per step (unit rates) and weighted per part. */
static CRANE__NOINLINE void step_excursions(const crane_model *m, const crane_sample *s0,
                                            const crane_sample *s1, const pose *p0,
                                            crane_real ex[RATES])
{
    int j;
    for (j = 0; j < RATES; ++j) {
        crane_real unit[RATES] = {0, 0, 0, 0, 0};
        unit[j] = 1;
        ex[j] = motion_bound(unit, m, s0, s1, 0, 1, p0);
    }
}

crane_status crane_guard(const crane_model *model, const crane_part *parts, size_t n_parts,
                         const crane_solid *obstacles, size_t n_obstacles,
                         const crane_sample *samples, size_t n_samples,
                         const crane_guard_config *config, crane_real *part_clearance,
                         crane_real *work, size_t work_capacity, crane_guard_result *result)
{
    const size_t n_pairs = n_parts * n_obstacles;
    enum guard_key { CUM = RATES, MIN_KEY = RATES + 1 };
    crane_real *key, *per;
    crane_real margin, hit_rate[4] = {0, 0, 0, 0}, e_lo, e_hi;
    scene sc;
    pose cur;
    crane_solid ps;
    size_t i, j, k, which;
    int field, searching = 1;
    crane_status st;

    if (model == NULL || samples == NULL || config == NULL || result == NULL ||
        (n_parts != 0u && (parts == NULL || part_clearance == NULL)) ||
        (n_obstacles != 0u && obstacles == NULL) || (n_parts != 0u && work == NULL)) {
        return CRANE_E_NULL;
        }
    st = check_config(config);
    if (st == CRANE_OK) {
        st = crane_guard_check(parts, n_parts, obstacles, n_obstacles, &which, &field);
    }
    if (st != CRANE_OK) {
        return st;
    }
    if (n_samples == 0) {
        return CRANE_E_SAMPLES;
    }
    st = check_samples(model, samples, n_samples);
    if (st != CRANE_OK) {
        return st;
    }
    if (n_parts != 0u && (n_obstacles > ((size_t)-1) / n_parts - CRANE_GUARD_PART_WORK ||
                    work_capacity < n_pairs + CRANE_GUARD_PART_WORK * n_parts)) {
        return CRANE_E_CAPACITY;
                    }

    sc.m = model;
    sc.parts = parts;
    sc.obstacles = obstacles;
    sc.posed = &ps;
    sc.evaluations = 0;
    key = work;
    per = &work[n_pairs]; /* per part: its RATES motion rates, cumulative bound, smallest key */
    extension_range(samples, n_samples, &e_lo, &e_hi);
    for (i = 0; i < n_parts; ++i) {
        crane_real *pp = &per[CRANE_GUARD_PART_WORK * i];
        part_rates(model, &parts[i], e_lo, e_hi, pp);
        pp[CUM] = 0;
        pp[MIN_KEY] = (crane_real)INFINITY;
        part_clearance[i] = (crane_real)INFINITY;
    }
    result->signal = CRANE_GO;
    result->contact = 0;
    result->at_start = 0;
    result->t = 0;
    result->part = result->obstacle = -1;
    result->clearance = (crane_real)INFINITY;
    for (k = 0; k < 3; ++k) {
        result->on_part[k] = result->on_obstacle[k] = 0;
    }
    result->theta[0] = result->theta[1] = result->slew = result->extension = 0;
    for (k = 0; k < 4; ++k) {
        result->gradient[k] = result->approach[k] = 0;
    }
    result->stop_latest = 0;
    margin = config->margin;

    /* Each pair keeps key = its clearance when last evaluated + the part's cumulative motion bound
     * then, so its lower bound now is key - cum (cum: the part's bound summed from t = 0); a part
     * whose smallest key keeps every pair above its threshold costs O(1) per step. */
    pose_sample(model, &samples[0], &cur);
    for (i = 0; i < n_parts; ++i) {
        crane_real *pp = &per[CRANE_GUARD_PART_WORK * i];
        part_solid(model, &parts[i], &cur, &ps);
        for (j = 0; j < n_obstacles; ++j) {
            const crane_real d = clearance(&sc, j, NULL, NULL);
            key[i * n_obstacles + j] = d;
            if (d < pp[MIN_KEY]) {
                pp[MIN_KEY] = d;
            }
            if (d < part_clearance[i]) {
                part_clearance[i] = d;
            }
            if (d <= margin && (result->contact == 0 || d < result->clearance)) {
                record_contact(&sc, result, i, j, samples[0].t, &cur); /* re-poses ps: same pose */
                result->at_start = 1;
                for (k = 0; k < 4; ++k) {
                    hit_rate[k] = coord_rate(&samples[0], (int)k);
                }
            }
        }
    }
    searching = !result->contact;

    for (k = 1; k < n_samples; ++k) {
        const crane_sample *s0 = &samples[k - 1], *s1 = &samples[k];
        crane_real ex[RATES];
        int found = 0;
        step_excursions(model, s0, s1, &cur, ex); /* cur: the pose at s0 until re-posed here */
        pose_next(model, s1, &cur);
        for (i = 0; i < n_parts; ++i) {
            crane_real *pp = &per[CRANE_GUARD_PART_WORK * i];
            const crane_real floor_min = part_clearance[i] - config->clearance_tolerance;
            crane_real least, min_key = (crane_real)INFINITY;
            int r, posed = 0; /* ps: the part at this sample, posed when first needed */
            for (r = 0; r < RATES; ++r) {
                pp[CUM] += pp[r] * ex[r];
            }
            least = pp[MIN_KEY] - pp[CUM];
            if ((searching == 0 || least > margin) && least >= floor_min) {
                continue;
            }
            for (j = 0; j < n_obstacles; ++j) {
                crane_real *kj = &key[i * n_obstacles + j];
                const crane_real lb = *kj - pp[CUM];
                crane_real d;
                if (searching != 0 && lb <= margin) {
                    crane_real u_hit;
                    if (advance(&sc, i, j, pp, s0, s1, margin,
                                u_tolerance(config->time_tolerance, s1->t - s0->t), &u_hit,
                                &d) != 0) {
                        if (found == 0 || s0->t + u_hit * (s1->t - s0->t) < result->t) {
                            note_contact(&sc, result, i, j, s0, s1, u_hit, hit_rate);
                            if (result->clearance < part_clearance[i]) {
                                part_clearance[i] = result->clearance;
                            }
                            found = 1;
                        }
                        d = pair_distance(&sc, i, j, &cur, NULL, NULL);
                    }
                    posed = 1; /* both ways end with ps posed at this sample */
                    *kj = d + pp[CUM];
                    if (d < part_clearance[i]) {
                        part_clearance[i] = d;
                    }
                } else if (lb < floor_min) {
                    if (posed == 0) {
                        part_solid(model, &parts[i], &cur, &ps);
                    }
                    posed = 1;
                    d = clearance(&sc, j, NULL, NULL);
                    *kj = d + pp[CUM];
                    if (d < part_clearance[i]) {
                        part_clearance[i] = d;
                    }
                } else {
                    /* its bound clears the margin and the part's least clearance: key kept */
                }
                if (*kj < min_key) {
                    min_key = *kj;
                }
            }
            pp[MIN_KEY] = min_key;
        }
        if (found != 0) {
            searching = 0;
        }
    }

    if (result->contact != 0) {
        approach(&sc, result, hit_rate);
        result->stop_latest = result->t - config->reaction;
        result->signal = (result->at_start != 0 || result->stop_latest < config->cycle) ? CRANE_STOP
                                                                                   : CRANE_WARN;
    }
    result->evaluations = sc.evaluations;
    return CRANE_OK;
}

const char *crane__guard_status_message(crane_status status)
{
    switch ((int)status) {
    case CRANE_E_SOLID: return "an obstacle (solid) is not valid, or a distance between two planes was asked";
    case CRANE_E_PART: return "a crane part (shape) is not valid";
    case CRANE_E_GUARD: return "a guard setting is out of range (margin >= 0, reaction >= 0, cycle > 0, time_tolerance > 0, clearance_tolerance >= 0)";
    default: return crane__estimator_status_message(status); /* the next module's, or unknown */
    }
}
