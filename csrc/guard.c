/* SPDX-License-Identifier: MIT */
/*
 * The collision guard's verdict on a predicted future (docs/guard.md): the crane's parts posed
 * along the samples, their clearance to every obstacle, the first contact found between samples
 * by conservative advancement, the stop analysis and the signal.
 */
#include "guard_internal.h"

/* The crane at one pose: the trig of both joints and the pin Q of the side links (lift boom frame). */
typedef struct {
    crane_real th[2], c0, s0, c1, s1;
    crane_vec2 q;
} pose;

static void pose_at(const crane_model *m, crane_real th0, crane_real th1, pose *p)
{
    p->th[0] = th0;
    p->th[1] = th1;
    crane__sincos(th0, &p->s0, &p->c0);
    crane__sincos(th1, &p->s1, &p->c1);
    crane__tilt_from_angle(m, p->c1, p->s1, NULL, NULL, &p->q, NULL);
}

/* An anchor in the boom plane at a pose. */
static crane_vec2 plane_point(const crane_model *m, const pose *p, crane_anchor an)
{
    crane_vec2 v = an.at;
    switch (an.frame) {
    case CRANE_FRAME_BASE:
        return v;
    case CRANE_FRAME_LINK_PIN:
        v = crane__add(p->q, v);
        break;
    case CRANE_FRAME_OUTER:
        v = crane__add(m->params->tilt_pivot, crane__rot(p->c1, p->s1, v));
        break;
    case CRANE_FRAME_EXTENSION:
        v = crane__add(crane__add(m->params->extension_mount, crane__v2(m->extension, 0)), v);
        v = crane__add(m->params->tilt_pivot, crane__rot(p->c1, p->s1, v));
        break;
    default: /* CRANE_FRAME_LIFT */
        break;
    }
    return crane__add(m->params->lift_pivot, crane__rot(p->c0, p->s0, v));
}

static crane__v3 to_world(crane_vec2 v, crane_real cpsi, crane_real spsi)
{
    return crane__v3_make(v.x * cpsi, v.x * spsi, v.y);
}

static void part_solid(const crane_model *m, const crane_part *pt, const pose *p, crane_real cpsi,
                       crane_real spsi, crane_solid *s)
{
    const crane__v3 a = to_world(plane_point(m, p, pt->a), cpsi, spsi);
    int i;

    s->kind = pt->kind;
    s->radius = pt->radius;
    for (i = 0; i < 9; ++i)
        s->axes[i] = 0;
    for (i = 0; i < 3; ++i)
        s->half[i] = pt->half[i];
    if (pt->kind == CRANE_SOLID_CAPSULE) {
        crane__v3_store(s->a, a);
        crane__v3_store(s->b, to_world(plane_point(m, p, pt->b), cpsi, spsi));
        return;
    }
    /* sphere or box: hangs below its anchor; the box turns with the slew */
    crane__v3_store(s->a, crane__v3_make(a.x, a.y, a.z - pt->drop));
    crane__v3_store(s->b, crane__v3_make(a.x, a.y, a.z - pt->drop));
    s->axes[0] = cpsi;
    s->axes[1] = spsi;
    s->axes[3] = -spsi;
    s->axes[4] = cpsi;
    s->axes[8] = 1;
}

/* How far a point of an anchor can move per unit change of (theta0, theta1, phi), phi being the
 * angle of side link 1 (Q turns about P1 at radius l1). Chords are no longer than arcs, and
 * |R(a') v' - R(a) v| <= |a' - a| max|v| + |v' - v|, so a point moves at most
 * k[0] d0 + k[1] d1 + k[2] dphi, each d the largest excursion of that angle (motion_bound). */
static void anchor_rates(const crane_model *m, crane_anchor an, crane_real k[3])
{
    const crane_real r = crane__norm(an.at);
    k[0] = k[1] = k[2] = 0;
    switch (an.frame) {
    case CRANE_FRAME_LIFT:
        k[0] = r;
        break;
    case CRANE_FRAME_LINK_PIN:
        k[0] = crane__norm(m->params->link1_pivot) + m->tilt_l1 + r;
        k[2] = m->tilt_l1;
        break;
    case CRANE_FRAME_OUTER:
        k[0] = crane__norm(m->params->tilt_pivot) + r;
        k[1] = r;
        break;
    case CRANE_FRAME_EXTENSION: {
        const crane_real re = crane__norm(crane__add(
            crane__add(m->params->extension_mount, crane__v2(m->extension, 0)), an.at));
        k[0] = crane__norm(m->params->tilt_pivot) + re;
        k[1] = re;
        break;
    }
    default: /* the boom plane does not move during a prediction */
        break;
    }
}

static void part_rates(const crane_model *m, const crane_part *pt, crane_real k[3])
{
    anchor_rates(m, pt->a, k);
    if (pt->kind == CRANE_SOLID_CAPSULE) {
        crane_real kb[3];
        int i;
        /* every point of the segment is a convex combination of its ends */
        anchor_rates(m, pt->b, kb);
        for (i = 0; i < 3; ++i)
            k[i] = kb[i] > k[i] ? kb[i] : k[i];
    }
}

/* The angle side link 1 turns between two poses. */
static crane_real link_turn(const crane_model *m, const pose *a, const pose *b)
{
    const crane_vec2 u = crane__sub(a->q, m->params->link1_pivot), v = crane__sub(b->q, m->params->link1_pivot);
    return crane__fabs(crane__atan2(crane__cross(u, v), crane__dot(u, v)));
}

/* theta_j(u) over one step, u = (t - s0.t) / (s1.t - s0.t) in [0, 1]: the cubic Hermite
 * interpolant of the samples' angles and rates, c[0] + c[1] u + c[2] u^2 + c[3] u^3. It matches
 * the model's motion to O(h^4) (docs/guard.md, "Nothing is missed"). */
static void hermite(const crane_sample *s0, const crane_sample *s1, int j, crane_real c[4])
{
    const crane_real h = s1->t - s0->t, d = s1->theta[j] - s0->theta[j];
    const crane_real m0 = h * s0->omega[j], m1 = h * s1->omega[j];
    c[0] = s0->theta[j];
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
    if (v < *lo)
        *lo = v;
    if (v > *hi)
        *hi = v;
}

/* The range [lo, hi] of theta_j over [ua, ub]: its values at the ends and at the cubic's
 * stationary points between them (roots of c1 + 2 c2 u + 3 c3 u^2). */
static void angle_range(const crane_sample *s0, const crane_sample *s1, int j, crane_real ua,
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
            if (r0 > ua && r0 < ub)
                widen(cubic_at(c, r0), lo, hi);
            if (r1 > ua && r1 < ub)
                widen(cubic_at(c, r1), lo, hi);
        }
    } else if (qb != 0) {
        const crane_real r = -qc / qb;
        if (r > ua && r < ub)
            widen(cubic_at(c, r), lo, hi);
    }
}

static crane_real larger(crane_real a, crane_real b)
{
    return a > b ? a : b;
}

/* How far any point of a part (rates k, anchor_rates) can get, at any u in [ua, ub] of the step
 * s0 -> s1, from where it is at ua (pose *a): each joint's largest excursion from its angle at
 * ua, and side link 1's, which is monotone in theta1 (one sign of ds/dtheta1 over the stroke, the
 * crane check), so its extremes are at theta1's. */
static CRANE__NOINLINE crane_real motion_bound(const crane_real k[3], const crane_model *m,
                                               const crane_sample *s0, const crane_sample *s1,
                                               crane_real ua, crane_real ub, const pose *a)
{
    crane_real lo, hi, d;
    angle_range(s0, s1, 0, ua, ub, &lo, &hi);
    d = k[0] * larger(hi - a->th[0], a->th[0] - lo);
    angle_range(s0, s1, 1, ua, ub, &lo, &hi);
    d += k[1] * larger(hi - a->th[1], a->th[1] - lo);
    if (k[2] > 0) {
        pose e;
        crane_real turn;
        pose_at(m, a->th[0], lo, &e);
        turn = link_turn(m, a, &e);
        pose_at(m, a->th[0], hi, &e);
        d += k[2] * larger(turn, link_turn(m, a, &e));
    }
    return d;
}

/* Everything the search needs that stays fixed during one call. */
typedef struct {
    const crane_model *m;
    const crane_part *parts;
    const crane_solid *obstacles;
    crane_solid *posed;          /* the caller's one posed part: shared to keep frames small */
    crane_real cpsi, spsi;
    size_t evaluations;
} scene;

/* The clearance of the posed part (sc->posed) to obstacle j; the closest points if pa, pb. */
static crane_real clearance(scene *sc, size_t j, crane__v3 *pa, crane__v3 *pb)
{
    crane__v3 qa, qb;
    crane_real d = 0;
    (void)crane__solid_distance(sc->posed, &sc->obstacles[j], &d, pa ? pa : &qa, pb ? pb : &qb);
    sc->evaluations++;
    return d;
}

/* Poses part i at p into sc->posed and measures it against obstacle j. */
static crane_real pair_distance(scene *sc, size_t i, size_t j, const pose *p, crane__v3 *pa,
                                crane__v3 *pb)
{
    part_solid(sc->m, &sc->parts[i], p, sc->cpsi, sc->spsi, sc->posed);
    return clearance(sc, j, pa, pb);
}

/* The pose at u of the step s0 -> s1 (Hermite angles). */
static void pose_between(const crane_model *m, const crane_sample *s0, const crane_sample *s1,
                         crane_real u, pose *p)
{
    crane_real c0[4], c1[4];
    hermite(s0, s1, 0, c0);
    hermite(s0, s1, 1, c1);
    pose_at(m, cubic_at(c0, u), cubic_at(c1, u), p);
}

/* Conservative advancement of one pair over one step, from the sample s0 (pose *p0) to s1: from a
 * time with clearance d > margin, jump ahead as far as the motion bound lets the clearance drop by
 * less than d - margin (halving the jump until it does), evaluate there, repeat. Returns 1 with
 * *u_hit (the fraction of the step) if the clearance is <= margin there, or cannot be shown to
 * stay above it beyond (the jump shrank below tol, a fraction of the step); 0 if it stays above
 * over the whole step, with *d_end the clearance at s1. */
static CRANE__NOINLINE int advance(scene *sc, size_t i, size_t j, const crane_real k[3],
                                   const crane_sample *s0, const crane_sample *s1, const pose *p0,
                                   crane_real margin, crane_real tol, crane_real *u_hit,
                                   crane_real *d_end)
{
    pose a = *p0, b;
    crane_real ua = 0;
    crane_real d = pair_distance(sc, i, j, &a, NULL, NULL);

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
            pose_at(sc->m, s1->theta[0], s1->theta[1], &b);
            *d_end = pair_distance(sc, i, j, &b, NULL, NULL);
            return 0;
        }
        ua = ub;
        pose_between(sc->m, s0, s1, ua, &a);
        d = pair_distance(sc, i, j, &a, NULL, NULL);
    }
}

static crane_status check_config(const crane_guard_config *c)
{
    if (!crane__finite(c->margin) || !crane__finite(c->reaction) || !crane__finite(c->cycle) ||
        !crane__finite(c->time_tolerance) || !crane__finite(c->clearance_tolerance))
        return CRANE_E_NONFINITE;
    if (c->margin < 0 || c->reaction < 0 || !(c->cycle > 0) || !(c->time_tolerance > 0) ||
        c->clearance_tolerance < 0)
        return CRANE_E_GUARD;
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
    if (p->kind != CRANE_SOLID_CAPSULE && p->kind != CRANE_SOLID_SPHERE && p->kind != CRANE_SOLID_BOX)
        return CRANE_GUARD_FIELD_KIND;
    if (!anchor_ok(p->a))
        return CRANE_GUARD_FIELD_A;
    if (p->kind == CRANE_SOLID_CAPSULE) {
        if (!anchor_ok(p->b))
            return CRANE_GUARD_FIELD_B;
        if (!(crane__length_ok(p->radius) && p->radius >= 0))
            return CRANE_GUARD_FIELD_RADIUS;
        return 0;
    }
    if (!crane__length_ok(p->drop))
        return CRANE_GUARD_FIELD_DROP;
    if (p->kind == CRANE_SOLID_SPHERE)
        return crane__length_ok(p->radius) && p->radius > 0 ? 0 : CRANE_GUARD_FIELD_RADIUS;
    for (i = 0; i < 3; ++i)
        if (!(crane__length_ok(p->half[i]) && p->half[i] > 0))
            return CRANE_GUARD_FIELD_HALF;
    return 0;
}

crane_status crane_guard_check(const crane_part *parts, size_t n_parts, const crane_solid *obstacles,
                               size_t n_obstacles, size_t *which, int *field)
{
    size_t i;
    if ((n_parts && !parts) || (n_obstacles && !obstacles) || !which || !field)
        return CRANE_E_NULL;
    for (i = 0; i < n_parts; ++i) {
        const int f = part_field(&parts[i]);
        if (f) {
            *which = i;
            *field = f;
            return CRANE_E_PART;
        }
    }
    for (i = 0; i < n_obstacles; ++i) {
        const int f = crane__solid_field(&obstacles[i]);
        if (f) {
            *which = i;
            *field = f;
            return CRANE_E_SOLID;
        }
    }
    return CRANE_OK;
}

crane_status crane_part_solids(const crane_model *model, const crane_part *parts, size_t n_parts,
                               crane_real slew, const crane_real theta[2], crane_solid *out)
{
    size_t i, which;
    int field;
    crane_real cpsi, spsi;
    pose p;
    crane_status st;

    if (!model || !theta || (n_parts && (!parts || !out)))
        return CRANE_E_NULL;
    st = crane_guard_check(parts, n_parts, NULL, 0, &which, &field);
    if (st != CRANE_OK)
        return st;
    if (!crane__finite(slew) || !crane__finite(theta[0]) || !crane__finite(theta[1]))
        return CRANE_E_NONFINITE;
    crane__sincos(slew, &spsi, &cpsi);
    pose_at(model, theta[0], theta[1], &p);
    for (i = 0; i < n_parts; ++i)
        part_solid(model, &parts[i], &p, cpsi, spsi, &out[i]);
    return CRANE_OK;
}

static crane_status check_samples(const crane_model *m, const crane_sample *s, size_t n)
{
    size_t k;
    int j;
    for (k = 0; k < n; ++k) {
        if (!crane__finite(s[k].t))
            return CRANE_E_NONFINITE;
        if (k > 0 && !(s[k].t > s[k - 1].t))
            return CRANE_E_SAMPLES;
        for (j = 0; j < 2; ++j) {
            if (!crane__finite(s[k].theta[j]) || !crane__finite(s[k].omega[j]))
                return CRANE_E_NONFINITE;
            if (s[k].theta[j] < m->theta_min[j] || s[k].theta[j] > m->theta_max[j])
                return CRANE_E_ANGLE;
        }
    }
    return CRANE_OK;
}

/* The pair's clearance gradient in the joint angles and its rate from each joint's motion. */
static CRANE__NOINLINE void approach(scene *sc, crane_guard_result *r, crane_real omega0, crane_real omega1)
{
    const crane_real h = sizeof(crane_real) < sizeof(double) ? (crane_real)1e-3 : (crane_real)1e-6;
    const crane_real omega[2] = {omega0, omega1};
    int j;
    for (j = 0; j < 2; ++j) {
        pose p;
        crane_real dp, dm;
        pose_at(sc->m, r->theta[0] + (j == 0 ? h : 0), r->theta[1] + (j == 1 ? h : 0), &p);
        dp = pair_distance(sc, (size_t)r->part, (size_t)r->obstacle, &p, NULL, NULL);
        pose_at(sc->m, r->theta[0] - (j == 0 ? h : 0), r->theta[1] - (j == 1 ? h : 0), &p);
        dm = pair_distance(sc, (size_t)r->part, (size_t)r->obstacle, &p, NULL, NULL);
        r->gradient[j] = (dp - dm) / (2 * h);
        r->approach[j] = r->gradient[j] * omega[j];
    }
}

static CRANE__NOINLINE void record_contact(scene *sc, crane_guard_result *r, size_t i, size_t j, crane_real t,
                           const pose *p)
{
    crane__v3 pa, pb;
    r->contact = 1;
    r->t = t;
    r->part = (int)i;
    r->obstacle = (int)j;
    r->theta[0] = p->th[0];
    r->theta[1] = p->th[1];
    r->clearance = pair_distance(sc, i, j, p, &pa, &pb);
    crane__v3_store(r->on_part, pa);
    crane__v3_store(r->on_obstacle, pb);
}

/* The time tolerance as a fraction of a step, at least 1e-4: each jump of the advancement is
 * longer than half of it, so one pair takes at most 20,000 jumps over one step. */
static crane_real u_tolerance(crane_real time_tolerance, crane_real h)
{
    const crane_real u = time_tolerance / h, u_min = (crane_real)1e-4;
    return u > u_min ? u : u_min;
}

/* d theta_j / dt at the fraction u of the step (the Hermite angle's derivative). */
static CRANE__NOINLINE crane_real rate_at(const crane_sample *s0, const crane_sample *s1, int j,
                                          crane_real u)
{
    crane_real c[4];
    hermite(s0, s1, j, c);
    return (c[1] + u * (2 * c[2] + u * 3 * c[3])) / (s1->t - s0->t);
}

/* A contact of pair (i, j) at the fraction u of the step s0 -> s1: its time, pose, points and the
 * joint rates there (the Hermite angles' derivative). */
static CRANE__NOINLINE void note_contact(scene *sc, crane_guard_result *r, size_t i, size_t j,
                                         const crane_sample *s0, const crane_sample *s1,
                                         crane_real u, crane_real omega[2])
{
    pose p;
    pose_between(sc->m, s0, s1, u, &p);
    record_contact(sc, r, i, j, s0->t + u * (s1->t - s0->t), &p);
    omega[0] = rate_at(s0, s1, 0, u);
    omega[1] = rate_at(s0, s1, 1, u);
}

/* The largest excursion over the step s0 -> s1 (pose *p0 at s0) of theta0, theta1 and side link
 * 1's angle, from their values at s0: what motion_bound weighs with a part's rates. */
static CRANE__NOINLINE void step_excursions(const crane_model *m, const crane_sample *s0,
                                            const crane_sample *s1, const pose *p0,
                                            crane_real ex[3])
{
    const crane_real unit[3] = {1, 0, 0};
    const crane_real tilt[3] = {0, 1, 0};
    const crane_real link[3] = {0, 0, 1};
    ex[0] = motion_bound(unit, m, s0, s1, 0, 1, p0);
    ex[1] = motion_bound(tilt, m, s0, s1, 0, 1, p0);
    ex[2] = motion_bound(link, m, s0, s1, 0, 1, p0);
}

crane_status crane_guard(const crane_model *model, const crane_part *parts, size_t n_parts,
                         const crane_solid *obstacles, size_t n_obstacles, crane_real slew,
                         const crane_sample *samples, size_t n_samples,
                         const crane_guard_config *config, crane_real *part_clearance,
                         crane_real *work, size_t work_capacity, crane_guard_result *result)
{
    const size_t n_pairs = n_parts * n_obstacles;
    crane_real *key, *per;
    crane_real margin, hit_omega[2] = {0, 0};
    scene sc;
    pose prev, cur;
    crane_solid ps;
    size_t i, j, k, which;
    int field, searching = 1;
    crane_status st;

    if (!model || !samples || !config || !result || (n_parts && (!parts || !part_clearance)) ||
        (n_obstacles && !obstacles) || (n_pairs && !work))
        return CRANE_E_NULL;
    st = check_config(config);
    if (st == CRANE_OK)
        st = crane_guard_check(parts, n_parts, obstacles, n_obstacles, &which, &field);
    if (st != CRANE_OK)
        return st;
    if (!crane__finite(slew))
        return CRANE_E_NONFINITE;
    if (n_samples == 0)
        return CRANE_E_SAMPLES;
    st = check_samples(model, samples, n_samples);
    if (st != CRANE_OK)
        return st;
    if (n_parts && (n_obstacles > ((size_t)-1) / n_parts - 5 || work_capacity < n_pairs + 5 * n_parts))
        return CRANE_E_CAPACITY;

    sc.m = model;
    sc.parts = parts;
    sc.obstacles = obstacles;
    sc.posed = &ps;
    sc.evaluations = 0;
    crane__sincos(slew, &sc.spsi, &sc.cpsi);
    key = work;
    per = &work[n_pairs]; /* per part: its 3 motion rates, cumulative bound, smallest key */
    for (i = 0; i < n_parts; ++i) {
        part_rates(model, &parts[i], &per[5 * i]);
        per[5 * i + 3] = 0;
        per[5 * i + 4] = (crane_real)INFINITY;
        part_clearance[i] = (crane_real)INFINITY;
    }
    result->signal = CRANE_GO;
    result->contact = 0;
    result->at_start = 0;
    result->t = 0;
    result->part = result->obstacle = -1;
    result->clearance = (crane_real)INFINITY;
    for (k = 0; k < 3; ++k)
        result->on_part[k] = result->on_obstacle[k] = 0;
    result->theta[0] = result->theta[1] = 0;
    result->gradient[0] = result->gradient[1] = 0;
    result->approach[0] = result->approach[1] = 0;
    result->stop_latest = 0;
    margin = config->margin;

    /* Each pair keeps key = its clearance when last evaluated + the part's cumulative motion bound
     * then, so its lower bound now is key - cum (cum: the part's bound summed from t = 0); a part
     * whose smallest key keeps every pair above its threshold costs O(1) per step. */
    pose_at(model, samples[0].theta[0], samples[0].theta[1], &cur);
    for (i = 0; i < n_parts; ++i) {
        crane_real *pp = &per[5 * i];
        part_solid(model, &parts[i], &cur, sc.cpsi, sc.spsi, &ps);
        for (j = 0; j < n_obstacles; ++j) {
            const crane_real d = clearance(&sc, j, NULL, NULL);
            key[i * n_obstacles + j] = d;
            if (d < pp[4])
                pp[4] = d;
            if (d < part_clearance[i])
                part_clearance[i] = d;
            if (d <= margin && (!result->contact || d < result->clearance)) {
                record_contact(&sc, result, i, j, samples[0].t, &cur); /* re-poses ps: same pose */
                result->at_start = 1;
                hit_omega[0] = samples[0].omega[0];
                hit_omega[1] = samples[0].omega[1];
            }
        }
    }
    searching = !result->contact;

    for (k = 1; k < n_samples; ++k) {
        const crane_sample *s0 = &samples[k - 1], *s1 = &samples[k];
        crane_real ex[3];
        int found = 0;
        prev = cur;
        pose_at(model, s1->theta[0], s1->theta[1], &cur);
        step_excursions(model, s0, s1, &prev, ex);
        for (i = 0; i < n_parts; ++i) {
            crane_real *pp = &per[5 * i];
            const crane_real floor_min = part_clearance[i] - config->clearance_tolerance;
            crane_real least, min_key = (crane_real)INFINITY;
            int posed = 0; /* ps: the part at this sample, posed when first needed */
            pp[3] += pp[0] * ex[0] + pp[1] * ex[1] + pp[2] * ex[2];
            least = pp[4] - pp[3];
            if ((!searching || least > margin) && least >= floor_min)
                continue;
            for (j = 0; j < n_obstacles; ++j) {
                crane_real *kj = &key[i * n_obstacles + j];
                const crane_real lb = *kj - pp[3];
                crane_real d;
                if (searching && lb <= margin) {
                    crane_real u_hit;
                    if (advance(&sc, i, j, pp, s0, s1, &prev, margin,
                                u_tolerance(config->time_tolerance, s1->t - s0->t), &u_hit, &d)) {
                        if (!found || s0->t + u_hit * (s1->t - s0->t) < result->t) {
                            note_contact(&sc, result, i, j, s0, s1, u_hit, hit_omega);
                            if (result->clearance < part_clearance[i])
                                part_clearance[i] = result->clearance;
                            found = 1;
                        }
                        d = pair_distance(&sc, i, j, &cur, NULL, NULL);
                    }
                    posed = 1; /* both ways end with ps posed at this sample */
                    *kj = d + pp[3];
                    if (d < part_clearance[i])
                        part_clearance[i] = d;
                } else if (lb < floor_min) {
                    if (!posed)
                        part_solid(model, &parts[i], &cur, sc.cpsi, sc.spsi, &ps);
                    posed = 1;
                    d = clearance(&sc, j, NULL, NULL);
                    *kj = d + pp[3];
                    if (d < part_clearance[i])
                        part_clearance[i] = d;
                }
                if (*kj < min_key)
                    min_key = *kj;
            }
            pp[4] = min_key;
        }
        if (found)
            searching = 0;
    }

    if (result->contact) {
        approach(&sc, result, hit_omega[0], hit_omega[1]);
        result->stop_latest = result->t - config->reaction;
        result->signal = (result->at_start || result->stop_latest < config->cycle) ? CRANE_STOP
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
    default: return "unknown status";
    }
}
