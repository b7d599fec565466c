/* SPDX-License-Identifier: MIT */
/*
 * The four-joint prediction (docs/model.md, "Four joints"): fixed-step RK4 on (q, qd) of lift,
 * tilt, slew and extension (and the chamber pressures of valve-driven cylinders), with the end-stop
 * events of "End stops" over four joints and the extension's friction substeps. crane_predict
 * takes this path when the slew or the extension is not held; with both held it takes the planar
 * one (integrator.c), whose results it keeps bit for bit.
 *
 * Everything here runs on inputs that crane_predict has already validated.
 */
#include "crane_internal.h"

/* State layout: q[4], qd[4], then with valve-driven cylinders the pressures (p_a, p_b of joint j
 * at 8 + 2j, 9 + 2j) and the spools (16 + j); entries of joints that are not valve-driven stay 0. */
enum x4_slot { Q = 0, W = 4, P = 8, Y = 16, N_MECH = 8, N_ALL = 20 };

typedef struct {
    crane_real v[N_ALL];
} x4;

/* Per-prediction working data, on the caller's stack. */
typedef struct {
    const crane_model *m;
    const crane_inputs *in;
    const crane_state *s0;
    crane__bodies4 b;
    size_t cursor[4];           /* sample segment last used, per joint */
    signed char mode[4];        /* CRANE__FREE, _HELD, _STOP_LO, _STOP_HI (in q terms) */
    signed char lo_flag[4];     /* stop flag (actuator terms) at the lower limit of q */
    unsigned char valve[4];     /* joint j is valve-driven */
    int n;                      /* state entries in use: N_MECH, or N_ALL with valves */
    crane_real lo[4], hi[4];    /* limits of q: angle limits, [slew_min, slew_max], extension range */
    crane_real gf_ext;          /* the extension friction's slope at rest, N s/m */
} c4;

static int locked(const c4 *c, int j) { return c->mode[j] != CRANE__FREE; }

/* ds/dq of joint j at the configuration: the lift's from its triangle, the tilt's from the
 * four-bar, the rack's pinion radius for the slew, 1 for the extension. With stroke, the stroke
 * (for the slew and the extension from their coordinate q: r_p (psi - slew_min), e - extension_min). */
static crane_real ratio(const c4 *c, const crane__conf4 *cf, int j, crane_real q, crane_real *stroke)
{
    crane_real ds = 1, s;

    if (j == CRANE_LIFT) {
        crane__lift_from_angle(c->m, cf->c0, cf->s0, &s, &ds);
    } else if (j == CRANE_TILT) {
        ds = cf->tk.ds;
        s = cf->tk.stroke;
    } else {
        if (j == CRANE_SLEW)
            ds = c->m->params->slew_drive.pinion_radius;
        s = ds * (q - c->lo[j]);
    }
    if (stroke)
        *stroke = s;
    return ds;
}

/* The stroke of a stopped valve-driven actuator: the end of its range that it stopped at (a
 * valve-driven joint is never held). */
static crane_real locked_stroke(const c4 *c, int j)
{
    const int flag = c->mode[j] == CRANE__STOP_LO ? c->lo_flag[j] : -c->lo_flag[j];
    crane_real s_min, s_max;

    crane__actuator_range(c->m, j, &s_min, &s_max);
    return flag < 0 ? s_min : s_max;
}

/* Everything the accelerations need at (t, x): the configuration, the in-plane mass matrix Mp
 * (lift, tilt, extension), J_z and the net generalized forces b = tau - h, with actuator forces
 * only for the joints not in lk (a joint in lk that is stopped needs its own force only to decide
 * its release, which passes lk = the held joints). With sv, the valve-driven joints' strokes
 * (sv[j]) and stroke rates (sv[4 + j]). */
typedef struct {
    crane__conf4 cf;
    crane_real Mp[6], jz, b[4];
} dyn4;

static void forces4(c4 *c, crane_real t, const x4 *x, const int lk[4], dyn4 *d, crane_real *sv)
{
    const crane_model *m = c->m;
    static const crane_real zero[4] = {0, 0, 0, 0};
    crane_real h[4], jdot;
    int j;

    crane__conf4_at(m, &c->b, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d->cf);
    crane__id4(m, &c->b, &d->cf, &x->v[W], zero, m->params->gravity, h);
    crane__mass4(m, &c->b, &d->cf, d->Mp);
    crane__slew_inertia(m, &c->b, &d->cf, &x->v[W], &d->jz, &jdot);
    for (j = 0; j < 4; ++j) {
        crane_real ds, p_a, p_b, stroke;
        d->b[j] = -h[j];
        if (lk[j]) {
            if (sv && c->valve[j]) {
                sv[j] = locked_stroke(c, j);
                sv[4 + j] = 0;
            }
            continue;
        }
        ds = ratio(c, &d->cf, j, x->v[Q + j], &stroke);
        if (c->valve[j]) {
            p_a = x->v[P + 2 * j];
            p_b = x->v[P + 2 * j + 1];
            if (sv) {
                sv[j] = stroke;
                sv[4 + j] = ds * x->v[W + j];
            }
        } else {
            crane__drive_pressures(&c->in->drive[j], &c->cursor[j], t, &p_a, &p_b);
        }
        d->b[j] += crane__actuator_force(m, j, p_a, p_b, ds * x->v[W + j]) * ds;
    }
}

/* Index of in-plane joint k (0, 1, 2) in Mp's (lift, tilt, extension) and in the joint arrays. */
static const int PLANE[3] = {CRANE_LIFT, CRANE_TILT, CRANE_EXTENSION};

static crane_real mp(const crane_real Mp[6], int r, int k)
{
    static const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    return Mp[idx[r][k]];
}

/* Solves M a = b over the joints not in lk (the others get 0): the slew alone (M is block
 * diagonal), the free in-plane joints by Gaussian elimination (M is positive definite). */
static void solve4(const dyn4 *d, const crane_real b[4], const int lk[4], crane_real a[4])
{
    crane_real A[3][4];
    int f[3], n = 0, r, k, i;

    /* cppcheck 2.10's whole-program check sizes a with the float build's crane_real and indexes
     * it with the double build's (a false "ctuArrayIndex"; every caller passes crane_real[4]) */
    /* cppcheck-suppress ctuArrayIndex */
    a[CRANE_SLEW] = lk[CRANE_SLEW] ? 0 : b[CRANE_SLEW] / d->jz;
    for (k = 0; k < 3; ++k) {
        a[PLANE[k]] = 0;
        if (!lk[PLANE[k]]) {
            f[n] = k;
            ++n;
        }
    }
    for (r = 0; r < n; ++r) {
        for (k = 0; k < n; ++k)
            A[r][k] = mp(d->Mp, f[r], f[k]);
        A[r][n] = b[PLANE[f[r]]];
    }
    for (i = 0; i < n; ++i)
        for (r = i + 1; r < n; ++r) {
            const crane_real l = A[r][i] / A[i][i];
            for (k = i; k <= n; ++k)
                A[r][k] -= l * A[i][k];
        }
    for (i = n - 1; i >= 0; --i) {
        crane_real s = A[i][n];
        for (k = i + 1; k < n; ++k)
            s -= A[i][k] * a[PLANE[f[k]]];
        a[PLANE[f[i]]] = s / A[i][i];
    }
}

/* qdd at (t, x) with the joints in lk locked; with dh, the chamber and spool rates too. */
static void accel4(c4 *c, crane_real t, const x4 *x, const int lk[4], crane_real a[4], crane_real *dh)
{
    crane_real sv[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    int j;

    if (lk[0] && lk[1] && lk[2] && lk[3]) {
        for (j = 0; j < 4; ++j) {
            a[j] = 0;
            if (c->valve[j])
                sv[j] = locked_stroke(c, j);
        }
    } else {
        dyn4 d;
        forces4(c, t, x, lk, &d, dh ? sv : NULL);
        solve4(&d, d.b, lk, a);
    }
#if CRANE_HYDRAULICS
    if (dh)
        for (j = 0; j < 4; ++j)
            if (c->valve[j]) {
                crane_real r[3];
                crane__chamber_rates(c->m, j, crane__drive_lever(&c->in->drive[j], &c->cursor[j], t),
                                     sv[j], sv[4 + j], &x->v[P + 2 * j], x->v[Y + j], r);
                dh[2 * j] = r[0];
                dh[2 * j + 1] = r[1];
                dh[8 + j] = r[2];
            }
#else
    (void)dh;
#endif
}

static void lock_mask(const c4 *c, int lk[4])
{
    int j;
    for (j = 0; j < 4; ++j)
        lk[j] = locked(c, j);
}

/* Classic RK4 of size h from (t, x) into y (y != x): ((k1 + 2 k2) + 2 k3) + k4, as the planar one. */
static void rk4(c4 *c, crane_real t, const x4 *x, crane_real h, x4 *y)
{
    const crane_real h2 = h / 2, h6 = h / 6;
    crane_real k[N_ALL];
    x4 xs = *x;
    int lk[4], s, i;

    lock_mask(c, lk);
    for (i = N_MECH; i < N_ALL; ++i)
        k[i] = 0;
    for (s = 0; s < 4; ++s) {
        accel4(c, s == 0 ? t : s == 3 ? t + h : t + h2, &xs, lk, &k[W], c->n > N_MECH ? &k[P] : NULL);
        for (i = 0; i < 4; ++i)
            k[Q + i] = xs.v[W + i];
        for (i = 0; i < c->n; ++i) {
            if (s == 0)
                y->v[i] = k[i];
            else if (s < 3)
                y->v[i] = y->v[i] + 2 * k[i];
            else
                y->v[i] = x->v[i] + h6 * (y->v[i] + k[i]);
        }
        if (s < 3)
            for (i = 0; i < c->n; ++i)
                xs.v[i] = x->v[i] + (s == 2 ? h : h2) * k[i];
    }
    for (i = c->n; i < N_ALL; ++i)
        y->v[i] = x->v[i];
}

/* Plastic impact on joint i (docs/model.md, "Four joints"): over the free joints F,
 * qd_F <- qd_F - Minv e_i (qd_i / Minv_ii); M is block diagonal, so a slew impact stops the slew
 * alone and an in-plane impact leaves the slew rate. */
static void impact(c4 *c, x4 *x, int i)
{
    if (i != CRANE_SLEW) {
        dyn4 d;
        crane_real e[4] = {0, 0, 0, 0}, col[4];
        int lk[4], j;
        crane__conf4_at(c->m, &c->b, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d.cf);
        crane__mass4(c->m, &c->b, &d.cf, d.Mp);
        d.jz = 1;
        for (j = 0; j < 4; ++j)
            lk[j] = j == CRANE_SLEW || (j != i && locked(c, j));
        e[i] = 1;
        solve4(&d, e, lk, col);
        for (j = 0; j < 4; ++j)
            if (j != i && !lk[j])
                x->v[W + j] -= col[j] * (x->v[W + i] / col[i]);
    }
    x->v[W + i] = 0;
}

/* Puts joint i on its stop: q exactly at the limit, plastic impact, STOPPED. */
static void stop_joint(c4 *c, x4 *x, int i, int upper)
{
    x->v[Q + i] = upper ? c->hi[i] : c->lo[i];
    impact(c, x, i);
    c->mode[i] = (signed char)(upper ? CRANE__STOP_HI : CRANE__STOP_LO);
}

/* Which stopped joints leave their stops (docs/model.md, "End stops" over four joints): the
 * candidate sets in the order of their bitmask (lift 1, tilt 2, slew 4, extension 8); the first
 * where every released joint accelerates into its range and every joint kept on its stop is
 * pressed onto it. */
static int release_set(c4 *c, crane_real t, const x4 *x)
{
    int held[4], cand, j, any = 0;
    dyn4 d;

    for (j = 0; j < 4; ++j) {
        held[j] = c->mode[j] == CRANE__HELD;
        any = any || c->mode[j] >= CRANE__STOP_LO;
    }
    if (!any)
        return 0;
    forces4(c, t, x, held, &d, NULL);
    for (cand = 0; cand < 16; ++cand) {
        int lk[4], ok = 1;
        crane_real a[4], r[4];
        for (j = 0; j < 4; ++j) {
            const int released = (cand >> j) & 1;
            if (released && c->mode[j] < CRANE__STOP_LO)
                ok = 0;
            lk[j] = held[j] || (c->mode[j] >= CRANE__STOP_LO && !released);
        }
        if (!ok)
            continue;
        solve4(&d, d.b, lk, a);
        /* M a, for the reactions of the kept joints */
        for (j = 0; j < 3; ++j)
            r[PLANE[j]] = mp(d.Mp, j, 0) * a[CRANE_LIFT] + mp(d.Mp, j, 1) * a[CRANE_TILT] +
                          mp(d.Mp, j, 2) * a[CRANE_EXTENSION];
        r[CRANE_SLEW] = d.jz * a[CRANE_SLEW];
        for (j = 0; j < 4; ++j) {
            const crane_real inward = c->mode[j] == CRANE__STOP_LO ? 1 : -1;
            if (c->mode[j] < CRANE__STOP_LO)
                continue;
            if ((cand >> j) & 1)
                ok = ok && inward * a[j] > 0;
            else
                ok = ok && inward * (r[j] - d.b[j]) >= 0;
        }
        if (ok)
            return cand;
    }
    return 0;
}

static void release(c4 *c, crane_real t, const x4 *x)
{
    const int cand = release_set(c, t, x);
    int j;

    for (j = 0; j < 4; ++j)
        if ((cand >> j) & 1)
            c->mode[j] = CRANE__FREE;
}

static int any_stopped(const c4 *c)
{
    return c->mode[0] >= CRANE__STOP_LO || c->mode[1] >= CRANE__STOP_LO ||
           c->mode[2] >= CRANE__STOP_LO || c->mode[3] >= CRANE__STOP_LO;
}

/* Release inside a piece (docs/model.md, "Release inside a step"): bisects the piece size, advances
 * to hi and releases there; returns hi. y is scratch. */
static crane_real release_in_piece(c4 *c, crane_real t, x4 *x, crane_real h, x4 *y)
{
    crane_real lo = 0, hi = h;
    int k;

    for (k = 0; k < CRANE__RELEASE_BISECTIONS; ++k) {
        const crane_real mid = (lo + hi) / 2;
        rk4(c, t, x, mid, y);
        if (release_set(c, t + mid, y))
            hi = mid;
        else
            lo = mid;
    }
    rk4(c, t, x, hi, y);
    *x = *y;
    release(c, t + hi, x);
    return hi;
}

/* One step of size h from t, cut at impacts and releases (as integrator.c's step, four joints). */
static void step(c4 *c, crane_real t, x4 *x, crane_real h, crane_real t_end)
{
    crane_real rem = h;
    int piece;

    for (piece = 0; rem > 0; ++piece) {
        unsigned out = 0, upper = 0;
        crane_real tmin = rem;
        x4 x1;
        int i;

        rk4(c, t, x, rem, &x1);
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x1.v[Q + i] > c->hi[i])
                upper |= 1u << i;
            else if (!(x1.v[Q + i] < c->lo[i]))
                continue;
            out |= 1u << i;
        }
        if (!out) {
            if (piece < CRANE__MAX_PIECES - 1 && any_stopped(c) && release_set(c, t_end, &x1)) {
                const crane_real hi = release_in_piece(c, t, x, rem, &x1);
                t += hi;
                rem -= hi;
                continue;
            }
            *x = x1;
            return;
        }
        if (piece == CRANE__MAX_PIECES - 1) {
            *x = x1;
            for (i = 0; i < 4; ++i)
                if ((out >> i) & 1)
                    stop_joint(c, x, i, (upper >> i) & 1);
            return;
        }
        for (i = 0; i < 4; ++i) {
            if ((out >> i) & 1) {
                const int up = (upper >> i) & 1;
                const crane_real tau = crane__crossing_time(x->v[Q + i], x->v[W + i], x1.v[Q + i],
                                                            x1.v[W + i], rem,
                                                            up ? c->hi[i] : c->lo[i], up);
                if (tau < tmin)
                    tmin = tau;
            }
        }
        rk4(c, t, x, tmin, &x1);
        *x = x1;
        t += tmin;
        rem -= tmin;
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x->v[Q + i] <= c->lo[i])
                stop_joint(c, x, i, 0);
            else if (x->v[Q + i] >= c->hi[i])
                stop_joint(c, x, i, 1);
        }
    }
}

/* The substep count of a step of size h from x (docs/model.md, "Hydraulics" and "Four joints"):
 * the valve-driven cylinders' chamber stiffness and, with the extension not held, its friction's
 * rate lambda_e = G_f (M^-1)_ee over the joints that are not held; the larger count. */
static CRANE__NOINLINE long substeps(c4 *c, const x4 *x, crane_real h)
{
    long n = 1;
    dyn4 d;
    crane__conf4_at(c->m, &c->b, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d.cf);
#if CRANE_HYDRAULICS
    if (c->n > N_MECH) {
        const int valve[4] = {c->valve[0], c->valve[1], c->valve[2], c->valve[3]};
        crane_real stroke[4] = {0, 0, 0, 0};
        int j;
        for (j = 0; j < 4; ++j)
            if (c->valve[j]) {
                if (c->mode[j] != CRANE__FREE)
                    stroke[j] = locked_stroke(c, j);
                else
                    (void)ratio(c, &d.cf, j, x->v[Q + j], &stroke[j]);
            }
        n = crane__substeps(c->m, stroke, valve, h);
    }
#endif
    if (c->mode[CRANE_EXTENSION] != CRANE__HELD) {
        crane_real e[4] = {0, 0, 0, 0}, col[4], ne, minv;
        int lk[4], j;
        crane__mass4(c->m, &c->b, &d.cf, d.Mp);
        d.jz = 1;
        for (j = 0; j < 4; ++j)
            lk[j] = j == CRANE_SLEW || c->mode[j] == CRANE__HELD;
        e[CRANE_EXTENSION] = 1;
        solve4(&d, e, lk, col);
        /* (M^-1)_ee at most 4 / m_ext: the bound that check_work counts (crane_internal.h) */
        minv = col[CRANE_EXTENSION];
        if (minv > 4 / c->m->params->extension_boom.mass)
            minv = 4 / c->m->params->extension_boom.mass;
        ne = crane__ceil(h * c->gf_ext * minv / (crane_real)2.5);
        if (ne > (crane_real)n)
            n = (long)ne;
    }
    return n;
}

static void put_sample(c4 *c, crane_real t, const x4 *x, crane_sample *o)
{
    const crane_model *m = c->m;
    const crane_params *p = m->params;
    crane_real c0, s0, c1, s1, cpsi, spsi, e;
    crane_vec2 tip;
    int i;

    crane__sincos(x->v[Q], &s0, &c0);
    crane__sincos(x->v[Q + 1], &s1, &c1);
    o->t = t;
    for (i = 0; i < 4; ++i) {
        crane_real coord = x->v[Q + i];
        /* a held joint reports its initial coordinate, a stopped one exactly its limit */
        if (c->mode[i] == CRANE__STOP_LO)
            coord = c->lo[i];
        else if (c->mode[i] == CRANE__STOP_HI)
            coord = c->hi[i];
        if (i == CRANE_SLEW) {
            o->slew = c->mode[i] == CRANE__HELD ? c->s0->slew : coord;
            o->slew_rate = x->v[W + i];
        } else if (i == CRANE_EXTENSION) {
            o->extension = c->mode[i] == CRANE__HELD ? c->s0->extension : coord;
            o->extension_rate = x->v[W + i];
        } else {
            crane_real s;
            switch (c->mode[i]) {
            case CRANE__STOP_LO:
            case CRANE__STOP_HI: s = locked_stroke(c, i); break;
            case CRANE__HELD: s = c->s0->stroke[i]; break;
            default:
                if (i == CRANE_LIFT) {
                    crane__lift_from_angle(m, c0, s0, &s, NULL);
                } else {
                    crane__tilt_from_angle(m, c1, s1, &s, NULL, NULL, NULL);
                }
                /* the stroke -> angle -> stroke round trip can land a few 1e-16 m outside */
                if (s < m->stroke_min[i])
                    s = m->stroke_min[i];
                else if (s > m->stroke_max[i])
                    s = m->stroke_max[i];
                break;
            }
            o->stroke[i] = s;
            o->theta[i] = x->v[Q + i];
            o->omega[i] = x->v[W + i];
        }
        o->flow_a[i] = o->flow_b[i] = o->spool[i] = 0;
#if CRANE_HYDRAULICS
        if (c->valve[i]) {
            const crane_hydraulics *h = crane__circuit(m, i);
            const crane_real y = h->spool_time_constant > 0
                                     ? x->v[Y + i]
                                     : crane__drive_lever(&c->in->drive[i], &c->cursor[i], t);
            o->p_a[i] = x->v[P + 2 * i];
            o->p_b[i] = x->v[P + 2 * i + 1];
            crane__valve_flows(h, y, o->p_a[i], o->p_b[i], &o->flow_a[i], &o->flow_b[i]);
            o->spool[i] = y;
        } else
#endif
        if (c->mode[i] == CRANE__HELD) {
            o->p_a[i] = o->p_b[i] = 0;
        } else {
            crane__drive_pressures(&c->in->drive[i], &c->cursor[i], t, &o->p_a[i], &o->p_b[i]);
        }
        o->stop[i] = c->mode[i] == CRANE__STOP_LO   ? c->lo_flag[i]
                     : c->mode[i] == CRANE__STOP_HI ? -c->lo_flag[i]
                                                    : 0;
    }
    /* tip = O1 + R(th0) (O2 + R(th1) (mount + (e + tip_distance, 0))), then the slew */
    e = o->extension;
    tip = crane__add(p->lift_pivot,
                     crane__rot(c0, s0,
                                crane__add(p->tilt_pivot,
                                           crane__rot(c1, s1,
                                                      crane__add(p->extension_mount,
                                                                 crane__v2(e + p->tip_distance, 0))))));
    crane__sincos(o->slew, &spsi, &cpsi);
    o->tip[0] = tip.x * cpsi;
    o->tip[1] = tip.x * spsi;
    o->tip[2] = tip.y;
}

static int finite_state(const c4 *c, const x4 *x)
{
    int i;
    for (i = 0; i < c->n; ++i)
        if (!crane__finite(x->v[i]))
            return 0;
    return 1;
}

crane_status crane__integrate4(const crane_model *m, const crane_state *s0, const crane_inputs *in,
                               crane_real horizon, crane_real dt, long n_steps, long sample_every,
                               crane_sample *out, size_t *n_written)
{
    const crane_params *p = m->params;
    c4 c;
    x4 x;
    long k;
    size_t next;
    int i;

    c.m = m;
    c.in = in;
    c.s0 = s0;
    crane__bodies4_init(p, &c.b);
    c.n = N_MECH;
    for (i = 0; i < N_ALL; ++i)
        x.v[i] = 0;
    c.gf_ext = crane__extension_friction_slope(p);
    for (i = 0; i < 4; ++i) {
        c.cursor[i] = 0;
        c.valve[i] = (unsigned char)(CRANE_HYDRAULICS && in->drive[i].mode == CRANE_DRIVE_VALVE);
        c.mode[i] = (signed char)(in->drive[i].mode == CRANE_DRIVE_HOLD ? CRANE__HELD : CRANE__FREE);
        if (c.valve[i]) {
            c.n = N_ALL;
            x.v[P + 2 * i] = s0->p_a[i];
            x.v[P + 2 * i + 1] = s0->p_b[i];
            x.v[Y + i] = s0->spool[i];
        }
        if (i < 2) {
            crane_real ds;
            if (i == CRANE_LIFT)
                crane__lift_from_stroke(m, s0->stroke[i], &x.v[Q + i], &ds);
            else
                (void)crane__tilt_from_stroke(m, s0->stroke[i], &x.v[Q + i], &ds, NULL, NULL);
            x.v[W + i] = s0->stroke_rate[i] / ds;
            c.lo_flag[i] = (signed char)(ds > 0 ? -1 : 1);
            c.lo[i] = m->theta_min[i];
            c.hi[i] = m->theta_max[i];
        } else {
            c.lo_flag[i] = -1;
            x.v[Q + i] = i == CRANE_SLEW ? s0->slew : s0->extension;
            x.v[W + i] = i == CRANE_SLEW ? s0->slew_rate : s0->extension_rate;
            c.lo[i] = i == CRANE_SLEW ? p->slew_drive.slew_min : p->extension_min;
            c.hi[i] = i == CRANE_SLEW ? p->slew_drive.slew_max : p->extension_max;
        }
    }

    /* At t = 0: a free joint at a limit whose rate does not point into the range starts on it. */
    for (i = 0; i < 4; ++i) {
        int flag;
        if (c.mode[i] != CRANE__FREE)
            continue;
        if (i < 2) {
            const crane_real s = s0->stroke[i], v = s0->stroke_rate[i];
            if (s <= m->stroke_min[i] && v <= 0)
                flag = -1;
            else if (s >= m->stroke_max[i] && v >= 0)
                flag = 1;
            else
                continue;
        } else {
            if (x.v[Q + i] <= c.lo[i] && x.v[W + i] <= 0)
                flag = -1;
            else if (x.v[Q + i] >= c.hi[i] && x.v[W + i] >= 0)
                flag = 1;
            else
                continue;
        }
        stop_joint(&c, &x, i, flag != c.lo_flag[i]);
    }

    *n_written = 0;
    if (!finite_state(&c, &x))
        return CRANE_E_DIVERGED;
    put_sample(&c, 0, &x, &out[0]);
    for (k = 0, next = 1; k < n_steps; ++k) {
        const crane_real t = (crane_real)k * dt;
        const int last = k == n_steps - 1;
        const crane_real h = last ? horizon - t : dt;
        const crane_real t_end = last ? horizon : (crane_real)(k + 1) * dt;
        long j, n_sub = 1;
        crane_real sub = h;

        if ((c.n > N_MECH || c.mode[CRANE_EXTENSION] != CRANE__HELD) && h > 0) {
            n_sub = substeps(&c, &x, h);
            sub = h / (crane_real)n_sub;
        }
        for (j = 0; j < n_sub; ++j) {
            const int final = j == n_sub - 1;
            const crane_real t_sub = j == 0 ? t : t + (crane_real)j * sub;
            release(&c, t_sub, &x);
            if (h > 0)
                step(&c, t_sub, &x, final ? (j == 0 ? h : t_end - t_sub) : sub,
                     final ? t_end : t_sub + sub);
        }
        if (!finite_state(&c, &x)) {
            *n_written = next;
            return CRANE_E_DIVERGED;
        }
        if (last || (k + 1) % sample_every == 0)
            put_sample(&c, last ? horizon : (crane_real)(k + 1) * dt, &x, &out[next++]);
    }
    *n_written = next;
    return CRANE_OK;
}
