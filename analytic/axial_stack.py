"""The simplified axial model of a preloaded back-to-back pair on a shaft: stack lengths that grow
with their CTEs take up the bearings' axial deformation (seed 000's preload model), and its
extension with every part an elastic bar.

Source: Ning F., Fan X., Chen R., An J., Zhao Y., alternating-temperature tests of a space bearing
pair (NSK 71807C, 9Cr18, in a TC4 shaft and housing), journal paper in Chinese (the `source` of
studies/configs/seed000_71807C_TC4.toml), its section on the preload under alternating
temperature, eqs. (14)-(20). The equations are lost in our copy; the text states them in words:
at room temperature the shaft length L_s, the bearing width B and the spacer length L_g are
related through the bearings' axial deformation delta_a and axial clearance u_a (eq. 14); at
temperature B, L_g and L_s become B', L_g', L_s' with their own CTEs alpha_b, alpha_g, alpha_s
(eqs. 15-17); the same relation with u_aT and delta_a' (eq. 18); the contact angle follows from
delta_a' and the grown groove-centre distance B D_w' (eq. 19) and the preload from the contact
angle with the load-deflection constant K_n (eq. 20). The paper states that on heating the
bearings' axial deformation grows (9Cr18 grows faster than TC4), so the preload rises. Read that
way, with the shaft locating the inner rings at its length L_s and the spacer L_g between the two
bearings (L_s = 2 B + L_g at assembly, delta_a and u_a being microns):

    delta_a' - delta_a = 2 B theta_b + L_g theta_g - L_s theta_s            (eqs. 14-18)

theta = integral alpha dT (`Material.thermal_strain`), per part. Eqs. 19-20 are Harris's
axial-load relations (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 7): they are
`analytic.bearing.solve_pair` with the bearing grown uniformly (all 9Cr18: B D_w' = B D_w
(1 + theta_b), the free contact angle unchanged) and the pair's approach changed by the mismatch
above, shared by the two bearings.

`elastic_mismatch_mm` is the same length balance with the clamped inner stack (inner ring,
inner spacer, inner ring between the shaft shoulder and the nut) and the shaft as bars of
compliance L / (E A) in series (Timoshenko & Gere, Mechanics of Materials, ch. 2: statically
indeterminate axial members with temperature change): the stack, which grows more than the
shaft, is compressed and the shaft stretched by the same clamp force. The outer rings and the
outer spacer are held by a compliant cover and grow freely. With a rigid shaft and rigid rings
it is the paper's relation. Units: mm, N, MPa, C.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing import solve_pair
from analytic.bearing.geometry import SIGNS, BearingGeometry
from analytic.materials import Material


@dataclass(frozen=True)
class Bar:
    """A stack part as an axial bar: length (mm), cross-section area (mm^2), material."""
    length_mm: float
    area_mm2: float
    material: Material

    def growth_mm(self, T_C, T_ref_C) -> np.ndarray:
        """Free thermal growth L theta (mm)."""
        return self.length_mm * np.asarray(self.material.thermal_strain(np.asarray(T_C, float), T_ref_C))

    @property
    def compliance_mm_per_N(self) -> float:
        """L / (E A), mm/N."""
        return self.length_mm / (self.material.E_MPa * self.area_mm2)


@dataclass(frozen=True)
class AxialStack:
    """The axial stack of a back-to-back pair: each ring (width B, inner- and outer-ring
    sections), the inner spacer between the inner rings, the outer spacer (the paper's L_g)
    between the outer rings, and the shaft between its shoulder and the nut (the paper's L_s =
    2 B + inner spacer length)."""
    inner_ring: Bar
    outer_ring: Bar
    inner_spacer: Bar
    outer_spacer: Bar
    shaft: Bar


def paper_mismatch_mm(stack: AxialStack, T_C, T_ref_C: float) -> np.ndarray:
    """Change of the pair's axial deformation (mm) from T_ref to T, the paper's eqs. 14-18:
    2 B theta_b + L_g theta_g - L_s theta_s (all parts rigid; the shaft sets the inner rings)."""
    return (2 * stack.inner_ring.growth_mm(T_C, T_ref_C) + stack.outer_spacer.growth_mm(T_C, T_ref_C)
            - stack.shaft.growth_mm(T_C, T_ref_C))


def elastic_mismatch_mm(stack: AxialStack, T_C, T_ref_C: float) -> np.ndarray:
    """The same change (mm) with the parts as elastic bars (module docstring): the clamp force
    F = (stack growth - shaft growth) / (c_stack + c_shaft) compresses the inner stack, the
    inner-ring mid-planes move apart by B theta_b + L_is theta_is - F (c_ring + c_spacer) (half
    of each ring and the spacer lie between them), the outer ones by B theta_b + L_g theta_g."""
    ir, isp, sh = stack.inner_ring, stack.inner_spacer, stack.shaft
    c_stack = 2 * ir.compliance_mm_per_N + isp.compliance_mm_per_N
    F = ((2 * ir.growth_mm(T_C, T_ref_C) + isp.growth_mm(T_C, T_ref_C) - sh.growth_mm(T_C, T_ref_C))
         / (c_stack + sh.compliance_mm_per_N))
    sep_inner = (ir.growth_mm(T_C, T_ref_C) + isp.growth_mm(T_C, T_ref_C)
                 - F * (ir.compliance_mm_per_N + isp.compliance_mm_per_N))
    sep_outer = stack.outer_ring.growth_mm(T_C, T_ref_C) + stack.outer_spacer.growth_mm(T_C, T_ref_C)
    return sep_outer - sep_inner


def uniform_growth_shifts_mm(g: BearingGeometry, arrangement: str, T_C, T_ref_C: float):
    """(dr, dz), each (2, n): the inner-minus-outer groove-centre shifts of a bearing that grows
    uniformly with its ring material (dr = theta A0 cos a0, dz = s_j theta A0 sin a0)."""
    th = np.atleast_1d(np.asarray(g.ring.thermal_strain(np.asarray(T_C, float), T_ref_C)))
    a0 = np.radians(g.alpha0_deg)
    s = SIGNS[arrangement][:, None]
    return (np.broadcast_to(th * g.A0_mm * np.cos(a0), (2, th.size)).copy(),
            s * th * g.A0_mm * np.sin(a0))


def pair_preload_N(g: BearingGeometry, arrangement: str, T_C, T_ref_C: float,
                   preload_assembled_N: float, mismatch_mm) -> np.ndarray:
    """Preload (N) of a position-preloaded pair, uniform temperature T (rings and balls), whose
    axial approach grows by `mismatch_mm` (shared by both bearings) from the assembly state at
    T_ref: the paper's eqs. 19-20 through `analytic.bearing.solve_pair` (rigid preload path)."""
    T = np.atleast_1d(np.asarray(T_C, float))
    dr, dz = uniform_growth_shifts_mm(g, arrangement, T, T_ref_C)
    s = SIGNS[arrangement][:, None]
    dz = dz + s * 0.5 * np.atleast_1d(np.asarray(mismatch_mm, float))
    pair = solve_pair(g, arrangement, dr_mm=dr, dz_mm=dz, T_inner_ring_C=T, T_outer_ring_C=T,
                      T_ball_C=T, T_ref_C=T_ref_C, preload_kind="position",
                      preload_assembled_N=preload_assembled_N, axial_load_N=0.0,
                      dr_ref_mm=0.0, dz_ref_mm=0.0, compliance_mm_per_N=0.0)
    return np.asarray(pair.preload_N, float)
