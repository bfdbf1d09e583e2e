"""draw_cell: the two-arm work cell in Rerun (entity tree /cell).

The arms, the table and whatever else the cell's URDF describes are drawn
from the URDF (`tandem-scene --urdf`, or the user's own with tandem-view
--urdf): every link's visual bodies (boxes, cylinders, spheres, meshes) in
its colour, posed by the URDF's joints (urdf.py), in world coordinates:
/cell/robot/armK the bodies arm K's joints move, one entity per kind of
shape (a few log calls a frame), /cell/robot/fixed the others, once.
The revolute joints armK_joint1 .. armK_joint6 take ARMk_STATE's q_rad;
every other joint stays at zero. Besides: the gripper fingers (red closed,
grey open) at the tool frame armK_tool, the workpieces the camera sees plus
those held in a gripper, the stick when it is in, and the per-link contact
forces as arrows. arm_state_t carries only the magnitude of each link's
contact force (its 10 ms average is drawn), so an arrow points from the
stick at the middle of the link (between its joint and the next) when the
stick is in, and straight up otherwise; its length is 1 mm per newton (at
most 0.5 m) and its label gives the value.
"""
import numpy as np
import rerun as rr

from scene import rot_z_quat
from urdf import quat_of

WORKPIECE_COLOR = (240, 220, 40)
FORCE_M_PER_N = 0.001
FORCE_MIN_N = 1.0
ARM_JOINTS = 6


def arm_joint_names(arm):
    return [f"arm{arm}_joint{i}" for i in range(1, ARM_JOINTS + 1)]


def _extent(v):
    return max(v.size) if v.kind == "box" else max(2 * v.size[0], v.size[1]) if v.kind == "cylinder" \
        else 2 * v.size[0] if v.kind == "sphere" else 0.0


def arm_color(robot, arm):
    """An arm's colour: that of the largest visual body its joints move."""
    visuals = [v for link in robot.below(f"arm{arm}_joint1") for v in robot.links[link]]
    return max(visuals, key=_extent).rgb if visuals else (200, 200, 200)


class UrdfArm:
    """One arm of the URDF: its joints, the links they move, its tool frame."""

    def __init__(self, robot, arm):
        missing = [j for j in arm_joint_names(arm) if j not in robot.joints]
        if missing:
            raise SystemExit(f"tandem-view: the URDF has no joint {missing[0]}: arm {arm}'s joints must be named "
                             f"arm{arm}_joint1 .. arm{arm}_joint{ARM_JOINTS}")
        self.joints = [robot.joints[j] for j in arm_joint_names(arm)]
        self.moving = robot.below(self.joints[0].name)
        tool = f"arm{arm}_tool"
        self.tool = tool if tool in robot.links else self.joints[-1].child
        tj = robot.child_joint.get(self.tool)
        self.flange = tj.parent if tj is not None and self.tool != self.joints[-1].child else self.tool
        self.tool_length_m = float(np.linalg.norm(tj.origin[:3, 3])) if self.flange != self.tool else 0.0


class CellDrawer:
    def __init__(self, scene, robot):
        self.cell = scene["cell"]
        self.robot = robot
        self.arms = {k: UrdfArm(robot, k) for k in (1, 2)}
        self.colors = {k: arm_color(robot, k) for k in (1, 2)}
        # the visual bodies by who moves them: arm k's joints, or nothing
        moving = {link: k for k, a in self.arms.items() for link in a.moving}
        self.bodies = {}
        for link, visuals in robot.links.items():
            group = f"arm{moving[link]}" if link in moving else "fixed"
            self.bodies.setdefault(group, []).extend((link, v) for v in visuals)
        self.q = {}                # joint name -> rad, the newest of each arm
        self.tool = {}
        self.stick = None          # (centre, inserted)
        self.stick_len = (0.6, 0.02)
        self.det = None            # newest workpiece_detections_t
        self.holding = {}          # arm -> workpiece id held (-1 none)

    def log_static(self):
        """The bodies no arm joint moves, once; the meshes' files."""
        poses = self.robot.poses()
        for group, items in self.bodies.items():
            for i, (_, v) in enumerate(x for x in items if x[1].kind == "mesh"):
                rr.log(f"cell/robot/{group}/mesh{i}", rr.Asset3D(path=v.mesh, albedo_factor=v.rgb), static=True)
        self._log_bodies("fixed", poses, static=True)

    def _log_bodies(self, group, poses, static=False):
        """A group's bodies in world coordinates, one entity per kind of shape
        (few log calls a frame, whatever the number of links)."""
        ent = f"cell/robot/{group}"
        by_kind = {}
        for link, v in self.bodies.get(group, []):
            by_kind.setdefault(v.kind, []).append((v, poses[link] @ v.origin))
        for kind, vs in by_kind.items():
            centres = [W[:3, 3] for _, W in vs]
            quats = [quat_of(W[:3, :3]) for _, W in vs]
            colors = [v.rgb for v, _ in vs]
            if kind == "box":
                rr.log(f"{ent}/boxes", rr.Boxes3D(centers=centres, half_sizes=[np.array(v.size) / 2 for v, _ in vs],
                                                  quaternions=quats, colors=colors, fill_mode="solid"), static=static)
            elif kind == "cylinder":
                rr.log(f"{ent}/cylinders", rr.Cylinders3D(centers=centres, radii=[v.size[0] for v, _ in vs],
                                                          lengths=[v.size[1] for v, _ in vs], quaternions=quats,
                                                          colors=colors, fill_mode="solid"), static=static)
            elif kind == "sphere":
                rr.log(f"{ent}/spheres", rr.Ellipsoids3D(centers=centres, half_sizes=[[v.size[0]] * 3 for v, _ in vs],
                                                         quaternions=quats, colors=colors, fill_mode="solid"),
                       static=static)
            else:
                for i, (v, W) in enumerate(vs):
                    rr.log(f"{ent}/mesh{i}", rr.Transform3D(translation=W[:3, 3], quaternion=quat_of(W[:3, :3]),
                                                            scale=v.size), static=static)

    def arm(self, s):
        a = self.arms[s.arm]
        for j, q in zip(a.joints, s.q_rad):
            self.q[j.name] = q
        poses = self.robot.poses(self.q)
        self._log_bodies(f"arm{s.arm}", poses)
        base = f"cell/arm{s.arm}"
        flange, tool = poses[a.flange], poses[a.tool]
        self.tool[s.arm] = tool[:3, 3]
        self._gripper(base, flange, s.gripper_closed, a.tool_length_m)
        # the 10 ms average (the force sensor's filter), not the raw 1 ms
        # value, whose single-step spikes of a stiff contact mean nothing
        ends = [(poses[j.parent] @ j.origin)[:3, 3] for j in a.joints] + [tool[:3, 3]]
        self._forces(base, ends, s.contact_force_10ms_N)
        rr.log(f"plots/contact_force/arm{s.arm}", rr.Scalars(s.max_contact_force_10ms_N))

    def _gripper(self, base, flange, closed, length):
        half = 0.015 if closed else 0.045
        o, y, z = flange[:3, 3], flange[:3, 1], flange[:3, 2]
        fingers = [[o + y * sgn * half, o + y * sgn * half + z * length] for sgn in (-1, 1)]
        fingers.append([o - y * half, o + y * half])
        rr.log(base + "/gripper", rr.LineStrips3D(fingers, radii=[0.008],
                                                  colors=[(220, 30, 30) if closed else (160, 160, 160)]))

    def _forces(self, base, ends, force_N):
        """ends: joint 1 .. 6 then the tool point; link i spans ends[i-1] .. ends[i]."""
        origins, vectors, labels = [], [], []
        for i, f in enumerate(force_N[:len(ends) - 1]):
            if f < FORCE_MIN_N:
                continue
            at = (ends[i] + ends[i + 1]) / 2
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
