"""The physical inputs of one model evaluation, per row of a conditions table.

This is the seam between the conditions table / effects and the model: the conditions CSV is turned
into a `PhysicsInputs` (baseline: every part at the ambient temperature unless its own column is
given), each switched-on effect transforms it (part temperatures, fits, CTE, viscosity law, friction,
preload), and the pipeline evaluates it. Effects never touch outputs.

All arrays have one entry per row. Units in names: C, um, N, rpm, s, 1/K^2.

Conventions for the fields effects write (see studies/model/effects/__init__.py):
- `interference_inner_um` / `interference_outer_um`: offset from the config's nominal diametral
  fit at T_ref (um); zero in the baseline; offsets add up. `interference_sleeve_um` /
  `interference_cartridge_um`: the same for a sleeve's / cartridge's fit (None = zero; the
  tolerance samples set them).
- `friction_coefficient`: change from the config's coefficient per row; zero in the baseline; the
  resolved coefficient is clipped at 0.
- `dalpha_per_K2["shaft"|"housing"]`: CTE slope of those parts (and nut / cover); zero in the
  baseline. `d2alpha_per_K3[...]`: their CTE curvature (1/K^3), likewise.
- `viscosity_slope_factor`: Walther slope factor about 40 C (1 = nominal).
- `preload_loss_N`: permanent loss subtracted from the assembled preload per row.
- `extra_compliance_mm_per_N`: axial compliance added in series to each bearing's preload path
  (mm/N, on top of the assembly's `[preload] path_compliance`); zero in the baseline.
- `cte_factor[FE part]`: factor on that part's thermal strain (a material lot whose CTE differs
  from the library's, `studies.diagnosis.ladder`); absent = 1 in the baseline.

`measured_parts` names the parts whose temperature the conditions table gave in its own column
(`T_<part>_C`); every other part follows the ambient. Effects that act on the ambient-following
parts (a thermal lag) read this flag, never compare arrays (a measured part that happens to sit
at the ambient is still measured).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

PARTS = ("shaft", "inner_ring", "ball", "outer_ring", "housing", "spacer")
PART_COLUMNS = {f"T_{p}_C": p for p in PARTS}
#: CTE slope (1/K^2) of the shaft (and nut) and housing (and cover) in the baseline
NO_CTE_SLOPE = {"shaft": 0.0, "housing": 0.0}
CONDITION_COLUMNS = ("time_s", "T_ambient_C", *PART_COLUMNS, "speed_rpm", "preload_assembled_N",
                     "axial_load_N", "radial_load_N", "moment_Nmm")


@dataclass
class PhysicsInputs:
    """Per-row physical inputs. `T_C[part]` for part in PARTS; `spacer` is both spacers, the nut
    follows the shaft and the cover follows the housing. The fields effects write are changes from
    the configuration, zero in the baseline, so that an effect at its off value adds exactly zero
    (see the module docstring)."""
    n_rows: int
    T_C: dict[str, np.ndarray]
    speed_rpm: np.ndarray
    preload_assembled_N: np.ndarray
    axial_load_N: np.ndarray
    interference_inner_um: np.ndarray                  # offset from the config's fit (um)
    interference_outer_um: np.ndarray
    friction_coefficient: np.ndarray                   # change from the config's coefficient
    preload_loss_N: np.ndarray                         # permanent preload loss per row (N)
    time_s: np.ndarray | None = None
    T_ambient_C: np.ndarray | None = None
    dalpha_per_K2: dict[str, float] = field(default_factory=lambda: dict(NO_CTE_SLOPE))
    viscosity_slope_factor: float = 1.0
    extra_compliance_mm_per_N: float = 0.0             # added to the preload-path compliance
    radial_load_N: np.ndarray | None = None            # on the shaft at the pair's mid-point
    moment_Nmm: np.ndarray | None = None               # tilting moment on the shaft (N mm)
    d2alpha_per_K3: dict[str, float] = field(default_factory=lambda: dict(NO_CTE_SLOPE))
    measured_parts: frozenset[str] = frozenset()       # parts with their own T_<part>_C column
    cte_factor: dict[str, float] = field(default_factory=dict)   # FE part -> thermal strain factor
    interference_sleeve_um: np.ndarray | None = None    # offset of the sleeve's fit (um; None: 0)
    interference_cartridge_um: np.ndarray | None = None  # offset of the cartridge's fit

    def copy(self, **changes) -> "PhysicsInputs":
        """Shallow copy with fields replaced (arrays are never modified in place)."""
        new = replace(self, T_C=dict(self.T_C), dalpha_per_K2=dict(self.dalpha_per_K2),
                      d2alpha_per_K3=dict(self.d2alpha_per_K3), cte_factor=dict(self.cte_factor))
        return replace(new, **changes) if changes else new

    def take(self, rows: np.ndarray) -> "PhysicsInputs":
        """The inputs of the given rows (an index array; rows may repeat), e.g. to evaluate the
        same operating points under several model settings in one run."""
        rows = np.asarray(rows, int)

        def pick(v):
            return None if v is None else np.asarray(v)[rows]

        return replace(self, n_rows=rows.size, T_C={k: np.asarray(v)[rows] for k, v in self.T_C.items()},
                       speed_rpm=pick(self.speed_rpm), preload_assembled_N=pick(self.preload_assembled_N),
                       axial_load_N=pick(self.axial_load_N), time_s=pick(self.time_s),
                       T_ambient_C=pick(self.T_ambient_C),
                       interference_inner_um=pick(self.interference_inner_um),
                       interference_outer_um=pick(self.interference_outer_um),
                       interference_sleeve_um=pick(self.interference_sleeve_um),
                       interference_cartridge_um=pick(self.interference_cartridge_um),
                       friction_coefficient=pick(self.friction_coefficient),
                       preload_loss_N=pick(self.preload_loss_N),
                       radial_load_N=pick(self.radial_load_N), moment_Nmm=pick(self.moment_Nmm),
                       dalpha_per_K2=dict(self.dalpha_per_K2),
                       d2alpha_per_K3=dict(self.d2alpha_per_K3), cte_factor=dict(self.cte_factor))


    def distinct_rows(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(rows, inverse) when some rows repeat another's inputs, else None: `rows` the first
        row of each distinct set of per-row inputs, in row order, and `inverse` (n_rows,) the
        position in `rows` of every row's set, so that `take(rows)` evaluated and indexed by
        `inverse` gives every row. Compared: every per-row field the model route reads (part
        temperatures, speed, preloads, loads, fit and friction offsets), bit for bit; not
        `time_s` and `T_ambient_C`, which `studies.model.pipeline.Pipeline.run` does not read
        (the effects that act through time, a thermal lag or a run-in, have written what they
        do into the part temperatures or the friction by then). A table of cycles sampled
        every minute repeats its temperatures (seed 000's 500-row cycles: 71 distinct rows)."""
        n = self.n_rows
        cols = [*(self.T_C[k] for k in sorted(self.T_C)), self.speed_rpm,
                self.preload_assembled_N, self.axial_load_N, self.interference_inner_um,
                self.interference_outer_um, self.friction_coefficient, self.preload_loss_N,
                *(v for v in (self.radial_load_N, self.moment_Nmm, self.interference_sleeve_um,
                              self.interference_cartridge_um) if v is not None)]
        M = np.column_stack([np.broadcast_to(np.asarray(c, float), (n,)) for c in cols])
        _, first, inverse = np.unique(M, axis=0, return_index=True, return_inverse=True)
        if first.size == n:
            return None
        order = np.argsort(first)                  # the distinct sets in row order
        rank = np.empty_like(order)
        rank[order] = np.arange(order.size)
        return first[order], rank[inverse.ravel()]


def baseline_inputs(columns: dict[str, np.ndarray], n_rows: int, T_ref_C: float,
                    preload_N: float, speed_rpm: float) -> PhysicsInputs:
    """Baseline: uniform temperature, no lag. A part column overrides the ambient for that part
    (and flags it in `measured_parts`); with no ambient column the reference temperature is
    used."""
    amb = columns.get("T_ambient_C")
    base = amb if amb is not None else np.full(n_rows, T_ref_C)
    T = {p: np.asarray(columns.get(f"T_{p}_C", base), float) for p in PARTS}

    def col(name, default):
        v = columns.get(name)
        return np.asarray(v, float) if v is not None else np.full(n_rows, float(default))

    return PhysicsInputs(n_rows=n_rows, T_C=T, speed_rpm=col("speed_rpm", speed_rpm),
                         preload_assembled_N=col("preload_assembled_N", preload_N),
                         axial_load_N=col("axial_load_N", 0.0),
                         radial_load_N=col("radial_load_N", 0.0), moment_Nmm=col("moment_Nmm", 0.0),
                         interference_inner_um=np.zeros(n_rows), interference_outer_um=np.zeros(n_rows),
                         friction_coefficient=np.zeros(n_rows), preload_loss_N=np.zeros(n_rows),
                         time_s=columns.get("time_s"), T_ambient_C=amb,
                         measured_parts=frozenset(p for p in PARTS if columns.get(f"T_{p}_C")
                                                  is not None))
