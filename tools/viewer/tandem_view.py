#!/usr/bin/env python3
"""tandem-view: live 3D viewer of a tandem LCM bus in the browser (Rerun).

Subscribes to the bus (live or an lcm-logplayer replay) and serves Rerun's
web viewer: both PUMAs, gripper, workpieces, table, stick, contact forces;
the Pioneers with headings, sonar cones and echoes, LED beacons, formation
slots, obstacles and goal; plots of s(t) per arm, the formation error, the
contact force, the Petri marking and an event log.

It must never slow the daemons: the LCM handlers only keep the newest raw
message per channel (no decoding, no drawing), and a frame is drawn at most
--rate-hz times a second from whatever is newest then. Only the low-rate
channels that carry events (ARM_EVENTS, PETRI_MARKING, HEALTH_*, SIM_STATUS,
TEAM, SIM_CONTROL) are decoded as they come, so no event is lost between
two frames.
"""
import argparse
import os
import select
import struct
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
# the lcm-gen --python types: next to the script when installed, else the build tree
sys.path.insert(0, os.environ.get("TANDEM_GEN_PYTHON", os.path.join(HERE, "..", "..", "build", "gen", "python")))

import lcm  # noqa: E402
import rerun as rr  # noqa: E402

import scene as scene_mod  # noqa: E402
from draw_cell import CellDrawer  # noqa: E402
from draw_team import TeamDrawer  # noqa: E402
from events import EventLog  # noqa: E402
from layout import blueprint  # noqa: E402

# channel (or LCM regex) -> how it is used: "latest" keeps the newest raw
# message for the next frame, "now" decodes it in the handler
SUBSCRIPTIONS = {
    "ARM[12]_STATE": "latest", "VISION_DETECTIONS": "latest",
    "ROVER_TRUTH": "latest", "ROVER[0-9]+_SONAR": "latest", "ROVER[0-9]+_BEACONS": "latest",
    "ROVER[0-9]+_STATE": "latest", "ROVERS_SENSORS": "latest", "ROVERS_BEACONS": "latest",
    "ROVERS_STATE": "latest",
    "ARM_EVENTS": "now", "PETRI_MARKING": "now", "HEALTH_.*": "now", "SIM_CONTROL": "now",
    "SIM_STATUS": "now", "TEAM": "now", "TEAMS": "now",
}


# LCM keeps every channel name it sees, subscribed or not, for good: a
# flood of made-up names grows the process without end (docs/security.md
# §5-6). The daemons renew their handle on their resident memory; the
# viewer's memory is mostly Rerun's store, so it counts the names instead
# (a catch-all subscription sees every one) and renews its handle once it
# has seen NAMES_MAX distinct ones. A cell has a few hundred channels at
# most (4 per rover, 128 rovers), so a renewal means a flood.
NAMES_MAX = int(os.environ.get("TANDEM_VIEW_NAMES_MAX", "4096"))
DRAIN_MAX = 10000   # messages taken from an old handle before it is closed
UNDECODABLE_MAX = 64  # channels counted one by one when they do not decode


class Bus:
    """The viewer's LCM handle, renewed when it has seen NAMES_MAX names."""

    def __init__(self, url, subscriptions):
        self.url = url
        self.subscriptions = subscriptions   # [(pattern, handler)]
        self.names = set()
        self.renewals = 0
        self.said_s = 0.0
        self.lc = self.open()

    def open(self):
        lc = lcm.LCM(self.url)
        for pattern, handler in self.subscriptions:
            lc.subscribe(pattern, handler)
        lc.subscribe(".*", self.on_any)
        return lc

    def on_any(self, channel, data):
        if len(self.names) < NAMES_MAX:
            self.names.add(channel)

    def fileno(self):
        return self.lc.fileno()

    def handle(self):
        self.lc.handle()
        if len(self.names) >= NAMES_MAX:
            self.renew()

    def renew(self):
        """A new handle subscribed as the old one; what the old one still
        holds is handled (bounded), then it is closed with its names."""
        old, self.lc = self.lc, self.open()
        for _ in range(DRAIN_MAX):
            if old.handle_timeout(0) <= 0:
                break
        del old
        self.names = set()
        self.renewals += 1
        now = time.monotonic()
        if self.renewals == 1 or now - self.said_s >= 10.0:   # a flood renews many times a second
            self.said_s = now
            print(f"tandem-view: LCM handle renewed ({NAMES_MAX} channel names seen; "
                  f"renewals {self.renewals})", file=sys.stderr, flush=True)


def parse_args(argv):
    here_bin = os.path.join(HERE, "..", "..", "build", "bin")
    p = argparse.ArgumentParser(prog="tandem-view", description=__doc__.split("\n\n")[0])
    p.add_argument("--lcm-url", default=os.environ.get("LCM_DEFAULT_URL", "udpm://239.255.76.67:7667?ttl=0"))
    p.add_argument("--web-port", type=int, default=9090, help="port of the web viewer page (default 9090)")
    p.add_argument("--grpc-port", type=int, default=9876, help="port the page streams data from (default 9876)")
    p.add_argument("--rate-hz", type=float, default=15.0, help="frames drawn per second at most (default 15)")
    p.add_argument("--world", default="open", help="rover world the simulator runs (default open)")
    p.add_argument("--world-file", help="the simulator's world from a map_server YAML (tandem-sim --world-file)")
    p.add_argument("--start", help="with --world-file: X,Y,THETA as given to tandem-sim")
    p.add_argument("--goal", help="with --world-file: X,Y as given to tandem-sim")
    p.add_argument("--rovers", type=int, default=3, help="robots in the team (default 3)")
    p.add_argument("--formation", default="line", help="initial formation (default line)")
    p.add_argument("--urdf", help="draw the cell from this URDF (default: tandem-scene --urdf); arm K's joints "
                                   "are armK_joint1 .. armK_joint6, its tool frame armK_tool")
    p.add_argument("--bin", default=os.environ.get("TANDEM_BIN", here_bin), help="directory of tandem-scene")
    p.add_argument("--stats-s", type=float, default=10.0, help="seconds between load lines on stderr (0 = none)")
    p.add_argument("--version", action="store_true", help="program version")
    return p.parse_args(argv)


class Bridge:
    def __init__(self, args, scene, robot):
        self.cell = CellDrawer(scene, robot)
        self.team = TeamDrawer(scene)
        self.events = EventLog()
        self.latest = {}
        self.received = 0
        self.frames = 0
        self.undecodable = {}     # channel -> messages that did not decode

    def on_latest(self, channel, data):
        self.received += 1
        self.latest[channel] = data

    def on_now(self, channel, data):
        self.received += 1
        self.guarded(channel, self.events.handle, channel, data, self.cell, self.team)

    def guarded(self, channel, fn, *args):
        """A message that does not decode (another version of the types,
        a truncated datagram) is counted and reported once, never fatal."""
        try:
            fn(*args)
        except (ValueError, struct.error, IndexError) as e:
            if channel not in self.undecodable and len(self.undecodable) >= UNDECODABLE_MAX:
                channel = "(other channels)"   # a flood of names stays a few entries
            n = self.undecodable.get(channel, 0)
            self.undecodable[channel] = n + 1
            if n == 0:
                print(f"tandem-view: {channel}: message does not decode ({e}); "
                      f"types out of date? (make viewer)", file=sys.stderr, flush=True)

    def draw(self):
        """One frame from the newest message of every channel."""
        latest, self.latest = self.latest, {}
        # ground truth first: sonar cones and beacon rays hang on the poses
        for channel in sorted(latest, key=lambda c: (c != "ROVER_TRUTH", c)):
            self.guarded(channel, self.events.draw_latest, channel, latest[channel], self.cell, self.team)
        self.events.draw_progress()
        if "VISION_DETECTIONS" in latest or "ARM1_STATE" in latest or "ARM2_STATE" in latest:
            self.cell.workpieces()
        self.frames += 1


def serve(args, scene):
    rr.init("tandem")
    uri = rr.serve_grpc(grpc_port=args.grpc_port, default_blueprint=blueprint(scene), server_memory_limit="512MiB")
    rr.serve_web_viewer(web_port=args.web_port, open_browser=False, connect_to=uri)
    url = f"http://localhost:{args.web_port}/?url=" + uri.replace("+", "%2B").replace(":", "%3A").replace("/", "%2F")
    print(f"tandem-view: open {url}", flush=True)
    return url


def run(args):
    scene = scene_mod.load(os.path.join(args.bin, "tandem-scene"), args.world, args.rovers, args.formation,
                           scene_mod.world_file_args(args.world_file, args.start, args.goal))
    robot = scene_mod.load_urdf(os.path.join(args.bin, "tandem-scene"), args.urdf)
    serve(args, scene)
    b = Bridge(args, scene, robot)
    b.cell.log_static()
    b.team.log_static()
    lc = Bus(args.lcm_url, [(pattern, b.on_latest if how == "latest" else b.on_now)
                            for pattern, how in SUBSCRIPTIONS.items()])
    period = 1.0 / args.rate_hz
    next_frame = t_stats = time.monotonic()
    cpu0, n0, f0 = time.process_time(), 0, 0
    while True:
        wait = max(0.0, next_frame - time.monotonic())
        if select.select([lc.fileno()], [], [], wait)[0]:  # a renewal changes it
            lc.handle()
            continue
        b.draw()
        next_frame += period
        now = time.monotonic()
        next_frame = max(next_frame, now)
        if args.stats_s > 0 and now - t_stats >= args.stats_s:
            cpu = time.process_time()
            print(f"tandem-view: {(b.received - n0) / (now - t_stats):.0f} msg/s in, "
                  f"{(b.frames - f0) / (now - t_stats):.1f} frames/s drawn, "
                  f"CPU {100 * (cpu - cpu0) / (now - t_stats):.0f}% of one core", file=sys.stderr, flush=True)
            t_stats, cpu0, n0, f0 = now, cpu, b.received, b.frames


def main(argv):
    args = parse_args(argv)
    if args.version:
        print(f"tandem-view (tandem) {os.environ.get('TANDEM_VERSION', 'unknown')}")
        return 0
    try:
        run(args)
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
