/* SPDX-License-Identifier: MIT */
/*
 * The integrator of every crane (docs/model.md, "Integration and samples", "End stops", "Four
 * joints", "Hydraulics"): fixed-step RK4 with substeps on (q, qd) of lift, tilt, slew and
 * extension and the chamber pressures and spools of valve-driven actuators, with the end-stop
 * events over the four joints. One pipeline for every model; the model's shape picks the
 * dynamics kernel (dynamics.c): the planar one (the two booms, the extension boom and the load
 * lumped with the outer boom) when the slew and the extension are held, the spatial one
 * otherwise. Both kernels give the same physics; the planar one is cheaper and keeps the two-joint
 * model's results bit for bit.
 *
 * Everything here runs on inputs that crane_predict has already validated.
 */
#include "crane_internal.h"

/* State layout: q[4], qd[4], then with valve-driven actuators joint j's p_a, p_b and spool at
 * H + 3j (the order of crane__chamber_rates's rates); entries of joints that are not valve-driven
 * stay 0. */
enum x_slot { Q = 0, W = 4, H = CRANE__NMECH, N_MECH = CRANE__NMECH, N_ALL = CRANE__NX };

/* What is valid in the dynamics' cache (ctx_t's d): the trig of cf at key_th, its four-bar at the
 * tilt angle key_th[1]. */
enum { CACHE_TRIG = 1, CACHE_TK = 2 };

/* The working storage's parts (crane.h): the state, the dynamics' cache, ROS34PW2's matrix and
 * the context of one prediction, in the caller's crane_work. */
typedef crane__vector xstate;
typedef crane__dyn dyn;
#if CRANE_ROSW
typedef crane__wjac wjac;
#endif
typedef crane_work ctx_t;

static int locked(const ctx_t *c, int j) { return c->mode[j] != CRANE__FREE; }

#if CRANE_ROSW
/* Actuator j's limit valves' modes as crane__limit_rates and crane__chamber_jacobian take them:
 * bits 0 and 1 its chambers' valves open, bits 2 and 3 their vacuum floors held in. */
static unsigned limit_modes(const ctx_t *c, int j)
{
    return (((unsigned)c->open >> (2 * j)) & 3u) | ((((unsigned)c->floor >> (2 * j)) & 3u) << 2);
}
#endif

static int valve(const ctx_t *c, int j) { return (int)((c->lim.valves >> j) & 1u); }

/* The stop flag (actuator terms: -1 stroke_min, +1 stroke_max) at the lower limit of q. */
static int lo_flag(const ctx_t *c, int j) { return ((c->lo_is_max >> j) & 1) != 0 ? 1 : -1; }

/* State entries in use: the pressures and spools only with valves. */
static int n_used(const ctx_t *c) { return c->lim.valves != 0u ? N_ALL : N_MECH; }

/* The joints that can move: the planar kernel's two booms (lift, tilt), else all four. */
static int n_moving(const ctx_t *c) { return c->planar != 0u ? 2 : 4; }

/* dst = src over the state entries in use; the others are never read (a step's end state leaves
 * them unset). A loop over the entries rather than a copy of the whole struct: without valves
 * that is 8 of its 20 entries, and the copies are made a few times a step. gcc would turn the
 * loop into a call of memmove, which newlib's size-optimised build copies byte by byte. */
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("no-tree-loop-distribute-patterns")))
#endif
static void copy_state(const ctx_t *c, xstate *dst, const xstate *src)
{
    int i;
    for (i = 0; i < n_used(c); ++i) {
        dst->v[i] = src->v[i];
    }
}

/* The lower (upper) limit of q of joint j: the angle limits, [slew_min, slew_max], the extension
 * range. Read where needed rather than kept in the context (the caller's crane_work). */
static crane_real lo_q(const ctx_t *c, int j)
{
    if (j < 2) {
        return c->lim.m->theta_min[j];
    }
    return j == CRANE_SLEW ? c->lim.m->params->slew_drive.slew_min : c->lim.m->params->extension_min;
}

static crane_real hi_q(const ctx_t *c, int j)
{
    if (j < 2) {
        return c->lim.m->theta_max[j];
    }
    return j == CRANE_SLEW ? c->lim.m->params->slew_drive.slew_max : c->lim.m->params->extension_max;
}

/* Joint j is in the set js (bit j: lift 1, tilt 2, slew 4, extension 8). Joint sets are masks
 * rather than arrays of flags: RK4 keeps one for its four stages (the stack). */
static int in_set(unsigned js, int j) { return (int)((js >> j) & 1u); }

/* The configuration at x into c->d.cf, from the cache where it holds the same angles; the
 * four-bar only with need_tk. */
static CRANE__ALWAYS_INLINE const crane__conf *configure(ctx_t *c, const xstate *x, int need_tk)
{
    dyn *const d = &c->d;
    crane__conf *const cf = &d->cf;

    if ((c->cache & CACHE_TRIG) == 0 || x->v[Q] != d->key_th[0] || x->v[Q + 1] != d->key_th[1]) {
        /* the four-bar stays valid while the tilt angle does */
        const unsigned keep =
            (c->cache & CACHE_TRIG) != 0 && x->v[Q + 1] == d->key_th[1] ? CACHE_TK : 0;
        /* one sin/cos per joint angle; the absolute outer boom angle by the angle-sum formulas */
        crane__sincos(x->v[Q], &cf->s0, &cf->c0);
        crane__sincos(x->v[Q + 1], &cf->s1, &cf->c1);
        cf->c01 = cf->c0 * cf->c1 - cf->s0 * cf->s1;
        cf->s01 = cf->s0 * cf->c1 + cf->c0 * cf->s1;
        d->key_th[0] = x->v[Q];
        d->key_th[1] = x->v[Q + 1];
        c->cache = (unsigned char)((c->cache & keep) | CACHE_TRIG);
    }
    cf->e = x->v[Q + 3];
    if (need_tk != 0 && (c->cache & CACHE_TK) == 0) {
        crane__tilt_kinematics(c->lim.m, cf->c1, cf->s1, &cf->tk);
        c->cache |= CACHE_TK;
    }
    return cf;
}

/* ds/dq of joint j at the configuration: the lift's from its triangle, the tilt's from the
 * four-bar, the rack's pinion radius for the slew, 1 for the extension. With stroke, the stroke
 * (for the slew and the extension from their coordinate q: r_p (psi - slew_min), e - extension_min). */
static crane_real ratio(ctx_t *c, int j, crane_real q, crane_real *stroke)
{
    const dyn *const d = &c->d;
    crane_real ds = 1, s;

    if (j == CRANE_LIFT) {
        crane__lift_from_angle(c->lim.m, d->cf.c0, d->cf.s0, &s, &ds);
    } else if (j == CRANE_TILT) {
        ds = d->cf.tk.ds;
        s = d->cf.tk.stroke;
    } else {
        if (j == CRANE_SLEW) {
            ds = c->lim.m->params->slew_drive.pinion_radius;
        }
        s = ds * (q - lo_q(c, j));
    }
    if (stroke != NULL) {
        *stroke = s;
    }
    return ds;
}

/* The stroke of a stopped valve-driven actuator: the end of its range that it stopped at (a
 * valve-driven joint is never held). */
static crane_real locked_stroke(const ctx_t *c, int j)
{
    const int flag = c->mode[j] == CRANE__STOP_LO ? lo_flag(c, j) : -lo_flag(c, j);
    crane_real s_min, s_max;

    crane__actuator_range(c->lim.m, j, &s_min, &s_max);
    return flag < 0 ? s_min : s_max;
}

/* Joint j's drive at t (crane__drive_pressures, crane__drive_lever). The lever's interpolation
 * is out of line, one copy for RK4's stages and the samples (the code budget); the pressures'
 * stay inline, since their outputs would otherwise take stack on the deepest path. */
static CRANE__ALWAYS_INLINE void pressures(ctx_t *c, int j, crane_real t, crane_real *p_a,
                                           crane_real *p_b)
{
    crane__drive_pressures(&c->in->drive[j], &c->cursor[j], t, p_a, p_b);
}

#if CRANE_HYDRAULICS
static crane_real lever(ctx_t *c, int j, crane_real t)
{
    return crane__drive_lever(&c->in->drive[j], &c->cursor[j], t);
}

/* The chamber and spool rates at t of valve-driven joint j at stroke s and stroke rate v, written
 * over its pressures and spool in x (which they are read from first): RK4 takes a stage's rates
 * from there, and keeps no array of them (the stack). */
static CRANE__ALWAYS_INLINE void valve_rates(ctx_t *c, crane_real t, xstate *x, int j,
                                             crane_real s, crane_real v)
{
    crane_real r[3];
    int k;

    crane__chamber_rates(c->lim.m, j, lever(c, j, t), s, v, &x->v[H + 3 * j], x->v[H + 3 * j + 2], r);
#if CRANE_ROSW
    if (c->rosw != 0u) {
        crane__limit_rates(c->lim.m, j, s, &x->v[H + 3 * j], limit_modes(c, j), r);
    }
#endif
    for (k = 0; k < 3; ++k) {
        x->v[H + 3 * j + k] = r[k];
    }
}
#endif

/* The kernel's mass matrix at c->d.cf over (lift, tilt, extension), Mp = (M00, M01, M0e, M11,
 * M1e, Mee). */
static CRANE__ALWAYS_INLINE void mass(const ctx_t *c, crane_real Mp[6])
{
    if (c->planar != 0u) {
        crane__mass_planar(c->lim.m, &c->d.cf, Mp);
    } else {
        crane__mass_spatial(c->lim.m, &c->b, &c->d.cf, Mp);
    }
}

/* Fills c->d at (t, x): the configuration, J_z and b = tau - h, with actuator forces only for
 * the joints not in lk (a joint in lk that is stopped needs its own force only to decide its
 * release, which passes lk = the held joints); no dynamics when all four are locked. With rates
 * (then x itself), each valve-driven joint's chamber and spool rates replace its pressures and
 * spool in x, once its force has read them (valve_rates). */
static CRANE__ALWAYS_INLINE void forces(ctx_t *c, crane_real t, const xstate *x, unsigned lk,
                                        xstate *rates)
{
    const crane_model *m = c->lim.m;
    static const crane_real zero[4] = {0, 0, 0, 0};
    dyn *const d = &c->d;
    int j;

    if (lk != 15u) {
        /* the planar kernel needs the four-bar for the side links and a free tilt's ds/dtheta */
        const crane__conf *cf =
            configure(c, x, c->planar == 0u || m->links != 0 || in_set(lk, CRANE_TILT) == 0);
        /* a locked slew's inertia and force are never read */
        d->jz = 1;
        if (c->planar != 0u) {
            crane__id_planar(m, cf, &x->v[W], zero, m->params->gravity, d->b);
            d->b[CRANE_SLEW] = d->b[CRANE_EXTENSION] = 0;
        } else {
            /* the bias h = ID(q, qd, 0) goes into b, negated there (no array of its own) */
            crane__id_spatial(m, &c->b, cf, &x->v[W], zero, m->params->gravity, d->b);
            if (in_set(lk, CRANE_SLEW) == 0) {
                crane_real jdot;
                crane__slew_inertia(m, &c->b, cf, &x->v[W], &d->jz, &jdot, d->b);
                d->b[CRANE_SLEW] = crane__slew_torque(d->jz, jdot, x->v[W + CRANE_SLEW], 0);
            }
        }
        for (j = 0; j < 4; ++j) {
            d->b[j] = -d->b[j];
        }
    }
    /* the actuators of the joints that can move: the planar kernel's slew and extension are held */
    for (j = 0; j < (c->planar != 0u ? 2 : 4); ++j) {
        crane_real stroke = 0, v = 0;
        if (in_set(lk, j) != 0) {
            if (valve(c, j) != 0) {
                stroke = locked_stroke(c, j);
            }
        } else {
            const crane_real ds = ratio(c, j, x->v[Q + j], &stroke);
            crane_real p_a, p_b;
            v = ds * x->v[W + j];
            if (valve(c, j) != 0) {
                p_a = x->v[H + 3 * j];
                p_b = x->v[H + 3 * j + 1];
            } else {
                pressures(c, j, t, &p_a, &p_b);
            }
            d->b[j] += crane__actuator_force(m, j, p_a, p_b, v) * ds;
        }
#if CRANE_HYDRAULICS
        if (rates != NULL && valve(c, j) != 0) {
            valve_rates(c, t, rates, j, stroke, v);
        }
#else
        (void)stroke;
        (void)rates;
#endif
    }
}

/* Index of in-plane joint k (0, 1, 2) in Mp's (lift, tilt, extension) and in the joint arrays. */
static const int PLANE[3] = {CRANE_LIFT, CRANE_TILT, CRANE_EXTENSION};

/* The r-th of the free joints packed by solve. */
static int free_at(unsigned f, int r) { return (int)((f >> (2 * r)) & 3u); }

static crane_real mp(const crane_real Mp[6], int r, int k)
{
    static const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    return Mp[idx[r][k]];
}

/* Solves M a = b over the joints not in lk (the others get 0), M the mass matrix: Mp, or without
 * it the kernel's at c->d.cf. The planar kernel's: the two booms, the free one alone or both by
 * Cramer's rule (the closed form). Out of line like solve_spatial, one frame or the other on the
 * deepest path. */
static CRANE__NOINLINE void solve_planar(const ctx_t *c, const crane_real *Mp,
                                         const crane_real b[4], unsigned lk, crane_real a[4])
{
    crane_real A[6];
    const crane_real *M = Mp;

    /* cppcheck 2.10's whole-program check sizes a with the float build's crane_real and indexes
     * it with the double build's (a false "ctuArrayIndex"; every caller passes crane_real[4]) */
    /* cppcheck-suppress ctuArrayIndex */
    a[CRANE_SLEW] = a[CRANE_EXTENSION] = 0;
    if (in_set(lk, CRANE_LIFT) != 0 && in_set(lk, CRANE_TILT) != 0) {
        a[CRANE_LIFT] = a[CRANE_TILT] = 0;
        return;
    }
    if (Mp == NULL) {
        mass(c, A);
        M = A;
    }
    if (in_set(lk, CRANE_LIFT) != 0) {
        a[CRANE_LIFT] = 0;
        a[CRANE_TILT] = b[CRANE_TILT] / M[3];
    } else if (in_set(lk, CRANE_TILT) != 0) {
        a[CRANE_LIFT] = b[CRANE_LIFT] / M[0];
        a[CRANE_TILT] = 0;
    } else {
        const crane_real det = M[0] * M[3] - M[1] * M[1];
        a[CRANE_LIFT] = (M[3] * b[CRANE_LIFT] - M[1] * b[CRANE_TILT]) / det;
        a[CRANE_TILT] = (M[0] * b[CRANE_TILT] - M[1] * b[CRANE_LIFT]) / det;
    }
}

/* The spatial kernel's: the slew alone (M is block diagonal, J_z = c->d.jz), the free in-plane
 * joints by Gaussian elimination (M is positive definite). The mass matrix is worked here into the
 * last six places of the elimination's own matrix A (6..11, in Mp's order; A's rows are 4 long,
 * the free joints' columns, then b): A is filled row by row from the front, and each place is
 * written only after the last read of the Mp entry it held (so for every set of free joints), so
 * that Mp takes no storage of its own beside the dynamics (the stack). */
static CRANE__NOINLINE void solve_spatial(const ctx_t *c, const crane_real *Mp,
                                          const crane_real b[4], unsigned lk, crane_real a[4])
{
    crane_real A[3 * 4];
    const crane_real *M = Mp;
    /* the free in-plane joints (their indices into PLANE), two bits each (the stack) */
    unsigned f = 0;
    int n = 0, r, k, i;

    /* cppcheck 2.10's whole-program check sizes a with the float build's crane_real and indexes
     * it with the double build's (a false "ctuArrayIndex"; every caller passes crane_real[4]) */
    /* cppcheck-suppress ctuArrayIndex */
    a[CRANE_SLEW] = in_set(lk, CRANE_SLEW) != 0 ? 0 : b[CRANE_SLEW] / c->d.jz;
    for (k = 0; k < 3; ++k) {
        a[PLANE[k]] = 0;
        if (in_set(lk, PLANE[k]) == 0) {
            f |= (unsigned)k << (2 * n);
            ++n;
        }
    }
    if (n == 0) {
        return;
    }
    if (Mp == NULL) {
        crane__mass_spatial(c->lim.m, &c->b, &c->d.cf, &A[6]);
        M = &A[6];
    }
    for (r = 0; r < n; ++r) {
        for (k = 0; k < n; ++k) {
            A[4 * r + k] = mp(M, free_at(f, r), free_at(f, k));
        }
        A[4 * r + n] = b[PLANE[free_at(f, r)]];
    }
    /* (column i below the pivot is not read again: its update is skipped) */
    for (i = 0; i < n; ++i) {
        for (r = i + 1; r < n; ++r) {
            const crane_real l = A[4 * r + i] / A[4 * i + i];
            for (k = i + 1; k <= n; ++k) {
                A[4 * r + k] -= l * A[4 * i + k];
            }
        }
    }
    for (i = n - 1; i >= 0; --i) {
        crane_real s = A[4 * i + n];
        for (k = i + 1; k < n; ++k) {
            s -= A[4 * i + k] * a[PLANE[free_at(f, k)]];
        }
        a[PLANE[free_at(f, i)]] = s / A[4 * i + i];
    }
}

/* M a = b by the kernel's solver. */
static CRANE__ALWAYS_INLINE void solve(const ctx_t *c, const crane_real *Mp, const crane_real b[4],
                                       unsigned lk, crane_real a[4])
{
    if (c->planar != 0u) {
        solve_planar(c, Mp, b, lk, a);
    } else {
        solve_spatial(c, Mp, b, lk, a);
    }
}

/* The joints that are held or stopped. */
static unsigned lock_mask(const ctx_t *c)
{
    unsigned lk = 0;
    int j;
    for (j = 0; j < 4; ++j) {
        if (locked(c, j) != 0) {
            lk |= 1u << j;
        }
    }
    return lk;
}

/* Entries [from, to) of RK4's bookkeeping at stage s, each entry's rate there being xs->v[i + off]:
 * the stage sum ((k1 + 2 k2) + 2 k3) + k4 accumulates in y, and the next stage's state x + cs k is
 * written over xs (the rate is read first). Out of line, a leaf: its loop then takes none of
 * rk4's registers, whose frame is on the stack budget's deepest path. */
static CRANE__NOINLINE void stage(const xstate *x, xstate *xs, xstate *y, int from, int to, int off,
                                  int s, crane_real cs, crane_real h6)
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
        for (i = from; i < to; ++i) {
            y->v[i] = x->v[i] + h6 * (y->v[i] + xs->v[i + off]);
        }
    }
}

/* Classic RK4 of size h from (t, x) into y (y != x): ((k1 + 2 k2) + 2 k3) + k4, its four stages in
 * one loop so that the dynamics are called from one place. There is no array of stage rates: the
 * stage state xs holds them where they are read (the velocities are the positions' rates, solve
 * writes the accelerations over the velocities once the positions are done, the chamber rates
 * replace the pressures), and it is then overwritten by the next stage's state (the stack). */
static void rk4(ctx_t *c, crane_real t, const xstate *x, crane_real h, xstate *y)
{
    const crane_real h2 = h / 2, h6 = h / 6;
    const unsigned lk = lock_mask(c);
    /* the joints that can move: the planar kernel's two booms (the slew and the extension are
     * held, their entries stay those of x), else all four */
    const int nq = n_moving(c);
    xstate xs;
    int s, i;

    copy_state(c, &xs, x);
    for (s = 0; s < 4; ++s) {
        const crane_real ts = s == 0 ? t : s == 3 ? t + h : t + h2, cs = s == 2 ? h : h2;
        forces(c, ts, &xs, lk, &xs);
        stage(x, &xs, y, Q, Q + nq, W - Q, s, cs, h6);
        /* all four locked: zeros, without reading c->d */
        solve(c, NULL, c->d.b, lk, &xs.v[W]);
        stage(x, &xs, y, W, W + nq, 0, s, cs, h6);
#if CRANE_HYDRAULICS
        if (c->lim.valves != 0u) {
            /* the entries of joints that are not valve-driven are 0, and so read as rates */
            stage(x, &xs, y, H, N_ALL, 0, s, cs, h6);
            /* the relief and anti-cavitation valves, implicitly: over the stage's step on the
             * next stage's state, over h on the result */
            crane__limit_valves(&c->lim, s < 2 ? h2 : h, s < 3 ? &xs.v[H] : &y->v[H], 3);
        }
#endif
    }
    for (i = nq; i < 4; ++i) {
        y->v[Q + i] = x->v[Q + i];
        y->v[W + i] = x->v[W + i];
    }
}

/* Plastic impact on joint i (docs/model.md, "End stops", "Four joints"): over the free joints F,
 * qd_F <- qd_F - Minv e_i (qd_i / Minv_ii); M is block diagonal, so a slew impact stops the slew
 * alone and an in-plane impact leaves the slew rate. With the planar kernel's two booms this is
 * qd_j <- qd_j + M_ij / M_jj qd_i. */
static void impact(ctx_t *c, xstate *x, int i)
{
    if (i != CRANE_SLEW) {
        const unsigned lk = (lock_mask(c) & ~(1u << i)) | (1u << CRANE_SLEW);
        (void)configure(c, x, 1);
        if (c->planar != 0u) {
            const int j = 1 - i;
            if (in_set(lk, j) == 0) {
                crane_real Mp[6];
                mass(c, Mp);
                x->v[W + j] += Mp[1] / Mp[j == 0 ? 0 : 3] * x->v[W + i];
            }
        } else {
            crane_real e[4] = {0, 0, 0, 0}, col[4];
            int j;
            e[i] = 1;
            solve(c, NULL, e, lk, col);
            for (j = 0; j < 4; ++j) {
                if (j != i && in_set(lk, j) == 0) {
                    x->v[W + j] -= col[j] * (x->v[W + i] / col[i]);
                }
            }
        }
    }
    x->v[W + i] = 0;
}

/* Puts joint i on its stop: q exactly at the limit, plastic impact, STOPPED. */
static void stop_joint(ctx_t *c, xstate *x, int i, int upper)
{
    x->v[Q + i] = upper != 0 ? hi_q(c, i) : lo_q(c, i);
    impact(c, x, i);
    c->mode[i] = (signed char)(upper != 0 ? CRANE__STOP_HI : CRANE__STOP_LO);
}

/* Which stopped joints leave their stops (docs/model.md, "End stops"): the solution of the
 * contact complementarity problem. Candidate sets are tried in the order of their bitmask (lift
 * 1, tilt 2, slew 4, extension 8); the first where every released joint accelerates into its
 * range and every joint kept on its stop is pushed onto it (its reaction r = M a - b points into
 * the range) is taken. With one stopped joint this is simply "released if its free acceleration
 * points inward"; with more, it keeps a joint from being released when only another's being
 * locked makes it want to leave. */
static int release_set(ctx_t *c, crane_real t, const xstate *x)
{
    const dyn *const d = &c->d;
    unsigned held = 0, stopped = 0, cand;
    crane_real Mp[6];
    int j;

    for (j = 0; j < 4; ++j) {
        if (c->mode[j] == CRANE__HELD) {
            held |= 1u << j;
        } else if (c->mode[j] >= CRANE__STOP_LO) {
            stopped |= 1u << j;
        } else {
            /* free: neither held nor stopped */
        }
    }
    if (stopped == 0u) {
        return 0;
    }
    /* the stopped joints' actuator forces decide their release: only held joints are locked */
    forces(c, t, x, held, NULL);
    mass(c, Mp);
    /* the candidates are subsets of the stopped joints: below 4 with the planar kernel */
    for (cand = 0; cand < (c->planar != 0u ? 4u : 16u); ++cand) {
        int ok = 1;
        crane_real a[4], r[4];
        /* only stopped joints can be released */
        if ((cand & ~stopped) != 0u) {
            continue;
        }
        solve(c, Mp, d->b, held | (stopped & ~cand), a);
        /* M a, for the reactions of the kept joints */
        for (j = 0; j < 3; ++j) {
            r[PLANE[j]] = mp(Mp, j, 0) * a[CRANE_LIFT] + mp(Mp, j, 1) * a[CRANE_TILT] +
                          mp(Mp, j, 2) * a[CRANE_EXTENSION];
        }
        r[CRANE_SLEW] = d->jz * a[CRANE_SLEW];
        for (j = 0; j < 4; ++j) {
            const crane_real inward = c->mode[j] == CRANE__STOP_LO ? 1 : -1;
            if (in_set(stopped, j) == 0) {
                continue;
            }
            if (in_set(cand, j) != 0) {
                ok = ok != 0 && inward * a[j] > 0;
            } else {
                ok = ok != 0 && inward * (r[j] - d->b[j]) >= 0;
            }
        }
        if (ok != 0) {
            return (int)cand;
        }
    }
    /* No candidate consistent (only in a degenerate tie, e.g. an acceleration exactly 0): none. */
    return 0;
}

/* Applies the release rule at (t, x): the released joints become FREE. */
static void release(ctx_t *c, crane_real t, const xstate *x)
{
    const int cand = release_set(c, t, x);
    int j;

    for (j = 0; j < 4; ++j) {
        if (((cand >> j) & 1) != 0) {
            c->mode[j] = CRANE__FREE;
        }
    }
}

static int any_stopped(const ctx_t *c)
{
    return c->mode[0] >= CRANE__STOP_LO || c->mode[1] >= CRANE__STOP_LO ||
           c->mode[2] >= CRANE__STOP_LO || c->mode[3] >= CRANE__STOP_LO;
}

/* Release inside a piece (docs/model.md, "Release inside a step"): the piece from (t, x) over
 * size h ended with a STOPPED joint that the release rule would let go of. Bisects the piece size
 * (lo: an RK4 step of that size ends where the rule releases nothing; hi: where it releases
 * something), advances to hi and releases there; returns hi. y is scratch for the search. */
static crane_real release_in_piece(ctx_t *c, crane_real t, xstate *x, crane_real h, xstate *y)
{
    crane_real lo = 0, hi = h;
    int k;

    for (k = 0; k < CRANE__RELEASE_BISECTIONS; ++k) {
        const crane_real mid = (lo + hi) / 2;
        rk4(c, t, x, mid, y);
        if (release_set(c, t + mid, y) != 0) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    rk4(c, t, x, hi, y);
    copy_state(c, x, y);
    release(c, t + hi, x);
    return hi;
}

/* One step of size h from t_start, cut at end-stop events: impacts and releases. Each event piece
 * normally stops or releases a joint, so two or three pieces are the rule; if the shorter RK4 step
 * lands a rounding error inside the limit the joint is not stopped yet and the next piece finds it
 * again a hair later (as the specification reads). MAX_PIECES only bounds that in pathological
 * cases: the last piece takes the whole rest, puts any joint that overshot on its limit and does
 * no release search. */
static void step(ctx_t *c, crane_real t_start, xstate *x, crane_real h, crane_real t_end)
{
    crane_real t = t_start; /* the current piece's start */
    crane_real rem = h;
    int piece;

    c->release_clear = 0;
    for (piece = 0; rem > 0; ++piece) {
        unsigned out = 0, upper = 0; /* bit i: joint i beyond a limit, the upper one */
        crane_real tmin = rem;
        xstate x1;
        int i;

        rk4(c, t, x, rem, &x1);
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE) {
                continue;
            }
            if (x1.v[Q + i] > hi_q(c, i)) {
                upper |= 1u << i;
            } else if (!(x1.v[Q + i] < lo_q(c, i))) {
                continue;
            } else {
                /* below its lower limit */
            }
            out |= 1u << i;
        }
        if (out == 0u) {
            /* A piece without an impact, which ends at the step's end (its time is taken as t_end,
             * the next step's start time, so that this check and the release at the next step's
             * start are one evaluation): a STOPPED joint may have come free inside it. */
            if (piece < CRANE__MAX_PIECES - 1 && any_stopped(c) != 0) {
                if (release_set(c, t_end, &x1) != 0) {
                    /* x1 is free again: the search's scratch (the stack) */
                    const crane_real hi = release_in_piece(c, t, x, rem, &x1);
                    t += hi;
                    rem -= hi;
                    continue;
                }
                c->release_clear = 1;
            }
            copy_state(c, x, &x1);
            return;
        }
        if (piece == CRANE__MAX_PIECES - 1) {
            copy_state(c, x, &x1);
            for (i = 0; i < 4; ++i) {
                if (((out >> i) & 1u) != 0u) {
                    stop_joint(c, x, i, (upper >> i) & 1);
                }
            }
            return;
        }
        for (i = 0; i < 4; ++i) {
            if (((out >> i) & 1u) != 0u) {
                const int up = (upper >> i) & 1;
                const crane_real tau = crane__crossing_time(x->v[Q + i], x->v[W + i], x1.v[Q + i],
                                                            x1.v[W + i], rem,
                                                            up != 0 ? hi_q(c, i) : lo_q(c, i), up);
                if (tau < tmin) {
                    tmin = tau;
                }
            }
        }
        rk4(c, t, x, tmin, &x1); /* x1 is free again: rk4 cannot write over its x */
        copy_state(c, x, &x1);
        t += tmin;
        rem -= tmin;
        /* In joint order, every free joint at or beyond a limit goes onto it. */
        for (i = 0; i < 4; ++i) {
            if (c->mode[i] != CRANE__FREE) {
                continue;
            }
            if (x->v[Q + i] <= lo_q(c, i)) {
                stop_joint(c, x, i, 0);
            } else if (x->v[Q + i] >= hi_q(c, i)) {
                stop_joint(c, x, i, 1);
            } else {
                /* inside its range: stays free */
            }
        }
    }
}

/* The substep count of a step of size h from x (docs/model.md, "Hydraulics" and "Four joints"):
 * the valve-driven actuators' chamber stiffness (from their strokes; a stopped one's is its
 * stop's) and, with the extension not held, its friction's rate lambda_e = G_f (M^-1)_ee over
 * the joints that are not held; the larger count. Out of line, so that its locals are not in
 * crane__integrate's frame under the step (the stack). */
static CRANE__NOINLINE long substeps(ctx_t *c, const xstate *x, crane_real h)
{
    const int ext = c->mode[CRANE_EXTENSION] != CRANE__HELD;
    long n = 1;

    (void)configure(c, x, ext != 0 || valve(c, CRANE_TILT) != 0);
#if CRANE_HYDRAULICS
    if (c->lim.valves != 0u) {
        const int driven[4] = {valve(c, 0), valve(c, 1), valve(c, 2), valve(c, 3)};
        crane_real stroke[4] = {0, 0, 0, 0};
        int j;
        for (j = 0; j < 4; ++j) {
            if (driven[j] != 0) {
                if (c->mode[j] != CRANE__FREE) {
                    stroke[j] = locked_stroke(c, j);
                } else {
                    (void)ratio(c, j, x->v[Q + j], &stroke[j]);
                }
            }
        }
        n = crane__substeps(c->lim.m, stroke, driven, h, c->lim.coef);
    }
#endif
    if (ext != 0) {
        crane_real e[4] = {0, 0, 0, 0}, col[4], ne, minv;
        unsigned lk = 1u << CRANE_SLEW;
        int j;
        for (j = 0; j < 4; ++j) {
            if (c->mode[j] == CRANE__HELD) {
                lk |= 1u << j;
            }
        }
        e[CRANE_EXTENSION] = 1;
        solve(c, NULL, e, lk, col);
        /* (M^-1)_ee at most 4 / m_ext: the bound that check_work counts (crane_internal.h) */
        minv = col[CRANE_EXTENSION];
        if (minv > 4 / c->lim.m->params->extension_boom.mass) {
            minv = 4 / c->lim.m->params->extension_boom.mass;
        }
        ne = crane__ceil(h * crane__extension_friction_slope(c->lim.m->params) * minv /
                         (crane_real)2.5);
        if (ne > (crane_real)n) {
            n = (long)ne;
        }
    }
    return n;
}

static void put_sample(ctx_t *c, crane_real t, const xstate *x, crane_sample *o)
{
    const crane_model *m = c->lim.m;
    const crane_params *p = m->params;
    /* the four-bar's stroke only, not its dynamics (the side links' mass terms) */
    const crane__conf *cf = configure(c, x, 0);
    crane_real cpsi, spsi;
    crane_vec2 tip;
    int i;

    o->t = t;
    for (i = 0; i < 4; ++i) {
        crane_real coord = x->v[Q + i];
        /* a held joint reports its initial coordinate, a stopped one exactly its limit */
        if (c->mode[i] == CRANE__STOP_LO) {
            coord = lo_q(c, i);
        } else if (c->mode[i] == CRANE__STOP_HI) {
            coord = hi_q(c, i);
        } else {
            /* free or held: x's coordinate (a held joint reports its initial one below) */
        }
        if (i == CRANE_SLEW) {
            o->slew = c->mode[i] == CRANE__HELD ? c->s0->slew : coord;
            o->slew_rate = c->mode[i] == CRANE__HELD ? 0 : x->v[W + i];
        } else if (i == CRANE_EXTENSION) {
            o->extension = c->mode[i] == CRANE__HELD ? c->s0->extension : coord;
            o->extension_rate = c->mode[i] == CRANE__HELD ? 0 : x->v[W + i];
        } else {
            crane_real s;
            switch (c->mode[i]) {
            case CRANE__STOP_LO:
            case CRANE__STOP_HI: s = locked_stroke(c, i); break;
            case CRANE__HELD: s = c->s0->stroke[i]; break;
            default:
                if (i == CRANE_TILT && (c->cache & CACHE_TK) == 0) {
                    /* the stroke alone, from the function that fills tk (kinematics.c) */
                    crane__tilt_from_angle(m, cf->c1, cf->s1, &s, NULL, NULL, NULL);
                } else {
                    (void)ratio(c, i, x->v[Q + i], &s);
                }
                /* The stroke -> angle -> stroke round trip can land a few 1e-16 m outside the
                 * range (docs/model.md, "End stops"): the reported stroke is clamped, the angle
                 * is not. */
                if (s < crane__stroke_min(m, i)) {
                    s = crane__stroke_min(m, i);
                } else if (s > crane__stroke_max(m, i)) {
                    s = crane__stroke_max(m, i);
                } else {
                    /* within its range */
                }
                break;
            }
            o->stroke[i] = s;
            o->theta[i] = x->v[Q + i];
            o->omega[i] = x->v[W + i];
        }
        o->flow_a[i] = o->flow_b[i] = o->spool[i] = 0;
#if CRANE_HYDRAULICS
        if (valve(c, i) != 0) {
            const crane_hydraulics *h = crane__circuit(m, i);
            const crane_real y = h->spool_time_constant > 0 ? x->v[H + 3 * i + 2] : lever(c, i, t);
            o->p_a[i] = x->v[H + 3 * i];
            o->p_b[i] = x->v[H + 3 * i + 1];
            crane__valve_flows(h, y, o->p_a[i], o->p_b[i], &o->flow_a[i], &o->flow_b[i]);
            o->spool[i] = y;
        } else
#endif
        if (c->mode[i] == CRANE__HELD) {
            o->p_a[i] = o->p_b[i] = 0;
        } else {
            pressures(c, i, t, &o->p_a[i], &o->p_b[i]);
        }
        /* Stop flags are in actuator terms (docs/model.md): the tilt's lower angle stop is +1. */
        o->stop[i] = c->mode[i] == CRANE__STOP_LO   ? lo_flag(c, i)
                     : c->mode[i] == CRANE__STOP_HI ? -lo_flag(c, i)
                                                    : 0;
    }
    /* tip = O1 + R(th0) (O2 + R(th1) (mount + (e, 0) + (tip_distance, 0))), then the slew */
    tip = crane__add(p->lift_pivot,
                     crane__rot(cf->c0, cf->s0,
                                crane__add(p->tilt_pivot,
                                           crane__rot(cf->c1, cf->s1,
                                                      crane__add(crane__add(p->extension_mount,
                                                                            crane__v2(o->extension, 0)),
                                                                 crane__v2(p->tip_distance, 0))))));
    if (o->slew == 0) {
        /* a slew at zero (held, as every planar future's is): sin(+-0) = +-0 and cos = 1
         * exactly, without a third sine and cosine per sample */
        spsi = o->slew;
        cpsi = 1;
    } else {
        crane__sincos(o->slew, &spsi, &cpsi);
    }
    o->tip[0] = tip.x * cpsi;
    o->tip[1] = tip.x * spsi;
    o->tip[2] = tip.y;
}

/* Finite, and the chambers and spools in their physical domain (crane_predict's
 * CRANE_E_DIVERGED): an integrator gone unstable shows there first, and finite garbage is never
 * a result. */
static int finite_state(const ctx_t *c, const xstate *x)
{
    /* the joints that can move (held ones keep their validated initial state) */
    const int nq = n_moving(c);
    int i;
    for (i = 0; i < nq; ++i) {
        if (crane__finite(x->v[Q + i]) == 0 || crane__finite(x->v[W + i]) == 0) {
            return 0;
        }
    }
    for (i = H; i < n_used(c); ++i) {
        /* the pressures, then the spool, of each valve-driven joint from H on (x_slot) */
        const crane_real lim = (i - H) % 3 == 2 ? 1 : (crane_real)CRANE_PRESSURE_MAX;
        if (crane__in_range(x->v[i], -lim, lim) == 0) {
            return 0;
        }
    }
    return 1;
}

#if CRANE_ROSW
/* ---- The error-controlled method: ROS34PW2 (docs/model.md, "Integration") ---- */

/* Rang and Angermann's ROS34PW2 (2005): a Rosenbrock-W method of four stages, order 3 with any
 * Jacobian, L-stable, stiffly accurate, with an embedded solution of order 2. In Hairer and
 * Wanner's transformed variables (Solving ODEs II, IV.7 (7.25)):
 *   (I - gamma h J) U_i = gamma h f(t + alpha_i h, x + sum_j a_ij U_j) + gamma sum_j c_ij U_j,
 *   x1 = x + sum_i m_i U_i, error sum_i e_i U_i,
 * from the published gamma, alpha_ij, gamma_ij, b and b^ (a = alpha Gamma^-1, c = -Gamma^-1 off
 * the diagonal, m = b Gamma^-1, e = (b - b^) Gamma^-1; worked in 40 digits). a and c are packed
 * by rows (stage i's from (i - 1) i / 2). The time is a state with a zero Jacobian column, which a
 * W-method allows: f's explicit time dependence (the levers) costs no order. */
static const crane_real ROS_GAMMA = (crane_real)0.43586652150845900;
static const crane_real ROS_ALPHA[4] = {0, (crane_real)0.87173304301691801,
                                       (crane_real)0.73157995778885238, 1};
static const crane_real ROS_A[6] = {2, (crane_real)1.4192173174557647,
                                    (crane_real)-0.25923221167296971, (crane_real)4.1847604823191607,
                                    (crane_real)-0.28519201735549591, (crane_real)2.2942803602790417};
static const crane_real ROS_C[6] = {(crane_real)-4.5885607205580835, (crane_real)-4.1847604823191607,
                                    (crane_real)0.28519201735549591, (crane_real)-6.3681792001283578,
                                    (crane_real)-6.7956209444668362, (crane_real)2.8700986043310561};
static const crane_real ROS_M[4] = {(crane_real)4.1847604823191601, (crane_real)-0.28519201735549587,
                                    (crane_real)2.2942803602790414, 1};
static const crane_real ROS_E[4] = {(crane_real)0.27774994764796811, (crane_real)-1.403239895175999,
                                    (crane_real)1.7726301276675507, (crane_real)0.5};

/* The step control (docs/model.md, "Integration"): the first step, the largest and the smallest,
 * and the factors a step may shrink or grow by. */
static const crane_real ROS_FIRST_STEP = (crane_real)1e-3;
static const crane_real ROS_MAX_STEP = (crane_real)0.1;
static const crane_real ROS_MIN_STEP = (crane_real)1e-7;
static const crane_real ROS_SHRINK = (crane_real)0.2, ROS_GROW = 5, ROS_SAFETY = (crane_real)0.9;
/* A rate's tolerance over its coordinate's, 1/s: a rate held to its coordinate's tolerance per
 * second. The rates' errors bind most steps of a valve-driven future (the booms ringing on the
 * oil spring), and looser ran 300 random valve futures faster (3x: 1.3x, 10x: 1.7x), but the
 * oil spring carries a rate's error into the ringing's phase and so into the chamber pressures:
 * valve-end-stop's pressures 0.29 bar off the converged run at 1, 0.55 at 2, 0.81 at 3 (the
 * target 0.5), and a tighter pressure tolerance does not win it back (3x with a 3.3x tighter
 * one: 0.81 bar); weighted by the oil spring (100 /s, the coordinates held tighter), the stiff
 * corners and random valve futures of the tests miss the targets (docs/model.md, "Error
 * control"). */
static const crane_real ROS_RATE_SCALE = 1;
/* An event this early in a step (as a fraction of it) is looked at again with a step this much
 * shorter. */
static const crane_real ROS_EVENT_FRACTION = (crane_real)0.125;
/* A spool's tolerance (it is dimensionless, in [-1, 1]) */
static const crane_real ROS_SPOOL_TOLERANCE = (crane_real)1e-3;
/* A chamber whose own slope over a step, -h dp'/dp, exceeds this is sampled linearly
 * (dense_sample). Measured against the converged run: at 10, a chamber held at the supply
 * pressure 1.14 -> 0.19 bar and lever-open's samples 0.003 -> 0.021 bar; at 1, moving chambers'
 * samples worse (slew-while-lifting 0.008 -> 0.089 bar); at 100, the held chamber missed. */
static const crane_real STIFF_SAMPLE = 10;


/* Mp's diagonal entry of in-plane joint j (lift, tilt, extension). */
static int mp_diag(int j) { return j == CRANE_LIFT ? 0 : j == CRANE_TILT ? 3 : 5; }

/* f(t, x) into f (f may be x): the coordinates' rates (the joint rates), the accelerations and,
 * with valves, the chamber rates with the limit valves' flows and the spool rates. */
static void rates(ctx_t *c, crane_real t, const xstate *x, xstate *f)
{
    const unsigned lk = lock_mask(c);
    const int nq = n_moving(c);
    int i;

    if (f != x) {
        copy_state(c, f, x);
    }
    forces(c, t, f, lk, f);
    for (i = 0; i < 4; ++i) {
        f->v[Q + i] = i < nq ? f->v[W + i] : 0;
    }
    solve(c, NULL, c->d.b, lk, &f->v[W]);
}

/* Which chambers' limit valves are open at x, f = f(x) under the modes c->open (which this sets):
 * a chamber beyond its setting, or at it, with its free rate (f without its limit valve's flow)
 * pointing beyond; and any chamber beyond its setting by more than the valve's override, where
 * the valve passes more than its nominal flow. A chamber just beyond, by the finite gradient of a
 * valve that was open, whose free rate points back (a boom stopped by an impact, the valve's flow
 * turning) closes now: the valve would close within microseconds (C(V)/G_lim), and open it would
 * hold the chamber on its setting over the whole step. Between steps a chamber crosses a setting
 * only at an event (integrate_rosw), so J's slopes are f's over every step. */
static void limits_open(ctx_t *c, const xstate *x, const xstate *f)
{
    const unsigned char was = c->open;
    int k;

    c->open = 0;
#if CRANE_HYDRAULICS
    for (k = 0; k < 8; ++k) {
        const int j = k >> 1;
        if (valve(c, j) != 0) {
            const crane_real *p = &x->v[H + 3 * j];
            crane_real set, rate = f->v[H + 3 * j + (k & 1)];
            const int side = crane__limit_side(c->lim.m, j, p[k & 1], &set);
            const int cav = set == crane__circuit(c->lim.m, j)->cavitation_pressure;
            const int near = crane__fabs(p[k & 1] - set) <= CRANE__LIMIT_OVERRIDE;
            if (((was >> k) & 1u) != 0u && side != 0 && near != 0) {
                crane_real stroke = 0, lim[2] = {0, 0};
                if (locked(c, j) != 0) {
                    stroke = locked_stroke(c, j);
                } else {
                    (void)configure(c, x, 1);
                    (void)ratio(c, j, x->v[Q + j], &stroke);
                }
                crane__limit_rates(c->lim.m, j, stroke, p, 1u << (k & 1), lim);
                rate -= lim[k & 1];
            }
            if ((side != 0 || p[k & 1] == set) &&
                ((cav != 0 ? rate < 0 : rate > 0) || near == 0)) {
                c->open = (unsigned char)(c->open | (1u << k));
            }
        }
    }
#else
    (void)was;
    (void)x;
    (void)f;
    (void)k;
#endif
}

/* J at (t, x) (the W-method's matrix), right after rates at (t, x) (which left J_z in c->d). */
static CRANE__NOINLINE void w_matrix(ctx_t *c, crane_real t, const xstate *x, wjac *J)
{
    const crane_model *m = c->lim.m;
    const int nq = n_moving(c);
    int j, k;

    (void)configure(c, x, 1);
    mass(c, J->mp);
    J->jz = c->d.jz;
    for (j = 0; j < 4; ++j) {
        crane_real stroke = 0;
        J->ds[j] = 0;
        J->fr[j] = 0;
        J->spool[j] = 0;
        J->area[j][0] = 0;
        J->area[j][1] = 0;
        for (k = 0; k < 8; ++k) {
            J->ch[j][k] = 0;
        }
        if (j >= nq) {
            continue;
        }
        if (locked(c, j) == 0) {
            const crane_real ds = ratio(c, j, x->v[Q + j], &stroke);
            const crane_real slope =
                crane__friction_slope(crane__actuator_friction(m, j), ds * x->v[W + j]);
            J->ds[j] = ds;
            /* a falling friction (Stribeck) is left out: it would make the system singular
             * for long steps, and the W-method keeps its order without it */
            J->fr[j] = slope > 0 ? ds * ds * slope : 0;
        } else if (valve(c, j) != 0) {
            stroke = locked_stroke(c, j);
        } else {
            continue;
        }
#if CRANE_HYDRAULICS
        if (valve(c, j) != 0) {
            const crane_hydraulics *h = crane__circuit(m, j);
            const crane_real tau = h->spool_time_constant;
            crane_real a_a, a_b;
            crane__chamber_jacobian(m, j, tau > 0 ? x->v[H + 3 * j + 2] : lever(c, j, t), stroke,
                                    &x->v[H + 3 * j], limit_modes(c, j), J->ch[j]);
            crane__actuator_areas(m, j, &a_a, &a_b);
            J->area[j][0] = a_a * J->ds[j];
            J->area[j][1] = -a_b * J->ds[j];
            J->spool[j] = tau > 0 ? 1 / tau : 0;
        }
#else
        (void)t;
#endif
    }
}

/* Solves (I - gh J) k = r in place (r becomes k). Each valve-driven actuator's chambers are
 * solved in terms of its joint rate (2 x 2, closed form), which leaves the joint rates' system
 * (M + gh D - gh G W) k_w = M r_w + gh G u: the mass matrix with the friction's and the oil
 * spring's terms on its diagonal (each actuator acts on its own joint), solved by the kernel's
 * solver; then the coordinates k_q = r_q + gh k_w and the chambers. */
static CRANE__NOINLINE void wsolve(ctx_t *c, const wjac *J, crane_real gh, xstate *r)
{
    const unsigned lk = lock_mask(c);
    crane_real Mp[6], b[4], a[4], w[4][2];
    int j, k;

    for (k = 0; k < 3; ++k) {
        b[PLANE[k]] = mp(J->mp, k, 0) * r->v[W + CRANE_LIFT] + mp(J->mp, k, 1) * r->v[W + CRANE_TILT] +
                      mp(J->mp, k, 2) * r->v[W + CRANE_EXTENSION];
    }
    b[CRANE_SLEW] = J->jz * r->v[W + CRANE_SLEW];
    for (k = 0; k < 6; ++k) {
        Mp[k] = J->mp[k];
    }
    c->d.jz = J->jz;
    for (j = 0; j < 4; ++j) {
        crane_real diag = gh * J->fr[j];
        w[j][0] = 0;
        w[j][1] = 0;
        if (valve(c, j) != 0) {
            const crane_real *P = J->ch[j];
            crane_real *u = &r->v[H + 3 * j];
            const crane_real b11 = 1 - gh * P[0], b12 = -gh * P[1], b21 = -gh * P[2];
            const crane_real b22 = 1 - gh * P[3], det = b11 * b22 - b12 * b21;
            /* the spool's row first (it depends on nothing else), its gain into the chambers' */
            const crane_real ky = u[2] / (1 + gh * J->spool[j]);
            const crane_real ra = u[0] + gh * P[6] * ky, rb = u[1] + gh * P[7] * ky;
            const crane_real ua = (b22 * ra - b12 * rb) / det;
            const crane_real ub = (b11 * rb - b21 * ra) / det;
            const crane_real ca = gh * J->ds[j] * P[4], cb = gh * J->ds[j] * P[5];
            u[0] = ua;
            u[1] = ub;
            u[2] = ky;
            w[j][0] = (b22 * ca - b12 * cb) / det;
            w[j][1] = (b11 * cb - b21 * ca) / det;
            diag -= gh * (J->area[j][0] * w[j][0] + J->area[j][1] * w[j][1]);
            b[j] += gh * (J->area[j][0] * ua + J->area[j][1] * ub);
        }
        if (j == CRANE_SLEW) {
            c->d.jz += diag;
        } else {
            Mp[mp_diag(j)] += diag;
        }
    }
    solve(c, Mp, b, lk, a);
    for (j = 0; j < 4; ++j) {
        r->v[W + j] = a[j];
        r->v[Q + j] += gh * a[j];
        if (valve(c, j) != 0) {
            r->v[H + 3 * j] += w[j][0] * a[j];
            r->v[H + 3 * j + 1] += w[j][1] * a[j];
        }
    }
}

/* Entry i's tolerance: tip metres over the reach for an angle, metres for the extension (and the
 * same per second for their rates), Pa for a pressure. */
static crane_real tolerance(const ctx_t *c, int i)
{
    if (i < H) {
        const crane_real tol = (i & 3) == CRANE_EXTENSION ? c->tol_tip : c->tol_q;
        return i < W ? tol : tol * ROS_RATE_SCALE;
    }
    return (i - H) % 3 == 2 ? ROS_SPOOL_TOLERANCE : c->tol_p;
}

/* Which chambers' vacuum floors J holds over the step from x, f = f(x) under the limit valves'
 * modes: an open anti-cavitation valve's chamber below the floor's knee, or at it with its rate
 * pointing below. Between steps a chamber crosses the knee only at an event (chamber_crossing),
 * so J's slopes are f's over every step. */
static void floors_in(ctx_t *c, const xstate *x, const xstate *f)
{
    int k;

    c->floor = 0;
#if CRANE_HYDRAULICS
    for (k = 0; k < 8; ++k) {
        if (((c->open >> k) & 1u) != 0u) {
            const int j = k >> 1;
            const crane_real p = x->v[H + 3 * j + (k & 1)];
            const crane_real knee = crane__floor_knee(c->lim.m, j);
            if (p < knee || (p == knee && f->v[H + 3 * j + (k & 1)] < 0)) {
                c->floor = (unsigned char)(c->floor | (1u << k));
            }
        }
    }
#else
    (void)x;
    (void)f;
    (void)k;
#endif
}

/* A step's start at (t, x): the limit valves' modes (limits_open, from f = f(t, x) as the last
 * step left it, or computed here if valid is 0), f under them and J (the last rates were at x,
 * leaving its J_z in c->d). */
static void step_start(ctx_t *c, crane_real t, const xstate *x, xstate *f, int valid, wjac *J)
{
    const unsigned char open = c->open, floor = c->floor;

    if (valid == 0) {
        rates(c, t, x, f);
    }
    limits_open(c, x, f);
    if (c->open != open) {
        rates(c, t, x, f); /* under the new modes */
    }
    floors_in(c, x, f);
    if (c->floor != floor) {
        rates(c, t, x, f); /* under the new floors */
    }
    if (c->dopri == 0u) {
        w_matrix(c, t, x, J);
    }
}

/* One ROS34PW2 step of size h from (t, x), f0 = f(t, x), into y; returns the error's largest
 * ratio to its tolerance (NaN if the step failed). The stages' sums run a stage at a time over
 * the entries (each entry's terms in the same order as the formulas above: the same arithmetic as
 * an entry at a time, in a loop the compiler keeps simple); c->fs is free under this method and
 * holds a stage's sum of earlier stages. */
static CRANE__NOINLINE crane_real ros_step(ctx_t *c, crane_real t, const xstate *x,
                                           const xstate *f0, const wjac *J, crane_real h,
                                           xstate *y)
{
    const crane_real gh = ROS_GAMMA * h;
    const int n = n_used(c);
    /* the stages u[s], each solved where it was formed (no copies between them) */
    xstate *const u = c->stage;
    xstate *const sum = &c->fs;
    crane_real err = 0;
    int s, i, k;

    /* the first stage: gamma h f0 plus gamma times its empty sum of earlier stages (0, added as
     * the formula adds it) */
    for (i = 0; i < n; ++i) {
        u[0].v[i] = gh * f0->v[i] + ROS_GAMMA * (crane_real)0;
    }
    wsolve(c, J, gh, &u[0]);
    for (s = 1; s < 4; ++s) {
        const int row = (s - 1) * s / 2;
        xstate *const us = &u[s];
        /* the stage's point x + sum_k a_sk U_k, and f there in place */
        for (i = 0; i < n; ++i) {
            us->v[i] = x->v[i] + ROS_A[row] * u[0].v[i];
        }
        for (k = 1; k < s; ++k) {
            const crane_real a = ROS_A[row + k];
            for (i = 0; i < n; ++i) {
                us->v[i] += a * u[k].v[i];
            }
        }
        rates(c, t + ROS_ALPHA[s] * h, us, us);
        /* gamma h f + gamma sum_k c_sk U_k (the sum from 0, as the formula's) */
        for (i = 0; i < n; ++i) {
            sum->v[i] = (crane_real)0 + ROS_C[row] * u[0].v[i];
        }
        for (k = 1; k < s; ++k) {
            const crane_real cc = ROS_C[row + k];
            for (i = 0; i < n; ++i) {
                sum->v[i] += cc * u[k].v[i];
            }
        }
        for (i = 0; i < n; ++i) {
            us->v[i] = gh * us->v[i] + ROS_GAMMA * sum->v[i];
        }
        wsolve(c, J, gh, us);
    }
    for (i = 0; i < n; ++i) {
        const crane_real e = ROS_E[0] * u[0].v[i] + ROS_E[1] * u[1].v[i] + ROS_E[2] * u[2].v[i] +
                             ROS_E[3] * u[3].v[i];
        const crane_real r = crane__fabs(e) / tolerance(c, i);
        y->v[i] = x->v[i] + (ROS_M[0] * u[0].v[i] + ROS_M[1] * u[1].v[i] + ROS_M[2] * u[2].v[i] +
                             ROS_M[3] * u[3].v[i]);
        if (!(r <= err) && err == err) {
            err = r; /* the largest; a NaN, once met, stays (a later entry must not hide it) */
        }
    }
    return err;
}

/* Dormand and Prince's explicit pair DOPRI5(4) (Hairer, Norsett and Wanner, Solving ODEs I,
 * II.5, Table 5.2): seven stages, the seventh at the step's end (FSAL: f(t + h, x1)); the solution
 * of order 5, the error of the embedded order 4. Rows of the stages' a by stage, b the solution's
 * weights, d = b - b^ the error's. */
static const crane_real DP_C[7] = {0, (crane_real)0.2, (crane_real)0.3, (crane_real)0.8,
                                   (crane_real)(8.0 / 9.0), 1, 1};
static const crane_real DP_A[21] = {
    (crane_real)0.2,
    (crane_real)(3.0 / 40.0), (crane_real)(9.0 / 40.0),
    (crane_real)(44.0 / 45.0), (crane_real)(-56.0 / 15.0), (crane_real)(32.0 / 9.0),
    (crane_real)(19372.0 / 6561.0), (crane_real)(-25360.0 / 2187.0), (crane_real)(64448.0 / 6561.0),
    (crane_real)(-212.0 / 729.0),
    (crane_real)(9017.0 / 3168.0), (crane_real)(-355.0 / 33.0), (crane_real)(46732.0 / 5247.0),
    (crane_real)(49.0 / 176.0), (crane_real)(-5103.0 / 18656.0),
    (crane_real)(35.0 / 384.0), 0, (crane_real)(500.0 / 1113.0), (crane_real)(125.0 / 192.0),
    (crane_real)(-2187.0 / 6784.0), (crane_real)(11.0 / 84.0)};
static const crane_real DP_D[7] = {
    (crane_real)(35.0 / 384.0 - 5179.0 / 57600.0), 0,
    (crane_real)(500.0 / 1113.0 - 7571.0 / 16695.0), (crane_real)(125.0 / 192.0 - 393.0 / 640.0),
    (crane_real)(-2187.0 / 6784.0 + 92097.0 / 339200.0), (crane_real)(11.0 / 84.0 - 187.0 / 2100.0),
    (crane_real)(-1.0 / 40.0)};

/* Its dense output of order 4 (Hairer, Norsett and Wanner I, II.6; their DOPRI5 code's
 * CONTD5): x(t + s h) = x0 + s (dx + (1 - s) (b + s (c + (1 - s) h sum_i DP_DENSE_i k_i))) with
 * dx = x1 - x0, b = h k1 - dx, c = dx - h k7 - b. */
static const crane_real DP_DENSE[7] = {
    (crane_real)(-12715105075.0 / 11282082432.0), 0,
    (crane_real)(87487479700.0 / 32700410799.0), (crane_real)(-10690763975.0 / 1880347072.0),
    (crane_real)(701980252875.0 / 199316789632.0), (crane_real)(-1453857185.0 / 822651844.0),
    (crane_real)(69997945.0 / 29380423.0)};

/* One DOPRI5(4) step of size h from (t, x), f0 = f(t, x), into y with fy = f(t + h, y); returns
 * the error's largest ratio to its tolerance (NaN if the step failed). Futures without valve
 * drives only: the mechanical entries. */
static CRANE__NOINLINE crane_real dp_step(ctx_t *c, crane_real t, const xstate *x, const xstate *f0,
                                          crane_real h, xstate *y, xstate *fy)
{
    crane_real (*const k)[N_MECH] = c->work.dp.k, err = 0;
    int s, i, m;

    for (i = 0; i < N_MECH; ++i) {
        k[0][i] = f0->v[i];
    }
    for (s = 1; s < 7; ++s) {
        const int row = (s - 1) * s / 2;
        for (i = 0; i < N_MECH; ++i) {
            crane_real v = 0;
            for (m = 0; m < s; ++m) {
                v += DP_A[row + m] * k[m][i];
            }
            fy->v[i] = x->v[i] + h * v;
        }
        rates(c, t + DP_C[s] * h, fy, fy);
        if (s < 6) {
            for (i = 0; i < N_MECH; ++i) {
                k[s][i] = fy->v[i];
            }
        }
    }
    for (i = 0; i < N_MECH; ++i) {
        crane_real v = 0, e = 0, r;
        for (m = 0; m < 6; ++m) {
            v += DP_A[15 + m] * k[m][i];
            e += DP_D[m] * k[m][i];
        }
        e += DP_D[6] * fy->v[i];
        y->v[i] = x->v[i] + h * v;
        r = crane__fabs(h * e) / tolerance(c, i);
        if (!(r <= err) && err == err) {
            err = r; /* the largest; a NaN, once met, stays (a later entry must not hide it) */
        }
    }
    return err;
}

/* The explicit pair's friction reversals: the largest fraction (<= 1) of the accepted step from x
 * to x1 that keeps every free joint whose rate changes sign within its actuator's Stribeck
 * velocity of speed change (ds/dq at x). The friction law turns over within that band; a step
 * that jumps across it integrates the turn with a polynomial, which the order-4 estimate does not
 * see (docs/model.md, "the explicit pair"). */
static crane_real reversal_fraction(ctx_t *c, const xstate *x, const xstate *x1)
{
    crane_real frac = 1;
    int i, conf = 0;

    for (i = 0; i < n_moving(c); ++i) {
        const crane_real w0 = x->v[W + i], w1 = x1->v[W + i];
        if (locked(c, i) == 0 && ((w0 < 0 && w1 > 0) || (w0 > 0 && w1 < 0))) {
            crane_real dv, vs;
            if (conf == 0) {
                (void)configure(c, x, 1);
                conf = 1;
            }
            dv = crane__fabs(ratio(c, i, x->v[Q + i], NULL) * (w1 - w0));
            vs = crane__actuator_friction(c->lim.m, i)->stribeck_velocity;
            if (dv > vs && vs / dv < frac) {
                frac = vs / dv;
            }
        }
    }
    return frac;
}

/* The step of the method in use: DOPRI5(4) (fy its f at the end) or ROS34PW2 (fy untouched). */
static crane_real adaptive_step(ctx_t *c, crane_real t, const xstate *x, const xstate *f0,
                                const wjac *J, crane_real h, xstate *y, xstate *fy)
{
    if (c->dopri != 0u) {
        return dp_step(c, t, x, f0, h, y, fy);
    }
    return ros_step(c, t, x, f0, J, h, y);
}

/* A proposed step rounded down onto the grid m 2^e, m in {16, 17, ..., 31} / 32 (steps 3-6 %
 * apart), by exact operations (frexp, a product by 32, floor, ldexp): an error ratio that two
 * implementations compute a few ulps apart then proposes the same step (almost always), and the
 * C core and the twin take the same steps (docs/model.md, "Integration"). */
static crane_real on_grid(crane_real h)
{
    int e;
    const crane_real m = crane__frexp(h, &e);
    return crane__ldexp(crane__floor(m * 32) / 32, e);
}

/* The step size's factor from an accepted or rejected step's error ratio: err^(-1/(p + 1)) with
 * the estimate's order p (3 for ROS34PW2's embedded order 2, 5 for DOPRI5's order 4). */
static crane_real error_root(const ctx_t *c, crane_real err)
{
    return c->dopri != 0u ? crane__pow(err, (crane_real)0.2) : crane__cbrt(err);
}

/* Every rate in use is finite. */
static int finite_rates(const ctx_t *c, const xstate *f)
{
    int i, ok = 1;

    for (i = 0; i < n_used(c); ++i) {
        if (crane__finite(f->v[i]) == 0) {
            ok = 0;
        }
    }
    return ok;
}

/* The spools of a step's end back into [-1, 1]: the spool's lag cannot take it beyond the lever,
 * but the step's rounding and its error (within the tolerance) can, by a hair. */
static void spools_in_range(const ctx_t *c, xstate *x)
{
    int j;

    for (j = 0; j < 4; ++j) {
        if (valve(c, j) != 0) {
            crane_real *y = &x->v[H + 3 * j + 2];
            if (*y > 1) {
                *y = 1;
            } else if (*y < -1) {
                *y = -1;
            } else {
                /* in range */
            }
        }
    }
}

/* The explicit pair's dense output over the step from x0 to x1 of size h (f1 its end's rates,
 * its k7): per entry b = h k1 - dx, c = dx - h k7 - b and h sum_i DP_DENSE_i k_i (dx = x1 - x0),
 * once a step for all its samples. */
static void dense_coefficients(ctx_t *c, const xstate *x0, const xstate *x1, const xstate *f1,
                               crane_real h)
{
    int i, m;

    for (i = 0; i < N_MECH; ++i) {
        const crane_real dx = x1->v[i] - x0->v[i], b = h * c->work.dp.k[0][i] - dx;
        crane_real d = 0;
        for (m = 0; m < 6; ++m) {
            d += DP_DENSE[m] * c->work.dp.k[m][i];
        }
        d += DP_DENSE[6] * f1->v[i];
        c->work.dp.d[0][i] = b;
        c->work.dp.d[1][i] = dx - h * f1->v[i] - b;
        c->work.dp.d[2][i] = h * d;
    }
}

/* Entry i of the sample at th = (ts - t) / h in the step from (t, x0) to x1 of size h: for
 * ROS34PW2 the cubic Hermite interpolant from its values and rates at both ends (dense output,
 * order 3 like the step), for the explicit pair its own of order 4. */
static crane_real dense_entry(const ctx_t *c, int i, crane_real th, const xstate *x0,
                              const xstate *f0, const xstate *x1, const xstate *f1, crane_real h)
{
    if (c->dopri != 0u) {
        /* the explicit pair's own dense output (order 4, from the step's stages) */
        return x0->v[i] +
               th * ((x1->v[i] - x0->v[i]) +
                     (1 - th) * (c->work.dp.d[0][i] + th * (c->work.dp.d[1][i] + (1 - th) * c->work.dp.d[2][i])));
    }
    return (1 - th) * x0->v[i] + th * x1->v[i] +
           th * (th - 1) *
               ((1 - 2 * th) * (x1->v[i] - x0->v[i]) + (th - 1) * h * f0->v[i] + th * h * f1->v[i]);
}

/* The sample at ts in [t, t + h) of the step from (t, x0) to x1 (dense_entry), interpolating only
 * what a sample reads: a held or stopped joint stays exactly where it is (interpolated, rounding
 * would move it off its stop by an ulp), and only the valve-driven actuators' chambers and spools
 * are read (put_sample). */
static CRANE__NOINLINE void dense_sample(ctx_t *c, crane_real t, const xstate *x0,
                                         const xstate *f0, const xstate *x1, const xstate *f1,
                                         crane_real h, crane_real ts, crane_sample *o)
{
    const crane_real th = (ts - t) / h;
    xstate xs;
    int j;

    for (j = 0; j < 4; ++j) {
        if (locked(c, j) != 0) {
            xs.v[Q + j] = x0->v[Q + j];
            xs.v[W + j] = x0->v[W + j];
        } else {
            /* between its stops: the cubic of a joint just released, accelerating away from its
             * stop, first leaves it outwards by up to 1e-12 rad */
            const crane_real q = dense_entry(c, Q + j, th, x0, f0, x1, f1, h);
            const crane_real lo = lo_q(c, j), hi = hi_q(c, j);
            xs.v[W + j] = dense_entry(c, W + j, th, x0, f0, x1, f1, h);
            xs.v[Q + j] = q < lo ? lo : (q > hi ? hi : q);
        }
    }
    /* the valve-driven actuators' chambers and spools (the explicit pair has none) */
    if (c->dopri == 0u && c->lim.valves != 0u) {
        const crane_real lim = -STIFF_SAMPLE / h;
        for (j = 0; j < 4; ++j) {
            if (valve(c, j) != 0) {
                const unsigned open = ((unsigned)c->open >> (2 * j)) & 3u;
                const int k = H + 3 * j;
                crane_real y;
                int side;
                for (side = 0; side < 2; ++side) {
                    /* a chamber that relaxes within a tenth of the step (its own slope
                     * -h dp'/dp over STIFF_SAMPLE; an open limit valve's always) sits on its
                     * quasi-steady path at both ends: interpolated linearly. The cubic through
                     * its end rates would carry the end's departure from that path, within the
                     * tolerance, times the slope: a chamber held at the supply pressure swung by
                     * a bar between two samples of an 82-ms step. */
                    if (((open >> side) & 1u) != 0u || c->work.J.ch[j][side * 3] < lim) {
                        xs.v[k + side] = (1 - th) * x0->v[k + side] + th * x1->v[k + side];
                    } else {
                        xs.v[k + side] = dense_entry(c, k + side, th, x0, f0, x1, f1, h);
                    }
                }
                /* the spool in [-1, 1] (the cubic can pass a clamped end) */
                y = dense_entry(c, k + 2, th, x0, f0, x1, f1, h);
                xs.v[k + 2] = y > 1 ? 1 : (y < -1 ? -1 : y);
            }
        }
    }
    put_sample(c, ts, &xs, o);
}


/* The first free joint (by crossing time, then joint order) that the step from x to x1 of size h
 * takes beyond a limit, and the crossing time; -1 if none. */
static int first_crossing(const ctx_t *c, const xstate *x, const xstate *x1, crane_real h,
                          crane_real *tau, int *upper)
{
    int i, first = -1;

    for (i = 0; i < 4; ++i) {
        int up;
        crane_real ti;
        if (c->mode[i] != CRANE__FREE) {
            continue;
        }
        if (x1->v[Q + i] > hi_q(c, i)) {
            up = 1;
        } else if (x1->v[Q + i] < lo_q(c, i)) {
            up = 0;
        } else {
            continue;
        }
        ti = crane__crossing_time(x->v[Q + i], x->v[W + i], x1->v[Q + i], x1->v[W + i], h,
                                  up != 0 ? hi_q(c, i) : lo_q(c, i), up);
        if (first < 0 || ti < *tau) {
            first = i;
            *tau = ti;
            *upper = up;
        }
    }
    return first;
}

/* The first chamber (by crossing time) whose limit valve the step from x to x1 of size h opens
 * or closes against c->open, or whose vacuum floor's knee it crosses against c->floor, and the
 * crossing time (the pressure's linear interpolation on the step; *tau is only lowered); its index
 * H + 3j + side, or -1, and *at the setting or the knee crossed. A crossing at the step's start
 * (a chamber exactly at its setting or knee) is none: the step is taken as it is. */
static int chamber_crossing(const ctx_t *c, const xstate *x, const xstate *x1, crane_real h,
                            crane_real *tau, crane_real *at)
{
    int k, first = -1;

#if CRANE_HYDRAULICS
    for (k = 0; k < 8; ++k) {
        if (valve(c, k >> 1) != 0) {
            const int i = H + 3 * (k >> 1) + (k & 1);
            const int open = (c->open >> k) & 1;
            const crane_real knee = crane__floor_knee(c->lim.m, k >> 1);
            crane_real set, tk;
            const int side = crane__limit_side(c->lim.m, k >> 1, x1->v[i], &set);
            if (x1->v[i] == x->v[i]) {
                continue;
            }
            if ((open != 0) != (side != 0)) {
                tk = h * ((x->v[i] - set) / (x->v[i] - x1->v[i]));
                if (tk > 0 && tk < *tau) {
                    *tau = tk;
                    *at = set;
                    first = i;
                }
            }
            if (open != 0 && ((c->floor >> k) & 1u) != (x1->v[i] < knee ? 1u : 0u)) {
                tk = h * ((x->v[i] - knee) / (x->v[i] - x1->v[i]));
                if (tk > 0 && tk < *tau) {
                    *tau = tk;
                    *at = knee;
                    first = i;
                }
            }
        }
    }
#else
    (void)c;
    (void)x;
    (void)x1;
    (void)h;
    (void)tau;
    (void)at;
    (void)k;
#endif
    return first;
}

/* The prediction with ROS34PW2 from x at t = 0 (its sample written): adaptive steps, samples at
 * the kept multiples of dt by dense output, the end-stop events located in the step. */
static CRANE__NOINLINE crane_status integrate_rosw(ctx_t *c, xstate *x, crane_real horizon,
                                                   crane_real dt, long n_steps, long sample_every,
                                                   crane_sample *out, size_t *n_written)
{
    const long cap = crane__attempt_cap(horizon) + crane__knot_count(c->in, horizon);
    xstate *const f0 = &c->f0, *const x1 = &c->x1, *const f1 = &c->f1, *const fs = &c->fs;
    wjac *const J = &c->work.J;
    crane_real t = 0, h = dt < ROS_FIRST_STEP ? dt : ROS_FIRST_STEP, grow = ROS_GROW;
    long attempts = 0, kept = sample_every;
    size_t next = 1;
    int more = 1;

    release(c, 0, x);
    c->open = 0;
    c->floor = 0;
    step_start(c, 0, x, f0, 0, J);
    /* an int controls the loop (MISRA 14.1): 0 once the step that ends at the horizon is taken */
    while (more != 0) {
        crane_real hs = h < ROS_MAX_STEP ? h : ROS_MAX_STEP, err, tau = 0, at = 0;
        int last = 0, first, chamber, upper = 0, changed = 0, i;

        if (hs >= horizon - t) {
            hs = horizon - t;
            last = 1;
        }
        {
            /* the explicit pair's steps end at a sampled drive's knot: its estimate misjudges a
             * kink inside a step. ROS34PW2's end at a pressure drive's knot, and at a lever's
             * only where its stages would miss what the lever does inside the step (the drives'
             * rule): a smooth dense lever log does not make every step as short as its samples'
             * spacing, and a lever pulse between two stages is not stepped over unseen. */
            const crane_real t_end = last != 0 ? horizon : t + hs;
            const crane_real knot =
                c->dopri != 0u ? crane__next_knot(c->in, 4, t, t_end, hs)
                               : crane__rosw_step_end(c->lim.m, c->in, t, t_end, hs, ROS_SPOOL_TOLERANCE);
            if (knot < t_end) {
                hs = knot - t;
                last = 0;
            }
        }
        ++attempts;
        if (attempts > cap) {
            *n_written = next;
            return CRANE_E_TOLERANCE;
        }
        err = adaptive_step(c, t, x, f0, J, hs, x1, fs);
        if (!(err <= 1)) {
            if (hs <= ROS_MIN_STEP) {
                /* a stage that is not finite even at the smallest step: the model diverged */
                *n_written = next;
                return err == err ? CRANE_E_TOLERANCE : CRANE_E_DIVERGED;
            }
            grow = 1;
            h = err == err ? ROS_SAFETY / error_root(c, err) : ROS_SHRINK;
            h = on_grid(hs * (h > ROS_SHRINK ? h : ROS_SHRINK));
            if (h < ROS_MIN_STEP) {
                h = ROS_MIN_STEP;
            }
            continue;
        }
        if (c->dopri != 0u && hs > ROS_MIN_STEP) {
            const crane_real frac = reversal_fraction(c, x, x1);
            if (frac < 1) {
                /* a friction reversal jumped across: again, shorter */
                grow = 1;
                h = on_grid(hs * (frac > ROS_SHRINK ? frac : ROS_SHRINK));
                if (h < ROS_MIN_STEP) {
                    h = ROS_MIN_STEP;
                }
                continue;
            }
        }
        /* the next step's proposal, from this step's error; not larger right after a rejection */
        h = err > 0 ? ROS_SAFETY / error_root(c, err) : ROS_GROW;
        h = on_grid(hs * (h < grow ? h : grow));
        grow = ROS_GROW;
        /* an end stop or a limit valve's setting inside the step: the step is cut at the first
         * and the joint goes onto its stop, the chamber onto the setting */
        tau = hs;
        first = first_crossing(c, x, x1, hs, &tau, &upper);
        chamber = chamber_crossing(c, x, x1, hs, &tau, &at);
        if (chamber >= 0) {
            first = -1;
        }
        if ((first >= 0 || chamber >= 0) && tau < hs * ROS_EVENT_FRACTION &&
            hs > ROS_FIRST_STEP * ROS_EVENT_FRACTION) {
            /* an event right at the step's start is seen through a long step's interpolant (a
             * joint just off its stop that the step carries back): retry shorter, to see it */
            h = hs * ROS_EVENT_FRACTION;
            grow = 1;
            continue;
        }
        if (first >= 0 || chamber >= 0) {
            hs = tau;
            last = 0;
            (void)adaptive_step(c, t, x, f0, J, hs, x1, fs);
            changed = 2; /* x1 is not the whole step's */
            if (any_stopped(c) != 0 && release_set(c, t + hs, x1) != 0) {
                /* a stopped joint comes free before the event: the release first (below); the
                 * event is found again in the next step */
                first = -1;
                chamber = -1;
            }
#if CRANE_HYDRAULICS
            if (chamber >= 0) {
                x1->v[chamber] = at;
                changed = 1;
            }
#endif
        }
        if (first < 0 && chamber < 0 && any_stopped(c) != 0 && release_set(c, t + hs, x1) != 0) {
            /* a stopped joint comes free inside the step: bisect for the time (f1 is scratch) */
            crane_real lo = 0, hi = hs;
            int k;
            for (k = 0; k < CRANE__RELEASE_BISECTIONS; ++k) {
                const crane_real mid = (lo + hi) / 2;
                (void)adaptive_step(c, t, x, f0, J, mid, f1, fs);
                if (release_set(c, t + mid, f1) != 0) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            if (hi < hs) {
                last = 0;
            }
            hs = hi;
            (void)adaptive_step(c, t, x, f0, J, hs, x1, fs);
            changed = 1;
        }
        spools_in_range(c, x1);
        if (c->dopri != 0u && changed == 0) {
            copy_state(c, f1, fs); /* the pair's last stage is f(t + hs, x1) (FSAL) */
        } else {
            rates(c, t + hs, x1, f1);
        }
        if (changed == 2) {
            changed = 0;
        }
        /* the samples are interpolated with f1 too: it must be finite as well */
        if (finite_state(c, x1) == 0 || finite_rates(c, f1) == 0) {
            *n_written = next;
            return CRANE_E_DIVERGED;
        }
        /* the kept sample times in [t, t + hs), by dense output */
        if (c->dopri != 0u && kept < n_steps && (crane_real)kept * dt < t + hs) {
            dense_coefficients(c, x, x1, f1, hs);
        }
        while (kept < n_steps && (crane_real)kept * dt < t + hs) {
            dense_sample(c, t, x, f0, x1, f1, hs, (crane_real)kept * dt, &out[next++]);
            kept += sample_every;
        }
        t = last != 0 ? horizon : t + hs;
        if (first >= 0) {
            stop_joint(c, x1, first, upper);
            changed = 1;
        }
        /* every other free joint beyond a limit, or at it with its rate not pointing into the
         * range, goes onto it too, in joint order (one at it moving inward stays free: a joint
         * just released may not have moved its coordinate by an ulp yet) */
        for (i = 0; i < 4; ++i) {
            const crane_real q = x1->v[Q + i], w = x1->v[W + i];
            if (c->mode[i] != CRANE__FREE) {
                continue;
            }
            if (q < lo_q(c, i) || (q == lo_q(c, i) && w <= 0)) {
                stop_joint(c, x1, i, 0);
                changed = 1;
            } else if (q > hi_q(c, i) || (q == hi_q(c, i) && w >= 0)) {
                stop_joint(c, x1, i, 1);
                changed = 1;
            } else {
                /* inside its range, or at a limit moving into it: stays free */
            }
        }
        if (changed != 0) {
            release(c, t, x1);
            /* a new start after an event: the step is found again from the first one's size */
            if (h > ROS_FIRST_STEP) {
                h = ROS_FIRST_STEP;
            }
        } else {
            copy_state(c, f0, f1);
        }
        copy_state(c, x, x1);
        if (last == 0) {
            step_start(c, t, x, f0, changed == 0, J);
        }
        more = last == 0;
    }
    put_sample(c, horizon, x, &out[next++]);
    *n_written = next;
    return CRANE_OK;
}

#endif /* CRANE_ROSW */

crane_status crane__integrate(const crane_model *m, const crane_state *s0, const crane_inputs *in,
                              crane_real horizon, crane_real dt, long n_steps, long sample_every,
                              crane_sample *out, size_t *n_written, crane_work *work)
{
    ctx_t *const c = work;
    xstate *const x = &work->x;
    long k;
    size_t next;
    int i;

    c->lim.m = m;
    c->in = in;
    c->s0 = s0;
    crane__bodies_init(m->params, &c->b);
    c->lim.valves = 0;
    c->lo_is_max = 0;
    c->cache = 0;
    c->release_clear = 0;
#if CRANE_ROSW
    c->rosw = (unsigned char)(in->solver.method != CRANE_METHOD_RK4);
    c->dopri = 0;
    {
        /* the angles' tolerance: tip metres over the crane's reach (lift pivot to the tip with the
         * telescope out), which bounds the tip's motion per radian of any joint */
        const crane_params *p = m->params;
        const crane_real reach =
            crane__norm(p->tilt_pivot) +
            crane__norm(crane__add(p->extension_mount,
                                   crane__v2(p->extension_max + p->tip_distance, 0)));
        c->tol_tip = in->solver.tip_tolerance > 0 ? in->solver.tip_tolerance : CRANE__TIP_TOLERANCE;
        c->tol_p = in->solver.pressure_tolerance > 0 ? in->solver.pressure_tolerance
                                                    : CRANE__PRESSURE_TOLERANCE;
        c->tol_q = c->tol_tip / reach;
    }
#endif
    c->planar = (unsigned char)(in->drive[CRANE_SLEW].mode == CRANE_DRIVE_HOLD &&
                               in->drive[CRANE_EXTENSION].mode == CRANE_DRIVE_HOLD);
    for (i = 0; i < N_ALL; ++i) {
        x->v[i] = 0;
    }
    for (i = 0; i < 4; ++i) {
        c->cursor[i] = 0;
        c->mode[i] = (signed char)(in->drive[i].mode == CRANE_DRIVE_HOLD ? CRANE__HELD : CRANE__FREE);
        if (CRANE_HYDRAULICS != 0 && in->drive[i].mode == CRANE_DRIVE_VALVE) {
            c->lim.valves |= 1u << i;
            x->v[H + 3 * i] = s0->p_a[i];
            x->v[H + 3 * i + 1] = s0->p_b[i];
            x->v[H + 3 * i + 2] = s0->spool[i];
        }
        if (i < 2) {
            crane_real ds;
            if (i == CRANE_LIFT) {
                crane__lift_from_stroke(m, s0->stroke[i], &x->v[Q + i], &ds);
            } else {
                (void)crane__tilt_from_stroke(m, s0->stroke[i], &x->v[Q + i], &ds, NULL, NULL);
            }
            x->v[W + i] = s0->stroke_rate[i] / ds;
            /* Which stroke limit is the lower angle limit follows the sign of ds/dtheta, which
             * the crane check keeps constant over the stroke. */
            if (!(ds > 0)) {
                c->lo_is_max = (unsigned char)(c->lo_is_max | (1u << i));
            }
        } else {
            x->v[Q + i] = i == CRANE_SLEW ? s0->slew : s0->extension;
            x->v[W + i] = i == CRANE_SLEW ? s0->slew_rate : s0->extension_rate;
        }
    }

    /* At t = 0: a free joint at a limit whose rate does not point into the range starts on that
     * stop, in joint order, with a plastic impact. */
    for (i = 0; i < 4; ++i) {
        int flag; /* the stop's flag: -1 stroke_min, +1 stroke_max */
        if (c->mode[i] != CRANE__FREE) {
            continue;
        }
        if (i < 2) {
            const crane_real s = s0->stroke[i], v = s0->stroke_rate[i];
            if (s <= crane__stroke_min(m, i) && v <= 0) {
                flag = -1;
            } else if (s >= crane__stroke_max(m, i) && v >= 0) {
                flag = 1;
            } else {
                continue;
            }
        } else {
            if (x->v[Q + i] <= lo_q(c, i) && x->v[W + i] <= 0) {
                flag = -1;
            } else if (x->v[Q + i] >= hi_q(c, i) && x->v[W + i] >= 0) {
                flag = 1;
            } else {
                continue;
            }
        }
        /* the upper limit of q is the one whose flag is not lo_flag */
        stop_joint(c, x, i, flag != lo_flag(c, i));
    }

    /* A state that stops being finite (only with absurd parameters, e.g. gravity 1e135) ends
     * the prediction with CRANE_E_DIVERGED and the samples written before it, all finite. */
    *n_written = 0;
    if (finite_state(c, x) == 0) {
        return CRANE_E_DIVERGED;
    }
    put_sample(c, 0, x, &out[0]);
#if CRANE_ROSW
    /* the default's pick: ROS34PW2 where the future is stiff (a valve drive's chambers, a
     * moving telescope's friction: RK4's substep sources), the explicit pair elsewhere */
    c->dopri = (unsigned char)(c->rosw != 0u && (in->solver.method == CRANE_METHOD_DOPRI5 ||
                                               (in->solver.method == CRANE_METHOD_DEFAULT &&
                                                c->lim.valves == 0u &&
                                                c->mode[CRANE_EXTENSION] == CRANE__HELD)));
    if (c->rosw != 0u) {
        return integrate_rosw(c, x, horizon, dt, n_steps, sample_every, out, n_written);
    }
#endif
    /* Samples after every sample_every-th step and after the last one. The kinematic cache is
     * keyed by the angles themselves, so it stays valid whatever happens in between. */
    for (k = 0, next = 1; k < n_steps; ++k) {
        const int last = k == n_steps - 1;
        const crane_real t_end = last != 0 ? horizon : (crane_real)(k + 1) * dt;
        crane_real t = (crane_real)k * dt;
        int more;

        /* The step, cut at the knots of sampled drives inside it into pieces, each integrated as
         * a step of its own (docs/model.md, "Integration and samples"). */
        do {
            const crane_real t_q = crane__next_knot(in, 4, t, t_end, dt);
            const crane_real h = t_q - t;
            long j, n_sub = 1;
            crane_real sub = h;

            /* docs/model.md "Hydraulics", "Four joints": with valve-driven actuators or a moving
             * extension, n equal substeps, each a full step of the scheme (one call site of step,
             * so that it stays inlined: the stack). */
            if ((c->lim.valves != 0u || c->mode[CRANE_EXTENSION] != CRANE__HELD) && h > 0) {
                n_sub = substeps(c, x, h);
                sub = h / (crane_real)n_sub;
            }
            for (j = 0; j < n_sub; ++j) {
                const int final = j == n_sub - 1;
                const crane_real t_sub = j == 0 ? t : t + (crane_real)j * sub;
                if (c->release_clear == 0u) {
                    release(c, t_sub, x);
                }
                if (h > 0) {
                    step(c, t_sub, x, final != 0 ? (j == 0 ? h : t_q - t_sub) : sub,
                         final != 0 ? t_q : t_sub + sub);
                }
            }
            more = t_q < t_end; /* an int controls the loop (MISRA 14.1) */
            t = t_q;
        } while (more != 0);
        if (finite_state(c, x) == 0) {
            *n_written = next;
            return CRANE_E_DIVERGED;
        }
        if (last != 0 || (k + 1) % sample_every == 0) {
            put_sample(c, last != 0 ? horizon : (crane_real)(k + 1) * dt, x, &out[next++]);
        }
    }
    *n_written = next;
    return CRANE_OK;
}
