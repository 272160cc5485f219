"""Lamé stage: the closed-form neighbours of the FE fit values, per row.

Where an FE result feeds the bearing model, the closed-form value is carried beside it: the inner
fit as two Lamé cylinders (shaft and inner ring only), in plane stress and in plane strain (the
two 2-D idealisations; the FE of a short ring tied to its neighbours need not lie between them,
seed 000's inner fit is 5 % above the plane-strain value), spinning at the row's speed
(`analytic.lame.rotating_fit_pressure_MPa`, the static value at rest); the outer fit as two
cylinders (outer ring in housing) or, with a sleeve or cartridge, as concentric layers
(`analytic.lame.multilayer_pressures_MPa`); the inner raceway's radial growth as Lamé ring
expansion plus free thermal growth.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import lame
from studies.model.inputs import PhysicsInputs
from studies.model.stages.fe import FEStage, FEState


@dataclass(frozen=True)
class LameNeighbours:
    """Closed-form neighbours of the FE values, arrays (n,) over rows unless said.

    fit_pressure_inner_MPa / fit_pressure_inner_plane_strain_MPa: inner fit, two-cylinder Lamé
    (shaft, inner ring), plane stress / plane strain, spinning at the row's speed, MPa.
    fit_pressure_outer_MPa / fit_pressure_outer_plane_strain_MPa: outer fit (outer ring in what
    it sits in), MPa. layer_names: the sleeve / cartridge layers (`Assembly.layers`, may be
    empty); layer_pressure_MPa (n, n_layers): the plane-stress pressure at the outside of each
    layer, MPa. raceway_u_r_inner_A_mm: radial displacement of bearing A's inner raceway point,
    Lamé ring expansion plus free thermal growth, mm."""
    fit_pressure_inner_MPa: np.ndarray
    fit_pressure_inner_plane_strain_MPa: np.ndarray
    fit_pressure_outer_MPa: np.ndarray
    fit_pressure_outer_plane_strain_MPa: np.ndarray
    layer_names: tuple[str, ...]
    layer_pressure_MPa: np.ndarray
    raceway_u_r_inner_A_mm: np.ndarray


def lame_neighbours(stage: FEStage, fe: FEState, inputs: PhysicsInputs) -> LameNeighbours:
    """The `LameNeighbours` of the rows' FE state `fe` (its free interferences) at the inputs'
    part temperatures and speeds; materials and geometry of the FE stage's assembly."""
    a, b = stage.asm, stage.asm.bearing
    ms, mr, mh = (stage.materials[p] for p in ("shaft", "inner_ring_A", "housing"))
    inner = dict(r_inner_mm=a.shaft.bore_diameter_mm / 2, r_fit_mm=a.shaft.seat_diameter_mm / 2,
                 r_outer_mm=b.inner_ring_outer_diameter_mm / 2, E_inner_MPa=ms.E_MPa,
                 nu_inner=ms.nu, E_outer_MPa=mr.E_MPa, nu_outer=mr.nu)
    outer = dict(r_inner_mm=b.outer_ring_inner_diameter_mm / 2,
                 r_fit_mm=a.housing.bore_diameter_mm / 2,
                 r_outer_mm=a.housing.outer_diameter_mm / 2, E_inner_MPa=mr.E_MPa,
                 nu_inner=mr.nu, E_outer_MPa=mh.E_MPa, nu_outer=mh.nu)
    th_ring = mr.thermal_strain(np.asarray(inputs.T_C["inner_ring"], float), a.T_ref_C)
    r_race = b.inner_ring_outer_diameter_mm / 2
    spin = dict(rho_inner_N_s2_mm4=ms.density_N_s2_mm4, rho_outer_N_s2_mm4=mr.density_N_s2_mm4,
                omega_rad_s=np.sqrt(stage.omega2(inputs)))
    di, do = fe.interference_um[:, 0], fe.interference_um[:, 1]
    u_lame = lame.rotating_fit_displacement_mm(r_race, "outer", **inner, interference_um=di,
                                               **spin) + th_ring * r_race
    if a.layers():      # ring / sleeve / cartridge / housing: the multi-layer Lamé solution
        p_stress, p_strain = (_layers_MPa(stage, fe, inputs, k)
                              for k in ("plane_stress", "plane_strain"))
    else:
        p_stress, p_strain = (np.atleast_1d(lame.fit_pressure_MPa(**outer, interference_um=do,
                                                                  assumption=k))[:, None]
                              for k in ("plane_stress", "plane_strain"))
    return LameNeighbours(
        lame.rotating_fit_pressure_MPa(**inner, interference_um=di, **spin),
        lame.rotating_fit_pressure_MPa(**inner, interference_um=di, **spin,
                                       assumption="plane_strain"),
        p_stress[:, 0], p_strain[:, 0], tuple(n for n, _ in a.layers()), p_stress[:, 1:], u_lame)


def _layers_MPa(stage: FEStage, fe: FEState, inputs: PhysicsInputs, assumption: str) -> np.ndarray:
    """(n, 1 + n_layers) interface pressures (MPa) of the concentric outer ring (effective
    section) / sleeve / cartridge / housing (`lame.multilayer_pressures_MPa`), at the rows'
    free interferences: the outer fit's `interference_um[:, 1]` and each layer's
    `layer_interference_um` (its fit plus its thermal mismatch with the part outside it, from
    the FE stage; NaN for a state without them)."""
    a, b = stage.asm, stage.asm.bearing
    parts = ["outer_ring_A"] + [n for n, _ in a.layers()] + ["housing"]
    radii = [b.outer_ring_inner_diameter_mm / 2, b.outside_diameter_mm / 2]
    for _, layer in a.layers():
        radii.append(radii[-1] + layer.radial_thickness_mm)
    radii.append(a.housing.outer_diameter_mm / 2)
    n = fe.interference_um.shape[0]
    layers = (np.full((n, len(a.layers())), np.nan) if fe.layer_interference_um is None
              else fe.layer_interference_um)
    d_um = np.column_stack([fe.interference_um[:, 1], layers])
    mats = [stage.materials[p] for p in parts]
    return lame.multilayer_pressures_MPa(radii, [m.E_MPa for m in mats], [m.nu for m in mats],
                                         d_um, assumption)
