"""Lubricant properties and elastohydrodynamic film: viscosity-temperature (ASTM D341 / Walther),
a space-oil library with sources, Hamrock-Dowson point-contact film thickness, film parameter
lambda and the lubrication regime of GB/T 28878.2-2016 Annex B.1.

Units: temperatures C (K only inside the Walther law), kinematic viscosity nu in mm^2/s (= cSt),
dynamic viscosity eta in Pa*s, density kg/m^3, pressure-viscosity coefficient alpha in 1/Pa,
lengths mm (film thickness and roughness in um), loads N, moduli MPa, speeds mm/s.

Walther / ASTM D341 (ASTM D341-20, eq. 1 with Z = nu + 0.7, valid for nu >= 2 mm^2/s; the
corrections of D341 for thinner oils are not implemented, none of the space oils here goes below
about 10 mm^2/s in -60..150 C):

    log10(log10(nu + 0.7)) = A - B log10(T_K)

A and B come from two datasheet points exactly, or from three or more by least squares in the
transformed variables (x = log10 T_K, y = log10 log10(nu + 0.7)). The `viscosity_temperature`
effect scales the slope B by `slope_factor` about the 40 C point (the ISO VG reference temperature),
so nu(40 C) is unchanged:  B' = s B,  A' = A + (s - 1) B log10(313.15).

Lubricant library: `analytic/data/space_oil_viscosity.csv` (copied from the project's reference
data; its '#' header names every source and is kept, see `csv_sources`). Properties that the CSV does not
give are assumptions stated in `_FAMILY_DEFAULTS` with their source or rationale.
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

K0 = 273.15
T_PIVOT_C = 40.0
#: an oil temperature this far (K) outside the Walther fit's range makes the range warning say
#: what the rows then mean (`WaltherLaw.extrapolation_warning`): the reference data's own case,
#: a 40/100 C fit of Pennzane SHF X-2000 at -40 C, is +57 % off (BESSETTE1997, tests/
#: test_lubricant_table.py); 20 K is our threshold (assumption: the D341 chart is drawn between
#: measured points, ASTM D341 sec. 1, and 20 K is about a third of a typical fit's span)
EXTRAPOLATION_FAR_K = 20.0
DATA_CSV = Path(__file__).parent / "data" / "space_oil_viscosity.csv"


# --------------------------------------------------------------------------- Walther / ASTM D341
def walther_transform(nu_mm2_s):
    """y = log10(log10(nu + 0.7)) (ASTM D341, nu in mm^2/s, valid for nu >= 2 mm^2/s)."""
    return np.log10(np.log10(np.asarray(nu_mm2_s, float) + 0.7))


def walther_inverse(y):
    """nu in mm^2/s from y = log10(log10(nu + 0.7)) (ASTM D341)."""
    return 10.0 ** (10.0 ** np.asarray(y, float)) - 0.7


@dataclass(frozen=True)
class WaltherLaw:
    """log10(log10(nu + 0.7)) = A - B log10(T_K) (ASTM D341); nu in mm^2/s, T in K.

    fit_range_C: the temperature span of the points it was fitted to; outside it the law is an
    extrapolation (see studies/validation/lubricant_viscosity.py for how far that can be trusted).
    """
    A: float
    B: float
    fit_range_C: tuple[float, float] = (np.nan, np.nan)
    source: str = ""

    def nu_mm2_s(self, T_C, slope_factor=1.0):
        """Kinematic viscosity (mm^2/s) at T_C; slope_factor scales B about 40 C (see module)."""
        law = self.with_slope_factor(slope_factor) if slope_factor != 1.0 else self
        x = np.log10(np.asarray(T_C, float) + K0)
        return walther_inverse(law.A - law.B * x)

    def T_C(self, nu_mm2_s):
        """The temperature (C) at which this law gives nu_mm2_s (its inverse)."""
        return 10.0 ** ((self.A - walther_transform(nu_mm2_s)) / self.B) - K0

    def extrapolation_warning(self, nu_mm2_s, name: str) -> str | None:
        """One line when any of the viscosities nu_mm2_s (mm^2/s, from this law) lies at a
        temperature outside `fit_range_C` (beyond 0.01 K): the law is then an extrapolation."""
        nu = np.asarray(nu_mm2_s, float).ravel()
        nu = nu[np.isfinite(nu)]
        lo, hi = self.fit_range_C
        if not nu.size or not np.isfinite(lo):
            return None
        T = self.T_C(nu)
        out = (T < lo - 0.01) | (T > hi + 0.01)
        if not out.any():
            return None
        beyond_K = float(max(lo - T.min(), T.max() - hi))
        far = (f"; up to {beyond_K:.0f} K beyond it (viscosity up to {nu[out].max():.4g} mm2/s): "
               "the viscosity, viscous torque and film of those rows are the law's guess, not "
               "data (a 40/100 C fit of Pennzane X-2000 is +57 % off at -40 C, BESSETTE1997)"
               if beyond_K > EXTRAPOLATION_FAR_K else "")
        return (f"lubricant {name}: oil temperature {T[out].min():.1f}..{T[out].max():.1f} C in "
                f"{int(out.sum())} "
                f"of {T.size} rows is outside the Walther fit's range {lo:g}..{hi:g} C: the "
                "viscosity there is extrapolated (give viscosity points that span the range)"
                + far)

    def with_slope_factor(self, slope_factor: float, T_pivot_C: float = T_PIVOT_C) -> "WaltherLaw":
        """Same nu at T_pivot_C, slope B scaled by slope_factor (> 0)."""
        if not slope_factor > 0:
            raise ValueError(f"slope_factor must be > 0, got {slope_factor}")
        x0 = np.log10(T_pivot_C + K0)
        B = slope_factor * self.B
        return WaltherLaw(self.A + (B - self.B) * x0, B, self.fit_range_C,
                          f"{self.source} (slope x{slope_factor:g} about {T_pivot_C:g} C)")


def fit_walther(T_C, nu_mm2_s, source: str = "") -> WaltherLaw:
    """Walther law through two points (exact) or least squares in (log10 T_K, log10 log10(nu+0.7))
    for three or more points (ASTM D341). Raises ValueError for < 2 distinct temperatures."""
    T = np.asarray(T_C, float).ravel()
    nu = np.asarray(nu_mm2_s, float).ravel()
    if T.size != nu.size or np.unique(T).size < 2:
        raise ValueError("a Walther fit needs at least two points at distinct temperatures")
    if np.any(nu < 2.0):
        raise ValueError("ASTM D341 with Z = nu + 0.7 is valid for nu >= 2 mm^2/s")
    x = np.log10(T + K0)
    y = walther_transform(nu)
    X = np.column_stack([np.ones_like(x), -x])
    (A, B), *_ = np.linalg.lstsq(X, y, rcond=None)
    return WaltherLaw(float(A), float(B), (float(T.min()), float(T.max())), source)


# --------------------------------------------------------------------------- Vogel (VFT) law
@dataclass(frozen=True)
class VogelLaw:
    """Vogel-Fulcher-Tammann: nu = exp(a + b / (T_K - T0_K)) (Vogel 1921; used for lubricants
    e.g. in Seeton, Tribology Letters 22 (2006) 67). Three parameters, fitted exactly through
    three points; T0_K is the divergence temperature (below the glass transition)."""
    a: float
    b: float
    T0_K: float
    fit_range_C: tuple[float, float] = (np.nan, np.nan)

    def nu_mm2_s(self, T_C):
        return np.exp(self.a + self.b / (np.asarray(T_C, float) + K0 - self.T0_K))


def fit_vogel(T_C, nu_mm2_s) -> VogelLaw:
    """VFT law exactly through three points (ln nu = a + b/(T - T0)). Raises ValueError when
    the points' curvature has the wrong sign for a VFT law (no 0 < T0 < min T solution)."""
    from scipy.optimize import brentq

    T = np.asarray(T_C, float) + K0
    if T.size != 3:
        raise ValueError("fit_vogel needs exactly three points")
    order = np.argsort(T)
    T = T[order]
    y = np.log(np.asarray(nu_mm2_s, float)[order])
    target = (y[0] - y[1]) / (y[1] - y[2])

    def g(T0):
        return (1 / (T[0] - T0) - 1 / (T[1] - T0)) / (1 / (T[1] - T0) - 1 / (T[2] - T0)) - target

    lo, hi = 1e-6, T[0] - 1e-6
    if np.sign(g(lo)) == np.sign(g(hi)):
        raise ValueError("no VFT law (0 K < T0 < lowest temperature) through these points")
    T0 = brentq(g, lo, hi, xtol=1e-12)
    b = (y[0] - y[1]) / (1 / (T[0] - T0) - 1 / (T[1] - T0))
    a = y[0] - b / (T[0] - T0)
    return VogelLaw(float(a), float(b), float(T0), (float(T[0] - K0), float(T[2] - K0)))


# --------------------------------------------------------------------------- lubricant library
@dataclass(frozen=True)
class FamilyDefaults:
    """Properties not in the CSV, per chemical family, with their source or rationale."""
    density_kg_m3: float
    density_T_C: float
    density_source: str
    alpha_per_Pa: float
    alpha_source: str


_FAMILY_DEFAULTS: dict[str, FamilyDefaults] = {
    # Linear perfluoropolyethers (Fomblin Z, Brayco 815Z).
    "PFPE": FamilyDefaults(
        density_kg_m3=1850.0, density_T_C=20.0,
        density_source="assumption: typical linear-PFPE (Fomblin Z type) datasheet density "
                       "1.85 g/mL at 20 C; not in the project CSV",
        alpha_per_Pa=1.5e-8,
        alpha_source="assumption: mid value of the 1.0-1.8e-8 1/Pa range usually quoted for "
                     "linear PFPE (Fomblin Z); film thickness scales with alpha^0.49, so the "
                     "range means about +-15 % in h"),
    # Multiply alkylated cyclopentane (Pennzane SHF X-2000 base, Nye 2001a).
    "MAC": FamilyDefaults(
        density_kg_m3=840.0, density_T_C=25.0,
        density_source="BESSETTE1997 (Pennzane SHF X-2000 0.84 g/mL at 25 C, in the project CSV); "
                       "taken for Nye 2001a too (same base oil)",
        alpha_per_Pa=1.0e-8,
        alpha_source="assumption: order of magnitude for MAC used in this project (brief); "
                     "replace with a measured value when available"),
}
# The density is taken constant in temperature: a volumetric expansion of order 7e-4 /K changes
# it by < 10 % over -60..80 C, against a viscosity change of two to three orders of magnitude.

# Which family each CSV lubricant belongs to, and short aliases.
_FAMILY_OF = {"Fomblin": "PFPE", "Brayco": "PFPE", "Pennzane": "MAC", "Nye 2001a": "MAC"}
ALIASES = {
    "Fomblin Z25": "Fomblin Z25", "Z25": "Fomblin Z25",
    "Fomblin Z60": "Fomblin Z60", "Z60": "Fomblin Z60",
    "Nye 2001a": "Nye 2001a (Pennzane MAC)", "2001a": "Nye 2001a (Pennzane MAC)",
    "Pennzane SHF X-2000": "Pennzane SHF X-2000 (base MAC)",
    "X-2000": "Pennzane SHF X-2000 (base MAC)", "Pennzane": "Pennzane SHF X-2000 (base MAC)",
    "Brayco 815Z": "Brayco 815Z (PFPE; base oil of Braycote 600EF/601EF)",
    "815Z": "Brayco 815Z (PFPE; base oil of Braycote 600EF/601EF)",
    "Brayco 814": "Brayco 814 (PFPE; discontinued)",
}


@dataclass(frozen=True)
class Lubricant:
    """One oil: datasheet viscosity points (T_C, nu_mm2_s, source key) and derived properties."""
    name: str
    family: str
    viscosity_points: tuple[tuple[float, float, str], ...]
    density_kg_m3: float
    density_source: str
    alpha_per_Pa: float
    alpha_source: str
    viscosity_index: float | None = None
    pour_point_C: float | None = None
    extra: dict = field(default_factory=dict, hash=False, compare=False)

    @property
    def oil_family(self) -> str:
        """"mineral" or "synthetic" (OIL_FAMILIES): a user table's `family` (default mineral),
        synthetic for the library's PFPE and MAC oils."""
        return self.extra.get("oil_family", "synthetic" if self.family in _SYNTHETIC_FAMILIES
                              else "mineral")

    @property
    def T_points_C(self) -> np.ndarray:
        return np.array([p[0] for p in self.viscosity_points])

    @property
    def nu_points_mm2_s(self) -> np.ndarray:
        return np.array([p[1] for p in self.viscosity_points])

    def walther(self, temperatures_C=None) -> WaltherLaw:
        """Walther law fitted to the datasheet points at `temperatures_C` (default: all points;
        two points exactly, more by least squares). ValueError if fewer than two points."""
        T, nu = self.T_points_C, self.nu_points_mm2_s
        if temperatures_C is not None:
            keep = np.isin(T, np.asarray(temperatures_C, float))
            T, nu = T[keep], nu[keep]
        if T.size < 2:
            raise ValueError(f"{self.name}: fewer than two viscosity points"
                             f"{'' if temperatures_C is None else ' at ' + str(temperatures_C)}"
                             " - no Walther law can be fitted from the project data (give the "
                             "oil as a [lubricants.NAME] table with two or more points)")
        srcs = sorted({p[2] for p in self.viscosity_points if p[0] in T})
        return fit_walther(T, nu, source=f"{self.name}: Walther fit to {list(T)} C ({', '.join(srcs)})")

    def statement(self) -> str:
        """One sentence for a report: the oil, its Walther fit (points, temperature range), density
        and pressure-viscosity coefficient with their sources."""
        law = self.walther()
        lo, hi = law.fit_range_C
        pts = ", ".join(f"{nu:g} cSt at {T:g} C" for T, nu, _ in self.viscosity_points)
        return (f"Oil {self.name}: viscosity by the Walther (ASTM D341) fit through {pts}, "
                f"valid {lo:g}..{hi:g} C (extrapolated outside, a warning says so); density "
                f"{self.density_kg_m3:g} kg/m^3 ({self.density_source}); pressure-viscosity "
                f"coefficient {self.alpha_per_Pa * 1e9:g} 1/GPa ({self.alpha_source}).")

    def nu_mm2_s(self, T_C, slope_factor: float = 1.0):
        """Kinematic viscosity (mm^2/s) from the Walther law of all datasheet points."""
        return self.walther().nu_mm2_s(T_C, slope_factor)

    def eta_Pa_s(self, T_C, slope_factor: float = 1.0):
        """Dynamic viscosity (Pa*s) = nu * rho (density constant, see `density_source`)."""
        return dynamic_viscosity_Pa_s(self.nu_mm2_s(T_C, slope_factor), self.density_kg_m3)


def dynamic_viscosity_Pa_s(nu_mm2_s, density_kg_m3):
    """eta = rho nu; nu in mm^2/s (1e-6 m^2/s), rho in kg/m^3 -> Pa*s."""
    return np.asarray(nu_mm2_s, float) * 1e-6 * np.asarray(density_kg_m3, float)


def read_viscosity_csv(path: str | Path = DATA_CSV):
    """Parse the space-oil CSV: returns (sources, rows). sources maps a key such as 'ESTL2018' to
    its citation text from the '#' header; rows are dicts of the CSV columns (value as float,
    temperature_C as float or None)."""
    sources: dict[str, str] = {}
    notes: list[str] = []
    body: list[str] = []
    key = None
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("#"):
                text = line[1:].strip()
                m = re.match(r"\[([A-Za-z0-9_]+)\]\s*(.*)", text)
                if m:
                    key = m.group(1)
                    sources[key] = m.group(2)
                elif key and line.startswith("#  ") and not text.startswith(("Notes", "Sources")):
                    sources[key] += " " + text
                else:
                    key = None
                    notes.append(text)
            elif line.strip():
                body.append(line)
    rows = []
    for r in csv.DictReader(body):
        T = r["temperature_C"].strip()
        rows.append({"lubricant": r["lubricant"], "temperature_C": float(T) if T else None,
                     "property": r["property"], "value": float(r["value"]), "unit": r["unit"],
                     "source": r["source"]})
    sources["_notes"] = " ".join(notes)
    return sources, rows


@lru_cache(maxsize=4)
def _library(path: str) -> tuple[dict[str, str], dict[str, Lubricant]]:
    sources, rows = read_viscosity_csv(path)
    names = list(dict.fromkeys(r["lubricant"] for r in rows))
    lib = {}
    for name in names:
        mine = [r for r in rows if r["lubricant"] == name]
        family = next(f for k, f in _FAMILY_OF.items() if name.startswith(k))
        fam = _FAMILY_DEFAULTS[family]
        pts = tuple(sorted((r["temperature_C"], r["value"], r["source"]) for r in mine
                           if r["property"] == "kinematic_viscosity"))
        prop = {r["property"]: r for r in mine if r["property"] != "kinematic_viscosity"}
        density, dsrc = fam.density_kg_m3, fam.density_source
        if "density" in prop:      # g/mL in the CSV
            density = prop["density"]["value"] * 1000.0
            dsrc = f"{prop['density']['source']} ({prop['density']['value']} g/mL at " \
                   f"{prop['density']['temperature_C']:g} C, project CSV)"
        lib[name] = Lubricant(
            name=name, family=family, viscosity_points=pts, density_kg_m3=density,
            density_source=dsrc, alpha_per_Pa=fam.alpha_per_Pa, alpha_source=fam.alpha_source,
            viscosity_index=prop["viscosity_index"]["value"] if "viscosity_index" in prop else None,
            pour_point_C=prop["pour_point"]["value"] if "pour_point" in prop else None,
            extra={k: v for k, v in prop.items()})
    return sources, lib


def lubricant_library(path: str | Path = DATA_CSV) -> dict[str, Lubricant]:
    """All lubricants of the CSV by full name."""
    return dict(_library(str(path))[1])


def csv_sources(path: str | Path = DATA_CSV) -> dict[str, str]:
    """Citation text of every source key in the CSV header ('_notes': the header's notes)."""
    return dict(_library(str(path))[0])


def get_lubricant(name: str, user: tuple[Lubricant, ...] = (),
                  path: str | Path = DATA_CSV) -> Lubricant:
    """Look an oil up: first among `user` (a config's own `[lubricants.NAME]` tables, which may
    take a library name), then by full CSV name or alias (e.g. 'Fomblin Z25', 'X-2000', '815Z').
    KeyError names the known ones."""
    for lub in user:
        if lub.name == name:
            return lub
    lib = lubricant_library(path)
    key = ALIASES.get(name, name)
    if key not in lib:
        own = f"; the file's own: {', '.join(u.name for u in user)}" if user else ""
        raise KeyError(f"unknown lubricant '{name}' (known: {', '.join(sorted(lib))}; "
                       f"aliases: {', '.join(sorted(ALIASES))}{own}; or give a "
                       f"[lubricants.NAME] table)")
    return lib[key]


#: keys of a `[lubricants.NAME]` table (units in the names); all but `source` required
LUBRICANT_TABLE_KEYS = ("kinematic_viscosity_cSt", "density_kg_m3", "pressure_viscosity_per_GPa",
                        "source", "family")
#: a `[lubricants.NAME]` table's `family`: the base oil's class, for the SKF model's full-film
#: friction coefficient (mu_EHL 0.05 mineral, 0.04 synthetic; analytic/friction/skf2004.py)
OIL_FAMILIES = ("mineral", "synthetic")
#: the library's chemical families are synthetic base oils (PFPE, multiply alkylated cyclopentane)
_SYNTHETIC_FAMILIES = ("PFPE", "MAC")


def _finite(v) -> bool:
    return (not isinstance(v, bool) and isinstance(v, (int, float)) and v == v
            and abs(v) != float("inf"))


#: a user oil's density below this (kg/m^3) is a value typed in g/cm^3: liquid lubricants are
#: about 700 (light hydrocarbons) to 1900 (PFPE; the library's 840-1850), so the bound is a
#: factor 7 below the lightest (the project's bound, a unit check, not a property)
DENSITY_MIN_KG_M3 = 100.0
#: a pressure-viscosity coefficient below this (1/GPa) is a value typed in 1/Pa (1e-8 1/Pa =
#: 10 1/GPa): the library's oils are 10-15 1/GPa (`_FAMILY_DEFAULTS`, assumptions stated
#: there); the project's bound, four decades below them (a unit check, not a property)
ALPHA_MIN_PER_GPA = 1e-3


def lubricant_from_table(name: str, table: dict) -> Lubricant:
    """A user's oil from a `[lubricants.NAME]` table:
    `kinematic_viscosity_cSt = [[T_C, nu], ...]` (at least two points at distinct temperatures,
    nu >= 2 mm^2/s = cSt, the validity of ASTM D341 with Z = nu + 0.7), `density_kg_m3` (> 0,
    taken constant in temperature as for the library oils), `pressure_viscosity_per_GPa` (the
    Barus coefficient alpha of eta = eta0 exp(alpha p), > 0; 1/GPa = 1e-9 1/Pa) and `source`
    (text). The viscosity-temperature law is the Walther fit through the points (`fit_walther`),
    valid over their temperature span. ValueError (one line naming the key) on a missing, unknown
    or out-of-range value; the caller adds the file."""
    pre = f"lubricants.{name}"
    for key in table:
        if key not in LUBRICANT_TABLE_KEYS:
            raise ValueError(f"{pre}.{key}: unknown key (known: {', '.join(LUBRICANT_TABLE_KEYS)})")
    missing = [k for k in LUBRICANT_TABLE_KEYS[:3] if k not in table]
    if missing:
        raise ValueError(f"{pre}: missing {', '.join(missing)}")
    pts = table["kinematic_viscosity_cSt"]
    key = f"{pre}.kinematic_viscosity_cSt"
    if (not isinstance(pts, list) or not all(isinstance(p, list) and len(p) == 2
                                             and all(_finite(v) for v in p) for p in pts)):
        raise ValueError(f"{key}: give [[T_C, nu_cSt], ...], pairs of finite numbers")
    if len({float(p[0]) for p in pts}) < 2 or len({float(p[0]) for p in pts}) != len(pts):
        raise ValueError(f"{key}: needs at least two points at distinct temperatures for the "
                         f"Walther fit (ASTM D341), got {len(pts)}")
    for T, nu in pts:
        if not -150.0 <= T <= 300.0:
            raise ValueError(f"{key}: temperature {T:g} C outside -150..300 C")
        if nu < 2.0:
            raise ValueError(f"{key}: {nu:g} cSt at {T:g} C is below 2 cSt, where ASTM D341 "
                             "(Z = nu + 0.7) is not valid")
    for k in ("density_kg_m3", "pressure_viscosity_per_GPa"):
        v = table[k]
        if not _finite(v) or v <= 0:
            raise ValueError(f"{pre}.{k}: must be a finite number > 0, got {v!r}")
    rho, alpha = (table[k] for k in ("density_kg_m3", "pressure_viscosity_per_GPa"))
    if rho < DENSITY_MIN_KG_M3:
        raise ValueError(f"{pre}.density_kg_m3: {rho:g} kg/m^3 is below any liquid lubricant's "
                         f"(limit {DENSITY_MIN_KG_M3:g}): typed in g/cm^3? ({rho:g} g/cm^3 = "
                         f"{rho * 1e3:g} kg/m^3)")
    if alpha < ALPHA_MIN_PER_GPA:
        raise ValueError(f"{pre}.pressure_viscosity_per_GPa: {alpha:g} 1/GPa is below any "
                         f"lubricant's (limit {ALPHA_MIN_PER_GPA:g}): typed in 1/Pa? ({alpha:g} "
                         f"1/Pa = {alpha * 1e9:g} 1/GPa)")
    src = str(table.get("source", ""))
    fam = table.get("family", "mineral")
    if fam not in OIL_FAMILIES:
        raise ValueError(f"{pre}.family: must be one of {', '.join(map(repr, OIL_FAMILIES))}, "
                         f"got {fam!r}")
    return Lubricant(
        name=name, family="user", viscosity_points=tuple(sorted(
            (float(T), float(nu), src or "config") for T, nu in pts)),
        density_kg_m3=float(table["density_kg_m3"]),
        density_source=src or "the config's [lubricants] table",
        alpha_per_Pa=float(table["pressure_viscosity_per_GPa"]) * 1e-9,
        alpha_source=src or "the config's [lubricants] table", extra={"oil_family": fam})


# --------------------------------------------------------------------------- EHL film
def reduced_modulus_MPa(E1_MPa, nu1, E2_MPa, nu2):
    """Effective modulus E' = 2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) in MPa (Hamrock & Dowson
    1977 definition; note E' = 2 E* of Johnson's Contact Mechanics)."""
    return 2.0 / ((1 - np.asarray(nu1) ** 2) / np.asarray(E1_MPa, float)
                  + (1 - np.asarray(nu2) ** 2) / np.asarray(E2_MPa, float))


def ellipticity_hamrock_dowson(Rx_mm, Ry_mm):
    """Approximate ellipticity k = a/b = 1.03 (Ry/Rx)^0.64 (Hamrock & Dowson, J. Lubr. Technol.
    99 (1977) 264, the simplified expression of Part III)."""
    return 1.03 * (np.asarray(Ry_mm, float) / np.asarray(Rx_mm, float)) ** 0.64


@dataclass(frozen=True)
class EHLFilm:
    """Hamrock-Dowson point-contact film: thicknesses in um, dimensionless groups."""
    h_min_um: np.ndarray
    h_central_um: np.ndarray
    U: np.ndarray
    G: np.ndarray
    W: np.ndarray
    k: np.ndarray


def hamrock_dowson_film(Rx_mm, Ry_mm, E_reduced_MPa, eta0_Pa_s, alpha_per_Pa,
                        entrainment_speed_mm_s, load_N, k=None) -> EHLFilm:
    """Isothermal fully flooded EHL film of a point contact (Hamrock & Dowson, J. Lubr. Technol.
    99 (1977) 264, Part III; also GB/T 28878.2-2016 eq. B.3):

        H_min = h_min / Rx = 3.63 U^0.68 G^0.49 W^-0.073 (1 - exp(-0.68 k))
        H_c   = h_c / Rx   = 2.69 U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k))

    with U = eta0 u / (E' Rx), G = alpha E', W = w / (E' Rx^2); u = mean entrainment speed
    (u_a + u_b)/2, Rx the reduced radius in the rolling direction (Rx < Ry), E' from
    `reduced_modulus_MPa`. Units here: Rx, Ry mm; E' MPa (N/mm^2); eta0 Pa*s (= 1e-6 N s/mm^2);
    alpha 1/Pa (= 1e6 1/MPa); u mm/s; w N. k defaults to 1.03 (Ry/Rx)^0.64.
    Fitted by the authors for 1 <= k <= 8; U and W over about two and one decades.
    """
    Rx = np.asarray(Rx_mm, float)
    Ep = np.asarray(E_reduced_MPa, float)
    U = np.asarray(eta0_Pa_s, float) * 1e-6 * np.asarray(entrainment_speed_mm_s, float) / (Ep * Rx)
    G = np.asarray(alpha_per_Pa, float) * 1e6 * Ep
    W = np.asarray(load_N, float) / (Ep * Rx * Rx)
    kk = ellipticity_hamrock_dowson(Rx, Ry_mm) if k is None else np.asarray(k, float)
    H_min = 3.63 * U**0.68 * G**0.49 * W**-0.073 * (1 - np.exp(-0.68 * kk))
    H_c = 2.69 * U**0.67 * G**0.53 * W**-0.067 * (1 - 0.61 * np.exp(-0.73 * kk))
    return EHLFilm(H_min * Rx * 1e3, H_c * Rx * 1e3, U, G, W, kk)


def ball_raceway_radii_mm(ball_diameter_mm, pitch_diameter_mm, contact_angle_deg,
                          groove_ratio, raceway: str):
    """Reduced radii (Rx, Ry) in mm of a ball/raceway contact (Hamrock & Dowson, Ball Bearing
    Lubrication 1981 ch. 3; Harris & Kotzalas Vol. 1 ch. 2):
        inner: Rx = Dw (dm - Dw cos a) / (2 dm);  outer: Rx = Dw (dm + Dw cos a) / (2 dm)
        Ry = f Dw / (2 f - 1)  (f = groove radius / Dw)."""
    Dw = np.asarray(ball_diameter_mm, float)
    dm = np.asarray(pitch_diameter_mm, float)
    c = np.cos(np.radians(contact_angle_deg))
    f = np.asarray(groove_ratio, float)
    if raceway == "inner":
        Rx = Dw * (dm - Dw * c) / (2 * dm)
    elif raceway == "outer":
        Rx = Dw * (dm + Dw * c) / (2 * dm)
    else:
        raise ValueError("raceway must be 'inner' or 'outer'")
    return Rx, f * Dw / (2 * f - 1)


def entrainment_speed_mm_s(speed_rpm, ball_diameter_mm, pitch_diameter_mm, contact_angle_deg):
    """Mean entrainment (rolling) speed u = |omega_i - omega_o| (dm^2 - Dw^2 cos^2 a) / (4 dm)
    in mm/s for the relative ring speed n in rpm (pure rolling; Hamrock & Dowson, Ball Bearing
    Lubrication, 1981, ch. 3). Same for the inner and outer contacts."""
    w = 2 * np.pi * np.asarray(speed_rpm, float) / 60.0
    dm = np.asarray(pitch_diameter_mm, float)
    Dc = np.asarray(ball_diameter_mm, float) * np.cos(np.radians(contact_angle_deg))
    return np.abs(w) * (dm * dm - Dc * Dc) / (4 * dm)


# --------------------------------------------------------------------------- lambda and regime
def composite_roughness_um(Rq1_um, Rq2_um):
    """sigma = sqrt(Rq1^2 + Rq2^2), um (GB/T 28878.2-2016 eq. B.1)."""
    return np.hypot(np.asarray(Rq1_um, float), np.asarray(Rq2_um, float))


def film_parameter(h_min_um, Rq1_um, Rq2_um):
    """Film parameter lambda = h_min / sqrt(Rq1^2 + Rq2^2) (GB/T 28878.2-2016 eq. B.1)."""
    return np.asarray(h_min_um, float) / composite_roughness_um(Rq1_um, Rq2_um)


# GB/T 28878.2-2016 Annex B.1 (after Hamrock's regime chart) gives overlapping ranges: boundary
# lambda < 1; mixed 1 < lambda < 3; partial EHL 3 < lambda <= 10; full EHL and hydrodynamic up to
# lambda < 100 from a lower bound that is illegible in our copy of the text (Hamrock's chart has
# 5). We split the ranges at 1, 3 and 10 so that every lambda gets exactly one regime.
REGIME_EDGES = (1.0, 3.0, 10.0)
REGIMES = ("boundary", "mixed", "partial_ehl", "full_film")


def lubrication_regime(lam):
    """Regime name(s) per GB/T 28878.2-2016 Annex B.1: 'boundary' (lambda < 1), 'mixed'
    (1 <= lambda < 3), 'partial_ehl' (3 <= lambda < 10), 'full_film' (lambda >= 10)."""
    lam = np.asarray(lam, float)
    idx = np.searchsorted(REGIME_EDGES, lam, side="right")
    if lam.ndim == 0:
        return REGIMES[int(idx)]
    return np.asarray(REGIMES, dtype=object)[idx]
