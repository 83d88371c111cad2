"""Vector helpers and the camera frame of the plugin tests' independent truth: perspective rays
through pixel centres (the filter's documented convention), in plain Python so that pvpython and
pvbatch need nothing else."""
import math


def sub(a, b):
    return [a[k] - b[k] for k in range(3)]


def dot(a, b):
    return sum(a[k] * b[k] for k in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    n = math.sqrt(dot(a, a))
    return [x / n for x in a]


def camera_frame(centre, position, view_angle_degrees):
    """Forward, right and up unit vectors of a camera at `position` looking at `centre` with
    view up +y, and the tangent of half its vertical view angle."""
    forward = unit(sub(centre, position))
    right = unit(cross(forward, [0.0, 1.0, 0.0]))
    up = cross(right, forward)
    return forward, right, up, math.tan(math.radians(view_angle_degrees) / 2)
