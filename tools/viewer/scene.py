"""scene: the static geometry of the tandem world for the viewer.

Everything comes from `tandem-scene`, which prints the core's own const
tables (work cell, rover world, sonar ring, formation slots) as JSON, and
the cell as URDF (--urdf: the arms' DH chains, the table), so the viewer
never keeps a second copy of a number the controllers use.
"""
import json
import math
import os
import subprocess

import urdf


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


def load_urdf(scene_bin, path=None):
    """The cell's robot description: the file given, else tandem-scene --urdf's."""
    if path:
        return urdf.load(path)
    out = subprocess.run([scene_bin, "--urdf"], check=True, capture_output=True, text=True).stdout
    return urdf.Robot(out, os.path.dirname(os.path.abspath(scene_bin)))


def rot_z_quat(theta):
    """Quaternion (x, y, z, w) of a turn about world z."""
    return [0.0, 0.0, math.sin(theta / 2.0), math.cos(theta / 2.0)]
