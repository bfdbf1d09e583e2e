"""foxglove: the tandem world in Foxglove's well-known schemas.

Foxglove's 3D panel draws messages by schema name: foxglove.FrameTransform
(a parent -> child frame) and foxglove.SceneUpdate (boxes, cylinders,
spheres, lines in a frame). This module turns the static geometry that
tandem-scene prints (the core's own tables) and the messages of a log
(arm joint angles, rover ground truth, camera detections, the stick) into
those, so the 3D panel shows the cell as the controllers model it.

Frames: world; armK_base (the mounting surface, the cell's arm_base_T),
armK_link0 (base_height_m above it, DH frame 0), armK_link1..armK_link6
(standard DH: A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i), as in
arm_model.h), armK_tool (tool_length_m along the flange's z); roverK
(point O of robot K, heading theta). These are the cell URDF's link frames
(tandem-scene --urdf), so the links' visual bodies of the URDF are drawn
locked to them (/scene/arm_bodies, sent once).
"""
import math

import numpy as np

LIGHT = {"r": 0.7, "g": 0.7, "b": 0.7, "a": 1.0}

# JSON schemas of the parts of Foxglove's schemas used here (the fields
# Foxglove reads; it identifies the schema by its name).
_TIME = {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}}
_VEC3 = {"type": "object", "properties": {k: {"type": "number"} for k in "xyz"}}
_QUAT = {"type": "object", "properties": {k: {"type": "number"} for k in "xyzw"}}
_POSE = {"type": "object", "properties": {"position": _VEC3, "orientation": _QUAT}}
_COLOR = {"type": "object", "properties": {k: {"type": "number"} for k in "rgba"}}
_PRIM = {"type": "array", "items": {"type": "object"}}
FRAME_TRANSFORM_SCHEMA = {
    "title": "foxglove.FrameTransform", "type": "object",
    "properties": {"timestamp": _TIME, "parent_frame_id": {"type": "string"},
                   "child_frame_id": {"type": "string"}, "translation": _VEC3, "rotation": _QUAT}}
SCENE_UPDATE_SCHEMA = {
    "title": "foxglove.SceneUpdate", "type": "object",
    "properties": {
        "deletions": {"type": "array", "items": {"type": "object", "properties": {
            "timestamp": _TIME, "type": {"type": "integer"}, "id": {"type": "string"}}}},
        "entities": {"type": "array", "items": {"type": "object", "properties": {
            "timestamp": _TIME, "frame_id": {"type": "string"}, "id": {"type": "string"},
            "lifetime": _TIME, "frame_locked": {"type": "boolean"}, "metadata": _PRIM,
            "arrows": _PRIM, "cubes": _PRIM, "spheres": _PRIM, "cylinders": _PRIM,
            "lines": _PRIM, "triangles": _PRIM, "texts": _PRIM, "models": _PRIM}}}}}


def stamp(t_ns):
    return {"sec": t_ns // 1_000_000_000, "nsec": t_ns % 1_000_000_000}


def quat_of(R):
    """Quaternion {x, y, z, w} of a rotation matrix (Shepperd's method:
    the largest of the four candidates keeps the division well away from 0)."""
    t = np.trace(R)
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        q = (0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        v = [0.0, 0.0, 0.0]
        v[i] = 0.25 * s
        v[j] = (R[j, i] + R[i, j]) / s
        v[k] = (R[k, i] + R[i, k]) / s
        q = ((R[k, j] - R[j, k]) / s, v[0], v[1], v[2])
    return {"x": q[1], "y": q[2], "z": q[3], "w": q[0]}


def transform(t_ns, parent, child, T):
    return {"timestamp": stamp(t_ns), "parent_frame_id": parent, "child_frame_id": child,
            "translation": {"x": T[0, 3], "y": T[1, 3], "z": T[2, 3]}, "rotation": quat_of(T[:3, :3])}


def dh(theta, d, a, alpha):
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                     [0, sa, ca, d], [0, 0, 0, 1.0]])


def translation(x, y, z):
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def pose(x, y, z, yaw=0.0):
    return {"position": {"x": x, "y": y, "z": z},
            "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}}


def color(r, g, b, a=1.0):
    return {"r": r, "g": g, "b": b, "a": a}


def entity(t_ns, frame, eid, **prims):
    e = {"timestamp": stamp(t_ns), "frame_id": frame, "id": eid, "lifetime": stamp(0),
         "frame_locked": frame != "world", "metadata": []}
    for k in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"):
        e[k] = prims.get(k, [])
    return e


def cube(p, size, c):
    return {"pose": p, "size": {"x": size[0], "y": size[1], "z": size[2]}, "color": c}


class Scene:
    """Foxglove messages from the static scene and the log's messages."""

    def __init__(self, scene, robot=None):
        self.s = scene
        self.robot = robot            # the cell's URDF (urdf.Robot), for the links' bodies
        cell = scene["cell"]
        self.tool_m = cell["tool_length_m"]
        self.models = [scene["arm1_model"], scene["arm2_model"]]
        self.bases = [np.array(T, dtype=float).reshape(4, 4) for T in cell["arm_base_T"]]

    def static_transforms(self, t_ns):
        out = []
        for k, (m, B) in enumerate(zip(self.models, self.bases), start=1):
            out.append(transform(t_ns, "world", f"arm{k}_base", B))
            out.append(transform(t_ns, f"arm{k}_base", f"arm{k}_link0", translation(0, 0, m["base_height_m"])))
        return out

    def arm_transforms(self, t_ns, arm, q):
        """DH frames 1..6 and the tool of arm `arm` (1 or 2) at joint angles q."""
        m = self.models[arm - 1]
        out, parent = [], f"arm{arm}_link0"
        for i in range(6):
            A = dh(q[i] + m["theta_offset_rad"][i], m["d_m"][i], m["a_m"][i], m["alpha_rad"][i])
            child = f"arm{arm}_link{i + 1}"
            out.append(transform(t_ns, parent, child, A))
            parent = child
        out.append(transform(t_ns, parent, f"arm{arm}_tool", translation(0, 0, self.tool_m)))
        return out

    def arm_lines(self, t_ns, arm, q):
        """The arm's skeleton (mounting surface, every joint, tool) in world,
        so the 3D panel shows bodies and not only axes."""
        m = self.models[arm - 1]
        T = self.bases[arm - 1] @ translation(0, 0, m["base_height_m"])
        pts = [self.bases[arm - 1][:3, 3], T[:3, 3]]
        for i in range(6):
            T = T @ dh(q[i] + m["theta_offset_rad"][i], m["d_m"][i], 0.0, 0.0)
            pts.append(T[:3, 3])
            T = T @ dh(0.0, 0.0, m["a_m"][i], m["alpha_rad"][i])
            pts.append(T[:3, 3])
        pts.append((T @ translation(0, 0, self.tool_m))[:3, 3])
        line = {"type": 0, "pose": pose(0, 0, 0), "thickness": 0.06, "scale_invariant": False,
                "points": [{"x": p[0], "y": p[1], "z": p[2]} for p in pts],
                "color": color(0.9, 0.55, 0.1), "colors": [], "indices": []}
        return {"deletions": [], "entities": [entity(t_ns, "world", f"arm{arm}", lines=[line])]}

    def link_bodies(self, t_ns):
        """The URDF's visual bodies of every link whose frame /tf carries
        (armK_base, armK_link0..6), each entity locked to its link's frame."""
        ents = []
        for link, visuals in (self.robot.links.items() if self.robot else ()):
            if not (link.startswith("arm") and ("_link" in link or link.endswith("_base"))) or not visuals:
                continue
            prims = {"cubes": [], "cylinders": [], "spheres": [], "models": []}
            for v in visuals:
                p = {"position": dict(zip("xyz", v.origin[:3, 3])), "orientation": quat_of(v.origin[:3, :3])}
                c = color(*(x / 255 for x in v.rgb))
                if v.kind == "box":
                    prims["cubes"].append({"pose": p, "size": dict(zip("xyz", v.size)), "color": c})
                elif v.kind == "cylinder":
                    d = 2 * v.size[0]
                    prims["cylinders"].append({"pose": p, "size": {"x": d, "y": d, "z": v.size[1]},
                                               "bottom_scale": 1.0, "top_scale": 1.0, "color": c})
                elif v.kind == "sphere":
                    d = 2 * v.size[0]
                    prims["spheres"].append({"pose": p, "size": {"x": d, "y": d, "z": d}, "color": c})
                else:
                    prims["models"].append({"pose": p, "scale": dict(zip("xyz", v.size)), "color": c,
                                            "override_color": False, "url": "file://" + v.mesh,
                                            "media_type": "", "data": ""})
            ents.append(entity(t_ns, link, f"{link}_body", **prims))
        return {"deletions": [], "entities": ents}

    def rover_transforms(self, t_ns, truth):
        return [transform(t_ns, "world", f"rover{truth.robot[i]}",
                          translation(truth.x_m[i], truth.y_m[i], 0.0) @ _rot_z(truth.theta_rad[i]))
                for i in range(truth.n)]

    def static_scene(self, t_ns, rovers):
        c = self.s["cell"]
        ents = [entity(t_ns, "world", "table", cubes=[cube(pose(*c["table_center_m"]), c["table_size_m"], LIGHT)])]
        w = self.s["rover_world"]
        cubes, cyls = [], []
        for o in w["obstacles"]:
            h = o["height_m"]
            if o["kind"] == "box":
                cubes.append(cube(pose(o["c_m"][0], o["c_m"][1], h / 2, o["angle_rad"]),
                                  [2 * o["half_m"][0], 2 * o["half_m"][1], h], color(0.45, 0.45, 0.5)))
            else:
                d = 2 * o["r_m"]
                cyls.append({"pose": pose(o["c_m"][0], o["c_m"][1], h / 2), "size": {"x": d, "y": d, "z": h},
                             "bottom_scale": 1.0, "top_scale": 1.0, "color": color(0.45, 0.45, 0.5)})
        ents.append(entity(t_ns, "world", "walls", cubes=cubes, cylinders=cyls))
        g = w["goal_m"]
        ents.append(entity(t_ns, "world", "goal", spheres=[{"pose": pose(g[0], g[1], 0.05),
                                                            "size": {"x": 0.3, "y": 0.3, "z": 0.1},
                                                            "color": color(0.9, 0.15, 0.15, 0.8)}]))
        b = self.s["rover"]
        off = b["beacon_d_m"] + b["body_offset_m"]       # O -> axle centre C -> box centre (signed)
        for k in rovers:
            ents.append(entity(t_ns, f"rover{k}", f"rover{k}", cubes=[cube(
                pose(off, 0.0, 0.12), [b["body_length_m"], b["body_width_m"], 0.24], color(0.2, 0.4, 0.9))]))
        return {"deletions": [], "entities": ents}

    def workpieces(self, t_ns, det):
        size = self.s["cell"]["workpiece_size_m"]
        cubes = [cube(pose(*w.position_m, w.yaw_rad), size, color(0.85, 0.75, 0.2)) for w in det.workpieces[:det.n]]
        return {"deletions": [], "entities": [entity(t_ns, "world", "workpieces", cubes=cubes)]}

    def stick(self, t_ns, st):
        if not st.stick_inserted:
            return {"deletions": [{"timestamp": stamp(t_ns), "type": 0, "id": "stick"}], "entities": []}
        length = 0.6
        p = st.stick_position_m
        cyl = {"pose": pose(p[0], p[1], p[2] - length / 2), "size": {"x": 0.04, "y": 0.04, "z": length},
               "bottom_scale": 1.0, "top_scale": 1.0, "color": color(0.15, 0.8, 0.3)}
        return {"deletions": [], "entities": [entity(t_ns, "world", "stick", cylinders=[cyl])]}


def _rot_z(theta):
    T = np.eye(4)
    c, s = math.cos(theta), math.sin(theta)
    T[:2, :2] = [[c, -s], [s, c]]
    return T
