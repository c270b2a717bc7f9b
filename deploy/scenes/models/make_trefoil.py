#!/usr/bin/env python3
"""Writes trefoil.obj: a closed tube around a trefoil knot, quads, no other data.

    python3 deploy/scenes/models/make_trefoil.py > deploy/scenes/models/trefoil.obj
"""
import math

SEGMENTS, SIDES, RADIUS = 120, 12, 0.45


def curve(t):
    return (math.sin(t) + 2 * math.sin(2 * t), math.cos(t) - 2 * math.cos(2 * t), -math.sin(3 * t))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


print(f"# A trefoil knot tube: {SEGMENTS} x {SIDES} quads, made by make_trefoil.py")
h = 1e-4
for i in range(SEGMENTS):
    t = 2 * math.pi * i / SEGMENTS
    p, ahead, behind = curve(t), curve(t + h), curve(t - h)
    tangent = unit(sub(ahead, behind))
    # The Frenet frame: periodic, so the tube closes on itself; the knot's curvature is never 0.
    normal = unit(sub(sub(ahead, p), sub(p, behind)))
    normal = unit(cross(cross(tangent, normal), tangent))
    binormal = cross(tangent, normal)
    for j in range(SIDES):
        a = 2 * math.pi * j / SIDES
        v = [p[k] + RADIUS * (math.cos(a) * normal[k] + math.sin(a) * binormal[k]) for k in range(3)]
        print("v {:.6f} {:.6f} {:.6f}".format(*v))
for i in range(SEGMENTS):
    for j in range(SIDES):
        corner = lambda di, dj: (i + di) % SEGMENTS * SIDES + (j + dj) % SIDES + 1
        print(f"f {corner(0, 0)} {corner(0, 1)} {corner(1, 1)} {corner(1, 0)}")  # outward
