#!/usr/bin/env python3
"""urdf_check: the URDF of `tandem-scene --urdf`, read by a parser not ours.

Loads the URDF with yourdfpy (which also builds its kinematic tree and so
refuses a malformed one) and checks that its forward kinematics agree
with tandem-kin's to TOL on reference configurations (zero, the range
ends, random ones inside the ranges): the flange pose of each arm in its
mounting frame, and the tool pose (tandem-kin --tool). Also that every
revolute joint carries its limits, effort and velocity and every DH link
its mass, as the table gives them (checked against tandem-kin's grav,
which uses the masses: M(q) gravity torques computed from the URDF's
inertials must agree).
    urdf_check.py BIN_DIR
"""
import os
import subprocess
import sys

import numpy as np
import yourdfpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "viewer"))
import urdf as viewer_urdf  # noqa: E402  the browser viewer's reader

TOL = 1e-9
G = 9.81


def kin(bin_dir, *args):
    out = subprocess.run([os.path.join(bin_dir, "tandem-kin"), *map(str, args)],
                         check=True, capture_output=True, text=True).stdout
    return np.array([[float(x) for x in line.split()] for line in out.strip().splitlines()])


def configs(robot, arm, n_random=20):
    joints = [robot.joint_map[f"arm{arm}_joint{i}"] for i in range(1, 7)]
    lo = np.array([j.limit.lower for j in joints])
    hi = np.array([j.limit.upper for j in joints])
    rng = np.random.default_rng(7)
    yield np.zeros(6)
    yield lo
    yield hi
    for _ in range(n_random):
        yield lo + rng.random(6) * (hi - lo)


def grav_urdf(robot, arm, q):
    """Gravity torques from the URDF's masses and centres of mass: tau_i =
    z_{i-1} . sum over links j >= i of (p_com_j - p_{i-1}) x m_j g, in the
    mounting frame, joint i turning about z of frame i-1."""
    base = f"arm{arm}_base"
    tau = np.zeros(6)
    coms = []
    for j in range(1, 7):
        link = robot.link_map[f"arm{arm}_link{j}"]
        T = robot.get_transform(frame_to=link.name, frame_from=base)
        c = T @ np.append(link.inertial.origin[:3, 3], 1.0)
        coms.append((link.inertial.mass, c[:3]))
    for i in range(1, 7):
        T = robot.get_transform(frame_to=f"arm{arm}_link{i - 1}", frame_from=base)
        z, p = T[:3, 2], T[:3, 3]
        f = np.array([0.0, 0.0, -G])
        tau[i - 1] = -sum(z @ np.cross(c - p, m * f) for m, c in coms[i - 1:])
    return tau


def viewer_pose_error(robot, viewer):
    """Largest difference over every link between the viewer's world poses
    and yourdfpy's, for yourdfpy's configuration of every joint."""
    poses = viewer.poses(dict(zip(robot.actuated_joint_names, robot.cfg)))
    return max(float(np.abs(poses[name] - robot.get_transform(frame_to=name, frame_from=robot.base_link)).max())
               for name in poses)


def viewer_visuals(robot, viewer):
    """The viewer draws each link's visuals where and as the URDF says:
    the same number, shapes and origins as yourdfpy reads."""
    errs, n = [], 0
    for link in robot.robot.links:
        mine = viewer.links[link.name]
        if len(mine) != len(link.visuals):
            errs.append(f"link {link.name}: the viewer has {len(mine)} visuals, yourdfpy {len(link.visuals)}")
            continue
        for v, theirs in zip(mine, link.visuals):
            o = theirs.origin if theirs.origin is not None else np.eye(4)
            g = theirs.geometry
            size = (list(g.box.size) if g.box else [g.cylinder.radius, g.cylinder.length] if g.cylinder
                    else [g.sphere.radius] if g.sphere else None)
            if np.abs(v.origin - o).max() > TOL or (size is not None and np.abs(np.array(v.size) - size).max() > TOL):
                errs.append(f"link {link.name}: a visual differs from yourdfpy's")
            n += 1
    print(f"urdf_check: {n} visual bodies, as yourdfpy reads them, in the viewer's reader")
    return errs


def viewer_refuses():
    """The viewer's reader refuses what is not one tree of links."""
    bad = {
        "two roots": '<robot name="r"><link name="a"/><link name="b"/></robot>',
        "a joint to no link": '<robot name="r"><link name="a"/><joint name="j" type="fixed">'
                              '<parent link="a"/><child link="b"/></joint></robot>',
        "a cycle": '<robot name="r"><link name="w"/><link name="a"/><link name="b"/>'
                   '<joint name="j0" type="fixed"><parent link="w"/><child link="a"/></joint>'
                   '<joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>'
                   '<joint name="j2" type="fixed"><parent link="b"/><child link="a"/></joint></robot>',
        "a shapeless visual": '<robot name="r"><link name="a"><visual><geometry/></visual></link></robot>',
        "not a robot": '<model name="r"/>',
    }
    errs = []
    for what, text in bad.items():
        try:
            viewer_urdf.Robot(text)
            errs.append(f"the viewer's reader took a URDF with {what}")
        except viewer_urdf.UrdfError:
            pass
    return errs


def main(bin_dir):
    urdf = subprocess.run([os.path.join(bin_dir, "tandem-scene"), "--urdf"], check=True,
                          capture_output=True, text=True).stdout
    path = os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "cell.urdf")
    with open(path, "w") as f:
        f.write(urdf)
    robot = yourdfpy.URDF.load(path, load_meshes=False, build_collision_scene_graph=False)
    revolute = [j for j in robot.robot.joints if j.type == "revolute"]
    bad = [j.name for j in revolute if not (j.limit and j.limit.lower < j.limit.upper
                                             and j.limit.effort > 0 and j.limit.velocity > 0)]
    print(f"urdf_check: {len(robot.robot.links)} links, {len(robot.robot.joints)} joints "
          f"({len(revolute)} revolute), {len(robot.actuated_joint_names)} actuated; "
          f"root {robot.base_link}")
    errs = [f"joint {n}: no limits, effort or velocity" for n in bad]
    if len(revolute) != 12:
        errs.append(f"{len(revolute)} revolute joints, expected 12")
    viewer = viewer_urdf.load(path)
    errs += viewer_visuals(robot, viewer)
    worst = {"flange": 0.0, "tool": 0.0, "grav": 0.0, "viewer": 0.0}
    n = 0
    for arm in (1, 2):
        for q in configs(robot, arm):
            cfg = {f"arm{arm}_joint{i + 1}": q[i] for i in range(6)}
            robot.update_cfg(cfg)
            base = f"arm{arm}_base"
            for what, frame, extra in (("flange", f"arm{arm}_link6", []),
                                       ("tool", f"arm{arm}_tool", ["--tool", 0, 0, 0.1])):
                T_urdf = robot.get_transform(frame_to=frame, frame_from=base)
                T_kin = kin(bin_dir, *extra, "fk", *q)
                worst[what] = max(worst[what], float(np.abs(T_urdf - T_kin).max()))
            worst["viewer"] = max(worst["viewer"], viewer_pose_error(robot, viewer))
            g_kin = kin(bin_dir, "grav", *q).ravel()
            worst["grav"] = max(worst["grav"], float(np.abs(grav_urdf(robot, arm, q) - g_kin).max()))
            n += 1
    print(f"urdf_check: {n} configurations: flange pose max |URDF - tandem-kin| {worst['flange']:.2e}, "
          f"tool pose {worst['tool']:.2e}, gravity torques {worst['grav']:.2e} N m; "
          f"the viewer's link poses vs yourdfpy {worst['viewer']:.2e}")
    if worst["viewer"] > TOL:
        errs.append(f"the viewer's reader (tools/viewer/urdf.py) places links more than {TOL} off yourdfpy")
    errs += viewer_refuses()
    if worst["flange"] > TOL or worst["tool"] > TOL:
        errs.append(f"forward kinematics differ by more than {TOL}")
    if worst["grav"] > 1e-6:
        errs.append("gravity torques from the URDF's masses differ from tandem-kin grav by more than 1e-6 N m")
    for e in errs:
        print(f"urdf_check: {e}", file=sys.stderr)
    print(f"urdf-test: {0 if errs else 1} passed, {1 if errs else 0} failed")
    return 1 if errs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
