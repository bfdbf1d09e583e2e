/* Unit tests for behaviour: closed-loop error dynamics of move-to-goal and
 * keep-formation checked by central finite differences on the exact
 * kinematic model, saturation, avoid, dead-zone alternation, narrow-passage
 * detection and the three blending modes; the slot-tracking handover of
 * the formation command (far from the slot). The control point O lies at
 * a signed distance d behind the axle: the error dynamics hold for both
 * signs; the seed law's heading dynamics are stable only with O ahead
 * (d < 0), shown by the linearisation and in closed loop. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "behaviour.h"
#include "prng.h"

static double urand(prng_state *r, double lo, double hi)
{
    return lo + (hi - lo) * prng_uniform(r);
}

/* O pose after moving C with u for dt (dt may be negative). */
/* A signed d with 0.05 <= |d| <= 0.4 (O behind or ahead of the axle). */
static double urand_d(prng_state *r)
{
    const double m = urand(r, 0.05, 0.4);
    return prng_uniform(r) < 0.5 ? -m : m;
}

static pose2 o_after(const pose2 *o, const unicycle_cmd *u, double d, double dt)
{
    pose2 c, out;
    unicycle_c_from_o(&c, o, d);
    unicycle_step_exact(&c, u->v_mps, u->w_radps, dt);
    unicycle_o_from_c(&out, &c, d);
    return out;
}

static void test_goal_error_dynamics(void **state)
{
    prng_state rng;
    const double h = 1e-5;
    int n = 0, tries = 0;
    (void)state;
    prng_seed(&rng, 3);
    while (n < 500 && tries < 100000) {
        const double d = urand_d(&rng), a1 = urand(&rng, 0.1, 2.0), a2 = urand(&rng, 0.1, 3.0);
        pose2 o = { urand(&rng, -5, 5), urand(&rng, -5, 5), urand(&rng, -VEC2_PI, VEC2_PI) };
        const double g[2] = { urand(&rng, -5, 5), urand(&rng, -5, 5) };
        double r, phi, rp, php, rm, phm;
        unicycle_cmd u;
        pose2 op, om;
        tries++;
        behaviour_goal_polar(&r, &phi, &o, g);
        if (r * cos(phi) - d < 0.1 || fabs(phi) > 3.0)
            continue;
        assert_int_equal(behaviour_goal_raw(&u, r, phi, d, a1, a2), 0);
        op = o_after(&o, &u, d, h);
        om = o_after(&o, &u, d, -h);
        behaviour_goal_polar(&rp, &php, &op, g);
        behaviour_goal_polar(&rm, &phm, &om, g);
        assert_true(fabs((rp - rm) / (2 * h) + a1 * r) < 1e-5 * (1 + fabs(a1 * r)));
        assert_true(fabs(vec2_angle_diff_rad(php, phm) / (2 * h) + a2 * phi) <
                    1e-5 * (1 + fabs(u.w_radps)));
        n++;
    }
    assert_int_equal(n, 500);
}

static void test_goal_singular_and_turn(void **state)
{
    behaviour_params p;
    unicycle_cmd u;
    pose2 o = { 0, 0, 0 };
    double g[2] = { -2.0, 0.1 }; /* behind, slightly left: r cos phi < d */
    (void)state;
    behaviour_params_default(&p);
    /* eq. 5 is singular at r cos phi = d: with O behind (d > 0) for a goal
     * ahead, with O ahead (d < 0) only for a goal behind */
    assert_int_equal(behaviour_goal_raw(&u, 0.15, 0.0, 0.15, 1, 1), BEHAVIOUR_ERR_ARG);
    assert_int_equal(behaviour_goal_raw(&u, 0.15, VEC2_PI, -0.15, 1, 1), BEHAVIOUR_ERR_ARG);
    assert_int_equal(behaviour_goal_raw(&u, 0.15, 0.0, -0.15, 1, 1), 0);
    assert_int_equal(behaviour_goal(&u, &o, g, &p), BEH_GOAL_TURN);
    assert_true(u.v_mps == 0.0 && u.w_radps > 0.0 && u.w_radps <= p.w_max_radps);
    g[0] = 0.1;
    g[1] = 0.1;
    assert_int_equal(behaviour_goal(&u, &o, g, &p), BEH_GOAL_REACHED);
    assert_true(u.v_mps == 0.0 && u.w_radps == 0.0);
    g[0] = NAN;
    assert_int_equal(behaviour_goal(&u, &o, g, &p), BEHAVIOUR_ERR_ARG);
}

static void test_goal_saturated_closed_loop_reaches(void **state)
{
    /* Far goal, behind and to the side: saturated commands stay in limits
     * and the robot arrives. */
    behaviour_params p;
    pose2 o = { 0, 0, 2.5 };
    const double g[2] = { 8.0, -3.0 };
    int k, st = -1;
    (void)state;
    behaviour_params_default(&p);
    for (k = 0; k < 20 * 120; k++) {
        unicycle_cmd u;
        st = behaviour_goal(&u, &o, g, &p);
        assert_true(st >= 0);
        assert_true(fabs(u.v_mps) <= p.v_max_mps + 1e-12 &&
                    fabs(u.w_radps) <= p.w_max_radps + 1e-12);
        if (st == BEH_GOAL_REACHED)
            break;
        o = o_after(&o, &u, p.d_m, 0.05);
    }
    assert_int_equal(st, BEH_GOAL_REACHED);
}

/* Reference R0 moving as a unicycle O point with (V0, w0). */
static unicycle_state ref_after(const unicycle_state *r, double d, double dt)
{
    pose2 o = { r->x_m, r->y_m, r->theta_rad };
    unicycle_cmd u = { r->v_mps, r->w_radps };
    unicycle_state out = *r;
    o = o_after(&o, &u, d, dt);
    out.x_m = o.x_m;
    out.y_m = o.y_m;
    out.theta_rad = o.theta_rad;
    return out;
}

static void test_formation_error_dynamics(void **state)
{
    prng_state rng;
    behaviour_params p;
    const double h = 1e-5;
    int n = 0, tries = 0;
    (void)state;
    prng_seed(&rng, 7);
    behaviour_params_default(&p);
    p.v_fm_max_mps = p.w_fm_max_radps = 1e9; /* check the unsaturated law */
    while (n < 500 && tries < 100000) {
        unicycle_state ref = { urand(&rng, -3, 3), urand(&rng, -3, 3),
                               urand(&rng, -VEC2_PI, VEC2_PI), urand(&rng, -0.5, 0.8),
                               urand(&rng, -0.8, 0.8) };
        pose2 o = { ref.x_m + urand(&rng, -3, 3), ref.y_m + urand(&rng, -3, 3),
                    urand(&rng, -VEC2_PI, VEC2_PI) };
        const double l_d = urand(&rng, 0, 2), phi_d = urand(&rng, -VEC2_PI, VEC2_PI);
        double l, phi, lp, php, lm, phm, Rd;
        unicycle_cmd u;
        unicycle_state rp, rm;
        pose2 op, om;
        tries++;
        p.d_m = urand_d(&rng);
        p.b1 = urand(&rng, 0.1, 2.0);
        p.b2 = urand(&rng, 0.1, 2.0);
        behaviour_formation_polar(&l, &phi, &o, &ref);
        if (l < 0.3 || fabs(phi) > 3.0)
            continue;
        assert_int_equal(behaviour_formation(&u, &Rd, &o, &ref, l_d, phi_d, &p), 0);
        assert_true(fabs(Rd - behaviour_slot_error(l, phi, l_d, phi_d)) < 1e-12);
        op = o_after(&o, &u, p.d_m, h);
        om = o_after(&o, &u, p.d_m, -h);
        rp = ref_after(&ref, p.d_m, h);
        rm = ref_after(&ref, p.d_m, -h);
        behaviour_formation_polar(&lp, &php, &op, &rp);
        behaviour_formation_polar(&lm, &phm, &om, &rm);
        assert_true(fabs((lp - lm) / (2 * h) - p.b1 * (l_d - l)) <
                    1e-5 * (1 + fabs(u.v_mps) + fabs(u.w_radps)));
        assert_true(
            fabs(vec2_angle_diff_rad(php, phm) / (2 * h) - p.b2 * vec2_wrap_rad(phi_d - phi)) <
            1e-5 * (1 + fabs(u.v_mps) + fabs(u.w_radps)) / l);
        n++;
    }
    assert_int_equal(n, 500);
}

static void test_formation_converges_saturated(void **state)
{
    /* Reference on a circle; the follower ends up in its slot. */
    behaviour_params p;
    unicycle_state ref = { 0, 0, 0, 0.2, 0.1 };
    pose2 o = { -1.0, 1.5, 1.0 };
    double Rd = 1e9;
    int k;
    (void)state;
    behaviour_params_default(&p);
    for (k = 0; k < 20 * 60; k++) {
        unicycle_cmd u;
        assert_int_equal(behaviour_formation(&u, &Rd, &o, &ref, 0.8, -VEC2_PI / 2, &p), 0);
        assert_true(fabs(u.v_mps) <= p.v_fm_max_mps && fabs(u.w_radps) <= p.w_fm_max_radps);
        o = o_after(&o, &u, p.d_m, 0.05);
        ref = ref_after(&ref, p.d_m, 0.05);
    }
    assert_true(Rd < 0.01);
}

/* Slot error after 60 s of following a reference driving straight at
 * 0.3 m/s, V never negative (the Pioneer has no rear sonar: the rover
 * clips V >= 0), starting from a robot pushed to the side of its slot
 * (left-rear slot of a triangle, robot 2 m further left, 1 m ahead, nose
 * turned 30 deg away, as after passing an obstacle on the wrong side).
 * track = 1: behaviour_formation_track; 0: the seed law alone; d_m the
 * signed O offset. Also the largest distance from the slot on the way. */
static double slot_follow(int track, double d_m, double *worst_m)
{
    behaviour_params p;
    unicycle_state ref = { 0, 0, 0, 0.3, 0.0 };
    const double l_d = hypot(0.29, 0.5), phi_d = atan2(0.5, -0.29);
    pose2 o = { 0.7, 2.5, 0.5 };
    double Rd = 0.0;
    int k;
    behaviour_params_default(&p);
    p.d_m = d_m;
    *worst_m = 0.0;
    for (k = 0; k < 20 * 60; k++) {
        unicycle_cmd u;
        if (track)
            assert_int_equal(behaviour_formation_track(&u, &Rd, &o, &ref, l_d, phi_d, &p), 0);
        else
            assert_int_equal(behaviour_formation(&u, &Rd, &o, &ref, l_d, phi_d, &p), 0);
        if (u.v_mps < 0.0)
            u.v_mps = 0.0;
        assert_true(u.v_mps <= p.v_fm_max_mps && fabs(u.w_radps) <= p.w_fm_max_radps);
        if (Rd > *worst_m)
            *worst_m = Rd;
        o = o_after(&o, &u, p.d_m, 0.05);
        ref.x_m += ref.v_mps * 0.05;
    }
    return Rd;
}

static void test_formation_track_recovers_far_slot(void **state)
{
    double worst_seed, worst_track, end_seed, end_track;
    (void)state;
    /* the seed law moves O by swinging the tail: far off the slot with
     * V >= 0 the robot turns away and orbits the team (the obstacles-world
     * failure); tracking steers the nose to the slot and settles */
    double end_ahead, worst_ahead;
    end_seed = slot_follow(0, 0.15, &worst_seed);
    end_track = slot_follow(1, 0.15, &worst_track);
    end_ahead = slot_follow(0, -0.15, &worst_ahead);
    print_message(
        "seed law, O behind: end %.2f m, worst %.2f m; O ahead: end %.3f m, worst %.2f m; "
        "track: end %.3f m, worst %.2f m\n",
        end_seed, worst_seed, end_ahead, worst_ahead, end_track, worst_track);
    assert_true(end_track < 0.05);
    assert_true(worst_track < 2.6); /* never further than the start */
    assert_true(end_seed > 1.0);    /* O behind: the robot orbits off */
    assert_true(end_ahead < 0.01);  /* O ahead: the seed law settles */
    assert_true(worst_ahead < 2.6);
}

/* On the slot (l = l_d, phi = phi_d), reference straight at V0: the seed
 * law's w as a function of the heading is (V0 / d) sin(theta - theta0)
 * (docs/formation.md), so the linearised heading dynamics are
 * theta' = (V0 / d) (theta - theta0): unstable with O behind (d > 0),
 * stable with O ahead (d < 0). Checked against the law itself, and its
 * slope by a central difference. */
static void test_seed_heading_linearisation(void **state)
{
    const double ds[2] = { 0.15, -0.15 }, v0 = 0.3, h = 1e-6;
    unicycle_state ref = { 1.0, -2.0, 0.4, 0.3, 0.0 };
    const double l_d = 1.2, phi_d = 2.1;
    int i, k;
    (void)state;
    for (i = 0; i < 2; i++) {
        behaviour_params p;
        pose2 o;
        unicycle_cmd up, um;
        double slope;
        behaviour_params_default(&p);
        p.d_m = ds[i];
        p.v_fm_max_mps = p.w_fm_max_radps = 1e9;
        o.x_m = ref.x_m + l_d * cos(phi_d + ref.theta_rad);
        o.y_m = ref.y_m + l_d * sin(phi_d + ref.theta_rad);
        for (k = -6; k <= 6; k++) {
            unicycle_cmd u;
            o.theta_rad = ref.theta_rad + 0.25 * k;
            assert_int_equal(behaviour_formation(&u, NULL, &o, &ref, l_d, phi_d, &p), 0);
            assert_true(fabs(u.w_radps - v0 / p.d_m * sin(0.25 * k)) < 1e-9);
        }
        o.theta_rad = ref.theta_rad + h;
        behaviour_formation(&up, NULL, &o, &ref, l_d, phi_d, &p);
        o.theta_rad = ref.theta_rad - h;
        behaviour_formation(&um, NULL, &o, &ref, l_d, phi_d, &p);
        slope = (up.w_radps - um.w_radps) / (2 * h);
        assert_true(fabs(slope - v0 / p.d_m) < 1e-6);
        /* the sign is the point: O behind diverges, O ahead converges */
        assert_true(p.d_m > 0.0 ? slope > 0.0 : slope < 0.0);
    }
}

/* Closed loop on the slot, reference straight at 0.3 m/s, heading 0.05 rad
 * off, unsaturated and unclipped: O stays on its slot in both cases (the
 * law linearises the output exactly), but with O behind the heading runs
 * away to the other equilibrium, driving backwards; with O ahead it
 * settles on the team heading with V = V0. */
static void test_seed_heading_closed_loop(void **state)
{
    const double ds[2] = { 0.15, -0.15 };
    int i, k;
    (void)state;
    for (i = 0; i < 2; i++) {
        behaviour_params p;
        unicycle_state ref = { 0, 0, 0, 0.3, 0.0 };
        pose2 o = { 0.0, 1.0, 0.05 };
        unicycle_cmd u = { 0, 0 };
        double Rd = 0.0, worst = 0.0;
        behaviour_params_default(&p);
        p.d_m = ds[i];
        p.v_fm_max_mps = p.w_fm_max_radps = 1e9;
        for (k = 0; k < 2000; k++) {
            assert_int_equal(behaviour_formation(&u, &Rd, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
            if (Rd > worst)
                worst = Rd;
            o = o_after(&o, &u, p.d_m, 0.005);
            ref.x_m += ref.v_mps * 0.005;
        }
        print_message(
            "d %+.2f: heading error after 10 s %.3f rad, V %.3f, worst slot error %.4f m\n", p.d_m,
            o.theta_rad, u.v_mps, worst);
        assert_true(worst < 0.01);
        if (p.d_m > 0.0) {
            assert_true(fabs(vec2_wrap_rad(o.theta_rad)) > 3.0);
            assert_true(u.v_mps < -0.25);
        } else {
            assert_true(fabs(o.theta_rad) < 1e-4);
            assert_true(fabs(u.v_mps - 0.3) < 1e-3);
        }
    }
}

/* The seed law as flown (O ahead, V >= 0) from offsets behind, beside and
 * ahead of the slot, near (0.15 m, where nothing saturates or clips, so the
 * seed's error dynamics l' = b1 (l_d - l), phi' = b2 (phi_d - phi) must
 * hold along the whole run; heading 0.1 rad off) and far (1-1.5 m, heading
 * 0.3 rad off):
 * V never negative, the robot ends on its slot on the team heading. */
static void test_seed_ahead_converges_from_offsets(void **state)
{
    /* slot (l_d, phi_d) = (1, 90 deg): at (0, 1) relative to R0 */
    static const double start[6][2] = { { -0.15, 1.0 }, { 0.0, 1.15 },
                                        { 0.15, 1.0 }, /* behind, beside, ahead */
                                        { -1.5, 1.0 },  { 0.0, 2.5 },
                                        { 1.0, 1.0 } };
    int s, k;
    (void)state;
    for (s = 0; s < 6; s++) {
        behaviour_params p;
        unicycle_state ref = { 0, 0, 0, 0.3, 0.0 };
        pose2 o = { start[s][0], start[s][1], s < 3 ? 0.1 : 0.3 };
        const double dt = 0.002;
        double l0, phi0, Rd = 0.0, dyn_err = 0.0, vmin = 1e9, vmax = 0.0, wmax = 0.0;
        behaviour_params_default(&p);
        assert_true(p.d_m < 0.0);
        behaviour_formation_polar(&l0, &phi0, &o, &ref);
        for (k = 0; k < (int)(60.0 / dt); k++) {
            unicycle_cmd u;
            double l, phi;
            assert_int_equal(behaviour_formation_seed(&u, &Rd, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
            if (u.v_mps < vmin)
                vmin = u.v_mps;
            if (u.v_mps > vmax)
                vmax = u.v_mps;
            if (fabs(u.w_radps) > wmax)
                wmax = fabs(u.w_radps);
            behaviour_formation_polar(&l, &phi, &o, &ref);
            if (s < 3) {
                /* closed form of the seed's error dynamics */
                const double t = k * dt;
                dyn_err = fmax(dyn_err, fabs(l - (1.0 + (l0 - 1.0) * exp(-p.b1 * t))));
                dyn_err = fmax(dyn_err,
                               fabs(phi - (VEC2_PI / 2 + (phi0 - VEC2_PI / 2) * exp(-p.b2 * t))));
            }
            o = o_after(&o, &u, p.d_m, dt);
            ref.x_m += ref.v_mps * dt;
        }
        print_message("start %d: end slot error %.4f m, heading %.4f rad, min V %.3f, "
                      "max |w| %.3f, error-dynamics residual %.4f\n",
                      s, Rd, o.theta_rad, vmin, wmax, dyn_err);
        assert_true(vmin >= 0.0);
        assert_true(Rd < 0.005);
        assert_true(fabs(vec2_wrap_rad(o.theta_rad)) < 0.005);
        if (s < 3) {
            /* never clipped nor saturated: the seed's law as is */
            assert_true(vmin > 0.0 && vmax < p.v_fm_max_mps && wmax < p.w_fm_max_radps);
            assert_true(dyn_err < 0.002);
        }
    }
}

/* A robot facing backward (heading -+2.94 rad, the team heading 0, the
 * team moving at 0.3 m/s), its slot behind it: the law's O velocity is
 * behind it, V is floored at 0, and it turns the short way onto the team
 * heading (left from -2.94, right from +2.94) whatever the slot's small
 * sideways offset; the law's own turn (the sideways part of the backward
 * velocity over |d|) changes sign with that offset: in a blend it pulled
 * against the goal behaviour's turn as often as with it. From there it
 * takes its slot with V >= 0. With the team standing (V0 = 0) the turn is
 * the law's own: there is no slot coming to wait for. */
static void test_seed_backward_turns_onto_team_heading(void **state)
{
    static const double th0[2] = { -2.94, 2.94 };
    const double dt = 0.002;
    int s, k, law_left = 0, law_right = 0;
    (void)state;
    for (s = 0; s < 2; s++) {
        behaviour_params p;
        unicycle_state ref = { 0, 0, 0, 0.3, 0.0 };
        pose2 o;
        unicycle_cmd u, law;
        double Rd = 0.0, vmin = 1e9, y;
        behaviour_params_default(&p);
        for (y = 0.7; y <= 1.3 + 1e-9; y += 0.05) { /* the slot (0, 1) from beside to 0.3 m off */
            o = (pose2){ -0.4, y, th0[s] };
            assert_int_equal(behaviour_formation_seed(&u, &Rd, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
            assert_int_equal(behaviour_formation(&law, NULL, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
            if (!(law.v_mps < 0.0))
                continue; /* O may move ahead: the law as is */
            assert_true(u.v_mps == 0.0 && u.w_radps * -th0[s] > 0.0);
            if (law.w_radps > 0.0)
                law_left++;
            else
                law_right++;
        }
        o = (pose2){ -0.4, 1.2, th0[s] };
        for (k = 0; k < (int)(40.0 / dt); k++) {
            assert_int_equal(behaviour_formation_seed(&u, &Rd, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
            if (u.v_mps < vmin)
                vmin = u.v_mps;
            o = o_after(&o, &u, p.d_m, dt);
            ref.x_m += ref.v_mps * dt;
        }
        print_message("from heading %+.2f: end slot error %.4f m, heading %.4f, min V %.3f\n",
                      th0[s], Rd, o.theta_rad, vmin);
        assert_true(vmin >= 0.0);
        assert_true(Rd < 0.005 && fabs(vec2_wrap_rad(o.theta_rad)) < 0.005);
        /* the team standing: the law's own turn */
        ref.v_mps = 0.0;
        ref.x_m = 0.0;
        o = (pose2){ -0.6, 1.2, th0[s] }; /* the slot behind it */
        assert_int_equal(behaviour_formation_seed(&u, &Rd, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
        assert_int_equal(behaviour_formation(&law, NULL, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
        assert_true(law.v_mps < 0.0);
        assert_true(u.v_mps == 0.0 && fabs(u.w_radps - law.w_radps) < 1e-12);
    }
    print_message("the law's own turn over those offsets: %d left, %d right\n", law_left,
                  law_right);
    assert_true(law_left + law_right >= 20 && law_left > 0 && law_right > 0);
}

static void test_formation_track_bands(void **state)
{
    behaviour_params p;
    unicycle_state ref = { 0, 0, 0, 0.3, 0.0 };
    unicycle_cmd a, b;
    double Rd_a, Rd_b;
    pose2 o = { 0.05, 1.02, 0.03 }; /* slot (0, 1): 0.05 m off */
    (void)state;
    behaviour_params_default(&p);
    p.d_m = 0.15; /* O behind: the seed law's wrong turn */
    /* the slot error reported is the seed law's R_d */
    assert_int_equal(behaviour_formation(&a, &Rd_a, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
    assert_int_equal(behaviour_formation_track(&b, &Rd_b, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
    assert_true(Rd_a < p.form_near_m && Rd_a == Rd_b);
    /* near the slot, nose 0.03 rad left of the team heading and O 0.02 m
     * left of the slot: turn right, back onto the team heading (the seed
     * law turns left here: it moves O right by swinging the tail) */
    print_message("near: seed w %.3f, track w %.3f\n", a.w_radps, b.w_radps);
    assert_true(b.w_radps < 0.0 && a.w_radps > 0.0);
    /* O ahead: the seed law turns right too */
    p.d_m = -0.15;
    assert_int_equal(behaviour_formation(&a, &Rd_a, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
    assert_true(a.w_radps < 0.0);
    assert_true(fabs(b.v_mps - ref.v_mps) < 0.05);
    /* far, slot ahead to the right: drive and turn toward it */
    o = (pose2){ -3.0, 3.0, 0.0 };
    assert_int_equal(behaviour_formation_track(&b, &Rd_b, &o, &ref, 1.0, -VEC2_PI / 2, &p), 0);
    assert_true(b.v_mps > 0.0 && b.w_radps < 0.0);
    /* slot 1.5 m behind: wait (V = 0), never reverse */
    o = (pose2){ 1.5, 1.0, 0.0 };
    assert_int_equal(behaviour_slot_track(&b, &o, &ref, 1.0, VEC2_PI / 2, &p), 0);
    assert_true(b.v_mps == 0.0);
    /* bad input */
    o.x_m = NAN;
    assert_int_equal(behaviour_formation_track(&b, &Rd_b, &o, &ref, 1.0, 0.0, &p),
                     BEHAVIOUR_ERR_ARG);
    assert_true(b.v_mps == 0.0 && b.w_radps == 0.0);
    behaviour_params_default(&p);
    p.form_far_m = p.form_near_m;
    assert_int_equal(behaviour_params_validate(&p), BEHAVIOUR_ERR_ARG);
    behaviour_params_default(&p);
    p.d_st_rear_max_m = -0.1;
    assert_int_equal(behaviour_params_validate(&p), BEHAVIOUR_ERR_ARG);
    p.d_st_rear_max_m = NAN;
    assert_int_equal(behaviour_params_validate(&p), BEHAVIOUR_ERR_ARG);
}

static void ring(double r[8], double v)
{
    int i;
    for (i = 0; i < 8; i++)
        r[i] = v;
}

static void test_sonar_groups_and_avoid(void **state)
{
    behaviour_params p;
    sonar_groups g;
    double r[8];
    unicycle_cmd u;
    (void)state;
    behaviour_params_default(&p);
    ring(r, 5.0);
    r[1] = 0.9;
    r[6] = 1.4;
    r[3] = NAN;
    behaviour_sonar_groups(&g, r);
    assert_true(g.right_front_m == 0.9 && g.left_front_m == 1.4 && g.front_m == 0.0 &&
                g.min_m == 0.0);
    ring(r, 5.0);
    behaviour_sonar_groups(&g, r);
    assert_int_equal(behaviour_avoid(&u, &g, 0.33, 1.0, &p), 0);
    assert_true(u.v_mps == 0.33 && u.w_radps == 0.0);
    r[1] = 0.7;
    r[4] = 1.2; /* obstacle right-front: turn left */
    behaviour_sonar_groups(&g, r);
    assert_int_equal(behaviour_avoid(&u, &g, 0.33, 1.0, &p), 1);
    assert_true(fabs(u.v_mps - p.k_v * 1.2) < 1e-12);
    assert_true(u.w_radps > 0.0 && u.w_radps <= p.w_max_radps);
    ring(r, 5.0);
    r[6] = 0.5; /* mirror: turn right, clamped */
    behaviour_sonar_groups(&g, r);
    behaviour_avoid(&u, &g, 0.33, 1.0, &p);
    assert_true(u.w_radps == -p.w_max_radps);
}

static void test_d_st(void **state)
{
    behaviour_params p;
    (void)state;
    behaviour_params_default(&p);
    /* abreast slot at +-90 deg: the seed's form gives d_s + D/2 */
    assert_true(fabs(behaviour_d_st(&p, 2.0, 1.0, VEC2_PI / 2) - (p.d_s_m + 1.0)) < 1e-12);
    /* behind R0: the seed's form within one spacing (a triangle of three's
     * rear row), then no more (a column of twelve's rearmost, 5.5 m) */
    assert_true(fabs(behaviour_d_st(&p, 2.0, 1.0, VEC2_PI * 5.0 / 6.0) -
                     (p.d_s_m + 1.0 + sqrt(3.0) / 2.0)) < 1e-12);
    assert_true(fabs(behaviour_d_st(&p, 0.38, 5.5, VEC2_PI) - (p.d_s_m + 0.19 + 1.0)) < 1e-12);
    /* ahead of R0 unbounded: the seed's form */
    assert_true(fabs(behaviour_d_st(&p, 6.0, 2.0, 0.0) - (p.d_s_m + 1.0)) < 1e-12);
    /* lateral variant: edge robot needs only d_s, centre d_s + D/2 */
    p.d_st_lateral = 1;
    assert_true(fabs(behaviour_d_st(&p, 2.0, 1.0, VEC2_PI / 2) - p.d_s_m) < 1e-12);
    assert_true(fabs(behaviour_d_st(&p, 2.0, 0.0, 0.0) - (p.d_s_m + 1.0)) < 1e-12);
    /* never below d_s */
    assert_true(behaviour_d_st(&p, 0.0, 3.0, VEC2_PI / 2) == p.d_s_m);
}

static void test_dead_zone_alternation(void **state)
{
    behaviour_params p;
    behaviour_exception e;
    sonar_groups blocked = { 0.3, 0.3, 0.3, 0.3, 0.3, 0.3 }, clear = { 2, 2, 2, 2, 2, 0.3 };
    unicycle_cmd u;
    int k, entry;
    (void)state;
    behaviour_params_default(&p);
    behaviour_exception_init(&e);
    /* shorter than the threshold, then a free direction: timer clears */
    for (k = 0; k < 15; k++)
        assert_int_equal(behaviour_exception_step(&e, &u, &blocked, 0.1, &p), 0);
    assert_int_equal(behaviour_exception_step(&e, &u, &clear, 0.1, &p), 0);
    assert_true(e.blocked_s == 0.0);
    for (entry = 1; entry <= 4; entry++) {
        for (k = 0; k < 19; k++)
            assert_int_equal(behaviour_exception_step(&e, &u, &blocked, 0.1, &p), 0);
        assert_int_equal(behaviour_exception_step(&e, &u, &blocked, 0.1 + 1e-9, &p), 1);
        assert_int_equal(e.entries, entry);
        assert_true(u.v_mps == p.v_k_mps);
        assert_true(u.w_radps == ((entry % 2) ? p.w_k_radps : -p.w_k_radps));
        /* stays active while the front stays blocked */
        assert_int_equal(behaviour_exception_step(&e, &u, &blocked, 0.1, &p), 1);
        assert_int_equal(behaviour_exception_step(&e, &u, &clear, 0.1, &p), 0);
        assert_true(u.v_mps == 0.0 && u.w_radps == 0.0);
    }
    assert_int_equal(behaviour_exception_step(&e, &u, &clear, -1.0, &p), BEHAVIOUR_ERR_ARG);
}

static void test_passage_narrow(void **state)
{
    behaviour_params p;
    sonar_groups g = { 5, 5, 5, 0.5, 0.6, 0.5 };
    (void)state;
    behaviour_params_default(&p);
    /* corridor 0.5 + 0.6 + 0.38 = 1.48 m */
    assert_int_equal(behaviour_passage_narrow(&g, 1.48 - p.passage_safety_m + 0.01, &p), 1);
    assert_int_equal(behaviour_passage_narrow(&g, 1.48 - p.passage_safety_m - 0.01, &p), 0);
}

static behaviour_inputs sample_inputs(void)
{
    behaviour_inputs in;
    in.u[BEH_GOAL].v_mps = 0.5;
    in.u[BEH_GOAL].w_radps = 0.2;
    in.u[BEH_FORMATION].v_mps = 0.1;
    in.u[BEH_FORMATION].w_radps = -0.4;
    in.u[BEH_AVOID].v_mps = 0.3;
    in.u[BEH_AVOID].w_radps = 0.9;
    in.u[BEH_EXCEPTION].v_mps = 0.0;
    in.u[BEH_EXCEPTION].w_radps = -0.6;
    in.exception_active = 0;
    in.avoid_active = 0;
    in.R_d_m = 0.45;
    in.d_st_m = 1.2;
    in.min_range_m = 2.4;
    return in;
}

static void test_blend_weighted(void **state)
{
    behaviour_params p;
    behaviour_inputs in = sample_inputs();
    behaviour_blender b;
    double s = 0, v = 0, w = 0;
    int i;
    (void)state;
    behaviour_params_default(&p);
    p.k2 = 0.7;
    p.k3 = 1.3;
    p.k4 = 0.4;
    assert_int_equal(behaviour_blend(&b, &in, BEH_BLEND_WEIGHTED, &p), 0);
    assert_true(b.weight_raw[BEH_EXCEPTION] == 0.0);
    assert_true(fabs(b.weight_raw[BEH_GOAL] - p.k2) < 1e-15);
    assert_true(fabs(b.weight_raw[BEH_FORMATION] * p.d_r_m / in.R_d_m - p.k3) < 1e-12);
    assert_true(fabs(b.weight_raw[BEH_AVOID] * in.min_range_m / in.d_st_m - p.k4) < 1e-12);
    for (i = 0; i < BEH_COUNT; i++) {
        s += b.weight[i];
        v += b.weight_raw[i] * in.u[i].v_mps;
        w += b.weight_raw[i] * in.u[i].w_radps;
        assert_true(fabs(b.weight[i] * (b.weight_raw[0] + b.weight_raw[1] + b.weight_raw[2]) -
                         b.weight_raw[i]) < 1e-12);
        assert_true(b.weight[i] <= b.weight[b.winner]);
    }
    assert_true(fabs(s - 1.0) < 1e-12);
    s = b.weight_raw[0] + b.weight_raw[1] + b.weight_raw[2];
    assert_true(fabs(b.u.v_mps - v / s) < 1e-12 && fabs(b.u.w_radps - w / s) < 1e-12);
    /* all behaviours agreeing: blend equals them */
    for (i = 0; i < BEH_COUNT; i++) {
        in.u[i].v_mps = 0.25;
        in.u[i].w_radps = -0.1;
    }
    behaviour_blend(&b, &in, BEH_BLEND_WEIGHTED, &p);
    assert_true(fabs(b.u.v_mps - 0.25) < 1e-15 && fabs(b.u.w_radps + 0.1) < 1e-15);
    /* a zero echo keeps the avoid weight finite and dominant */
    in = sample_inputs();
    in.min_range_m = 0.0;
    assert_int_equal(behaviour_blend(&b, &in, BEH_BLEND_WEIGHTED, &p), 0);
    assert_int_equal(b.winner, BEH_AVOID);
    /* exception overrides everything */
    in = sample_inputs();
    in.exception_active = 1;
    for (i = 0; i < 3; i++) {
        assert_int_equal(behaviour_blend(&b, &in, i, &p), 0);
        assert_true(b.u.v_mps == in.u[BEH_EXCEPTION].v_mps &&
                    b.u.w_radps == in.u[BEH_EXCEPTION].w_radps);
        assert_true(b.weight[BEH_EXCEPTION] == 1.0 && b.winner == BEH_EXCEPTION);
    }
    in.R_d_m = NAN;
    assert_int_equal(behaviour_blend(&b, &in, BEH_BLEND_WEIGHTED, &p), BEHAVIOUR_ERR_ARG);
    in = sample_inputs();
    assert_int_equal(behaviour_blend(&b, &in, 9, &p), BEHAVIOUR_ERR_ARG);
}

static void test_blend_subsumption_vecsum(void **state)
{
    behaviour_params p;
    behaviour_inputs in = sample_inputs();
    behaviour_blender b;
    int i;
    (void)state;
    behaviour_params_default(&p);
    in.R_d_m = p.d_r_m * 0.5;
    behaviour_blend(&b, &in, BEH_BLEND_SUBSUMPTION, &p);
    assert_int_equal(b.winner, BEH_GOAL);
    assert_true(b.u.v_mps == in.u[BEH_GOAL].v_mps && b.u.w_radps == in.u[BEH_GOAL].w_radps);
    in.R_d_m = p.d_r_m * 1.5;
    behaviour_blend(&b, &in, BEH_BLEND_SUBSUMPTION, &p);
    assert_int_equal(b.winner, BEH_FORMATION);
    assert_true(b.u.v_mps == in.u[BEH_FORMATION].v_mps);
    in.avoid_active = 1;
    behaviour_blend(&b, &in, BEH_BLEND_SUBSUMPTION, &p);
    assert_int_equal(b.winner, BEH_AVOID);
    assert_true(b.u.w_radps == in.u[BEH_AVOID].w_radps);
    for (i = 0; i < BEH_COUNT; i++)
        assert_true(b.weight[i] == (i == BEH_AVOID ? 1.0 : 0.0));
    behaviour_blend(&b, &in, BEH_BLEND_VECSUM, &p);
    for (i = 0; i < 3; i++)
        assert_true(fabs(b.weight[i] - 1.0 / 3.0) < 1e-15);
    assert_true(fabs(3 * b.u.v_mps - (in.u[0].v_mps + in.u[1].v_mps + in.u[2].v_mps)) < 1e-12);
    assert_true(fabs(3 * b.u.w_radps - (in.u[0].w_radps + in.u[1].w_radps + in.u[2].w_radps)) <
                1e-12);
}

static void test_params(void **state)
{
    behaviour_params p;
    (void)state;
    behaviour_params_default(&p);
    assert_int_equal(behaviour_params_validate(&p), 0);
    p.d_m = 0.0;
    assert_int_equal(behaviour_params_validate(&p), BEHAVIOUR_ERR_ARG);
    behaviour_params_default(&p);
    p.k3 = NAN;
    assert_int_equal(behaviour_params_validate(&p), BEHAVIOUR_ERR_ARG);
    assert_int_equal(behaviour_params_validate(NULL), BEHAVIOUR_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_goal_error_dynamics),
        cmocka_unit_test(test_goal_singular_and_turn),
        cmocka_unit_test(test_goal_saturated_closed_loop_reaches),
        cmocka_unit_test(test_formation_error_dynamics),
        cmocka_unit_test(test_formation_converges_saturated),
        cmocka_unit_test(test_formation_track_recovers_far_slot),
        cmocka_unit_test(test_formation_track_bands),
        cmocka_unit_test(test_seed_heading_linearisation),
        cmocka_unit_test(test_seed_heading_closed_loop),
        cmocka_unit_test(test_seed_ahead_converges_from_offsets),
        cmocka_unit_test(test_seed_backward_turns_onto_team_heading),
        cmocka_unit_test(test_sonar_groups_and_avoid),
        cmocka_unit_test(test_d_st),
        cmocka_unit_test(test_dead_zone_alternation),
        cmocka_unit_test(test_passage_narrow),
        cmocka_unit_test(test_blend_weighted),
        cmocka_unit_test(test_blend_subsumption_vecsum),
        cmocka_unit_test(test_params),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
