"""feed: what a person follows in a run, found in the messages on the bus.

The viewer's events panel lists these, one line each with its simulated
time, instead of the messages themselves (the arms' 10 Hz STATUS and
PROGRESS would flood it). Each comes from a channel the cell already
publishes; no daemon sends anything for the viewer:

  ARM_EVENTS      rows started, done, rejected; blocks (stick in an arm);
                  joint faults and their clearing
  PETRI_MARKING   transitions started (their rows sent) and fired; stalls; the net dead or an invariant
                  broken; the supervisor resumed from its journal, re-sending
                  rows, no longer hearing an arm or the simulator
  SIM_STATUS      the stick in and out; workpieces placed, delivered,
                  dropped; lockstep participants dropped; pause
  HEALTH_*        safe holds; restarts (a new pid under the same name)
  ROVERk_STATE / ROVERS_STATE   each robot's mode
  TEAM            the team's formation; announcements (leave, rejoin, give way ...)

EventFeed keeps the last value of every counter and flag and returns an
Event where one changed. Before a source's first message every counter
and flag counts as zero, so a viewer started late still lists what is so
when it joins (t1 fired, the stick in, a safe hold) in one line each;
a pid has no such zero: the first one seen is no restart.
Pure Python on lcm-gen's message objects: tests feed it without Rerun.
"""

SIM_DT_S = 0.001
INFO, WARN, ERROR = "INFO", "WARN", "ERROR"

ARM_EVENT = {0: ("started row", INFO), 2: ("done row", INFO), 3: ("BLOCKED", WARN), 4: ("unblocked", INFO),
             5: ("REJECTED row", WARN), 6: ("FAULT", ERROR), 7: ("fault cleared", INFO)}
ARM_PROGRESS, ARM_STATUS = 1, 8      # periodic, not events
MODE_NAMES = {0: "formation", 1: "dead-zone escape", 2: "changing formation", 3: "at goal", 4: "safe stop"}
FORMATIONS = {0: "line", 1: "triangle", 2: "column"}
ANNOUNCE = {1: "leaves the formation", 2: "rejoins", 3: "asks to shrink", 4: "asks for a formation change",
            5: "asks to restore the formation", 6: "gives way"}


class Event:
    __slots__ = ("step", "level", "source", "text")

    def __init__(self, step, level, source, text):
        self.step, self.level, self.source, self.text = step, level, source, text

    def line(self):
        t = f"t={self.step * SIM_DT_S:8.3f} s" if self.step >= 0 else "t=       ? s"
        return f"{t}  {self.source:<10} {self.text}"

    def __repr__(self):
        return f"Event({self.line()!r}, {self.level})"


class EventFeed:
    def __init__(self):
        self.last = {}          # (source, key) -> last value seen

    def _changed(self, source, key, value, first=0):
        """(old, new) when value differs from the last one seen (before the
        first: `first`), else None; first=None: the first value is no change."""
        k = (source, key)
        old = self.last.get(k, first)
        self.last[k] = value
        return (old, value) if old is not None and old != value else None

    # ---- ARM_EVENTS ---------------------------------------------------------
    def action_event(self, e):
        if e.event in (ARM_PROGRESS, ARM_STATUS) or e.event not in ARM_EVENT:
            return []
        what, level = ARM_EVENT[e.event]
        text = what
        if e.event in (0, 2, 5):
            text += f" {e.action_id} (t{e.transition}, segment {e.segment})"
        if e.event == 3:
            text += f" at s={e.s_m:.3f} of {e.s_f_m:.3f} m"
        if e.detail:
            text += f": {e.detail}"
        return [Event(e.step, level, f"arm {e.arm}", text)]

    # ---- PETRI_MARKING --------------------------------------------------------
    def marking(self, m):
        src, out = "supervisor", []

        def ev(level, text):
            out.append(Event(m.step, level, src, text))

        running = tuple(j + 1 for j in range(m.n_transitions) if m.running[j])
        c = self._changed(src, "running", running, first=())
        if c:
            for t in sorted(set(c[1]) - set(c[0])):
                ev(INFO, f"started t{t} (rows sent), workpiece {m.workpiece_id}")
        c = self._changed(src, "fired", m.fired_count)
        if c and c[1] > c[0]:
            n = c[1] - c[0]
            more = f" ({n} since the last marking seen)" if n > 1 else ""
            ev(INFO, f"fired t{m.last_fired} (#{m.fired_count}){more}, workpiece {m.workpiece_id}")
        c = self._changed(src, "stalled", m.stalled)
        if c:
            ev(ERROR, f"STALL: work pending, nothing completed for {m.since_progress_s:.1f} s "
                      f"(limit {m.stall_limit_s:.1f} s)" if m.stalled else "stall over: work completes again")
        c = self._changed(src, "dead", m.dead)
        if c and m.dead:
            ev(ERROR, "the net is DEAD: no transition enabled and none running")
        c = self._changed(src, "invariants_ok", m.invariants_ok, first=1)
        if c and not m.invariants_ok:
            ev(ERROR, f"a place INVARIANT failed ({m.invariant_violations} so far)")
        c = self._changed(src, "resumed", m.resumed)
        if c and m.resumed:
            ev(WARN, "restarted: resumed from its journal")
        c = self._changed(src, "rows_reissued", m.rows_reissued)
        if c and c[1] > c[0]:
            ev(WARN, f"sent {c[1] - c[0]} row(s) again (an arm lost them)")
        c = self._changed(src, "dones_recovered", m.dones_recovered)
        if c and c[1] > c[0]:
            ev(WARN, f"took {c[1] - c[0]} completion(s) from an arm's status (its DONE was lost)")
        c = self._changed(src, "arms_silent", m.arms_silent)
        if c:
            for arm in (1, 2):
                bit = 1 << (arm - 1)
                if (c[0] ^ c[1]) & bit:
                    ev(*((WARN, f"hears nothing from arm {arm}") if c[1] & bit else (INFO, f"hears arm {arm} again")))
        c = self._changed(src, "sim_silent", m.sim_silent)
        if c:
            ev(*((WARN, "hears nothing from the simulator") if m.sim_silent else (INFO, "hears the simulator again")))
        return out

    # ---- SIM_STATUS -----------------------------------------------------------
    def sim_status(self, st):
        src, out = "sim", []

        def ev(level, text):
            out.append(Event(st.step, level, src, text))

        c = self._changed(src, "stick", st.stick_inserted)
        if c:
            ev(WARN, f"stick IN at arm {st.stick_target}, link {st.stick_link}" if st.stick_inserted
               else "stick out")
        for key, level, text in (("workpieces_spawned", INFO, "workpiece placed"),
                                 ("workpieces_delivered", INFO, "workpiece delivered"),
                                 ("workpieces_dropped", ERROR, "workpiece DROPPED"),
                                 ("lockstep_timeouts", WARN, "lockstep dropped a participant that did not answer")):
            value = getattr(st, key)
            c = self._changed(src, key, value)
            if c and c[1] > c[0]:
                ev(level, f"{text} ({key.split('_')[-1]}: {value})")
        c = self._changed(src, "paused", st.paused)
        if c:
            ev(INFO, "paused" if st.paused else "running again")
        return out

    # ---- HEALTH_* ------------------------------------------------------------
    def health(self, h):
        out = []
        c = self._changed(h.name, "pid", h.pid, first=None)
        if c:
            out.append(Event(h.step, WARN, h.name, f"RESTARTED (pid {c[0]} -> {c[1]})"))
        c = self._changed(h.name, "safe_hold", h.safe_hold)
        if c:
            out.append(Event(h.step, WARN if h.safe_hold else INFO, h.name,
                             f"HOLDS SAFE: {h.status}" if h.safe_hold else f"left safe hold: {h.status}"))
        return out

    # ---- rovers ---------------------------------------------------------------
    def rover_state(self, st):
        c = self._changed(f"rover {st.robot}", "mode", st.mode)
        if not c:
            return []
        return [Event(st.step, WARN if st.mode == 4 else INFO, f"rover {st.robot}",
                      f"mode {MODE_NAMES.get(c[0], c[0])} -> {MODE_NAMES.get(st.mode, st.mode)}")]

    def team(self, t):
        out = []
        c = self._changed(f"rover {t.robot}", "formation", (t.formation, round(t.formation_scale, 2)), first=(0, 1.0))
        if c:
            (f0, s0), (f1, s1) = c
            what = (f"formation {FORMATIONS.get(f0, f0)} -> {FORMATIONS.get(f1, f1)}" if f0 != f1
                    else f"formation scale {s0:.2f} -> {s1:.2f}")
            out.append(Event(t.step, INFO, f"rover {t.robot}", what))
        c = self._changed(f"rover {t.robot}", "announce", t.announce_seq)
        if c and t.announce in ANNOUNCE:
            out.append(Event(t.step, INFO, f"rover {t.robot}", ANNOUNCE[t.announce]))
        return out
