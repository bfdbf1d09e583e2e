/* tandem-kin: command-line calculator over the arm kinematics and dynamics
 * core (arm_model, arm_kin, arm_dyn): FK, Jacobian, all IK branches and
 * gravity torques of the PUMA 560 or the seed-002 arm. A tool, not core:
 * stdio is fine here; it links the core library and the option table
 * (src/daemons/common/options.h).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arm_dyn.h"
#include "arm_kin.h"
#include "arm_model.h"
#include "vec3.h"
#include "options.h"
#include "version.h"

#define PI 3.14159265358979323846
#define EXIT_BAD_ARGS 2

typedef struct kin_options {
    int arm; /* index in options_arm_model_names */
    int deg;
    double tool_p[3];
    int have_tool;
    double payload_kg;
} kin_options;

static const option_entry kin_table[] = {
    { .name = "arm",
      .type = OPTION_CHOICE,
      OPTION_AT(kin_options, arm),
      .choices = options_arm_model_names,
      .meta = "NAME",
      .help = "arm model",
      .def = "puma560" },
    { .name = "deg",
      .type = OPTION_FLAG,
      OPTION_AT(kin_options, deg),
      .help = "joint angles in and out in degrees (default rad)" },
    { .name = "tool",
      .type = OPTION_DOUBLE,
      OPTION_AT(kin_options, tool_p),
      .nargs = 3,
      .min = -HUGE_VAL,
      .max = HUGE_VAL,
      OPTION_SEEN(kin_options, have_tool),
      .meta = "X Y Z",
      .help = "tool point offset from the flange, flange axes, m" },
    { .name = "payload",
      .type = OPTION_DOUBLE,
      OPTION_AT(kin_options, payload_kg),
      .min = 0.0,
      .max = HUGE_VAL,
      .meta = "KG",
      .help = "point mass held at the tool point (the flange origin without --tool); "
              "used by grav only",
      .def = "0" },
    OPTION_HELP_ENTRY('h'),
    { .name = NULL }
};

static const char usage_text[] =
    "usage: tandem-kin [OPTIONS] COMMAND ARGS...\n"
    "\n"
    "Kinematics and dynamics calculator for the tandem arm models.\n"
    "Poses are in the base frame (mounting surface, z up), metres;\n"
    "4x4 matrices are row-major.\n"
    "\n"
    "Commands:\n"
    "  fk Q1..Q6      print the 4x4 flange pose (tool pose with --tool):\n"
    "                 4 lines of 4 numbers\n"
    "  jac Q1..Q6     print the 6x6 geometric Jacobian of the flange (tool\n"
    "                 point with --tool) in base coordinates; rows vx vy vz\n"
    "                 wx wy wz, columns joints 1..6, per rad/s\n"
    "  ik T11..T44    16 numbers, a row-major 4x4 flange (tool) pose; print\n"
    "                 one line per branch: name and six angles, followed by\n"
    "                 '# outside-limits q..' or '# unreachable'. Exit status\n"
    "                 1 if no branch reaches the pose. The output of fk can\n"
    "                 be fed back: tandem-kin ik $(tandem-kin fk ...)\n"
    "  grav Q1..Q6    print the six joint torques (N m) that hold the arm\n"
    "                 against gravity (9.81 m/s^2 along -z of the base)\n"
    "\n"
    "Options (before the command):\n";

static const char epilog_text[] =
    "\n"
    "Branch names: left|right (shoulder) - up|down (elbow) - noflip|flip\n"
    "(wrist). Bad arguments: message on stderr, exit status 2.\n";

static int bad_args(const char *msg, const char *what)
{
    if (what)
        fprintf(stderr, "tandem-kin: %s: '%s' (try --help)\n", msg, what);
    else
        fprintf(stderr, "tandem-kin: %s (try --help)\n", msg);
    return EXIT_BAD_ARGS;
}

/* parse_number: not a whole-string finite number */
#define NUMBER_BAD (-1)

/* Whole-string finite number, else NUMBER_BAD. */
static int parse_number(const char *s, double *out)
{
    char *end;
    double v;
    if (!s || !*s)
        return NUMBER_BAD;
    errno = 0;
    v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v))
        return NUMBER_BAD;
    *out = v;
    return 0;
}

static int parse_numbers(char **argv, int n, double *out)
{
    int i;
    for (i = 0; i < n; i++)
        if (parse_number(argv[i], &out[i]) != 0)
            return bad_args("not a finite number", argv[i]);
    return 0;
}

static void print_row(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        printf("%s%.12g", i ? " " : "", v[i] == 0.0 ? 0.0 : v[i]); /* no "-0" */
    printf("\n");
}

/* Rotation part orthonormal and last row 0 0 0 1. */
static int is_rigid(const double T[16])
{
    double R[9], RtR[9];
    int i;
    tf_rot(R, T);
    rot_tmul(RtR, R, R);
    for (i = 0; i < 9; i++)
        if (fabs(RtR[i] - (i % 4 == 0 ? 1.0 : 0.0)) > 1e-6)
            return 0;
    if (fabs(T[12]) > 1e-9 || fabs(T[13]) > 1e-9 || fabs(T[14]) > 1e-9 || fabs(T[15] - 1.0) > 1e-9)
        return 0;
    return R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
               R[2] * (R[3] * R[7] - R[4] * R[6]) >
           0.0;
}

static int cmd_ik(const arm_model *m, const arm_tool *tool, int deg, const double T[16])
{
    arm_ik_result r;
    int b, j, rc;
    if (!is_rigid(T))
        return bad_args("ik: the 16 numbers are not a rigid transform", NULL);
    rc = arm_ik(m, tool, T, &r);
    if (rc != 0)
        return bad_args("ik: the arm model is not of PUMA type", m->name);
    for (b = 0; b < ARM_IK_NBRANCH; b++) {
        const arm_ik_branch *br = &r.branch[b];
        printf("%-17s", arm_ik_branch_name(b));
        if (br->status & ARM_IK_UNREACHABLE) {
            printf(" # unreachable\n");
            continue;
        }
        for (j = 0; j < ARM_NJ; j++)
            printf(" %14.9g", deg ? br->q_rad[j] * 180.0 / PI : br->q_rad[j]);
        if (br->status & ARM_IK_OUTSIDE_LIMITS) {
            printf(" # outside-limits");
            for (j = 0; j < ARM_NJ; j++)
                if (br->limit_bits & (1u << j))
                    printf(" q%d", j + 1);
        }
        printf("\n");
    }
    return r.unreachable ? 1 : 0;
}

int main(int argc, char **argv)
{
    kin_options o = { 0, 0, { 0, 0, 0 }, 0, 0.0 };
    const option_program prog = {
        .name = "tandem-kin",
        .usage = usage_text,
        .epilog = epilog_text,
        .groups = { { kin_table, &o } },
        .n_groups = 1,
        .args =
            OPTIONS_ARGS_STOP, /* the command ends the options: negative numbers are never options */
    };
    if (version_requested(argc, argv, "tandem-kin"))
        return 0;
    const arm_model *m;
    arm_tool tool;
    int nargs, j, rc, first;
    double v[16];
    const char *cmd;

    first = options_parse(&prog, argc, argv, 1);
    if (first < 0)
        return options_exit_status(first);
    m = arm_model_by_name(options_arm_model_names[o.arm]);
    if (first >= argc)
        return bad_args("missing command (fk, jac, ik, grav)", NULL);
    cmd = argv[first++];
    nargs = argc - first;
    arm_tool_none(&tool);
    if (o.have_tool)
        arm_tool_offset(&tool, o.tool_p);

    if (strcmp(cmd, "ik") == 0) {
        if (nargs != 16)
            return bad_args("ik needs exactly 16 numbers (row-major 4x4)", NULL);
        if ((rc = parse_numbers(argv + first, 16, v)) != 0)
            return rc;
        return cmd_ik(m, o.have_tool ? &tool : NULL, o.deg, v);
    }
    if (strcmp(cmd, "fk") != 0 && strcmp(cmd, "jac") != 0 && strcmp(cmd, "grav") != 0)
        return bad_args("unknown command (fk, jac, ik, grav)", cmd);
    if (nargs != ARM_NJ)
        return bad_args("needs exactly six joint angles Q1..Q6", cmd);
    if ((rc = parse_numbers(argv + first, ARM_NJ, v)) != 0)
        return rc;
    if (o.deg)
        for (j = 0; j < ARM_NJ; j++)
            v[j] *= PI / 180.0;

    if (strcmp(cmd, "fk") == 0) {
        double T[16];
        arm_fk(m, o.have_tool ? &tool : NULL, v, T);
        for (j = 0; j < 4; j++)
            print_row(T + 4 * j, 4);
    } else if (strcmp(cmd, "jac") == 0) {
        double J[36];
        arm_jacobian(m, o.have_tool ? &tool : NULL, v, J);
        for (j = 0; j < 6; j++)
            print_row(J + 6 * j, 6);
    } else {
        double tau[ARM_NJ];
        arm_payload pl;
        arm_payload_point(&pl, o.payload_kg, o.tool_p);
        arm_gravity(m, v, NULL, o.payload_kg > 0.0 ? &pl : NULL, tau);
        print_row(tau, ARM_NJ);
    }
    return 0;
}
