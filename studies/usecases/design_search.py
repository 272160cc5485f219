"""`bearingfem design`: search for an athermal stack, each candidate through the exact model.

Design variables (the assembly's own values are one candidate):
- the inner and outer spacer materials, from the material library (`analytic/materials.py`;
  materials with equal E, nu and CTE are one choice);
- the common spacer length, `LENGTH_FACTORS` x the assembly's;
- the clamp scheme of nut and cover (rigid or compliant faces), with `--clamps`;
- the assembled preload, `PRELOAD_FACTORS` x the assembly's (no new FE: one bearing run);
- with `--vary`, settings beside the stack (`Setting`): the preload kind and spring rate, the
  free contact angle, the ISO 286 classes of the shaft seat and the housing bore. They leave the
  stack's FE alone: one task evaluates a stack under all its settings on one FE set-up
  (`_TaskSetups`: a spec seen before is reused; the fit classes stay in the stack's family).

Every stack is its own FE model: the search screens all of them on a mesh twice as coarse
(`SCREEN_MESH_FACTOR`) and re-evaluates the best ones on the assembly's mesh (each through the
normal, cached FE set-up), so the ranking printed is the fine one. The screening's FE set-ups come
from `fem.parametric`: the stacks of one spacer length and clamp scheme (a family) share one
reference FE (mesh, assembly, factorisation, unit solutions, the spacers of the assembly's
materials), and a member's set-up follows from it exactly by condensing the two spacers and a
low-rank update (equal to the stack's own set-up to round-off, about 1e-12 relative: tests/
test_parametric.py); no stack is meshed or factorised on its own, only one stack per family.
A task frees its FE objects before it returns (`_task_memory`: collected, then the heap trimmed), so
a worker's memory stays flat over any number of stacks (`bench --design` measures it).

Over the temperature range (uniform temperature, round steps) each candidate gets its preload
range (max - min), its smallest preload, whether each fit assembled with interference stays
closed, its largest contact pressure against the limit `simulate` checks, and its largest torque.
Feasible: fits closed, preload kept, contact pressure within the limit; `in_band`: the preload
stays inside the band (`Band`: x the assembled preload, or in N) at every temperature. Ranked by
the relative preload variation (range / assembled preload); the Pareto set is the feasible
designs no other beats on all of relative preload variation, largest torque and
contact-pressure margin.

Why a design works (`preload_split`): for the best design and the assembly as given, the preload
change from the reference temperature to each end of the range split into parts that add up to
it: the bearing's own thermal geometry, the radial groove-centre shifts (fits, ring growth), the
axial ones (stack lengths) and their interaction, with the same pipeline run on the FE answer
with shifts held at their assembly values (`FEOptions`).

Results are typed (`DesignResult`, `Design`, `Metrics`, `StackAnswers`); columns only in
design.json (`DesignResult.to_json`).
"""
from __future__ import annotations

import gc
import itertools
import json
from contextlib import contextmanager
from dataclasses import asdict, dataclass, replace
from functools import partial
from pathlib import Path

import numpy as np

from analytic.materials import MATERIALS, get_material
from fem.parametric import parametric_setup
from fem.setup import cached_setup, full_fe
from studies.model.checks import assembly_checks, fit_pressure_MPa
from studies.model.config_checks import check_assembly
from studies.model.inputs import baseline_inputs
from studies.model.memory import release_freed_memory
from studies.model.parallel import Blocks, map_blocks
from studies.model.pipeline import FEOptions, Pipeline
from studies.model.tolerances import designed_closed, fits_of
from studies.usecases.report_tools import nice_step
from studies.usecases.report_tools import line_plot, md_table, write_report_files

LENGTH_FACTORS = (0.5, 1.0, 1.5, 2.0)
PRELOAD_FACTORS = (0.5, 0.75, 1.0, 1.25, 1.5)
SCREEN_MESH_FACTOR = 2.0
N_TEMPERATURES = 15
CONFIRM = 5                      # best designs re-evaluated on the assembly's mesh
#: the parts whose material the search varies (the screening's FE set-up family, fem.parametric)
SPACERS = ("inner_spacer", "outer_spacer")


@dataclass(frozen=True)
class Stack:
    """The FE-relevant design variables of one candidate."""
    inner_spacer_material: str
    outer_spacer_material: str
    spacer_length_mm: float
    nut_clamp: str
    cover_clamp: str
    ring_section_delta_mm: float = 0.0   # effective ring sections thickened radially by this

    def assembly(self, asm):
        b, d = asm.bearing, self.ring_section_delta_mm
        return replace(asm, inner_spacer=replace(asm.inner_spacer, material=self.inner_spacer_material,
                                                 length_mm=self.spacer_length_mm),
                       outer_spacer=replace(asm.outer_spacer, material=self.outer_spacer_material,
                                            length_mm=self.spacer_length_mm),
                       nut=replace(asm.nut, clamp=self.nut_clamp),
                       cover=replace(asm.cover, clamp=self.cover_clamp),
                       bearing=replace(b, inner_ring_outer_diameter_mm=b.inner_ring_outer_diameter_mm + 2 * d,
                                       outer_ring_inner_diameter_mm=b.outer_ring_inner_diameter_mm - 2 * d))


def distinct_materials() -> list[str]:
    """One name per distinct (E, nu, CTE) in the library, the first listed."""
    seen, names = set(), []
    for name, m in MATERIALS.items():
        key = (m.E_MPa, m.nu, m.alpha_per_K)
        if key not in seen:
            seen.add(key)
            names.append(name)
    return names


#: every (nut, cover) clamp scheme
ALL_CLAMPS = tuple((n, c) for n in ("rigid", "compliant") for c in ("rigid", "compliant"))


def candidates(asm, clamps: bool = False, length_factors=LENGTH_FACTORS,
               materials=None, ring_deltas_mm=(0.0,)) -> list[Stack]:
    """The assembly as given first, then every combination of spacer materials (the library's
    distinct ones, or `materials`), common spacer length (x the given one), clamp scheme (with
    `clamps` all four, else the given one) and ring-section change (mm, radially)."""
    mats = materials or distinct_materials()
    L0 = asm.inner_spacer.length_mm
    schemes = ALL_CLAMPS if clamps else ((asm.nut.clamp, asm.cover.clamp),)
    out = [Stack(asm.inner_spacer.material, asm.outer_spacer.material, L0, asm.nut.clamp,
                 asm.cover.clamp)]
    for mi in mats:
        for mo in mats:
            for f in length_factors:
                for n, c in schemes:
                    for d in ring_deltas_mm:
                        s = Stack(mi, mo, round(f * L0, 6), n, c, float(d))
                        if s not in out:
                            out.append(s)
    return out


def parametric_setup_of(asm):
    """The screening's FE set-up route for the stacks of `asm`: `fem.parametric` with the spacers
    as the variable parts, their reference materials the assembly's own (fixed, so the numbers do
    not depend on which worker sees which stack first)."""
    ref = {p: get_material(getattr(asm, p).material, asm.materials) for p in SPACERS}
    return partial(parametric_setup, variable=SPACERS, reference=ref)


def _family_of(s: Stack) -> tuple:
    """What puts a stack in another FE family than its neighbours (all but the spacer
    materials)."""
    return (s.spacer_length_mm, s.nut_clamp, s.cover_clamp, s.ring_section_delta_mm)


@dataclass(frozen=True)
class Band:
    """The preload band a design should keep at every temperature: `low`..`high` as fractions of
    the assembled preload (`--band`, the default 0.8..1.2) or, with `absolute`, in newtons
    (`--band-N`)."""
    low: float
    high: float
    absolute: bool = False

    def limits_N(self, assembled_N: float) -> tuple[float, float]:
        """(lowest, highest) preload in the band for this assembled preload, N."""
        if self.absolute:
            return self.low, self.high
        return self.low * assembled_N, self.high * assembled_N

    def text(self) -> str:
        """The band in words (the report)."""
        if self.absolute:
            return f"{self.low:g}..{self.high:g} N"
        return f"{self.low:g}..{self.high:g} x the assembled preload"


#: the design variables that leave the stack's FE alone (`--vary KEY=V1,V2,...`), by key: the
#: parser of one value. Fit classes change the FE set-up only through the contact status the
#: preload-path compliance is taken at (`fem.parametric.family_key`: same family).
SETTING_KEYS = {"preload_kind": str, "spring_rate_N_per_mm": float,
                "contact_angle_free_deg": float, "inner_shaft_class": str,
                "outer_housing_class": str, "nut_clamp_force_N": float,
                "cover_clamp_force_N": float, "sleeve_material": str,
                "sleeve_radial_thickness_mm": float, "sleeve_shaft_class": str}
#: the setting keys of the liner ([sleeve]): they change the stack's FE (a new set-up, its own
#: family in `fem.parametric`), the athermal lever of a stack whose rings sit in a liner
LINER_KEYS = ("sleeve_material", "sleeve_radial_thickness_mm", "sleeve_shaft_class")


@dataclass(frozen=True)
class Setting:
    """The design variables of a candidate beside its stack (no new FE model: one stack's FE
    serves every setting).

    preload_kind: "position" (a rigid offset) or "spring". spring_rate_N_per_mm: the rate k of
    the preload spring (N/mm), compressed at assembly to the assembled preload; 0 with "spring":
    a constant force (`analytic.bearing.solve_pair`, preload_kind "spring"); k > 0: the spring's
    compliance 1/k sits in the preload loop in series with the path and the two bearings, i.e.
    1/(2k) per bearing added to the path compliance (`analytic.bearing.axial`: each bearing
    X + c F(X) = X_nom, the loop A - path - B carries 2c; springs in series add compliances:
    Timoshenko & Gere, Mechanics of Materials, ch. 2). Always 0 with "position".
    contact_angle_free_deg: the bearing's free contact angle (deg). inner_shaft_class,
    outer_housing_class: ISO 286 classes of the shaft seat and the housing bore
    (`analytic.tolerances.iso286_limits_um`; "" = as given); the mean assembly sits at the middle
    of each band (`Assembly.mean_fits_um`). nut_clamp_force_N, cover_clamp_force_N: the force
    (N) a clamp with a force (clamp = "force") is tightened to (0 for a rigid or compliant
    clamp): the FE set-up holds the clamp's spring, not its force, so the stack's FE serves every
    force (`studies.model.stages.fe.FEStage.tighten` finds the overlap per force).
    sleeve_material, sleeve_radial_thickness_mm (mm), sleeve_shaft_class: the liner ([sleeve]:
    its material from the library or the file, its thickness, the ISO 286 class of its OD; ""
    or 0 without a sleeve). A thickness change moves the bore it sits in (the housing's, or the
    cartridge's with it) by twice the change, as `[sleeve]` requires; these change the FE
    (LINER_KEYS)."""
    preload_kind: str
    spring_rate_N_per_mm: float
    contact_angle_free_deg: float
    inner_shaft_class: str
    outer_housing_class: str
    nut_clamp_force_N: float = 0.0
    cover_clamp_force_N: float = 0.0
    sleeve_material: str = ""
    sleeve_radial_thickness_mm: float = 0.0
    sleeve_shaft_class: str = ""

    @classmethod
    def given(cls, asm) -> "Setting":
        """The assembly's own values."""
        f, sl = asm.fits, asm.sleeve
        return cls(asm.preload.kind, 0.0, float(asm.bearing.contact_angle_free_deg),
                   f.inner_shaft_class, f.outer_housing_class,
                   float(asm.nut.clamp_force_N), float(asm.cover.clamp_force_N),
                   sl.material if sl else "", float(sl.radial_thickness_mm) if sl else 0.0,
                   f.sleeve_shaft_class)

    @property
    def extra_compliance_mm_per_N(self) -> float:
        """The spring's compliance per bearing in the preload path, mm/N (0 without)."""
        k = self.spring_rate_N_per_mm
        return 0.5 / k if self.preload_kind == "spring" and k > 0 else 0.0

    def assembly(self, asm):
        """`asm` with this setting (unchanged values leave the assembly equal to `asm`)."""
        kind = "spring" if self.preload_kind == "spring" and self.spring_rate_N_per_mm == 0 \
            else "position"
        f = asm.fits
        if self.inner_shaft_class != f.inner_shaft_class:
            f = replace(f, inner_shaft_class=self.inner_shaft_class, inner_shaft_deviation_um=())
        if self.outer_housing_class != f.outer_housing_class:
            f = replace(f, outer_housing_class=self.outer_housing_class,
                        outer_housing_deviation_um=())
        b = asm.bearing
        if self.contact_angle_free_deg != b.contact_angle_free_deg:
            b = replace(b, contact_angle_free_deg=self.contact_angle_free_deg)
        p = asm.preload if kind == asm.preload.kind else replace(asm.preload, kind=kind)
        clamps = {name: replace(getattr(asm, name), clamp_force_N=v)
                  for name, v in (("nut", self.nut_clamp_force_N),
                                  ("cover", self.cover_clamp_force_N))
                  if v != getattr(asm, name).clamp_force_N}
        liner = {}
        sl = asm.sleeve
        if sl is not None:
            if self.sleeve_shaft_class != f.sleeve_shaft_class:
                f = replace(f, sleeve_shaft_class=self.sleeve_shaft_class,
                            sleeve_shaft_deviation_um=())
            new = replace(sl, material=self.sleeve_material or sl.material,
                          radial_thickness_mm=self.sleeve_radial_thickness_mm
                          or sl.radial_thickness_mm)
            if new != sl:
                liner["sleeve"] = new
                grow = 2.0 * (new.radial_thickness_mm - sl.radial_thickness_mm)
                if grow:              # the bore the liner sits in follows it (and what is outside)
                    liner["housing"] = replace(asm.housing, bore_diameter_mm=
                                               asm.housing.bore_diameter_mm + grow)
        return replace(asm, fits=f, bearing=b, preload=p, **clamps, **liner)

    def label(self, given: "Setting") -> str:
        """What differs from `given`, in words ("" when nothing does)."""
        parts = []
        if (self.preload_kind, self.spring_rate_N_per_mm) != (given.preload_kind,
                                                              given.spring_rate_N_per_mm):
            parts.append("position preload" if self.preload_kind == "position" else
                         "constant-force spring" if self.spring_rate_N_per_mm == 0 else
                         f"spring {self.spring_rate_N_per_mm:g} N/mm")
        if self.contact_angle_free_deg != given.contact_angle_free_deg:
            parts.append(f"contact angle {self.contact_angle_free_deg:g} deg")
        if self.inner_shaft_class != given.inner_shaft_class:
            parts.append(f"shaft {self.inner_shaft_class or 'no class'}")
        if self.outer_housing_class != given.outer_housing_class:
            parts.append(f"housing {self.outer_housing_class or 'no class'}")
        for name in ("nut", "cover"):
            v = getattr(self, f"{name}_clamp_force_N")
            if v != getattr(given, f"{name}_clamp_force_N"):
                parts.append(f"{name} {v:g} N")
        if self.sleeve_material != given.sleeve_material:
            parts.append(f"sleeve {self.sleeve_material}")
        if self.sleeve_radial_thickness_mm != given.sleeve_radial_thickness_mm:
            parts.append(f"sleeve {self.sleeve_radial_thickness_mm:g} mm")
        if self.sleeve_shaft_class != given.sleeve_shaft_class:
            parts.append(f"sleeve OD {self.sleeve_shaft_class or 'no class'}")
        return ", ".join(parts)


class DesignError(ValueError):
    """A design variable the search cannot take: one line naming the flag and the value."""


def settings_of(asm, vary: dict[str, tuple] | None = None) -> list[Setting]:
    """The assembly's own setting first, then every combination of the values of `vary` (key of
    SETTING_KEYS -> values; keys not given keep the assembly's value). A spring rate applies to
    the spring preload only (a position preload has none). DesignError (one line) for an unknown
    key, a spring rate below 0, a contact angle outside 0..60 deg or a class the ISO 286 tables
    do not carry for the seat's diameter."""
    from studies.model.tolerances import deviation_limits_um

    g = Setting.given(asm)
    vary = dict(vary or {})
    for key, values in vary.items():
        if key not in SETTING_KEYS:
            raise DesignError(f"--vary {key}: unknown (known: {', '.join(SETTING_KEYS)})")
        if not values:
            raise DesignError(f"--vary {key}: no values")
    for v in vary.get("preload_kind", ()):
        if v not in ("position", "spring"):
            raise DesignError(f"--vary preload_kind={v}: 'position' or 'spring'")
    for v in vary.get("spring_rate_N_per_mm", ()):
        if not v >= 0:
            raise DesignError(f"--vary spring_rate_N_per_mm={v:g}: must be >= 0 (0: constant force)")
    for v in vary.get("contact_angle_free_deg", ()):
        if not 0 < v < 60:
            raise DesignError(f"--vary contact_angle_free_deg={v:g}: outside 0..60 deg")
    for name in ("nut", "cover"):
        for v in vary.get(f"{name}_clamp_force_N", ()):
            if getattr(asm, name).clamp != "force":
                raise DesignError(f"--vary {name}_clamp_force_N: the {name}'s clamp is "
                                  f"{getattr(asm, name).clamp!r}; a force needs clamp = \"force\"")
            if not v > 0:
                raise DesignError(f"--vary {name}_clamp_force_N={v:g}: must be > 0")
    for key in LINER_KEYS:
        if key in vary and asm.sleeve is None:
            raise DesignError(f"--vary {key}: the assembly has no [sleeve]")
    for v in vary.get("sleeve_material", ()):
        try:
            get_material(v, asm.materials)
        except KeyError as exc:
            raise DesignError(f"--vary sleeve_material={v}: {exc.args[0]}") from None
    for v in vary.get("sleeve_radial_thickness_mm", ()):
        if not v > 0:
            raise DesignError(f"--vary sleeve_radial_thickness_mm={v:g}: must be > 0")
    if "spring_rate_N_per_mm" in vary and "spring" not in vary.get("preload_kind",
                                                                   (g.preload_kind,)):
        raise DesignError("--vary spring_rate_N_per_mm: a rate needs a spring preload (the "
                          f"assembly's is {g.preload_kind}); add --vary preload_kind=spring")
    axes = [vary.get(k, (getattr(g, k),)) for k in SETTING_KEYS]
    out = [g]
    for values in itertools.product(*axes):
        s = Setting(*values)
        if s.preload_kind == "position":
            s = replace(s, spring_rate_N_per_mm=0.0)
        if s not in out:
            out.append(s)
    for s in out:
        try:
            a = s.assembly(asm)
            deviation_limits_um(a)
            if a.sleeve != asm.sleeve:          # a liner's geometry against the stack's
                check_assembly(a, "--vary")
        except ValueError as exc:
            raise DesignError(f"--vary: {exc.args[0]}") from None
    return out


@dataclass(frozen=True)
class StackAnswers:
    """One candidate's answers at every assembled preload and temperature, arrays
    (n_preloads, n_T): preload (N), largest contact pressure (MPa), friction torque (N mm);
    fit_pressure_MPa: every fit of the assembly (inner, outer, its sleeve / cartridge,
    `tolerances.fits_of`) -> its pressure (MPa) as `simulate`'s fit_open check reads it
    (`checks.fit_pressure_MPa`); dofs: the FE model's displacement DOFs."""
    preload_N: np.ndarray
    max_contact_pressure_MPa: np.ndarray
    fit_pressure_MPa: dict
    torque_Nmm: np.ndarray
    dofs: int

    @property
    def fit_pressure_inner_MPa(self) -> np.ndarray:
        return self.fit_pressure_MPa["inner"]

    @property
    def fit_pressure_outer_MPa(self) -> np.ndarray:
        return self.fit_pressure_MPa["outer"]


class _TaskSetups:
    """The FE set-ups of one task's pipelines (a `setup_of` for `Pipeline`): a spec seen before
    is handed back, so the settings that leave the FE alone share one set-up; a new one comes
    from the stack's family (`fem.parametric`, when `family` is given) or from the normal cached
    route (`fem.setup.cached_setup`, the full FE built only when the cache has none; one full
    FE per section, whatever the compliance plan). Lives for one task only: nothing is kept
    between stacks."""

    def __init__(self, family=None):
        self.family = family
        self.setups: dict[str, object] = {}
        self.full: dict[str, object] = {}

    def _full_fe(self, spec):
        key = replace(spec, compliance=None).key()
        if key not in self.full:
            self.full[key] = full_fe(spec)
        return self.full[key]

    def __call__(self, spec):
        key = spec.key()
        if key not in self.setups:
            self.setups[key] = (self.family(spec) if self.family is not None
                                else cached_setup(spec, lambda: self._full_fe(spec)))
        return self.setups[key]


def evaluate_settings(asm, stack: Stack, settings: tuple[Setting, ...], T_C: np.ndarray,
                      preloads_N: np.ndarray, mesh_factor: float,
                      parametric: bool = False) -> tuple[StackAnswers, ...]:
    """Preload, contact pressure, fit pressures and torque of one stack under each setting at
    every temperature and preload. One task of the search. `parametric`: the FE set-up from the
    stack's family (`fem.parametric`, equal to the full set-up to round-off) instead of the
    stack's own (cached) one. Every FE object of the task is released before it returns
    (`_task_memory`)."""
    with _task_memory():
        return _evaluate(asm, stack, settings, T_C, preloads_N, mesh_factor, parametric)


def _evaluate(asm, stack, settings, T_C, preloads_N, mesh_factor, parametric):
    a = stack.assembly(asm)
    family = parametric_setup_of(asm) if parametric and asm.fits.contact == "frictionless" else None
    setups = _TaskSetups(family)
    nT, nP = T_C.size, preloads_N.size
    cols = {"T_ambient_C": np.tile(T_C, nP), "preload_assembled_N": np.repeat(preloads_N, nT)}
    out = []
    for s in settings:
        a_s = s.assembly(a)
        pl = Pipeline(a_s, mesh_factor=mesh_factor, setup_of=setups)
        inp = baseline_inputs(cols, nT * nP, a_s.T_ref_C, a_s.preload.assembled_N,
                              a_s.lubrication.speed_rpm)
        if s.extra_compliance_mm_per_N:
            inp = inp.copy(extra_compliance_mm_per_N=s.extra_compliance_mm_per_N)
        res = pl.run(inp)
        out.append(StackAnswers(res.preload_N.reshape(nP, nT),
                                res.max_contact_pressure_MPa.reshape(nP, nT),
                                {f: fit_pressure_MPa(res, f).reshape(nP, nT) for f in fits_of(a_s)},
                                res.torque_Nmm.reshape(nP, nT), int(pl.ndofs)))
    return tuple(out)


def evaluate_stack(asm, stack: Stack, T_C: np.ndarray, preloads_N: np.ndarray,
                   mesh_factor: float, parametric: bool = False,
                   setting: Setting | None = None) -> StackAnswers:
    """`evaluate_settings` of one setting (default: the assembly's own)."""
    return evaluate_settings(asm, stack, (setting or Setting.given(asm),), T_C, preloads_N,
                             mesh_factor, parametric)[0]


@contextmanager
def _task_memory():
    """Give a task's native memory back when it ends (`studies.model.memory`). The FE objects
    of a stack form reference cycles (the FE stage and its superposition's solver callback), so
    dropping them frees nothing until Python's cycle collector runs, and a heap trim before
    that finds nothing to return: a Dask worker (trim threshold 1 GiB) grew 11..19 MB a stack on
    the full set-up route. So: collect, then trim. The objects alive when the task starts are
    frozen for its duration (`gc.freeze`), so the collection scans only what the task made
    (about a millisecond, not the ~40 ms of a full collection in a loaded process)."""
    gc.freeze()
    try:
        yield
    finally:
        gc.collect()
        gc.unfreeze()
        release_freed_memory()


@dataclass(frozen=True)
class Metrics:
    """What the search ranks a candidate at one assembled preload by (over the temperatures).

    preload_range_N: max - min preload; preload_variation: that / the assembled preload;
    fits_closed: every fit of the assembly designed with interference (`tolerances.
    designed_closed`: inner, outer, sleeve, cartridge) stays closed, as `simulate`'s fit_open
    checks read it; open_fits: the fits that open somewhere in the range; contact_pressure_margin:
    limit / largest contact pressure - 1; feasible: fits closed, preload kept, contact pressure
    within the limit; in_band: feasible and the preload inside the band at every temperature."""
    preload_assembled_N: float
    preload_range_N: float
    preload_variation: float
    preload_min_N: float
    preload_max_N: float
    fits_closed: bool
    max_contact_pressure_MPa: float
    contact_pressure_margin: float
    torque_max_Nmm: float
    feasible: bool
    in_band: bool
    open_fits: tuple[str, ...] = ()


def _metrics(asm, r: StackAnswers, preloads_N, band: Band) -> list[Metrics]:
    limit = next(c.allowable for c in assembly_checks(asm) if c.name == "max_contact_pressure_MPa")
    designed = designed_closed(asm)
    out = []
    for k, P0 in enumerate(preloads_N):
        P = r.preload_N[k]
        lo, hi = band.limits_N(float(P0))
        opened = tuple(f for f, p in r.fit_pressure_MPa.items()
                       if designed[f] and not p[k].min() > 0)     # the check: open at p <= 0
        closed = not opened
        p_max = float(r.max_contact_pressure_MPa[k].max())
        feasible = bool(closed and P.min() > 0 and p_max <= limit)
        out.append(Metrics(float(P0), float(np.ptp(P)), float(np.ptp(P) / P0), float(P.min()),
                           float(P.max()), bool(closed), p_max,
                           float(limit / p_max - 1) if p_max > 0 else float("inf"),
                           float(r.torque_Nmm[k].max()), feasible,
                           bool(feasible and P.min() >= lo and P.max() <= hi), opened))
    return out


@dataclass(frozen=True)
class Design:
    """One candidate at one assembled preload: its stack (index into the search's stacks) and
    setting, its metrics, on which mesh ("screen" or "fine")."""
    stack_index: int
    stack: Stack
    setting_index: int
    setting: Setting
    metrics: Metrics
    is_given: bool
    mesh: str

    def row(self) -> dict:
        """The design as design.json writes it (the file edge): JSON types, so the API's
        `to_json` equals the file read back (open_fits a list, not the metrics' tuple)."""
        return {"stack": self.stack_index, **asdict(self.stack), "setting": self.setting_index,
                **asdict(self.setting), **asdict(self.metrics),
                "open_fits": list(self.metrics.open_fits), "is_given": self.is_given,
                "mesh": self.mesh}


def rank_key(d: Design):
    """Sort key: feasible first, then the smaller relative preload variation."""
    return (not d.metrics.feasible, d.metrics.preload_variation)


def pareto(designs: list[Design]) -> list[Design]:
    """Feasible designs that no other feasible design beats on all of relative preload variation
    (lower), largest torque (lower) and contact-pressure margin (higher)."""
    feas = [d for d in designs if d.metrics.feasible]

    def key(d):
        m = d.metrics
        return np.array([m.preload_variation, m.torque_max_Nmm, -m.contact_pressure_margin])
    front = []
    for d in feas:
        kd = key(d)
        if not any(np.all(key(e) <= kd) and np.any(key(e) < kd) for e in feas if e is not d):
            front.append(d)
    return sorted(front, key=lambda d: d.metrics.preload_variation)


@dataclass(frozen=True)
class PreloadSplit:
    """The preload change from the reference temperature to one end of the range (N), split so
    that the parts add up: with f(R, A) the preload with the radial (R) and axial (A)
    groove-centre shifts of the FE applied or held at their assembly values (0),
      own         = f(0, 0) - f_ref       the bearing's own thermal geometry (rings, balls)
      radial      = f(R, 0) - f(0, 0)     the fits and ring growth
      axial       = f(0, A) - f(0, 0)     the stack lengths
      interaction = f(R, A) - f(R, 0) - f(0, A) + f(0, 0)
    change = own + radial + axial + interaction exactly (a two-factor decomposition; the
    interaction is what the radial and axial parts do together beyond their sum: the pair's
    stiffness is not linear). `residual_N` is the round-off left. dz_A_um, dr_A_um: bearing A's
    axial and radial groove-centre shift change (um)."""
    T_C: float
    change_N: float
    own_N: float
    radial_N: float
    axial_N: float
    interaction_N: float
    dz_A_um: float
    dr_A_um: float

    @property
    def residual_N(self) -> float:
        return self.change_N - (self.own_N + self.radial_N + self.axial_N + self.interaction_N)


@dataclass(frozen=True)
class ConstraintCount:
    """How many of the screened designs fail one feasibility constraint: name (the check of
    `simulate` it is: fit_open_<fit>, preload_lost, max_contact_pressure_MPa), failed, of."""
    name: str
    failed: int
    of: int


@dataclass(frozen=True)
class Why:
    """The preload change split at the cold and the hot end (`PreloadSplit`), for the assembly
    as given and for the best design, at the best design's assembled preload (no feasible
    design: the assembly as given at its own preload, best empty); constraints: each
    feasibility constraint's count of failing screened designs (`ConstraintCount`)."""
    given: tuple[PreloadSplit, ...]
    best: tuple[PreloadSplit, ...]
    constraints: tuple[ConstraintCount, ...] = ()

    @property
    def failed_everywhere(self) -> tuple[str, ...]:
        """The constraints every screened design fails (what makes a search infeasible)."""
        return tuple(c.name for c in self.constraints if c.of and c.failed == c.of)


@dataclass(frozen=True)
class DesignResult:
    """What `run` found. designs: confirmed on the assembly's mesh, ranked; screened: every
    design on the screening mesh, ranked; pareto: the screened Pareto set (empty when no design
    is feasible: `why.failed_everywhere` then says which constraint failed in every design).
    `to_json` is design.json (the file edge)."""
    range_C: tuple[float, float]
    temperatures_C: tuple[float, ...]
    band: Band
    n_stacks: int
    n_settings: int
    n_designs: int
    given: Design
    designs: list[Design]
    screened: list[Design]
    pareto: list[Design]
    why: Why | None
    provenance: dict
    #: the plausibility warnings of the assembly (`checks.plausibility_warnings`), one line each
    warnings: tuple[str, ...] = ()

    def to_frame(self):
        """The confirmed designs, ranked, as a `pandas.DataFrame` (the rows of design.json's
        "designs")."""
        import pandas as pd

        return pd.DataFrame([d.row() for d in self.designs])

    def to_json(self) -> dict:
        w = self.why
        return {"range_C": list(self.range_C), "temperatures_C": list(self.temperatures_C),
                "band": [self.band.low, self.band.high],
                "band_unit": "N" if self.band.absolute else "fraction of the assembled preload",
                "n_stacks": self.n_stacks, "n_settings": self.n_settings,
                "n_designs": self.n_designs, "given": self.given.row(),
                "designs": [d.row() for d in self.designs],
                "screened": [d.row() for d in self.screened],
                "pareto": [d.row() for d in self.pareto],
                "why": None if w is None else {
                    **{label: [{**asdict(e), "residual_N": e.residual_N}
                               for e in getattr(w, label)] for label in ("given", "best")},
                    "constraints": [asdict(c) for c in w.constraints],
                    "failed_everywhere": list(w.failed_everywhere)},
                "provenance": self.provenance}


def _designs(asm, stacks, settings, items, answers, P0, band, mesh) -> list[Design]:
    """The designs of evaluated (stack, setting) pairs at every assembled preload."""
    out = []
    for (i, j), r in zip(items, answers):
        a = settings[j].assembly(stacks[i].assembly(asm))
        for m in _metrics(a, r, P0, band):
            out.append(Design(i, stacks[i], j, settings[j], m, i == 0 and j == 0, mesh))
    return out


def run(asm, T_min_C: float, T_max_C: float, out: Path, provenance: dict,
        band: Band = Band(0.8, 1.2), clamps: bool = False, progress=print,
        workers: int | None = None, scheduler: str | None = None,
        screen_mesh_factor: float = SCREEN_MESH_FACTOR, confirm_mesh_factor: float = 1.0,
        length_factors=LENGTH_FACTORS, materials: list[str] | None = None, bar=None,
        vary: dict[str, tuple] | None = None) -> DesignResult:
    """Search, write design.json, plots and the report into `out`. `bar(done, total)` follows
    the stacks (the command line's progress bar); `vary`: the settings' values
    (`settings_of`)."""
    step = nice_step(T_max_C - T_min_C, N_TEMPERATURES)
    T = np.unique(np.concatenate([[T_min_C, T_max_C, asm.T_ref_C],
                                  step * np.arange(np.ceil(T_min_C / step), np.floor(T_max_C / step) + 1)]))
    T = T[(T >= T_min_C) & (T <= T_max_C)]
    P0 = asm.preload.assembled_N * np.array(PRELOAD_FACTORS)
    stacks = candidates(asm, clamps, length_factors, materials)
    settings = settings_of(asm, vary)
    every = tuple(range(len(settings)))
    progress(f"design: {len(stacks)} stacks x {len(settings)} settings x {P0.size} preloads x "
             f"{T.size} temperatures (screening mesh x{screen_mesh_factor:g}) ...")
    with Blocks(workers, scheduler) as where:      # one cluster for screening and confirm
        # submitted family by family (spacer length, clamps, ring sections): a worker then
        # builds few of the families (fem.parametric); the results go back to the stacks' order
        order = sorted(range(len(stacks)), key=lambda i: _family_of(stacks[i]))
        done = map_blocks(evaluate_settings,
                          [(asm, stacks[i], settings, T, P0, screen_mesh_factor, True)
                           for i in order], where=where,
                          progress=bar or (lambda d, n: progress(f"  stack {d} of {n}")
                                           if d % 20 == 0 or d == n else None))
        by_stack = dict(zip(order, done))
        items = [(i, j) for i in range(len(stacks)) for j in every]
        designs = _designs(asm, stacks, settings, items,
                           [by_stack[i][j] for i, j in items], P0, band, "screen")
        # confirm the best feasible ones (and the assembly as given) on the fine mesh
        ranked = sorted(designs, key=rank_key)
        best = list(dict.fromkeys([(0, 0)] + [(d.stack_index, d.setting_index) for d in ranked
                                              if d.metrics.feasible][:CONFIRM]))
        progress(f"design: confirming {len(best)} candidates on the assembly's mesh ...")
        fine = map_blocks(evaluate_stack, [(asm, stacks[i], T, P0, confirm_mesh_factor, False,
                                            settings[j]) for i, j in best], where=where)
    confirmed = sorted(_designs(asm, stacks, settings, best, fine, P0, band, "fine"), key=rank_key)
    given = next(d for d in confirmed if d.is_given
                 and d.metrics.preload_assembled_N == asm.preload.assembled_N)
    top = next((d for d in confirmed if d.metrics.feasible), None)
    why = _why(asm, top, T, designs)
    result = DesignResult((T_min_C, T_max_C), tuple(float(t) for t in T), band, len(stacks),
                          len(settings), len(designs), given, confirmed,
                          sorted(designs, key=rank_key), pareto(designs), why, provenance)
    (out / "design.json").write_text(json.dumps(result.to_json(), indent=1, default=float) + "\n")
    _report(asm, out, result, T, P0, fine, best)
    return result


def preload_split(asm, T_ends_C, preload_N: float, setting: Setting | None = None,
                  mesh_factor: float = 1.0) -> tuple[PreloadSplit, ...]:
    """The preload change from the reference temperature to each of `T_ends_C` (uniform
    temperature) of `asm` under `setting` at the assembled preload `preload_N`, split into the
    bearing's own growth, the radial- and the axial-shift parts and their interaction
    (`PreloadSplit`: four pipeline runs on the same FE answer, `FEOptions`)."""
    a = asm if setting is None else setting.assembly(asm)
    pl = Pipeline(a, mesh_factor=mesh_factor)
    Ts = np.concatenate([[a.T_ref_C], np.asarray(T_ends_C, float)])
    inp = baseline_inputs({"T_ambient_C": Ts}, Ts.size, a.T_ref_C, preload_N,
                          a.lubrication.speed_rpm)
    if setting is not None and setting.extra_compliance_mm_per_N:
        inp = inp.copy(extra_compliance_mm_per_N=setting.extra_compliance_mm_per_N)
    res = pl.run(inp)
    fe, ref = res.fe, res.fe_ref
    f_RA = res.preload_N
    f_R0 = pl.run(inp, fe_options=FEOptions(shifts="radial_only")).preload_N
    f_0A = pl.run(inp, fe_options=FEOptions(shifts="axial_only")).preload_N
    held = fe.with_shifts(dr_mm=ref.dr_mm, dz_mm=ref.dz_mm)        # both sets at assembly
    f_00 = pl.run(inp, fe_options=FEOptions(states=(held, ref))).preload_N
    return tuple(PreloadSplit(float(Ts[k]), float(f_RA[k] - f_RA[0]), float(f_00[k] - f_RA[0]),
                              float(f_R0[k] - f_00[k]), float(f_0A[k] - f_00[k]),
                              float(f_RA[k] - f_R0[k] - f_0A[k] + f_00[k]),
                              float(1e3 * (fe.dz_mm[0, k] - ref.dz_mm[0, k])),
                              float(1e3 * (fe.dr_mm[0, k] - ref.dr_mm[0, k])))
                 for k in range(1, Ts.size))


def constraint_counts(asm, designs: list[Design]) -> tuple[ConstraintCount, ...]:
    """Per feasibility constraint (`Metrics.feasible`: each fit of `asm` designed closed, the
    preload, the contact pressure), how many of `designs` fail it."""
    fails = {f"fit_open_{f}": 0 for f, closed in designed_closed(asm).items() if closed}
    fails.update(preload_lost=0, max_contact_pressure_MPa=0)
    for d in designs:
        m = d.metrics
        for f in m.open_fits:
            fails[f"fit_open_{f}"] = fails.get(f"fit_open_{f}", 0) + 1
        fails["preload_lost"] += not m.preload_min_N > 0
        fails["max_contact_pressure_MPa"] += m.contact_pressure_margin < 0
    return tuple(ConstraintCount(k, int(v), len(designs)) for k, v in fails.items())


def _why(asm, best: Design | None, T, designs: list[Design]) -> Why:
    """`preload_split` at both ends of the range for the assembly as given and the best design,
    at the best design's assembled preload (the assembly's mesh); with no feasible design the
    assembly as given at its own preload. The constraint counts over `designs`."""
    P = best.metrics.preload_assembled_N if best is not None else asm.preload.assembled_N
    return Why(preload_split(asm, (T[0], T[-1]), P),
               () if best is None else
               preload_split(best.stack.assembly(asm), (T[0], T[-1]), P, best.setting),
               constraint_counts(asm, designs))


def _label(d: Design, given: Setting) -> str:
    s = d.stack
    extra = d.setting.label(given)
    return (f"spacers {s.inner_spacer_material}/{s.outer_spacer_material} "
            f"{s.spacer_length_mm:g} mm, clamps {s.nut_clamp}/{s.cover_clamp}, "
            f"{d.metrics.preload_assembled_N:g} N" + (f", {extra}" if extra else ""))


def _report(asm, out, res: DesignResult, T, P0, fine, best):
    k0 = int(np.argmin(np.abs(P0 - asm.preload.assembled_N)))
    g0 = Setting.given(asm)
    series = {}
    for (i, j), r in zip(best, fine):
        d = next(x for x in res.designs if (x.stack_index, x.setting_index) == (i, j))
        s, extra = d.stack, d.setting.label(g0)
        lab = ("as given" if (i, j) == (0, 0) else f"{s.inner_spacer_material}/"
               f"{s.outer_spacer_material} {s.spacer_length_mm:g} mm"
               + (f", {extra}" if extra else ""))
        series[lab] = r.preload_N[k0]
    line_plot(out / "preload_vs_temperature.png", T, series, "temperature (C)", "preload (N)",
              f"Preload over the range, assembled {P0[k0]:g} N (fine mesh)", markers=True)
    _scatter(out / "pareto.png", res)
    g, rows = res.given, []
    for d in res.designs[:10]:
        m = d.metrics
        rows.append([_label(d, g0), m.preload_variation, m.preload_range_N, m.preload_min_N,
                     m.preload_max_N, "yes" if m.fits_closed else "NO",
                     m.contact_pressure_margin, m.torque_max_Nmm,
                     "yes" if m.feasible else "no", "yes" if m.in_band else "no"])
    gm = g.metrics
    lines = [f"# Athermal stack search: {asm.name}", "",
             f"bearingfem {res.provenance['version']}; range {res.range_C[0]:g}..{res.range_C[1]:g} C "
             f"({len(T)} temperatures), preload band {res.band.text()}; {res.n_stacks} stacks"
             + (f" x {res.n_settings} settings" if res.n_settings > 1 else "")
             + f" x {len(P0)} assembled preloads = {res.n_designs} designs, each stack its own FE "
             "model (screened on a coarser mesh, the best re-evaluated on the assembly's mesh: the "
             "numbers below).", "",
             f"As given: {_label(g, g0)}: preload range {gm.preload_range_N:.1f} N over the range "
             f"({gm.preload_min_N:.1f}..{gm.preload_max_N:.1f} N, "
             f"{100 * gm.preload_variation:.0f} % of the assembled preload).", "",
             "## Best designs (fine mesh)", "",
             md_table(["design", "range / assembled", "preload range (N)", "min (N)", "max (N)",
                       "fits closed", "contact-pressure margin", "max torque (N mm)", "feasible",
                       "in band"], rows), "",
             "![preload](preload_vs_temperature.png)", "",
             "## Pareto set (screening mesh)", "",
             "Feasible designs that no other beats on relative preload variation, largest torque and "
             "contact-pressure margin at once.", "",
             md_table(["design", "range / assembled", "max torque (N mm)", "contact-pressure margin"],
                      [[_label(d, g0), d.metrics.preload_variation, d.metrics.torque_max_Nmm,
                        d.metrics.contact_pressure_margin] for d in res.pareto[:15]])
             if res.pareto else infeasible_text(res.why), "",
             "![pareto](pareto.png)", ""]
    w = res.why
    if w is not None and w.best:
        lines += ["## Why the best design works", "",
                  "The preload change from the reference temperature to each end of the range, "
                  "split into parts that add up to it: the bearing's own thermal geometry (every "
                  "groove-centre shift held at its assembly value), the radial shifts (fits, ring "
                  "growth), the axial shifts (stack lengths), and their interaction (what the "
                  "radial and axial shifts do together beyond the sum of each alone: the pair's "
                  "stiffness is not linear). The last column is what is left of the change after "
                  "the four parts (round-off).", "",
                  md_table(["stack", "end", "preload change (N)", "own growth (N)",
                            "radial shifts (N)", "axial shifts (N)", "interaction (N)",
                            "residual (N)", "dz A change (um)", "dr A change (um)"],
                           [[lab, f"{e.T_C:g} C", e.change_N, e.own_N, e.radial_N, e.axial_N,
                             e.interaction_N, f"{e.residual_N:.1e}", e.dz_A_um, e.dr_A_um]
                            for lab in ("given", "best") for e in getattr(w, lab)]), "",
                  _explain(w, res.designs[0]), ""]
    write_report_files(out, lines, f"Athermal stack search: {asm.name}")


def infeasible_text(w: Why) -> str:
    """The empty Pareto set in words: the constraints every design failed, the others' counts."""
    every = w.failed_everywhere
    counts = ", ".join(f"{c.name} {c.failed} of {c.of}" for c in w.constraints)
    return ("No feasible design: " + (f"{' and '.join(every)} failed in every design"
                                      if every else "no design met every constraint at once")
            + f" (designs failing each constraint: {counts}).")


def _explain(w: Why, best: Design) -> str:
    """The decomposition in words, end by end, from the numbers (nothing assumed)."""
    parts = []
    for e, end in ((0, "cold"), (1, "hot")):
        b, g = w.best[e], w.given[e]
        how = "against" if b.radial_N * b.axial_N < 0 else "with"
        parts.append(f"at the {end} end ({b.T_C:g} C) the axial shifts act {how} the radial ones "
                     f"({b.axial_N:+.1f} N vs {b.radial_N:+.1f} N; as given {g.axial_N:+.1f} vs "
                     f"{g.radial_N:+.1f} N), interaction {b.interaction_N:+.1f} N, own growth "
                     f"{b.own_N:+.1f} N, total {b.change_N:+.1f} N (as given {g.change_N:+.1f} N)")
    s = best.stack
    return (f"With {s.inner_spacer_material} inner and {s.outer_spacer_material} outer "
            f"spacers of {s.spacer_length_mm:g} mm the spacers' axial growth difference "
            "changes the axial groove-centre shifts, while the radial ones (fits, ring growth) stay "
            "almost as they were: " + "; ".join(parts) + ". The radial part is not linear in "
            "temperature (a fit tightens or opens), the axial part nearly is, so a spacer choice "
            "can balance the two only on average over the range.")


def _scatter(path, res: DesignResult):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    d = res.screened
    feas = [x.metrics for x in d if x.metrics.feasible]
    inf = [x.metrics for x in d if not x.metrics.feasible]
    ax.scatter([x.preload_variation for x in inf], [x.torque_max_Nmm for x in inf], s=6,
               c="lightgrey", label="infeasible")
    ax.scatter([x.preload_variation for x in feas], [x.torque_max_Nmm for x in feas], s=8,
               c="tab:blue", label="feasible")
    p = [x.metrics for x in res.pareto]
    ax.scatter([x.preload_variation for x in p], [x.torque_max_Nmm for x in p], s=18,
               c="tab:red", label="Pareto set")
    ax.set_xlabel("preload range over the temperature range / assembled preload")
    ax.set_ylabel("largest friction torque (N mm)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title("Designs: preload stability vs torque", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
