"""layout: the viewer's Rerun blueprint (which views, where, looking at what).

Top row: the work cell (3D, looking at the arms over the table) and the
rover team (3D, from above and behind the start). Bottom row: s(t) per arm,
the formation error per robot, the Petri net marking as a row of tokens,
and the events panel (feed.py), widest, as a list of sim time, level and
text. Side panels start collapsed so that the scene gets the page.
"""
import rerun.blueprint as rrb
from rerun.blueprint.encodings import TextLogColumn, TimelineColumn

# fractions of the bottom row: s(t), formation error, marking + force, events
BOTTOM_SHARES = [2, 2, 2, 5]


def blueprint(scene):
    # the team starts around its team-frame origin and drives toward the
    # goal along +x: look a few metres ahead of the start, from behind
    ox, oy = scene["rover_world"]["team_origin"][:2]
    look = [ox + 3.0, oy, 0.0]
    cell = rrb.Spatial3DView(origin="/cell", name="work cell (PUMA 560 pair)",
                             eye_controls=rrb.EyeControls3D(position=[0.0, -1.75, 1.35], look_target=[0.0, 0.35, 0.45],
                                                            eye_up=[0, 0, 1]))
    team = rrb.Spatial3DView(origin="/team", name="rover team",
                             eye_controls=rrb.EyeControls3D(position=[look[0] - 4.0, look[1] - 6.0, 7.0],
                                                            look_target=look, eye_up=[0, 0, 1]))
    plots = rrb.Horizontal(
        rrb.TimeSeriesView(origin="/plots/s", name="s(t) per arm [m]"),
        rrb.TimeSeriesView(origin="/plots/formation_error", name="formation error [m]"),
        rrb.Vertical(rrb.Spatial2DView(origin="/petri", name="Petri net marking"),
                     rrb.TimeSeriesView(origin="/plots/contact_force", name="max contact force, 10 ms avg [N]")),
        rrb.TextLogView(origin="/events", name="events",
                        columns=rrb.TextLogColumns(
                            timeline_columns=[TimelineColumn("sim_time")],
                            text_log_columns=[TextLogColumn("LogLevel"), TextLogColumn("Body"),
                                              TextLogColumn("EntityPath", visible=False)]),
                        format_options=rrb.TextLogFormat(monospace_body=True)),
        column_shares=BOTTOM_SHARES,
    )
    return rrb.Blueprint(rrb.Vertical(rrb.Horizontal(cell, team), plots, row_shares=[3, 2]),
                         collapse_panels=True)
