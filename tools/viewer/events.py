"""events: decodes tandem messages for the viewer and routes them.

draw_latest() turns the newest message of a "latest" channel into drawing
calls (one per frame); handle() takes every message of the low-rate event
channels as it arrives: action events (s(t) and the event log), the Petri
marking (a row of tokens, a dark one where a place is marked), health
(safe holds and overruns into the log) and SIM_CONTROL (stick size).
Every message is placed on the "sim_time" timeline at its simulator step,
so a replay with lcm-logplayer lands on the same time axis as the run.
"""
import re

import numpy as np
import rerun as rr
from tandem import (action_event_t, arm_state_t, beacon_obs_t, health_t, petri_marking_t, rover_state_t,
                    rover_truth_t, rovers_beacons_t, rovers_sensors_t, rovers_state_t, sim_control_t,
                    sim_status_t, sonar_scan_t, team_msg_t, workpiece_detections_t)

EVENT_NAMES = {0: "STARTED", 1: "PROGRESS", 2: "DONE", 3: "BLOCKED", 4: "UNBLOCKED", 5: "REJECTED"}
MODE_NAMES = {0: "formation", 1: "dead-zone escape", 2: "changing formation", 3: "at goal", 4: "safe stop"}
SIM_DT_S = 0.001


def at_step(step):
    if step >= 0:
        rr.set_time("sim_time", duration=step * SIM_DT_S)


class EventLog:
    def __init__(self):
        self.s_latest = {}       # arm -> action_event_t (PROGRESS)
        self.mode = {}           # robot -> mode
        self.safe = {}           # daemon -> safe_hold
        self.marking = None
        self.fired = 0

    # ---- every message of the event channels ----------------------------
    def handle(self, channel, data, cell):
        if channel == "ARM_EVENTS":
            self._action(action_event_t.decode(data))
        elif channel == "PETRI_MARKING":
            self._marking(petri_marking_t.decode(data))
        elif channel.startswith("HEALTH_"):
            self._health(health_t.decode(data))
        elif channel == "SIM_CONTROL":
            cell.stick_control(sim_control_t.decode(data))

    def _action(self, e):
        if e.event == e.PROGRESS:
            self.s_latest[e.arm] = e
            return
        at_step(e.step)
        rr.log(f"plots/s/arm{e.arm}", rr.Scalars(e.s_m))
        level = "WARN" if e.event in (e.BLOCKED, e.REJECTED) else "INFO"
        rr.log("events", rr.TextLog(f"arm {e.arm} {EVENT_NAMES.get(e.event, e.event)} action {e.action_id} "
                                    f"(t{e.transition}, segment {e.segment}) s={e.s_m:.3f}/{e.s_f_m:.3f} m "
                                    f"{e.detail}", level=level))

    def _marking(self, m):
        key = (bytes(b & 0xFF for b in m.marking), bytes(b & 0xFF for b in m.running))
        if m.fired_count > self.fired and m.last_fired > 0:
            at_step(m.step)
            rr.log("events", rr.TextLog(f"supervisor fired t{m.last_fired} (#{m.fired_count}), "
                                        f"workpiece {m.workpiece_id}", level="DEBUG"))
        self.fired = m.fired_count
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

    def _health(self, h):
        was = self.safe.get(h.name, 0)
        self.safe[h.name] = h.safe_hold
        if h.safe_hold != was:
            at_step(h.step)
            rr.log("events", rr.TextLog(f"{h.name} {'HOLDS SAFE' if h.safe_hold else 'left safe hold'}: {h.status}",
                                        level="WARN" if h.safe_hold else "INFO"))

    # ---- the newest message of a "latest" channel, once per frame ---------
    def draw_latest(self, channel, data, cell, team):
        if channel in ("ARM1_STATE", "ARM2_STATE"):
            s = arm_state_t.decode(data)
            at_step(s.step)
            cell.arm(s)
            cell.holding[s.arm] = s.holding_workpiece
        elif channel == "VISION_DETECTIONS":
            cell.det = workpiece_detections_t.decode(data)
        elif channel == "SIM_STATUS":
            st = sim_status_t.decode(data)
            at_step(st.step)
            cell.stick_status(st)
        elif channel == "ROVER_TRUTH":
            t = rover_truth_t.decode(data)
            at_step(t.step)
            team.truth(t)
        elif channel == "TEAM":
            team.team(team_msg_t.decode(data))
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
        if self.mode.get(st.robot) != st.mode:
            self.mode[st.robot] = st.mode
            rr.log("events", rr.TextLog(f"rover {st.robot}: {MODE_NAMES.get(st.mode, st.mode)}"))

    def draw_progress(self):
        """s(t) of the synchronised segments, decimated to the frame rate."""
        latest, self.s_latest = self.s_latest, {}
        for arm, e in latest.items():
            at_step(e.step)
            rr.log(f"plots/s/arm{arm}", rr.Scalars(e.s_m))
