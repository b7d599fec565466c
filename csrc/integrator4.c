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

/* State layout: q[4], qd[4], then with valve-driven cylinders joint j's p_a, p_b and spool at
 * H + 3j (the order of crane__chamber_rates's rates); entries of joints that are not valve-driven
 * stay 0. */
enum x4_slot { Q = 0, W = 4, H = 8, N_MECH = 8, N_ALL = 20 };

typedef struct {
    crane_real v[N_ALL];
} x4;

/* Everything the accelerations need at (t, x): the configuration (for the in-plane mass matrix,
 * which solve4 works from it), J_z and the net generalized forces b = tau - h. */
typedef struct {
    crane__conf4 cf;
    crane_real jz, b[4];
} dyn4;

/* Per-prediction working data, on the caller's stack. */
typedef struct {
    const crane_model *m;
    const crane_inputs *in;
    const crane_state *s0;
    crane__bodies4 b;
    size_t cursor[4];           /* sample segment last used, per joint */
    signed char mode[4];        /* CRANE__FREE, _HELD, _STOP_LO, _STOP_HI (in q terms) */
    /* Bit j: joint j's lower limit of q is its actuator's stroke_max (stop flag +1 there; else
     * -1), and joint j is valve-driven (some joint is: the state carries pressures and spools).
     * Masks, not arrays of flags: this context is on the stack budget's deepest path. */
    unsigned char lo_is_max, valves;
    /* The one scratch of every evaluation of the dynamics (RK4's stages, the release rule, the
     * impacts, the substep count), which never overlap: a frame of its own in each would stack
     * on this one (the stack). */
    dyn4 d;
} c4;

static int locked(const c4 *c, int j) { return c->mode[j] != CRANE__FREE; }

static int valve(const c4 *c, int j) { return (c->valves >> j) & 1; }

/* The stop flag (actuator terms: -1 stroke_min, +1 stroke_max) at the lower limit of q. */
static int lo_flag(const c4 *c, int j) { return (c->lo_is_max >> j) & 1 ? 1 : -1; }

/* State entries in use: the pressures and spools only with valves. */
static int n_used(const c4 *c) { return c->valves ? N_ALL : N_MECH; }

/* The lower (upper) limit of q of joint j: the angle limits, [slew_min, slew_max], the extension
 * range. Read where needed rather than kept in c4 (the stack). */
static crane_real lo4(const c4 *c, int j)
{
    if (j < 2)
        return c->m->theta_min[j];
    return j == CRANE_SLEW ? c->m->params->slew_drive.slew_min : c->m->params->extension_min;
}

static crane_real hi4(const c4 *c, int j)
{
    if (j < 2)
        return c->m->theta_max[j];
    return j == CRANE_SLEW ? c->m->params->slew_drive.slew_max : c->m->params->extension_max;
}

/* Joint j is in the set js (bit j: lift 1, tilt 2, slew 4, extension 8). Joint sets are masks
 * rather than arrays of flags: RK4 keeps one for its four stages (the stack). */
static int in_set(unsigned js, int j) { return (int)((js >> j) & 1u); }

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
        s = ds * (q - lo4(c, j));
    }
    if (stroke)
        *stroke = s;
    return ds;
}

/* The stroke of a stopped valve-driven actuator: the end of its range that it stopped at (a
 * valve-driven joint is never held). */
static crane_real locked_stroke(const c4 *c, int j)
{
    const int flag = c->mode[j] == CRANE__STOP_LO ? lo_flag(c, j) : -lo_flag(c, j);
    crane_real s_min, s_max;

    crane__actuator_range(c->m, j, &s_min, &s_max);
    return flag < 0 ? s_min : s_max;
}

/* Joint j's drive at t (crane__drive_pressures, crane__drive_lever). The lever's interpolation
 * is out of line, one copy for RK4's stages and the samples (the code budget); the pressures'
 * stay inline, since their outputs would otherwise take stack on the deepest path. */
static CRANE__ALWAYS_INLINE void pressures4(c4 *c, int j, crane_real t, crane_real *p_a,
                                            crane_real *p_b)
{
    crane__drive_pressures(&c->in->drive[j], &c->cursor[j], t, p_a, p_b);
}

#if CRANE_HYDRAULICS
static crane_real lever4(c4 *c, int j, crane_real t)
{
    return crane__drive_lever(&c->in->drive[j], &c->cursor[j], t);
}

/* The chamber and spool rates at t of valve-driven joint j at stroke s and stroke rate v, written
 * over its pressures and spool in x (which they are read from first): RK4 takes a stage's rates
 * from there, and keeps no array of them (the stack). */
static CRANE__ALWAYS_INLINE void valve_rates4(c4 *c, crane_real t, x4 *x, int j, crane_real s,
                                              crane_real v)
{
    crane_real r[3];
    int k;

    crane__chamber_rates(c->m, j, lever4(c, j, t), s, v,
                         &x->v[H + 3 * j], x->v[H + 3 * j + 2], r);
    for (k = 0; k < 3; ++k)
        x->v[H + 3 * j + k] = r[k];
}
#endif

/* Fills c->d at (t, x): the configuration, J_z and b = tau - h, with actuator forces only for
 * the joints not in lk (a joint in lk that is stopped needs its own force only to decide its
 * release, which passes lk = the held joints); nothing when all four are locked. With rates (then
 * x itself), each valve-driven joint's chamber and spool rates replace its pressures and spool in
 * x, once its force has read them (valve_rates4). */
static CRANE__ALWAYS_INLINE void forces4(c4 *c, crane_real t, const x4 *x, unsigned lk, x4 *rates)
{
    const crane_model *m = c->m;
    static const crane_real zero[4] = {0, 0, 0, 0};
    dyn4 *const d = &c->d;
    int j;

    if (lk != 15u) {
        crane__conf4_at(m, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d->cf);
        /* the bias h = ID(q, qd, 0) goes into b, negated there (no array of its own: the stack) */
        crane__id4(m, &c->b, &d->cf, &x->v[W], zero, m->params->gravity, d->b);
        /* a locked slew's inertia and force are never read */
        d->jz = 1;
        if (!in_set(lk, CRANE_SLEW)) {
            crane_real jdot;
            crane__slew_inertia(m, &c->b, &d->cf, &x->v[W], &d->jz, &jdot, d->b);
            d->b[CRANE_SLEW] = crane__slew_torque(d->jz, jdot, x->v[W + CRANE_SLEW], 0);
        }
        for (j = 0; j < 4; ++j)
            d->b[j] = -d->b[j];
    }
    for (j = 0; j < 4; ++j) {
        crane_real stroke = 0, v = 0;
        if (in_set(lk, j)) {
            if (valve(c, j))
                stroke = locked_stroke(c, j);
        } else {
            const crane_real ds = ratio(c, &d->cf, j, x->v[Q + j], &stroke);
            crane_real p_a, p_b;
            v = ds * x->v[W + j];
            if (valve(c, j)) {
                p_a = x->v[H + 3 * j];
                p_b = x->v[H + 3 * j + 1];
            } else {
                pressures4(c, j, t, &p_a, &p_b);
            }
            d->b[j] += crane__actuator_force(m, j, p_a, p_b, v) * ds;
        }
#if CRANE_HYDRAULICS
        if (rates && valve(c, j))
            valve_rates4(c, t, rates, j, stroke, v);
#else
        (void)stroke;
        (void)rates;
#endif
    }
}

/* Index of in-plane joint k (0, 1, 2) in Mp's (lift, tilt, extension) and in the joint arrays. */
static const int PLANE[3] = {CRANE_LIFT, CRANE_TILT, CRANE_EXTENSION};

/* The r-th of the free joints packed by solve4. */
static int free_at(unsigned f, int r) { return (int)((f >> (2 * r)) & 3u); }

static crane_real mp(const crane_real Mp[6], int r, int k)
{
    static const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    return Mp[idx[r][k]];
}

/* Solves M a = b over the joints not in lk (the others get 0): the slew alone (M is block
 * diagonal, J_z = c->d.jz), the free in-plane joints by Gaussian elimination (M is positive
 * definite) on Mp, or without it on the mass matrix at c->d.cf. That one is worked here into the
 * last six places of the elimination's own matrix A (6..11, in Mp's order; A's rows are 4 long,
 * the free joints' columns, then b): A is filled row by row from the front, and each place is
 * written only after the last read of the Mp entry it held (so for every set of free joints), so
 * that Mp takes no storage of its own beside the dynamics (the stack). */
static void solve4(const c4 *c, const crane_real *Mp, const crane_real b[4], unsigned lk,
                   crane_real a[4])
{
    crane_real A[3 * 4];
    const crane_real *M = Mp;
    /* the free in-plane joints (their indices into PLANE), two bits each (the stack) */
    unsigned f = 0;
    int n = 0, r, k, i;

    /* cppcheck 2.10's whole-program check sizes a with the float build's crane_real and indexes
     * it with the double build's (a false "ctuArrayIndex"; every caller passes crane_real[4]) */
    /* cppcheck-suppress ctuArrayIndex */
    a[CRANE_SLEW] = in_set(lk, CRANE_SLEW) ? 0 : b[CRANE_SLEW] / c->d.jz;
    for (k = 0; k < 3; ++k) {
        a[PLANE[k]] = 0;
        if (!in_set(lk, PLANE[k])) {
            f |= (unsigned)k << (2 * n);
            ++n;
        }
    }
    if (n == 0)
        return;
    if (!Mp) {
        crane__mass4(c->m, &c->b, &c->d.cf, &A[6]);
        M = &A[6];
    }
    for (r = 0; r < n; ++r) {
        for (k = 0; k < n; ++k)
            A[4 * r + k] = mp(M, free_at(f, r), free_at(f, k));
        A[4 * r + n] = b[PLANE[free_at(f, r)]];
    }
    /* (column i below the pivot is not read again: its update is skipped) */
    for (i = 0; i < n; ++i)
        for (r = i + 1; r < n; ++r) {
            const crane_real l = A[4 * r + i] / A[4 * i + i];
            for (k = i + 1; k <= n; ++k)
                A[4 * r + k] -= l * A[4 * i + k];
        }
    for (i = n - 1; i >= 0; --i) {
        crane_real s = A[4 * i + n];
        for (k = i + 1; k < n; ++k)
            s -= A[4 * i + k] * a[PLANE[free_at(f, k)]];
        a[PLANE[free_at(f, i)]] = s / A[4 * i + i];
    }
}

/* The joints that are held or stopped. */
static unsigned lock_mask4(const c4 *c)
{
    unsigned lk = 0;
    int j;
    for (j = 0; j < 4; ++j)
        if (locked(c, j))
            lk |= 1u << j;
    return lk;
}

/* Entries [from, to) of RK4's bookkeeping at stage s, each entry's rate there being xs->v[i + off]:
 * the stage sum ((k1 + 2 k2) + 2 k3) + k4 accumulates in y, and the next stage's state x + cs k is
 * written over xs (the rate is read first). Out of line, a leaf: its loop then takes none of
 * rk4_4's registers, whose frame is on the stack budget's deepest path. */
static CRANE__NOINLINE void stage4(const x4 *x, x4 *xs, x4 *y, int from, int to, int off, int s,
                                   crane_real cs, crane_real h6)
{
    int i;

    /* one loop per kind of stage (the branch out of the loop: this runs 8 times a step) */
    if (s == 0) {
        for (i = from; i < to; ++i) {
            const crane_real k = xs->v[i + off];
            y->v[i] = k;
            xs->v[i] = x->v[i] + cs * k;
        }
    } else if (s < 3) {
        for (i = from; i < to; ++i) {
            const crane_real k = xs->v[i + off];
            y->v[i] = y->v[i] + 2 * k;
            xs->v[i] = x->v[i] + cs * k;
        }
    } else {
        for (i = from; i < to; ++i)
            y->v[i] = x->v[i] + h6 * (y->v[i] + xs->v[i + off]);
    }
}

/* Classic RK4 of size h from (t, x) into y (y != x): ((k1 + 2 k2) + 2 k3) + k4, as the planar one,
 * its four stages in one loop so that the dynamics are called from one place. There is no array
 * of stage rates: the stage state xs holds them where they are read (the velocities are the
 * positions' rates, solve4 writes the accelerations over the velocities once the positions are
 * done, the chamber rates replace the pressures), and it is then overwritten by the next stage's
 * state (the stack). */
static void rk4_4(c4 *c, crane_real t, const x4 *x, crane_real h, x4 *y)
{
    const crane_real h2 = h / 2, h6 = h / 6;
    const unsigned lk = lock_mask4(c);
    const int n = n_used(c);
    x4 xs = *x;
    int s, i;

    for (s = 0; s < 4; ++s) {
        const crane_real ts = s == 0 ? t : s == 3 ? t + h : t + h2, cs = s == 2 ? h : h2;
        forces4(c, ts, &xs, lk, &xs);
        stage4(x, &xs, y, Q, W, W - Q, s, cs, h6);
        /* all four locked: zeros, without reading c->d */
        solve4(c, NULL, c->d.b, lk, &xs.v[W]);
        /* the entries of joints that are not valve-driven are 0, and so read as rates */
        stage4(x, &xs, y, W, n, 0, s, cs, h6);
    }
    for (i = n; i < N_ALL; ++i)
        y->v[i] = x->v[i];
}

/* Plastic impact on joint i (docs/model.md, "Four joints"): over the free joints F,
 * qd_F <- qd_F - Minv e_i (qd_i / Minv_ii); M is block diagonal, so a slew impact stops the slew
 * alone and an in-plane impact leaves the slew rate. */
static void impact4(c4 *c, x4 *x, int i)
{
    if (i != CRANE_SLEW) {
        dyn4 *const d = &c->d;
        crane_real e[4] = {0, 0, 0, 0}, col[4];
        const unsigned lk = (lock_mask4(c) & ~(1u << i)) | (1u << CRANE_SLEW);
        int j;
        crane__conf4_at(c->m, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d->cf);
        e[i] = 1;
        solve4(c, NULL, e, lk, col);
        for (j = 0; j < 4; ++j)
            if (j != i && !in_set(lk, j))
                x->v[W + j] -= col[j] * (x->v[W + i] / col[i]);
    }
    x->v[W + i] = 0;
}

/* Puts joint i on its stop: q exactly at the limit, plastic impact, STOPPED. */
static void stop_joint4(c4 *c, x4 *x, int i, int upper)
{
    x->v[Q + i] = upper ? hi4(c, i) : lo4(c, i);
    impact4(c, x, i);
    c->mode[i] = (signed char)(upper ? CRANE__STOP_HI : CRANE__STOP_LO);
}

/* Which stopped joints leave their stops (docs/model.md, "End stops" over four joints): the
 * candidate sets in the order of their bitmask (lift 1, tilt 2, slew 4, extension 8); the first
 * where every released joint accelerates into its range and every joint kept on its stop is
 * pressed onto it. */
static int release_set4(c4 *c, crane_real t, const x4 *x)
{
    const dyn4 *const d = &c->d;
    unsigned held = 0, stopped = 0, cand;
    crane_real Mp[6];
    int j;

    for (j = 0; j < 4; ++j) {
        if (c->mode[j] == CRANE__HELD)
            held |= 1u << j;
        else if (c->mode[j] >= CRANE__STOP_LO)
            stopped |= 1u << j;
    }
    if (!stopped)
        return 0;
    forces4(c, t, x, held, NULL);
    crane__mass4(c->m, &c->b, &d->cf, Mp);
    for (cand = 0; cand < 16u; ++cand) {
        int ok = 1;
        crane_real a[4], r[4];
        /* only stopped joints can be released */
        if (cand & ~stopped)
            continue;
        solve4(c, Mp, d->b, held | (stopped & ~cand), a);
        /* M a, for the reactions of the kept joints */
        for (j = 0; j < 3; ++j)
            r[PLANE[j]] = mp(Mp, j, 0) * a[CRANE_LIFT] + mp(Mp, j, 1) * a[CRANE_TILT] +
                          mp(Mp, j, 2) * a[CRANE_EXTENSION];
        r[CRANE_SLEW] = d->jz * a[CRANE_SLEW];
        for (j = 0; j < 4; ++j) {
            const crane_real inward = c->mode[j] == CRANE__STOP_LO ? 1 : -1;
            if (!in_set(stopped, j))
                continue;
            if (in_set(cand, j))
                ok = ok && inward * a[j] > 0;
            else
                ok = ok && inward * (r[j] - d->b[j]) >= 0;
        }
        if (ok)
            return (int)cand;
    }
    return 0;
}

static void release4(c4 *c, crane_real t, const x4 *x)
{
    const int cand = release_set4(c, t, x);
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
static crane_real release_in_piece4(c4 *c, crane_real t, x4 *x, crane_real h, x4 *y)
{
    crane_real lo = 0, hi = h;
    int k;

    for (k = 0; k < CRANE__RELEASE_BISECTIONS; ++k) {
        const crane_real mid = (lo + hi) / 2;
        rk4_4(c, t, x, mid, y);
        if (release_set4(c, t + mid, y))
            hi = mid;
        else
            lo = mid;
    }
    rk4_4(c, t, x, hi, y);
    *x = *y;
    release4(c, t + hi, x);
    return hi;
}

/* One step of size h from t, cut at impacts and releases (as integrator.c's step, four joints). */
static void step4(c4 *c, crane_real t, x4 *x, crane_real h, crane_real t_end)
{
    crane_real rem = h;
    int piece;

    for (piece = 0; rem > 0; ++piece) {
        unsigned out = 0, upper = 0;
        crane_real tmin = rem;
        x4 x1;
        int i;

        rk4_4(c, t, x, rem, &x1);
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x1.v[Q + i] > hi4(c, i))
                upper |= 1u << i;
            else if (!(x1.v[Q + i] < lo4(c, i)))
                continue;
            out |= 1u << i;
        }
        if (!out) {
            if (piece < CRANE__MAX_PIECES - 1 && any_stopped(c) && release_set4(c, t_end, &x1)) {
                const crane_real hi = release_in_piece4(c, t, x, rem, &x1);
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
                    stop_joint4(c, x, i, (upper >> i) & 1);
            return;
        }
        for (i = 0; i < 4; ++i) {
            if ((out >> i) & 1) {
                const int up = (upper >> i) & 1;
                const crane_real tau = crane__crossing_time(x->v[Q + i], x->v[W + i], x1.v[Q + i],
                                                            x1.v[W + i], rem,
                                                            up ? hi4(c, i) : lo4(c, i), up);
                if (tau < tmin)
                    tmin = tau;
            }
        }
        rk4_4(c, t, x, tmin, &x1);
        *x = x1;
        t += tmin;
        rem -= tmin;
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x->v[Q + i] <= lo4(c, i))
                stop_joint4(c, x, i, 0);
            else if (x->v[Q + i] >= hi4(c, i))
                stop_joint4(c, x, i, 1);
        }
    }
}

/* The substep count of a step of size h from x (docs/model.md, "Hydraulics" and "Four joints"):
 * the valve-driven cylinders' chamber stiffness and, with the extension not held, its friction's
 * rate lambda_e = G_f (M^-1)_ee over the joints that are not held; the larger count. */
static CRANE__NOINLINE long substeps4(c4 *c, const x4 *x, crane_real h)
{
    dyn4 *const d = &c->d;
    long n = 1;
    crane__conf4_at(c->m, x->v[Q], x->v[Q + 1], x->v[Q + 3], &d->cf);
#if CRANE_HYDRAULICS
    if (c->valves) {
        const int driven[4] = {valve(c, 0), valve(c, 1), valve(c, 2), valve(c, 3)};
        crane_real stroke[4] = {0, 0, 0, 0};
        int j;
        for (j = 0; j < 4; ++j)
            if (driven[j]) {
                if (c->mode[j] != CRANE__FREE)
                    stroke[j] = locked_stroke(c, j);
                else
                    (void)ratio(c, &d->cf, j, x->v[Q + j], &stroke[j]);
            }
        n = crane__substeps(c->m, stroke, driven, h);
    }
#endif
    if (c->mode[CRANE_EXTENSION] != CRANE__HELD) {
        crane_real e[4] = {0, 0, 0, 0}, col[4], ne, minv;
        unsigned lk = 1u << CRANE_SLEW;
        int j;
        for (j = 0; j < 4; ++j)
            if (c->mode[j] == CRANE__HELD)
                lk |= 1u << j;
        e[CRANE_EXTENSION] = 1;
        solve4(c, NULL, e, lk, col);
        /* (M^-1)_ee at most 4 / m_ext: the bound that check_work counts (crane_internal.h) */
        minv = col[CRANE_EXTENSION];
        if (minv > 4 / c->m->params->extension_boom.mass)
            minv = 4 / c->m->params->extension_boom.mass;
        ne = crane__ceil(h * crane__extension_friction_slope(c->m->params) * minv /
                         (crane_real)2.5);
        if (ne > (crane_real)n)
            n = (long)ne;
    }
    return n;
}

static void put_sample4(c4 *c, crane_real t, const x4 *x, crane_sample *o)
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
            coord = lo4(c, i);
        else if (c->mode[i] == CRANE__STOP_HI)
            coord = hi4(c, i);
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
                if (s < crane__stroke_min(m, i))
                    s = crane__stroke_min(m, i);
                else if (s > crane__stroke_max(m, i))
                    s = crane__stroke_max(m, i);
                break;
            }
            o->stroke[i] = s;
            o->theta[i] = x->v[Q + i];
            o->omega[i] = x->v[W + i];
        }
        o->flow_a[i] = o->flow_b[i] = o->spool[i] = 0;
#if CRANE_HYDRAULICS
        if (valve(c, i)) {
            const crane_hydraulics *h = crane__circuit(m, i);
            const crane_real y = h->spool_time_constant > 0
                                     ? x->v[H + 3 * i + 2]
                                     : lever4(c, i, t);
            o->p_a[i] = x->v[H + 3 * i];
            o->p_b[i] = x->v[H + 3 * i + 1];
            crane__valve_flows(h, y, o->p_a[i], o->p_b[i], &o->flow_a[i], &o->flow_b[i]);
            o->spool[i] = y;
        } else
#endif
        if (c->mode[i] == CRANE__HELD) {
            o->p_a[i] = o->p_b[i] = 0;
        } else {
            pressures4(c, i, t, &o->p_a[i], &o->p_b[i]);
        }
        o->stop[i] = c->mode[i] == CRANE__STOP_LO   ? lo_flag(c, i)
                     : c->mode[i] == CRANE__STOP_HI ? -lo_flag(c, i)
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

/* Finite, and the chambers and spools in their physical domain (crane_predict's
 * CRANE_E_DIVERGED): an integrator gone unstable shows there first. */
static int finite_state4(const c4 *c, const x4 *x)
{
    int i;
    for (i = 0; i < n_used(c); ++i) {
        /* the pressures, then the spool, of each valve-driven joint from H on (x4_slot) */
        const crane_real lim = (i - H) % 3 == 2 ? 1 : (crane_real)CRANE_PRESSURE_MAX;
        if (i < H ? !crane__finite(x->v[i]) : !crane__in_range(x->v[i], -lim, lim))
            return 0;
    }
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
    c.valves = 0;
    c.lo_is_max = 0;
    for (i = 0; i < N_ALL; ++i)
        x.v[i] = 0;
    for (i = 0; i < 4; ++i) {
        c.cursor[i] = 0;
        c.mode[i] = (signed char)(in->drive[i].mode == CRANE_DRIVE_HOLD ? CRANE__HELD : CRANE__FREE);
        if (CRANE_HYDRAULICS && in->drive[i].mode == CRANE_DRIVE_VALVE) {
            c.valves = (unsigned char)(c.valves | (1u << i));
            x.v[H + 3 * i] = s0->p_a[i];
            x.v[H + 3 * i + 1] = s0->p_b[i];
            x.v[H + 3 * i + 2] = s0->spool[i];
        }
        if (i < 2) {
            crane_real ds;
            if (i == CRANE_LIFT)
                crane__lift_from_stroke(m, s0->stroke[i], &x.v[Q + i], &ds);
            else
                (void)crane__tilt_from_stroke(m, s0->stroke[i], &x.v[Q + i], &ds, NULL, NULL);
            x.v[W + i] = s0->stroke_rate[i] / ds;
            if (!(ds > 0))
                c.lo_is_max = (unsigned char)(c.lo_is_max | (1u << i));
        } else {
            x.v[Q + i] = i == CRANE_SLEW ? s0->slew : s0->extension;
            x.v[W + i] = i == CRANE_SLEW ? s0->slew_rate : s0->extension_rate;
        }
    }

    /* At t = 0: a free joint at a limit whose rate does not point into the range starts on it. */
    for (i = 0; i < 4; ++i) {
        int flag;
        if (c.mode[i] != CRANE__FREE)
            continue;
        if (i < 2) {
            const crane_real s = s0->stroke[i], v = s0->stroke_rate[i];
            if (s <= crane__stroke_min(m, i) && v <= 0)
                flag = -1;
            else if (s >= crane__stroke_max(m, i) && v >= 0)
                flag = 1;
            else
                continue;
        } else {
            if (x.v[Q + i] <= lo4(&c, i) && x.v[W + i] <= 0)
                flag = -1;
            else if (x.v[Q + i] >= hi4(&c, i) && x.v[W + i] >= 0)
                flag = 1;
            else
                continue;
        }
        stop_joint4(&c, &x, i, flag != lo_flag(&c, i));
    }

    *n_written = 0;
    if (!finite_state4(&c, &x))
        return CRANE_E_DIVERGED;
    put_sample4(&c, 0, &x, &out[0]);
    for (k = 0, next = 1; k < n_steps; ++k) {
        const int last = k == n_steps - 1;
        const crane_real t_end = last ? horizon : (crane_real)(k + 1) * dt;
        crane_real t = (crane_real)k * dt;
        int more;

        /* cut at the knots of sampled drives, as crane__integrate */
        do {
            const crane_real t_q = crane__next_knot(in, 4, t, t_end, dt);
            const crane_real h = t_q - t;
            long j, n_sub = 1;
            crane_real sub = h;

            if ((c.valves || c.mode[CRANE_EXTENSION] != CRANE__HELD) && h > 0) {
                n_sub = substeps4(&c, &x, h);
                sub = h / (crane_real)n_sub;
            }
            for (j = 0; j < n_sub; ++j) {
                const int final = j == n_sub - 1;
                const crane_real t_sub = j == 0 ? t : t + (crane_real)j * sub;
                release4(&c, t_sub, &x);
                if (h > 0)
                    step4(&c, t_sub, &x, final ? (j == 0 ? h : t_q - t_sub) : sub,
                          final ? t_q : t_sub + sub);
            }
            more = t_q < t_end; /* an int controls the loop (MISRA 14.1) */
            t = t_q;
        } while (more);
        if (!finite_state4(&c, &x)) {
            *n_written = next;
            return CRANE_E_DIVERGED;
        }
        if (last || (k + 1) % sample_every == 0)
            put_sample4(&c, last ? horizon : (crane_real)(k + 1) * dt, &x, &out[next++]);
    }
    *n_written = next;
    return CRANE_OK;
}
