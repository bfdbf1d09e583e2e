/* Unit tests of the world file reader (src/daemons/common/world_file.c):
 * a map_server YAML with its image as P5 and as P2 gives the same grid
 * (image rows top to bottom, map_server's thresholds and negate, unknown
 * taken as occupied); every broken field is refused with its code and a
 * message naming the field; write then read gives the map and the site
 * back; the options refuse --start/--goal without a file and a goal on
 * an obstacle. */
#define _XOPEN_SOURCE 700
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "world_file.h"

static rover_map M, M2;
static rover_world_config W;
static char dir[64];
static char why[WORLD_FILE_WHY_MAX];

/* 4 x 3 image, top row first: a wall along the top, a grey (unknown)
 * pixel and a dark (occupied) pixel in the middle row, free bottom row. */
static const int pix[3][4] = { { 0, 0, 0, 0 }, { 254, 128, 10, 254 }, { 254, 254, 254, 254 } };

static const char *path(const char *name)
{
    static char p[4][128];
    static int k;
    k = (k + 1) % 4;
    snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
    return p[k];
}

static void write_text(const char *name, const char *text)
{
    FILE *f = fopen(path(name), "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void write_images(void)
{
    FILE *f = fopen(path("m5.pgm"), "wb");
    int r, c;
    assert_non_null(f);
    fprintf(f, "P5\n# a comment\n4 3\n255\n");
    for (r = 0; r < 3; r++)
        for (c = 0; c < 4; c++)
            fputc(pix[r][c], f);
    fclose(f);
    f = fopen(path("m2.pgm"), "w");
    fprintf(f, "P2\n4 3\n# comment between\n255\n");
    for (r = 0; r < 3; r++)
        for (c = 0; c < 4; c++)
            fprintf(f, "%d%c", pix[r][c], c == 3 ? '\n' : ' ');
    fclose(f);
    f = fopen(path("short.pgm"), "wb");
    fprintf(f, "P5\n4 3\n255\n");
    for (r = 0; r < 11; r++)
        fputc(254, f);
    fclose(f);
    write_text("text.pgm", "this is not an image\n");
}

static const char *good =
    "image: m5.pgm\nresolution: 0.5\norigin: [1.0, -2.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    "tandem:\n  start: [1.5, -1.25, 0.3]\n  goal: [2.5, -1.75]\n  landmarks: [[0, 0], [3, 1]]\n";

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/tandem-world-XXXXXX");
    assert_non_null(mkdtemp(dir));
    write_images();
    return 0;
}

static int teardown(void **state)
{
    static const char *const names[] = { "m5.pgm", "m2.pgm",   "short.pgm", "text.pgm",
                                         "w.yaml", "out.yaml", "out.pgm",   NULL };
    int k;
    (void)state;
    for (k = 0; names[k]; k++)
        remove(path(names[k]));
    rmdir(dir);
    return 0;
}

/* good with one line replaced (from: the text to replace). */
static int read_variant(const char *from, const char *to)
{
    char text[1024];
    const char *at = strstr(good, from ? from : good); /* NULL: the whole file */
    assert_non_null(at);
    snprintf(text, sizeof text, "%.*s%s%s", (int)(at - good), good, to,
             at + strlen(from ? from : good));
    write_text("w.yaml", text);
    why[0] = '\0';
    return world_file_read(path("w.yaml"), &M, &(rover_map_site){ 0 }, why, sizeof why);
}

static void test_p5_and_p2_give_the_same_grid(void **state)
{
    rover_map_site s;
    int i, j;
    (void)state;
    write_text("w.yaml", good);
    assert_int_equal(world_file_read(path("w.yaml"), &M, &s, why, sizeof why), WORLD_FILE_OK);
    assert_int_equal(read_variant("image: m5.pgm", "image: m2.pgm"), WORLD_FILE_OK);
    memcpy(&M2, &M, sizeof M);
    write_text("w.yaml", good);
    assert_int_equal(world_file_read(path("w.yaml"), &M, &s, why, sizeof why), WORLD_FILE_OK);
    assert_int_equal(M.width, 4);
    assert_int_equal(M.height, 3);
    assert_true(M.resolution_m == 0.5 && M.origin_x_m == 1.0 && M.origin_y_m == -2.0);
    assert_memory_equal(M.cell, M2.cell, 12);
    /* map row j is image row 2 - j; grey (p = 0.5, between the thresholds) is occupied */
    for (j = 0; j < 3; j++)
        for (i = 0; i < 4; i++) {
            const double p = (255.0 - pix[2 - j][i]) / 255.0;
            assert_int_equal(M.cell[j * 4 + i], p < 0.196 ? ROVER_MAP_FREE : ROVER_MAP_OCCUPIED);
        }
    assert_int_equal(rover_map_blocked(&M, 1.1, -1.9), 0); /* bottom-left: free */
    assert_int_equal(rover_map_blocked(&M, 1.1, -0.6), 1); /* top row: the wall */
    assert_true(s.start.x_m == 1.5 && s.start.y_m == -1.25 && s.start.theta_rad == 0.3);
    assert_true(s.goal_m[0] == 2.5 && s.goal_m[1] == -1.75);
    assert_int_equal(s.n_landmarks, 2);
    assert_true(s.landmark_m[1][0] == 3.0 && s.landmark_m[1][1] == 1.0);
    /* negate: dark is free, so the top row's wall becomes free */
    assert_int_equal(read_variant("negate: 0", "negate: 1"), WORLD_FILE_OK);
    assert_int_equal(rover_map_blocked(&M, 1.1, -0.6), 0);
    assert_int_equal(rover_map_blocked(&M, 1.1, -1.9), 1);
    assert_int_equal(read_variant("landmarks: [[0, 0], [3, 1]]", "landmarks: auto"), WORLD_FILE_OK);
}

typedef struct broken {
    const char *from, *to;
    int rc;
    const char *field; /* the message names it */
} broken;

static void test_each_broken_field_is_refused_with_its_reason(void **state)
{
    static const broken cases[] = {
        { "image: m5.pgm", "image: nowhere.pgm", WORLD_FILE_ERR_IMAGE, "image: cannot read" },
        { "image: m5.pgm", "image: short.pgm", WORLD_FILE_ERR_IMAGE, "pixel data short" },
        { "image: m5.pgm", "image: text.pgm", WORLD_FILE_ERR_IMAGE, "not a PGM" },
        { "image: m5.pgm\n", "", WORLD_FILE_ERR_FIELD, "image: missing" },
        { "resolution: 0.5", "resolution: 0", WORLD_FILE_ERR_FIELD, "resolution: must be > 0" },
        { "resolution: 0.5", "resolution: -0.5", WORLD_FILE_ERR_FIELD, "resolution: must be > 0" },
        { "resolution: 0.5", "resolution: fine", WORLD_FILE_ERR_FIELD,
          "resolution: not a finite number" },
        { "resolution: 0.5\n", "", WORLD_FILE_ERR_FIELD, "resolution: missing" },
        { "origin: [1.0, -2.0, 0.0]", "origin: [1.0, -2.0]", WORLD_FILE_ERR_FIELD,
          "origin: 2 numbers, need 3" },
        { "origin: [1.0, -2.0, 0.0]", "origin: [1.0, -2.0, 0.5]", WORLD_FILE_ERR_FIELD,
          "origin: yaw must be 0" },
        { "negate: 0", "negate: 2", WORLD_FILE_ERR_FIELD, "negate: must be 0 or 1" },
        { "occupied_thresh: 0.65", "occupied_thresh: 0.1", WORLD_FILE_ERR_FIELD,
          "free_thresh, occupied_thresh" },
        { "free_thresh: 0.196", "free_thresh: -1", WORLD_FILE_ERR_FIELD,
          "free_thresh, occupied_thresh" },
        { "occupied_thresh: 0.65\n", "", WORLD_FILE_ERR_FIELD, "occupied_thresh: missing" },
        { "negate: 0", "negate: 0\nmode: raw", WORLD_FILE_ERR_FIELD, "mode: only trinary" },
        { "tandem:", "tandom:", WORLD_FILE_ERR_FIELD, "tandem: missing" },
        { "start: [1.5, -1.25, 0.3]", "start: [1.5, -1.25]", WORLD_FILE_ERR_FIELD, "tandem.start" },
        { "goal: [2.5, -1.75]", "goal: [2.5, north]", WORLD_FILE_ERR_FIELD, "tandem.goal" },
        { "landmarks: [[0, 0], [3, 1]]", "landmarks: [[0, 0], [3]]", WORLD_FILE_ERR_FIELD,
          "tandem.landmarks[1]" },
        { "landmarks: [[0, 0], [3, 1]]", "landmarks: some", WORLD_FILE_ERR_FIELD,
          "tandem.landmarks" },
        { "image: m5.pgm", "image: [m5.pgm", WORLD_FILE_ERR_YAML, "line" },
        { NULL, "- a list\n- not a mapping\n", WORLD_FILE_ERR_YAML, "not a YAML mapping" },
    };
    size_t k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const int rc = read_variant(cases[k].from, cases[k].to);
        if (rc != cases[k].rc || !strstr(why, cases[k].field) || !strstr(why, "w.yaml"))
            fail_msg("case %zu (%s): rc %d, want %d; message '%s' should name '%s'", k, cases[k].to,
                     rc, cases[k].rc, why, cases[k].field);
    }
    assert_int_equal(
        world_file_read(path("none.yaml"), &M, &(rover_map_site){ 0 }, why, sizeof why),
        WORLD_FILE_ERR_OPEN);
    assert_non_null(strstr(why, "none.yaml"));
}

static void test_write_then_read_gives_the_world_back(void **state)
{
    rover_map_site s, s2;
    (void)state;
    write_text("w.yaml", good);
    assert_int_equal(world_file_read(path("w.yaml"), &M, &s, why, sizeof why), WORLD_FILE_OK);
    assert_int_equal(world_file_write(dir, "out", &M, &s, why, sizeof why), WORLD_FILE_OK);
    assert_int_equal(world_file_read(path("out.yaml"), &M2, &s2, why, sizeof why), WORLD_FILE_OK);
    assert_true(M2.width == M.width && M2.height == M.height && M2.resolution_m == M.resolution_m &&
                M2.origin_x_m == M.origin_x_m && M2.origin_y_m == M.origin_y_m);
    assert_memory_equal(M2.cell, M.cell, 12);
    assert_memory_equal(&s2, &s, sizeof s);
}

static void test_options_refuse_what_gives_no_layout(void **state)
{
    world_opts o = { ROVER_WORLD_OPEN, NULL, "1,2,0", NULL };
    char yaml[128];
    (void)state;
    assert_int_equal(world_opts_layout(&W, &o, 3, 1.0, 0, "test"), WORLD_FILE_ERR_OPTION);
    o.start = NULL;
    assert_int_equal(world_opts_layout(&W, &o, 3, 1.0, 0, "test"), WORLD_FILE_OK);
    assert_int_equal(W.world, ROVER_WORLD_OPEN);
    /* the 4 x 3 map is too small for a team: its start is refused; a
     * goal given on the wall is refused too */
    write_text("w.yaml", good);
    snprintf(yaml, sizeof yaml, "%s", path("w.yaml"));
    o.file = yaml;
    assert_int_equal(world_opts_layout(&W, &o, 1, 1.0, 0, "test"), WORLD_FILE_ERR_MAP);
    o.start = "1,2";
    assert_int_equal(world_opts_layout(&W, &o, 1, 1.0, 0, "test"), WORLD_FILE_ERR_OPTION);
    o.start = NULL;
    o.goal = "x,y";
    assert_int_equal(world_opts_layout(&W, &o, 1, 1.0, 0, "test"), WORLD_FILE_ERR_OPTION);
    assert_string_equal(world_file_strerror(WORLD_FILE_ERR_IMAGE),
                        "the image is missing or not a PGM of the stated size");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_p5_and_p2_give_the_same_grid),
        cmocka_unit_test(test_each_broken_field_is_refused_with_its_reason),
        cmocka_unit_test(test_write_then_read_gives_the_world_back),
        cmocka_unit_test(test_options_refuse_what_gives_no_layout),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
