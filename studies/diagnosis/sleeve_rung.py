"""The `sleeve` rung of the model-form ladder: a sleeve between the outer rings and the
housing that the assembly file lacks.

A sleeve (a cartridge ring pressed into the housing, the outer rings in its bore) puts a layer of
another material between the rings and the housing: the outer rings' seat then expands with the
sleeve, which is held by the housing, so the outer fit, the outer raceway and the preload follow
a temperature law between the housing's and the sleeve's (the hidden case: a 3 mm 17-4PH
sleeve in an aluminium housing, where a fit error wanted more than its +-20 um).

The form: `[sleeve]` with a material from a short list of the materials sleeves are made of
(`SLEEVE_MATERIALS`: a bearing steel, a precipitation-hardening stainless steel, the low-expansion
Invar and titanium; `analytic.materials` with their sources) and a radial thickness on a short
grid within bounds (`SLEEVE_THICKNESS_MM`, 1.5 and 3 mm: a thin liner to a cartridge wall; a
variant the housing's wall cannot hold, `config_checks.check_assembly`, is left out). The
housing bore opens by twice the thickness, the sleeve spans both outer rings and the outer
spacer, its fit in the housing 0 (`sleeve_assembly`).

Fitted like a switch (`ladder.FormShare`): prediction = file + share (form - file), share 0..1
(1 = the form itself), and the variant (material x thickness, an index into `variants`) profiled
over its finite set (`fitspec`: the engine's profile of a threshold), so the held-out refits
re-select it. Each variant is one FE set-up of its own (mesh and unit solutions, cached on disk
beside the meshes: seconds the first time, then read back); the rung is screened only when the
baseline residual depends on the temperature (`ladder.Indication`), i.e. when its slope in
temperature can be the outer-ring support's expansion.

Units: mm, -.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping

from studies.model.config import ConfigError, Layer
from studies.model.config_checks import check_assembly
from studies.model.effects import Effect

#: sleeve materials tried (library names, `analytic.materials`): steel (GCr15 / AISI 52100,
#: [ASM-52100]), 17-4PH ([17-4PH]), Invar 36 ([Invar36]), titanium (TC4 / Ti-6Al-4V, [MIL-TC4])
SLEEVE_MATERIALS = ("GCr15", "17-4PH", "Invar36", "TC4")
#: radial thicknesses tried (mm): a thin liner and a cartridge wall
SLEEVE_THICKNESS_MM = (1.5, 3.0)


def sleeve_assembly(asm, material: str, thickness_mm: float):
    """The assembly with a sleeve of `material` and radial thickness `thickness_mm` between the
    outer rings and the housing: the housing bore opened by 2 x the thickness, the sleeve as long
    as both outer rings and the outer spacer, its fit in the housing 0."""
    b = asm.bearing
    layer = Layer(material=material, radial_thickness_mm=float(thickness_mm),
                  length_mm=2.0 * b.width_mm + asm.outer_spacer.length_mm)
    h = replace(asm.housing, bore_diameter_mm=b.outside_diameter_mm + 2.0 * float(thickness_mm))
    return replace(asm, sleeve=layer, housing=h)


class SleeveForm(Effect):
    """sleeve: a sleeve the file lacks (module docstring).

    Parameters: share (-, 0..1, off 0: the part of the way from the file's prediction to the
    form's), variant (-, index into `variants`, profiled; off 0)."""
    name = "sleeve"
    kind = "model_form"            # `ladder.KIND`
    units = {"share": "-", "variant": "-"}
    acts_through = ("temperature_C",)
    cost = "fe_setup"
    change = ("a [sleeve] between the outer rings and the housing: material "
              + ", ".join(SLEEVE_MATERIALS) + "; radial thickness "
              + ", ".join(f"{t:g}" for t in SLEEVE_THICKNESS_MM) + " mm")
    hint = ("look at the drawing or measure the housing bore: a sleeve sets how the outer rings' "
            "seat follows the temperature; give it in [sleeve] and diagnose again")

    def __init__(self, variants: tuple[tuple[str, float], ...]):
        self.variants = tuple(variants)
        self.parameters = ("share", "variant")
        self.bounds = {"share": (0.0, 1.0), "variant": (0.0, float(len(self.variants) - 1))}
        self.off = {"share": 0.0, "variant": 0.0}
        self.scale = {"share": 0.1, "variant": 1.0}

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy()

    def variant(self, params: Mapping[str, float]) -> tuple[str, float]:
        """(material, thickness_mm) of the parameters' variant (validated)."""
        return self.variants[int(round(self.validate(params)["variant"]))]

    def assembly(self, asm, params: Mapping[str, float]):
        """The assembly with the parameters' sleeve (`sleeve_assembly`)."""
        return sleeve_assembly(asm, *self.variant(params))

    def text(self, params: Mapping[str, float]) -> str:
        m, t = self.variant(params)
        return f"a {t:g} mm {m} sleeve"

    def describe(self) -> str:
        return "model form: " + self.change + " (share of the form's change fitted, 0..1)"


def sleeve_candidate(asm) -> dict:
    """The `ladder.Rung` fields of the sleeve rung for an assembly without a sleeve:
    {"candidate": SleeveForm of the variants its housing can hold} or {"why_not": ...}."""
    ok, why = [], None
    for m in SLEEVE_MATERIALS:
        for t in SLEEVE_THICKNESS_MM:
            try:
                check_assembly(sleeve_assembly(asm, m, t), "<sleeve>")
            except ConfigError as exc:
                why = str(exc)
                continue
            ok.append((m, t))
    if not ok:
        return {"why_not": f"the assembly cannot hold a sleeve of the listed thicknesses: {why}"}
    return {"candidate": SleeveForm(tuple(ok))}


def sleeve_grid(effect, conditions, T_ref_C) -> dict[str, list]:
    """The profiled variants (`fitspec`): every one (each gives distinct predictions)."""
    return {"variant": [float(i) for i in range(len(effect.variants))]}
