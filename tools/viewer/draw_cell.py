"""draw_cell: the two-arm work cell in Rerun (entity tree /cell).

Both PUMAs as link polylines from their measured joint angles (FK from the
core's DH table), gripper fingers (red closed, grey open), the table, the
workpieces the camera sees plus those held in a gripper, the stick when it
is in, and the per-link contact forces as arrows. arm_state_t carries only
the magnitude of each link's contact force (its 10 ms average is drawn), so an arrow points from the
stick at the link when the stick is in, and straight up otherwise; its
length is 1 mm per newton (at most 0.5 m) and its label gives the value.
"""
import numpy as np
import rerun as rr

from scene import ArmFK, rot_z_quat

ARM_COLORS = {1: (255, 128, 0), 2: (30, 110, 255)}
WORKPIECE_COLOR = (240, 220, 40)
FORCE_M_PER_N = 0.001
FORCE_MIN_N = 1.0


class CellDrawer:
    def __init__(self, scene):
        cell = scene["cell"]
        self.cell = cell
        self.fk = {1: ArmFK(scene["arm1_model"], cell["arm_base_T"][0], cell["tool_length_m"]),
                   2: ArmFK(scene["arm2_model"], cell["arm_base_T"][1], cell["tool_length_m"])}
        self.tool = {}
        self.stick = None          # (centre, inserted)
        self.stick_len = (0.6, 0.02)
        self.det = None            # newest workpiece_detections_t
        self.holding = {}          # arm -> workpiece id held (-1 none)

    def log_static(self):
        c = self.cell
        rr.log("cell/table", rr.Boxes3D(centers=[c["table_center_m"]],
                                        half_sizes=[np.array(c["table_size_m"]) / 2],
                                        colors=[(150, 120, 90)], fill_mode="solid"), static=True)
        for k, fk in self.fk.items():
            rr.log(f"cell/arm{k}/base", rr.Cylinders3D(centers=[fk.base[:3, 3] + [0, 0, 0.02]], lengths=[0.04],
                                                       radii=[0.12], colors=[(90, 90, 90)], fill_mode="solid"),
                   static=True)

    def arm(self, s):
        fk = self.fk[s.arm]
        pts, flange = fk.frames(s.q_rad)
        color = ARM_COLORS[s.arm]
        base = f"cell/arm{s.arm}"
        rr.log(base + "/links", rr.LineStrips3D([pts], radii=[0.03], colors=[color]))
        rr.log(base + "/joints", rr.Points3D(pts[1::2], radii=[0.045], colors=[(60, 60, 60)]))
        self.tool[s.arm] = fk.tool_point(flange)
        self._gripper(base, flange, s.gripper_closed, fk.tool_length_m)
        # the 10 ms average (the force sensor's filter), not the raw 1 ms
        # value, whose single-step spikes of a stiff contact mean nothing
        self._forces(base, pts, s.contact_force_10ms_N)
        rr.log(f"plots/contact_force/arm{s.arm}", rr.Scalars(s.max_contact_force_10ms_N))

    def _gripper(self, base, flange, closed, length):
        half = 0.015 if closed else 0.045
        o, y, z = flange[:3, 3], flange[:3, 1], flange[:3, 2]
        fingers = [[o + y * sgn * half, o + y * sgn * half + z * length] for sgn in (-1, 1)]
        fingers.append([o - y * half, o + y * half])
        rr.log(base + "/gripper", rr.LineStrips3D(fingers, radii=[0.008],
                                                  colors=[(220, 30, 30) if closed else (160, 160, 160)]))

    def _forces(self, base, pts, force_N):
        origins, vectors, labels = [], [], []
        for i, f in enumerate(force_N):
            if f < FORCE_MIN_N:
                continue
            at = (pts[2 * i + 1] + pts[2 * i + 3]) / 2     # middle of link i+1
            d = np.array([0.0, 0.0, 1.0])
            if self.stick and self.stick[1]:
                v = at - np.array(self.stick[0])
                d = v / max(np.linalg.norm(v), 1e-9)
            origins.append(at - d * min(f * FORCE_M_PER_N, 0.5))
            vectors.append(d * min(f * FORCE_M_PER_N, 0.5))
            labels.append(f"{f:.0f} N")
        rr.log(base + "/contact", rr.Arrows3D(origins=origins or np.zeros((0, 3)), vectors=vectors or np.zeros((0, 3)),
                                              labels=labels, colors=[(255, 0, 255)], radii=[0.012]))

    def workpieces(self):
        """The camera's workpieces, and those held (not on the table) at the grippers."""
        det, held = self.det, {}
        for arm, wid in self.holding.items():
            if wid >= 0:
                held.setdefault(wid, []).append(arm)
        size = np.array(self.cell["workpiece_size_m"]) / 2
        centres, quats, labels, seen = [], [], [], set()
        for w in det.workpieces[:det.n] if det else []:
            centres.append(w.position_m)
            quats.append(rot_z_quat(w.yaw_rad))
            labels.append(f"#{w.id}")
            seen.add(w.id)
        for wid, arms in held.items():
            if wid in seen or not all(a in self.tool for a in arms):
                continue
            # arm 1 grips the -x end, arm 2 the +x end (cell_grasp_point)
            g = self.cell["grasp_offset_m"]
            cs = [self.tool[a] + np.array([g if a == 1 else -g, 0, 0]) for a in arms]
            centres.append(np.mean(cs, axis=0))
            quats.append(rot_z_quat(0.0))
            labels.append(f"#{wid} held")
        rr.log("cell/workpieces", rr.Boxes3D(centers=centres or np.zeros((0, 3)), half_sizes=[size] * len(centres),
                                             quaternions=quats or None, labels=labels,
                                             colors=[WORKPIECE_COLOR], fill_mode="solid"))

    def stick_status(self, st):
        self.stick = (list(st.stick_position_m), bool(st.stick_inserted))
        if st.stick_inserted:
            length, radius = self.stick_len
            p = np.array(st.stick_position_m) - [0, 0, length / 2]
            rr.log("cell/stick", rr.Capsules3D(lengths=[length], radii=[radius], translations=[p],
                                               colors=[(40, 200, 80)], labels=[f"stick -> arm {st.stick_target}"]))
        else:
            rr.log("cell/stick", rr.Clear(recursive=False))

    def stick_control(self, ctl):
        if ctl.command == ctl.INSERT_STICK:
            self.stick_len = (ctl.length_m, ctl.radius_m)
