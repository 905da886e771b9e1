#!/usr/bin/python3
"""Writes the demo arm's meshes (urdf/meshes/*.stl, binary STL, metres) from a few numbers.

Each is a solid of revolution: a closed profile (r, z) turned about the link's z axis, so
the meshes are closed (watertight) and their sizes are readable here rather than hidden in
a binary file. Run again after changing a number; the URDF refers to the files by name.

    scripts/make_arm_meshes.py [output_dir]      (default: urdf/meshes next to this script)
"""
import math
import os
import struct
import sys


def lathe(profile, segments):
    """Triangles (three (x, y, z) tuples, outward for a counter-clockwise profile) of the
    closed polygon `profile` [(r, z), ...] turned about z; points with r = 0 are on the axis."""
    def ring(r, z):
        return [(r * math.cos(2 * math.pi * k / segments), r * math.sin(2 * math.pi * k / segments), z)
                for k in range(segments)]
    rings = [ring(r, z) if r > 0 else [(0.0, 0.0, z)] * segments for r, z in profile]
    triangles = []
    for i in range(len(profile)):
        a_ring, b_ring = rings[i], rings[(i + 1) % len(profile)]
        for k in range(segments):
            a, b = a_ring[k], a_ring[(k + 1) % segments]
            c, d = b_ring[(k + 1) % segments], b_ring[k]
            for tri in ((a, b, c), (a, c, d)):
                if len(set(tri)) == 3:  # the axis collapses one of the two
                    triangles.append(tri)
    return triangles


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    return tuple(x / length for x in n)


def write_stl(path, name, triangles):
    with open(path, "wb") as f:
        f.write(name.encode().ljust(80, b" ")[:80])
        f.write(struct.pack("<I", len(triangles)))
        for tri in triangles:
            f.write(struct.pack("<3f", *normal(*tri)))
            for v in tri:
                f.write(struct.pack("<3f", *v))
            f.write(struct.pack("<H", 0))


def frustum(r_bottom, r_top, length, segments):
    """A bar along +z from 0 to length, tapering from r_bottom to r_top."""
    return lathe([(0.0, 0.0), (r_bottom, 0.0), (r_top, length), (0.0, length)], segments)


def cup(radius, height, wall, bottom, segments):
    """Open-top cup standing on z = 0: solid walls and bottom around an empty cavity."""
    return lathe([(0.0, 0.0), (radius, 0.0), (radius, height), (radius - wall, height),
                  (radius - wall, bottom), (0.0, bottom)], segments)


MESHES = {
    # name: (triangles, what it is)
    "upper_arm.stl": (frustum(0.028, 0.022, 0.22, 8), "upper arm, 22 cm, octagonal, tapering"),
    "forearm.stl": (frustum(0.022, 0.018, 0.18, 8), "forearm, 18 cm, octagonal, tapering"),
    "cup.stl": (cup(0.05, 0.09, 0.012, 0.012, 32), "cup, 10 cm wide, 9 cm tall, 1.2 cm walls"),
}

if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "urdf", "meshes")
    os.makedirs(out, exist_ok=True)
    for name, (triangles, what) in MESHES.items():
        write_stl(os.path.join(out, name), "pbf_ros " + what, triangles)
        print("%-14s %4d triangles  (%s)" % (name, len(triangles), what))
