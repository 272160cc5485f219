"""Material library: elastic, thermal-expansion and thermal properties, each with its source.

Units: E_MPa, nu (-), alpha_per_K at the 20 C reference, dalpha_per_K2 (1/K^2: the instantaneous
CTE is alpha(T) = alpha_per_K + dalpha_per_K2 * (T - 20 C)), density_kg_m3, conductivity_W_mK,
specific_heat_J_kgK.

The thermal strain from T_ref to T is the integral of the instantaneous CTE (exact for the linear
law, so the FE's superposition on theta = integral alpha dT stays exact, fem/solver.py):

    theta(T_ref, T) = alpha_20 (T - T_ref) + dalpha/2 [(T - 20)^2 - (T_ref - 20)^2]

Sources (numbers transcribed, typical handbook values at room temperature):
  [ASM-440C]  ASM Handbook Vol. 1 / AK Steel 440C product data: E 200 GPa, nu 0.28, CTE
              10.2e-6/K (0-100 C), k 24.2 W/mK, cp 460 J/kgK, rho 7650 kg/m^3.
  [CN-9Cr18]  China Aeronautical Materials Handbook, 9Cr18 (95Cr18): E 200 GPa, nu 0.3,
              CTE 10.5e-6/K (20-100 C), rho 7700, k 24, cp 460.  Ning et al. (the 71807C
              pair in TC4, studies/configs/seed000_71807C_TC4.toml) quote a CTE difference of
              about 1.5e-6/K between 9Cr18 and TC4 (fit rates -0.05/+0.07 um/C).
  [ASM-52100] ASM Handbook Vol. 1, AISI 52100 (GCr15): E 210 GPa, nu 0.30, CTE 11.9e-6/K
              (20-100 C), rho 7810, k 46.6, cp 475.
  [M50]       Harris & Kotzalas, Rolling Bearing Analysis 5th ed. Vol. 1 Table 5.x (M50):
              E 203 GPa, nu 0.28, CTE 11.3e-6/K; rho 7830, k 25.8, cp 460 (Latrobe data sheet).
  [MIL-TC4]   MIL-HDBK-5J / ASM Ti-6Al-4V annealed: E 113.8 GPa, nu 0.342, rho 4430,
              k 6.7 W/mK, cp 526; CTE 8.6e-6/K (20-100 C) in ASM, 9.0e-6/K in the Chinese
              handbook for TC4 (20-100 C); we take 9.0e-6 so that 9Cr18-TC4 = 1.5e-6 as in
              Ning et al.
              The instantaneous CTE rises with temperature (NIST cryogenic data suggest about
              8e-9 /K^2 over -60..100 C); the baseline keeps it constant, as Ning et al. do (their
              fit rates assume a constant CTE difference), and the `cte_nonlinearity` effect
              switches the slope on.
  [Si3N4]     Harris & Kotzalas Vol. 1 (hybrid bearings), Cerbec NBD200 data: E 310 GPa,
              nu 0.27, CTE 3.2e-6/K, rho 3200, k 30, cp 680.
  [Al2024]    ASM, 2024-T3 (Chinese 2A12): E 73.1 GPa, nu 0.33, CTE 23.2e-6/K (20-100 C),
              rho 2780, k 121, cp 875.
  [Al6061]    ASM, 6061-T6: E 68.9 GPa, nu 0.33, CTE 23.6e-6/K (20-100 C), rho 2700, k 167,
              cp 896.
  [17-4PH]    AK Steel 17-4PH H1025 data: E 196 GPa, nu 0.272, CTE 10.8e-6/K (21-93 C),
              rho 7800, k 18.3, cp 460.
  [Invar36]   Carpenter Technology, Invar 36 technical data sheet (annealed): E 141 GPa
              (20.5e6 psi), nu 0.259, CTE 1.3e-6/K (0.72e-6/F, -18..93 C), rho 8050 (0.291
              lb/in^3), k 10.15 W/mK, cp 515 J/kgK.
"""
from __future__ import annotations

from dataclasses import dataclass

T_CTE_REF_C = 20.0  # temperature at which alpha_per_K is quoted

#: kg/m^3 -> N s^2/mm^4 (the mass-density unit of the internal mm, N, s system): 1 N = 1 kg m/s^2
#: = 1e3 kg mm/s^2, so 1 kg = 1e-3 N s^2/mm; 1 m^3 = 1e9 mm^3; hence 1 kg/m^3 = 1e-3 / 1e9
#: N s^2/mm^4 = 1e-12 N s^2/mm^4 (1 N s^2/mm^4 = 1 tonne/mm^3). Steel 7800 kg/m^3 = 7.8e-9.
KG_M3_TO_N_S2_MM4 = 1e-12


@dataclass(frozen=True)
class Material:
    name: str
    E_MPa: float
    nu: float
    alpha_per_K: float
    density_kg_m3: float
    conductivity_W_mK: float
    specific_heat_J_kgK: float
    dalpha_per_K2: float = 0.0
    source: str = ""
    d2alpha_per_K3: float = 0.0

    def thermal_strain(self, T_C, T_ref_C):
        """theta = integral_{T_ref}^{T} alpha(T') dT' (dimensionless), exact for the quadratic law
        alpha(T) = alpha_per_K + dalpha_per_K2 (T - 20) + d2alpha_per_K3 (T - 20)^2 (T in C, 20 C =
        T_CTE_REF_C; the curvature term is zero unless the cte_nonlinearity curvature form sets it)."""
        a, b = T_C - T_CTE_REF_C, T_ref_C - T_CTE_REF_C
        theta = self.alpha_per_K * (T_C - T_ref_C) + 0.5 * self.dalpha_per_K2 * (a * a - b * b)
        if self.d2alpha_per_K3 != 0.0:
            theta = theta + self.d2alpha_per_K3 * (a * a * a - b * b * b) / 3.0
        return theta

    @property
    def density_N_s2_mm4(self) -> float:
        """Mass density in N s^2/mm^4 (kg/m^3 x KG_M3_TO_N_S2_MM4 = 1e-12): rho omega^2 r is
        then a body force in N/mm^3 for omega in rad/s and r in mm."""
        return self.density_kg_m3 * KG_M3_TO_N_S2_MM4

    def with_dalpha(self, dalpha_per_K2: float, d2alpha_per_K3: float = 0.0) -> "Material":
        """Copy with a different CTE slope (used by the cte_nonlinearity effect) and curvature
        (its generalised form, `studies.model.effects.cte_curvature`)."""
        return Material(**{**self.__dict__, "dalpha_per_K2": dalpha_per_K2,
                           "d2alpha_per_K3": d2alpha_per_K3})


_STEEL_9CR18 = dict(E_MPa=200e3, nu=0.30, alpha_per_K=10.5e-6, density_kg_m3=7700.0,
                    conductivity_W_mK=24.0, specific_heat_J_kgK=460.0, source="CN-9Cr18")
_STEEL_52100 = dict(E_MPa=210e3, nu=0.30, alpha_per_K=11.9e-6, density_kg_m3=7810.0,
                    conductivity_W_mK=46.6, specific_heat_J_kgK=475.0, source="ASM-52100")

MATERIALS: dict[str, Material] = {
    "9Cr18": Material("9Cr18", **_STEEL_9CR18),
    "G95Cr18": Material("G95Cr18", **_STEEL_9CR18),
    "440C": Material("440C", E_MPa=200e3, nu=0.28, alpha_per_K=10.2e-6, density_kg_m3=7650.0,
                     conductivity_W_mK=24.2, specific_heat_J_kgK=460.0, source="ASM-440C"),
    "GCr15": Material("GCr15", **_STEEL_52100),
    "52100": Material("52100", **_STEEL_52100),
    "M50": Material("M50", E_MPa=203e3, nu=0.28, alpha_per_K=11.3e-6, density_kg_m3=7830.0,
                    conductivity_W_mK=25.8, specific_heat_J_kgK=460.0, source="M50"),
    "TC4": Material("TC4", E_MPa=113.8e3, nu=0.342, alpha_per_K=9.0e-6, density_kg_m3=4430.0,
                    conductivity_W_mK=6.7, specific_heat_J_kgK=526.0, source="MIL-TC4"),
    "Si3N4": Material("Si3N4", E_MPa=310e3, nu=0.27, alpha_per_K=3.2e-6, density_kg_m3=3200.0,
                      conductivity_W_mK=30.0, specific_heat_J_kgK=680.0, source="Si3N4"),
    "2A12": Material("2A12", E_MPa=73.1e3, nu=0.33, alpha_per_K=23.2e-6, density_kg_m3=2780.0,
                     conductivity_W_mK=121.0, specific_heat_J_kgK=875.0, source="Al2024"),
    "6061": Material("6061", E_MPa=68.9e3, nu=0.33, alpha_per_K=23.6e-6, density_kg_m3=2700.0,
                     conductivity_W_mK=167.0, specific_heat_J_kgK=896.0, source="Al6061"),
    "17-4PH": Material("17-4PH", E_MPa=196e3, nu=0.272, alpha_per_K=10.8e-6,
                       density_kg_m3=7800.0, conductivity_W_mK=18.3, specific_heat_J_kgK=460.0,
                       source="17-4PH"),
    "Invar36": Material("Invar36", E_MPa=141e3, nu=0.259, alpha_per_K=1.3e-6,
                        density_kg_m3=8050.0, conductivity_W_mK=10.15, specific_heat_J_kgK=515.0,
                        source="Invar36"),
}
ALIASES = {"Invar": "Invar36", "Ti-6Al-4V": "TC4", "2024": "2A12", "AISI52100": "52100", "95Cr18": "G95Cr18"}


def get_material(name: str, user: tuple[Material, ...] = ()) -> Material:
    """Look a material up by name: first among `user` (a config's own `[materials.NAME]` tables,
    which may override a library name), then in the library by name or alias. KeyError names
    the known ones."""
    for m in user:
        if m.name == name:
            return m
    key = ALIASES.get(name, name)
    if key not in MATERIALS:
        known = sorted({*MATERIALS, *(m.name for m in user)})
        raise KeyError(f"unknown material '{name}' (known: {', '.join(known)})")
    return MATERIALS[key]


#: keys of a `[materials.NAME]` table and the Material field each sets (units in the names)
TABLE_KEYS = {"E_MPa": "E_MPa", "nu": "nu", "cte_per_K": "alpha_per_K",
              "dcte_per_K2": "dalpha_per_K2", "density_kg_m3": "density_kg_m3",
              "conductivity_W_mK": "conductivity_W_mK",
              "specific_heat_J_kgK": "specific_heat_J_kgK", "source": "source"}


def material_from_table(name: str, table: dict) -> Material:
    """A user's material from a `[materials.NAME]` table: the keys of `TABLE_KEYS` (CTE at 20 C
    as `cte_per_K`, its slope as `dcte_per_K2`), starting from the library material `base`
    (a name or alias) when given, or from the library material of the same name (override),
    else every key but `dcte_per_K2` and `source` is required. ValueError (one line, naming the
    key) on a missing, unknown or out-of-range value; the caller adds the file."""
    table = dict(table)
    base_name = table.pop("base", None)
    if base_name is not None and not isinstance(base_name, str):
        raise ValueError(f"materials.{name}.base: must be a material name, got {base_name!r}")
    try:
        base = get_material(base_name if base_name is not None else name)
    except KeyError as exc:
        if base_name is not None:
            raise ValueError(f"materials.{name}.base: {exc.args[0]}") from None
        base = None
    values = dict(base.__dict__) if base else {"dalpha_per_K2": 0.0, "source": ""}
    values["name"] = name
    for key, v in table.items():
        if key not in TABLE_KEYS:
            raise ValueError(f"materials.{name}.{key}: unknown key (known: base, "
                             f"{', '.join(TABLE_KEYS)})")
        if key == "source":
            values["source"] = str(v)
            continue
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v != v or abs(v) == float("inf"):
            raise ValueError(f"materials.{name}.{key}: must be a finite number, got {v!r}")
        values[TABLE_KEYS[key]] = float(v)
    missing = [k for k, f in TABLE_KEYS.items() if f not in values]
    if missing:
        raise ValueError(f"materials.{name}: missing {', '.join(missing)} (or give base = "
                         f"\"<library material>\" to start from)")
    for key, ok, what in (("E_MPa", values["E_MPa"] > 0, "> 0"),
                          ("nu", 0.0 <= values["nu"] < 0.5, "in 0..0.5"),
                          ("cte_per_K", abs(values["alpha_per_K"]) < 1e-3, "below 1e-3 /K in size"),
                          ("density_kg_m3", values["density_kg_m3"] > 0, "> 0"),
                          ("conductivity_W_mK", values["conductivity_W_mK"] > 0, "> 0"),
                          ("specific_heat_J_kgK", values["specific_heat_J_kgK"] > 0, "> 0")):
        if not ok:
            raise ValueError(f"materials.{name}.{key}: must be {what}, got {values[TABLE_KEYS[key]]:g}")
    return Material(**values)
