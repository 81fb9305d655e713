"""Closed-form view factors and shadow areas used to verify the ray tracer.

Sources: Incropera, DeWitt, Bergman & Lavine, *Fundamentals of Heat and Mass Transfer*,
6th ed., Table 13.2 (= Howell's catalogue of configuration factors, C-11 and C-14).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull

__all__ = ["parallel_rectangles", "perpendicular_rectangles", "strip_to_wall",
           "sky_view_beside_infinite_wall", "convex_shadow_area"]


def parallel_rectangles(x, y, gap):
    """View factor between two aligned, directly opposed parallel rectangles [-].

    Parameters
    ----------
    x, y : float
        Side lengths of both rectangles [m].
    gap : float
        Distance between their planes [m].

    Notes
    -----
    Incropera Table 13.2 "aligned parallel rectangles" (Howell C-11), with X = x/gap and
    Y = y/gap:
    F = 2/(π X Y) { ln √[(1+X²)(1+Y²)/(1+X²+Y²)] + X √(1+Y²) atan(X/√(1+Y²))
        + Y √(1+X²) atan(Y/√(1+X²)) − X atan X − Y atan Y }.
    """
    X = x / gap
    Y = y / gap
    return 2.0 / (np.pi * X * Y) * (
        0.5 * np.log((1 + X**2) * (1 + Y**2) / (1 + X**2 + Y**2))
        + X * np.sqrt(1 + Y**2) * np.arctan(X / np.sqrt(1 + Y**2))
        + Y * np.sqrt(1 + X**2) * np.arctan(Y / np.sqrt(1 + X**2))
        - X * np.arctan(X) - Y * np.arctan(Y))


def perpendicular_rectangles(edge, width_i, width_j):
    """View factor F_ij from rectangle i to rectangle j, perpendicular with a common edge [-].

    Parameters
    ----------
    edge : float
        Length of the common edge [m].
    width_i, width_j : float
        Widths of rectangles i and j, perpendicular to the common edge [m].

    Notes
    -----
    Incropera Table 13.2 "perpendicular rectangles with a common edge" (Howell C-14), with
    H = width_j/edge, W = width_i/edge:
    F_ij = 1/(π W) { W atan(1/W) + H atan(1/H) − √(H²+W²) atan(1/√(H²+W²))
        + ¼ ln( [(1+W²)(1+H²)/(1+W²+H²)] · [W²(1+W²+H²)/((1+W²)(W²+H²))]^(W²)
                · [H²(1+H²+W²)/((1+H²)(H²+W²))]^(H²) ) }.
    """
    H = width_j / edge
    W = width_i / edge
    s = np.sqrt(H**2 + W**2)
    log_term = (np.log((1 + W**2) * (1 + H**2) / (1 + W**2 + H**2))
                + W**2 * np.log(W**2 * (1 + W**2 + H**2) / ((1 + W**2) * (W**2 + H**2)))
                + H**2 * np.log(H**2 * (1 + H**2 + W**2) / ((1 + H**2) * (H**2 + W**2))))
    return (W * np.arctan(1 / W) + H * np.arctan(1 / H) - s * np.arctan(1 / s)
            + 0.25 * log_term) / (np.pi * W)


def strip_to_wall(length, near, far, height):
    """View factor from a horizontal strip to a vertical wall beside it [-].

    The strip (length ``length`` along the wall's foot, from ``near`` to ``far`` away from
    the wall) and the wall (same length, height ``height``) are aligned rectangles.

    Notes
    -----
    View-factor algebra on the common-edge formula: with S(w) the rectangle from the wall's
    foot to distance w, A(far) F(S(far)→wall) = A(near) F(S(near)→wall) + A(strip) F(strip→wall),
    so F_strip→wall = [far·F(far) − near·F(near)] / (far − near) with
    F(w) = :func:`perpendicular_rectangles`(length, w, height).
    """
    f_far = perpendicular_rectangles(length, far, height)
    f_near = perpendicular_rectangles(length, near, height) if near > 0 else 0.0
    return (far * f_far - near * f_near) / (far - near)


def sky_view_beside_infinite_wall(distance, height):
    """Sky view factor of an upward horizontal point at ``distance`` from an infinitely long
    wall of ``height`` on flat ground [-].

    Notes
    -----
    For infinitely long (2-D) geometry, integrating the cosine-weighted hemisphere along the
    length leaves dF = ½ cos θ dθ in the cross-section (θ from the normal), so a surface seen
    between θ1 < θ2 has F = (sin θ2 − sin θ1)/2 (the differential limit of Hottel's crossed
    strings). The wall spans θ from 90° − β to 90° with
    β = atan(height/distance) its elevation, so F_wall = (1 − cos β)/2 and
    F_sky = (1 + cos β)/2. A horizontal upward point sees nothing below its horizon, so the
    ground/sea takes no share.
    """
    beta = np.arctan2(height, distance)
    return 0.5 * (1.0 + np.cos(beta))


def convex_shadow_area(vertices, sun_dir, plane_z):
    """Area of the shadow of a convex solid on the horizontal plane z = ``plane_z`` [m²].

    The solid lies above the plane; its shadow is the convex hull of its vertices projected
    along the sun direction ``s`` (p − (p_z − plane_z)/s_z · s), whose area is the 2-D
    "volume" of scipy's ConvexHull (Qhull).
    """
    v = np.asarray(vertices, dtype=np.float64)
    s = np.asarray(sun_dir, dtype=np.float64)
    s = s / np.linalg.norm(s)
    t = (v[:, 2] - plane_z) / s[2]
    proj = v[:, :2] - t[:, None] * s[None, :2]
    return float(ConvexHull(proj).volume)
