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

/* Squared distance between p0 + s d1 and q0 + t d2. */
static crane_real seg_gap2(crane__v3 p0, crane__v3 d1, crane_real s, crane__v3 q0, crane__v3 d2,
                           crane_real t)
{
    const crane__v3 g = crane__v3_sub(lerp3(p0, d1, s), lerp3(q0, d2, t));
    return crane__v3_dot(g, g);
}

/* Segment-segment: the squared distance is a convex quadratic in (s, t) on the unit square; its
 * minimum is the interior stationary point or lies on one of the four edges, where it is a 1-D
 * clamped minimum. Every candidate is evaluated and the smallest kept, so near-parallel segments
 * (an ill-conditioned stationary point) still get the exact boundary minimum. */
static crane_real seg_seg(crane__v3 p0, crane__v3 p1, crane__v3 q0, crane__v3 q1, crane__v3 *pa,
                          crane__v3 *pb)
{
    const crane__v3 d1 = crane__v3_sub(p1, p0), d2 = crane__v3_sub(q1, q0);
    const crane__v3 r = crane__v3_sub(p0, q0);
    const crane_real a = crane__v3_dot(d1, d1), e = crane__v3_dot(d2, d2);
    const crane_real b = crane__v3_dot(d1, d2), c = crane__v3_dot(d1, r), f = crane__v3_dot(d2, r);
    crane_real cs[5], ct[5], best, bs = 0, bt = 0;
    int n = 0, i;

    /* edges s = 0, s = 1 (t free), t = 0, t = 1 (s free) */
    cs[n] = 0;
    ct[n++] = e > 0 ? clamp01(f / e) : 0;
    cs[n] = 1;
    ct[n++] = e > 0 ? clamp01((b + f) / e) : 0;
    ct[n] = 0;
    cs[n++] = a > 0 ? clamp01(-c / a) : 0;
    ct[n] = 1;
    cs[n++] = a > 0 ? clamp01((b - c) / a) : 0;
    {
        const crane_real den = a * e - b * b;
        if (den > 0) {
            const crane_real s = (b * f - c * e) / den, t = (a * f - b * c) / den;
            if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
                cs[n] = s;
                ct[n++] = t;
            }
        }
    }
    best = seg_gap2(p0, d1, cs[0], q0, d2, ct[0]);
    bs = cs[0];
    bt = ct[0];
    for (i = 1; i < n; ++i) {
        const crane_real g = seg_gap2(p0, d1, cs[i], q0, d2, ct[i]);
        if (g < best) {
            best = g;
            bs = cs[i];
            bt = ct[i];
        }
    }
    *pa = lerp3(p0, d1, bs);
    *pb = lerp3(q0, d2, bt);
    return crane__sqrt(best);
}

/* Box axes and centre. */
typedef struct {
    crane__v3 c, u[3];
    crane_real h[3];
} box3;

static box3 box_of(const crane_solid *s)
{
    box3 b;
    int i;
    b.c = crane__v3_load(s->a);
    for (i = 0; i < 3; ++i) {
        b.u[i] = crane__v3_load(s->axes + 3 * i);
        b.h[i] = s->half[i];
    }
    return b;
}

static crane__v3 to_box(const box3 *b, crane__v3 p)
{
    const crane__v3 r = crane__v3_sub(p, b->c);
    return crane__v3_make(crane__v3_dot(r, b->u[0]), crane__v3_dot(r, b->u[1]),
                          crane__v3_dot(r, b->u[2]));
}

static crane__v3 from_box(const box3 *b, crane__v3 q)
{
    return crane__v3_add(b->c, crane__v3_add(crane__v3_scale(q.x, b->u[0]),
                                             crane__v3_add(crane__v3_scale(q.y, b->u[1]),
                                                           crane__v3_scale(q.z, b->u[2]))));
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

/* Segment-box, exact: in the box frame the squared distance from p(t) = p0 + t d is
 * sum_i excess_i(t)^2, a convex piecewise quadratic whose pieces change where p_i(t) = +-h_i. On
 * each piece it is one quadratic A t^2 + B t + C (the axes outside the slab at the piece's middle),
 * minimised in closed form; the minimum over the pieces is the exact distance. */
static crane_real seg_box(crane__v3 s0, crane__v3 s1, const box3 *bx, crane__v3 *pa, crane__v3 *pb)
{
    const crane__v3 l0 = to_box(bx, s0), l1 = to_box(bx, s1);
    const crane_real p0[3] = {l0.x, l0.y, l0.z};
    const crane_real d[3] = {l1.x - l0.x, l1.y - l0.y, l1.z - l0.z};
    crane_real brk[8], best, bt = 0;
    int nb = 0, i, j, k;

    brk[nb++] = 0;
    brk[nb++] = 1;
    for (i = 0; i < 3; ++i) {
        if (d[i] != 0) {
            for (k = -1; k <= 1; k += 2) {
                const crane_real t = ((crane_real)k * bx->h[i] - p0[i]) / d[i];
                if (t > 0 && t < 1)
                    brk[nb++] = t;
            }
        }
    }
    for (i = 1; i < nb; ++i) { /* insertion sort of at most 8 */
        const crane_real v = brk[i];
        j = i - 1;
        while (j >= 0 && brk[j] > v) {
            brk[j + 1] = brk[j];
            --j;
        }
        brk[j + 1] = v;
    }
    best = box_gap2(p0, d, bx->h, 0);
    for (i = 0; i < nb; ++i) {
        const crane_real g = box_gap2(p0, d, bx->h, brk[i]);
        if (g < best) {
            best = g;
            bt = brk[i];
        }
    }
    for (i = 0; i + 1 < nb; ++i) {
        const crane_real ta = brk[i], tb = brk[i + 1], tm = (ta + tb) / 2;
        crane_real A = 0, B = 0;
        if (!(tb > ta))
            continue;
        for (j = 0; j < 3; ++j) {
            const crane_real x = p0[j] + tm * d[j];
            if (x > bx->h[j] || x < -bx->h[j]) {
                const crane_real off = p0[j] - (x > 0 ? bx->h[j] : -bx->h[j]);
                A += d[j] * d[j];
                B += 2 * d[j] * off;
            }
        }
        if (A > 0) {
            crane_real t = -B / (2 * A);
            t = t < ta ? ta : (t > tb ? tb : t);
            {
                const crane_real g = box_gap2(p0, d, bx->h, t);
                if (g < best) {
                    best = g;
                    bt = t;
                }
            }
        }
    }
    {
        const crane__v3 p = crane__v3_make(p0[0] + bt * d[0], p0[1] + bt * d[1], p0[2] + bt * d[2]);
        const crane__v3 q = crane__v3_make(p.x - excess(p.x, bx->h[0]), p.y - excess(p.y, bx->h[1]),
                                           p.z - excess(p.z, bx->h[2]));
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

static crane__v3 box_vertex(const box3 *b, int v)
{
    return from_box(b, crane__v3_make((v & 1) ? b->h[0] : -b->h[0], (v & 2) ? b->h[1] : -b->h[1],
                                      (v & 4) ? b->h[2] : -b->h[2]));
}

/* Box-box: if the boxes are apart, a closest pair has a vertex or an edge point of one box on the
 * other (vertex-face, edge-edge, face-vertex; parallel faces and edges have such a pair too); if
 * they overlap, an edge of one meets the other or one contains the other (its edges are inside).
 * So the minimum over the 12 edges of each box against the other box is exact. */
static crane_real box_box(const box3 *x, const box3 *y, crane__v3 *pa, crane__v3 *pb)
{
    crane_real best = -1;
    int side, v, i;
    for (side = 0; side < 2 && best != 0; ++side) {
        const box3 *m = side ? y : x, *o = side ? x : y;
        for (v = 0; v < 8 && best != 0; ++v) {
            for (i = 0; i < 3; ++i) {
                const int w = v | (1 << i);
                crane__v3 qa, qb;
                crane_real dd;
                if (w == v)
                    continue;
                dd = seg_box(box_vertex(m, v), box_vertex(m, w), o, &qa, &qb);
                if (best < 0 || dd < best) {
                    best = dd;
                    *pa = side ? qb : qa;
                    *pb = side ? qa : qb;
                }
            }
        }
    }
    return best;
}

static crane_real box_plane(const box3 *b, crane__v3 p, crane__v3 n, crane__v3 *pa, crane__v3 *pb)
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
    if (seglike(a->kind)) {
        crane__v3 a0, a1;
        segment_of(a, &a0, &a1);
        if (seglike(b->kind)) {
            crane__v3 b0, b1;
            segment_of(b, &b0, &b1);
            *d = seg_seg(a0, a1, b0, b1, pa, pb);
        } else if (b->kind == CRANE_SOLID_BOX) {
            const box3 bx = box_of(b);
            *d = seg_box(a0, a1, &bx, pa, pb);
        } else {
            *d = seg_plane(a0, a1, crane__v3_load(b->a), crane__v3_load(b->b), pa, pb);
        }
        return 1;
    }
    if (a->kind == CRANE_SOLID_BOX) {
        const box3 ba = box_of(a);
        if (b->kind == CRANE_SOLID_BOX) {
            const box3 bb = box_of(b);
            *d = box_box(&ba, &bb, pa, pb);
        } else {
            *d = box_plane(&ba, crane__v3_load(b->a), crane__v3_load(b->b), pa, pb);
        }
        return 1;
    }
    return 0;
}

static crane_real radius_of(const crane_solid *s)
{
    return seglike(s->kind) ? s->radius : 0;
}

int crane__solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                          crane__v3 *pa, crane__v3 *pb)
{
    /* order: seglike < box < plane, so core_distance sees (a, b) with b not "smaller" */
    const int ra = seglike(a->kind) ? 0 : (a->kind == CRANE_SOLID_BOX ? 1 : 2);
    const int rb = seglike(b->kind) ? 0 : (b->kind == CRANE_SOLID_BOX ? 1 : 2);
    const int swap = rb < ra;
    const crane_solid *x = swap ? b : a, *y = swap ? a : b;
    crane__v3 px, py;
    crane_real d, rx, ry;

    if (!core_distance(x, y, &d, &px, &py))
        return 0;
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
    *pa = swap ? py : px;
    *pb = swap ? px : py;
    return 1;
}

static int finite3(const crane_real *v)
{
    return crane__finite(v[0]) && crane__finite(v[1]) && crane__finite(v[2]);
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

    if (s->kind < CRANE_SOLID_PLANE || s->kind > CRANE_SOLID_CYLINDER)
        return CRANE_FIELD_KIND;
    if (!finite3(s->a))
        return CRANE_FIELD_A;
    if (s->kind == CRANE_SOLID_PLANE) {
        const crane__v3 n = crane__v3_load(s->b);
        if (!finite3(s->b) || crane__fabs(crane__v3_dot(n, n) - 1) > tol)
            return CRANE_FIELD_B;
        return 0;
    }
    if (s->kind == CRANE_SOLID_BOX) {
        for (i = 0; i < 3; ++i)
            if (!(crane__finite(s->half[i]) && s->half[i] > 0))
                return CRANE_FIELD_HALF;
        for (i = 0; i < 9; ++i)
            if (!crane__finite(s->axes[i]))
                return CRANE_FIELD_AXES;
        for (i = 0; i < 3; ++i) {
            const crane__v3 ui = crane__v3_load(s->axes + 3 * i);
            for (j = i; j < 3; ++j) {
                const crane_real want = i == j ? 1 : 0;
                if (crane__fabs(crane__v3_dot(ui, crane__v3_load(s->axes + 3 * j)) - want) > tol)
                    return CRANE_FIELD_AXES;
            }
        }
        return 0;
    }
    if (s->kind != CRANE_SOLID_SPHERE && !finite3(s->b))
        return CRANE_FIELD_B;
    if (!(crane__finite(s->radius) && s->radius >= 0) ||
        (s->kind != CRANE_SOLID_CAPSULE && !(s->radius > 0)))
        return CRANE_FIELD_RADIUS;
    if (s->kind == CRANE_SOLID_CYLINDER) {
        const crane__v3 g = crane__v3_sub(crane__v3_load(s->b), crane__v3_load(s->a));
        if (!(crane__v3_dot(g, g) > 0))
            return CRANE_FIELD_B;
    }
    return 0;
}

crane_status crane_solid_check(const crane_solid *s, int *field)
{
    int f;
    if (!s || !field)
        return CRANE_E_NULL;
    f = crane__solid_field(s);
    *field = f;
    return f ? (crane_status)CRANE_E_SOLID : CRANE_OK;
}

crane_status crane_solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                                  crane_real pa[3], crane_real pb[3])
{
    crane__v3 qa, qb;
    crane_real d;

    if (!a || !b || !distance || !pa || !pb)
        return CRANE_E_NULL;
    if (crane__solid_field(a) || crane__solid_field(b))
        return (crane_status)CRANE_E_SOLID;
    if (!crane__solid_distance(a, b, &d, &qa, &qb))
        return (crane_status)CRANE_E_SOLID;
    *distance = d;
    crane__v3_store(pa, qa);
    crane__v3_store(pb, qb);
    return CRANE_OK;
}
