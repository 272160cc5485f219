"""A preloaded clamp (nut on the shaft, cover or threaded ring in the housing) as a bolted joint:
its default stiffness and the force split between clamp and stack.

The clamp and the stack it holds are two springs: tightened to the preload F_i, an external
load P that unloads the stack changes the clamp's force by C P and the stack's by -(1 - C) P,
with the joint constant C = k_b / (k_b + k_m) (k_b the clamp's stiffness, k_m the stack's); the
stack's faces separate at P_0 = F_i / (1 - C). An axial interference delta (the overlap the
clamp is tightened with, or a thermal mismatch) gives F = delta k_b k_m / (k_b + k_m).
Source: Shigley's Mechanical Engineering Design, 10th ed., ch. 8, "Tension joints - the external load" (joint constant C, separation
load); VDI 2230 Part 1 (2015), sec. 5.3 (load factor; thermal additional load: the same form). Units: mm, N, MPa.
"""
from __future__ import annotations

import math


def thread_clamp_stiffness_N_per_mm(d_mm: float, E_seat_MPa: float, area_seat_mm2: float,
                                    E_clamp_MPa: float, area_clamp_mm2: float) -> float:
    """Axial stiffness (N/mm) of a clamp held by a thread of nominal diameter d_mm: the engaged
    thread of the part it is screwed onto (shaft or housing: modulus E_seat_MPa, load-carrying
    section area_seat_mm2) and the clamping ring itself (nut or cover: E_clamp_MPa,
    area_clamp_mm2) in series,

        1 / k = 0.5 d / (E_seat A_seat) + 0.4 d / (E_clamp A_clamp)

    VDI 2230 Part 1 (2015), sec. 5.1.1 (compliance of the bolt): compliance of the engaged thread delta_G = l_G / (E_S
    A_d3), l_G = 0.5 d, and of the nut delta_M = l_M / (E_M A_N), l_M = 0.4 d. For the thin-walled
    threads of bearing stacks the bolt's core and nominal areas (A_d3, A_N) are replaced by the
    annuli that carry the load (the shaft or housing wall and the ring's own section): an
    assumption of this model, stated where the default is used."""
    for name, v in (("d_mm", d_mm), ("E_seat_MPa", E_seat_MPa), ("area_seat_mm2", area_seat_mm2),
                    ("E_clamp_MPa", E_clamp_MPa), ("area_clamp_mm2", area_clamp_mm2)):
        if not v > 0:
            raise ValueError(f"{name} must be > 0, got {v}")
    return 1.0 / (0.5 * d_mm / (E_seat_MPa * area_seat_mm2) + 0.4 * d_mm / (E_clamp_MPa * area_clamp_mm2))


def annulus_area_mm2(d_outer_mm: float, d_inner_mm: float) -> float:
    """Area (mm^2) of an annulus between two diameters: pi / 4 (D^2 - d^2)."""
    return math.pi / 4.0 * (d_outer_mm ** 2 - d_inner_mm ** 2)


def joint_constant(k_clamp_N_per_mm: float, k_stack_N_per_mm: float) -> float:
    """C = k_b / (k_b + k_m): the share of an external load the clamp takes (Shigley ch. 8)."""
    return k_clamp_N_per_mm / (k_clamp_N_per_mm + k_stack_N_per_mm)


def series_force_N(delta_mm: float, k_clamp_N_per_mm: float, k_stack_N_per_mm: float) -> float:
    """Force (N) of an axial overlap delta_mm shared by clamp and stack in series:
    delta k_b k_m / (k_b + k_m) (two springs in series; VDI 2230 Part 1 (2015) sec. 5.3: the
    thermal additional load of a joint has this form)."""
    return delta_mm * k_clamp_N_per_mm * k_stack_N_per_mm / (k_clamp_N_per_mm + k_stack_N_per_mm)


def separating_load_N(clamp_force_N: float, C: float) -> float:
    """External load (N) at which the stack's faces separate: P_0 = F_i / (1 - C) (Shigley
    ch. 8: the members' force reaches zero)."""
    return clamp_force_N / (1.0 - C)


def tightening_force_N(torque_Nmm: float, d_mm: float, pitch_mm: float, mu_thread: float,
                       mu_face: float, D_Km_mm: float) -> float:
    """Assembly preload F_M (N) of a nut or screw tightened to torque_Nmm (N mm) on a metric
    (ISO 60 deg) thread of nominal diameter d_mm and pitch pitch_mm, with thread friction
    mu_thread (mu_G), friction mu_face (mu_K) on its face of mean friction diameter D_Km_mm:

        M_A = F_M (0.16 P + 0.58 d_2 mu_G + D_Km / 2 mu_K),   d_2 = d - 0.649519 P

    (0.16 P ~ P / (2 pi): the lead; 0.58 ~ 1 / (2 cos 30 deg): the thread flank's friction).
    Source: VDI 2230 Part 1 (2015), calculation step R13 (tightening torque); d_2, the pitch
    diameter of the basic profile, from ISO 724. Units: N, mm."""
    for name, v in (("torque_Nmm", torque_Nmm), ("d_mm", d_mm), ("pitch_mm", pitch_mm),
                    ("D_Km_mm", D_Km_mm)):
        if not v > 0:
            raise ValueError(f"{name} must be > 0, got {v}")
    for name, v in (("mu_thread", mu_thread), ("mu_face", mu_face)):
        if not v >= 0:
            raise ValueError(f"{name} must be >= 0, got {v}")
    d2 = d_mm - 0.649519 * pitch_mm
    return torque_Nmm / (0.16 * pitch_mm + 0.58 * d2 * mu_thread + 0.5 * D_Km_mm * mu_face)
