"""scene: the static geometry of the tandem world for the viewer.

Everything comes from `tandem-scene`, which prints the core's own const
tables (DH parameters, work cell, rover world, sonar ring, formation slots)
as JSON, so the viewer never keeps a second copy of a number the
controllers use. Forward kinematics here follows arm_model.h: standard DH,
A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i), frame 0 base_height_m above
the mounting surface, whose world pose is the cell's arm_base_T.
"""
import json
import math
import subprocess

import numpy as np


def world_file_args(world_file, start, goal):
    """tandem-scene's words for a world from a file (none for a built-in)."""
    words = []
    if world_file:
        words += ["--world-file", world_file]
        if start:
            words += ["--start", start]
        if goal:
            words += ["--goal", goal]
    return words


def load(scene_bin, world, rovers, formation, extra=()):
    """Runs tandem-scene and returns its JSON as a dict. A world file's walls
    are its merged boxes, as the simulator and the sonar see them."""
    out = subprocess.run([scene_bin, "--world", world, "--rovers", str(max(rovers, 1)),
                          "--formation", formation, *extra],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def _rz_tz(theta, d):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, d], [0, 0, 0, 1.0]])


def _tx_rx(a, alpha):
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1, 0, 0, a], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


class ArmFK:
    """World-frame link geometry of one arm from its joint angles."""

    def __init__(self, model, base_T, tool_length_m):
        self.m = model
        self.base = np.array(base_T, dtype=float).reshape(4, 4)
        lift = np.eye(4)
        lift[2, 3] = model["base_height_m"]
        self.frame0 = self.base @ lift
        self.tool_length_m = tool_length_m

    def frames(self, q):
        """(polyline points, flange transform). The polyline runs from the
        mounting surface through every joint, with the intermediate point
        after the d_i offset so that the PUMA's shoulder offset shows."""
        m = self.m
        T = self.frame0
        pts = [self.base[:3, 3], T[:3, 3]]
        for i in range(6):
            T = T @ _rz_tz(q[i] + m["theta_offset_rad"][i], m["d_m"][i])
            pts.append(T[:3, 3])
            T = T @ _tx_rx(m["a_m"][i], m["alpha_rad"][i])
            pts.append(T[:3, 3])
        return np.array(pts), T

    def tool_point(self, flange):
        return flange[:3, 3] + flange[:3, 2] * self.tool_length_m


def rot_z_quat(theta):
    """Quaternion (x, y, z, w) of a turn about world z."""
    return [0.0, 0.0, math.sin(theta / 2.0), math.cos(theta / 2.0)]
