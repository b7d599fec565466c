/* SPDX-License-Identifier: MIT */
/*
 * Fixed-step RK4 with end stops (docs/model.md, "Cylinders", "End stops", "Integration and
 * samples"). Everything here runs on inputs that crane_predict has already validated.
 */
#include "crane_internal.h"

enum integrator_bisections { RELEASE_BISECTIONS = CRANE__RELEASE_BISECTIONS };

/* theta, omega; with valve-driven cylinders also (p_a, p_b) of each joint and the spools (the
 * entries of joints that are not valve-driven stay 0). */
typedef struct {
    crane_real th[2], w[2];
#if CRANE_HYDRAULICS
    crane_real p[4], y[2];
#endif
} xstate;

/* Per-prediction working data, on the caller's stack. */
typedef struct {
    const crane_model *m;
    const crane_inputs *in;
    const crane_state *s0;      /* the initial strokes are reported for held joints */
    size_t cursor[2];           /* pressure sample segment last used, per joint */
    signed char mode[2];        /* CRANE__FREE, _HELD, _STOP_LO, _STOP_HI */
    signed char lo_flag[2];     /* stop flag at the lower angle limit: -1 stroke_min, +1 stroke_max
                                 * (the upper angle limit has the other one) */
#if CRANE_HYDRAULICS
    unsigned char valve[2];     /* joint i is valve-driven */
    unsigned char hyd;          /* some joint is: the state carries pressures */
#endif
    /* The last step ended with the release rule run at its end (the next step's start time and
     * state) releasing nothing: the release at the next step's start would repeat it exactly. */
    unsigned char release_clear;
    unsigned char kin_valid, kin_has_lift, tk_valid; /* the caches below hold values */
    /* Kinematics at the state of the last sample (trig of both angles, ds/dtheta and stroke of
     * the joints that were free): the next step's release check and first RK4 stage are at the
     * same angles, so they reuse it instead of evaluating the same trig and four-bar again. */
    crane_real kin_th[2];
    crane_real kin_c0, kin_s0, kin_c1, kin_s1;
    crane_real kin_ds_lift;
    crane_real j0;              /* crane__mass_matrix_j0, worked once */
    /* The four-bar (tilt ds/dtheta, stroke, side links) at the last tilt angle it was needed at:
     * with the tilt held or stopped the angle never changes, and with it free the last sample,
     * the next release check and the next step's first RK4 stage share one angle. */
    crane_real tk_th;
    crane__tilt_kin tk;
} ctx_t;

/* Joint i is valve-driven (never in a build without CRANE_HYDRAULICS, whose validation refuses
 * valve drives; the fields are left out there, to keep its stack smaller). */
static inline int is_valve(const ctx_t *c, int i)
{
#if CRANE_HYDRAULICS
    return c->valve[i];
#else
    (void)c;
    (void)i;
    return 0;
#endif
}

/* The stroke at joint i's stop flag (-1: stroke_min, +1: stroke_max). */
static crane_real flag_stroke(const ctx_t *c, int i, int flag)
{
    return flag < 0 ? crane__stroke_min(c->m, i) : crane__stroke_max(c->m, i);
}

/* The four-bar at theta1 (cos c1, sin s1), computed only when the angle differs from the last. */
static CRANE__ALWAYS_INLINE const crane__tilt_kin *tilt_kin(ctx_t *c, crane_real th1, crane_real c1, crane_real s1)
{
    if (!c->tk_valid || c->tk_th != th1) {
        crane__tilt_kinematics(c->m, c1, s1, &c->tk);
        c->tk_th = th1;
        c->tk_valid = 1;
    }
    return &c->tk;
}

/* Pressures of a pressure-driven joint at time t (crane__drive_pressures). */
static void pressures(ctx_t *c, int i, crane_real t, crane_real *p_a, crane_real *p_b)
{
    crane__drive_pressures(&c->in->drive[i], &c->cursor[i], t, p_a, p_b);
}

#if CRANE_HYDRAULICS
/* The lever of a valve-driven joint at time t (crane__drive_lever). */
static crane_real lever(ctx_t *c, int i, crane_real t)
{
    return crane__drive_lever(&c->in->drive[i], &c->cursor[i], t);
}

/* The stroke of a locked (stopped) valve-driven joint: its stop's. */
static crane_real stop_stroke(const ctx_t *c, int i)
{
    return flag_stroke(c, i, c->mode[i] == CRANE__STOP_LO ? c->lo_flag[i] : -c->lo_flag[i]);
}

/* The chamber and spool rates of valve-driven joint i into dh (dp_a at 2i, dp_b at 2i+1, dy at
 * 4+i), at its stroke and stroke rate. */
static void valve_rates(ctx_t *c, crane_real t, const xstate *x, int i, crane_real stroke,
                        crane_real v, crane_real dh[6])
{
    crane_real r[3];

    crane__chamber_rates(c->m, i, lever(c, i, t), stroke, v, &x->p[2 * i], x->y[i], r);
    dh[2 * i] = r[0];
    dh[2 * i + 1] = r[1];
    dh[4 + i] = r[2];
}

#endif

/* Mass matrix M (M00, M01, M11) and the net joint torques b = tau - h at (t, theta, omega);
 * cylinder torques only for the joints that are not locked (lk[i] = 0: a locked joint's own
 * torque is not needed to move the crane, only to decide whether it leaves its stop). With sv, also the valve-driven
 * joints' strokes (sv[i]) and stroke rates (sv[2 + i]), for their chamber rates: the caller
 * evaluates those after this returns, so that the valve's frames do not stack on this one's
 * (the stack budget of docs/embedding.md). */
static void forces(ctx_t *c, crane_real t, const xstate *x, const int lk[2], crane_real M[3],
                   crane_real b[2], crane_real *sv)
{
    const crane_model *m = c->m;
    static const crane_real zero[2] = {0, 0};
    crane_real c0, s0, c1, s1, c01, s01, h[2];
    crane_vec2 C1, C2, r12;
    const crane__tilt_kin *tk = NULL;
    int i;
    const int cached = c->kin_valid && x->th[0] == c->kin_th[0] && x->th[1] == c->kin_th[1];

    /* One sin/cos per joint angle (or none, at the last sample's angles); the absolute outer
     * boom angle by the angle-sum formulas. */
    if (cached) {
        c0 = c->kin_c0;
        s0 = c->kin_s0;
        c1 = c->kin_c1;
        s1 = c->kin_s1;
    } else {
        crane__sincos(x->th[0], &s0, &c0);
        crane__sincos(x->th[1], &s1, &c1);
    }
    c01 = c0 * c1 - s0 * s1;
    s01 = s0 * c1 + c0 * s1;
    C1 = crane__rot(c0, s0, m->params->lift_boom.com);
    C2 = crane__rot(c01, s01, m->c2);
    r12 = crane__rot(c0, s0, m->params->tilt_pivot);
    /* The four-bar is needed for the side links and for a driven tilt cylinder's ds/dtheta. */
    if (m->links || !lk[CRANE_TILT])
        tk = tilt_kin(c, x->th[1], c1, s1);
    crane__inverse_dynamics(m, C1, C2, r12, c0, s0, m->links ? tk : NULL, x->w, zero,
                            m->params->gravity, h);
    crane__mass_matrix(m, c->j0, c1, s1, m->links ? tk : NULL, M);

    for (i = 0; i < 2; ++i) {
        crane_real ds, p_a, p_b, stroke = 0;
        b[i] = -h[i];
        if (lk[i]) {
#if CRANE_HYDRAULICS
            if (sv && c->valve[i]) {
                sv[i] = stop_stroke(c, i);
                sv[2 + i] = 0;
            }
#endif
            continue;
        }
        if (i == CRANE_TILT) {
            ds = tk->ds;
            stroke = tk->stroke;
        } else if (is_valve(c, i)) {
            crane__lift_from_angle(m, c0, s0, &stroke, &ds);
        } else if (cached && c->kin_has_lift) {
            ds = c->kin_ds_lift;
        } else {
            crane__lift_from_angle(m, c0, s0, NULL, &ds);
        }
#if CRANE_HYDRAULICS
        if (c->valve[i]) {
            p_a = x->p[2 * i];
            p_b = x->p[2 * i + 1];
            if (sv) {
                sv[i] = stroke;
                sv[2 + i] = ds * x->w[i];
            }
        } else
#endif
        {
            (void)stroke;
            (void)sv;
            pressures(c, i, t, &p_a, &p_b);
        }
        b[i] += crane__cylinder_force(m, i, p_a, p_b, ds * x->w[i]) * ds;
    }
}

/* Solves M alpha = b for the unlocked joints; locked joints get alpha = 0. */
static void solve(const crane_real M[3], const crane_real b[2], const int lk[2], crane_real alpha[2])
{
    if (lk[0] && lk[1]) {
        alpha[0] = alpha[1] = 0;
    } else if (lk[0]) {
        alpha[0] = 0;
        alpha[1] = b[1] / M[2];
    } else if (lk[1]) {
        alpha[0] = b[0] / M[0];
        alpha[1] = 0;
    } else {
        const crane_real det = M[0] * M[2] - M[1] * M[1];
        alpha[0] = (M[2] * b[0] - M[1] * b[1]) / det;
        alpha[1] = (M[0] * b[1] - M[1] * b[0]) / det;
    }
}

/* Joint accelerations at (t, theta, omega); locked joints (held or stopped) get alpha = 0. With
 * dh (valve-driven joints), also the chamber and spool rates. */
static void accel(ctx_t *c, crane_real t, const xstate *x, const int lk[2], crane_real alpha[2],
                  crane_real *dh)
{
    crane_real M[3], b[2];
#if CRANE_HYDRAULICS
    crane_real sv[4]; /* the valve-driven joints' strokes and stroke rates */
    int i;

    if (lk[0] && lk[1]) {
        alpha[0] = alpha[1] = 0;
        for (i = 0; i < 2; ++i) {
            sv[i] = c->valve[i] ? stop_stroke(c, i) : 0;
            sv[2 + i] = 0;
        }
    } else {
        forces(c, t, x, lk, M, b, dh ? sv : NULL);
        solve(M, b, lk, alpha);
    }
    if (dh)
        for (i = 0; i < 2; ++i)
            if (c->valve[i])
                valve_rates(c, t, x, i, sv[i], sv[2 + i], dh);
#else
    (void)dh;
    if (lk[0] && lk[1]) {
        alpha[0] = alpha[1] = 0;
        return;
    }
    forces(c, t, x, lk, M, b, NULL);
    solve(M, b, lk, alpha);
#endif
}

static void lock_mask(const ctx_t *c, int lk[2])
{
    lk[0] = c->mode[0] != CRANE__FREE;
    lk[1] = c->mode[1] != CRANE__FREE;
}

/* y = x + h * (dtheta, domega) (and the pressures and spools + h * dh, with valves), written in
 * place: dth may be y->w (each rate is read before its entry is written), which spares RK4 a
 * second stage state (the stack). Without dh, y's pressures and spools are left as they are. */
static void axpy(const xstate *x, crane_real h, const crane_real *dth, const crane_real dw[2],
                 const crane_real *dh, xstate *y)
{
    y->th[0] = x->th[0] + h * dth[0];
    y->th[1] = x->th[1] + h * dth[1];
    y->w[0] = x->w[0] + h * dw[0];
    y->w[1] = x->w[1] + h * dw[1];
#if CRANE_HYDRAULICS
    /* without rates (no valve-driven joint) the pressures and spools stay those of x, which RK4's
     * stage state already holds */
    if (dh) {
        int k;
        for (k = 0; k < 4; ++k)
            y->p[k] = x->p[k] + h * dh[k];
        for (k = 0; k < 2; ++k)
            y->y[k] = x->y[k] + h * dh[4 + k];
    }
#else
    (void)dh;
#endif
}

/* Classic RK4, its four stages in one loop so that accel (forces and all) has one call site and
 * is inlined once. The stage sums are accumulated in *y as the stages go (one stage state, one
 * acceleration, no sums of their own: the stack), in the order ((k1 + 2 k2) + 2 k3) + k4, which is
 * the textbook expression's; so y must not be x. */
static void rk4(ctx_t *c, crane_real t, const xstate *x, crane_real h, xstate *y)
{
    const crane_real h2 = h / 2, h6 = h / 6;
    crane_real a[2];
#if CRANE_HYDRAULICS
    /* the rates of joints that are not valve-driven stay 0: their entries of the state too */
    crane_real dh[6] = {0, 0, 0, 0, 0, 0};
    crane_real *const pdh = c->hyd ? dh : NULL;
#else
    crane_real *const pdh = NULL;
#endif
    xstate xs = *x;
    int lk[2], k, i;

    lock_mask(c, lk);
    for (k = 0; k < 4; ++k) {
        accel(c, k == 0 ? t : k == 3 ? t + h : t + h2, &xs, lk, a, pdh);
#if CRANE_HYDRAULICS
        if (pdh) {
            for (i = 0; i < 6; ++i) {
                crane_real *const sum = i < 4 ? &y->p[i] : &y->y[i - 4];
                if (k == 0)
                    *sum = dh[i];
                else if (k < 3)
                    *sum = *sum + 2 * dh[i];
                else
                    *sum = (i < 4 ? x->p[i] : x->y[i - 4]) + h6 * (*sum + dh[i]);
            }
        }
#endif
        for (i = 0; i < 2; ++i) {
            if (k == 0) {
                y->th[i] = xs.w[i];
                y->w[i] = a[i];
            } else if (k < 3) {
                y->th[i] = y->th[i] + 2 * xs.w[i];
                y->w[i] = y->w[i] + 2 * a[i];
            } else {
                y->th[i] = x->th[i] + h6 * (y->th[i] + xs.w[i]);
                y->w[i] = x->w[i] + h6 * (y->w[i] + a[i]);
            }
        }
        if (k < 3)
            axpy(x, k == 2 ? h : h2, xs.w, a, pdh, &xs);
    }
#if CRANE_HYDRAULICS
    if (!pdh) {
        for (i = 0; i < 4; ++i)
            y->p[i] = x->p[i];
        y->y[0] = x->y[0];
        y->y[1] = x->y[1];
    }
#endif
}

/* Plastic impact on joint i: an impulse on joint i alone takes omega_i to 0, which conserves the
 * other joint's generalized momentum when it is free. */
static void impact(ctx_t *c, xstate *x, int i)
{
    const int j = 1 - i;

    if (c->mode[j] == CRANE__FREE) {
        crane_real M[3], c1, s1;
        crane__sincos(x->th[1], &s1, &c1);
        crane__mass_matrix(c->m, c->j0, c1, s1, c->m->links ? tilt_kin(c, x->th[1], c1, s1) : NULL,
                           M);
        /* omega - Minv e_i omega_i / Minv_ii, written without the inverse. */
        x->w[j] += M[1] / M[j == 0 ? 0 : 2] * x->w[i];
    }
    x->w[i] = 0;
}

/* Puts joint i on its stop: theta exactly at the limit, plastic impact, STOPPED. */
static void stop_joint(ctx_t *c, xstate *x, int i, int upper)
{
    x->th[i] = upper ? c->m->theta_max[i] : c->m->theta_min[i];
    impact(c, x, i);
    c->mode[i] = (signed char)(upper ? CRANE__STOP_HI : CRANE__STOP_LO);
}

/* Which stopped joints leave their stops: the solution of the two-contact complementarity problem.
 * Candidates (bit i set = joint i released) are tried in the order none, lift, tilt, both; the
 * first where every released joint accelerates into its range and every joint kept on its stop
 * is pushed onto it (its reaction r = M alpha - b points into the range) is taken. With one
 * stopped joint this is simply "released if its free acceleration points inward"; with two, it
 * keeps a joint from being released when only the other's being locked makes it want to leave. */
static int release_set(ctx_t *c, crane_real t, const xstate *x)
{
    int held[2], cand, i;
    crane_real M[3], b[2];

    if (c->mode[0] < CRANE__STOP_LO && c->mode[1] < CRANE__STOP_LO)
        return 0;
    for (i = 0; i < 2; ++i)
        held[i] = c->mode[i] == CRANE__HELD;
    /* the stopped joints' cylinder torques decide their release: only held joints are locked */
    forces(c, t, x, held, M, b, NULL);
    for (cand = 0; cand < 4; ++cand) {
        int lk[2], ok = 1;
        crane_real alpha[2];
        for (i = 0; i < 2; ++i) {
            const int released = (cand >> i) & 1;
            if (released && c->mode[i] < CRANE__STOP_LO)
                ok = 0;
            lk[i] = held[i] || (c->mode[i] >= CRANE__STOP_LO && !released);
        }
        if (!ok)
            continue;
        solve(M, b, lk, alpha);
        for (i = 0; i < 2; ++i) {
            const crane_real inward = c->mode[i] == CRANE__STOP_LO ? 1 : -1;
            if (c->mode[i] < CRANE__STOP_LO)
                continue;
            if ((cand >> i) & 1)
                ok = ok && inward * alpha[i] > 0;
            else
                ok = ok && inward * (M[i] * alpha[0] + M[i + 1] * alpha[1] - b[i]) >= 0;
        }
        if (ok)
            return cand;
    }
    /* No candidate consistent (only in a degenerate tie, e.g. an acceleration exactly 0): none. */
    return 0;
}

/* Applies the release rule at (t, x): the released joints become FREE. */
static void release(ctx_t *c, crane_real t, const xstate *x)
{
    const int cand = release_set(c, t, x);
    int i;

    for (i = 0; i < 2; ++i)
        if ((cand >> i) & 1)
            c->mode[i] = CRANE__FREE;
}

/* Release inside a piece (docs/model.md, "Release inside a step"): the piece from (t, x) over
 * size h ended with a STOPPED joint that the release rule would let go of. Bisects the piece size
 * (lo: an RK4 step of that size ends where the rule releases nothing; hi: where it releases
 * something), advances to hi and releases there; returns hi. y is scratch for the search. */
static crane_real release_in_piece(ctx_t *c, crane_real t, xstate *x, crane_real h, xstate *y)
{
    crane_real lo = 0, hi = h;
    int k;

    for (k = 0; k < RELEASE_BISECTIONS; ++k) {
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

/* One step of size h from t, cut at end-stop events: impacts and releases. Each event piece
 * normally stops or releases a joint, so two or three pieces are the rule; if the shorter RK4 step
 * lands a rounding error inside the limit the joint is not stopped yet and the next piece finds it
 * again a hair later (as the specification reads). MAX_PIECES only bounds that in pathological
 * cases: the last piece takes the whole rest, puts any joint that overshot on its limit and does
 * no release search. */
enum integrator_pieces { MAX_PIECES = CRANE__MAX_PIECES };

static void step(ctx_t *c, crane_real t, xstate *x, crane_real h, crane_real t_end)
{
    const crane_model *m = c->m;
    crane_real rem = h;
    int piece;

    c->release_clear = 0;
    for (piece = 0; rem > 0; ++piece) {
        unsigned out = 0, upper = 0; /* bit i: joint i beyond a limit, the upper one */
        crane_real tmin = rem;
        xstate x1;
        int i;

        rk4(c, t, x, rem, &x1);
        for (i = 0; i < 2; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x1.th[i] > m->theta_max[i])
                upper |= 1u << i;
            else if (!(x1.th[i] < m->theta_min[i]))
                continue;
            out |= 1u << i;
        }
        if (!out) {
            /* A piece without an impact, which ends at the step's end (its time is taken as t_end,
             * the next step's start time, so that this check and the release at the next step's
             * start are one evaluation): a STOPPED joint may have come free inside it. */
            if (piece < MAX_PIECES - 1 &&
                (c->mode[0] >= CRANE__STOP_LO || c->mode[1] >= CRANE__STOP_LO)) {
                if (release_set(c, t_end, &x1)) {
                    /* x1 is free again: the search's scratch (the stack) */
                    const crane_real hi = release_in_piece(c, t, x, rem, &x1);
                    t += hi;
                    rem -= hi;
                    continue;
                }
                c->release_clear = 1;
            }
            *x = x1;
            return;
        }
        if (piece == MAX_PIECES - 1) {
            *x = x1;
            for (i = 0; i < 2; ++i)
                if ((out >> i) & 1)
                    stop_joint(c, x, i, (upper >> i) & 1);
            return;
        }
        for (i = 0; i < 2; ++i) {
            if ((out >> i) & 1) {
                const int up = (upper >> i) & 1;
                const crane_real tau = crane__crossing_time(x->th[i], x->w[i], x1.th[i], x1.w[i], rem,
                                                     up ? m->theta_max[i] : m->theta_min[i], up);
                if (tau < tmin)
                    tmin = tau;
            }
        }
        rk4(c, t, x, tmin, &x1); /* x1 is free again: rk4 cannot write over its x */
        *x = x1;
        t += tmin;
        rem -= tmin;
        /* In joint order, every free joint at or beyond a limit goes onto it. */
        for (i = 0; i < 2; ++i) {
            if (c->mode[i] != CRANE__FREE)
                continue;
            if (x->th[i] <= m->theta_min[i])
                stop_joint(c, x, i, 0);
            else if (x->th[i] >= m->theta_max[i])
                stop_joint(c, x, i, 1);
        }
    }
}

static void put_sample(ctx_t *c, crane_real t, const xstate *x, crane_real cpsi, crane_real spsi,
                       crane_sample *o)
{
    const crane_model *m = c->m;
    crane_real c0, s0, c1, s1;
    crane_vec2 tip;
    int i;

    crane__sincos(x->th[0], &s0, &c0);
    crane__sincos(x->th[1], &s1, &c1);
    tip = crane__add(m->params->lift_pivot,
                     crane__rot(c0, s0,
                                crane__add(m->params->tilt_pivot,
                                           crane__rot(c1, s1, crane__tip(m)))));

    c->kin_valid = 1;
    c->kin_th[0] = x->th[0];
    c->kin_th[1] = x->th[1];
    c->kin_c0 = c0;
    c->kin_s0 = s0;
    c->kin_c1 = c1;
    c->kin_s1 = s1;
    c->kin_has_lift = 0;
    o->t = t;
    for (i = 0; i < 2; ++i) {
        crane_real s;
        switch (c->mode[i]) {
        case CRANE__STOP_LO: s = flag_stroke(c, i, c->lo_flag[i]); break;
        case CRANE__STOP_HI: s = flag_stroke(c, i, -c->lo_flag[i]); break;
        case CRANE__HELD: s = c->s0->stroke[i]; break;
        default:
            /* The stroke and ds/dtheta share the same kinematics: both at once, ds cached. */
            if (i == CRANE_LIFT) {
                crane__lift_from_angle(m, c0, s0, &s, &c->kin_ds_lift);
                c->kin_has_lift = 1;
            } else {
                s = tilt_kin(c, x->th[1], c1, s1)->stroke;
            }
            /* The stroke -> angle -> stroke round trip can land a few 1e-16 m outside the range
             * (docs/model.md, "End stops"): the reported stroke is clamped, the angle is not. */
            if (s < crane__stroke_min(m, i))
                s = crane__stroke_min(m, i);
            else if (s > crane__stroke_max(m, i))
                s = crane__stroke_max(m, i);
            break;
        }
        o->stroke[i] = s;
        o->theta[i] = x->th[i];
        o->omega[i] = x->w[i];
        o->flow_a[i] = o->flow_b[i] = o->spool[i] = 0;
#if CRANE_HYDRAULICS
        if (c->valve[i]) {
            const crane_hydraulics *h = crane__circuit(m, i);
            const crane_real y = h->spool_time_constant > 0 ? x->y[i] : lever(c, i, t);
            o->p_a[i] = x->p[2 * i];
            o->p_b[i] = x->p[2 * i + 1];
            crane__valve_flows(h, y, o->p_a[i], o->p_b[i], &o->flow_a[i], &o->flow_b[i]);
            o->spool[i] = y;
        } else
#endif
        if (c->mode[i] == CRANE__HELD) {
            o->p_a[i] = o->p_b[i] = 0;
        } else {
            pressures(c, i, t, &o->p_a[i], &o->p_b[i]);
        }
        /* Stop flags are in cylinder terms (docs/model.md): the tilt's lower angle stop is +1. */
        o->stop[i] = c->mode[i] == CRANE__STOP_LO   ? c->lo_flag[i]
                     : c->mode[i] == CRANE__STOP_HI ? -c->lo_flag[i]
                                                    : 0;
    }
    /* The slew and the extension are held (crane_predict accepts nothing else yet). */
    for (i = CRANE_SLEW; i <= CRANE_EXTENSION; ++i) {
        o->stop[i] = 0;
        o->p_a[i] = o->p_b[i] = o->flow_a[i] = o->flow_b[i] = o->spool[i] = 0;
    }
    o->slew = c->s0->slew;
    o->extension = c->s0->extension;
    o->slew_rate = o->extension_rate = 0;
    o->tip[0] = tip.x * cpsi;
    o->tip[1] = tip.x * spsi;
    o->tip[2] = tip.y;
}

/* theta and omega (and the pressures and spools, which stay 0 without valve-driven joints) are
 * all finite. */
static int finite_state(const ctx_t *c, const xstate *x)
{
#if CRANE_HYDRAULICS
    /* the physical domain too (crane_predict's CRANE_E_DIVERGED): an integrator gone unstable
     * shows there first, and finite garbage is never a result */
    int k;
    for (k = 0; c->hyd && k < 4; ++k)
        if (!crane__in_range(x->p[k], -(crane_real)CRANE_PRESSURE_MAX, (crane_real)CRANE_PRESSURE_MAX))
            return 0;
    if (c->hyd && (!crane__in_range(x->y[0], -1, 1) || !crane__in_range(x->y[1], -1, 1)))
        return 0;
#else
    (void)c;
#endif
    return crane__finite(x->th[0]) && crane__finite(x->th[1]) && crane__finite(x->w[0]) &&
           crane__finite(x->w[1]);
}

#if CRANE_HYDRAULICS
/* The substep count of a step of size h from the state x (docs/model.md, "Hydraulics"), from the
 * strokes of the valve-driven joints (a stopped joint's is its stop's). Out of line, so that its
 * locals are not in crane__integrate's frame under the step (the stack budget). */
static CRANE__NOINLINE long substeps(ctx_t *c, const xstate *x, crane_real h)
{
    const int valve[4] = {c->valve[0], c->valve[1], 0, 0};
    crane_real stroke[4] = {0, 0, 0, 0}, s1, c1;
    int i;

    for (i = 0; i < 2; ++i) {
        stroke[i] = 0;
        if (!c->valve[i])
            continue;
        if (c->mode[i] != CRANE__FREE) {
            stroke[i] = stop_stroke(c, i);
        } else if (i == CRANE_LIFT) {
            crane_real c0, s0;
            crane__sincos(x->th[0], &s0, &c0);
            crane__lift_from_angle(c->m, c0, s0, &stroke[i], NULL);
        } else {
            crane__sincos(x->th[1], &s1, &c1);
            stroke[i] = tilt_kin(c, x->th[1], c1, s1)->stroke;
        }
    }
    return crane__substeps(c->m, stroke, valve, h);
}
#endif

crane_status crane__integrate(const crane_model *m, const crane_state *s0, const crane_inputs *in,
                              crane_real horizon, crane_real dt, long n_steps, long sample_every,
                              crane_sample *out, size_t *n_written)
{
    crane_real cpsi, spsi;
    ctx_t c;
    xstate x;
    long k;
    size_t next;
    int i;

    crane__sincos(s0->slew, &spsi, &cpsi);
    c.m = m;
    c.in = in;
    c.s0 = s0;
    c.kin_valid = 0;
    c.kin_has_lift = 0;
    c.tk_valid = 0;
    c.j0 = crane__mass_matrix_j0(m);
    c.release_clear = 0;
#if CRANE_HYDRAULICS
    c.hyd = 0;
    for (i = 0; i < 2; ++i) {
        c.valve[i] = (unsigned char)(in->drive[i].mode == CRANE_DRIVE_VALVE);
        c.hyd = (unsigned char)(c.hyd || c.valve[i]);
        x.p[2 * i] = c.valve[i] ? s0->p_a[i] : 0;
        x.p[2 * i + 1] = c.valve[i] ? s0->p_b[i] : 0;
        x.y[i] = c.valve[i] ? s0->spool[i] : 0;
    }
#endif
    for (i = 0; i < 2; ++i) {
        crane_real ds;
        c.cursor[i] = 0;
        c.mode[i] = (signed char)(in->drive[i].mode == CRANE_DRIVE_HOLD ? CRANE__HELD : CRANE__FREE);
        if (i == CRANE_LIFT)
            crane__lift_from_stroke(m, s0->stroke[i], &x.th[i], &ds);
        else
            (void)crane__tilt_from_stroke(m, s0->stroke[i], &x.th[i], &ds, NULL, NULL);
        x.w[i] = s0->stroke_rate[i] / ds;
        /* Which stroke limit is the lower angle limit follows the sign of ds/dtheta, which the
         * crane check keeps constant over the stroke. */
        c.lo_flag[i] = (signed char)(ds > 0 ? -1 : 1);
    }

    /* At t = 0: a free joint at a stroke limit whose stroke rate does not point into the range
     * starts on that stop, in joint order, with a plastic impact. */
    for (i = 0; i < 2; ++i) {
        const crane_real s = s0->stroke[i], v = s0->stroke_rate[i];
        int flag; /* the stop's flag: -1 stroke_min, +1 stroke_max */
        if (c.mode[i] != CRANE__FREE)
            continue;
        if (s <= crane__stroke_min(m, i) && v <= 0)
            flag = -1;
        else if (s >= crane__stroke_max(m, i) && v >= 0)
            flag = 1;
        else
            continue;
        /* the upper angle limit is the one whose flag is not lo_flag */
        stop_joint(&c, &x, i, flag != c.lo_flag[i]);
    }

    /* A state that stops being finite (only with absurd parameters, e.g. gravity 1e135) ends
     * the prediction with CRANE_E_DIVERGED and the samples written before it, all finite. */
    *n_written = 0;
    if (!finite_state(&c, &x))
        return CRANE_E_DIVERGED;
    put_sample(&c, 0, &x, cpsi, spsi, &out[0]);
    /* Samples after every sample_every-th step and after the last one. The kinematic cache is
     * keyed by the angles themselves, so it stays valid whatever happens in between. */
    for (k = 0, next = 1; k < n_steps; ++k) {
        const int last = k == n_steps - 1;
        const crane_real t_end = last ? horizon : (crane_real)(k + 1) * dt;
        crane_real t = (crane_real)k * dt;
        int more;

        /* The step, cut at the knots of sampled drives inside it into pieces, each integrated as
         * a step of its own (docs/model.md, "Integration and samples"). */
        do {
            const crane_real t_q = crane__next_knot(in, 2, t, t_end, dt);
            const crane_real h = t_q - t;
#if CRANE_HYDRAULICS
            long j, n_sub = 1;
            crane_real sub = h;

            /* docs/model.md "Hydraulics": with valve-driven joints, n equal substeps, each a full
             * step of the scheme (one call site of step, so that it stays inlined: the stack). */
            if (c.hyd && h > 0) {
                n_sub = substeps(&c, &x, h);
                sub = h / (crane_real)n_sub;
            }
            for (j = 0; j < n_sub; ++j) {
                const int final = j == n_sub - 1;
                const crane_real t_sub = j == 0 ? t : t + (crane_real)j * sub;
                if (!c.release_clear)
                    release(&c, t_sub, &x);
                if (h > 0)
                    step(&c, t_sub, &x, final ? (j == 0 ? h : t_q - t_sub) : sub,
                         final ? t_q : t_sub + sub);
            }
#else
            if (!c.release_clear)
                release(&c, t, &x);
            if (h > 0)
                step(&c, t, &x, h, t_q);
#endif
            more = t_q < t_end; /* an int controls the loop (MISRA 14.1) */
            t = t_q;
        } while (more);
        if (!finite_state(&c, &x)) {
            *n_written = next;
            return CRANE_E_DIVERGED;
        }
        if (last || (k + 1) % sample_every == 0)
            put_sample(&c, last ? horizon : (crane_real)(k + 1) * dt, &x, cpsi, spsi, &out[next++]);
    }
    *n_written = next;
    return CRANE_OK;
}
