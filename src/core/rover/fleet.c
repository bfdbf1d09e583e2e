/* fleet: the layout of many teams in one open world, each team's lane,
 * start area and goal, and which robots make up each team (fleet.h).
 */
#include "fleet.h"
#include "formation.h"

#include <math.h>
#include <string.h>

/* Landmark rows: a row of posts along every border between lanes (and
 * outside the outer lanes), the posts spread evenly from behind the first
 * row's start to past the last row's goals. As many a border as a world
 * of ROVER_WORLD_MAX_LANDMARKS gave (8 at most), and more where those
 * would stand farther apart than ROVER_FLEET_POST_STEP_M, the camera's
 * reach, as many as ROVER_WORLD_MAX_POSTS holds: with rows of teams along
 * the way 64 posts stood some 60 m apart, robots crossed their 12 m on
 * odometry alone and took each other's slots 0.6 m off. */
static void fleet_landmarks(rover_world_config *w, const rover_fleet *f, double x_lo, double x_hi)
{
    const int rows = (f->teams < ROVER_FLEET_ROW_LANES ? f->teams : ROVER_FLEET_ROW_LANES) + 1;
    const int reach = (int)ceil((x_hi - x_lo) / ROVER_FLEET_POST_STEP_M) + 1;
    int per_row = ROVER_WORLD_MAX_LANDMARKS / rows, r, k;
    const double y0 = f->lane_y_m[0] + 0.5 * f->lane_m; /* the leftmost border */
    if (per_row > 8)
        per_row = 8;
    if (per_row < reach)
        per_row = reach;
    if (per_row > ROVER_WORLD_MAX_POSTS / rows)
        per_row = ROVER_WORLD_MAX_POSTS / rows;
    if (per_row < 1)
        per_row = 1;
    w->n_landmarks = 0;
    for (r = 0; r < rows && w->n_landmarks < ROVER_WORLD_MAX_POSTS; r++)
        for (k = 0; k < per_row && w->n_landmarks < ROVER_WORLD_MAX_POSTS; k++) {
            const double x = per_row == 1 ? 0.5 * (x_lo + x_hi)
                                          : x_lo + (x_hi - x_lo) * k / (per_row - 1);
            w->landmark_m[w->n_landmarks][0] = x;
            w->landmark_m[w->n_landmarks][1] = y0 - f->lane_m * r;
            w->n_landmarks++;
        }
}

/* The rows of teams and their pitch along the way: a row's start area
 * (team 0's robots, as rover_world_layout placed them) ROVER_FLEET_ROW_GAP_M
 * past the farthest a goal formation of the row behind reaches (its goal
 * plus the formation's depth either way). */
static void fleet_rows(const rover_world_config *w, rover_fleet *f, int per_team)
{
    double x_lo = w->start_c[0].x_m, x_hi = x_lo;
    int i;
    for (i = 1; i < per_team; i++) {
        x_lo = fmin(x_lo, w->start_c[i].x_m);
        x_hi = fmax(x_hi, w->start_c[i].x_m);
    }
    f->rows = (f->teams + ROVER_FLEET_ROW_LANES - 1) / ROVER_FLEET_ROW_LANES;
    f->row_m = (w->goal_m[0] - x_lo) + 2.0 * (x_hi - x_lo + ROVER_BODY_LENGTH_M) +
               ROVER_FLEET_ROW_GAP_M;
}

/* How far along the way team t's row lies from the first. */
static double row_x(const rover_fleet *f, int t)
{
    const int row = t / ROVER_FLEET_ROW_LANES; /* whole rows of lanes before t's */
    return f->row_m * (double)row;
}

int rover_fleet_layout(rover_world_config *w, rover_fleet *f, int teams, int per_team,
                       double spacing_m, int formation, int goals)
{
    formation_fsm_params fp;
    double width, x_lo, x_hi;
    int t, i;
    const int lanes = teams < ROVER_FLEET_ROW_LANES ? teams : ROVER_FLEET_ROW_LANES;
    if (!w || !f || teams < 1 || teams > ROVER_FLEET_MAX_TEAMS || per_team < 1 ||
        per_team > ROVER_TEAM_MAX || (long)teams * per_team > ROVER_WORLD_MAX_ROBOTS ||
        (goals != ROVER_FLEET_GOALS_AHEAD && goals != ROVER_FLEET_GOALS_CROSS))
        return ROVER_FLEET_ERR_ARG;
    /* one team's layout on the open world: team 0's robots in w->start_c[0..K-1] */
    if (rover_world_layout(w, ROVER_WORLD_OPEN, per_team, spacing_m, formation) != 0)
        return ROVER_FLEET_ERR_ARG;
    memset(f, 0, sizeof *f);
    f->teams = teams;
    f->per_team = per_team;
    f->goals = goals;
    formation_fsm_params_default(&fp);
    width = formation_width(formation, per_team, spacing_m, 1.0, fp.robot_width_m);
    if (per_team > ROVER_WORLD_ROW_MAX) /* a grid of rows of ROVER_WORLD_ROW_MAX abreast */
        width = fmax(width, spacing_m * (ROVER_WORLD_ROW_MAX - 1) + fp.robot_width_m);
    f->lane_m = width + ROVER_FLEET_LANE_GAP_M;
    fleet_rows(w, f, per_team);
    for (t = 0; t < teams; t++) /* team 0 leftmost (+y) in its row */
        f->lane_y_m[t] = f->lane_m * (0.5 * (lanes - 1) - t % ROVER_FLEET_ROW_LANES);
    /* every team's robots: team 0's (laid out about y = 0) shifted across
     * to the team's lane and along to its row, from the last team down so
     * that team 0's are read before they move */
    for (t = teams - 1; t >= 0; t--)
        for (i = 0; i < per_team; i++) {
            pose2 *c = &w->start_c[t * per_team + i];
            *c = w->start_c[i];
            c->x_m += row_x(f, t);
            c->y_m += f->lane_y_m[t];
        }
    for (t = 0; t < teams; t++) {
        const int partner = goals == ROVER_FLEET_GOALS_CROSS && (t ^ 1) < teams ? (t ^ 1) : t;
        f->goal_m[t][0] = w->goal_m[0] + row_x(f, t);
        f->goal_m[t][1] = f->lane_y_m[partner];
    }
    for (t = 0; t < teams; t++) {
        double sx = 0.0, sy = 0.0;
        for (i = t * per_team; i < (t + 1) * per_team; i++) {
            sx += w->start_c[i].x_m - ROVER_BEACON_D_M;
            sy += w->start_c[i].y_m;
        }
        f->origin[t].x_m = sx / per_team;
        f->origin[t].y_m = sy / per_team;
        f->origin[t].theta_rad = 0.0;
    }
    w->n_robots = teams * per_team;
    w->team_origin = f->origin[0];
    w->goal_m[0] = f->goal_m[0][0];
    w->goal_m[1] = f->goal_m[0][1];
    w->goal_nominal_m[0] = w->goal_m[0];
    w->goal_nominal_m[1] = w->goal_m[1];
    w->goal_fits = 1; /* the open world: nothing in a goal formation's way */
    w->y_max_m = f->lane_y_m[0] + 0.5 * f->lane_m + 1.0;
    w->y_min_m = f->lane_y_m[lanes - 1] - 0.5 * f->lane_m - 1.0;
    w->x_max_m += row_x(f, teams - 1);
    x_lo = w->x_min_m + 1.0;
    x_hi = f->goal_m[teams - 1][0] + 3.0;
    fleet_landmarks(w, f, x_lo, x_hi);
    return 0;
}

int rover_fleet_team_of(const rover_fleet *f, int32_t id)
{
    if (!f || f->per_team < 1 || id < 1 || id > (int32_t)f->teams * f->per_team)
        return ROVER_FLEET_ERR_ARG;
    return (int)((id - 1) / f->per_team);
}

int rover_fleet_members(const rover_fleet *f, int team, int32_t *lo, int32_t *hi)
{
    if (!f || !lo || !hi || team < 0 || team >= f->teams)
        return ROVER_FLEET_ERR_ARG;
    *lo = (int32_t)team * f->per_team + 1;
    *hi = (int32_t)(team + 1) * f->per_team;
    return 0;
}

pose2 rover_fleet_frame_of(const rover_world_config *w, const rover_fleet *f, int32_t id)
{
    const int t = f && f->teams > 1 ? rover_fleet_team_of(f, id) : ROVER_FLEET_ERR_ARG;
    return t >= 0 ? f->origin[t] : w->team_origin;
}

int rover_fleet_goals_id(const char *name)
{
    if (name && strcmp(name, "ahead") == 0)
        return ROVER_FLEET_GOALS_AHEAD;
    if (name && strcmp(name, "cross") == 0)
        return ROVER_FLEET_GOALS_CROSS;
    return ROVER_FLEET_ERR_ARG;
}

const char *rover_fleet_goals_name(int goals)
{
    return goals == ROVER_FLEET_GOALS_CROSS ? "cross" : "ahead";
}
