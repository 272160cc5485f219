"""The model-form ladder: the model's own richer forms, which the given assembly file does not
use, as candidate explanations of measured data (docs/diagnosis.md "The
model-form ladder").

Each switch the assembly file has is a rung: one typed record (`Rung`) holding the config change
that makes the form, the candidate (an `Effect` with the form's parameters, each bounded by physics
or the data sheet, with its source), the conditions features it acts through (the open-world
characterisation's names, `studies.diagnosis.openworld`) and its cost. A rung whose form the
config already uses is not on the ladder. The rungs (names of docs/cli.md, "kind": "model_form"):

| rung | config change | parameters (bounds) | cost |
| --- | --- | --- | --- |
| `ball_model_quasi_dynamic` | `[operating] ball_model = "quasi_dynamic"` | `share` (0..1) | pair |
| `raceway_control` | `[operating] raceway_control`: jones (outer when the config has jones); only for a quasi-dynamic config | `share` (0..1) | pair |
| `ring_section_grooved` | `[mesh] ring_section = "grooved"` | `share` (0..1) | FE set-up |
| `material_lot` | the CTE of the shaft's and the housing's lot | `cte_factor_shaft`, `cte_factor_housing` (1 +- CTE_LOT_SCATTER) | inputs |
| `unlogged_load` | a constant radial load and moment the conditions do not log | `radial_load_N` (0..C0), `moment_Nmm` (+-C0 x span) | inputs (the pair's 5-DOF solve) |
| `groove_conformity` | `[bearing] inner_groove_ratio` (rectangle-section files; the free contact angle held) | `inner_groove_ratio` (`GROOVE_RATIO_RANGE` 0.51..0.56, the makers' range, sourced; off: the file's) | pair (the file's FE set-up, the pair of the changed geometry) |
| `preload_spring` | `[preload] kind = "spring"` | carried by the listed `preload_path_compliance` (the spring is its soft limit) | - |
| `fits_in_band` | as-built fits anywhere in the `[fits]` tolerance band | carried by the listed `interference_error`, whose bounds are the band (`assembly_bounds`) | - |
| `sleeve` | a `[sleeve]` the file lacks | not tried: its material and thickness are drawing data, not bounded by a data sheet | - |
| `thermal_transient_fe` | the part temperatures from the stack's reduced transient conduction FE and a lumped mount (`studies.diagnosis.transient_rung`) | `film_resistance_m2K_W`, `G_face_W_K`, `G_env_W_K`, `C_mount_J_K`, `fit_conductance_factor`, `heat_scale` (handbook ranges, sourced there) | inputs (a reduced trial, then the pipeline) |
| `torque_model_skf`, `rolling_ehl`, `starved_film`, `solid_film_pressure` | the friction laws of `analytic.friction` the file does not use (`studies.diagnosis.friction_rungs`: forms, and the speed / temperature / load variation each needs) | `share` (0..1) | pair |

A parameter rung (`groove_conformity`) changes a number of the file's assembly that makers rarely
publish: its candidate fits the number itself within the range the makers use, and its prediction
is the pipeline of the assembly with that number (no share; at the file's value the file's
prediction bit for bit).

A switch has no continuous parameter of its own: its candidate fits `share`, the part of the
way from the config's prediction to the form's (prediction = config + share (form - config),
share 0 = the config exactly, 1 = the form exactly; the bound 1 is the form itself). The linear
path lets the engine's likelihood-ratio test, BIC and held-out refits treat a switch like any
one-parameter candidate (share has a sign: 0 is its lower bound, the chi-bar-square null of the
engine); a fitted share near 1 says the data want the form, a share well below 1 that they want
part of its change only (then the form is not the explanation, and the report says so through
`at_bound` / the parameter's value).

Besides the rungs, the unlisted sensor look-alikes (`lookalikes`, kind "sensor"): a
thermometer offset within its IEC 60751 class (`thermometer_offset`, dT_K +-0.8 K). It is no model
form and never a cause: it is fitted and compared like a candidate, and a claim it fits about as
well is not made (`studies.diagnosis.decision.unlisted_lookalike`): a 0.5 K offset of the chamber
thermometer moves seed 000's preload by less than a sigma per row but, over 240 rows, as a fit
error, a CTE slope or a share of the grooved section would (the second source,
`chamber_offset`: claimed as `cte_nonlinearity` or `interference_error` before 2026-11-25). It is
screened under the same indication as the rungs (it acts through the temperature).

Evaluation: every rung goes through the one route, `studies.model.pipeline.Pipeline`: an
"inputs" rung writes `PhysicsInputs` fields (`radial_load_N`, `moment_Nmm`, `cte_factor`) as an
effect does, on the config's pipeline (a CTE factor is one more thermal strain through the
existing superposition: no new FE); a "pair" rung runs the pipeline of the changed assembly,
whose FE set-up equals the config's (loaded from the set-up cache; a parameter rung's pipeline
takes the config's set-up object itself, one pipeline per parameter value, the last few kept); an "FE set-up" rung runs the
pipeline of the changed assembly with its own FE set-up (mesh and unit solutions: seconds the
first time, then from the cache). `FormRoute` holds those pipelines for one diagnosis.

Cost control (`Indication`): rungs are screened only when the baseline leaves structure and the
open-world characterisation of the baseline residual selects a feature the rung acts through
(or one not separable from it); the others are reported `not_applicable` with the reason. The
`thermal_transient_fe` rung is further staged (`studies.diagnosis.staging`): screened only where
no lumped thermal form explains the pass without it. The CLI's candidate list puts the rungs
after the listed effects, the FE set-up rungs last.

Units: N, N mm, mm, C; factors and shares dimensionless.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable, Mapping

import numpy as np

from analytic.safety import static_load_rating_C0_N
from infra.memo import Memo
from studies.model.config import Assembly, ConfigError
from studies.model.config_checks import check_assembly
from studies.model.effects import Effect
from studies.diagnosis import friction_rungs
from studies.diagnosis.sleeve_rung import SleeveForm, sleeve_candidate
from studies.diagnosis.transient_rung import ThermalTransientFE

#: the kind of a ladder candidate in diagnosis.json (docs/cli.md); listed effects are "effect"
KIND = "model_form"
#: the kind of an unlisted sensor look-alike (`ThermometerOffset`): fitted and compared like a
#: candidate, never a cause (`studies.diagnosis.decision`)
LOOKALIKE = "sensor"
#: IEC 60751:2022 tolerance class B of a platinum resistance thermometer, +-(0.3 + 0.005 |t|) K:
#: its two coefficients (K, K/C), and the largest |t| (C) the bound is taken at (the rigs'
#: -60..100 C range)
PT100_CLASS_B_K = (0.3, 0.005)
THERMOMETER_T_MAX_C = 100.0

#: relative scatter of a material lot's CTE about the library value (+-). No lot-to-lot scatter of
#: the CTE is specified (AMS 4928 fixes Ti-6Al-4V's composition and strength, not its CTE;
#: MIL-HDBK-5J / MMPDS give typical values), so the spread of independent data sheets for the
#: same range, 20-100 C, stands in for it: Ti-6Al-4V 8.6e-6 /K (ASM / MIL-HDBK-5J; BT Metals
#: Ti 6Al-4V data sheet 8.60e-6; Fort Wayne Metals ASTM F136 data sheet 8.64e-6 at 22 C) against
#: 9.0e-6 /K (China Aeronautical Materials Handbook, TC4, the library's value): 4.4 % below it;
#: 9Cr18 10.5e-6 (CN handbook) against 440C 10.2e-6 (ASM), 2.9 % (`analytic.materials`, sources
#: [MIL-TC4], [CN-9Cr18], [ASM-440C]). (The data sheets' 9.7e-6 /K is Ti-6Al-4V's mean CTE from
#: 20 to 650 C, not a scatter.) A lot inside that spread is within +-5 %.
CTE_LOT_SCATTER = 0.05
#: the parts whose material lot the ladder fits (bar stock bought per lot; the rings and balls are
#: the bearing maker's, who holds their steel to tighter limits)
LOT_PARTS = ("shaft", "housing")

#: pipeline costs of a rung, cheapest first (the order the CLI screens them in)
COSTS = ("inputs", "pair", "fe_setup")

#: the raceway groove radius ratios f = r / Dw bearing makers use in angular-contact ball bearings
#: (-), the `groove_conformity` rung's bounds: 0.51 to 0.56. Sources: Harris & Kotzalas,
#: Essential Concepts of Bearing Technology (5th ed., ch. 2, raceway conformity; Rolling Bearing
#: Analysis Vol. 1 ch. 2 in `analytic.catalogue`): 0.515..0.54 in ball bearings; ISO 281:2007 and
#: ISO 76:2006 take their rating factors (f_c, f_0) for groove radii up to 0.52 Dw (inner) and
#: 0.53 Dw (outer), the ceiling of a full-rating design, which low-torque designs exceed with
#: reduced ratings (`analytic.safety`); an angular-contact patent's ranges, inner 0.51..0.54 and
#: outer 0.54..0.56 (patentalert.com z00050546); Dynaroll's technical note on raceway curvature
#: (dynaroll.com/raceway-curvature.asp): 0.56 +- 0.03 "for small bearings where low torque is a
#: primary requirement". The union of the angular-contact statements, 0.51..0.56 (Dynaroll's upper
#: 0.59, for instrument bearings, left out); a file's own ratio outside it widens it to that value.
GROOVE_RATIO_RANGE = (0.51, 0.56)


# ====================================================================== the candidates
class ModelForm(Effect):
    """A candidate of the ladder (kind `KIND`), described by the config change it stands for."""
    kind = KIND
    change: str

    def describe(self) -> str:
        return "model form: " + self.change


class FormShare(ModelForm):
    """A switch of the assembly file as a candidate: the one parameter `share` (module
    docstring). The inputs are not changed: `FormRoute` blends the outputs."""
    parameters = ("share",)
    units = {"share": "-"}
    bounds = {"share": (0.0, 1.0)}
    off = {"share": 0.0}
    scale = {"share": 0.1}

    def __init__(self, name: str, hint: str, acts_through: tuple[str, ...], cost: str,
                 change: str):
        self.name, self.hint, self.acts_through, self.cost, self.change = (
            name, hint, acts_through, cost, change)

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy()

    def describe(self) -> str:
        return f"model form: {self.change} (share of the form's change fitted, 0..1)"


class MaterialLot(ModelForm):
    """material_lot: the shaft's and the housing's lot have a CTE other than the library's.

    Physics: the thermal strain of the part is theta = f alpha (T - T_ref) (the lot's whole CTE
    curve scaled by f; the FE is linear in theta, so the superposition stays exact), written into
    `PhysicsInputs.cte_factor[part]`.

    Parameters: cte_factor_shaft, cte_factor_housing (-), bounds 1 +- CTE_LOT_SCATTER, off 1.
    Source of the scatter: `CTE_LOT_SCATTER` (the spread of the handbooks for one alloy)."""
    name = "material_lot"
    parameters = tuple(f"cte_factor_{p}" for p in LOT_PARTS)
    units = {p: "-" for p in parameters}
    bounds = {p: (1.0 - CTE_LOT_SCATTER, 1.0 + CTE_LOT_SCATTER) for p in parameters}
    off = {p: 1.0 for p in parameters}
    scale = {p: 0.01 for p in parameters}
    acts_through = ("temperature_C",)
    cost = "inputs"
    change = "the shaft's and the housing's material lot: CTE x cte_factor (+-5 %)"
    hint = ("measure the CTE of the lot (dilatometer, ASTM E228) or the fits at two temperatures: "
            "a lot's CTE changes the fits linearly in T - T_ref, a CTE slope quadratically")

    def _apply(self, inputs, p, T_ref_C):
        f = dict(inputs.cte_factor)
        for part in LOT_PARTS:
            f[part] = f.get(part, 1.0) * p[f"cte_factor_{part}"]
        return inputs.copy(cte_factor=f)


class AlloyOffSheet(MaterialLot):
    """alloy_off_sheet: the shaft's and the housing's CTE off the library's by up to
    ALLOY_OFF_SHEET (+-20 %): a wrong alloy or temper rather than a lot. Never a candidate: the
    look-alike a sleeve claim must beat (`studies.diagnosis.selection.sleeve_lookalike`: a
    sleeve the drawing lacks makes the outer rings' seat follow the temperature as a housing of
    another CTE would). Physics and parameters: `MaterialLot`'s, wider bounds."""
    name = "alloy_off_sheet"
    bounds = {p: (1.0 - 4.0 * CTE_LOT_SCATTER, 1.0 + 4.0 * CTE_LOT_SCATTER)
              for p in MaterialLot.parameters}
    change = "the shaft's and the housing's CTE off the library's (+-20 %: another alloy)"


class UnloggedLoad(ModelForm):
    """unlogged_load: a constant radial load and tilting moment on the shaft that the conditions
    do not log (a belt, a coupling's misalignment, the rig's own weight).

    Physics: added to every row's `radial_load_N` and `moment_Nmm` (at the pair's mid-point);
    the pair's 5-DOF equilibrium (`analytic.bearing.combined`) carries them.

    Parameters: radial_load_N in [0, C0] and moment_Nmm in [-C0 L, C0 L], off 0, with C0 one
    bearing's static load rating (ISO 76:2006 eq. 1, `analytic.safety.static_load_rating_C0_N`:
    beyond it the raceways dent, which a rig would not carry unnoticed) and L the bearing span
    (a moment M puts M / L on each bearing)."""
    name = "unlogged_load"
    parameters = ("radial_load_N", "moment_Nmm")
    units = {"radial_load_N": "N", "moment_Nmm": "N mm"}
    off = {"radial_load_N": 0.0, "moment_Nmm": 0.0}
    acts_through = ("preload_assembled_N", "axial_load_N", "radial_load_N")
    cost = "inputs"
    change = "a constant radial load and moment the conditions do not log"
    hint = ("log the shaft's radial load and moment (strain gauges on the housing, a load cell "
            "under the rig) or run with the drive uncoupled: an unlogged load changes the torque "
            "most at low preload")

    def __init__(self, C0_N: float, span_mm: float):
        self.bounds = {"radial_load_N": (0.0, float(C0_N)),
                       "moment_Nmm": (-float(C0_N) * span_mm, float(C0_N) * span_mm)}
        self.scale = {"radial_load_N": 0.01 * float(C0_N),
                      "moment_Nmm": 0.01 * float(C0_N) * span_mm}

    def _apply(self, inputs, p, T_ref_C):
        n = inputs.n_rows

        def add(v, x):
            return (np.zeros(n) if v is None else np.asarray(v, float)) + x

        return inputs.copy(radial_load_N=add(inputs.radial_load_N, p["radial_load_N"]),
                           moment_Nmm=add(inputs.moment_Nmm, p["moment_Nmm"]))


class ThermometerOffset(Effect):
    """thermometer_offset: the temperature sensors read dT_K off (a calibration offset within
    the thermometer's class), an unlisted sensor error, not a cause of the model.

    Physics: every part temperature the rig gives (or derives from its chamber thermometer)
    reads T_true + dT_K, so the model's true part temperatures are T_C - dT_K, written into
    `PhysicsInputs.T_C` for every part.

    Parameter: dT_K (K), bounds +-(0.3 + 0.005 x 100) = +-0.8 K, the IEC 60751 class B
    tolerance of a Pt100 at 100 C (`PT100_CLASS_B_K`, `THERMOMETER_T_MAX_C`), off 0.

    It is a look-alike every claim must beat (kind `LOOKALIKE`): a small uniform temperature
    offset moves the fits, the preload and the torque by what a fit error, a CTE change or a
    section change of a few tenths of a sigma would (docs/diagnosis.md); a claim it fits about
    as well is not made (`studies.diagnosis.decision`)."""
    name = "thermometer_offset"
    parameters = ("dT_K",)
    units = {"dT_K": "K"}
    bounds = {"dT_K": (-(PT100_CLASS_B_K[0] + PT100_CLASS_B_K[1] * THERMOMETER_T_MAX_C),
                       PT100_CLASS_B_K[0] + PT100_CLASS_B_K[1] * THERMOMETER_T_MAX_C)}
    off = {"dT_K": 0.0}
    scale = {"dT_K": 0.1}
    kind = LOOKALIKE
    acts_through = ("temperature_C",)
    cost = "inputs"
    change = "the temperature sensors read dT_K off (IEC 60751 class B: +-0.8 K at 100 C)"
    hint = ("calibrate the thermometers against a reference (ice point, a calibrated Pt100 in "
            "the chamber): a sensor offset is not a property of the stack")

    def _apply(self, inputs, p, T_ref_C):
        T = {k: np.asarray(v, float) - p["dT_K"] for k, v in inputs.T_C.items()}
        return inputs.copy(T_C=T)

    def describe(self) -> str:
        return "sensor look-alike: " + self.change


class GrooveConformity(ModelForm):
    """groove_conformity: the inner raceway's groove radius ratio f_i = r_i / Dw is not the
    file's (makers rarely publish it: `analytic.catalogue` assumes it).

    Physics: the pair of the assembly with `[bearing] inner_groove_ratio = f_i` (the free contact
    angle, the published one, held): the ball / inner-raceway curvature sum and difference
    (Harris & Kotzalas ch. 2: 1/Ry = (2 f - 1) / (f Dw)), hence the Hertz contact's stiffness,
    ellipse and pressure (ch. 6), the distance of the groove centres A = (f_i + f_o - 1) Dw that
    sets the contact angle under load (ch. 2), and the friction torque's spin and differential
    slip on the ellipse. Evaluated through the one route (`Pipeline.run` of that assembly,
    `FormRoute`): a rectangle-section file's FE set-up does not depend on the ratio (the FE
    answers are the file's; the groove-centre offsets move with f, `studies.model.stages.grooves`),
    so a ratio costs the pair's solve, no FE set-up ("pair").

    One parameter, the inner ratio, the outer held at the file's: on the shipped seed 000 with the
    friction scale calibrated, a change of f_i and one of f_o move torque and preload along
    directions whose cosine is 0.992 (T x preload grid) and 0.994 (-60..80 C cycles), an f_i
    change of 0.01 differing from the best f_o change by 2.1 and 4.0 sigma (1 % noise;
    docs/diagnosis.md "The model-form ladder"): the data cannot tell the two apart, and a second
    parameter would double the rung's calls. A fitted f_i then says "the conformity", inner or
    outer (about 0.8 x the f_i change as an f_o change).

    Parameter: inner_groove_ratio (-), bounds `GROOVE_RATIO_RANGE` (widened to hold the file's
    value), off the file's value."""
    name = "groove_conformity"
    parameters = ("inner_groove_ratio",)
    units = {"inner_groove_ratio": "-"}
    acts_through = ("preload_assembled_N", "axial_load_N")
    cost = "pair"
    change = ("the inner raceway's groove radius ratio f_i = r_i / Dw "
              f"({GROOVE_RATIO_RANGE[0]:g}..{GROOVE_RATIO_RANGE[1]:g}, the range makers use)")
    hint = ("measure the inner raceway's groove radius (a profile trace of a sectioned ring, or "
            "ask the maker for the drawing) or the pair's axial stiffness at two preloads: the "
            "conformity sets the contacts' load-deflection law and ellipse, so its signature is "
            "in how torque and preload follow the load")

    def __init__(self, f_file: float):
        f = float(f_file)
        self.off = {"inner_groove_ratio": f}
        self.bounds = {"inner_groove_ratio": (min(GROOVE_RATIO_RANGE[0], f),
                                              max(GROOVE_RATIO_RANGE[1], f))}
        self.scale = {"inner_groove_ratio": 0.005}

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy()

    def assembly(self, asm: Assembly, params: Mapping[str, float]) -> Assembly:
        """The assembly with the fitted ratio (validated); the file's own object at `off`."""
        f = self.validate(params)["inner_groove_ratio"]
        if f == asm.bearing.inner_groove_ratio:
            return asm
        return replace(asm, bearing=replace(asm.bearing, inner_groove_ratio=f))


class FrictionSwitch(FormShare):
    """A friction rung's switch (`friction_rungs`): applicable only where the
    conditions vary what its law changes (`friction_rungs.applicability`)."""

    def applicable(self, conditions):
        why = super().applicable(conditions)
        return why if why is not None else friction_rungs.applicability(self.name, conditions)


class NotTried(ModelForm):
    """A rung that is not a candidate of its own (carried by a listed effect, or not bounded):
    listed among the candidates as not applicable, with the reason (`Rung.why_not`)."""
    parameters = ()
    cost = "inputs"

    def __init__(self, rung: "Rung"):
        self.name, self.acts_through, self.change = rung.name, rung.acts_through, rung.change
        self.reason = (f"carried by {rung.covered_by}: " if rung.covered_by else "") + rung.why_not
        self.hint = self.reason

    def applicable(self, conditions):
        return self.reason

    def describe(self) -> str:
        return f"model form: {self.change} (not a candidate of its own)"


def unlogged_load_starts(effect, conditions, T_ref_C) -> list[dict]:
    """Starting points of `unlogged_load` (fitspec): the response is even in a load acting alone
    (a radial load's first-order change cancels around the ring), so the Gauss-Newton step from
    0 does not find it: radial loads and moments log-spaced from 0.1 % of their bound up."""
    F, M = effect.bounds["radial_load_N"][1], effect.bounds["moment_Nmm"][1]
    f = np.geomspace(1e-3, 0.1, 3)
    return ([{"radial_load_N": float(F * x)} for x in f]
            + [{"moment_Nmm": float(s * M * x)} for x in f for s in (1.0, -1.0)])


# ====================================================================== the rungs
@dataclass(frozen=True)
class Rung:
    """One model form the config does not use. name: docs/cli.md's; change: the config change in
    words; cost: "inputs", "pair" or "fe_setup" (`COSTS`); acts_through: open-world features;
    candidate: the effect the diagnosis fits (None when not tried); configure: the assembly
    with the form (switch rungs); covered_by: the listed effect that carries the form;
    why_not: why it is not a candidate of its own."""
    name: str
    change: str
    cost: str
    acts_through: tuple[str, ...]
    candidate: Effect | None = None
    configure: Callable[[Assembly], Assembly] | None = None
    covered_by: str | None = None
    why_not: str | None = None


def _switch(name: str, change: str, cost: str, acts: tuple[str, ...], hint: str,
            configure: Callable[[Assembly], Assembly], asm: Assembly) -> Rung:
    """A switch rung, checked against the assembly rules (a form the file cannot hold, e.g.
    grooves the ring section has no room for, is not tried: `why_not`)."""
    try:
        check_assembly(configure(asm), f"<{name}>")
    except ConfigError as exc:
        return Rung(name, change, cost, acts, why_not=f"the assembly cannot hold it: {exc}")
    return Rung(name, change, cost, acts, FormShare(name, hint, acts, cost, change), configure)


def ladder(asm: Assembly) -> list[Rung]:
    """Every rung of the ladder for this assembly (the forms its file does not use), cheapest
    first; the ones that are candidates have `candidate` set."""
    op, rungs = asm.operating, []
    rungs.append(Rung(MaterialLot.name, MaterialLot.change, "inputs", MaterialLot.acts_through,
                      MaterialLot()))
    g = asm.bearing
    C0 = float(static_load_rating_C0_N(g.ball_count, g.ball_diameter_mm, g.pitch_diameter_mm,
                                       g.contact_angle_free_deg))
    span = _bearing_span_mm(asm)
    rungs.append(Rung(UnloggedLoad.name, UnloggedLoad.change, "inputs", UnloggedLoad.acts_through,
                      UnloggedLoad(C0, span)))
    rungs.append(_groove_rung(asm))
    if op.ball_model == "static":
        rungs.append(_switch(
            "ball_model_quasi_dynamic", '[operating] ball_model = "quasi_dynamic"', "pair",
            ("speed_rpm", "revolutions"),
            "measure at two speeds at one temperature: the balls' centrifugal force and "
            "gyroscopic moment change the contact angles and the torque with the square of the "
            "speed", lambda a: replace(a, operating=replace(a.operating,
                                                             ball_model="quasi_dynamic")), asm))
    else:
        other = "outer" if op.raceway_control == "jones" else "jones"
        rungs.append(_switch(
            "raceway_control", f'[operating] raceway_control = "{other}"', "pair",
            ("speed_rpm", "revolutions"),
            "measure the torque at two speeds: the raceway control sets which contact spins",
            lambda a: replace(a, operating=replace(a.operating, raceway_control=other)), asm))
    if asm.mesh.ring_section == "rectangle":
        rungs.append(_switch(
            "ring_section_grooved", '[mesh] ring_section = "grooved"', "fe_setup",
            ("temperature_C", "preload_assembled_N"),
            "measure the fits and the preload over a temperature range: the grooved rings are "
            "softer than their effective rectangles, so the fits pass less of the thermal change "
            "to the raceways",
            lambda a: replace(a, mesh=replace(a.mesh, ring_section="grooved")), asm))
    if asm.preload.kind == "position":
        rungs.append(Rung("preload_spring", '[preload] kind = "spring"', "inputs",
                          ("temperature_C", "preload_assembled_N"),
                          covered_by="preload_path_compliance",
                          why_not="a spring preload is the soft limit of the preload path's "
                                  "compliance: the listed preload_path_compliance reaches it "
                                  "(bound 5e4 um/kN, as soft as a wave spring)"))
    rungs.append(Rung("fits_in_band", "as-built fits anywhere in their tolerance band", "inputs",
                      ("temperature_C",), covered_by="interference_error",
                      why_not="the listed interference_error is bounded to the tolerance band "
                              "when [fits] gives tolerances (studies.model.effects."
                              "assembly_bounds), else to +-20 um"))
    if asm.sleeve is None:      # studies/diagnosis/sleeve_rung.py
        rungs.append(Rung("sleeve", SleeveForm.change, "fe_setup", SleeveForm.acts_through,
                          **sleeve_candidate(asm)))
    rungs.append(_transient_rung(asm))      # studies/diagnosis/transient_rung.py
    for name, change, acts, hint, configure, why_not in friction_rungs.forms(asm):
        r = (Rung(name, change, "pair", acts, why_not=why_not) if configure is None
             else _switch(name, change, "pair", acts, hint, configure, asm))
        if r.candidate is not None:
            r = replace(r, candidate=FrictionSwitch(name, hint, acts, "pair", change))
        rungs.append(r)
    return sorted(rungs, key=lambda r: COSTS.index(r.cost))


def _groove_rung(asm: Assembly) -> Rung:
    """The `groove_conformity` rung: tried on rectangle-section files whose assembly holds the
    ratio at both bounds (`check_assembly`: the groove bottom inside the ring's section)."""
    e = GrooveConformity(asm.bearing.inner_groove_ratio)
    acts = GrooveConformity.acts_through
    if asm.mesh.ring_section == "grooved":
        return Rung(e.name, e.change, "fe_setup", acts,
                    why_not="the grooved ring section meshes the groove: every ratio would be an "
                            "FE set-up of its own")
    try:
        for f in e.bounds["inner_groove_ratio"]:
            check_assembly(e.assembly(asm, {"inner_groove_ratio": f}), f"<{e.name}>")
    except ConfigError as exc:
        return Rung(e.name, e.change, "pair", acts,
                    why_not=f"the assembly cannot hold the range: {exc}")
    return Rung(e.name, e.change, "pair", acts, e)


def _transient_rung(asm: Assembly) -> Rung:
    """The `thermal_transient_fe` rung (`transient_rung.ThermalTransientFE`): tried on every
    assembly whose part temperatures the conditions do not give (it needs `time_s` and
    `T_ambient_C`, `Effect.applicable`); not where the file computes them already
    (`[thermal] mode = "transient"`)."""
    e = ThermalTransientFE
    if asm.thermal.mode == "transient":
        return Rung(e.name, e.change, "inputs", e.acts_through,
                    why_not='the file computes the part temperatures ([thermal] mode = '
                            '"transient")')
    return Rung(e.name, e.change, "inputs", e.acts_through, ThermalTransientFE(asm))


def _bearing_span_mm(asm: Assembly) -> float:
    """Distance of the ball planes of bearings A and B (mm): the inner rings' mid-planes
    (`studies.model.stack.stack_positions`, as the pipeline's bearing stage takes it)."""
    from studies.model.stack import stack_positions

    z = stack_positions(asm)
    return 0.5 * (sum(z["inner_ring_B"]) - sum(z["inner_ring_A"]))


def lookalikes() -> list[Effect]:
    """The unlisted sensor look-alikes every claim must beat (kind `LOOKALIKE`): fitted and
    compared like candidates, never a cause (`studies.diagnosis.decision`)."""
    return [ThermometerOffset()]


def candidates(asm: Assembly) -> list[Effect]:
    """The ladder's candidates for this assembly, cheapest first (FE set-up rungs last); a rung
    that is not a candidate of its own is listed as `NotTried` (not applicable, with why); then
    the sensor look-alikes (`lookalikes`)."""
    rungs = ladder(asm)
    return ([r.candidate for r in rungs if r.candidate is not None]
            + [NotTried(r) for r in rungs if r.candidate is None] + lookalikes())


def is_form(effect) -> bool:
    """True for a ladder candidate."""
    return getattr(effect, "kind", "effect") == KIND


def is_lookalike(effect) -> bool:
    """True for an unlisted sensor look-alike (`ThermometerOffset`): never a cause."""
    return getattr(effect, "kind", "effect") == LOOKALIKE


# ====================================================================== evaluation
class FormRoute:
    """The model forms of one assembly evaluated through its pipeline: inputs rungs as effects;
    a parameter rung (`GrooveConformity`) by the pipeline of the assembly with its parameter;
    switch rungs by the pipeline of the changed assembly (of the parameter rung's assembly when
    both are fitted together). Pipelines are built on first use and the last few kept here; a
    parameter rung's pipeline shares the file's FE set-up (its `SetupSpec` is the file's)."""

    #: pipelines of parameter-rung assemblies kept (a fit moves the parameter every call)
    KEEP = 6

    def __init__(self, pipeline):
        self.pl = pipeline
        self.rungs = {r.name: (replace(r, candidate=r.candidate.bind(pipeline))
                               if isinstance(r.candidate, ThermalTransientFE) else r)
                      for r in ladder(pipeline.asm) if r.candidate is not None}
        # the sensor look-alikes, and the alloy look-alike a sleeve claim must beat
        self.lookalikes = {e.name: e for e in lookalikes() + [AlloyOffSheet()]}
        self._pipelines: dict = {}     # switch rung name -> its pipeline on the file
        self._param = Memo(self.KEEP)        # parameter rung assembly -> its pipeline
        self._switch_on = Memo(self.KEEP)    # (switch rung, parameter rung assembly) -> pipeline
        sleeve = self.rungs.get(SleeveForm.name)
        self._sleeves = Memo(max(self.KEEP, len(sleeve.candidate.variants) if sleeve else 0))

    def split(self, effects: Mapping[str, Mapping[str, float]]) -> tuple[dict, dict]:
        """(listed effects, ladder rungs and sensor look-alikes) of an effects dict
        {name: parameters}."""
        mine = self.rungs.keys() | self.lookalikes.keys()
        listed = {k: v for k, v in (effects or {}).items() if k not in mine}
        forms = {k: v for k, v in (effects or {}).items() if k in mine}
        return listed, forms

    def apply_inputs(self, inputs, forms: Mapping[str, Mapping[str, float]]):
        """The inputs with the inputs rungs and the sensor look-alikes applied (`Effect.apply`,
        validated)."""
        for name, params in forms.items():
            e = self.lookalikes[name] if name in self.lookalikes else self.rungs[name].candidate
            if e.cost == "inputs":
                inputs = e.apply(inputs, params, self.pl.asm.T_ref_C)
        return inputs

    def assembly(self, forms: Mapping[str, Mapping[str, float]]) -> Assembly:
        """The assembly of the parameter rungs among `forms` (the file's when there is none or
        all are at their off values)."""
        asm = self.pl.asm
        for name, params in forms.items():
            rung = self.rungs.get(name)
            if rung is not None and isinstance(rung.candidate, GrooveConformity):
                asm = rung.candidate.assembly(asm, params)
        return asm

    def _of(self, asm: Assembly):
        """The pipeline of a parameter rung's assembly (the file's own for the file's assembly),
        sharing the file's FE set-up; the last `KEEP` kept."""
        from studies.model.pipeline import Pipeline

        if asm is self.pl.asm:
            return self.pl

        def setup_of(spec):
            if spec != self.pl.spec:        # a rung that moves the FE set-up is a switch
                raise RuntimeError("a parameter rung changed the FE set-up")
            return self.pl.setup

        return self._param.get_or_make(
            asm, lambda: Pipeline(asm, mesh_factor=self.pl.mesh_factor, setup_of=setup_of))

    def pipeline(self, name: str, asm: Assembly | None = None):
        """The pipeline of the assembly (default the file's) with switch rung `name`'s form
        (same mesh factor): the file's switches kept for the diagnosis, those on a parameter
        rung's assembly the last `KEEP`."""
        from studies.model.pipeline import Pipeline

        base = self.pl.asm if asm is None else asm
        make = lambda: Pipeline(self.rungs[name].configure(base), mesh_factor=self.pl.mesh_factor)
        if base is self.pl.asm:
            hit = self._pipelines.get(name)
            if hit is None:
                hit = self._pipelines[name] = make()
            return hit
        return self._switch_on.get_or_make((name, base), make)

    def form_pipeline(self, name: str, asm: Assembly, params: Mapping[str, float]):
        """The pipeline of switch rung `name`'s form on `asm` (`pipeline`); the sleeve rung's
        of its parameters' variant (`sleeve_rung.SleeveForm`, one FE set-up per variant: all
        kept for the diagnosis, the profile revisits them)."""
        from studies.model.pipeline import Pipeline

        cand = self.rungs[name].candidate
        if not isinstance(cand, SleeveForm):
            return self.pipeline(name, asm)
        return self._sleeves.get_or_make(
            (cand.variant(params), asm),
            lambda: Pipeline(cand.assembly(asm, params), mesh_factor=self.pl.mesh_factor))

    def columns(self, inputs, forms: Mapping[str, Mapping[str, float]],
                columns: tuple[str, ...]) -> dict[str, np.ndarray]:
        """The named columns of the inputs (inputs rungs already applied) through the pipeline
        of the parameter rungs' assembly (the config's without them), each switch rung's share
        of its form's change added (module docstring). Rows repeating another row's inputs
        (`PhysicsInputs.distinct_rows`) are evaluated once: the route is row by row, so each
        row's numbers are its own (the same to round-off, ~1e-14 of a column: the FE's
        active-set groups and the pair's vectorised iterations hold other rows); where that
        evaluation fails, the whole table is evaluated, so a failure names its table row."""
        rows = inputs.distinct_rows()
        if rows is None:
            return self._columns(inputs, forms, columns)
        first, inverse = rows
        try:
            sub = self._columns(inputs.take(first), forms, columns)
        except Exception:              # the failure as the whole table's evaluation gives it
            return self._columns(inputs, forms, columns)
        return {c: v[inverse] for c, v in sub.items()}

    def _columns(self, inputs, forms: Mapping[str, Mapping[str, float]],
                 columns: tuple[str, ...]) -> dict[str, np.ndarray]:
        """`columns` on every row of `inputs`."""
        from studies.model.columns import to_columns

        asm = self.assembly(forms)
        base = to_columns(self._of(asm).run(inputs), flags=False, only=columns)
        out = {c: np.asarray(base[c], float) for c in columns}
        for name, params in forms.items():
            rung = self.rungs.get(name)
            if rung is None or not isinstance(rung.candidate, (FormShare, SleeveForm)):
                continue
            share = rung.candidate.validate(params)["share"]
            if share == 0.0:
                continue
            form = to_columns(self.form_pipeline(name, asm, params).run(inputs), flags=False,
                              only=columns)
            for c in columns:
                out[c] = out[c] + share * (np.asarray(form[c], float) - base[c])
        return out


# ====================================================================== cost control
@dataclass(frozen=True)
class Indication:
    """What the baseline residual points at (module docstring, "Cost control"): whether it has
    structure, and the open-world features selected on it (with the ones not separable from
    them)."""
    structure: bool
    features: frozenset[str] = field(default_factory=frozenset)

    def why_not(self, effect) -> str | None:
        """None when the rung is to be screened, else the reason it is not (listed effects:
        always None)."""
        if not (is_form(effect) or is_lookalike(effect)):
            return None
        what = "model form" if is_form(effect) else "sensor look-alike"
        if not self.structure:
            return f"{what} not tried: the baseline leaves no structure"
        if not set(effect.acts_through) & self.features:
            found = ", ".join(sorted(self.features)) or "no named condition"
            return (f"{what} not indicated: it acts through "
                    f"{', '.join(effect.acts_through)}; the baseline residual depends on {found}")
        return None


def indication(pb, b) -> Indication:
    """The `Indication` of a calibrated problem (`studies.diagnosis.problem.Problem`) and its
    `Baseline`: the open-world characterisation (`studies.diagnosis.openworld.characterise`) of
    the baseline residual, when it has structure."""
    from studies.diagnosis.openworld import characterise

    if not b.structure:
        return Indication(False)
    ow = characterise({c: pb.scaled_residual(c, b.fit.pred[c]) for c in pb.columns}, pb.valid,
                      pb.conditions, pb.blocks, pb.noise.sigma_w, pb.noise.rho)
    feats: set[str] = set()
    for col in ow.columns:
        if col.depends:
            feats |= set(col.selected)
            for near in col.not_separable.values():
                feats |= set(near)
    feats |= {a for a, k in ow.aliases.items() if k in feats}    # the same quantity here
    return Indication(True, frozenset(feats))


def forms_through(effects, feature: str) -> list[str]:
    """Names of the ladder candidates among `effects` that act through an open-world feature."""
    return [e.name for e in effects if is_form(e) and feature in e.acts_through]
