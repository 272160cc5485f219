"""Groove-centre reconstruction: the displacement of each ring's raceway groove centre from the
FE's probed displacements, and the inner-minus-outer shifts the bearing model takes.

Grooved ring sections: the circle of the ring's thermally grown groove radius fitted to the
displaced groove points (`fem.post.circle_centre_weights`). Rectangular sections: the raceway
point's displacement plus the ring's thermal strain times the centre's offset from that point
(`fem.post.groove_centre_shift`); the offsets follow Harris & Kotzalas Vol. 1 ch. 2 (both centres
on the contact line through the ball centre at the free contact angle). Units mm.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing import SIGNS, BearingGeometry
from analytic.bearing.land import groove_centre_radius_mm
from fem.post import circle_centre_weights, groove_centre_shift

#: the four rings whose groove centres the bearing model needs, in the order of every array here
RINGS = ("inner_ring_A", "inner_ring_B", "outer_ring_A", "outer_ring_B")


@dataclass(frozen=True)
class GrooveCentres:
    """How the groove centres of RINGS are read from probed displacements.

    probe_points_rz_mm (2, n_probe): the points the FE probes, r and z (mm): the raceway points of
    RINGS, then (grooved sections) each ring's groove points. weights: per ring (W, w_theta) of
    the circle fit (None for rectangular sections). offset_mm (4, 2): groove centre minus
    raceway point per ring (r, z), mm."""
    probe_points_rz_mm: np.ndarray
    weights: list | None
    offset_mm: np.ndarray

    @classmethod
    def of(cls, section, geom: BearingGeometry, arrangement: str) -> "GrooveCentres":
        """The centres of a section's rings (`meshes.section`) for a bearing of geometry `geom`
        in `arrangement` (DB, DF, ...)."""
        pts = np.array([section.raceway_points[r] for r in RINGS]).T
        weights = None
        if section.grooves:         # + the groove points whose circle fit gives each centre
            grooves = [section.groove_of(r) for r in RINGS]
            weights = [circle_centre_weights(np.array(g.points_rz_mm).T, (g.r_mm, g.z_mm))
                       for g in grooves]
            pts = np.hstack([pts] + [np.array(g.points_rz_mm).T for g in grooves])
        return cls(pts, weights, centre_offsets_mm(geom, arrangement, pts[:, :4]))

    def centres(self, probe: np.ndarray, theta_rings: np.ndarray) -> np.ndarray:
        """(n, 4, 2) groove-centre displacements (mm) of RINGS from the probed displacements
        (n, n_probe; u_r, u_z of each raceway point first) and each ring's thermal strain
        (n, 4)."""
        n = probe.shape[0]
        centre = np.empty((n, 4, 2))
        m = 0 if self.weights is None else self.weights[0][0].shape[1]
        for k in range(4):
            if self.weights is None:
                centre[:, k, :] = groove_centre_shift(probe[:, 2 * k:2 * k + 2], theta_rings[:, k],
                                                      self.offset_mm[k])
            else:
                cols = slice(8 + k * m, 8 + (k + 1) * m)
                W, w_theta = self.weights[k]
                centre[:, k, :] = probe[:, cols] @ W.T + theta_rings[:, k, None] * w_theta
        return centre

    def shifts_mm(self, probe: np.ndarray, theta_rings: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
        """(dr, dz), each (2, n): inner minus outer groove-centre displacement of bearings A and
        B, radial and axial (mm), what `analytic.bearing.solve_pair` takes."""
        c = self.centres(probe, theta_rings)
        dr = np.stack([c[:, 0, 0] - c[:, 2, 0], c[:, 1, 0] - c[:, 3, 0]])
        dz = np.stack([c[:, 0, 1] - c[:, 2, 1], c[:, 1, 1] - c[:, 3, 1]])
        return dr, dz


def centre_offsets_mm(g: BearingGeometry, arrangement: str, pts: np.ndarray) -> np.ndarray:
    """(4, 2) groove-centre position minus raceway point (pts (2, 4), r and z), per ring of RINGS,
    mm. Inner centre: r = dm/2 + (f_i - 1/2) Dw cos a0, z = z_mid + s_j (f_i - 1/2) Dw sin a0;
    outer centre: r = dm/2 - (f_o - 1/2) Dw cos a0, z = z_mid - s_j (f_o - 1/2) Dw sin a0
    (Harris & Kotzalas Vol. 1 ch. 2: both centres on the contact line through the ball centre;
    s_j the arrangement sign of bearing j)."""
    a0 = np.radians(g.alpha0_deg)
    s = SIGNS[arrangement]
    off = np.zeros((4, 2))
    for k, ring in enumerate(RINGS):
        j = 0 if ring.endswith("A") else 1
        inner = ring.startswith("inner")
        f = g.f_i if inner else g.f_o
        sgn = 1.0 if inner else -1.0
        rc = groove_centre_radius_mm(g, "inner" if inner else "outer")
        zc = pts[1, k] + sgn * s[j] * (f - 0.5) * g.Dw_mm * np.sin(a0)
        off[k] = (rc - pts[0, k], zc - pts[1, k])
    return off
