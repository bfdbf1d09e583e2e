#!/usr/bin/env python3
"""feed_test: the events panel's feed (feed.py) on messages encoded and
decoded by lcm-gen's Python types, as they come off the bus.

Checks that each thing a person follows gives one event, at its sim time
and level, that the periodic messages (an arm's 10 Hz STATUS and PROGRESS,
an unchanged marking or health) give none, and that a viewer that joins
late lists what is so then (but no restart for the first pid it sees).
Run by make view-test before the browser.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "build", "gen", "python"))

from feed import ERROR, INFO, WARN, EventFeed  # noqa: E402
from tandem import action_event_t, health_t, petri_marking_t, rover_state_t, sim_status_t, team_msg_t  # noqa: E402

failures, cases = [], []


def wire(msg):
    """Through the bytes, as the viewer gets it."""
    return type(msg).decode(msg.encode())


def expect(what, events, n, level=None, words=()):
    lines = [e.line() for e in events]
    ok = len(events) == n and all(level is None or e.level == level for e in events) and \
        all(w in " ".join(lines) for w in words)
    cases.append(what)
    print(f"feed_test: {what}: {lines or '(none)'} {'ok' if ok else 'FAILED'}")
    if not ok:
        failures.append(what)


def marking(step, fired, last, stalled=0, silent=0, resumed=0, running=0):
    m = petri_marking_t()
    m.step, m.fired_count, m.last_fired, m.stalled, m.arms_silent, m.resumed = step, fired, last, stalled, silent, resumed
    m.n_places, m.marking, m.n_transitions, m.running = 2, [1, 0], 2, [running & 1, running >> 1]
    m.invariants_ok, m.workpiece_id, m.since_progress_s, m.stall_limit_s = 1, 1, 12.0, 10.0
    return wire(m)


def action(step, event, arm=1, detail=""):
    e = action_event_t()
    e.step, e.event, e.arm, e.action_id, e.transition, e.detail, e.s_m, e.s_f_m = step, event, arm, 7, 3, detail, 0.2, 0.5
    return wire(e)


def health(step, name, pid, hold=0):
    h = health_t()
    h.step, h.name, h.pid, h.safe_hold, h.status = step, name, pid, hold, "ok" if not hold else "state stale"
    return wire(h)


def status(step, stick=0, delivered=0):
    s = sim_status_t()
    s.step, s.stick_inserted, s.stick_target, s.stick_link, s.workpieces_delivered = step, stick, 2, 3, delivered
    return wire(s)


def main():
    f = EventFeed()
    expect("first marking, nothing fired yet", f.marking(marking(100, 0, 0)), 0)
    expect("t1 started", f.marking(marking(800, 0, 0, running=1)), 1, INFO, ["t=   0.800 s", "started t1"])
    expect("t1 fired", f.marking(marking(4300, 1, 1)), 1, INFO, ["t=   4.300 s", "supervisor", "fired t1"])
    expect("the same marking again (10 Hz)", f.marking(marking(4400, 1, 1)), 0)
    expect("stall begins", f.marking(marking(20000, 1, 1, stalled=1)), 1, ERROR, ["STALL"])
    expect("arm 2 silent, stall over", f.marking(marking(21000, 1, 1, silent=2)), 2, None,
           ["stall over", "hears nothing from arm 2"])
    expect("resumed from the journal", f.marking(marking(22000, 1, 1, silent=2, resumed=1)), 1, WARN, ["journal"])
    expect("arm STATUS (10 Hz) is no event", f.action_event(action(5000, action_event_t.STATUS, detail="idle")), 0)
    expect("arm PROGRESS is no event", f.action_event(action(5000, action_event_t.PROGRESS)), 0)
    expect("arm started a row", f.action_event(action(5001, action_event_t.STARTED)), 1, INFO, ["arm 1", "started row 7"])
    expect("arm blocked", f.action_event(action(6000, action_event_t.BLOCKED, 2)), 1, WARN, ["arm 2", "BLOCKED"])
    expect("arm fault", f.action_event(action(6100, action_event_t.FAULT, 2, "q3 over speed")), 1, ERROR,
           ["FAULT: q3 over speed"])
    expect("first health: no restart", f.health(health(1000, "tandem-arm-1", 41)), 0)
    late = EventFeed()
    expect("a viewer joining after t2 fired lists it", late.marking(marking(9000, 2, 2)), 1, INFO,
           ["fired t2 (#2) (2 since the last marking seen)"])
    expect("... and a hold already on", late.health(health(9000, "tandem-arm-2", 50, hold=1)), 1, WARN,
           ["HOLDS SAFE"])
    expect("safe hold", f.health(health(2000, "tandem-arm-1", 41, hold=1)), 1, WARN, ["HOLDS SAFE"])
    expect("restart: a new pid", f.health(health(9000, "tandem-arm-1", 57)), 2, None, ["RESTARTED", "left safe hold"])
    expect("first status, nothing in", f.sim_status(status(100)), 0)
    expect("stick in", f.sim_status(status(7000, stick=1)), 1, WARN, ["stick IN at arm 2, link 3"])
    expect("stick out, a delivery", f.sim_status(status(8000, stick=0, delivered=1)), 2, None,
           ["stick out", "workpiece delivered"])
    r = rover_state_t()
    r.robot, r.mode, r.step = 2, 0, 100
    expect("first rover state, in formation", f.rover_state(wire(r)), 0)
    r.mode, r.step = 1, 3000
    expect("rover mode change", f.rover_state(wire(r)), 1, INFO, ["rover 2", "formation -> dead-zone escape"])
    t = team_msg_t()
    t.robot, t.formation, t.formation_scale, t.step = 1, 0, 1.0, 100
    expect("first team message, line", f.team(wire(t)), 0)
    t.formation, t.step, t.announce, t.announce_seq = 2, 5000, team_msg_t.ANNOUNCE_CHANGE, 1
    expect("formation change and its announcement", f.team(wire(t)), 2, INFO, ["line -> column", "formation change"])
    print(f"feed_test: {len(cases) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
