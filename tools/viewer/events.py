"""events: decodes tandem messages for the viewer and routes them.

draw_latest() turns the newest message of a "latest" channel into drawing
calls (one per frame); handle() takes every message of the low-rate event
channels as it arrives: action events (s(t)), the Petri marking (a row of
tokens, a dark one where a place is marked), SIM_STATUS (the stick),
TEAM (the formation slots), SIM_CONTROL (stick size). Whatever a person
follows in them (feed.py: transitions, blocks, faults, holds, restarts,
stalls, modes) goes to the events panel, one line each.
Every message is placed on the "sim_time" timeline at its simulator step,
so a replay with lcm-logplayer lands on the same time axis as the run.
"""
import re

import numpy as np
import rerun as rr
from feed import SIM_DT_S, EventFeed
from tandem import (action_event_t, arm_state_t, beacon_obs_t, health_t, petri_marking_t, rover_state_t,
                    rover_truth_t, rovers_beacons_t, rovers_sensors_t, rovers_state_t, sim_control_t,
                    sim_status_t, sonar_scan_t, team_msg_t, teams_msg_t, workpiece_detections_t)


def at_step(step):
    if step >= 0:
        rr.set_time("sim_time", duration=step * SIM_DT_S)


class EventLog:
    def __init__(self):
        self.s_latest = {}       # arm -> action_event_t (PROGRESS)
        self.marking = None
        self.feed = EventFeed()
        self.logged = 0          # events put in the panel

    def log(self, events):
        for e in events:
            at_step(e.step)
            rr.log("events", rr.TextLog(e.line(), level=e.level))
            self.logged += 1

    # ---- every message of the event channels ----------------------------
    def handle(self, channel, data, cell, team):
        if channel == "ARM_EVENTS":
            self._action(action_event_t.decode(data))
        elif channel == "PETRI_MARKING":
            self._marking(petri_marking_t.decode(data))
        elif channel.startswith("HEALTH_"):
            self.log(self.feed.health(health_t.decode(data)))
        elif channel == "SIM_CONTROL":
            cell.stick_control(sim_control_t.decode(data))
        elif channel == "SIM_STATUS":
            st = sim_status_t.decode(data)
            self.log(self.feed.sim_status(st))
            at_step(st.step)
            cell.stick_status(st)
        elif channel == "TEAM":
            self._team(team, team_msg_t.decode(data))
        elif channel == "TEAMS":  # a host's robots' team messages, batched
            for t in teams_msg_t.decode(data).team:
                self._team(team, t)

    def _team(self, team, t):
        self.log(self.feed.team(t))
        team.team(t)

    def _action(self, e):
        if e.event == e.PROGRESS:
            self.s_latest[e.arm] = e
            return
        if e.event != e.STATUS:
            at_step(e.step)
            rr.log(f"plots/s/arm{e.arm}", rr.Scalars(e.s_m))
        self.log(self.feed.action_event(e))

    def _marking(self, m):
        key = (bytes(b & 0xFF for b in m.marking), bytes(b & 0xFF for b in m.running))
        self.log(self.feed.marking(m))
        if key == self.marking:
            return
        self.marking = key
        at_step(m.step)
        n = m.n_places
        rr.log("petri/places", rr.Points2D([[1.0 * i, 0.0] for i in range(n)], radii=[0.42] * n,
                                           colors=[(20, 20, 20) if m.marking[i] else (225, 225, 225) for i in range(n)],
                                           labels=[f"p{i + 1}" for i in range(n)]))
        run = [[1.0 * j, 1.2] for j in range(m.n_transitions) if m.running[j]]
        rr.log("petri/running", rr.Points2D(run or np.zeros((0, 2)), radii=[0.3], colors=[(255, 140, 0)],
                                            labels=[f"t{j + 1}" for j in range(m.n_transitions) if m.running[j]]))

    # ---- the newest message of a "latest" channel, once per frame ---------
    def draw_latest(self, channel, data, cell, team):
        if channel in ("ARM1_STATE", "ARM2_STATE"):
            s = arm_state_t.decode(data)
            at_step(s.step)
            cell.arm(s)
            cell.holding[s.arm] = s.holding_workpiece
        elif channel == "VISION_DETECTIONS":
            cell.det = workpiece_detections_t.decode(data)
        elif channel == "ROVER_TRUTH":
            t = rover_truth_t.decode(data)
            at_step(t.step)
            team.truth(t)
        else:
            self._draw_rover(channel, data, team)

    def _draw_rover(self, channel, data, team):
        kind = re.sub(r"^ROVER[0-9]+_", "ROVERk_", channel)
        if kind == "ROVERk_SONAR":
            team.sonar(sonar_scan_t.decode(data))
        elif kind == "ROVERS_SENSORS":
            for scan in rovers_sensors_t.decode(data).sonar:
                team.sonar(scan)
        elif kind == "ROVERk_BEACONS":
            team.beacons(beacon_obs_t.decode(data))
        elif kind == "ROVERS_BEACONS":
            for obs in rovers_beacons_t.decode(data).obs:
                team.beacons(obs)
        elif kind == "ROVERk_STATE":
            self._rover_state(rover_state_t.decode(data))
        elif kind == "ROVERS_STATE":
            for st in rovers_state_t.decode(data).state:
                self._rover_state(st)

    def _rover_state(self, st):
        at_step(st.step)
        rr.log(f"plots/formation_error/R{st.robot}", rr.Scalars(st.formation_err_m))
        self.log(self.feed.rover_state(st))

    def draw_progress(self):
        """s(t) of the synchronised segments, decimated to the frame rate."""
        latest, self.s_latest = self.s_latest, {}
        for arm, e in latest.items():
            at_step(e.step)
            rr.log(f"plots/s/arm{arm}", rr.Scalars(e.s_m))
