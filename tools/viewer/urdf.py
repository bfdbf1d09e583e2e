"""urdf: a robot description (URDF) as the viewer draws it.

Reads the links, joints and materials of a URDF (`tandem-scene --urdf`
writes the cell's; a user may give their own with tandem-view --urdf) and
computes every link's world pose from the joint positions: a joint's
child is its parent's pose times the joint's origin times its motion
(a turn about the axis for revolute and continuous joints, a slide for
prismatic ones; fixed joints do not move). Each link's visual bodies
(box, cylinder, sphere, mesh) keep their origin in the link frame and their
colour from the material they name, as the URDF specification says.

Only the Python standard library and numpy, so that tests and tools that
have no Rerun can use it too.
"""
import math
import os
import xml.etree.ElementTree as ET

import numpy as np

DEFAULT_RGBA = (0.7, 0.7, 0.7, 1.0)


class UrdfError(ValueError):
    pass


def _floats(text, n, what):
    try:
        v = [float(x) for x in (text or "").split()]
    except ValueError as e:
        raise UrdfError(f"{what}: not numbers: {text!r}") from e
    if len(v) != n or not all(math.isfinite(x) for x in v):
        raise UrdfError(f"{what}: needs {n} finite numbers, got {text!r}")
    return v


def rpy_matrix(r, p, y):
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def origin_matrix(el, what):
    """The 4x4 of an <origin xyz rpy> element (identity when absent)."""
    T = np.eye(4)
    if el is not None:
        T[:3, 3] = _floats(el.get("xyz", "0 0 0"), 3, what + " origin xyz")
        T[:3, :3] = rpy_matrix(*_floats(el.get("rpy", "0 0 0"), 3, what + " origin rpy"))
    return T


def axis_angle(axis, q):
    """Rotation matrix of a turn by q about the unit vector axis (Rodrigues)."""
    x, y, z = axis
    c, s, v = math.cos(q), math.sin(q), 1.0 - math.cos(q)
    return np.array([[c + x * x * v, x * y * v - z * s, x * z * v + y * s],
                     [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
                     [z * x * v - y * s, z * y * v + x * s, c + z * z * v]])


def quat_of(R):
    """Quaternion (x, y, z, w) of a rotation matrix."""
    w = math.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2.0, R[2, 1] - R[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2.0, R[0, 2] - R[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2.0, R[1, 0] - R[0, 1])
    return [x, y, z, w]


class Visual:
    """One visual body of a link: kind box | cylinder | sphere | mesh, its
    size (box: x y z; cylinder: radius, length; sphere: radius; mesh: scale),
    the mesh file, its pose in the link frame and its colour (0-255 RGB)."""

    def __init__(self, kind, size, origin, rgb, mesh=None):
        self.kind, self.size, self.origin, self.rgb, self.mesh = kind, size, origin, rgb, mesh


class Joint:
    def __init__(self, name, kind, parent, child, origin, axis, lower=None, upper=None):
        self.name, self.kind, self.parent, self.child = name, kind, parent, child
        self.origin, self.axis, self.lower, self.upper = origin, axis, lower, upper


def _rgb(rgba):
    return tuple(int(round(255 * max(0.0, min(1.0, c)))) for c in rgba[:3])


class Robot:
    """A parsed URDF: links (name -> [Visual]), joints (name -> Joint), the root link."""

    def __init__(self, text, base_dir="."):
        try:
            root = ET.fromstring(text)
        except ET.ParseError as e:
            raise UrdfError(f"not XML: {e}") from e
        if root.tag != "robot":
            raise UrdfError(f"the root element is <{root.tag}>, not <robot>")
        self.name = root.get("name", "")
        self.base_dir = base_dir
        materials = {}
        for m in root.findall("material"):
            c = m.find("color")
            if c is not None:
                materials[m.get("name")] = _floats(c.get("rgba"), 4, f"material {m.get('name')}")
        self.links = {}
        for link in root.findall("link"):
            name = link.get("name")
            if not name or name in self.links:
                raise UrdfError(f"a link without a name or named twice: {name!r}")
            self.links[name] = [self._visual(v, materials, name) for v in link.findall("visual")]
        self.joints = {}
        self.child_joint = {}       # child link -> joint
        for j in root.findall("joint"):
            self._joint(j)
        roots = [n for n in self.links if n not in self.child_joint]
        if len(roots) != 1:
            raise UrdfError(f"a URDF is one tree with one root link; roots: {roots}")
        self.root = roots[0]
        self.order = self._topological()

    def _visual(self, v, materials, link):
        what = f"link {link} visual"
        g = v.find("geometry")
        if g is None or len(g) != 1:
            raise UrdfError(f"{what}: needs one <geometry> shape")
        shape = g[0]
        if shape.tag == "box":
            kind, size = "box", _floats(shape.get("size"), 3, what + " box size")
        elif shape.tag == "cylinder":
            kind, size = "cylinder", [float(shape.get("radius", "nan")), float(shape.get("length", "nan"))]
        elif shape.tag == "sphere":
            kind, size = "sphere", [float(shape.get("radius", "nan"))]
        elif shape.tag == "mesh":
            kind, size = "mesh", _floats(shape.get("scale", "1 1 1"), 3, what + " mesh scale")
        else:
            raise UrdfError(f"{what}: unknown shape <{shape.tag}>")
        if not all(math.isfinite(x) for x in size):
            raise UrdfError(f"{what}: {kind} without its size")
        rgba = DEFAULT_RGBA
        m = v.find("material")
        if m is not None:
            c = m.find("color")
            if c is not None:
                rgba = _floats(c.get("rgba"), 4, what + " material")
            elif m.get("name") in materials:
                rgba = materials[m.get("name")]
        mesh = self._mesh_path(shape.get("filename")) if kind == "mesh" else None
        return Visual(kind, size, origin_matrix(v.find("origin"), what), _rgb(rgba), mesh)

    def _mesh_path(self, filename):
        """A mesh file: package://P/rest and file:// are looked for beside the URDF."""
        if not filename:
            raise UrdfError("a mesh without a filename")
        for prefix in ("file://", "package://"):
            if filename.startswith(prefix):
                filename = filename[len(prefix):]
                if prefix == "package://":
                    filename = filename.split("/", 1)[-1]
        return filename if os.path.isabs(filename) else os.path.join(self.base_dir, filename)

    def _joint(self, j):
        name, kind = j.get("name"), j.get("type")
        if kind not in ("fixed", "revolute", "continuous", "prismatic"):
            raise UrdfError(f"joint {name}: type {kind!r} is not drawn (fixed, revolute, continuous, prismatic)")
        parent, child = j.find("parent"), j.find("child")
        if parent is None or child is None:
            raise UrdfError(f"joint {name}: needs a parent and a child")
        parent, child = parent.get("link"), child.get("link")
        for link in (parent, child):
            if link not in self.links:
                raise UrdfError(f"joint {name}: no link {link!r}")
        if child in self.child_joint:
            raise UrdfError(f"link {child} is the child of two joints")
        axis = np.array(_floats((j.find("axis").get("xyz") if j.find("axis") is not None else "1 0 0"), 3,
                                f"joint {name} axis"))
        norm = np.linalg.norm(axis)
        if kind != "fixed" and norm < 1e-12:
            raise UrdfError(f"joint {name}: zero axis")
        lim = j.find("limit")
        lower = float(lim.get("lower", "nan")) if lim is not None else None
        upper = float(lim.get("upper", "nan")) if lim is not None else None
        self.joints[name] = Joint(name, kind, parent, child, origin_matrix(j.find("origin"), f"joint {name}"),
                                  axis / (norm or 1.0), lower, upper)
        self.child_joint[child] = self.joints[name]

    def _topological(self):
        """Links from the root down, each after its parent; refuses a cycle."""
        children = {}
        for j in self.joints.values():
            children.setdefault(j.parent, []).append(j.child)
        order, todo = [], [self.root]
        while todo:
            link = todo.pop()
            order.append(link)
            todo.extend(children.get(link, []))
        if len(order) != len(self.links):
            raise UrdfError("the joints do not join every link to the root once")
        return order

    def below(self, joint_name):
        """Every link the joint moves (its child and all below it)."""
        child = self.joints[joint_name].child
        return [n for n in self.order if n == child or self._is_below(n, child)]

    def _is_below(self, link, top):
        while link in self.child_joint:
            link = self.child_joint[link].parent
            if link == top:
                return True
        return False

    def poses(self, q=None):
        """World (root) pose of every link for joint positions q (joint name ->
        rad or m; a joint not given is at 0)."""
        q = q or {}
        T = {self.root: np.eye(4)}
        for link in self.order[1:]:
            j = self.child_joint[link]
            T[link] = T[j.parent] @ j.origin @ self.motion(j, q.get(j.name, 0.0))
        return T

    @staticmethod
    def motion(j, q):
        M = np.eye(4)
        if j.kind in ("revolute", "continuous"):
            M[:3, :3] = axis_angle(j.axis, q)
        elif j.kind == "prismatic":
            M[:3, 3] = j.axis * q
        return M


def load(path):
    with open(path, encoding="utf-8") as f:
        return Robot(f.read(), os.path.dirname(os.path.abspath(path)))
