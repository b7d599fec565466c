/* SPDX-License-Identifier: MIT */
/*
 * Exact distances between the solids of the collision guard (docs/guard.md, "Distances").
 *
 * Every solid is one of three cores grown by a radius: a segment (capsule, sphere = a segment of
 * length 0, vertical cylinder = its capsule, which is conservative), a box, or a half-space. The
 * distance between two solids is the distance between their cores minus the radii, floored at 0:
 * growing a convex set by r moves its boundary out by exactly r.
 */
#include "guard_internal.h"

static crane_real clamp01(crane_real x)
{
    return x < 0 ? 0 : (x > 1 ? 1 : x);
}

static crane__v3 lerp3(crane__v3 a, crane__v3 d, crane_real t)
{
    return crane__v3_add(a, crane__v3_scale(t, d));
}

/* Segment-segment: the squared distance is a convex quadratic in (s, t) on the unit square; its
 * minimum is the interior stationary point or lies on one of the four edges, where it is a 1-D
 * clamped minimum. Every candidate is evaluated and the smallest kept, so near-parallel segments
 * (an ill-conditioned stationary point) still get the exact boundary minimum. */
typedef struct {
    crane__v3 p0, d1, q0, d2;
    crane_real best, s, t;
} seg_pair;

static CRANE__NOINLINE void seg_try(seg_pair *c, crane_real s, crane_real t)
{
    const crane__v3 g = crane__v3_sub(lerp3(c->p0, c->d1, s), lerp3(c->q0, c->d2, t));
    const crane_real g2 = crane__v3_dot(g, g);
    if (c->best < 0 || g2 < c->best) {
        c->best = g2;
        c->s = s;
        c->t = t;
    }
}

static CRANE__NOINLINE crane_real seg_seg(crane__v3 p0, crane__v3 p1, crane__v3 q0, crane__v3 q1,
                                          crane__v3 *pa, crane__v3 *pb)
{
    seg_pair c;
    crane_real a, e, b, cc, f, den;
    crane__v3 r;

    c.p0 = p0;
    c.q0 = q0;
    c.d1 = crane__v3_sub(p1, p0);
    c.d2 = crane__v3_sub(q1, q0);
    c.best = -1;
    c.s = c.t = 0;
    r = crane__v3_sub(p0, q0);
    a = crane__v3_dot(c.d1, c.d1);
    e = crane__v3_dot(c.d2, c.d2);
    b = crane__v3_dot(c.d1, c.d2);
    cc = crane__v3_dot(c.d1, r);
    f = crane__v3_dot(c.d2, r);
    /* edges s = 0, s = 1 (t free), t = 0, t = 1 (s free) */
    seg_try(&c, 0, e > 0 ? clamp01(f / e) : 0);
    seg_try(&c, 1, e > 0 ? clamp01((b + f) / e) : 0);
    seg_try(&c, a > 0 ? clamp01(-cc / a) : 0, 0);
    seg_try(&c, a > 0 ? clamp01((b - cc) / a) : 0, 1);
    den = a * e - b * b;
    if (den > 0) {
        const crane_real s = (b * f - cc * e) / den, t = (a * f - b * cc) / den;
        if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
            seg_try(&c, s, t);
        }
    }
    *pa = lerp3(c.p0, c.d1, c.s);
    *pb = lerp3(c.q0, c.d2, c.t);
    return crane__sqrt(c.best);
}

/* A box solid's frame: its axes are the rows of s->axes, its centre s->a. */
static crane__v3 box_axis(const crane_solid *b, int i)
{
    return crane__v3_load(b->axes + 3 * i);
}

static crane__v3 to_box(const crane_solid *b, crane__v3 p)
{
    const crane__v3 r = crane__v3_sub(p, crane__v3_load(b->a));
    return crane__v3_make(crane__v3_dot(r, box_axis(b, 0)), crane__v3_dot(r, box_axis(b, 1)),
                          crane__v3_dot(r, box_axis(b, 2)));
}

static crane__v3 from_box(const crane_solid *b, crane__v3 q)
{
    return crane__v3_add(crane__v3_load(b->a),
                         crane__v3_add(crane__v3_scale(q.x, box_axis(b, 0)),
                                       crane__v3_add(crane__v3_scale(q.y, box_axis(b, 1)),
                                                     crane__v3_scale(q.z, box_axis(b, 2)))));
}

static crane_real excess(crane_real x, crane_real h)
{
    return x > h ? x - h : (x < -h ? x + h : 0);
}

/* Squared distance of the box-frame point p0 + t d to the box |x_i| <= h_i. */
static crane_real box_gap2(const crane_real p0[3], const crane_real d[3], const crane_real h[3],
                           crane_real t)
{
    crane_real s = 0;
    int i;
    for (i = 0; i < 3; ++i) {
        const crane_real e = excess(p0[i] + t * d[i], h[i]);
        s += e * e;
    }
    return s;
}

/* The breakpoint of p0_i + t d_i = +-h_i that comes first after t, or 1 if none: the pieces of
 * seg_box are visited in order without storing (and sorting) the breakpoints. */
static crane_real next_break(const crane_real p0[3], const crane_real d[3], const crane_real h[3],
                             crane_real t)
{
    crane_real next = 1;
    int i, k;
    for (i = 0; i < 3; ++i) {
        if (d[i] == 0) {
            continue;
        }
        for (k = -1; k <= 1; k += 2) {
            const crane_real b = ((crane_real)k * h[i] - p0[i]) / d[i];
            if (b > t && b < next) {
                next = b;
            }
        }
    }
    return next;
}

/* Segment-box, exact: in the box frame the squared distance from p(t) = p0 + t d is
 * sum_i excess_i(t)^2, a convex piecewise quadratic whose pieces change where p_i(t) = +-h_i. On
 * each piece it is one quadratic A t^2 + B t + C (the axes outside the slab at the piece's middle),
 * minimised in closed form; the minimum over the pieces (and their ends) is the exact distance. */
static crane_real seg_box(crane__v3 s0, crane__v3 s1, const crane_solid *bx, crane__v3 *pa,
                          crane__v3 *pb)
{
    const crane__v3 l0 = to_box(bx, s0), l1 = to_box(bx, s1);
    const crane_real p0[3] = {l0.x, l0.y, l0.z};
    const crane_real d[3] = {l1.x - l0.x, l1.y - l0.y, l1.z - l0.z};
    crane_real best = box_gap2(p0, d, bx->half, 0), bt = 0, ta = 0;
    int j;

    while (ta < 1) {
        const crane_real tb = next_break(p0, d, bx->half, ta), tm = (ta + tb) / 2;
        crane_real A = 0, B = 0, g;
        for (j = 0; j < 3; ++j) {
            const crane_real x = p0[j] + tm * d[j];
            if (x > bx->half[j] || x < -bx->half[j]) {
                const crane_real off = p0[j] - (x > 0 ? bx->half[j] : -bx->half[j]);
                A += d[j] * d[j];
                B += 2 * d[j] * off;
            }
        }
        g = box_gap2(p0, d, bx->half, tb);
        if (g < best) {
            best = g;
            bt = tb;
        }
        if (A > 0) {
            crane_real t = -B / (2 * A);
            t = t < ta ? ta : (t > tb ? tb : t);
            g = box_gap2(p0, d, bx->half, t);
            if (g < best) {
                best = g;
                bt = t;
            }
        }
        ta = tb;
    }
    {
        const crane__v3 p = crane__v3_make(p0[0] + bt * d[0], p0[1] + bt * d[1], p0[2] + bt * d[2]);
        const crane__v3 q = crane__v3_make(p.x - excess(p.x, bx->half[0]),
                                           p.y - excess(p.y, bx->half[1]),
                                           p.z - excess(p.z, bx->half[2]));
        *pa = from_box(bx, p);
        *pb = from_box(bx, q);
    }
    return crane__sqrt(best);
}

/* Segment-half-space (the solid is where n.(x - p) <= 0): the signed height is linear along the
 * segment, so its minimum is at an end. 0 if the segment reaches the solid. */
static crane_real seg_plane(crane__v3 s0, crane__v3 s1, crane__v3 p, crane__v3 n, crane__v3 *pa,
                            crane__v3 *pb)
{
    const crane_real h0 = crane__v3_dot(n, crane__v3_sub(s0, p));
    const crane_real h1 = crane__v3_dot(n, crane__v3_sub(s1, p));
    const crane__v3 s = h1 < h0 ? s1 : s0;
    const crane_real h = h1 < h0 ? h1 : h0;
    *pa = s;
    *pb = crane__v3_sub(s, crane__v3_scale(h, n));
    return h > 0 ? h : 0;
}

static crane__v3 box_vertex(const crane_solid *b, int v)
{
    return from_box(b, crane__v3_make((v & 1) != 0 ? b->half[0] : -b->half[0],
                                      (v & 2) != 0 ? b->half[1] : -b->half[1],
                                      (v & 4) != 0 ? b->half[2] : -b->half[2]));
}

/* Box-box: if the boxes are apart, a closest pair has a vertex or an edge point of one box on the
 * other (vertex-face, edge-edge, face-vertex; parallel faces and edges have such a pair too); if
 * they overlap, an edge of one meets the other or one contains the other (its edges are inside).
 * So the minimum over the 12 edges of each box against the other box is exact. */
static CRANE__NOINLINE crane_real box_box(const crane_solid *x, const crane_solid *y, crane__v3 *pa,
                                          crane__v3 *pb)
{
    crane_real best = -1;
    int side, v, i;
    for (side = 0; side < 2 && best != 0; ++side) {
        const crane_solid *m = side != 0 ? y : x, *o = side != 0 ? x : y;
        for (v = 0; v < 8 && best != 0; ++v) {
            for (i = 0; i < 3; ++i) {
                const int w = v | (1 << i);
                crane__v3 qa, qb;
                crane_real dd;
                if (w == v) {
                    continue;
                }
                dd = seg_box(box_vertex(m, v), box_vertex(m, w), o, &qa, &qb);
                if (best < 0 || dd < best) {
                    best = dd;
                    *pa = side != 0 ? qb : qa;
                    *pb = side != 0 ? qa : qb;
                }
            }
        }
    }
    return best;
}

static CRANE__NOINLINE crane_real box_plane(const crane_solid *b, crane__v3 p, crane__v3 n, crane__v3 *pa, crane__v3 *pb)
{
    crane_real best = 0;
    int v;
    for (v = 0; v < 8; ++v) {
        const crane__v3 q = box_vertex(b, v);
        const crane_real h = crane__v3_dot(n, crane__v3_sub(q, p));
        if (v == 0 || h < best) {
            best = h;
            *pa = q;
        }
    }
    *pb = crane__v3_sub(*pa, crane__v3_scale(best, n));
    return best > 0 ? best : 0;
}

static int seglike(int kind)
{
    return kind == CRANE_SOLID_CAPSULE || kind == CRANE_SOLID_SPHERE || kind == CRANE_SOLID_CYLINDER;
}

static void segment_of(const crane_solid *s, crane__v3 *a, crane__v3 *b)
{
    *a = crane__v3_load(s->a);
    *b = s->kind == CRANE_SOLID_SPHERE ? *a : crane__v3_load(s->b);
}

/* The point r along the unit direction from c towards o (c itself if o == c). */
static crane__v3 grow(crane__v3 c, crane__v3 o, crane_real r)
{
    const crane__v3 g = crane__v3_sub(o, c);
    const crane_real l = crane__v3_norm(g);
    return l > 0 ? crane__v3_add(c, crane__v3_scale(r / l, g)) : c;
}

/* Distance between the cores of a (seglike, box or plane) and b, with b never seglike when a
 * is not (the caller orders the pair). */
static int core_distance(const crane_solid *a, const crane_solid *b, crane_real *d, crane__v3 *pa,
                         crane__v3 *pb)
{
    if (seglike(a->kind) != 0) {
        crane__v3 a0, a1;
        segment_of(a, &a0, &a1);
        if (seglike(b->kind) != 0) {
            crane__v3 b0, b1;
            segment_of(b, &b0, &b1);
            *d = seg_seg(a0, a1, b0, b1, pa, pb);
        } else if (b->kind == CRANE_SOLID_BOX) {
            *d = seg_box(a0, a1, b, pa, pb);
        } else {
            *d = seg_plane(a0, a1, crane__v3_load(b->a), crane__v3_load(b->b), pa, pb);
        }
        return 1;
    }
    if (a->kind == CRANE_SOLID_BOX) {
        if (b->kind == CRANE_SOLID_BOX) {
            *d = box_box(a, b, pa, pb);
        } else {
            *d = box_plane(a, crane__v3_load(b->a), crane__v3_load(b->b), pa, pb);
        }
        return 1;
    }
    return 0;
}

static crane_real radius_of(const crane_solid *s)
{
    return seglike(s->kind) != 0 ? s->radius : 0;
}

/* The order of the kinds for core_distance: seglike 0 < box 1 < plane 2. */
static int kind_rank(int kind)
{
    int rank;
    if (seglike(kind) != 0) {
        rank = 0;
    } else if (kind == CRANE_SOLID_BOX) {
        rank = 1;
    } else {
        rank = 2;
    }
    return rank;
}

int crane__solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                          crane__v3 *pa, crane__v3 *pb)
{
    /* so that core_distance sees (a, b) with b not "smaller" */
    const int swap = kind_rank(b->kind) < kind_rank(a->kind);
    const crane_solid *x = swap != 0 ? b : a, *y = swap != 0 ? a : b;
    crane__v3 px, py;
    crane_real d, rx, ry;

    if (core_distance(x, y, &d, &px, &py) == 0) {
        return 0;
    }
    rx = radius_of(x);
    ry = radius_of(y);
    if (d > rx + ry) {
        const crane__v3 cx = px;
        px = grow(px, py, rx);
        py = grow(py, cx, ry);
        d -= rx + ry;
    } else {
        d = 0;
    }
    *distance = d;
    *pa = swap != 0 ? py : px;
    *pb = swap != 0 ? px : py;
    return 1;
}

static int finite3(const crane_real *v)
{
    return crane__length_ok(v[0]) && crane__length_ok(v[1]) && crane__length_ok(v[2]);
}

/* Tolerance of the unit-length and orthogonality checks (float rounding of a caller's matrix). */
static crane_real unit_tol(void)
{
    return sizeof(crane_real) < sizeof(double) ? (crane_real)1e-5 : (crane_real)1e-9;
}

int crane__solid_field(const crane_solid *s)
{
    const crane_real tol = unit_tol();
    int i, j;

    if (s->kind < CRANE_SOLID_PLANE || s->kind > CRANE_SOLID_CYLINDER) {
        return CRANE_GUARD_FIELD_KIND;
    }
    if (finite3(s->a) == 0) {
        return CRANE_GUARD_FIELD_A;
    }
    if (s->kind == CRANE_SOLID_PLANE) {
        const crane__v3 n = crane__v3_load(s->b);
        if (finite3(s->b) == 0 || crane__fabs(crane__v3_dot(n, n) - 1) > tol) {
            return CRANE_GUARD_FIELD_B;
        }
        return 0;
    }
    if (s->kind == CRANE_SOLID_BOX) {
        for (i = 0; i < 3; ++i) {
            if (!(crane__length_ok(s->half[i]) != 0 && s->half[i] > 0)) {
                return CRANE_GUARD_FIELD_HALF;
            }
        }
        for (i = 0; i < 9; ++i) {
            if (crane__finite(s->axes[i]) == 0) {
                return CRANE_GUARD_FIELD_AXES;
            }
        }
        for (i = 0; i < 3; ++i) {
            const crane__v3 ui = crane__v3_load(s->axes + 3 * i);
            for (j = i; j < 3; ++j) {
                const crane_real want = i == j ? 1 : 0;
                if (crane__fabs(crane__v3_dot(ui, crane__v3_load(s->axes + 3 * j)) - want) > tol) {
                    return CRANE_GUARD_FIELD_AXES;
                }
            }
        }
        return 0;
    }
    if (s->kind != CRANE_SOLID_SPHERE && finite3(s->b) == 0) {
        return CRANE_GUARD_FIELD_B;
    }
    if (!(crane__length_ok(s->radius) != 0 && s->radius >= 0) ||
        (s->kind != CRANE_SOLID_CAPSULE && !(s->radius > 0))) {
        return CRANE_GUARD_FIELD_RADIUS;
        }
    if (s->kind == CRANE_SOLID_CYLINDER) {
        const crane__v3 g = crane__v3_sub(crane__v3_load(s->b), crane__v3_load(s->a));
        if (!(crane__v3_dot(g, g) > 0)) {
            return CRANE_GUARD_FIELD_B;
        }
    }
    return 0;
}

crane_status crane_solid_check(const crane_solid *s, int *field)
{
    int f;
    if (s == NULL || field == NULL) {
        return CRANE_E_NULL;
    }
    f = crane__solid_field(s);
    *field = f;
    return f != 0 ? CRANE_E_SOLID : CRANE_OK;
}

crane_status crane_solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                                  crane_real pa[3], crane_real pb[3])
{
    crane__v3 qa, qb;
    crane_real d;

    if (a == NULL || b == NULL || distance == NULL || pa == NULL || pb == NULL) {
        return CRANE_E_NULL;
    }
    if (crane__solid_field(a) != 0 || crane__solid_field(b) != 0) {
        return CRANE_E_SOLID;
    }
    if (crane__solid_distance(a, b, &d, &qa, &qb) == 0) {
        return CRANE_E_SOLID;
    }
    *distance = d;
    crane__v3_store(pa, qa);
    crane__v3_store(pb, qb);
    return CRANE_OK;
}
