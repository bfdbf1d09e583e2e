/* sim_stick: the hand-held stick of the arm cell (docs/method/carry.md §8), part of the
 * arm model's state (sim_arms). INSERT_STICK puts a compliant rod (its
 * contact is a spring-damper, sim_world.c) either at a given pose or ahead
 * of a named link of one arm, in the first candidate pose that touches no
 * link of either arm; an arm is never thrown by a rod that went in inside
 * its geometry. REMOVE_STICK takes it out.
 */
#include "sim_arms.h"
#include <math.h>
#include <stdio.h>
#include "vec3.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

void sim_stick_remove(sim_arms *arms)
{
    if (arms->stick) {
        dGeomDestroy(arms->stick);
        arms->stick = NULL;
    }
}

/* The stick's pose: the point ahead of the target link and the frame that
 * candidate poses are built in. "The link" is its longest capsule (the
 * forearm of link 3 lies along z3, not x3). */
typedef struct stick_frame {
    double p[3];      /* capsule centre of the target link */
    double dir[3];    /* unit motion of that point across the link */
    double along[3];  /* unit capsule axis */
    double across[3]; /* dir x along: the rod's axis in the first candidate */
    double reach_m;   /* link radius + rod radius: touching distance */
} stick_frame;

static void stick_frame_for_link(const sim_arms *arms, const tandem_sim_control_t *c,
                                 stick_frame *f)
{
    const sim_arm *a = &arms->pair[c->target - 1];
    const int i = c->link - 1;
    dBodyID b = a->link[i];
    dGeomID g = a->geom[i][0];
    dReal r0 = 0, l0 = 0, r1 = 0, l1 = 0;
    const dReal *p, *R;
    dVector3 v;
    if (a->geom[i][0])
        dGeomCapsuleGetParams(a->geom[i][0], &r0, &l0);
    if (a->geom[i][1])
        dGeomCapsuleGetParams(a->geom[i][1], &r1, &l1);
    if (!g || (a->geom[i][1] && l1 > l0))
        g = a->geom[i][1];
    p = g ? dGeomGetPosition(g) : dBodyGetPosition(b);
    R = g ? dGeomGetRotation(g) : dBodyGetRotation(b);
    vec3_set(f->p, p[0], p[1], p[2]);
    vec3_set(f->along, R[2], R[6], R[10]); /* capsule axis (its z) */
    dBodyGetPointVel(b, p[0], p[1], p[2], v);
    vec3_set(f->dir, v[0], v[1], v[2]);
    vec3_axpy(f->dir, f->dir, -vec3_dot(f->dir, f->along), f->along); /* across the link */
    if (vec3_normalize(f->dir, f->dir) < 1e-3) {
        /* not moving: above the link, where a lift would go */
        vec3_set(f->dir, 0.0, 0.0, 1.0);
        vec3_axpy(f->dir, f->dir, -vec3_dot(f->dir, f->along), f->along);
        if (vec3_normalize(f->dir, f->dir) < 1e-6)
            vec3_set(f->dir, 1.0, 0.0, 0.0);
    }
    vec3_cross(f->across, f->dir, f->along);
    if (vec3_normalize(f->across, f->across) < 1e-6)
        vec3_set(f->across, 0.0, 0.0, 1.0);
    f->reach_m = sim_arm_link_radius_m[i] + c->radius_m;
}

/* 1 if the stick touches or overlaps any link of either arm. */
static int stick_touches_arms(const sim_arms *arms)
{
    dContactGeom cg[4];
    int k, i, g;
    for (k = 0; k < SIM_ARMS; k++)
        for (i = 0; i < ARM_NJ; i++)
            for (g = 0; g < 2; g++)
                if (arms->pair[k].geom[i][g] &&
                    dCollide(arms->stick, arms->pair[k].geom[i][g], 4, cg, sizeof cg[0]) > 0)
                    return 1;
    return 0;
}

static void stick_set_pose(dGeomID stick, const double centre[3], const double axis[3])
{
    double R[9];
    dMatrix3 Rm;
    sim_rot_z_to(R, axis); /* ODE capsules lie along their z axis */
    sim_ode_rotation(Rm, R);
    dGeomSetRotation(stick, Rm);
    dGeomSetPosition(stick, centre[0], centre[1], centre[2]);
}

/* Candidate stick poses, nearest first: the rod lies across the link's
 * path a gap ahead of it, turned about the motion by a tilt (never along
 * the link) and slid along its own axis by a shift (a rod reaching in from
 * one side past the link instead of spanning the arm). The first pose
 * that touches no link of either arm is taken: a rod that went in inside
 * the geometry would throw the arm with the penetration spring. */
static const double stick_gap_m[] = { 0.005, 0.010, 0.020, 0.040, 0.080 };
static const double stick_tilt_rad[] = { 0.0,    0.2618,  -0.2618, 0.5236, -0.5236,
                                         0.7854, -0.7854, 1.0472,  -1.0472 };
static const double stick_shift_share[] = { 0.0, 0.33, -0.33 }; /* of the rod's half length */
#define NELEM(x) ((int)(sizeof(x) / sizeof((x)[0])))

/* stick_place_for_link: every candidate pose touches an arm */
#define STICK_NO_PLACE (-1)

static int stick_place_for_link(sim_arms *arms, const tandem_sim_control_t *c, double centre[3],
                                double axis[3])
{
    stick_frame f;
    int ig, it, is;
    stick_frame_for_link(arms, c, &f);
    for (ig = 0; ig < NELEM(stick_gap_m); ig++)
        for (is = 0; is < NELEM(stick_shift_share); is++)
            for (it = 0; it < NELEM(stick_tilt_rad); it++) {
                const double ct = cos(stick_tilt_rad[it]), st = sin(stick_tilt_rad[it]);
                vec3_scale(axis, f.across, ct);
                vec3_axpy(axis, axis, st, f.along);
                vec3_copy(centre, f.p);
                vec3_axpy(centre, centre, f.reach_m + stick_gap_m[ig], f.dir);
                vec3_axpy(centre, centre, stick_shift_share[is] * 0.5 * c->length_m, axis);
                stick_set_pose(arms->stick, centre, axis);
                if (!stick_touches_arms(arms))
                    return 0;
            }
    return STICK_NO_PLACE;
}

/* The request's sizes, and its pose (given) or link (placed against). */
static int stick_request_valid(const tandem_sim_control_t *c, double axis[3])
{
    if (c->length_m <= 0.0 || c->length_m > 2.0 || c->radius_m <= 0.0 || c->radius_m > 0.1)
        return 0;
    if (c->link == 0 && (!(vec3_normalize(axis, c->axis) >= 1e-9) || !isfinite(c->position_m[0]) ||
                         !isfinite(c->position_m[1]) || !isfinite(c->position_m[2])))
        return 0;
    if (c->link != 0 && (c->target < 1 || c->target > SIM_ARMS || c->link < 1 || c->link > ARM_NJ))
        return 0;
    return 1;
}

static int stick_refused(sim_arms *arms, sim_world *w)
{
    sim_stick_remove(arms);
    w->stick_refused++;
    return SIM_ERR_CONTROL;
}

int sim_stick_control(sim_arms *arms, sim_world *w, const tandem_sim_control_t *c)
{
    double centre[3], axis[3];
    if (c->command == TANDEM_SIM_CONTROL_T_REMOVE_STICK) {
        sim_stick_remove(arms);
        return 1;
    }
    if (c->command != TANDEM_SIM_CONTROL_T_INSERT_STICK)
        return 0;
    if (!stick_request_valid(c, axis))
        return SIM_ERR_CONTROL;
    sim_stick_remove(arms);
    arms->stick = dCreateCapsule(w->space, c->radius_m, c->length_m);
    dGeomSetCategoryBits(arms->stick, SIM_CAT_STICK);
    dGeomSetCollideBits(arms->stick, SIM_CAT_ARM);
    if (c->link == 0) {
        vec3_copy(centre, c->position_m);
        stick_set_pose(arms->stick, centre, axis);
    } else if (stick_place_for_link(arms, c, centre, axis) != 0) {
        fprintf(
            stderr,
            "tandem-sim: no stick pose ahead of arm %d link %d clears both arms: not inserted\n",
            c->target, c->link);
        return stick_refused(arms, w);
    }
    if (stick_touches_arms(arms)) {
        /* an explicit pose inside an arm: refused, never thrown at it */
        fprintf(stderr, "tandem-sim: stick pose overlaps an arm: not inserted\n");
        return stick_refused(arms, w);
    }
    arms->stick_target = c->target;
    arms->stick_link = c->link;
    fprintf(stderr, "tandem-sim: stick in at (%.3f %.3f %.3f) for arm %d link %d\n", centre[0],
            centre[1], centre[2], c->target, c->link);
    return 1;
}

void sim_stick_status(const sim_arms *arms, tandem_sim_status_t *s)
{
    s->stick_inserted = arms->stick != NULL;
    s->stick_target = arms->stick_target;
    s->stick_link = arms->stick_link;
    if (arms->stick) {
        const dReal *p = dGeomGetPosition(arms->stick);
        vec3_set(s->stick_position_m, p[0], p[1], p[2]);
    }
}
