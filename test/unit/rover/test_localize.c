/* Unit tests for localize: the camera measurement Jacobian by central
 * differences (O behind and ahead of the axle), a long drive with wheel
 * slip on which the filter's error stays bounded while dead reckoning's
 * grows, the innovation gate against a wrong sighting, recovery after
 * the wheels spun in place, and input validation. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "localize.h"
#include "prng.h"
#include "unicycle.h"

static double urand(prng_state *r, double lo, double hi)
{
    return lo + (hi - lo) * prng_uniform(r);
}

static void test_measure_jacobian(void **state)
{
    const double lm[2][2] = { { 3.0, 1.0 }, { -2.0, 4.0 } };
    prng_state rng;
    int n;
    (void)state;
    prng_seed(&rng, 11);
    for (n = 0; n < 400; n++) {
        localize_params p;
        localizer l;
        const pose2 c0 = { 0, 0, 0 };
        double s[3], z[2], H[6], zp[2], zm[2], Hx[6];
        const double h = 1e-6;
        int i, k = n % 2;
        localize_params_default(&p);
        p.d_m = n % 4 < 2 ? -0.15 : 0.15;
        assert_int_equal(localize_init(&l, &p, &c0, 0.1, 0.1, lm, 2), 0);
        s[0] = urand(&rng, -1, 1);
        s[1] = urand(&rng, -1, 1);
        s[2] = urand(&rng, -3, 3);
        assert_int_equal(localize_measure(&l, s, k, z, H), 0);
        for (i = 0; i < 3; i++) {
            double sp[3] = { s[0], s[1], s[2] }, sm[3] = { s[0], s[1], s[2] };
            sp[i] += h;
            sm[i] -= h;
            localize_measure(&l, sp, k, zp, Hx);
            localize_measure(&l, sm, k, zm, Hx);
            assert_true(fabs((zp[0] - zm[0]) / (2 * h) - H[i]) < 1e-6);
            assert_true(fabs(vec2_wrap_rad(zp[1] - zm[1]) / (2 * h) - H[3 + i]) < 1e-6);
        }
    }
}

/* A kinematic Pioneer on a 24 m x 6 m circuit, 4 laps (about 240 m), with
 * wheel slip as the simulator models it (a Gauss-Markov surface velocity
 * per wheel, here 2 % of the rim speed, tau 0.5 s, four times the
 * simulator's) plus a 0.5 % error in one wheel's radius; landmarks every
 * 3 m on three lines; the camera sees those within 6 m and 60 deg of the
 * heading, 10 Hz, with the simulator's noise. Returns the largest error of
 * O (filter and, separately, dead reckoning) and the fraction of samples
 * where the filter's error lay within 3 sigma of its own covariance. */
typedef struct {
    double loc_max_m, odo_max_m, within_3sd;
    long fused;
} drive_result;

static void drive(drive_result *res, int use_camera)
{
    static double lm[LOCALIZE_LANDMARKS_MAX][2];
    const double wp[4][2] = { { 24, 0 }, { 24, 6 }, { 0, 6 }, { 0, 0 } };
    const double dt = 0.01, r = 0.0825, track = 0.33;
    localize_params p;
    localizer l;
    prng_state rng;
    pose2 truth = { 0, 0, 0 }, odo = { 0, 0, 0 };
    double slip[2] = { 0, 0 }, ang[2] = { 0, 0 }, prev[2] = { 0, 0 };
    int n = 0, k, w = 0, laps = 0, inside = 0, samples = 0;
    double x;
    for (x = -3.0; x <= 27.0 && n + 3 <= LOCALIZE_LANDMARKS_MAX; x += 3.0) {
        lm[n][0] = x;
        lm[n++][1] = -3.5;
        lm[n][0] = x;
        lm[n++][1] = 3.0;
        lm[n][0] = x;
        lm[n++][1] = 9.5;
    }
    localize_params_default(&p);
    assert_int_equal(localize_init(&l, &p, &truth, 0.0, 0.0, (const double(*)[2])lm, n), 0);
    prng_seed(&rng, 5);
    res->loc_max_m = res->odo_max_m = 0.0;
    for (k = 0; laps < 4; k++) {
        const double bx = wp[w][0] - truth.x_m, by = wp[w][1] - truth.y_m;
        const double e = vec2_angle_diff_rad(atan2(by, bx), truth.theta_rad);
        double v = 0.5 * cos(e), om = 1.5 * e, rim[2], ds, dth;
        int j;
        if (v < 0.0)
            v = 0.0;
        if (hypot(bx, by) < 0.4) {
            w = (w + 1) % 4;
            if (w == 0)
                laps++;
        }
        rim[0] = (v - 0.5 * track * om);
        rim[1] = (v + 0.5 * track * om);
        for (j = 0; j < 2; j++) {
            /* Gauss-Markov slip: x' = -x / tau + noise, stationary sd 2 % */
            const double sd = 0.02 * fabs(rim[j]), a = exp(-dt / 0.5);
            slip[j] = a * slip[j] + sd * sqrt(1 - a * a) * prng_gauss(&rng);
            ang[j] += rim[j] / r * dt;
        }
        /* the ground sees rim + slip; the right wheel is 0.5 % larger */
        unicycle_step_exact(&truth, 0.5 * (rim[0] + slip[0] + 1.005 * rim[1] + slip[1]),
                            (1.005 * rim[1] + slip[1] - rim[0] - slip[0]) / track, dt);
        ds = 0.5 * r * ((ang[0] - prev[0]) + (ang[1] - prev[1]));
        dth = r * ((ang[1] - prev[1]) - (ang[0] - prev[0])) / track;
        prev[0] = ang[0];
        prev[1] = ang[1];
        unicycle_step_exact(&odo, ds, dth, 1.0);
        assert_int_equal(localize_predict(&l, ds, dth), 0);
        if (use_camera && k % 10 == 0) {
            pose2 o;
            unicycle_o_from_c(&o, &truth, p.d_m);
            for (j = 0; j < n; j++) {
                const double dx = lm[j][0] - o.x_m, dy = lm[j][1] - o.y_m, d = hypot(dx, dy);
                const double b = vec2_angle_diff_rad(atan2(dy, dx), o.theta_rad);
                if (d > 6.0 || fabs(b) > 60.0 * VEC2_PI / 180.0)
                    continue;
                assert_true(localize_landmark(&l, j, d + (0.01 + 0.02 * d) * prng_gauss(&rng),
                                              b + 0.01 * prng_gauss(&rng)) >= 0);
            }
        }
        if (k % 10 == 0) {
            pose2 est, to, oo;
            double err;
            localize_pose_o(&l, &est);
            unicycle_o_from_c(&to, &truth, p.d_m);
            unicycle_o_from_c(&oo, &odo, p.d_m);
            err = hypot(est.x_m - to.x_m, est.y_m - to.y_m);
            res->loc_max_m = fmax(res->loc_max_m, err);
            res->odo_max_m = fmax(res->odo_max_m, hypot(oo.x_m - to.x_m, oo.y_m - to.y_m));
            inside += err <= 3.0 * sqrt(l.P[0] + l.P[4]);
            samples++;
        }
    }
    res->within_3sd = (double)inside / samples;
    res->fused = l.accepted;
}

static void test_long_drive_with_slip_stays_bounded(void **state)
{
    drive_result cam, dead;
    (void)state;
    drive(&cam, 1);
    drive(&dead, 0);
    print_message("240 m with slip: filter max error %.3f m (%.0f %% within 3 sd, %ld sightings); "
                  "dead reckoning %.2f m; filter without camera %.2f m\n",
                  cam.loc_max_m, 100.0 * cam.within_3sd, cam.fused, cam.odo_max_m, dead.loc_max_m);
    assert_true(cam.odo_max_m > 1.0);   /* the drift is real ... */
    assert_true(cam.loc_max_m < 0.1);   /* ... and bounded by the landmarks */
    assert_true(cam.within_3sd > 0.95); /* the covariance is honest */
    /* without sightings the filter is dead reckoning (midpoint arcs) */
    assert_true(fabs(dead.loc_max_m - dead.odo_max_m) < 0.05 * dead.odo_max_m);
}

static void test_gate_and_recovery(void **state)
{
    const double lm[3][2] = { { 4.0, 2.0 }, { 4.0, -2.0 }, { 2.0, 3.0 } };
    localize_params p;
    localizer l;
    const pose2 c0 = { 0, 0, 0 };
    pose2 c, o;
    int k, j;
    (void)state;
    localize_params_default(&p);
    assert_int_equal(localize_init(&l, &p, &c0, 0.02, 0.01, lm, 3), 0);
    /* a sighting 1 m off in range: gated out, the estimate does not move */
    assert_int_equal(localize_landmark(&l, 0, hypot(3.85, 2.0) + 1.0, atan2(2.0, 3.85)), 0);
    localize_pose_c(&l, &c);
    assert_true(c.x_m == 0.0 && c.y_m == 0.0);
    /* the wheels spin 1.5 m while the robot stands: every sighting is then
     * gated out until the covariance is raised, then it comes back */
    for (k = 0; k < 150; k++)
        localize_predict(&l, 0.01, 0.0);
    for (k = 0; k < 40; k++)
        for (j = 0; j < 3; j++) {
            const double dx = lm[j][0] - 0.15, dy = lm[j][1]; /* camera at O = C + 0.15 x */
            localize_landmark(&l, j, hypot(dx, dy), atan2(dy, dx));
        }
    localize_pose_o(&l, &o);
    print_message("after 1.5 m of wheel spin: %ld rejected, %ld resets, O at (%.3f, %.3f)\n",
                  l.rejected, l.resets, o.x_m, o.y_m);
    assert_true(l.resets >= 1);
    assert_true(hypot(o.x_m - 0.15, o.y_m) < 0.05);
}

static void test_bad_input(void **state)
{
    const double lm[1][2] = { { 1.0, 0.0 } };
    localize_params p;
    localizer l;
    const pose2 c0 = { 0, 0, 0 };
    double s[3] = { 0.85, 0, 0 }, z[2], H[6];
    (void)state;
    localize_params_default(&p);
    assert_int_equal(localize_params_validate(&p), 0);
    assert_int_equal(localize_params_validate(NULL),
                     LOCALIZE_ERR_ARG); /* was read before the check */
    p.bearing_sd_rad = 0.0;
    assert_int_equal(localize_init(&l, &p, &c0, 0.1, 0.1, lm, 1), LOCALIZE_ERR_ARG);
    localize_params_default(&p);
    assert_int_equal(localize_init(&l, &p, &c0, 0.1, 0.1, lm, LOCALIZE_LANDMARKS_MAX + 1),
                     LOCALIZE_ERR_ARG);
    assert_int_equal(localize_init(&l, &p, &c0, -0.1, 0.1, lm, 1), LOCALIZE_ERR_ARG);
    assert_int_equal(localize_init(&l, &p, &c0, 0.1, 0.1, lm, 1), 0);
    assert_int_equal(localize_landmark(&l, 1, 1.0, 0.0), LOCALIZE_ERR_ARG); /* unknown landmark */
    assert_int_equal(localize_landmark(&l, 0, NAN, 0.0), LOCALIZE_ERR_ARG);
    assert_int_equal(localize_predict(&l, INFINITY, 0.0), LOCALIZE_ERR_ARG);
    /* camera (O = C + 0.15 x) on the landmark: no bearing */
    assert_int_equal(localize_measure(&l, s, 0, z, H), LOCALIZE_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_measure_jacobian),
        cmocka_unit_test(test_long_drive_with_slip_stays_bounded),
        cmocka_unit_test(test_gate_and_recovery),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
