/* SPDX-License-Identifier: MIT */
/*
 * The dynamics kernels (docs/model.md, "Dynamics", "Side links", "Four joints"): iterative
 * Newton-Euler inverse dynamics and the mass matrix of a configuration, in two shapes. The planar
 * kernel: the lift boom and the outer boom with the extension boom and the load lumped into it at
 * the model's extension (the two-joint model, for futures that hold the slew and the extension).
 * The spatial kernel: the three in-plane bodies (lift boom, outer boom, body 3 = extension boom +
 * load sliding along the outer boom) with the slew's centripetal and gyroscopic loads, the side
 * links, and the slew equation J_z alpha_s + Jdot_z omega_s; its mass matrix is block diagonal
 * (the slew decouples from the in-plane joints). The integrator picks one by the future's shape;
 * crane_inverse_dynamics is the spatial one.
 */
#include "crane_internal.h"

/* The side links' torques (docs/model.md, "Side links"). Dot and cross products do not change
 * under the rotation R(theta0), so the links' terms are worked in the lift boom frame, with the base
 * acceleration (0, g) rotated into it: gl = (g sin theta0, g cos theta0). Per link, F = m acc with
 * acc = gl + alpha1 v + omega1^2 w + 2 w1 omega1 perp(v) + a1 perp(d) - w1^2 d and
 * N = I (a1 + k alpha1 + g omega1^2); tau0 += cross(d, F) + N and tau1 += F.v + N k expand into
 * the sums of crane__tilt_kin (cross(d, perp(v)) = d.v, perp(v).v = 0, cross(d, d) = 0). */
static void side_links(const crane__tilt_kin *tk, crane_real c0, crane_real s0,
                       const crane_real omega[2], const crane_real alpha[2], crane_real g,
                       crane_real tau[2])
{
    const crane_real w1 = omega[0], u = omega[1], a1 = alpha[0], a = alpha[1];
    const crane_vec2 gl = crane__v2(g * s0, g * c0);
    const crane_real uu = u * u;

    tau[0] += tk->M[0] * a1 + tk->M[1] * a + crane__cross(tk->md, gl) + tk->huu[0] * uu +
              2 * tk->dv * w1 * u;
    tau[1] += tk->M[1] * a1 + tk->M[2] * a + crane__dot(tk->mv, gl) + tk->huu[1] * uu -
              tk->dv * w1 * w1;
}

void crane__id_planar(const crane_model *m, const crane__conf *cf, const crane_real omega[2],
                      const crane_real alpha[2], crane_real g, crane_real tau[2])
{
    const crane_vec2 C1 = crane__rot(cf->c0, cf->s0, m->params->lift_boom.com);
    const crane_vec2 C2 = crane__rot(cf->c01, cf->s01, m->c2);
    const crane_vec2 r12 = crane__rot(cf->c0, cf->s0, m->params->tilt_pivot);
    const crane_real w1 = omega[0], w2 = omega[0] + omega[1];
    const crane_real a1 = alpha[0], a2 = alpha[0] + alpha[1];
    /* Forward: a base acceleration of +g upward stands in for gravity. */
    const crane_vec2 acc_o1 = crane__v2(0, g);
    const crane_vec2 acc_c1 = crane__add(acc_o1, crane__sub(crane__scale(a1, crane__perp(C1)),
                                                            crane__scale(w1 * w1, C1)));
    const crane_vec2 acc_o2 = crane__add(acc_o1, crane__sub(crane__scale(a1, crane__perp(r12)),
                                                            crane__scale(w1 * w1, r12)));
    const crane_vec2 acc_c2 = crane__add(acc_o2, crane__sub(crane__scale(a2, crane__perp(C2)),
                                                            crane__scale(w2 * w2, C2)));
    /* Backward: force and moment of each parent on its child at the joint. */
    const crane_vec2 f2 = crane__scale(m->m2, acc_c2);
    const crane_real n2 = m->i2 * a2 + crane__cross(C2, f2);
    const crane_body *const b1 = &m->params->lift_boom;
    const crane_real n1 = b1->izz * a1 + crane__cross(C1, crane__scale(b1->mass, acc_c1)) +
                          crane__cross(r12, f2) + n2;
    tau[0] = n1;
    tau[1] = n2;
    if (m->links != 0) {
        side_links(&cf->tk, cf->c0, cf->s0, omega, alpha, g, tau);
    }
}

/* The Newton-Euler recursion with omega = 0, g = 0 and alpha = e_j, simplified by hand:
 * cross(a, perp(b)) = a.b, and r12.C2 = O2.R(theta1)c2 does not depend on theta0. */
void crane__mass_planar(const crane_model *m, const crane__conf *cf, crane_real Mp[6])
{
    const crane_body *const b1 = &m->params->lift_boom;
    /* I1 + m1 |c1|^2 + m2 |O2|^2: the constant part of M00 */
    const crane_real j0 = (b1->izz + b1->mass * crane__norm2(b1->com)) +
                          m->m2 * crane__norm2(m->params->tilt_pivot);
    const crane_real k =
        m->m2 * crane__dot(m->params->tilt_pivot, crane__rot(cf->c1, cf->s1, m->c2));
    Mp[0] = j0 + m->j2 + 2 * k;
    Mp[1] = m->j2 + k;
    Mp[3] = m->j2;
    Mp[2] = Mp[4] = 0;
    Mp[5] = 1;
    if (m->links != 0) {
        Mp[0] += cf->tk.M[0];
        Mp[1] += cf->tk.M[1];
        Mp[3] += cf->tk.M[2];
    }
}

void crane__bodies_init(const crane_params *p, crane__bodies *b)
{
    const crane_body *ext = &p->extension_boom;
    const crane_real m_ext = ext->mass, m_load = p->load_mass;
    const crane_vec2 tip = crane__v2(p->tip_distance, 0);
    crane_vec2 d_ext, d_tip;

    /* The extension boom and the load slide together: one body, lumped by parallel axes. */
    b->m3 = m_ext + m_load;
    b->c3 = crane__scale(1 / b->m3, crane__add(crane__scale(m_ext, ext->com), crane__scale(m_load, tip)));
    d_ext = crane__sub(ext->com, b->c3);
    d_tip = crane__sub(tip, b->c3);
    b->izz3 = ext->izz + m_ext * crane__norm2(d_ext) + m_load * crane__norm2(d_tip);
    b->t3[0] = ext->ixx + m_ext * d_ext.y * d_ext.y + m_load * d_tip.y * d_tip.y;
    b->t3[1] = ext->iyy + m_ext * d_ext.x * d_ext.x + m_load * d_tip.x * d_tip.x;
    b->t3[2] = ext->ixy - m_ext * d_ext.x * d_ext.y - m_load * d_tip.x * d_tip.y;
    /* The pillar turns with the slew about the vertical axis at its distance com.x from it. */
    b->jp = p->pillar.mass * p->pillar.com.x * p->pillar.com.x + p->pillar.iyy;
}

void crane__conf_at(const crane_model *m, crane_real th0, crane_real th1, crane_real e,
                     crane__conf *cf)
{
    crane__sincos(th0, &cf->s0, &cf->c0);
    crane__sincos(th1, &cf->s1, &cf->c1);
    cf->c01 = cf->c0 * cf->c1 - cf->s0 * cf->s1;
    cf->s01 = cf->s0 * cf->c1 + cf->c0 * cf->s1;
    cf->e = e;
    crane__tilt_kinematics(m, cf->c1, cf->s1, &cf->tk);
}

/* The rotated arms of a configuration: C1 = R(th0) c1, C2 = R(th0 + th1) c_ob,
 * C3 = R(th0 + th1) (mount + (e, 0) + c3), r12 = R(th0) O2. Worked by each of their readers
 * rather than kept in crane__conf, which every crane_work holds (and the planar kernel does not
 * read). */
typedef struct {
    crane_vec2 C1, C2, C3, r12;
} arms;

static CRANE__ALWAYS_INLINE void arms_at(const crane_model *m, const crane__bodies *b,
                                         const crane__conf *cf, arms *a)
{
    const crane_params *p = m->params;
    a->C1 = crane__rot(cf->c0, cf->s0, p->lift_boom.com);
    a->C2 = crane__rot(cf->c01, cf->s01, p->outer_boom.com);
    a->C3 = crane__rot(cf->c01, cf->s01,
                       crane__add(p->extension_mount, crane__add(crane__v2(cf->e, 0), b->c3)));
    a->r12 = crane__rot(cf->c0, cf->s0, p->tilt_pivot);
}

/* A body's inertia about a vertical axis through its centre when turned by phi in the boom plane,
 * J_v = ixx s^2 + 2 ixy s c + iyy c^2 (c, s = cos, sin phi), and its derivative by phi. */
static CRANE__ALWAYS_INLINE crane_real jv(crane_real ixx, crane_real iyy, crane_real ixy,
                                          crane_real c, crane_real s)
{
    return ixx * s * s + 2 * ixy * s * c + iyy * c * c;
}

static CRANE__ALWAYS_INLINE crane_real jv_prime(crane_real ixx, crane_real iyy, crane_real ixy,
                                                crane_real c, crane_real s)
{
    return (ixx - iyy) * 2 * s * c + 2 * ixy * (c * c - s * s);
}

static CRANE__ALWAYS_INLINE crane_real body_jv_prime(const crane_body *b, crane_real c, crane_real s)
{
    return jv_prime(b->ixx, b->iyy, b->ixy, c, s);
}

void crane__id_spatial(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                const crane_real qd[4], const crane_real qdd[4], crane_real g, crane_real tau[4])
{
    const crane_params *p = m->params;
    const crane_real w1 = qd[0], w2 = qd[0] + qd[1], ws = qd[2], ve = qd[3];
    const crane_real a1 = qdd[0], a2 = qdd[0] + qdd[1], ae = qdd[3];
    const crane_real s2 = ws * ws;
    arms ar;
    crane_real x0, x2;
    crane_vec2 C1, C2, C3, r12;
    const crane_vec2 u = crane__v2(cf->c01, cf->s01);             /* the extension's direction */
    const crane_real m1 = p->lift_boom.mass, m2 = p->outer_boom.mass;
    crane_real n_g1 = 0, n_g23 = 0, cor, n1, n2;
    crane_vec2 acc_c1, acc_o2, acc_c2, acc_c3, f3, f2c, f2;

    arms_at(m, b, cf, &ar);
    C1 = ar.C1;
    C2 = ar.C2;
    C3 = ar.C3;
    r12 = ar.r12;
    x0 = p->lift_pivot.x;     /* O1's and O2's distance from the slew axis */
    x2 = x0 + r12.x;
    /* The slew's gyroscopic moment on each body, -1/2 omega_s^2 J_v'(phi) (Euler's w x J w). */
    if (s2 != 0) {
        n_g1 = (crane_real)-0.5 * s2 * body_jv_prime(&p->lift_boom, cf->c0, cf->s0);
        n_g23 = (crane_real)-0.5 * s2 *
                (body_jv_prime(&p->outer_boom, cf->c01, cf->s01) +
                 jv_prime(b->t3[0], b->t3[1], b->t3[2], cf->c01, cf->s01));
    }
    /* Forward: base acceleration (0, g) for gravity; every centre of mass also carries the slew's
     * centripetal acceleration (-omega_s^2 x, 0), x its distance from the slew axis. */
    acc_c1 = crane__v2(-a1 * C1.y - w1 * w1 * C1.x - s2 * (x0 + C1.x), g + a1 * C1.x - w1 * w1 * C1.y);
    acc_o2 = crane__v2(-a1 * r12.y - w1 * w1 * r12.x, g + a1 * r12.x - w1 * w1 * r12.y);
    acc_c2 = crane__v2(acc_o2.x - a2 * C2.y - w2 * w2 * C2.x - s2 * (x2 + C2.x),
                       acc_o2.y + a2 * C2.x - w2 * w2 * C2.y);
    /* Body 3 slides along u: its relative acceleration a_e u and the Coriolis 2 w2 v_e perp(u). */
    cor = 2 * w2 * ve;
    acc_c3 = crane__v2(acc_o2.x - a2 * C3.y - w2 * w2 * C3.x - cor * u.y + ae * u.x - s2 * (x2 + C3.x),
                       acc_o2.y + a2 * C3.x - w2 * w2 * C3.y + cor * u.x + ae * u.y);
    /* Backward: forces and moments about each joint. */
    f3 = crane__scale(b->m3, acc_c3);
    /* cppcheck 2.10's whole-program check sizes tau with the float build's crane_real and indexes
     * it with the double build's (a false "ctuArrayIndex"; every caller passes crane_real[4]) */
    /* cppcheck-suppress ctuArrayIndex */
    tau[3] = crane__dot(f3, u);
    f2c = crane__scale(m2, acc_c2);
    n2 = (p->outer_boom.izz + b->izz3) * a2 + n_g23 + crane__cross(C2, f2c) + crane__cross(C3, f3);
    f2 = crane__add(f2c, f3);
    n1 = p->lift_boom.izz * a1 + n_g1 + crane__cross(C1, crane__scale(m1, acc_c1)) +
         crane__cross(r12, f2) + n2;
    tau[0] = n1;
    tau[1] = n2;
    if (m->links != 0) {
        const crane_real w[2] = {qd[0], qd[1]}, a[2] = {qdd[0], qdd[1]};
        side_links(&cf->tk, cf->c0, cf->s0, w, a, g, tau);
    }
    /* the slew's own J_z alpha_s + Jdot_z omega_s and its loads on the side links are the
     * caller's (crane__slew_inertia, crane__slew_torque): the integrator has J_z for its mass
     * matrix anyway, and needs none of them with the slew locked */
    tau[2] = 0;
}

void crane__slew_inertia(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                         const crane_real qd[4], crane_real *jz, crane_real *jdot,
                         crane_real tau[2])
{
    const crane_params *p = m->params;
    const crane_real w1 = qd[0], w2 = qd[0] + qd[1], ve = qd[3], s2 = qd[2] * qd[2];
    const crane_body *lb = &p->lift_boom, *ob = &p->outer_boom;
    const crane_real x0 = p->lift_pivot.x;
    crane_real x2, x_1, xd_1, x_2, xd_2, x_3, xd_3;
    crane_real j = b->jp, jd = 0;
    crane__link_vec l;
    arms ar;
    int k;

    /* J_z = J_P + sum m x^2 + J_v(phi); Jdot_z = sum 2 m x xdot + J_v'(phi) phidot: x is a centre
     * of mass's distance from the slew axis, xdot its rate (docs/model.md, "Four joints"). */
    arms_at(m, b, cf, &ar);
    x2 = x0 + ar.r12.x;
    x_1 = x0 + ar.C1.x;
    xd_1 = -w1 * ar.C1.y;
    x_2 = x2 + ar.C2.x;
    xd_2 = -w1 * ar.r12.y - w2 * ar.C2.y;
    x_3 = x2 + ar.C3.x;
    xd_3 = -w1 * ar.r12.y - w2 * ar.C3.y + ve * cf->c01;

    j += lb->mass * x_1 * x_1 + jv(lb->ixx, lb->iyy, lb->ixy, cf->c0, cf->s0);
    jd += 2 * lb->mass * x_1 * xd_1 + body_jv_prime(lb, cf->c0, cf->s0) * w1;
    j += ob->mass * x_2 * x_2 + jv(ob->ixx, ob->iyy, ob->ixy, cf->c01, cf->s01);
    jd += 2 * ob->mass * x_2 * xd_2 + body_jv_prime(ob, cf->c01, cf->s01) * w2;
    j += b->m3 * x_3 * x_3 + jv(b->t3[0], b->t3[1], b->t3[2], cf->c01, cf->s01);
    jd += 2 * b->m3 * x_3 * xd_3 + jv_prime(b->t3[0], b->t3[1], b->t3[2], cf->c01, cf->s01) * w2;
    /* The side links one by one (only the slew needs them so; the planar terms take their sums
     * from crane__tilt_kin): per link its centre of mass d, its velocity per unit tilt rate v,
     * its turn rate per unit tilt rate kl and cos cl, sin sl of its turn relative to the lift
     * boom (R(phi1) takes link_pin to qp, R(phi2) link2_end to aq: the dot and cross products
     * over the equal lengths). Worked here from the four-bar rather than kept (the stack). */
    if (m->links != 0) {
        crane__link_vectors(m, &cf->tk, &l);
    }
    for (k = 0; m->links != 0 && k < 2; ++k) {
        const crane_body *lbody = k == 0 ? &p->side_link1 : &p->side_link2;
        const crane_vec2 pin = k == 0 ? p->link_pin : p->link2_end, rel = k == 0 ? l.qp : l.aq;
        const crane_real n = crane__norm2(pin), kl = k == 0 ? l.k1 : l.k2;
        const crane_real cl = crane__dot(pin, rel) / n, sl = crane__cross(pin, rel) / n;
        const crane_vec2 D = crane__rot(cf->c0, cf->s0, k == 0 ? l.d1 : l.d2);
        const crane_vec2 J = crane__rot(cf->c0, cf->s0, k == 0 ? l.v1 : l.v2);
        const crane_real cp = cf->c0 * cl - cf->s0 * sl;
        const crane_real sp = cf->s0 * cl + cf->c0 * sl;
        const crane_real x = x0 + D.x, xd = qd[1] * J.x - w1 * D.y;
        const crane_real jvp = body_jv_prime(lbody, cp, sp);
        j += lbody->mass * x * x + jv(lbody->ixx, lbody->iyy, lbody->ixy, cp, sp);
        jd += 2 * lbody->mass * x * xd + jvp * (w1 + kl * qd[1]);
        /* The slew's share on the links: the centripetal force along the boom plane's x and the
         * gyroscopic moment, by virtual work like the rest of their loads. */
        if (s2 != 0) {
            const crane_real fx = -lbody->mass * s2 * (x0 + D.x);
            const crane_real ng = (crane_real)-0.5 * s2 * jvp;
            tau[0] += -D.y * fx + ng;
            tau[1] += fx * J.x + ng * kl;
        }
    }
    *jz = j;
    *jdot = jd;
}

void crane__mass_spatial(const crane_model *m, const crane__bodies *b, const crane__conf *cf,
                  crane_real Mp[6])
{
    const crane_params *p = m->params;
    const crane_real m2 = p->outer_boom.mass, m3 = b->m3;
    const crane_vec2 u = crane__v2(cf->c01, cf->s01);
    const crane_real i23 = p->outer_boom.izz + b->izz3;
    arms ar;
    crane_vec2 R2, R3;
    crane_real j1;

    arms_at(m, b, cf, &ar);
    R2 = crane__add(ar.r12, ar.C2);
    R3 = crane__add(ar.r12, ar.C3);
    j1 = p->lift_boom.izz + p->lift_boom.mass * crane__norm2(ar.C1);

    /* crane__id_spatial's recursion at zero rates and gravity with a unit acceleration of one joint,
     * worked by hand (cross(a, perp(b)) = a.b; R2, R3: the centres of bodies 2 and 3 from O1):
     * lift: body b accelerates by perp(R_b); tilt: by perp(C_b); extension: body 3 by u. */
    Mp[0] = j1 + i23 + m2 * crane__norm2(R2) + m3 * crane__norm2(R3);
    Mp[1] = i23 + m2 * crane__dot(ar.C2, R2) + m3 * crane__dot(ar.C3, R3);
    Mp[2] = m3 * crane__cross(R3, u);
    Mp[3] = i23 + m2 * crane__norm2(ar.C2) + m3 * crane__norm2(ar.C3);
    Mp[4] = m3 * crane__cross(ar.C3, u);
    Mp[5] = m3;
    if (m->links != 0) {
        Mp[0] += cf->tk.M[0];
        Mp[1] += cf->tk.M[1];
        Mp[3] += cf->tk.M[2];
    }
}

crane_status crane_inverse_dynamics(const crane_model *model, const crane_real q[4],
                                     const crane_real qd[4], const crane_real qdd[4],
                                     crane_real tau[4])
{
    const crane_params *p;
    crane__bodies b;
    crane__conf cf;
    crane_real t[4];
    int i;

    if (model == NULL || q == NULL || qd == NULL || qdd == NULL || tau == NULL) {
        return CRANE_E_NULL;
    }
    p = model->params;
    for (i = 0; i < 4; ++i) {
        if (crane__finite(q[i]) == 0 || crane__finite(qd[i]) == 0 || crane__finite(qdd[i]) == 0) {
            return CRANE_E_NONFINITE;
        }
    }
    /* The model holds only between the angle limits: beyond them the four-bar may not close
     * (crane_joint_stroke and crane_points reject the same angles). */
    for (i = 0; i < 2; ++i) {
        if (q[i] < model->theta_min[i] || q[i] > model->theta_max[i]) {
            return CRANE_E_ANGLE;
        }
    }
    if (q[3] < p->extension_min || q[3] > p->extension_max) {
        return CRANE_E_EXTENSION;
    }
    crane__bodies_init(p, &b);
    crane__conf_at(model, q[0], q[1], q[3], &cf);
    crane__id_spatial(model, &b, &cf, qd, qdd, p->gravity, t);
    if (qd[2] != 0 || qdd[2] != 0) {
        crane_real jz, jdot;
        crane__slew_inertia(model, &b, &cf, qd, &jz, &jdot, t);
        t[2] = crane__slew_torque(jz, jdot, qd[2], qdd[2]);
    }
    /* squares of rates near 1e160 (double) overflow */
    for (i = 0; i < 4; ++i) {
        if (crane__finite(t[i]) == 0) {
            return CRANE_E_OVERFLOW;
        }
    }
    for (i = 0; i < 4; ++i) {
        tau[i] = t[i];
    }
    return CRANE_OK;
}
