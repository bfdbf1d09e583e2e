/* Unit tests for erlaw (docs/method/carry.md §3, 2.6): closed-loop error dynamics on a
 * point mass X'' = u (the plant the arm's computed-torque loop makes of
 * the arm), including a frozen ("blocked") mass and its release. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "erlaw.h"
#include "sprofile.h"
#include "vec3.h"

static const erlaw_gains G = { 0.25, 0.5, 4.0, 100.0, 20.0, 0.2, 5.0, 50.0 };
static const double P0[3] = { 0.4, -0.2, 0.3 };
static const double P1[3] = { 0.7, 0.2, 0.3 }; /* s_f = 0.5 m */
#define DT 1e-3
#define TOL_S 1e-3
#define TOL_V 5e-3

typedef struct {
    double x[3], v[3];
    double s_raw_max; /* furthest along e, unclamped: overshoot check */
    double speed_max;
} mass;

/* One 1 kHz cycle; a frozen mass keeps its position and zero speed. */
static erlaw_out cycle(erlaw_line *l, mass *m, erlaw_ref ref, double s_ext, int frozen)
{
    erlaw_out o;
    double d[3];
    int i;
    assert_int_equal(erlaw_line_step(l, m->x, m->v, ref, s_ext, DT, &o), 0);
    for (i = 0; i < 3; i++) {
        if (frozen) {
            m->v[i] = 0.0;
        } else {
            m->v[i] += o.u[i] * DT;
            m->x[i] += m->v[i] * DT;
        }
    }
    vec3_sub(d, m->x, l->p0_m);
    m->s_raw_max = fmax(m->s_raw_max, vec3_dot(d, l->ch.e));
    m->speed_max = fmax(m->speed_max, vec3_norm(m->v));
    return o;
}

static void mass_at(mass *m, const double p[3])
{
    vec3_copy(m->x, p);
    vec3_set(m->v, 0.0, 0.0, 0.0);
    m->s_raw_max = 0.0;
    m->speed_max = 0.0;
}

static int is_done(const erlaw_line *l, const mass *m)
{
    return erlaw_done(erlaw_line_s(l, m->x), erlaw_channel_length(&l->ch), vec3_norm(m->v), TOL_S,
                      TOL_V);
}

/* Runs until done; returns the time taken (or a big number). */
static double run_to_done(erlaw_line *l, mass *m, erlaw_ref ref, double t_max)
{
    double t = 0.0;
    while (!is_done(l, m) && t < t_max) {
        cycle(l, m, ref, 0.0, 0);
        t += DT;
    }
    return t;
}

static void test_reaches_goal_at_rest(void **st)
{
    erlaw_line l;
    mass m;
    double t, dist[3];
    int k;
    (void)st;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    t = run_to_done(&l, &m, ERLAW_REF_MEASURED, 30.0);
    assert_true(t < 10.0);
    /* stays there, at rest, without overshoot */
    for (k = 0; k < 3000; k++)
        cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 0);
    vec3_sub(dist, m.x, P1);
    assert_true(vec3_norm(dist) < TOL_S);
    assert_true(vec3_norm(m.v) < 1e-4);
    assert_true(m.s_raw_max <= 0.5 + TOL_S);
    /* the speed limit is respected up to the bias surplus k0/k_v */
    assert_true(m.speed_max <= G.v_m + G.k0 / G.k_v + 1e-3);
}

/* A cross-track offset is removed on the way (k_p acts across e). */
static void test_cross_track_error_decays(void **st)
{
    erlaw_line l;
    mass m;
    double start[3] = { 0.4, -0.2, 0.32 }, dist[3];
    (void)st;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, start);
    assert_true(run_to_done(&l, &m, ERLAW_REF_MEASURED, 30.0) < 10.0);
    vec3_sub(dist, m.x, P1);
    assert_true(vec3_norm(dist) < 2.0 * TOL_S);
}

/* Without p_bias, at s0 every term of eq. 6 is zero: the mass never
 * starts. With it, it does. */
static void test_bias_is_needed(void **st)
{
    erlaw_gains g0 = G;
    erlaw_line l;
    mass m;
    int k;
    (void)st;
    g0.k0 = 0.0;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &g0), 0);
    mass_at(&m, P0);
    for (k = 0; k < 5000; k++) {
        erlaw_out o = cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 0);
        assert_true(vec3_norm(o.u) == 0.0);
    }
    assert_true(erlaw_line_s(&l, m.x) == 0.0);
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    for (k = 0; k < 1000; k++)
        cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 0);
    assert_true(erlaw_line_s(&l, m.x) > 1e-3);
}

/* Short segment (k2 s_f < k1) against an opposing model error of half
 * the bias: eq. 7 as printed would be fading at s = 0 and never start;
 * with k2 raised for short segments the mass starts and arrives, short
 * by about d / (k_v sqrt(u_m)). */
static void test_short_segment_starts_against_disturbance(void **st)
{
    const double p1[3] = { 0.4 + 0.018, -0.2 + 0.024, 0.3 }; /* 0.03 m */
    const double d = 0.5 * G.k0, offset = d / (G.k_v * sqrt(G.u_m));
    erlaw_line l;
    mass m;
    double t = 0.0;
    int i;
    (void)st;
    assert_int_equal(erlaw_line_init(&l, P0, p1, &G), 0);
    mass_at(&m, P0);
    for (t = 0.0; t < 10.0; t += DT) {
        erlaw_out o;
        assert_int_equal(erlaw_line_step(&l, m.x, m.v, ERLAW_REF_MEASURED, 0.0, DT, &o), 0);
        assert_true(o.bias <= G.k0);
        for (i = 0; i < 3; i++) {
            m.v[i] += (o.u[i] - d * l.ch.e[i]) * DT;
            m.x[i] += m.v[i] * DT;
        }
    }
    assert_true(erlaw_done(erlaw_line_s(&l, m.x), 0.03, vec3_norm(m.v), offset + 1e-3, TOL_V));
}

/* Drives the mass to s ~ s_block, freezes it for block_s seconds, and
 * returns |u| after 0.1 s and at the end of the block. */
static void block_episode(erlaw_line *l, mass *m, erlaw_ref ref, double s_block, double block_s,
                          double *u_early, double *u_late, double *u_max)
{
    double t = 0.0;
    *u_max = 0.0;
    while (erlaw_line_s(l, m->x) < s_block)
        cycle(l, m, ref, 0.0, 0);
    for (t = 0.0; t < block_s; t += DT) {
        erlaw_out o = cycle(l, m, ref, 0.0, 1);
        double un = vec3_norm(o.u);
        if (t < 0.1)
            *u_early = un;
        *u_late = un;
        *u_max = fmax(*u_max, un);
    }
}

static void test_blocked_event_vs_time(void **st)
{
    const double bound = G.a_m + G.k_v * G.v_m + G.k0;
    erlaw_line l;
    mass m;
    double e1, l1, mx1, e2, l2, mx2;
    (void)st;
    /* event law: u is constant while frozen, bounded, whatever the time */
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    block_episode(&l, &m, ERLAW_REF_MEASURED, 0.2, 20.0, &e1, &l1, &mx1);
    assert_true(mx1 <= bound);
    assert_true(fabs(l1 - e1) < 1e-9);
    /* release: resumes and completes without overshoot */
    m.s_raw_max = 0.0;
    assert_true(run_to_done(&l, &m, ERLAW_REF_MEASURED, 30.0) < 10.0);
    assert_true(m.s_raw_max <= 0.5 + TOL_S);

    /* time-referenced baseline: u grows with the block duration */
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    block_episode(&l, &m, ERLAW_REF_TIME, 0.2, 0.5, &e2, &l2, &mx2);
    assert_true(l2 > 2.0 * e2);
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    block_episode(&l, &m, ERLAW_REF_TIME, 0.2, 3.0, &e2, &l2, &mx2);
    assert_true(l2 > 3.0 * bound); /* ~k_p (s_f - s): far above the event law */
    /* release: a lurch well above the speed limit */
    m.speed_max = 0.0;
    run_to_done(&l, &m, ERLAW_REF_TIME, 30.0);
    assert_true(m.speed_max > 2.0 * G.v_m);
}

/* Largest commanded acceleration along e from rest at P0 + s_r e (after
 * a protective stop there, resumed if asked) to the goal; the speed and
 * overshoot go into m. */
static double accel_after_stop(erlaw_line *l, mass *m, double s_r, int resume)
{
    double p[3], a_max = 0.0, t;
    erlaw_out o;
    assert_int_equal(erlaw_line_init(l, P0, P1, &G), 0);
    vec3_axpy(p, P0, s_r, l->ch.e);
    mass_at(m, p);
    if (resume)
        erlaw_channel_resume(&l->ch, erlaw_line_s(l, m->x));
    for (t = 0.0; t < 10.0 && !is_done(l, m); t += DT) {
        o = cycle(l, m, ERLAW_REF_MEASURED, 0.0, 0);
        a_max = fmax(a_max, vec3_dot(o.u, l->ch.e));
    }
    assert_true(is_done(l, m));
    return a_max;
}

/* Protective-stop resume (erlaw_channel_resume): from rest at cruise the
 * event law alone asks k_v v_m (5 m/s^2, ten times a_m); resumed, the
 * profile starts afresh where the arm stands, so the demand stays within
 * the planned acceleration plus the start-up bias (and the small lag of
 * the point mass behind V_d), the speed within v_m, and the reference
 * at s_r + d is the profile's at d. */
static void test_resume_from_rest_at_planned_acceleration(void **st)
{
    erlaw_line l;
    mass m;
    erlaw_out o;
    double a_plain, a_resumed, v_d, a_d, p[3];
    (void)st;
    a_plain = accel_after_stop(&l, &m, 0.25, 0);
    assert_true(a_plain > 0.9 * G.k_v * G.v_m);
    a_resumed = accel_after_stop(&l, &m, 0.25, 1);
    printf("from rest at cruise: %.2f m/s^2 plain, %.2f resumed (a_m %.2f, k0 %.2f)\n", a_plain,
           a_resumed, G.a_m, G.k0);
    assert_true(a_resumed <= 1.2 * (G.a_m + G.k0));
    assert_true(m.speed_max <= G.v_m * 1.01);
    assert_true(m.s_raw_max <= 0.5 + TOL_S);
    /* the ramp is the profile, started at s_r */
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    erlaw_channel_resume(&l.ch, 0.25);
    vec3_axpy(p, P0, 0.25 + 0.01, l.ch.e);
    assert_int_equal(
        erlaw_line_step(&l, p, (double[3]){ 0, 0, 0 }, ERLAW_REF_MEASURED, 0.0, DT, &o), 0);
    sprofile_at(&l.ch.prof, 0.01, &a_d, &v_d);
    assert_true(fabs(o.v_d - v_d) < 1e-12 && fabs(o.a_d - a_d) < 1e-12);
}

/* External reference (docs/method/carry.md §4): a leader mass runs the event law, the
 * follower tracks s_ref = its s. The leader is frozen at cruise: the
 * follower's speed falls below 1 cm/s within 50 ms, its lead over the
 * frozen reference stays below g + v0 / (e w), it rests at the gap and
 * resumes with the leader. */
static void test_external_reference_follower_stops(void **st)
{
    const double w = ERLAW_SYNC_OMEGA_RADPS;
    /* the event law cruises at up to v_m + k0/k_v (bias surplus) */
    const double lead_bound = ERLAW_FOLLOW_GAP_M + (G.v_m + G.k0 / G.k_v) / (exp(1.0) * w) + 1e-4;
    erlaw_line lead_l, fol_l;
    mass lead, fol;
    double t, t_freeze = -1.0, t_stop = -1.0, lead_max = 0.0, s_hold = 0.0;
    int k;
    (void)st;
    assert_int_equal(erlaw_line_init(&lead_l, P0, P1, &G), 0);
    assert_int_equal(erlaw_line_init(&fol_l, P0, P1, &G), 0);
    mass_at(&lead, P0);
    mass_at(&fol, P0);
    for (t = 0.0; t < 20.0 && !(is_done(&lead_l, &lead) && is_done(&fol_l, &fol)); t += DT) {
        const int frozen = t > 2.5 && t < 4.5;
        const double s_lead = erlaw_line_s(&lead_l, lead.x);
        erlaw_out o;
        /* s* = min: whichever mass is behind holds the other */
        cycle(&lead_l, &lead, ERLAW_REF_EXTERNAL, erlaw_line_s(&fol_l, fol.x), frozen);
        o = cycle(&fol_l, &fol, ERLAW_REF_EXTERNAL, s_lead, 0);
        assert_true(o.bias == 0.0 || !o.follower);
        if (frozen && t_freeze < 0.0) {
            t_freeze = t;
            s_hold = s_lead;
            /* frozen at cruise, the follower moving at full speed */
            assert_true(vec3_norm(fol.v) > 0.8 * G.v_m);
        }
        if (frozen) {
            const double lead_now = erlaw_line_s(&fol_l, fol.x) - s_hold;
            lead_max = fmax(lead_max, lead_now);
            if (t_stop < 0.0 && vec3_norm(fol.v) < 0.01)
                t_stop = t;
            if (t > 3.5) {
                assert_true(vec3_norm(fol.v) < 1e-4);
                assert_true(fabs(lead_now - ERLAW_FOLLOW_GAP_M) < 1e-4);
            }
        }
    }
    assert_true(t_stop > t_freeze && t_stop - t_freeze <= 0.050);
    assert_true(lead_max > 0.0 && lead_max <= lead_bound);
    /* both resumed and finished after the 2 s hold */
    assert_true(t < 20.0);
    /* without the rate term (old law: V_d(s_ref) as feed-forward) the
     * follower would coast until k_p lead ~ k_v v_m: 4 cm. */
    for (k = 0; k < 2; k++) {
        erlaw_out o;
        double x[3];
        /* min semantics: a reference ahead of the arm (or past s_f) is the
         * arm's own s, and the arm is then not a follower */
        vec3_axpy(x, P0, 0.1, lead_l.ch.e);
        assert_int_equal(
            erlaw_line_step(&fol_l, x, fol.v, ERLAW_REF_EXTERNAL, k ? 7.0 : 0.3, DT, &o), 0);
        assert_true(fabs(o.s_ref_m - 0.1) < 1e-12);
        assert_int_equal(o.follower, 0);
    }
}

/* A detected block (ERLAW_REF_BLOCKED, the pose held where the block was
 * met): the command on the frozen mass is the bias alone along e, far
 * below the event law's a_m + k_v v_m + k0; pushed back or sideways, the
 * held pose (not the planned line) is restored; on release the bias moves
 * the mass on. */
/* A follower never asks for more speed than its own profile gives at its
 * reference, whatever the partner's rate: near the goal a reference
 * running at 2 v_m (the clamp) still leaves v_d on the decelerating
 * profile. Without the cap the two arms of t3 took each other's rate and
 * reached the end at 0.39 m/s. */
static void test_follower_speed_capped_by_profile(void **st)
{
    erlaw_line l;
    erlaw_out o;
    double x[3], s_ext = 0.40;
    const double v0[3] = { 0, 0, 0 };
    int k;
    (void)st;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    for (k = 0; k < 3; k++)
        x[k] = P0[k] + 0.47 / 0.5 * (P1[k] - P0[k]); /* s = 0.47 of 0.5 m */
    for (k = 0; k < 40; k++) {
        s_ext += 2.0 * G.v_m * 1e-3; /* the partner races on */
        assert_int_equal(
            erlaw_line_step(&l, x, v0, ERLAW_REF_EXTERNAL, fmin(s_ext, 0.469), 1e-3, &o), 0);
    }
    {
        double a_d, v_prof;
        sprofile_at(&l.ch.prof, o.s_ref_m, &a_d, &v_prof);
        assert_true(o.follower);
        assert_true(l.ch.v_ext > v_prof + 0.05); /* the partner is faster ... */
        assert_true(o.v_d <= v_prof + 1e-12);    /* ... the follower is not */
    }
}

static void test_blocked_leans_with_bias(void **st)
{
    erlaw_line l;
    mass m;
    double s0;
    int k;
    (void)st;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    while (erlaw_line_s(&l, m.x) < 0.2)
        cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 0);
    m.x[1] += 0.03; /* the obstacle has pushed it 3 cm off the line */
    assert_int_equal(erlaw_line_hold(&l, m.x), 0);
    for (k = 0; k < 1000; k++) {
        erlaw_out o = cycle(&l, &m, ERLAW_REF_BLOCKED, erlaw_line_s(&l, m.x), 1);
        if (k == 0)
            continue; /* the mass still had its speed this cycle */
        assert_true(fabs(vec3_norm(o.u) - o.bias) < 1e-9);
        assert_true(o.bias <= G.k0 && o.bias > 0.5 * G.k0);
        assert_true(vec3_dot(o.u, l.ch.e) > 0.0);
    }
    s0 = erlaw_line_s(&l, m.x);
    /* pushed back 1 cm by the obstacle: the ground gained is held */
    {
        erlaw_out o;
        double x[3];
        vec3_axpy(x, m.x, -0.01, l.ch.e);
        assert_int_equal(erlaw_line_step(&l, x, m.v, ERLAW_REF_BLOCKED, s0, DT, &o), 0);
        assert_true(fabs(vec3_dot(o.u, l.ch.e) - (o.bias + G.k_p * 0.01)) < 1e-9);
        /* and 1 cm sideways: pulled back to the held pose, not the line */
        vec3_copy(x, m.x);
        x[2] -= 0.01;
        assert_int_equal(erlaw_line_step(&l, x, m.v, ERLAW_REF_BLOCKED, s0, DT, &o), 0);
        assert_true(fabs(o.u[2] - G.k_p * 0.01 - o.bias * l.ch.e[2]) < 1e-9);
        assert_true(fabs(o.u[1] - o.bias * l.ch.e[1]) < 1e-9);
    }
    /* released: the bias moves it on */
    for (k = 0; k < 300; k++)
        cycle(&l, &m, ERLAW_REF_BLOCKED, s0, 0);
    assert_true(erlaw_line_s(&l, m.x) > s0 + 1e-3);
}

/* Blocked 2 cm before the goal, where eq. 7's bias has faded: the held
 * arm still leans with the full start-up bias k0 (with the faded bias a
 * released arm crept for 19 s); released, the free mass moves on to where
 * the bias balances the hold spring, k0 / k_p ahead (cartseg's hold
 * ratchet then moves the hold point on with it). */
static void test_blocked_near_goal_leans_with_k0(void **st)
{
    erlaw_line l;
    mass m;
    erlaw_out o;
    double d[3], s_f, s0;
    int k;
    (void)st;
    vec3_sub(d, P1, P0);
    s_f = vec3_norm(d);
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    mass_at(&m, P0);
    while (erlaw_line_s(&l, m.x) < s_f - 0.02)
        cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 0);
    m.v[0] = m.v[1] = m.v[2] = 0.0;
    o = cycle(&l, &m, ERLAW_REF_MEASURED, 0.0, 1);
    assert_true(o.bias < 0.5 * G.k0); /* eq. 7 has faded here */
    assert_int_equal(erlaw_line_hold(&l, m.x), 0);
    o = cycle(&l, &m, ERLAW_REF_BLOCKED, 0.0, 1);
    assert_true(fabs(o.bias - G.k0) < 1e-12); /* blocked: the full k0 */
    s0 = erlaw_line_s(&l, m.x);
    for (k = 0; k < 2000; k++)
        cycle(&l, &m, ERLAW_REF_BLOCKED, 0.0, 0);
    printf("released 2 cm before the goal: moved on %.3f mm (k0 / k_p = %.3f mm)\n",
           (erlaw_line_s(&l, m.x) - s0) * 1e3, G.k0 / G.k_p * 1e3);
    assert_true(fabs(erlaw_line_s(&l, m.x) - s0 - G.k0 / G.k_p) < 0.05 * G.k0 / G.k_p);
}

/* Rotational double integrator R' = [w]x R, w' = u about a fixed axis. */
static void test_rotation_channel(void **st)
{
    const erlaw_gains gr = { 0.5, 1.0, 8.0, 100.0, 20.0, 0.2, 5.0, 20.0 };
    const double ax0[3] = { 0.0, 0.0, 1.0 }, ax1[3] = { 0.6, 0.0, 0.8 };
    double R0[9], R1[9], R[9], w[3] = { 0, 0, 0 }, Rt[9], M[9], axis[3];
    erlaw_rot r;
    double t = 0.0, theta_f;
    int k;
    (void)st;
    rot_from_axis_angle(R0, ax0, 0.3);
    rot_from_axis_angle(M, ax1, 1.2);
    rot_mul(R1, M, R0);
    assert_int_equal(erlaw_rot_init(&r, R0, R1, &gr), 0);
    theta_f = erlaw_channel_length(&r.ch);
    assert_true(fabs(theta_f - 1.2) < 1e-9);
    for (k = 0; k < 9; k++)
        R[k] = R0[k];
    while (t < 20.0 && !erlaw_done(erlaw_rot_angle(&r, R), theta_f, vec3_norm(w), 1e-3, 5e-3)) {
        erlaw_out o;
        double dR[9], Rn[9], wn;
        assert_int_equal(erlaw_rot_step(&r, R, w, ERLAW_REF_MEASURED, 0.0, DT, &o), 0);
        for (k = 0; k < 3; k++)
            w[k] += o.u[k] * DT;
        wn = vec3_norm(w);
        if (wn > 0.0) {
            double wa[3];
            vec3_scale(wa, w, 1.0 / wn);
            rot_from_axis_angle(dR, wa, wn * DT);
        } else {
            rot_identity(dR);
        }
        rot_mul(Rn, dR, R);
        for (k = 0; k < 9; k++)
            R[k] = Rn[k];
        t += DT;
    }
    assert_true(t < 10.0);
    rot_transpose(Rt, R1);
    rot_mul(M, R, Rt);
    assert_true(rot_to_axis_angle(axis, M) < 2e-3);
}

static void test_predicates(void **st)
{
    erlaw_block b;
    int k, blocked = 0;
    (void)st;
    assert_true(erlaw_done(0.4995, 0.5, 0.001, 1e-3, 5e-3));
    assert_false(erlaw_done(0.49, 0.5, 0.001, 1e-3, 5e-3));
    assert_false(erlaw_done(0.5, 0.5, 0.01, 1e-3, 5e-3));
    erlaw_block_reset(&b, 0.0);
    /* advancing: never blocked */
    for (k = 0; k < 2000; k++)
        blocked |= erlaw_block_update(&b, k * 1e-5, 1, DT, 1e-4, 0.5);
    assert_int_equal(blocked, 0);
    /* stuck while commanded: blocked after 0.5 s, not before */
    assert_int_equal(erlaw_block_update(&b, 0.03, 1, DT, 1e-4, 0.5), 0);
    for (k = 0; k < 499; k++)
        assert_int_equal(erlaw_block_update(&b, 0.03, 1, DT, 1e-4, 0.5), 0);
    for (k = 0; k < 10; k++)
        blocked = erlaw_block_update(&b, 0.03, 1, DT, 1e-4, 0.5);
    assert_int_equal(blocked, 1);
    /* moving again clears it; not commanding never reports */
    assert_int_equal(erlaw_block_update(&b, 0.031, 1, DT, 1e-4, 0.5), 0);
    for (k = 0; k < 2000; k++)
        assert_int_equal(erlaw_block_update(&b, 0.031, 0, DT, 1e-4, 0.5), 0);
}

static void test_invalid_input(void **st)
{
    erlaw_gains bad = G;
    erlaw_line l;
    erlaw_out o;
    double nanv[3] = { NAN, 0, 0 }, z[3] = { 0, 0, 0 };
    (void)st;
    bad.v_m = 0.0;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &bad), ERLAW_ERR_ARG);
    bad = G;
    bad.k2 = INFINITY;
    assert_int_equal(erlaw_line_init(&l, P0, P1, &bad), ERLAW_ERR_ARG);
    assert_int_equal(erlaw_line_init(&l, nanv, P1, &G), ERLAW_ERR_ARG);
    assert_int_equal(erlaw_line_init(&l, P0, P1, &G), 0);
    assert_int_equal(erlaw_line_step(&l, nanv, z, ERLAW_REF_MEASURED, 0, DT, &o), ERLAW_ERR_ARG);
    assert_true(vec3_norm(o.u) == 0.0);
    assert_int_equal(erlaw_line_step(&l, P0, z, ERLAW_REF_EXTERNAL, NAN, DT, &o), ERLAW_ERR_ARG);
    assert_int_equal(erlaw_line_step(&l, P0, z, (erlaw_ref)9, 0, DT, &o), ERLAW_ERR_ARG);
    assert_int_equal(erlaw_line_step(&l, P0, z, ERLAW_REF_TIME, 0, -1.0, &o), ERLAW_ERR_ARG);
    /* zero-length segment holds p0 */
    assert_int_equal(erlaw_line_init(&l, P0, P0, &G), 0);
    assert_int_equal(erlaw_line_step(&l, P0, z, ERLAW_REF_MEASURED, 0, DT, &o), 0);
    assert_true(vec3_norm(o.u) < G.k0);
    assert_true(erlaw_done(o.s_m, erlaw_channel_length(&l.ch), 0.0, TOL_S, TOL_V));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reaches_goal_at_rest),
        cmocka_unit_test(test_cross_track_error_decays),
        cmocka_unit_test(test_bias_is_needed),
        cmocka_unit_test(test_short_segment_starts_against_disturbance),
        cmocka_unit_test(test_blocked_event_vs_time),
        cmocka_unit_test(test_resume_from_rest_at_planned_acceleration),
        cmocka_unit_test(test_external_reference_follower_stops),
        cmocka_unit_test(test_follower_speed_capped_by_profile),
        cmocka_unit_test(test_blocked_leans_with_bias),
        cmocka_unit_test(test_blocked_near_goal_leans_with_k0),
        cmocka_unit_test(test_rotation_channel),
        cmocka_unit_test(test_predicates),
        cmocka_unit_test(test_invalid_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
