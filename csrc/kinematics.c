/* SPDX-License-Identifier: MIT */
/*
 * Joint kinematics (docs/model.md, "Lift kinematics" and "Tilt kinematics") and the crane's
 * point positions.
 */
#include <stdint.h>
#include "crane_internal.h"

/* circle() of docs/model.md; returns h2 (the mechanism closes only if h2 > 0). With h2 <= 0 the
 * point is computed with h2 clamped to 0, which keeps RK4 stages that overshoot a limit finite.
 * Inlined: its frame would otherwise sit at the bottom of the predict call's deepest path. */
static CRANE__ALWAYS_INLINE crane_real circle(crane_vec2 c0, crane_real r0, crane_vec2 c1,
                                             crane_real r1, crane_real sign, crane_vec2 *p)
{
    const crane_vec2 d = crane__sub(c1, c0);
    const crane_real D = crane__norm(d);
    crane_vec2 u;
    crane_real a, h2, h;

    if (!(D > 0)) {
        /* Concentric circles: no intersection point; report "does not close". */
        *p = c0;
        return -1;
    }
    u = crane__scale(1 / D, d);
    a = (r0 * r0 - r1 * r1 + D * D) / (2 * D);
    h2 = r0 * r0 - a * a;
    h = h2 > 0 ? crane__sqrt(h2) : 0;
    *p = crane__add(crane__add(c0, crane__scale(a, u)), crane__scale(sign * h, crane__perp(u)));
    return h2;
}

crane_real crane__wrap_tilt(crane_real theta)
{
    const crane_real two_pi = 2 * crane__pi();
    const crane_real hi = crane__pi() / 2;
    const crane_real lo = -3 * crane__pi() / 2;
    crane_real wrapped = theta;

    /* atan2 - alpha_a lies in (-2pi, 2pi), so one turn either way is enough. */
    if (wrapped > hi) {
        wrapped -= two_pi;
    } else if (wrapped <= lo) {
        wrapped += two_pi;
    } else {
        /* already in (lo, hi] */
    }
    return wrapped;
}

void crane__lift_from_stroke(const crane_model *m, crane_real stroke, crane_real *theta,
                             crane_real *ds)
{
    const crane_real db = m->lift_db, dr = m->lift_dr;
    const crane_real L = m->params->cylinder[CRANE_LIFT].length_retracted + stroke;
    crane_real cg = (db * db + dr * dr - L * L) / (2 * db * dr);
    crane_real gamma;

    /* The crane check keeps |cg| < 1 over the stroke; the clamp only guards rounding. */
    if (cg > 1) {
        cg = 1;
    } else if (cg < -1) {
        cg = -1;
    } else {
        /* within [-1, 1] */
    }
    gamma = crane__acos(cg);
    /* theta = gamma - eps + beta (eps, beta: crane__lift_offsets; this inverse runs only at the
     * start of a prediction and in queries, so they are not kept in the model) */
    {
        crane_real eps, beta;
        crane__lift_offsets(m->params, &eps, &beta);
        *theta = gamma - eps + beta;
    }
    *ds = db * dr * crane__sin(gamma) / L;
}

void crane__lift_from_angle(const crane_model *m, crane_real c0, crane_real s0,
                            crane_real *stroke, crane_real *ds)
{
    const crane_real db = m->lift_db, dr = m->lift_dr;
    /* gamma = theta0 + (eps - beta): its cos/sin by the angle-sum formulas, no trig call. */
    const crane_real cg = c0 * m->lift_cos_off - s0 * m->lift_sin_off;
    const crane_real sg = s0 * m->lift_cos_off + c0 * m->lift_sin_off;
    const crane_real L2 = db * db + dr * dr - 2 * db * dr * cg;
    const crane_real L = crane__sqrt(L2 > 0 ? L2 : 0);

    if (stroke != NULL) {
        *stroke = L - m->params->cylinder[CRANE_LIFT].length_retracted;
    }
    if (ds != NULL) {
        *ds = db * dr * sg / L;
    }
}

/* ds/dtheta1 by virtual velocities: A turns about O2, Q about P1, and QA is rigid. */
static crane_real tilt_ds(const crane_params *p, crane_vec2 q, crane_vec2 a, crane_real L)
{
    const crane_vec2 qp = crane__sub(q, p->link1_pivot);
    const crane_vec2 qa = crane__sub(q, a);
    const crane_real cyl = crane__dot(crane__sub(q, p->tilt_cylinder_base), crane__perp(qp)) / L;
    return cyl * crane__dot(qa, crane__perp(crane__sub(a, p->tilt_pivot))) /
           crane__dot(qa, crane__perp(qp));
}

int crane__tilt_from_stroke(const crane_model *m, crane_real stroke, crane_real *theta,
                            crane_real *ds, crane_vec2 *q, crane_vec2 *a)
{
    const crane_params *p = m->params;
    const crane_real L = p->cylinder[CRANE_TILT].length_retracted + stroke;
    crane_vec2 Q, A, oa;
    int ok = 1;

    if (!(circle(p->link1_pivot, m->tilt_l1, p->tilt_cylinder_base, L, -1, &Q) > 0)) {
        ok = 0;
    }
    if (!(circle(p->tilt_pivot, crane__norm(p->link2_attach), Q, m->tilt_l2, -1, &A) > 0)) {
        ok = 0;
    }
    oa = crane__sub(A, p->tilt_pivot);
    /* alpha_a = atan2(A.y, A.x) of link2_attach in the outer boom frame */
    *theta = crane__wrap_tilt(crane__atan2(oa.y, oa.x) -
                              crane__atan2(p->link2_attach.y, p->link2_attach.x));
    *ds = tilt_ds(p, Q, A, L);
    if (q != NULL) {
        *q = Q;
    }
    if (a != NULL) {
        *a = A;
    }
    return ok;
}

void crane__tilt_from_angle(const crane_model *m, crane_real c1, crane_real s1,
                            crane_real *stroke, crane_real *ds, crane_vec2 *q, crane_vec2 *a)
{
    const crane_params *p = m->params;
    const crane_vec2 A = crane__add(p->tilt_pivot, crane__rot(c1, s1, p->link2_attach));
    crane_vec2 Q;
    crane_real L;

    (void)circle(p->link1_pivot, m->tilt_l1, A, m->tilt_l2, m->tilt_branch, &Q);
    L = crane__norm(crane__sub(Q, p->tilt_cylinder_base));
    if (stroke != NULL) {
        *stroke = L - p->cylinder[CRANE_TILT].length_retracted;
    }
    if (ds != NULL) {
        *ds = tilt_ds(p, Q, A, L);
    }
    if (q != NULL) {
        *q = Q;
    }
    if (a != NULL) {
        *a = A;
    }
}

static void side_links(const crane_model *m, crane__tilt_kin *tk)
{
    const crane_params *p = m->params;
    crane__link_vec l;
    crane_vec2 ra, rhs, w1, w2, d1, d2, v1, v2;
    crane_real k1, k2, g1, g2;

    crane__link_vectors(m, tk, &l);
    ra = crane__sub(tk->a, p->tilt_pivot);
    k1 = l.k1;
    k2 = l.k2;
    d1 = l.d1;
    d2 = l.d2;
    v1 = l.v1;
    v2 = l.v2;
    rhs = crane__add(crane__scale(-1, ra),
                     crane__add(crane__scale(k1 * k1, l.qp), crane__scale(k2 * k2, l.aq)));
    g1 = crane__dot(rhs, l.aq) * l.inv_d;
    g2 = -crane__dot(rhs, l.qp) * l.inv_d;
    w1 = crane__sub(crane__scale(g1, crane__perp(l.e1)), crane__scale(k1 * k1, l.e1));
    w2 = crane__add(crane__sub(crane__scale(g1, crane__perp(l.qp)), crane__scale(k1 * k1, l.qp)),
                    crane__sub(crane__scale(g2, crane__perp(l.e2)), crane__scale(k2 * k2, l.e2)));
    {
        const crane_body *const l1 = &m->params->side_link1, *const l2 = &m->params->side_link2;
        const crane_real m1 = l1->mass, i1 = l1->izz, m2 = l2->mass, i2 = l2->izz;

        /* M's columns ID(theta, 0, e_j, 0), by virtual work (cross(d, perp(d)) = |d|^2,
         * cross(d, v) = perp(d).v), and the velocity-dependent and gravity sums. */
        tk->M[0] = m1 * crane__norm2(d1) + i1 + m2 * crane__norm2(d2) + i2;
        tk->M[1] = m1 * crane__cross(d1, v1) + i1 * k1 + m2 * crane__cross(d2, v2) + i2 * k2;
        tk->M[2] = m1 * crane__norm2(v1) + i1 * k1 * k1 + m2 * crane__norm2(v2) + i2 * k2 * k2;
        tk->md = crane__add(crane__scale(m1, d1), crane__scale(m2, d2));
        tk->mv = crane__add(crane__scale(m1, v1), crane__scale(m2, v2));
        tk->huu[0] = m1 * crane__cross(d1, w1) + i1 * g1 + m2 * crane__cross(d2, w2) + i2 * g2;
        tk->huu[1] = m1 * crane__dot(w1, v1) + i1 * g1 * k1 + m2 * crane__dot(w2, v2) + i2 * g2 * k2;
        tk->dv = m1 * crane__dot(d1, v1) + m2 * crane__dot(d2, v2);
    }
}

void crane__tilt_kinematics(const crane_model *m, crane_real c1, crane_real s1,
                            crane__tilt_kin *tk)
{
    /* crane__tilt_from_angle itself, so that the samples (which take the stroke alone from it)
     * and the dynamics read the same bits */
    crane__tilt_from_angle(m, c1, s1, &tk->stroke, &tk->ds, &tk->q, &tk->a);
    if (m->links != 0) {
        side_links(m, tk);
    }
}

/* x reduced to [0, 2pi): its callers' arguments lie in (-3pi, 5pi). */
static crane_real wrap_2pi(crane_real x)
{
    const crane_real two_pi = 2 * crane__pi();
    crane_real wrapped = x;
    int k;

    for (k = 0; k < 2; ++k) {
        if (wrapped < 0) {
            wrapped += two_pi;
        } else if (wrapped >= two_pi) {
            wrapped -= two_pi;
        } else {
            /* already in [0, 2pi) */
        }
    }
    return wrapped;
}

/* The pins of the four-bar at psi, the angle at P1 from u = (B2 - P1)/|B2 - P1| clockwise to
 * Q - P1 (Q to the right of P1 -> B2, as stroke -> angle puts it): Q = P1 + l1 R(-psi) u, A from Q.
 * Returns D = cross(Q - P1, A - Q), zero where side links 1 and 2 align. */
static crane_real fourbar_d(const crane_model *m, crane_vec2 u, crane_real psi)
{
    crane_vec2 q, a;
    crane_real s, c;

    crane__sincos(psi, &s, &c);
    q = crane__add(m->params->link1_pivot, crane__scale(m->tilt_l1, crane__rot(c, -s, u)));
    (void)circle(m->params->tilt_pivot, crane__norm(m->params->link2_attach), q, m->tilt_l2, -1,
                 &a);
    return crane__cross(crane__sub(q, m->params->link1_pivot), crane__sub(a, q));
}

/* docs/model.md, "Tilt kinematics": the exact validity of the four-bar over the tilt stroke.
 * Q turns about P1 by psi, which grows with the cylinder length L (law of cosines in the triangle
 * P1 B2 Q), over [psi0, psi1] inside (0, pi) exactly when the triangle closes at both stroke limits.
 * A closes over that arc when e = |Q - O2| stays inside (|ra - l2|, ra + l2): e^2 = c^2 + l1^2 +
 * 2 l1 c cos(psi - psi_c) (c = |P1 - O2|) is extreme at the arc's ends or at psi_c, psi_c + pi.
 * ds/dtheta1 (tilt_ds) is then finite and nonzero unless D = cross(Q - P1, A - Q) vanishes, i.e.
 * A = Q +- l2 w on the line P1 Q (w = (Q - P1)/l1): |P1 - O2 + (l1 +- l2) w| = ra, at most
 * four angles psi_c +- acos(r) in closed form. D keeps one sign between them, so its sign at the
 * ends, at those angles and half-way between them decides. The sign of D is the assembly that
 * angle -> stroke must pick for Q (tilt_branch). Finally theta1 must not cross the wrap of
 * (-3pi/2, pi/2] inside the stroke (it moves monotonically, so its ends decide).
 * Returns the field at fault (CRANE_FIELD_NONE if valid) and sets m->tilt_branch. */
crane_field crane__fourbar_check(crane_model *m)
{
    const crane_real lo = -3 * crane__pi() / 2, hi = crane__pi() / 2;
    const crane_real l1 = m->tilt_l1, l2 = m->tilt_l2, ra = crane__norm(m->params->link2_attach);
    const crane_vec2 b = crane__sub(m->params->tilt_cylinder_base, m->params->link1_pivot);
    const crane_vec2 cv = crane__sub(m->params->link1_pivot, m->params->tilt_pivot);
    const crane_real d = crane__norm(b), c = crane__norm(cv);
    const crane_real l0 = m->params->cylinder[CRANE_TILT].length_retracted;
    const crane_real len[2] = {l0 + crane__stroke_min(m, CRANE_TILT),
                               l0 + crane__stroke_max(m, CRANE_TILT)};
    const crane_field end_field[2] = {CRANE_FIELD_TILT_CYLINDER_STROKE_MIN,
                                      CRANE_FIELD_TILT_CYLINDER_STROKE_MAX};
    crane_real psi[2], e[2], pts[6], theta[2], ds[2], sign = 0, psi_c, e_lo, e_hi;
    crane_vec2 u;
    int k, j, n;

    if (!(l1 > 0)) {
        return CRANE_FIELD_GEOMETRY_LINK_PIN;
    }
    if (!(l2 > 0)) {
        return CRANE_FIELD_GEOMETRY_LINK2_END;
    }
    if (!(ra > 0)) {
        return CRANE_FIELD_GEOMETRY_LINK2_ATTACH;
    }
    if (!(d > 0)) {
        return CRANE_FIELD_GEOMETRY_TILT_CYLINDER_BASE;
    }
    u = crane__scale(1 / d, b);
    /* Triangle P1 B2 Q at the stroke limits (L grows with the stroke, so psi does too). */
    if (!(len[0] > crane__fabs(l1 - d))) {
        return end_field[0];
    }
    if (!(len[1] < l1 + d)) {
        return end_field[1];
    }
    for (k = 0; k < 2; ++k) {
        crane_real sp, cp;
        psi[k] = crane__acos((l1 * l1 + d * d - len[k] * len[k]) / (2 * l1 * d));
        crane__sincos(psi[k], &sp, &cp);
        e[k] = crane__norm(crane__add(cv, crane__scale(l1, crane__rot(cp, -sp, u))));
        if (!(e[k] > crane__fabs(ra - l2) && e[k] < ra + l2)) {
            return end_field[k];
        }
    }
    /* Triangle O2 Q A inside the arc: e's extremes at psi_c (c + l1) and psi_c + pi (|c - l1|). */
    e_lo = e[0] < e[1] ? e[0] : e[1];
    e_hi = e[0] < e[1] ? e[1] : e[0];
    psi_c = wrap_2pi(crane__atan2(u.y, u.x) - crane__atan2(cv.y, cv.x));
    if (c > 0 && psi_c > psi[0] && psi_c < psi[1]) {
        e_hi = c + l1;
    }
    if (c > 0 && wrap_2pi(psi_c + crane__pi()) > psi[0] && wrap_2pi(psi_c + crane__pi()) < psi[1]) {
        e_lo = crane__fabs(c - l1);
    }
    if (!(e_lo > crane__fabs(ra - l2) && e_hi < ra + l2)) {
        return CRANE_FIELD_GEOMETRY_LINK2_END;
    }
    /* The angles where D may vanish, in increasing order with the ends. */
    pts[0] = psi[0];
    n = 1;
    for (k = 0; k < 2 && c > 0; ++k) {
        const crane_real kk = k == 0 ? l1 + l2 : l1 - l2;
        const crane_real r = (ra * ra - c * c - kk * kk) / (2 * kk * c);
        if (kk == 0 || !(r >= -1 && r <= 1)) {
            continue;
        }
        for (j = 0; j < 2; ++j) {
            const crane_real x = wrap_2pi(psi_c + (j == 0 ? 1 : -1) * crane__acos(r));
            int i = n;
            if (!(x > psi[0] && x < psi[1])) {
                continue;
            }
            while (i > 1 && pts[i - 1] > x) {
                pts[i] = pts[i - 1];
                --i;
            }
            pts[i] = x;
            ++n;
        }
    }
    pts[n] = psi[1];
    ++n;
    for (k = 0; k < n; ++k) {
        /* at each point and half-way to the next */
        for (j = 0; j < (k + 1 < n ? 2 : 1); ++j) {
            const crane_real x = j == 0 ? pts[k] : (pts[k] + pts[k + 1]) / 2;
            const crane_real dk = fourbar_d(m, u, x);
            if (!(dk != 0) || (sign != 0 && (dk > 0 ? 1 : -1) != sign)) {
                return CRANE_FIELD_GEOMETRY_LINK2_END;
            }
            sign = dk > 0 ? 1 : -1;
        }
    }
    /* D < 0 puts Q to the left of P1 -> A: the +1 intersection of angle -> stroke. */
    m->tilt_branch = -sign;
    for (k = 0; k < 2; ++k) {
        const crane_real s =
            k == 0 ? crane__stroke_min(m, CRANE_TILT) : crane__stroke_max(m, CRANE_TILT);
        (void)crane__tilt_from_stroke(m, s, &theta[k], &ds[k], NULL, NULL);
        if (!(theta[k] > lo && theta[k] < hi) || crane__finite(ds[k]) == 0 || !(ds[k] != 0)) {
            return CRANE_FIELD_GEOMETRY_LINK2_ATTACH;
        }
    }
    if (!((theta[1] - theta[0]) * ds[0] > 0)) {
        return CRANE_FIELD_GEOMETRY_LINK2_ATTACH;
    }
    return CRANE_FIELD_NONE;
}

crane_status crane_joint_angle(const crane_model *model, int joint, crane_real stroke,
                               crane_real *theta, crane_real *dstroke_dtheta)
{
    crane_real th, ds;

    if (model == NULL || theta == NULL || dstroke_dtheta == NULL) {
        return CRANE_E_NULL;
    }
    if (joint != CRANE_LIFT && joint != CRANE_TILT) {
        return CRANE_E_CYLINDER;
    }
    if (crane__finite(stroke) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (stroke < crane__stroke_min(model, joint) || stroke > crane__stroke_max(model, joint)) {
        return CRANE_E_STROKE;
    }
    if (joint == CRANE_LIFT) {
        crane__lift_from_stroke(model, stroke, &th, &ds);
    } else {
        (void)crane__tilt_from_stroke(model, stroke, &th, &ds, NULL, NULL);
    }
    *theta = th;
    *dstroke_dtheta = ds;
    return CRANE_OK;
}

crane_status crane_joint_stroke(const crane_model *model, int joint, crane_real theta,
                                crane_real *stroke)
{
    crane_real s, c1, s1;

    if (model == NULL || stroke == NULL) {
        return CRANE_E_NULL;
    }
    if (joint != CRANE_LIFT && joint != CRANE_TILT) {
        return CRANE_E_CYLINDER;
    }
    if (crane__finite(theta) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (theta < model->theta_min[joint] || theta > model->theta_max[joint]) {
        return CRANE_E_ANGLE;
    }
    crane__sincos(theta, &s1, &c1);
    if (joint == CRANE_LIFT) {
        crane__lift_from_angle(model, c1, s1, &s, NULL);
    } else {
        crane__tilt_from_angle(model, c1, s1, &s, NULL, NULL, NULL);
    }
    *stroke = s;
    return CRANE_OK;
}

/* A boom-plane point (x, y) in the world: (x cos psi, x sin psi, y). */
static void put_world(crane_real *dst, crane_vec2 v, crane_real cpsi, crane_real spsi)
{
    dst[0] = v.x * cpsi;
    dst[1] = v.x * spsi;
    dst[2] = v.y;
}

/* The paper's chain T_w0 T01 T12 T2e (docs/model.md "Frames") applied in its planar form: each
 * 4x4 homogeneous transform is a rotation about z plus a translation, so only those blocks are
 * multiplied out (the twin multiplies the full 4x4 matrices; tests compare the two at 1e-12 m). */
crane_status crane_points(const crane_model *model, crane_real slew, size_t n,
                          const crane_real *theta, crane_real *xyz)
{
    const crane_params *p;
    crane_real cpsi, spsi;
    size_t k;

    if (model == NULL) {
        return CRANE_E_NULL;
    }
    if (n > 0 && (theta == NULL || xyz == NULL)) {
        return CRANE_E_NULL;
    }
    /* n poses are 2 n angles in and 3 CRANE_N_POINTS n coordinates out: a count whose sizes do
     * not fit a size_t describes no caller's array (and 2 n would wrap). */
    if (n > SIZE_MAX / (3 * (size_t)CRANE_N_POINTS * sizeof(crane_real))) {
        return CRANE_E_OVERFLOW;
    }
    if (crane__finite(slew) == 0) {
        return CRANE_E_NONFINITE;
    }
    /* Validate every pose before the first write. */
    for (k = 0; k < 2 * n; ++k) {
        if (crane__finite(theta[k]) == 0) {
            return CRANE_E_NONFINITE;
        }
    }
    for (k = 0; k < n; ++k) {
        int j;
        for (j = 0; j < 2; ++j) {
            if (theta[2 * k + (size_t)j] < model->theta_min[j] ||
                theta[2 * k + (size_t)j] > model->theta_max[j]) {
                return CRANE_E_ANGLE;
                }
        }
    }

    p = model->params;
    crane__sincos(slew, &spsi, &cpsi);
    for (k = 0; k < n; ++k) {
        const crane_vec2 o1 = p->lift_pivot;
        crane_vec2 q, a, pts[CRANE_N_POINTS];
        crane_real *dst = xyz + k * (size_t)CRANE_N_POINTS * 3;
        crane_real c0, s0, c1, s1;
        int i;

        crane__sincos(theta[2 * k], &s0, &c0);
        crane__sincos(theta[2 * k + 1], &s1, &c1);

        crane__tilt_from_angle(model, c1, s1, NULL, NULL, &q, &a);
        pts[0] = crane__v2(0, 0);
        pts[1] = o1;
        pts[2] = p->lift_cylinder_base;
        pts[3] = crane__add(o1, crane__rot(c0, s0, p->lift_cylinder_rod));
        pts[4] = crane__add(o1, crane__rot(c0, s0, p->tilt_cylinder_base));
        pts[5] = crane__add(o1, crane__rot(c0, s0, p->link1_pivot));
        pts[6] = crane__add(o1, crane__rot(c0, s0, q));
        pts[7] = crane__add(o1, crane__rot(c0, s0, a));
        pts[8] = crane__add(o1, crane__rot(c0, s0, p->tilt_pivot));
        pts[9] = crane__add(o1, crane__rot(c0, s0, crane__add(p->tilt_pivot,
                                                     crane__rot(c1, s1, p->extension_mount))));
        pts[10] = crane__add(o1, crane__rot(c0, s0, crane__add(p->tilt_pivot,
                                                      crane__rot(c1, s1, crane__tip(model)))));
        for (i = 0; i < CRANE_N_POINTS; ++i) {
            put_world(dst + 3 * i, pts[i], cpsi, spsi);
        }
    }
    return CRANE_OK;
}

#ifdef CRANE_FLOAT
/* sin and cos of x in float (see crane_internal.h). Arguments with |x| > 64 are first reduced
 * by fmodf(x, 2pi rounded to float), which is exact, so every argument of the reduction below is
 * below 64 in magnitude (and NaN/inf give NaN). Then Cody-Waite reduction by pi/2 with the
 * three-part constant of fdlibm's __ieee754_rem_pio2f (17 + 17 + 24 bits: k pi/2 exact in the
 * first two parts for |k| < 128), and fdlibm's __kernel_sinf/__kernel_cosf polynomials on
 * |r| <= pi/4 (terms below float precision dropped). Error about 1 ulp. */
void crane__sincosf(float x, float *sp, float *cp)
{
    static const float two_over_pi = 6.3661974669e-01f;
    static const float pio2_1 = 1.5707855225e+00f;  /* 0x3fc90f80 */
    static const float pio2_2 = 1.0804273188e-05f;  /* 0x37354400 */
    static const float pio2_3 = 6.0770943833e-11f;  /* 0x2e85a300 */
    static const float pio2_3t = 6.1232342629e-17f;
    static const float S1 = -1.6666667163e-01f, S2 = 8.3333337680e-03f, S3 = -1.9841270114e-04f,
                       S4 = 2.7557314297e-06f;
    static const float C1 = 4.1666667908e-02f, C2 = -1.3888889225e-03f, C3 = 2.4801587642e-05f,
                       C4 = -2.7557314297e-07f;
    float a = x; /* the argument, below 64 in magnitude once reduced */
    float r, z, s, c, fk;
    int k;

    if (!(fabsf(a) <= 64.0f)) {
        a = fmodf(a, 6.2831854820e+00f);
    }
    if (!(a == a)) {
        *sp = *cp = a;
        return;
    }
    fk = a * two_over_pi;
    k = (int)(fk < 0 ? fk - 0.5f : fk + 0.5f);
    fk = (float)k;
    r = ((a - fk * pio2_1) - fk * pio2_2) - (fk * pio2_3 + fk * pio2_3t);
    z = r * r;
    s = r + r * z * (S1 + z * (S2 + z * (S3 + z * S4)));
    c = 1.0f - 0.5f * z + z * z * (C1 + z * (C2 + z * (C3 + z * C4)));
    switch (k & 3) {
    case 0: *sp = s; *cp = c; break;
    case 1: *sp = c; *cp = -s; break;
    case 2: *sp = -s; *cp = -c; break;
    default: *sp = -c; *cp = s; break;
    }
}
#endif
