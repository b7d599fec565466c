/* SPDX-License-Identifier: MIT */
/*
 * The board's scenarios (scenarios.h). The paper's Figure 4 from the generated header
 * example/crane_scenarios.h (src/cranepredict/scenarios/paper-fig4.toml: lift at 175 bar on the
 * bore side, tilt held, from rest, 2 s; its 200 kg load is also the crane header's) at 2 ms, the
 * board's RK4 step, and at the C example's 1 ms; with BOARD_VALVES (make HYD=1) also lever-open:
 * the paper's pose at rest on closed valves, the lift lever fully open, at 2 ms.
 */
#include <string.h>
#include "crane_scenarios.h"
#include "scenarios.h"
#include "crane_patu655.h"

#define R(x) ((crane_real)(x))

static const board_scenario scenarios[] = {
    {"paper-dt2ms", CRANE_SCENARIO_PAPER_FIG4_HORIZON, R(2e-3), CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS,
     CRANE_SCENARIO_PAPER_FIG4_STATE, CRANE_SCENARIO_PAPER_FIG4_INPUTS},
    {"paper-dt1ms", CRANE_SCENARIO_PAPER_FIG4_HORIZON, R(1e-3), CRANE_SCENARIO_PAPER_FIG4_LOAD_MASS,
     CRANE_SCENARIO_PAPER_FIG4_STATE, CRANE_SCENARIO_PAPER_FIG4_INPUTS},
#ifdef BOARD_VALVES
    /* Valve-driven: needs the core built with its hydraulics (CRANE_HYDRAULICS, the default). */
    {"lever-open", CRANE_SCENARIO_LEVER_OPEN_HORIZON, R(2e-3), CRANE_SCENARIO_LEVER_OPEN_LOAD_MASS,
     CRANE_SCENARIO_LEVER_OPEN_STATE, CRANE_SCENARIO_LEVER_OPEN_INPUTS},
#endif
};
static const crane_params crane = CRANE_PATU655_INIT;

const board_scenario *board_scenarios(size_t *count)
{
    *count = sizeof scenarios / sizeof scenarios[0];
    return scenarios;
}

void board_crane(const board_scenario *sc, crane_params *params)
{
    *params = crane;
    params->load_mass = sc->load_mass;
}

char *board_put_str(char *p, const char *s)
{
    while (*s != '\0')
        *p++ = *s++;
    *p = '\0';
    return p;
}

char *board_put_u32(char *p, unsigned long v)
{
    char digits[12];
    int n = 0;

    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0)
        *p++ = digits[--n];
    *p = '\0';
    return p;
}

static char *put_real(char *p, crane_real x)
{
    static const char hex[] = "0123456789abcdef";
    unsigned char b[sizeof(crane_real)];
    size_t i;

    /* Most significant byte first: the bits read as one hex number. */
    memcpy(b, &x, sizeof b);
    *p++ = ' ';
    for (i = sizeof b; i-- > 0;) {
        *p++ = hex[b[i] >> 4];
        *p++ = hex[b[i] & 15u];
    }
    *p = '\0';
    return p;
}

static char *put_stop(char *p, int stop)
{
    p = board_put_str(p, stop < 0 ? " -" : " ");
    return board_put_u32(p, (unsigned long)(stop < 0 ? -stop : stop));
}

void board_format_sample(char *line, const char *name, size_t k, const crane_sample *s)
{
    char *p = board_put_str(line, "sample ");

    p = board_put_str(p, name);
    p = board_put_str(p, " ");
    p = board_put_u32(p, (unsigned long)k);
    p = put_real(p, s->t);
    p = put_real(p, s->tip[0]);
    p = put_real(p, s->tip[1]);
    p = put_real(p, s->tip[2]);
    p = put_real(p, s->stroke[CRANE_LIFT]);
    p = put_real(p, s->stroke[CRANE_TILT]);
    p = put_real(p, s->theta[CRANE_LIFT]);
    p = put_real(p, s->theta[CRANE_TILT]);
    p = put_real(p, s->p_a[CRANE_LIFT]);
    p = put_real(p, s->p_b[CRANE_LIFT]);
    p = put_real(p, s->p_a[CRANE_TILT]);
    p = put_real(p, s->p_b[CRANE_TILT]);
    p = put_stop(p, s->stop[CRANE_LIFT]);
    p = put_stop(p, s->stop[CRANE_TILT]);
    (void)board_put_str(p, "\n");
}

#ifdef BOARD_VALVES
const board_scenario *board_estimator_prepare(crane_params *params, crane_model *model,
                                              crane_sample *out, size_t capacity,
                                              crane_estimator_config *config,
                                              crane_real x0[CRANE_EST_N],
                                              crane_real covariance0[CRANE_EST_N * CRANE_EST_N],
                                              crane_real spool0[4])
{
    static const crane_estimator_config c = CRANE_EXAMPLE_ESTIMATOR_CONFIG;
    static const crane_real x[CRANE_EST_N] = CRANE_EXAMPLE_ESTIMATOR_X0;
    static const crane_real diagonal[CRANE_EST_N] = CRANE_EXAMPLE_ESTIMATOR_COVARIANCE0_DIAGONAL;
    static const crane_real spool[4] = CRANE_EXAMPLE_ESTIMATOR_SPOOL0;
    static crane_work work; /* the prediction's working storage (crane.h) */
    const board_scenario *sc = NULL;
    size_t i, n = 0;

    for (i = 0; i < sizeof scenarios / sizeof scenarios[0]; ++i) {
        if (strcmp(scenarios[i].name, "lever-open") == 0)
            sc = &scenarios[i];
    }
    if (sc == NULL)
        return NULL;
    board_crane(sc, params);
    if (crane_model_init(model, params, sc->state0.extension) != CRANE_OK ||
        crane_predict(params, &sc->state0, &sc->inputs,
                      BOARD_ESTIMATOR_PERIOD * BOARD_ESTIMATOR_CYCLES, BOARD_ESTIMATOR_PERIOD, out,
                      capacity, &n, &work) != CRANE_OK ||
        n != BOARD_ESTIMATOR_CYCLES + 1u)
        return NULL;
    *config = c;
    memcpy(x0, x, sizeof x);
    memcpy(spool0, spool, sizeof spool);
    for (i = 0; i < CRANE_EST_N * CRANE_EST_N; ++i)
        covariance0[i] = 0;
    for (i = 0; i < CRANE_EST_N; ++i)
        covariance0[i * (CRANE_EST_N + 1)] = diagonal[i];
    return sc;
}

void board_measurement(const crane_sample *s, crane_real z[CRANE_EST_N],
                       crane_real variance[CRANE_EST_N])
{
    static const crane_real v[CRANE_EST_N] = CRANE_EXAMPLE_ESTIMATOR_VARIANCE;
    int j;

    memcpy(variance, v, sizeof v);
    z[CRANE_EST_LIFT_STROKE] = s->stroke[CRANE_LIFT];
    z[CRANE_EST_TILT_STROKE] = s->stroke[CRANE_TILT];
    z[CRANE_EST_SLEW] = s->slew;
    z[CRANE_EST_EXTENSION] = s->extension;
    for (j = 0; j < 4; ++j) {
        z[CRANE_EST_RATES + j] = 0; /* not measured (variance 0) */
        z[CRANE_EST_PRESSURES + 2 * j] = s->p_a[j];
        z[CRANE_EST_PRESSURES + 2 * j + 1] = s->p_b[j];
    }
}

void board_format_estimate(char *line, size_t k, const crane_estimator *est)
{
    char *p = board_put_str(line, "estimate ");
    size_t i;

    p = board_put_u32(p, (unsigned long)k);
    for (i = 0; i < CRANE_EST_N; ++i)
        p = put_real(p, est->x[i]);
    (void)board_put_str(p, "\n");
}
#endif
