"""Limit deviations of the seats and the bearing rings (um, from the nominal diameter in mm).

Data carried in the project, with their sources:
- ISO 286-1:2010 Table 1 (standard tolerance grades IT4..IT7) and Tables 2-3 (fundamental
  deviations of shafts f, g, h, j, js, k, m, n, p and holes G, H, JS, K, M, N, P: ES = -ei + Delta
  for K, M, N up to IT8 and P up to IT7, Delta from Table 3, 0 for sizes up to 3 mm; the special
  case M6 over 250 up to 315 mm, ES = -9 um), ISO 286-2:2010 for the irregular J6 and J7 holes.
  Nominal sizes over 0 up to 500 mm ("over ... up to and including").
- ISO 492:2014 Tables 1-10 (radial bearings): the mean bore diameter deviation t_Delta_dmp and
  the mean outside diameter deviation t_Delta_Dmp of tolerance classes Normal, 6, 5, 4 and 2
  (upper deviation 0), d over 2.5 up to 180 mm and D over 6 up to 250 mm (class Normal) or 180 mm.

A class outside these tables is refused (ValueError, one line naming the class and the size).
"""
from __future__ import annotations

import re

import numpy as np

#: upper limits of the nominal size ranges (mm), ISO 286-1 Table 1 (first range: over 0 up to 3)
ISO286_SIZES_MM = (3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
#: standard tolerance grades (um), ISO 286-1:2010 Table 1
IT_UM = {
    4: (3, 4, 4, 5, 6, 7, 8, 10, 12, 14, 16, 18, 20),
    5: (4, 5, 6, 8, 9, 11, 13, 15, 18, 20, 23, 25, 27),
    6: (6, 8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40),
    7: (10, 12, 15, 18, 21, 25, 30, 35, 40, 46, 52, 57, 63),
}
#: upper deviation es (um) of shafts f, g, h (ISO 286-1:2010 Table 2)
SHAFT_ES_UM = {
    "f": (-6, -10, -13, -16, -20, -25, -30, -36, -43, -50, -56, -62, -68),
    "g": (-2, -4, -5, -6, -7, -9, -10, -12, -14, -15, -17, -18, -20),
    "h": (0,) * 13,
}
#: lower deviation ei (um) of the irregular shafts j5, j6 (one row) and j7 (ISO 286-1:2010 Table 2;
#: j4 is not defined)
SHAFT_J_EI_UM = {
    5: (-2, -2, -2, -3, -4, -5, -7, -9, -11, -13, -16, -18, -20),
    6: (-2, -2, -2, -3, -4, -5, -7, -9, -11, -13, -16, -18, -20),
    7: (-4, -4, -5, -6, -8, -10, -12, -15, -18, -21, -26, -28, -32),
}
#: Delta (um) of the holes K, M, N (grades up to 8) and P (up to 7) by grade, ISO 286-1:2010
#: Table 3 (0 up to 3 mm; above, Delta_n = IT_n - IT_(n-1))
DELTA_UM = {
    4: (0, 1.5, 1.5, 2, 2, 3, 3, 4, 4, 4, 4, 5, 5),
    5: (0, 1, 2, 3, 3, 4, 5, 5, 6, 6, 7, 7, 7),
    6: (0, 3, 3, 3, 4, 5, 6, 7, 7, 9, 9, 11, 13),
    7: (0, 4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23),
}
#: lower deviation ei (um) of shafts k (grades 4..7), m, n, p (ISO 286-1:2010 Table 2)
SHAFT_EI_UM = {
    "k": (0, 1, 1, 1, 2, 2, 2, 3, 3, 4, 4, 4, 5),
    "m": (2, 4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23),
    "n": (4, 8, 10, 12, 15, 17, 20, 23, 27, 31, 34, 37, 40),
    "p": (6, 12, 15, 18, 22, 26, 32, 37, 43, 50, 56, 62, 68),
}
#: upper deviation ES (um) of the irregular holes J6, J7 (ISO 286-2:2010 Table 4)
HOLE_J_ES_UM = {
    6: (2, 5, 5, 6, 8, 10, 13, 16, 18, 22, 25, 29, 33),
    7: (4, 6, 8, 10, 12, 14, 18, 22, 26, 30, 36, 39, 43),
}

#: ISO 492:2014, radial bearings: lower mean-diameter deviation (um; upper = 0) by class.
#: Bore d: ranges over 2.5 up to 10, 18, 30, 50, 80, 120, 180 mm.
ISO492_BORE_SIZES_MM = (10, 18, 30, 50, 80, 120, 180)
ISO492_BORE_LOWER_UM = {
    "Normal": (-8, -8, -10, -12, -15, -20, -25),
    "P6": (-7, -7, -8, -10, -12, -15, -18),
    "P5": (-5, -5, -6, -8, -9, -10, -13),
    "P4": (-4, -4, -5, -6, -7, -8, -10),
    "P2": (-2.5, -2.5, -2.5, -2.5, -4, -5, -7),
}
#: Outside diameter D: ranges over 6 up to 18, 30, 50, 80, 120, 150, 180, 250 mm.
ISO492_OD_SIZES_MM = (18, 30, 50, 80, 120, 150, 180, 250)
ISO492_OD_LOWER_UM = {
    "Normal": (-8, -9, -11, -13, -15, -18, -25, -30),
    "P6": (-7, -8, -9, -11, -13, -15, -18, None),
    "P5": (-5, -6, -7, -9, -10, -11, -13, None),
    "P4": (-4, -5, -6, -7, -8, -9, -10, None),
    "P2": (-2.5, -4, -4, -4, -5, -5, -7, None),
}
ISO492_CLASSES = tuple(ISO492_BORE_LOWER_UM)


def _range_index(d_mm: float, upper_limits, lowest: float, what: str) -> int:
    if not lowest < d_mm <= upper_limits[-1]:
        raise ValueError(f"{what}: nominal size {d_mm:g} mm is outside the tables "
                         f"(over {lowest:g} up to {upper_limits[-1]:g} mm)")
    return int(np.searchsorted(np.asarray(upper_limits, float), d_mm, side="left"))


def _parse_iso286(cls: str) -> tuple[str, int]:
    m = re.fullmatch(r"([a-zA-Z]{1,2})(\d)", cls.strip())
    if not m or int(m.group(2)) not in IT_UM:
        raise ValueError(f"'{cls}' is not an ISO 286 class the tables carry (letter(s) and "
                         f"grade {min(IT_UM)}..{max(IT_UM)}, e.g. k5, js6, j6, H6, J6, P7)")
    return m.group(1), int(m.group(2))


def iso286_limits_um(cls: str, d_mm: float) -> tuple[float, float]:
    """(lower, upper) limit deviation in um of an ISO 286 shaft (lower-case letter) or hole
    (upper-case letter) class at nominal diameter d_mm."""
    letters, grade = _parse_iso286(cls)
    i = _range_index(d_mm, ISO286_SIZES_MM, 0.0, f"ISO 286 class {cls}")
    it = float(IT_UM[grade][i])
    if letters == "js" or letters == "JS":
        return -it / 2, it / 2
    if letters.islower():
        if letters == "j" and grade in SHAFT_J_EI_UM:
            ei = float(SHAFT_J_EI_UM[grade][i])
            return ei, ei + it
        if letters in SHAFT_ES_UM:
            es = float(SHAFT_ES_UM[letters][i])
            return es - it, es
        if letters in SHAFT_EI_UM:
            ei = float(SHAFT_EI_UM[letters][i])
            if letters == "k" and grade > 7:
                ei = 0.0
            return ei, ei + it
    else:
        low = letters.lower()
        if letters == "J" and grade in HOLE_J_ES_UM:
            es = float(HOLE_J_ES_UM[grade][i])
            return es - it, es
        if letters in ("G", "H"):
            ei = -float(SHAFT_ES_UM[low][i])          # EI = -es (ISO 286-1 5.3.2)
            return ei, ei + it
        if letters in ("K", "M", "N", "P"):
            # ES = -ei + Delta (ISO 286-1 Table 3: K, M, N up to IT8, P up to IT7; every grade
            # carried here), with the special case M6 over 250 up to 315 mm: ES = -9 um
            if letters == "M" and grade == 6 and ISO286_SIZES_MM[i] == 315:
                es = -9.0
            else:
                es = -float(SHAFT_EI_UM[low][i]) + float(DELTA_UM[grade][i])
            return es - it, es
    raise ValueError(f"ISO 286 class {cls}: letter '{letters}' (grade {grade}) is not in the "
                     "tables carried (shafts f g h j5-7 js k m n p; holes G H JS J6-7 K M N P)")


def iso492_limits_um(cls: str, d_mm: float, surface: str) -> tuple[float, float]:
    """(lower, upper) mean diameter deviation in um of a bearing's bore (surface 'bore') or
    outside diameter ('od') for ISO 492 class Normal, P6, P5, P4 or P2."""
    key = "Normal" if cls in ("Normal", "P0", "0") else cls
    if key not in ISO492_CLASSES:
        raise ValueError(f"'{cls}' is not an ISO 492 class (one of {', '.join(ISO492_CLASSES)})")
    if surface == "bore":
        i = _range_index(d_mm, ISO492_BORE_SIZES_MM, 2.5, f"ISO 492 class {cls} bore")
        lower = ISO492_BORE_LOWER_UM[key][i]
    else:
        i = _range_index(d_mm, ISO492_OD_SIZES_MM, 6.0, f"ISO 492 class {cls} outside diameter")
        lower = ISO492_OD_LOWER_UM[key][i]
        if lower is None:
            raise ValueError(f"ISO 492 class {cls} outside diameter: {d_mm:g} mm is outside the "
                             f"tables (up to {ISO492_OD_SIZES_MM[-2]:g} mm)")
    return float(lower), 0.0
