/* bench_sonar_map: sonar rays per CPU second on a large map against the
 * built-in worlds (docs/formation.md, "Worlds from files"). The large map
 * is 100 m x 100 m at 0.1 m with 2000 obstacles of 0.2-1.2 m on a jittered
 * grid, merged by rover_map_merge into 2000 boxes; the built-in worlds are
 * their own obstacles as tandem-sim adds them. Rays start at random free
 * points with random headings and run to the sonar's 5 m range, as the
 * sonar ring casts them (sonar_cast: the uniform grid, a DDA walk).
 *   bench_sonar_map [RAYS]    (default 2000000 per world)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "prng.h"
#include "rover_map.h"
#include "sonar.h"

static rover_map M;
static rover_world_config W;
static rover_obstacle BOX[ROVER_WORLD_MAX_OBST];
static sonar_world SW;

static void add_obstacles(const rover_obstacle *o, int n)
{
    int k;
    sonar_world_init(&SW);
    for (k = 0; k < n; k++) {
        if (o[k].kind == ROVER_OBST_CIRCLE)
            sonar_world_add_circle(&SW, o[k].cx_m, o[k].cy_m, o[k].r_m, 0.0, o[k].height_m);
        else
            sonar_world_add_box(&SW, o[k].cx_m, o[k].cy_m, o[k].hx_m, o[k].hy_m, o[k].angle_rad,
                                0.0, o[k].height_m);
    }
    sonar_world_build(&SW);
}

static int inside_any(const rover_obstacle *o, int n, double x, double y)
{
    int k;
    for (k = 0; k < n; k++)
        if (rover_obstacle_distance(&o[k], x, y) <= 0.0)
            return 1;
    return 0;
}

/* Rays per CPU second from free points in [x0, x1] x [y0, y1]. */
static double rays_per_cpu_s(const rover_obstacle *o, int n, double x0, double y0, double x1,
                             double y1, long rays, long *hits)
{
    enum { STARTS = 4096 };
    static double sx[STARTS], sy[STARTS], dir[STARTS];
    prng_state r;
    clock_t c0, c1;
    long q;
    int k;
    prng_seed(&r, 5);
    for (k = 0; k < STARTS; k++) {
        do {
            sx[k] = x0 + (x1 - x0) * prng_uniform(&r);
            sy[k] = y0 + (y1 - y0) * prng_uniform(&r);
        } while (inside_any(o, n, sx[k], sy[k]));
        dir[k] = 6.283185307179586 * prng_uniform(&r);
    }
    *hits = 0;
    c0 = clock();
    for (q = 0; q < rays; q++) {
        sonar_hit h;
        const int k2 = (int)(q % STARTS);
        /* NOLINTNEXTLINE(bugprone-integer-division): q / STARTS: the whole round the ray belongs to */
        *hits += sonar_cast(&h, &SW, sx[k2], sy[k2], 0.2, dir[k2] + 1e-3 * (double)(q / STARTS),
                            5.0) == 1;
    }
    c1 = clock();
    return (double)rays / ((double)(c1 - c0) / CLOCKS_PER_SEC);
}

static int big_map(void)
{
    prng_state r;
    int gi, gj, i, j, placed = 0, n;
    const double cell_m = 100.0 / 45.0;
    memset(&M, 0, sizeof M);
    M.width = 1000;
    M.height = 1000;
    M.resolution_m = 0.1;
    prng_seed(&r, 3);
    for (gj = 0; gj < 45; gj++)
        for (gi = 0; gi < 45 && placed < 2000; gi++, placed++) {
            const int w = 2 + (int)(prng_uniform(&r) * 11), h = 2 + (int)(prng_uniform(&r) * 11);
            const int i0 = (int)((gi * cell_m + prng_uniform(&r) * (cell_m - 1.3)) / 0.1);
            const int j0 = (int)((gj * cell_m + prng_uniform(&r) * (cell_m - 1.3)) / 0.1);
            for (j = j0; j < j0 + h; j++)
                for (i = i0; i < i0 + w; i++)
                    M.cell[(long)j * 1000 + i] = ROVER_MAP_OCCUPIED;
        }
    if (rover_map_merge(&M, BOX, ROVER_WORLD_MAX_OBST, &n) != ROVER_MAP_OK)
        return -1;
    return n;
}

int main(int argc, char **argv)
{
    const long rays = argc > 1 ? atol(argv[1]) : 2000000L;
    double built_in_worst = 0.0, v;
    long hits;
    int world, n;
    printf("sonar rays per CPU second (sonar_cast, 5 m range, %ld rays per world):\n", rays);
    for (world = 0; world < ROVER_WORLD_COUNT; world++) {
        rover_world_layout(&W, world, 3, 1.0, 0);
        add_obstacles(W.obst, W.n_obst);
        v = rays_per_cpu_s(W.obst, W.n_obst, W.x_min_m, W.y_min_m, W.x_max_m, W.y_max_m, rays,
                           &hits);
        printf("  %-10s %5d prims  %12.0f rays/s  (%4.1f %% hit)\n", rover_world_name(world),
               W.n_obst, v, 100.0 * hits / rays);
        if (world == 0 || v < built_in_worst)
            built_in_worst = v;
    }
    n = big_map();
    if (n < 0) {
        printf("  the 100 m map did not merge\n");
        return 1;
    }
    add_obstacles(BOX, n);
    v = rays_per_cpu_s(BOX, n, 0.0, 0.0, 100.0, 100.0, rays, &hits);
    printf("  100x100 m  %5d boxes %12.0f rays/s  (%4.1f %% hit; grid %dx%d cells of %.2f m)\n", n,
           v, 100.0 * hits / rays, SW.nx, SW.ny, SW.cell_m);
    printf("  100 m map / slowest built-in world: %.2f (the bound: within 2x, i.e. >= 0.5)\n",
           v / built_in_worst);
    return 0;
}
