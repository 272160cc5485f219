"""The friction-model rungs of the model-form ladder: the friction laws of
`analytic.friction` that the assembly file does not use, as switch rungs (`ladder.FormShare`:
prediction = file + share (form - file), share 0..1), so that `diagnose` can propose them on
measured torque data.

| rung | config change | applies to | needs in the conditions |
| --- | --- | --- | --- |
| `torque_model_skf` | `[lubrication] viscous_model = "skf2004"` (SKF four-component model, catalogue constants) | oil | speed or temperature varying |
| `rolling_ehl` | `[lubrication] viscous_model = "ehl_rolling"` (EHL rolling resistance per contact) | oil | speed varying |
| `starved_film` | `[lubrication] viscous_model = "starved"` with the file's `oil_quantity_mg` | oil, a stated oil quantity | temperature varying |
| `solid_film_pressure` | `[lubrication] shear_strength = "pressure"`, tau0 and alpha of Singer et al. (1990) | solid film | temperature or preload varying |

A rung acts through what its law changes: a speed-law rung (its torque's dependence on the speed
is what differs from the file's law) tells nothing on data at one speed, where its change is a
constant factor the file's own friction coefficient already carries; a viscosity-law rung needs
the oil's temperature to vary; a load-law rung the contact load (the preload moves with the
temperature in a position-preloaded pair, or the assembled preload column varies). Where the
conditions lack that variation the rung is skipped with the reason (`applicability`, called by
`ladder.FrictionSwitch.applicable`; `ladder.ladder` registers the rungs of `forms`).

The starved form needs the bearing's oil quantity, which no data sheet bounds (it is what was
put into the bearing, `[lubrication] oil_quantity_mg`): a file without one (0 = flooded) does not
get the rung tried, with that reason (its fit on published data is in
`studies.validation.published_as_data`). The pressure-dependent shear strength's constants:
tau0 = 22.5 MPa and alpha = 0.001, the middle of what Singer, Bolster, Wegand, Fayeulle & Stupp,
Appl. Phys. Lett. 57 (1990) 995 fitted for sputtered MoS2 (tau0 20-25 MPa, alpha of order
0.001; `analytic.friction.solid_film`).

Units: those of `[lubrication]` (mg, MPa, -); the share is dimensionless.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import numpy as np

from studies.model.config import Assembly

#: Singer et al. (1990), sputtered MoS2: tau0 20-25 MPa, alpha of order 0.001 (module docstring)
SOLID_FILM_TAU0_MPA = 22.5
SOLID_FILM_ALPHA = 0.001

#: what each rung needs to vary in the conditions (any one of them)
NEEDS = {"torque_model_skf": ("speed", "temperature"), "rolling_ehl": ("speed",),
         "starved_film": ("temperature",), "solid_film_pressure": ("temperature", "preload")}
#: the open-world features each rung acts through (`studies.diagnosis.openworld`)
ACTS = {"speed": "speed_rpm", "temperature": "temperature_C", "preload": "preload_assembled_N"}


def varies(conditions: Mapping[str, np.ndarray], axis: str) -> bool:
    """Whether the conditions table varies along `axis` ("speed": the speed_rpm column;
    "temperature": any temperature column T_*_C; "preload": preload_assembled_N)."""
    if axis == "speed":
        cols = ["speed_rpm"]
    elif axis == "temperature":
        cols = [k for k in conditions if k.startswith("T_") and k.endswith("_C")]
    else:
        cols = ["preload_assembled_N"]
    for c in cols:
        v = np.asarray(conditions.get(c, ()), float)
        v = v[np.isfinite(v)]
        if v.size > 1 and np.ptp(v) > 0.0:
            return True
    return False


def applicability(name: str, conditions: Mapping[str, np.ndarray]) -> str | None:
    """None when the conditions vary what rung `name` changes, else why it is skipped."""
    need = NEEDS[name]
    if any(varies(conditions, a) for a in need):
        return None
    return (f"the conditions do not vary the {' or the '.join(need)}: the {name} law differs "
            "from the file's only through "
            + " or ".join({"speed": "the speed", "temperature": "the temperature",
                           "preload": "the contact load"}[a] for a in need)
            + ", so on these rows its change is a constant factor")


def forms(asm: Assembly) -> list[tuple[str, str, tuple[str, ...], str, object, str | None]]:
    """The friction rungs for this assembly: (name, change, acts_through, hint, configure,
    why_not) each; configure None with why_not when the rung is not tried. A form the file
    already uses is not on the ladder."""
    lub = asm.lubrication
    out = []
    acts = lambda n: tuple(ACTS[a] for a in NEEDS[n])
    if lub.kind == "oil":
        if lub.viscous_model != "skf2004":
            out.append(("torque_model_skf", '[lubrication] viscous_model = "skf2004"',
                        acts("torque_model_skf"),
                        "measure the torque at two speeds and two temperatures: the SKF rolling "
                        "term goes as (nu n)^0.6 reduced by inlet heating and starvation",
                        lambda a: _lub(a, viscous_model="skf2004"), None))
        if lub.viscous_model != "ehl_rolling":
            out.append(("rolling_ehl", '[lubrication] viscous_model = "ehl_rolling"',
                        acts("rolling_ehl"),
                        "measure the torque at two speeds: the EHL rolling resistance grows as "
                        "n^0.66 at fixed viscosity",
                        lambda a: _lub(a, viscous_model="ehl_rolling"), None))
        if lub.viscous_model != "starved":
            q = float(lub.oil_quantity_mg)
            out.append(("starved_film",
                        f'[lubrication] viscous_model = "starved" (oil_quantity_mg = {q:g})',
                        acts("starved_film"),
                        "measure the torque at two temperatures: a starved film weakens the "
                        "viscous term's viscosity dependence",
                        (lambda a, q=q: _lub(a, viscous_model="starved", oil_quantity_mg=q))
                        if q > 0 else None,
                        None if q > 0 else
                        "the starved form needs the oil put into the bearing ([lubrication] "
                        "oil_quantity_mg), which no data sheet bounds; the file gives none"))
    elif lub.kind == "solid_film" and lub.shear_strength != "pressure":
        out.append(("solid_film_pressure",
                    f'[lubrication] shear_strength = "pressure" (tau0_MPa = '
                    f"{SOLID_FILM_TAU0_MPA:g}, alpha_shear = {SOLID_FILM_ALPHA:g})",
                    acts("solid_film_pressure"),
                    "measure the torque at two preloads: a pressure-dependent shear strength "
                    "makes the friction coefficient fall as the contact pressure rises",
                    lambda a: _lub(a, shear_strength="pressure", tau0_MPa=SOLID_FILM_TAU0_MPA,
                                   alpha_shear=SOLID_FILM_ALPHA), None))
    return out


def _lub(asm: Assembly, **keys) -> Assembly:
    return replace(asm, lubrication=replace(asm.lubrication, **keys))
