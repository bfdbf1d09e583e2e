#!/usr/bin/env python3
"""mcap_check: checks an MCAP file written by tandem-log2mcap against its log.

Reads the log with LCM's own reader (lcm.EventLog, not ours), the MCAP
file with the mcap package's reader, and checks: every event of every
channel is in the MCAP file (counted per channel, and in the file's
summary), at its log time, and its JSON equals, field by field, what
lcm-gen's Python decoder makes of the logged bytes (floats bit for bit;
a non-finite float is null). Both of the mcap package's readers, CRCs checked. The geometry: /tf carries
foxglove.FrameTransform and /scene/* foxglove.SceneUpdate, and the arm's
tool frame composed from /tf lands where the simulator puts the tool
(arm_state_t.tool_position_m) to TOOL_TOL_M. A channel of a type that is
not tandem's (LCM_SELF_TEST) must be there, its bytes as logged.
    mcap_check.py LOG OUT.mcap
"""
import json
import math
import os
import sys

import lcm
import numpy as np
from mcap.reader import make_reader
from mcap.records import Message
from mcap.stream_reader import StreamReader

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "build", "gen", "python"))
TOOL_TOL_M = 1e-6      # ODE's joints give a little (measured: 1e-10 m typical); a wrong frame is metres off


def lcm_types():
    import importlib
    import pkgutil
    import tandem
    out = {}
    for m in pkgutil.iter_modules(tandem.__path__):
        cls = getattr(importlib.import_module(f"tandem.{m.name}"), m.name, None)
        if cls is not None and hasattr(cls, "_get_packed_fingerprint"):
            out[cls._get_packed_fingerprint()] = cls
    return out


def same(a, j, path, errs):
    """a: lcm-gen's value, j: the JSON value."""
    if isinstance(a, float):
        ok = (j is None and not math.isfinite(a)) or (isinstance(j, (int, float)) and float(j) == a)
        if not ok:
            errs.append(f"{path}: {a!r} != {j!r}")
    elif isinstance(a, (list, tuple, bytes, bytearray)):
        if not isinstance(j, list) or len(j) != len(a):
            errs.append(f"{path}: length {len(a)} != {j!r}")
            return
        for i, (x, y) in enumerate(zip(a, j)):
            same(x, y, f"{path}[{i}]", errs)
    elif hasattr(a, "__slots__"):
        if not isinstance(j, dict) or set(j) != set(a.__slots__):
            errs.append(f"{path}: fields {sorted(a.__slots__)} != {sorted(j) if isinstance(j, dict) else j!r}")
            return
        for k in a.__slots__:
            same(getattr(a, k), j[k], f"{path}.{k}", errs)
    elif a != j or type(a) is bool and type(j) is not bool:
        errs.append(f"{path}: {a!r} != {j!r}")


def quat_matrix(q):
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def matrix(tr):
    T = np.eye(4)
    T[:3, :3] = quat_matrix(tr["rotation"])
    T[:3, 3] = [tr["translation"][k] for k in "xyz"]
    return T


class Tf:
    """The newest transform of every child frame, to compose chains."""

    def __init__(self):
        self.parent = {}

    def add(self, tr):
        self.parent[tr["child_frame_id"]] = (tr["parent_frame_id"], matrix(tr))

    def world(self, frame):
        T = np.eye(4)
        while frame != "world":
            if frame not in self.parent:
                return None
            frame, A = self.parent[frame]
            T = A @ T
        return T


def link_bodies(mcap_path, updates, tf):
    """The cell's URDF is attached (cell.urdf), and /scene/arm_bodies draws
    its visuals: one entity per arm link that has bodies, locked to a frame
    /tf carries, with as many shapes as the URDF's link has visuals."""
    sys.path.insert(0, os.path.join(HERE, "..", "viewer"))
    import urdf
    with open(mcap_path, "rb") as f:
        att = [a for a in make_reader(f).iter_attachments() if a.name == "cell.urdf"]
    if len(att) != 1:
        return [f"{len(att)} cell.urdf attachments, expected 1"]
    robot = urdf.Robot(att[0].data.decode())
    want = {link: len(v) for link, v in robot.links.items()
            if v and link.startswith("arm") and ("_link" in link or link.endswith("_base"))}
    ents = {e["frame_id"]: sum(len(e[k]) for k in ("cubes", "cylinders", "spheres", "models"))
            for _, _, u in updates[:1] for e in u["entities"]}
    print(f"geometry: cell.urdf attached ({len(robot.links)} links); /scene/arm_bodies: "
          f"{sum(ents.values())} bodies on {len(ents)} link frames")
    errs = [] if ents == want else [f"/scene/arm_bodies {ents} != the URDF's visuals {want}"]
    return errs + [f"/scene/arm_bodies: frame {f} not in /tf" for f in ents if tf.world(f) is None]


def main(log_path, mcap_path):
    types = lcm_types()
    want = {}                       # channel -> [(log time ns, lcm-gen object)]
    for ev in lcm.EventLog(log_path, "r"):
        cls = types.get(ev.data[:8])
        want.setdefault(ev.channel, []).append((ev.timestamp * 1000, cls.decode(ev.data) if cls else ev.data))
    got, schemas, errs = {}, {}, []
    tf, tool_err, tool_checked, last_state = Tf(), 0.0, 0, {}
    with open(mcap_path, "rb") as f:
        r = make_reader(f, validate_crcs=True)
        summary = r.get_summary()
        # in the order written: lcm-logger's times are receive times and
        # need not grow monotonically (seen: a few ms back under load)
        for schema, channel, message in r.iter_messages(log_time_order=False):
            schemas[channel.topic] = schema.name if schema else None
            data = message.data if channel.message_encoding == "lcm" else json.loads(message.data)
            got.setdefault(channel.topic, []).append((message.sequence, message.log_time, data))
            if channel.topic == "/tf":
                tr = json.loads(message.data)
                tf.add(tr)
                # the tool frame written for the state logged at this time
                st = last_state.get(tr["child_frame_id"])
                if st is not None and st[0] == message.log_time:
                    T = tf.world(tr["child_frame_id"])
                    tool_err = max(tool_err, float(np.linalg.norm(T[:3, 3] - st[1])))
                    tool_checked += 1
            elif channel.topic in ("ARM1_STATE", "ARM2_STATE"):
                j = json.loads(message.data)
                last_state[f"arm{j['arm']}_tool"] = (message.log_time, j["tool_position_m"])
    counts = summary.statistics.channel_message_counts
    # every record read in file order, chunk and data CRCs checked (what
    # the indexed reader above does not walk)
    with open(mcap_path, "rb") as f:
        streamed = sum(isinstance(rec, Message) for rec in StreamReader(f, validate_crcs=True).records)
    if streamed != summary.statistics.message_count:
        errs.append(f"{streamed} message records in the file, summary says {summary.statistics.message_count}")
    by_topic = {c.topic: counts.get(cid, 0) for cid, c in summary.channels.items()}
    for ch in sorted(want):
        w, g = want[ch], [(t, d) for _, t, d in sorted(got.get(ch, []), key=lambda m: m[0])]
        line = f"{ch}: log {len(w)}, mcap {len(g)} (summary {by_topic.get(ch, 0)})"
        if len(w) != len(g) or by_topic.get(ch, 0) != len(w):
            errs.append(line + ": counts differ")
        raw = isinstance(w[0][1], bytes)
        if schemas.get(ch) != (None if raw else f"tandem.{type(w[0][1]).__name__}"):
            errs.append(f"{ch}: schema {schemas.get(ch)}")
        bad = []
        for i, ((tw, a), (tg, j)) in enumerate(zip(w, g)):
            if tw != tg:
                bad.append(f"message {i}: log time {tg} != {tw}")
            if not raw:
                same(a, j, f"message {i}", bad)
            elif a != j:
                bad.append(f"message {i}: bytes differ")
        errs += [f"{ch}: {b}" for b in bad[:5]]
        print(line + ("" if not bad else f", {len(bad)} field(s) differ"))
    for topic, name in (("/tf", "foxglove.FrameTransform"), ("/scene/static", "foxglove.SceneUpdate"),
                        ("/scene/arm_bodies", "foxglove.SceneUpdate")):
        if schemas.get(topic) != name:
            errs.append(f"{topic}: schema {schemas.get(topic)}, expected {name}")
    errs += link_bodies(mcap_path, got.get("/scene/arm_bodies", []), tf)
    print(f"geometry: {len(got.get('/tf', []))} transforms; tool frame from /tf vs the simulator's tool "
          f"position: max {tool_err:.2e} m over {tool_checked} states")
    if tool_checked == 0 or tool_err > TOOL_TOL_M:
        errs.append(f"tool frame off by {tool_err:.4f} m (checked {tool_checked})")
    for e in errs:
        print(f"mcap_check: {e}", file=sys.stderr)
    print(f"mcap_check: {sum(len(v) for v in want.values())} messages on {len(want)} channels: "
          f"{'ok' if not errs else f'{len(errs)} error(s)'}")
    return 1 if errs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
