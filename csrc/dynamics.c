/* SPDX-License-Identifier: MIT */
/*
 * Planar iterative Newton-Euler inverse dynamics of the two booms (docs/model.md, "Dynamics").
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

void crane__side_link_torques(const crane__tilt_kin *tk, crane_real c0, crane_real s0,
                              const crane_real omega[2], const crane_real alpha[2], crane_real g,
                              crane_real tau[2])
{
    side_links(tk, c0, s0, omega, alpha, g, tau);
}

void crane__inverse_dynamics(const crane_model *m, crane_vec2 C1, crane_vec2 C2, crane_vec2 r12,
                             crane_real c0, crane_real s0, const crane__tilt_kin *tk,
                             const crane_real omega[2], const crane_real alpha[2], crane_real g,
                             crane_real tau[2])
{
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
    if (tk)
        side_links(tk, c0, s0, omega, alpha, g, tau);
}

/* The Newton-Euler recursion with omega = 0, g = 0 and alpha = e_j, simplified by hand:
 * cross(a, perp(b)) = a.b, and r12.C2 = O2.R(theta1)c2 does not depend on theta0. */
void crane__mass_matrix(const crane_model *m, crane_real j0, crane_real c1, crane_real s1,
                        const crane__tilt_kin *tk, crane_real M[3])
{
    const crane_real k = m->m2 * crane__dot(m->params->tilt_pivot, crane__rot(c1, s1, m->c2));
    M[0] = j0 + m->j2 + 2 * k;
    M[1] = m->j2 + k;
    M[2] = m->j2;
    if (tk) {
        M[0] += tk->M[0];
        M[1] += tk->M[1];
        M[2] += tk->M[2];
    }
}

crane_status crane_inverse_dynamics(const crane_model *model, const crane_real theta[2],
                                    const crane_real omega[2], const crane_real alpha[2],
                                    crane_real tau[2])
{
    crane_real c0, s0, c01, s01, t[2];
    crane__tilt_kin tk;
    int i;

    if (!model || !theta || !omega || !alpha || !tau)
        return CRANE_E_NULL;
    for (i = 0; i < 2; ++i)
        if (!crane__finite(theta[i]) || !crane__finite(omega[i]) || !crane__finite(alpha[i]))
            return CRANE_E_NONFINITE;
    /* The model holds only between the angle limits: beyond them the four-bar may not close
     * (crane_joint_stroke and crane_points reject the same angles). */
    for (i = 0; i < 2; ++i)
        if (theta[i] < model->theta_min[i] || theta[i] > model->theta_max[i])
            return CRANE_E_ANGLE;
    crane__sincos(theta[0], &s0, &c0);
    crane__sincos(theta[0] + theta[1], &s01, &c01);
    if (model->links) {
        crane_real c1, s1;
        crane__sincos(theta[1], &s1, &c1);
        crane__tilt_kinematics(model, c1, s1, &tk);
    }
    crane__inverse_dynamics(model, crane__rot(c0, s0, model->params->lift_boom.com),
                            crane__rot(c01, s01, model->c2),
                            crane__rot(c0, s0, model->params->tilt_pivot), c0, s0,
                            model->links ? &tk : NULL, omega, alpha, model->params->gravity, t);
    /* omega^2 overflows for rates near the square root of the largest real (1e160 rad/s). */
    if (!crane__finite(t[0]) || !crane__finite(t[1]))
        return CRANE_E_OVERFLOW;
    tau[0] = t[0];
    tau[1] = t[1];
    return CRANE_OK;
}
