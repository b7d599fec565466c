/* SPDX-License-Identifier: MIT */
/*
 * State estimation (docs/live.md, "The estimator"): an extended Kalman filter over the model. Its
 * model step is the core's own prediction over the period between two measurements; its Jacobian
 * is by forward differences, every perturbed state predicted in one crane_predict_many call (so a
 * cycle costs CRANE_EST_N + 1 futures of one period). The measurement model is linear: a sensor
 * measures an estimated field. The update is in Joseph form; the covariance is then symmetrised
 * and, scaled by the fields' scales, its eigenvalues are floored at CRANE__EST_FLOOR; the estimate
 * is projected into the valid domain. Everything lives in the caller's crane_estimator: no heap,
 * and the stack holds only loop indices (its frame sits on crane_predict_many's).
 */
#include "crane_internal.h"

enum estimator_sizes { N = CRANE_EST_N };

/* The smallest eigenvalue of the scaled covariance: positive definite with room for rounding
 * (the covariance spans 1e-9 m^2 to 1e12 Pa^2; unscaled, rounding alone makes small eigenvalues
 * negative). */
static const crane_real CRANE__EST_FLOOR = (crane_real)1e-12;

/* Cyclic Jacobi sweeps before the eigen-decomposition gives up (it converges quadratically: a
 * 16 x 16 matrix needs 6-10). */
enum estimator_jacobi { JACOBI_SWEEPS = 50 };

static int config_ok(const crane_estimator_config *c)
{
    int i;

    if (crane__finite(c->dt) == 0 || !(c->dt > 0)) {
        return 0;
    }
    if (c->jacobian_columns < 0 || c->jacobian_columns > N) {
        return 0;
    }
    for (i = 0; i < N; ++i) {
        if (crane__finite(c->lo[i]) == 0 || crane__finite(c->hi[i]) == 0 ||
            !(c->lo[i] < c->hi[i])) {
            return 0;
        }
        if (crane__finite(c->noise[i]) == 0 || !(c->noise[i] >= 0)) {
            return 0;
        }
        if (crane__finite(c->fd_step[i]) == 0 || !(c->fd_step[i] > 0)) {
            return 0;
        }
        if (crane__finite(c->scale[i]) == 0 || !(c->scale[i] > 0)) {
            return 0;
        }
    }
    return 1;
}

/* Lower Cholesky factor of the m x m matrix a (row-major, stride N) into l; 0 if a is not
 * positive definite (a pivot <= 0 or not finite). */
static int cholesky(const crane_real *a, int m, crane_real *l)
{
    int i, j, k;

    for (i = 0; i < m; ++i) {
        for (j = 0; j <= i; ++j) {
            crane_real s = a[i * N + j];
            for (k = 0; k < j; ++k) {
                s -= l[i * N + k] * l[j * N + k];
            }
            if (i == j) {
                if (!(s > 0) || crane__finite(s) == 0) {
                    return 0;
                }
                l[i * N + i] = crane__sqrt(s);
            } else {
                l[i * N + j] = s / l[j * N + j];
            }
        }
        for (j = i + 1; j < m; ++j) {
            l[i * N + j] = 0;
        }
    }
    return 1;
}

/* Solves (l l^T) v = b in place (v = b on entry), l from cholesky. */
static void chol_solve(const crane_real *l, int m, crane_real *v)
{
    int i, k;

    for (i = 0; i < m; ++i) {
        crane_real s = v[i];
        for (k = 0; k < i; ++k) {
            s -= l[i * N + k] * v[k];
        }
        v[i] = s / l[i * N + i];
    }
    for (i = m - 1; i >= 0; --i) {
        crane_real s = v[i];
        for (k = i + 1; k < m; ++k) {
            s -= l[k * N + i] * v[k];
        }
        v[i] = s / l[i * N + i];
    }
}

/* c = a b^T (N x N, row-major); c must not alias a or b. */
static void mul_abt(const crane_real *a, const crane_real *b, crane_real *c)
{
    int i, j, k;

    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            crane_real s = 0;
            for (k = 0; k < N; ++k) {
                s += a[i * N + k] * b[j * N + k];
            }
            c[i * N + j] = s;
        }
    }
}

/* c = a b (N x N, row-major); c must not alias a or b. */
static void mul_ab(const crane_real *a, const crane_real *b, crane_real *c)
{
    int i, j, k;

    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            crane_real s = 0;
            for (k = 0; k < N; ++k) {
                s += a[i * N + k] * b[k * N + j];
            }
            c[i * N + j] = s;
        }
    }
}

/* Eigen-decomposition of the symmetric a (destroyed: its diagonal ends as the eigenvalues) by
 * cyclic Jacobi rotations; v gets the eigenvectors as columns. 0 if it did not converge. */
static int jacobi(crane_real *a, crane_real *v)
{
    int sweep, p, q, k;

    for (p = 0; p < N; ++p) {
        for (q = 0; q < N; ++q) {
            v[p * N + q] = p == q ? 1 : 0;
        }
    }
    for (sweep = 0; sweep < JACOBI_SWEEPS; ++sweep) {
        crane_real off = 0, diag = 0;
        for (p = 0; p < N; ++p) {
            diag += a[p * N + p] * a[p * N + p];
            for (q = p + 1; q < N; ++q) {
                off += a[p * N + q] * a[p * N + q];
            }
        }
        if (crane__finite(off) == 0 || crane__finite(diag) == 0) {
            return 0;
        }
        if (off <= diag * (crane_real)1e-30 || off == 0) {
            return 1;
        }
        for (p = 0; p < N; ++p) {
            for (q = p + 1; q < N; ++q) {
                const crane_real apq = a[p * N + q];
                crane_real theta, t, c, s;
                if (apq == 0) {
                    continue;
                }
                theta = (a[q * N + q] - a[p * N + p]) / (2 * apq);
                t = (theta >= 0 ? (crane_real)1 : (crane_real)-1) /
                    (crane__fabs(theta) + crane__sqrt(theta * theta + 1));
                c = 1 / crane__sqrt(t * t + 1);
                s = t * c;
                for (k = 0; k < N; ++k) { /* columns p and q */
                    const crane_real akp = a[k * N + p], akq = a[k * N + q];
                    a[k * N + p] = c * akp - s * akq;
                    a[k * N + q] = s * akp + c * akq;
                }
                for (k = 0; k < N; ++k) { /* rows p and q */
                    const crane_real apk = a[p * N + k], aqk = a[q * N + k];
                    a[p * N + k] = c * apk - s * aqk;
                    a[q * N + k] = s * apk + c * aqk;
                }
                for (k = 0; k < N; ++k) {
                    const crane_real vkp = v[k * N + p], vkq = v[k * N + q];
                    v[k * N + p] = c * vkp - s * vkq;
                    v[k * N + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    return 0;
}

/* P symmetric positive definite: symmetrised in the fields' scales and, if its smallest
 * eigenvalue there is below the floor, rebuilt from its eigen-decomposition with the eigenvalues
 * floored. Uses est->a, est->b, est->k as scratch. 0 if the covariance is beyond repair. */
static CRANE__NOINLINE int make_positive(crane_estimator *est)
{
    const crane_real *s = est->config.scale;
    crane_real *p = est->covariance, *ps = est->a, *l = est->b, *v = est->k;
    int i, j, k;

    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            ps[i * N + j] = (crane_real)0.5 * (p[i * N + j] + p[j * N + i]) / (s[i] * s[j]);
        }
    }
    /* the smallest eigenvalue is above the floor if and only if ps - floor I is positive definite */
    for (i = 0; i < N; ++i) {
        ps[i * N + i] -= CRANE__EST_FLOOR;
    }
    j = cholesky(ps, N, l);
    for (i = 0; i < N; ++i) {
        ps[i * N + i] += CRANE__EST_FLOOR;
    }
    if (j == 0) {
        /* l: the eigenvalues floored on the diagonal of ps, then v diag v^T */
        for (i = 0; i < N * N; ++i) {
            l[i] = ps[i];
        }
        if (jacobi(l, v) == 0) {
            return 0;
        }
        for (i = 0; i < N; ++i) {
            for (j = 0; j < N; ++j) {
                crane_real acc = 0;
                for (k = 0; k < N; ++k) {
                    const crane_real w = l[k * N + k] < CRANE__EST_FLOOR ? CRANE__EST_FLOOR : l[k * N + k];
                    acc += v[i * N + k] * w * v[j * N + k];
                }
                ps[i * N + j] = acc;
            }
        }
        for (i = 0; i < N; ++i) {
            for (j = 0; j < i; ++j) {
                ps[i * N + j] = ps[j * N + i] = (crane_real)0.5 * (ps[i * N + j] + ps[j * N + i]);
            }
        }
    }
    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            p[i * N + j] = ps[i * N + j] * (s[i] * s[j]);
            if (crane__finite(p[i * N + j]) == 0) {
                return 0;
            }
        }
    }
    return 1;
}

crane_status crane_estimator_init(crane_estimator *est, const crane_estimator_config *config,
                                  const crane_real x0[CRANE_EST_N],
                                  const crane_real covariance0[CRANE_EST_N * CRANE_EST_N],
                                  const crane_real spool0[4])
{
    int i;

    if (est == NULL || config == NULL || x0 == NULL || covariance0 == NULL || spool0 == NULL) {
        return CRANE_E_NULL;
    }
    if (config_ok(config) == 0) {
        return CRANE_E_ESTIMATOR;
    }
    for (i = 0; i < N; ++i) {
        if (crane__finite(x0[i]) == 0 || x0[i] < config->lo[i] || x0[i] > config->hi[i]) {
            return CRANE_E_ESTIMATOR;
        }
    }
    for (i = 0; i < N * N; ++i) {
        if (crane__finite(covariance0[i]) == 0) {
            return CRANE_E_NONFINITE;
        }
    }
    for (i = 0; i < 4; ++i) {
        if (crane__in_range(spool0[i], -1, 1) == 0) {
            return CRANE_E_VALVE;
        }
    }
    est->config = *config;
    for (i = 0; i < N; ++i) {
        est->x[i] = x0[i];
        est->field_nis[i] = 0;
    }
    for (i = 0; i < N * N; ++i) {
        est->covariance[i] = covariance0[i];
    }
    for (i = 0; i < 4; ++i) {
        est->spool[i] = spool0[i];
    }
    est->nis = 0;
    est->n_measured = 0;
    est->projected = 0;
    est->next_column = 0;
    est->jacobian_ready = 0;
    if (make_positive(est) == 0) {
        return CRANE_E_ESTIMATOR;
    }
    return CRANE_OK;
}

/* The State of an estimated vector x under the inputs (a held joint's rate is 0). */
static void state_of(const crane_estimator *est, const crane_real *x, const crane_inputs *in,
                     crane_state *s)
{
    int j;

    s->stroke[0] = x[CRANE_EST_LIFT_STROKE];
    s->stroke[1] = x[CRANE_EST_TILT_STROKE];
    s->slew = x[CRANE_EST_SLEW];
    s->extension = x[CRANE_EST_EXTENSION];
    s->stroke_rate[0] = x[CRANE_EST_RATES];
    s->stroke_rate[1] = x[CRANE_EST_RATES + 1];
    s->slew_rate = x[CRANE_EST_RATES + 2];
    s->extension_rate = x[CRANE_EST_RATES + 3];
    for (j = 0; j < 4; ++j) {
        s->p_a[j] = x[CRANE_EST_PRESSURES + 2 * j];
        s->p_b[j] = x[CRANE_EST_PRESSURES + 2 * j + 1];
        s->spool[j] = est->spool[j];
    }
    if (in->drive[CRANE_LIFT].mode == CRANE_DRIVE_HOLD) {
        s->stroke_rate[0] = 0;
    }
    if (in->drive[CRANE_TILT].mode == CRANE_DRIVE_HOLD) {
        s->stroke_rate[1] = 0;
    }
    if (in->drive[CRANE_SLEW].mode == CRANE_DRIVE_HOLD) {
        s->slew_rate = 0;
    }
    if (in->drive[CRANE_EXTENSION].mode == CRANE_DRIVE_HOLD) {
        s->extension_rate = 0;
    }
}

/* The Jacobian's columns this update renews: every one until all have been computed once (or
 * with jacobian_columns 0), else jacobian_columns of them in turn from next_column (the rest keep
 * the linearisation of the update that renewed them: at most N / jacobian_columns - 1 periods
 * old). Returns their number; the first is est->next_column (wrapping at N). */
static int columns(const crane_estimator *est)
{
    const int k = est->config.jacobian_columns;

    return est->jacobian_ready == 0 || k == 0 ? N : k;
}

/* Field of the r-th renewed column. */
static int column(const crane_estimator *est, int r)
{
    return (est->next_column + r) % N;
}

/* The nominal future and one per renewed column: futures[0] from x, futures[1 + r] from x with
 * field column(r) moved by its step, towards the inside of the domain (est->step). */
static CRANE__NOINLINE void perturb(crane_estimator *est, const crane_inputs *in, int n_cols)
{
    int r;

    state_of(est, est->x, in, &est->futures[0]);
    est->inputs[0] = *in;
    /* fixed RK4 steps: an adaptive step's choice would put its tolerance's noise into the
     * finite differences */
    est->inputs[0].solver.method = CRANE_METHOD_RK4;
    for (r = 0; r < n_cols; ++r) {
        crane_real xi[CRANE_EST_N];
        int k;
        const int i = column(est, r);
        const crane_real h = est->config.fd_step[i];
        for (k = 0; k < N; ++k) {
            xi[k] = est->x[k];
        }
        est->step[i] = est->x[i] + h <= est->config.hi[i] ? h : -h;
        xi[i] += est->step[i];
        state_of(est, xi, in, &est->futures[1 + r]);
        est->inputs[1 + r] = est->inputs[0];
    }
}

/* The estimated fields at a future's last sample (row y), its stroke rates through the boom
 * cylinders' transmissions (the kinematics of the strokes do not depend on the extension). */
static crane_status finals(const crane_model *m, const crane_sample *s, crane_real *y)
{
    int j;

    y[CRANE_EST_LIFT_STROKE] = s->stroke[0];
    y[CRANE_EST_TILT_STROKE] = s->stroke[1];
    y[CRANE_EST_SLEW] = s->slew;
    y[CRANE_EST_EXTENSION] = s->extension;
    for (j = 0; j < 2; ++j) {
        crane_real th, ds;
        const crane_status st = crane_joint_angle(m, j, s->stroke[j], &th, &ds);
        if (st != CRANE_OK) {
            return st;
        }
        y[CRANE_EST_RATES + j] = s->omega[j] * ds;
    }
    y[CRANE_EST_RATES + 2] = s->slew_rate;
    y[CRANE_EST_RATES + 3] = s->extension_rate;
    for (j = 0; j < 4; ++j) {
        y[CRANE_EST_PRESSURES + 2 * j] = s->p_a[j];
        y[CRANE_EST_PRESSURES + 2 * j + 1] = s->p_b[j];
    }
    return CRANE_OK;
}

/* The renewed columns into est->jacobian, then est->a = the propagated estimate's Jacobian F
 * (row-major) and y0 the nominal future's end; a held joint's pressures are not the model's (they
 * are kept, with F's row the identity). */
static CRANE__NOINLINE crane_status jacobian(crane_estimator *est, const crane_model *m,
                                             const crane_inputs *in, int n_cols, crane_real *y0)
{
    crane_real *f = est->a, yi[CRANE_EST_N];
    int i, k, j, r;
    crane_status st = finals(m, &est->samples[1], y0);

    if (st != CRANE_OK) {
        return st;
    }
    for (r = 0; r < n_cols; ++r) {
        i = column(est, r);
        st = finals(m, &est->samples[2 * (1 + r) + 1], yi);
        if (st != CRANE_OK) {
            return st;
        }
        for (k = 0; k < N; ++k) {
            est->jacobian[k * N + i] = (yi[k] - y0[k]) / est->step[i];
        }
    }
    for (i = 0; i < N * N; ++i) {
        f[i] = est->jacobian[i];
    }
    for (j = 0; j < 4; ++j) {
        if (in->drive[j].mode != CRANE_DRIVE_HOLD) {
            continue;
        }
        for (k = CRANE_EST_PRESSURES + 2 * j; k < CRANE_EST_PRESSURES + 2 * j + 2; ++k) {
            y0[k] = est->x[k];
            for (i = 0; i < N; ++i) {
                f[k * N + i] = i == k ? 1 : 0;
            }
        }
    }
    for (j = 0; j < 4; ++j) {
        est->spool[j] = est->samples[1].spool[j];
    }
    return CRANE_OK;
}

/* The covariance's time update P = F P F^T + Q period (F in est->a). */
static CRANE__NOINLINE void time_update(crane_estimator *est, crane_real period)
{
    int i;

    mul_ab(est->a, est->covariance, est->b);
    mul_abt(est->b, est->a, est->covariance);
    for (i = 0; i < N; ++i) {
        est->covariance[i * N + i] += est->config.noise[i] * period;
    }
}

/* The measurement update over the measured fields rows[0..m): gain, estimate, Joseph form, the
 * normalised innovation squared (all together and per field). 0 if S is not positive definite. */
static CRANE__NOINLINE int measurement_update(crane_estimator *est, const int *rows, int m,
                                              const crane_real *z, const crane_real *variance,
                                              crane_real *x)
{
    crane_real *p = est->covariance, *s = est->a, *l = est->b, *kt = est->k, *ikh = est->a;
    crane_real innov[CRANE_EST_N], w[CRANE_EST_N];
    int i, j, r;

    for (i = 0; i < m; ++i) {
        innov[i] = z[rows[i]] - x[rows[i]];
        for (j = 0; j < m; ++j) {
            s[i * N + j] = (crane_real)0.5 * (p[rows[i] * N + rows[j]] + p[rows[j] * N + rows[i]]);
        }
        s[i * N + i] += variance[rows[i]];
    }
    for (i = 0; i < N; ++i) {
        est->field_nis[i] = 0;
    }
    for (i = 0; i < m; ++i) {
        est->field_nis[rows[i]] = innov[i] * innov[i] / s[i * N + i];
    }
    if (cholesky(s, m, l) == 0) {
        return 0;
    }
    /* K^T (m x N): column c of K^T solves S k = P[c, rows]^T */
    for (i = 0; i < N; ++i) {
        for (r = 0; r < m; ++r) {
            w[r] = p[i * N + rows[r]];
        }
        chol_solve(l, m, w);
        for (r = 0; r < m; ++r) {
            kt[r * N + i] = w[r];
        }
    }
    for (r = 0; r < m; ++r) {
        w[r] = innov[r];
    }
    chol_solve(l, m, w);
    est->nis = 0;
    for (r = 0; r < m; ++r) {
        est->nis += innov[r] * w[r];
    }
    for (i = 0; i < N; ++i) {
        for (r = 0; r < m; ++r) {
            x[i] += kt[r * N + i] * innov[r];
        }
    }
    /* Joseph form: (I - K H) P (I - K H)^T + K R K^T */
    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            ikh[i * N + j] = i == j ? 1 : 0;
        }
    }
    for (r = 0; r < m; ++r) {
        for (i = 0; i < N; ++i) {
            ikh[i * N + rows[r]] -= kt[r * N + i];
        }
    }
    mul_ab(ikh, p, l);             /* l = (I - K H) P */
    mul_abt(l, ikh, p);            /* P = l (I - K H)^T */
    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            crane_real acc = 0;
            for (r = 0; r < m; ++r) {
                acc += kt[r * N + i] * variance[rows[r]] * kt[r * N + j];
            }
            p[i * N + j] += acc;
        }
    }
    return 1;
}

crane_status crane_estimator_update(crane_estimator *est, const crane_model *model,
                                    const crane_inputs *inputs, crane_real period,
                                    const crane_real z[CRANE_EST_N],
                                    const crane_real variance[CRANE_EST_N])
{
    crane_real *const y0 = est != NULL ? est->y0 : NULL;
    int *const rows = est != NULL ? est->rows : NULL;
    int m = 0, i, n_cols = N;
    size_t failed, count;
    crane_status st;

    if (est == NULL || model == NULL || inputs == NULL || z == NULL || variance == NULL) {
        return CRANE_E_NULL;
    }
    if (crane__finite(period) == 0) {
        return CRANE_E_NONFINITE;
    }
    if (!(period > 0)) {
        return CRANE_E_HORIZON;
    }
    for (i = 0; i < N; ++i) {
        if (crane__finite(variance[i]) == 0 || variance[i] < 0) {
            return CRANE_E_ESTIMATOR;
        }
        if (variance[i] > 0) {
            if (crane__finite(z[i]) == 0) {
                return CRANE_E_NONFINITE;
            }
            rows[m] = i;
            ++m;
        }
    }
    {
        const crane_real dt = est->config.dt < period ? est->config.dt : period;
        size_t every;
        long n_steps;
        crane_real q = crane__ceil(period / dt - (crane_real)1e-9);
        if (!(q <= (crane_real)CRANE_MAX_STEPS)) {
            return CRANE_E_STEPS;
        }
        n_steps = q < 1 ? 1 : (long)q;
        every = (size_t)n_steps;
        st = crane_sample_count_every(period, dt, every, &count);
        if (st != CRANE_OK) {
            return st;
        }
        if (count != 2) {
            return CRANE_E_CAPACITY;
        }
        n_cols = columns(est);
        perturb(est, inputs, n_cols);
        st = crane_predict_many(model->params, 1, (size_t)(1 + n_cols), est->futures, est->inputs,
                                period, dt, every, est->samples, 2, &failed,
                                &est->work);
        if (st != CRANE_OK) {
            return st;
        }
    }
    st = jacobian(est, model, inputs, n_cols, y0);
    if (st != CRANE_OK) {
        return st;
    }
    if (n_cols < N) {
        est->next_column = (est->next_column + n_cols) % N;
    }
    est->jacobian_ready = 1;
    time_update(est, period);
    est->n_measured = m;
    est->nis = 0;
    if (m > 0 && measurement_update(est, rows, m, z, variance, y0) == 0) {
        return CRANE_E_ESTIMATOR;
    }
    if (m == 0) {
        for (i = 0; i < N; ++i) {
            est->field_nis[i] = 0;
        }
    }
    if (make_positive(est) == 0) {
        return CRANE_E_ESTIMATOR;
    }
    est->projected = 0;
    for (i = 0; i < N; ++i) {
        if (crane__finite(y0[i]) == 0) {
            return CRANE_E_DIVERGED;
        }
        if (y0[i] < est->config.lo[i]) {
            y0[i] = est->config.lo[i];
            est->projected = 1;
        } else if (y0[i] > est->config.hi[i]) {
            y0[i] = est->config.hi[i];
            est->projected = 1;
        } else {
            /* within its bounds: kept */
        }
        est->x[i] = y0[i];
    }
    return CRANE_OK;
}

const char *crane__estimator_status_message(crane_status status)
{
    if (status == CRANE_E_ESTIMATOR) {
        return "an estimator setting, estimate or measurement variance is out of range, or its "
               "covariance cannot be kept positive definite";
    }
    return "unknown status";
}
