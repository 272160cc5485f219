"""Bearing internal geometry used by the seed reproductions: the one place for these numbers.

Every number carries its provenance:
  [ISO]     boundary dimensions d x D x B of the ISO 15 dimension series the designation belongs to
            (the same numbers are printed in every maker's catalogue).
  [cat]     read off the maker's designation: NSK "C" suffix = 15 deg nominal contact angle;
            NSK "TAC" ball-screw support bearings = 60 deg contact angle.
  [seed N]  stated in seed document N (see /work/shared/seeds).
  [assume]  assumption: the seeds' Table 1 (internal geometry) was lost in extraction and the maker
            catalogues reachable from here do not print ball size, ball count or groove radii.
            The rules used: pitch diameter dm = (d + D)/2; ball diameter an inch-series ball of
            about 0.6-0.66 of the section height (D - d)/2 for 15 deg precision bearings and about
            0.4 for the 60 deg TAC series (many small balls); ball count so that the balls fill
            about 75-80 % of the pitch circle (Z Dw / (pi dm)), the usual range for a machined or
            moulded cage; groove radius ratios f_i = 0.52-0.53, f_o = 0.53 (Harris & Kotzalas,
            Rolling Bearing Analysis 5th ed., Vol. 1 ch. 2: 0.515-0.54 typical for ball bearings).

Changing one of these changes every preload/stiffness/torque number downstream: the study reports
say that these are assumptions (the `[assume]` tags of the shipped assembly files; docs/cli.md
"report", the numbered assumptions).
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class BearingSpec:
    """A bearing as its user states it (an assembly's [bearing] table, a catalogue entry):
    boundary dimensions, internal geometry (Harris & Kotzalas Vol. 1 ch. 2 notation) and the
    effective ring sections the FE uses, in mm; materials by name.
    `analytic.bearing.geometry.BearingGeometry.from_spec` resolves it for the bearing model (kept
    here, with the data, so that the catalogue imports nothing of `analytic.bearing`)."""
    designation: str
    bore_mm: float
    outside_diameter_mm: float
    width_mm: float
    ball_diameter_mm: float
    ball_count: int
    pitch_diameter_mm: float
    inner_groove_ratio: float        # f_i = r_i / Dw
    outer_groove_ratio: float        # f_o = r_o / Dw
    contact_angle_free_deg: float
    inner_ring_outer_diameter_mm: float   # effective FE section of the inner ring
    outer_ring_inner_diameter_mm: float   # effective FE section of the outer ring
    ring_material: str
    ball_material: str
    inner_land_diameter_mm: float = 0.0   # shoulder on the loaded side; 0: inferred (bearing/land.py)
    outer_land_diameter_mm: float = 0.0


@dataclass(frozen=True)
class CatalogueEntry:
    """One bearing type: its `BearingSpec` and where each number comes from."""
    spec: BearingSpec
    sources: dict[str, str] = field(default_factory=dict)
    note: str = ""


CATALOGUE: dict[str, CatalogueEntry] = {
    "NSK 71807C": CatalogueEntry(
        spec=BearingSpec(
            designation="NSK 71807C",
            bore_mm=35.0, outside_diameter_mm=47.0, width_mm=7.0,
            ball_diameter_mm=3.969, ball_count=24, pitch_diameter_mm=41.0,
            inner_groove_ratio=0.52, outer_groove_ratio=0.53, contact_angle_free_deg=15.0,
            ring_material="9Cr18", ball_material="9Cr18",
            inner_ring_outer_diameter_mm=37.8, outer_ring_inner_diameter_mm=44.2),
        sources={"inner_ring_outer_diameter_mm": "assume (mean of groove bottom and land)",
                 "outer_ring_inner_diameter_mm": "assume (mean of groove bottom and land)",
                 "bore_mm": "ISO (718 series, 35x47x7)", "outside_diameter_mm": "ISO",
                 "width_mm": "ISO", "contact_angle_free_deg": "cat (C = 15 deg)",
                 "ball_diameter_mm": "assume (5/32 in; 0.66 of the 6 mm section)",
                 "ball_count": "assume (fill 0.74)", "pitch_diameter_mm": "assume ((d+D)/2)",
                 "inner_groove_ratio": "assume", "outer_groove_ratio": "assume",
                 "ring_material": "seed 000", "ball_material": "seed 000"},
        note="seed 000: pair back-to-back, MoS2 film, TC4 shaft and housing"),
    "NSK 25TAC62B": CatalogueEntry(
        spec=BearingSpec(
            designation="NSK 25TAC62B",
            bore_mm=25.0, outside_diameter_mm=62.0, width_mm=15.0,
            ball_diameter_mm=7.938, ball_count=14, pitch_diameter_mm=43.5,
            inner_groove_ratio=0.53, outer_groove_ratio=0.53, contact_angle_free_deg=60.0,
            ring_material="GCr15", ball_material="GCr15",
            inner_ring_outer_diameter_mm=37.0, outer_ring_inner_diameter_mm=50.0),
        sources={"inner_ring_outer_diameter_mm": "assume (mean of groove bottom and land)",
                 "outer_ring_inner_diameter_mm": "assume (mean of groove bottom and land)",
                 "bore_mm": "cat (25TAC62: 25x62x15)", "outside_diameter_mm": "cat",
                 "width_mm": "cat", "contact_angle_free_deg": "cat (TAC series: 60 deg)",
                 "ball_diameter_mm": "assume (5/16 in; 0.43 of the 18.5 mm section)",
                 "ball_count": "assume (fill 0.81)", "pitch_diameter_mm": "assume ((d+D)/2)",
                 "inner_groove_ratio": "assume", "outer_groove_ratio": "assume",
                 "ring_material": "assume (bearing steel; seed 003 does not say)",
                 "ball_material": "assume"},
        note="seed 003: ball-screw support pair back-to-back, 1500 N preload, 1000/1500 rpm"),
    "flywheel 7004C (hybrid)": CatalogueEntry(
        spec=BearingSpec(
            designation="flywheel 7004C (hybrid)",
            bore_mm=20.0, outside_diameter_mm=42.0, width_mm=12.0,
            ball_diameter_mm=6.35, ball_count=12, pitch_diameter_mm=31.0,
            inner_groove_ratio=0.52, outer_groove_ratio=0.53, contact_angle_free_deg=15.0,
            ring_material="G95Cr18", ball_material="Si3N4",
            inner_ring_outer_diameter_mm=25.5, outer_ring_inner_diameter_mm=36.5),
        sources={"inner_ring_outer_diameter_mm": "assume (mean of groove bottom and land)",
                 "outer_ring_inner_diameter_mm": "assume (mean of groove bottom and land)",
                 "bore_mm": "assume (seed 001 gives no size: a typical small flywheel "
                            "ACBB, ISO 7004 = 20x42x12)",
                 "outside_diameter_mm": "assume", "width_mm": "assume",
                 "contact_angle_free_deg": "assume (C = 15 deg)",
                 "ball_diameter_mm": "assume (1/4 in; 0.58 of the 11 mm section)",
                 "ball_count": "assume (fill 0.78)", "pitch_diameter_mm": "assume ((d+D)/2)",
                 "inner_groove_ratio": "assume", "outer_groove_ratio": "assume",
                 "ring_material": "seed 001", "ball_material": "seed 001"},
        note="seed 001: flywheel pair face-to-face, position preload 7 N, oil, 3500-9000 rpm"),
}
ALIASES = {"71807C": "NSK 71807C", "25TAC62B": "NSK 25TAC62B", "seed000": "NSK 71807C",
           "seed003": "NSK 25TAC62B", "seed001": "flywheel 7004C (hybrid)",
           "flywheel": "flywheel 7004C (hybrid)"}


def get_entry(name: str) -> CatalogueEntry:
    """Look a bearing up by designation or alias (KeyError lists the known ones)."""
    key = ALIASES.get(name, name)
    if key not in CATALOGUE:
        raise KeyError(f"unknown bearing '{name}' (known: {', '.join(sorted(CATALOGUE))})")
    return CATALOGUE[key]
