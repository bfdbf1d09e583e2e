"""draw_team: the Pioneer team in Rerun (entity tree /team).

Robots from the simulator's ground truth (ROVER_TRUTH: the LED beacon point
O and the heading), as chassis boxes with heading arrows and their LED
beacons; the front sonar ring as cones out to each transducer's last echo
(bright, with the echo point) or to its maximum range (faint); the beacon
observations as rays from the observer; the formation slots of the team's
current formation (from TEAM messages) about the team centroid, turned
toward the goal; the obstacles and the goal from the rover world layout.
"""
import math

import numpy as np
import rerun as rr

from scene import rot_z_quat

PALETTE = [(0, 200, 120), (230, 60, 200), (0, 190, 230), (250, 90, 60), (150, 110, 255), (200, 200, 0)]
FORMATIONS = ("line", "triangle", "column")
CONE_STEPS = 6


def robot_color(robot):
    return PALETTE[(robot - 1) % len(PALETTE)]


class TeamDrawer:
    def __init__(self, scene):
        self.world = scene["rover_world"]
        self.body = scene["rover"]
        self.slots = scene["formation"]
        self.pose = {}            # robot -> (O x, O y, theta), world frame
        self.formation = (0, 1.0)  # (type, scale) from TEAM

    def log_static(self):
        boxes, cyls = [], []
        for o in self.world["obstacles"]:
            (boxes if o["kind"] == "box" else cyls).append(o)
        if boxes:
            rr.log("team/obstacles/boxes", rr.Boxes3D(
                centers=[[o["c_m"][0], o["c_m"][1], o["height_m"] / 2] for o in boxes],
                half_sizes=[[o["half_m"][0], o["half_m"][1], o["height_m"] / 2] for o in boxes],
                quaternions=[rot_z_quat(o["angle_rad"]) for o in boxes],
                colors=[(120, 120, 130)], fill_mode="solid"), static=True)
        if cyls:
            rr.log("team/obstacles/circles", rr.Cylinders3D(
                centers=[[o["c_m"][0], o["c_m"][1], o["height_m"] / 2] for o in cyls],
                lengths=[o["height_m"] for o in cyls], radii=[o["r_m"] for o in cyls],
                colors=[(120, 120, 130)], fill_mode="solid"), static=True)
        g = self.world["goal_m"]
        ring = [[g[0] + 0.5 * math.cos(a), g[1] + 0.5 * math.sin(a), 0.01] for a in np.linspace(0, 2 * math.pi, 33)]
        rr.log("team/goal", rr.LineStrips3D([ring], radii=[0.03], colors=[(255, 40, 40)], labels=["goal"]),
               static=True)
        # the LED landmark posts (beacon height) and where each robot starts
        lm = self.world.get("landmarks_m", [])
        if lm:
            rr.log("team/landmarks", rr.Points3D([[x, y, 0.3] for x, y in lm], radii=[0.06],
                                                 colors=[(255, 200, 0)]), static=True)
        st = self.world.get("starts", [])
        if st:
            rr.log("team/starts", rr.Arrows3D(origins=[[x, y, 0.01] for x, y, _ in st],
                                              vectors=[[0.4 * math.cos(th), 0.4 * math.sin(th), 0.0]
                                                       for _, _, th in st],
                                              colors=[(40, 160, 40)]), static=True)

    def truth(self, t):
        self.pose = {t.robot[i]: (t.x_m[i], t.y_m[i], t.theta_rad[i]) for i in range(t.n) if t.alive[i]}
        b = self.body
        centres, quats, colors, origins, vecs, labels = [], [], [], [], [], []
        for r, (x, y, th) in self.pose.items():
            c, s = math.cos(th), math.sin(th)
            off = b["beacon_d_m"] + b["body_offset_m"]       # O -> axle centre C -> box centre
            centres.append([x + off * c, y + off * s, 0.12])
            quats.append(rot_z_quat(th))
            colors.append(robot_color(r))
            origins.append([x, y, 0.3])
            vecs.append([0.8 * c, 0.8 * s, 0.0])
            labels.append(f"R{r}")
        half = [b["body_length_m"] / 2, b["body_width_m"] / 2, 0.12]
        rr.log("team/robots/body", rr.Boxes3D(centers=centres, half_sizes=[half] * len(centres),
                                              quaternions=quats or None, colors=colors, labels=labels,
                                              fill_mode="solid"))
        rr.log("team/robots/heading", rr.Arrows3D(origins=origins or np.zeros((0, 3)), vectors=vecs or np.zeros((0, 3)),
                                                  colors=colors, radii=[0.05]))
        rr.log("team/robots/beacon", rr.Points3D([[o[0], o[1], 0.35] for o in origins], radii=[0.12],
                                                 colors=colors))
        self._slots()

    def _mount(self, robot, k):
        """World position and heading of sonar transducer k of a robot."""
        x, y, th = self.pose[robot]
        d = self.body["beacon_d_m"]
        mx, my, _ = self.body["sonar"][k]
        c, s = math.cos(th), math.sin(th)
        cx, cy = x + d * c, y + d * s
        return cx + mx * c - my * s, cy + mx * s + my * c, th

    def sonar(self, scan):
        if scan.robot not in self.pose:
            return
        half = self.body["sonar_cone_rad"] / 2
        rmax = self.body["sonar_range_max_m"]
        cones, colors, echoes = [], [], []
        base = robot_color(scan.robot)
        for k in range(min(scan.n, len(self.body["sonar"]))):
            px, py, th = self._mount(scan.robot, k)
            a0 = th + scan.angle_rad[k]
            r = min(scan.range_m[k], rmax)
            echo = r < rmax - 1e-6
            arc = [[px + r * math.cos(a), py + r * math.sin(a), 0.2]
                   for a in np.linspace(a0 - half, a0 + half, CONE_STEPS)]
            cones.append([[px, py, 0.2]] + arc + [[px, py, 0.2]])
            colors.append(base if echo else tuple(v // 2 + 110 for v in base))
            if echo:
                echoes.append([px + r * math.cos(a0), py + r * math.sin(a0), 0.2])
        ent = f"team/robots/R{scan.robot}"
        rr.log(ent + "/sonar", rr.LineStrips3D(cones, radii=[0.01], colors=colors))
        rr.log(ent + "/echoes", rr.Points3D(echoes or np.zeros((0, 3)), radii=[0.06], colors=[(255, 30, 30)]))

    def beacons(self, obs):
        if obs.observer not in self.pose:
            return
        x, y, th = self.pose[obs.observer]
        rays = [[[x, y, 0.35], [x + obs.range_m[i] * math.cos(th + obs.bearing_rad[i]),
                                y + obs.range_m[i] * math.sin(th + obs.bearing_rad[i]), 0.35]]
                for i in range(obs.n)]
        rr.log(f"team/robots/R{obs.observer}/beacon_obs", rr.LineStrips3D(
            rays, radii=[0.006], colors=[robot_color(obs.observer)]))

    def team(self, msg):
        self.formation = (msg.formation, msg.formation_scale)

    def _slots(self):
        if not self.pose:
            return
        ftype, scale = self.formation
        offsets = self.slots.get(FORMATIONS[ftype] if 0 <= ftype < 3 else "line", [])
        ids = sorted(self.pose)
        if len(offsets) < len(ids):
            return
        cx = np.mean([self.pose[r][0] for r in ids])
        cy = np.mean([self.pose[r][1] for r in ids])
        g = self.world["goal_m"]
        h = math.atan2(g[1] - cy, g[0] - cx)
        c, s = math.cos(h), math.sin(h)
        pts = [[cx + scale * (c * ox - s * oy), cy + scale * (s * ox + c * oy), 0.02]
               for ox, oy in (offsets[rank] for rank in range(len(ids)))]
        rr.log("team/formation_slots", rr.Points3D(pts, radii=[0.12], colors=[robot_color(r) for r in ids]))
