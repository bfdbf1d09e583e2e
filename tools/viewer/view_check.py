#!/usr/bin/env python3
"""view_check: loads the viewer page in headless Chromium and checks that
it really drew the arms, the rovers and the events.

Drives Chromium over the DevTools protocol (navigate, wait, screenshot),
then counts the pixels of each thing's colour inside the view where it must
appear: arm 1 and arm 2 in the work-cell view, in the colours their bodies
have in the cell's URDF (tandem-scene --urdf), each robot's colour in the
rover-team view (bodies, sonar cones, beacons), and the workpieces (yellow)
in the work-cell view; and reads the events panel with OCR (tesseract):
it must show at least one event line of feed.py (a sim time and what
happened, e.g. "t= 4.300 s  supervisor fired t1"). The page is checked
every few seconds until every check has passed at some time or the time
is up; the last screenshot that shows everything at once is written (else
the last one), the events panel's crop beside it, and the counts and the
lines read are printed.
Exit 0 when every check passed, 1 otherwise.
"""
import argparse
import base64
import colorsys
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import numpy as np
import websocket
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene  # noqa: E402
from draw_cell import WORKPIECE_COLOR, arm_color  # noqa: E402
from draw_team import robot_color  # noqa: E402

WIDTH, HEIGHT = 1400, 900
# regions as fractions of the page (x0, y0, x1, y1): the blueprint's top row
# is split in two halves below a title bar, above the plots (3:2 rows)
CELL_VIEW = (0.0, 0.05, 0.5, 0.6)
TEAM_VIEW = (0.5, 0.05, 1.0, 0.6)
EVENTS_VIEW = (0.55, 0.6, 1.0, 0.96)    # the bottom row's last 5/11 (layout.BOTTOM_SHARES)
OCR_SCALE = 3                           # egui's small text, enlarged for tesseract
# an event line as feed.Event.line() writes it: sim time, source, what happened
# (tesseract may drop the point and the space of "1.100 s")
EVENT_LINE = re.compile(r"t=\s*[\d.,]+\s*s\s+(supervisor|arm \d|sim|rover \d|tandem-\S+)\s+"
                        r"(fired|started|done|BLOCKED|unblocked|REJECTED|FAULT|fault|STALL|stall|stick|workpiece|"
                        r"mode|formation|HOLDS|left|RESTARTED|restarted|hears|sent|took|paused|running|lockstep|"
                        r"asks|gives|rejoins|leaves)")
HUE_TOLERANCE = 6       # of 256 (about 8 degrees) for a pixel to count
SATURATION_MIN = 0.7    # of the colour's saturation (the table's brown has the orange's hue, half its saturation)
VALUE_MIN = 60          # of 255: darker is shadow
# pixels of a colour that make "drawn": an arm's links and joints cover
# thousands at this size, a robot (body, beacon, heading, sonar cones)
# hundreds, a lit workpiece bar some tens
MIN_PIXELS = {"arm": 300, "workpieces": 40, "rover": 100, "events": 1}


def chromium_binary():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    sys.exit("view_check: no chromium on PATH (tools/deps.sh view-test installs it)")


class Cdp:
    """The least of the DevTools protocol: one page, request/response."""

    def __init__(self, port):
        for _ in range(150):
            try:
                tabs = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json", timeout=2))
                break
            except OSError:
                time.sleep(0.2)
        else:
            sys.exit("view_check: Chromium's DevTools port never answered")
        page = [t for t in tabs if t["type"] == "page"][0]
        # software WebGL on a loaded machine can take minutes per frame
        self.ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=300)
        self.n = 0

    def call(self, method, **params):
        self.n += 1
        self.ws.send(json.dumps({"id": self.n, "method": method, "params": params}))
        while True:
            r = json.loads(self.ws.recv())
            if r.get("id") == self.n:
                if "error" in r:
                    raise RuntimeError(f"{method}: {r['error']}")
                return r["result"]


def count(img, region, color):
    """Pixels of the colour's hue and about its saturation, at any brightness
    above the darkest: the solid bodies are shaded, lines and points are not."""
    hsv = np.asarray(crop(img, region).convert("HSV"), dtype=np.int32)
    h0, s0, _ = (round(255 * x) for x in colorsys.rgb_to_hsv(*(c / 255 for c in color)))
    dh = np.abs(hsv[..., 0] - h0)
    dh = np.minimum(dh, 256 - dh)
    return int(np.count_nonzero((dh <= HUE_TOLERANCE) & (hsv[..., 1] >= SATURATION_MIN * s0)
                                & (hsv[..., 2] >= VALUE_MIN)))


def checks(rovers, robot):
    c = [("arm 1", CELL_VIEW, arm_color(robot, 1)), ("arm 2", CELL_VIEW, arm_color(robot, 2)),
         ("workpieces", CELL_VIEW, WORKPIECE_COLOR)]
    return c + [(f"rover {k}", TEAM_VIEW, robot_color(k)) for k in range(1, rovers + 1)]


def crop(img, region):
    return img.crop(tuple(int(f * s) for f, s in zip(region, (img.width, img.height, img.width, img.height))))


def event_lines(img, out_png):
    """The event lines tesseract reads in the events panel."""
    panel = crop(img, EVENTS_VIEW).convert("L")
    panel = panel.resize((panel.width * OCR_SCALE, panel.height * OCR_SCALE), Image.LANCZOS)
    panel.save(out_png)
    r = subprocess.run(["tesseract", out_png, "-", "--psm", "6"], capture_output=True, text=True)
    return [m.group(0) + line[m.end():] for line in r.stdout.splitlines() for m in [EVENT_LINE.search(line)] if m]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("url")
    ap.add_argument("out_png")
    ap.add_argument("--rovers", type=int, default=3)
    ap.add_argument("--timeout-s", type=float, default=240.0)
    ap.add_argument("--settle-s", type=float, default=8.0, help="keep watching this long after the first pass")
    ap.add_argument("--devtools-port", type=int, default=9222)
    ap.add_argument("--bin", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "bin"),
                    help="directory of tandem-scene (the URDF's colours)")
    ap.add_argument("--urdf", help="the URDF the viewer was given (default: tandem-scene --urdf)")
    a = ap.parse_args()
    if not shutil.which("tesseract"):
        sys.exit("view_check: no tesseract on PATH (tools/deps.sh view-test installs it)")
    robot = scene.load_urdf(os.path.join(a.bin, "tandem-scene"), a.urdf)
    events_png = os.path.splitext(a.out_png)[0] + "-events.png"
    events_seen = []
    prof = tempfile.mkdtemp(prefix="tandem-view-chromium-")
    chrome = subprocess.Popen([chromium_binary(), "--headless=new", "--use-angle=swiftshader",
                               "--enable-unsafe-swiftshader", "--no-sandbox", "--no-first-run",
                               f"--remote-debugging-port={a.devtools_port}", f"--window-size={WIDTH},{HEIGHT}",
                               f"--user-data-dir={prof}", "about:blank"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ok, best, kept = False, {}, False
    try:
        cdp = Cdp(a.devtools_port)
        cdp.call("Page.navigate", url=a.url)
        t0, passed_at = time.monotonic(), None
        while time.monotonic() - t0 < a.timeout_s:
            time.sleep(3.0)
            png = base64.b64decode(cdp.call("Page.captureScreenshot", format="png")["data"])
            img = Image.open(io.BytesIO(png)).convert("RGB")
            counts = [(name, count(img, region, color)) for name, region, color in checks(a.rovers, robot)]
            lines = event_lines(img, events_png)
            events_seen = lines or events_seen
            counts.append(("events", len(lines)))
            for name, n in counts:
                best[name] = max(best.get(name, 0), n)
            # every thing must have been drawn at some time while watching (a
            # workpiece in a gripper may hide for a while); the screenshot kept
            # is the last one that shows all of them at once
            all_now = all(n >= MIN_PIXELS[name.split()[0]] for name, n in counts)
            if all_now or not kept:
                with open(a.out_png, "wb") as f:
                    f.write(png)
                kept = kept or all_now
            ok = all(n >= MIN_PIXELS[name.split()[0]] for name, n in best.items())
            print(f"view_check: t={time.monotonic() - t0:5.1f} s  " +
                  "  ".join(f"{name}: {n}" for name, n in counts), flush=True)
            if ok and passed_at is None:
                passed_at = time.monotonic()
            if passed_at is not None and time.monotonic() - passed_at >= a.settle_s:
                break
    finally:
        chrome.terminate()
        chrome.wait(10)
        shutil.rmtree(prof, ignore_errors=True)
    print(f"view_check: most pixels seen (events: lines read): " + "  ".join(f"{k}: {v}" for k, v in best.items()))
    for line in events_seen:
        print(f"view_check: events panel: {line}")
    print(f"view_check: {'PASS' if ok else 'FAIL'} (pixels needed per colour: {MIN_PIXELS}; "
          f"screenshot {a.out_png})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
