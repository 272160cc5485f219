"""Contact ellipse against the groove edge (land): is the ellipse truncated by the shoulder?

Geometry (cross-section of one ring, mm and degrees). The raceway groove is a circle of radius
r = f Dw about its curvature centre, which sits on the free contact line at a distance
(f - 1/2) Dw beyond the ball centre (Harris & Kotzalas, Rolling Bearing Analysis 5th ed. Vol. 1
ch. 2):

    inner ring:  r_c = dm/2 + (f_i - 1/2) Dw cos(alpha0),   groove surface r = r_c - f_i Dw cos(phi)
    outer ring:  r_c = dm/2 - (f_o - 1/2) Dw cos(alpha0),   groove surface r = r_c + f_o Dw cos(phi)

with phi the angle at the curvature centre measured from the radial direction (the contact point
of a contact at angle alpha sits at phi = alpha). The groove ends at the land (shoulder) of
diameter d_land, at

    cos(phi_land) = (r_c - d_land/2) / (f_i Dw)     (inner),   (d_land/2 - r_c) / (f_o Dw)  (outer).

The Hertz ellipse's semi-major axis a lies across the groove; on a surface of radius f Dw it spans
an angle a / (f Dw) (rad) either side of the contact point. The ellipse is truncated by the land
when alpha + a / (f Dw) > phi_land: the pressure that would lie beyond the edge is carried by the
edge instead (an edge stress the Hertz solution does not describe). Harris & Kotzalas Vol. 2
ch. 1 and ISO/TS 16281:2008 (truncation of the contact ellipse) state this check; the margin
`phi_land - alpha - a/(f Dw)` (deg) is what `simulate` reports (< 0: truncated).

Land diameters: `[bearing] inner_land_diameter_mm` / `outer_land_diameter_mm` (the shoulder on the
loaded side); when not given (0), the land follows from the effective ring section read as the
mean of groove bottom and land (the shipped configurations' stated assumption):
d_land = 2 d_eff - d_bottom.
"""
from __future__ import annotations

import numpy as np

from analytic.bearing.geometry import BearingGeometry, BearingSpec
from analytic.materials import Material


def groove_centre_radius_mm(g: BearingGeometry, side: str) -> float:
    """Radius of the groove curvature centre from the bearing axis (mm), side 'inner'/'outer'."""
    c = np.cos(np.radians(g.alpha0_deg))
    if side == "inner":
        return g.dm_mm / 2 + (g.f_i - 0.5) * g.Dw_mm * c
    return g.dm_mm / 2 - (g.f_o - 0.5) * g.Dw_mm * c


def groove_bottom_diameter_mm(g: BearingGeometry, side: str) -> float:
    """Diameter of the groove bottom (phi = 0), mm."""
    r_c = groove_centre_radius_mm(g, side)
    return 2 * (r_c - g.f_i * g.Dw_mm) if side == "inner" else 2 * (r_c + g.f_o * g.Dw_mm)


def land_diameters_mm(spec: BearingSpec, materials: tuple[Material, ...] = ()
                      ) -> tuple[float, float, str]:
    """(inner, outer) land diameters in mm and where they come from (given, or inferred from the
    effective ring sections as the mean of groove bottom and land)."""
    g = BearingGeometry.from_spec(spec, materials)
    d_i, d_o = spec.inner_land_diameter_mm, spec.outer_land_diameter_mm
    if d_i > 0 and d_o > 0:
        return d_i, d_o, "[bearing] land diameters"
    inferred = (2 * spec.inner_ring_outer_diameter_mm - groove_bottom_diameter_mm(g, "inner"),
                2 * spec.outer_ring_inner_diameter_mm - groove_bottom_diameter_mm(g, "outer"))
    return (d_i if d_i > 0 else inferred[0], d_o if d_o > 0 else inferred[1],
            "inferred: effective ring section = mean of groove bottom and land")


def land_angle_deg(g: BearingGeometry, side: str, land_diameter_mm: float) -> float:
    """Angle phi_land (deg) of the groove edge at the land, from the radial direction."""
    r_c = groove_centre_radius_mm(g, side)
    f = g.f_i if side == "inner" else g.f_o
    c = (r_c - land_diameter_mm / 2) / (f * g.Dw_mm) if side == "inner" else \
        (land_diameter_mm / 2 - r_c) / (f * g.Dw_mm)
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def land_margin_deg(g: BearingGeometry, side: str, land_diameter_mm: float,
                    contact_angle_deg: np.ndarray, a_mm: np.ndarray) -> np.ndarray:
    """phi_land - alpha - a/(f Dw) in degrees (< 0: the ellipse runs over the land)."""
    f = g.f_i if side == "inner" else g.f_o
    half = np.degrees(np.asarray(a_mm, float) / (f * g.Dw_mm))
    return land_angle_deg(g, side, land_diameter_mm) - np.asarray(contact_angle_deg, float) - half


def groove_centre_rz_mm(g: BearingGeometry, side: str, z_ball_mm: float,
                        sign: float) -> tuple[float, float]:
    """(r, z) in mm of a groove curvature centre of a bearing whose ball centre is at axial
    position z_ball_mm, arrangement sign `sign` (+1/-1, `geometry.SIGNS`). Both centres lie on
    the free contact line through the ball centre (Harris & Kotzalas Vol. 1 ch. 2):

        inner:  r = dm/2 + (f_i - 1/2) Dw cos a0,   z = z_ball + s (f_i - 1/2) Dw sin a0
        outer:  r = dm/2 - (f_o - 1/2) Dw cos a0,   z = z_ball - s (f_o - 1/2) Dw sin a0
    """
    f = g.f_i if side == "inner" else g.f_o
    k = 1.0 if side == "inner" else -1.0
    s0 = np.sin(np.radians(g.alpha0_deg))
    return groove_centre_radius_mm(g, side), z_ball_mm + k * sign * (f - 0.5) * g.Dw_mm * s0


def groove_point_rz_mm(g: BearingGeometry, side: str, z_ball_mm: float, sign: float,
                       phi_deg) -> np.ndarray:
    """(2, n) points (r, z) in mm of the groove surface at angles phi (deg) at the groove centre,
    phi = 0 the groove bottom, phi = alpha0 the free contact point (phi > 0 towards the side the
    ring takes its thrust from):

        inner:  X = X_c - f_i Dw (cos phi, s sin phi),   outer:  X = X_c + f_o Dw (cos phi, s sin phi)

    (the contact point lies f Dw from its centre along the contact line; Harris & Kotzalas Vol. 1
    ch. 2)."""
    f = g.f_i if side == "inner" else g.f_o
    k = -1.0 if side == "inner" else 1.0
    rc, zc = groove_centre_rz_mm(g, side, z_ball_mm, sign)
    phi = np.radians(np.atleast_1d(np.asarray(phi_deg, float)))
    return np.array([rc + k * f * g.Dw_mm * np.cos(phi), zc + k * sign * f * g.Dw_mm * np.sin(phi)])
