/* sim_world: ODE world, ground plane, contact generation with force
 * feedback, and the bit-exact state hash used by the determinism tests.
 */
#include "sim.h"
#include "vec3.h"
#include <string.h>

static void near_callback(void *data, dGeomID g1, dGeomID g2)
{
    sim_world *w = data;
    dContact c[8];
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    int n, i, stick;
    if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact))
        return;
    if (!b1 && !b2)
        return;
    if (!b1) {
        /* a body against a static geom: put the body first, so the contact
         * joint's feedback f1 is the force on it (ODE leaves f2 unset for a
         * joint with one body) and sim_contact_force_on sees it */
        dGeomID tg = g1;
        g1 = g2;
        g2 = tg;
        b1 = b2;
        b2 = 0;
    }
    stick = ((dGeomGetCategoryBits(g1) | dGeomGetCategoryBits(g2)) & SIM_CAT_STICK) != 0;
    n = dCollide(g1, g2, 8, &c[0].geom, sizeof(dContact));
    for (i = 0; i < n; i++) {
        dJointID j;
        memset(&c[i].surface, 0, sizeof c[i].surface);
        c[i].surface.mode = dContactSoftERP | dContactSoftCFM | dContactApprox1;
        c[i].surface.mu = 0.8;
        if (stick)
            sim_surface_spring(&c[i].surface, SIM_STICK_STIFFNESS_NPM / n,
                               SIM_STICK_DAMPING_NSPM / n);
        else {
            c[i].surface.soft_erp = 0.2;
            c[i].surface.soft_cfm = 1e-5;
        }
        j = dJointCreateContact(w->world, w->contacts, &c[i]);
        dJointAttach(j, b1, b2);
        if (w->n_contacts < SIM_MAX_CONTACTS) {
            sim_contact *sc = &w->contact[w->n_contacts++];
            sc->b1 = b1;
            sc->b2 = b2;
            dJointSetFeedback(j, &sc->fb);
        } else {
            w->contacts_dropped++;
        }
    }
}

void sim_surface_spring(dSurfaceParameters *s, double k_Npm, double c_Nspm)
{
    /* ODE's soft contact is a spring-damper: ERP = h k / (h k + c),
     * CFM = 1 / (h k + c) for step h (ODE manual, "Soft ERP and CFM") */
    const double hk = SIM_DT_S * k_Npm;
    s->soft_erp = hk / (hk + c_Nspm);
    s->soft_cfm = 1.0 / (hk + c_Nspm);
}

int sim_world_create(sim_world *w)
{
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    w->world = dWorldCreate();
    /* A simple space collides pairs in creation order: deterministic. */
    w->space = dSimpleSpaceCreate(0);
    w->contacts = dJointGroupCreate(0);
    dWorldSetGravity(w->world, 0, 0, -9.81);
    dWorldSetERP(w->world, 0.2);
    dWorldSetCFM(w->world, 1e-9);
    dWorldSetQuickStepNumIterations(w->world, 50);
    dRandSetSeed((unsigned long)(w->seed & 0xffffffffu));
    w->ground = dCreatePlane(w->space, 0, 0, 1, 0);
    dGeomSetCategoryBits(w->ground, SIM_CAT_GROUND);
    w->step = 0;
    w->time_s = 0.0;
    w->n_bodies = 0;
    return 0;
}

void sim_world_destroy(sim_world *w)
{
    dJointGroupDestroy(w->contacts);
    dSpaceDestroy(w->space);
    dWorldDestroy(w->world);
    dCloseODE();
}

dBodyID sim_body_create(sim_world *w)
{
    dBodyID b = dBodyCreate(w->world);
    if (w->n_bodies < SIM_MAX_BODIES)
        w->bodies[w->n_bodies++] = b;
    return b;
}

void sim_world_step(sim_world *w)
{
    w->n_contacts = 0;
    dJointGroupEmpty(w->contacts);
    dSpaceCollide(w->space, w, near_callback);
    /* dWorldStep (the exact LCP solver) keeps the light wrist links of a
     * PUMA stable under stiff joint limits at 1 kHz. */
    dWorldStep(w->world, SIM_DT_S);
    w->step++;
    w->time_s = (double)w->step * SIM_DT_S;
}

double sim_contact_force_on(const sim_world *w, dBodyID b)
{
    double fx = 0.0, fy = 0.0, fz = 0.0;
    int i;
    for (i = 0; i < w->n_contacts; i++) {
        const sim_contact *c = &w->contact[i];
        if (c->b1 == b) {
            fx += c->fb.f1[0];
            fy += c->fb.f1[1];
            fz += c->fb.f1[2];
        } else if (c->b2 == b) {
            fx += c->fb.f2[0];
            fy += c->fb.f2[1];
            fz += c->fb.f2[2];
        }
    }
    return dSqrt(fx * fx + fy * fy + fz * fz);
}

uint64_t sim_hash_bytes(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ULL;
    }
    return h;
}

uint64_t sim_state_hash(const sim_world *w)
{
    uint64_t h = 1469598103934665603ULL;
    int i;
    for (i = 0; i < w->n_bodies; i++) {
        dBodyID b = w->bodies[i];
        h = sim_hash_bytes(h, dBodyGetPosition(b), 3 * sizeof(dReal));
        h = sim_hash_bytes(h, dBodyGetQuaternion(b), 4 * sizeof(dReal));
        h = sim_hash_bytes(h, dBodyGetLinearVel(b), 3 * sizeof(dReal));
        h = sim_hash_bytes(h, dBodyGetAngularVel(b), 3 * sizeof(dReal));
    }
    return h;
}

void sim_ode_rotation(dMatrix3 out, const double R[9])
{
    int r;
    for (r = 0; r < 3; r++) {
        out[4 * r] = R[3 * r];
        out[4 * r + 1] = R[3 * r + 1];
        out[4 * r + 2] = R[3 * r + 2];
        out[4 * r + 3] = 0.0;
    }
}

void sim_from_ode_rotation(double R[9], const dReal *ode)
{
    int r;
    for (r = 0; r < 3; r++) {
        R[3 * r] = ode[4 * r];
        R[3 * r + 1] = ode[4 * r + 1];
        R[3 * r + 2] = ode[4 * r + 2];
    }
}

void sim_rot_z_to(double R[9], const double axis[3])
{
    const double z[3] = { 0.0, 0.0, 1.0 };
    double k[3];
    vec3_cross(k, z, axis);
    if (vec3_norm(k) < 1e-12) /* parallel or antiparallel: turn about x */
        vec3_set(k, 1.0, 0.0, 0.0);
    rot_from_axis_angle(R, k, atan2(vec3_norm(k), vec3_dot(z, axis)));
}
