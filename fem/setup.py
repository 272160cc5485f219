"""The FE set-up of a stack for the superposition, kept on disk across runs.

What `fem.solver.Superposition.evaluate` needs (the contact problem condensed to the fit interface
and the probed unit solutions, `fem.solver.Condensed`) and the preload-path compliance
(`fem.compliance`) come from the full FE: mesh, assembly, one factorisation and one unit solution
per part and per contact pair. `cached_setup` stores them beside the mesh cache (`meshes.cache`:
one file per key, written atomically, checked on every read, a damaged or foreign file rebuilt
with one warning), so a second run of the same stack reads a small file instead.

The key hashes everything the stored numbers depend on: the section (rectangles, splits, fits,
supports, refined lines, probe points, element sizes), the material of every part (all of its
properties: E, nu, CTE and the density the centrifugal unit solution scales with), which parts
spin (the rotor sub-assembly: they carry the centrifugal load), the contact
variant, where the compliance is taken (arrangement signs, assembled interferences), the versions
of bearingfem, gmsh and scikit-fem, and FORMAT (raised whenever what is stored or how it is
computed changes).
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from analytic.materials import Material
from fem.compliance import assembled_closed_set, preload_path_compliance_mm_per_N
from fem.model import StackModel, build_model, part_materials
from fem.solver import Condensed, FitSolver, condense
from infra.version import __version__
from meshes.cache import cache_dir, cached_file, npz_arrays
from meshes.section import Section

if TYPE_CHECKING:
    import scipy.sparse as sp

#: version of the stored layout and of the computation behind it (2: a centrifugal load column
#: (omega^2) after the part thermal strains; 3: loops of ties at ring corners of bonded fits no
#: longer fix those corners axially, fem/solver.py)
FORMAT = 3


class SetupError(RuntimeError):
    """A stored set-up is unusable (damaged, foreign, inconsistent); one-line message."""


@dataclass(frozen=True)
class CompliancePlan:
    """Where the preload-path compliance is taken (`fem.compliance`): the arrangement signs
    (s_A, s_B) and the radial interference (mm) of every FE fit at assembly."""
    signs: tuple[float, float]
    delta_assembled_mm: tuple[float, ...]


@dataclass(frozen=True)
class SetupSpec:
    """Everything an FE set-up depends on. probe_points_rz: the (r, z) points (mm) whose
    displacements the superposition returns (u_r, u_z interleaved, in this order); compliance:
    None when the preload-path compliance is not wanted; materials: (part, material) in part
    order; rotating_parts: the parts that spin with the shaft (their centrifugal load at
    omega = 1 rad/s is the superposition's omega^2 column). `of` makes one from points given as
    a (2, n) array of r and z."""
    section: Section
    contact: str
    probe_points_rz: tuple[tuple[float, float], ...]
    compliance: CompliancePlan | None
    materials: tuple[tuple[str, Material], ...]
    rotating_parts: tuple[str, ...] = ()

    @classmethod
    def of(cls, section: Section, contact: str, probe_points_rz, compliance: CompliancePlan | None,
           materials: dict[str, Material] | None = None,
           rotating_parts: tuple[str, ...] = ()) -> "SetupSpec":
        mats = part_materials(section, materials)
        pts = tuple((float(r), float(z)) for r, z in np.asarray(probe_points_rz, float).T)
        return cls(section, contact, pts, compliance, tuple(mats.items()), tuple(rotating_parts))

    def key(self) -> str:
        """Hex SHA-256 (24 digits) of the spec, FORMAT and the versions of the code."""
        section = asdict(self.section)
        if not section["faces"]:           # (sections without contact faces keep their keys)
            del section["faces"]
        data = {"format": FORMAT, "versions": _versions(), "section": section,
                "contact": self.contact, "probe_points_rz": self.probe_points_rz,
                "compliance": None if self.compliance is None else asdict(self.compliance),
                "materials": [[p, asdict(m)] for p, m in self.materials],
                "rotating_parts": list(self.rotating_parts)}
        text = json.dumps(data, sort_keys=True, default=list)
        return hashlib.sha256(text.encode()).hexdigest()[:24]


def _versions() -> dict[str, str]:
    out = {"bearingfem": __version__}
    for dist in ("gmsh", "scikit-fem"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "unknown"
    return out


@dataclass(frozen=True)
class FESetup:
    """The FE set-up of one `SetupSpec`. key: `SetupSpec.key()`. ndofs: displacement DOFs of the
    FE model. part_names, fit_names: FE parts and fits in model order. fit_r_mm, fit_length_mm
    (n_fits,): radius and length (mm) of each fit. condensed: the superposition's arrays.
    compliance_mm_per_N: preload-path compliance per bearing (mm/N), NaN when not planned."""
    key: str
    ndofs: int
    part_names: tuple[str, ...]
    fit_names: tuple[str, ...]
    fit_r_mm: np.ndarray
    fit_length_mm: np.ndarray
    condensed: Condensed
    compliance_mm_per_N: float


@dataclass(frozen=True)
class FullFE:
    """The full FE of a spec: the assembled model, its contact solver and the probe matrix
    (2 n_points, ndofs)."""
    model: StackModel
    solver: FitSolver
    probe: sp.csr_matrix


def full_fe(spec: SetupSpec) -> FullFE:
    """Mesh (from the mesh cache), assemble and wrap the FE model of `spec`."""
    model = build_model(spec.section, spec.contact, dict(spec.materials), spec.rotating_parts)
    return FullFE(model, FitSolver(model), model.probe_matrix(np.array(spec.probe_points_rz).T))


def compute_setup(spec: SetupSpec, fe: FullFE) -> FESetup:
    """The set-up of `spec` from its full FE (the uncached route; `cached_setup` stores its
    result): condensation (`fem.solver.condense`) and, when planned, the compliance, whose
    assembled contact state starts from the condensed problem's (`assembled_closed_set`)."""
    m = fe.model
    c = spec.compliance
    condensed = condense(fe.solver, fe.probe)
    comp = (np.nan if c is None else preload_path_compliance_mm_per_N(
        fe.solver, fe.probe, np.array(c.signs), np.array(c.delta_assembled_mm),
        assembled_closed_set(condensed, fe.solver, np.array(c.delta_assembled_mm))))
    return FESetup(spec.key(), int(m.ndofs), tuple(m.part_names), tuple(f.name for f in m.fits),
                   np.array([f.r_mm for f in m.fits], float),
                   np.array([f.length_mm for f in m.fits], float), condensed, float(comp))


def cached_setup(spec: SetupSpec, fe: Callable[[], FullFE], progress=None) -> FESetup:
    """The set-up of `spec` from the cache, else computed from `fe()` (called only then) and
    stored. A stored file that is unusable is rebuilt with one warning line."""
    d = cache_dir("setups", "FE set-up")
    key = spec.key()

    def make(tmp: Path) -> None:
        full = fe()
        if progress:
            progress(f"unit solutions ({full.model.ndofs} DOF) ...")
        write_setup(compute_setup(spec, full), tmp)

    return cached_file(d / f"setup_{key}.npz", make, lambda p: read_setup(p, spec, key),
                       what="FE set-up", writer="bearingfem", error=SetupError)


# ---------------------------------------------------------------------------- file layout
_ARRAYS = ("fit_of_pair", "B", "A", "probe_units", "bonded_force")


def _digest(arrays: dict[str, np.ndarray]) -> str:
    """SHA-256 over the names, dtypes, shapes and bytes of the arrays (sorted by name)."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def write_setup(s: FESetup, path: Path) -> None:
    """Store a set-up as an .npz (no pickles) with a digest of its content."""
    c = s.condensed
    arrays = {"format": np.array(FORMAT), "key": np.array(s.key), "ndofs": np.array(s.ndofs),
              "part_names": np.array(s.part_names), "fit_names": np.array(s.fit_names),
              "fit_r_mm": s.fit_r_mm, "fit_length_mm": s.fit_length_mm,
              "compliance_mm_per_N": np.array(s.compliance_mm_per_N), "bonded": np.array(c.bonded),
              **{k: getattr(c, k) for k in _ARRAYS}}
    arrays["digest"] = np.array(_digest(arrays))
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)


def read_setup(path: Path, spec: SetupSpec, key: str | None = None) -> FESetup:
    """Read a stored set-up and check it belongs to `spec` (SetupError, one line, otherwise):
    readable, its digest sound, its format, key, parts and fits this spec's, array shapes
    consistent, every number finite."""
    key = spec.key() if key is None else key
    a = npz_arrays(path, SetupError)
    need = {"format", "key", "ndofs", "part_names", "fit_names", "fit_r_mm", "fit_length_mm",
            "compliance_mm_per_N", "bonded", "digest", *_ARRAYS}
    if set(a) != need:
        raise SetupError("not a set-up file of this format")
    digest = str(a.pop("digest"))
    if _digest(a) != digest:
        raise SetupError("its content does not match its digest")
    if int(a["format"]) != FORMAT:
        raise SetupError(f"format {int(a['format'])}, expected {FORMAT}")
    if str(a["key"]) != key:
        raise SetupError("it was made for other inputs")
    sec = spec.section
    if tuple(a["part_names"].tolist()) != tuple(sec.parts()):
        raise SetupError("its parts are not this section's")
    if tuple(a["fit_names"].tolist()) != sec.contact_names():
        raise SetupError("its fits are not this section's")
    c = _condensed(a, len(sec.parts()), len(sec.contact_names()), 2 * len(spec.probe_points_rz))
    comp = float(a["compliance_mm_per_N"])
    if (spec.compliance is None) != np.isnan(comp) or np.isinf(comp):
        raise SetupError("its compliance does not match the plan")
    return FESetup(key, int(a["ndofs"]), tuple(a["part_names"].tolist()),
                   tuple(a["fit_names"].tolist()), a["fit_r_mm"], a["fit_length_mm"], c, comp)


def _condensed(a: dict, n_parts: int, n_fits: int, n_probe: int) -> Condensed:
    """The `Condensed` of a file's arrays, shapes and values checked."""
    fop = a["fit_of_pair"]
    n = fop.size
    bonded = bool(a["bonded"])
    n_loads = n_parts + 1                   # thermal strain per part, omega^2
    cols = n_loads + (n_fits if bonded else n)
    shapes = {"fit_of_pair": (n,), "probe_units": (n_probe, cols),
              "B": (0, 0) if bonded else (n, n_loads), "A": (0, 0) if bonded else (n, n),
              "bonded_force": (n, cols) if bonded else (0, 0),
              "fit_r_mm": (n_fits,), "fit_length_mm": (n_fits,)}
    for name, shape in shapes.items():
        if a[name].shape != shape:
            raise SetupError(f"array {name} has shape {a[name].shape}, expected {shape}")
    if fop.dtype.kind not in "iu" or (n and (fop.min() < 0 or fop.max() >= n_fits)):
        raise SetupError("its pair-to-fit map is not this section's")
    for name in ("B", "A", "probe_units", "bonded_force", "fit_r_mm", "fit_length_mm"):
        if not np.all(np.isfinite(a[name])):
            raise SetupError(f"array {name} holds non-finite numbers")
    if not np.array_equal(a["A"], a["A"].T):
        raise SetupError("its flexibility matrix is not symmetric")
    return Condensed(bonded, n_parts, n_fits, fop, a["B"], a["A"], a["probe_units"],
                     a["bonded_force"])
