"""Element sizes of an assembly's mesh, chosen for a stated discretisation error.

The error measured here is that of the FE quantities that feed the bearing model: the mean fit
pressures (inner and outer fits of both bearings; relative to their Richardson value) and the
groove-centre shifts (per bearing the vector (dr, dz): length of its error over its own length,
since dz alone is near zero at some temperatures). `[mesh] target_error` (default 1e-3 = 0.1 %)
is the largest such error the default sizes aim at; sizes given in `[mesh]` win, the others
follow the rule.

The rule (all lengths in mm):

    L      = min(inner ring section height, outer ring section height, ring width / 4)
             (section heights from the bore, the effective ring diameters and the outside
             diameter: (d_iro - d)/2, (D - d_ori)/2; the width is the fit length)
    f      = F_REF * (target_error / 1e-3) ** (1 / ORDER)
    size   = min(SIZE_PER_L * L * f, ring width)         bulk
    fit    = min(FIT_PER_L * L * f, L)                   along fits and raceways
    corner = min(CORNER_PER_L * L * f**2, fit)           at the ends of fits and clamped faces

One family of meshes: `meshes.section.Section.scaled(k)` is the same rule at f * k (bulk and fit
sizes times k, corner size times k**2), so a three-level check (f, f/2, f/4) extrapolates along
the family the rule picks from.

Why these lengths. The error of the stack is not spread evenly: the ends of the fits and of the
tied (clamped) faces are stress singularities, and without grading there the fit pressures and,
worse, the axial groove shift converge only at order 1 (seed 000, old default sizes 1.0/0.25 mm:
22.3k DOF, dz_A off by 0.5 % of its Richardson value, 0.25 % with 55.8k DOF; halving the bulk
size changed nothing, halving the fit size halved the error). Graded to a small corner size
(`meshes.build.CORNER_GRADE`), the same seed 000 error fell to 0.02 % at 16.7k DOF: the corner
size sets the error, roughly as corner^0.75; fit and bulk sizes far less (305-size stack at
f = 1: corner size / 4 cut the outer-fit pressure error 3x, fit size / 2 by 5 %, bulk size / 2
not at all). Measured orders in the factor k of the family: 1.2..2.1 for the fit pressures
(median about 1.5), hence ORDER = 1.5. The ring section and the fit length are the lengths the
singular fields and the fit live on, so L is the smaller of the thinnest ring section and a
quarter of the fit length; the ball enters the FE only through the effective ring sections, so
it needs no length of its own.

Calibration (GRADE 0.5, Richardson value from the levels f, f/2, f/4 of each assembly; worst
error over the fit pressures and groove-shift vectors at T_min and T_max of `[operating]` with
the mean fits and at T_ref with both fits closed by 5 um; "f for 0.1 %" = f at which that worst
error is 1e-3 along the measured power law):

    assembly (L mm)                    f = 2 (L units)     f = 1             f for 0.1 %
    seed000 71807C in TC4 (1.40)       5.2k DOF 2.1e-3     11.3k 4.6e-4      1.68
    seed001 7004 hybrid (2.75)         3.9k 2.4e-3         9.0k 7.4e-4       1.22
    template 7004 in 6061 (2.75)       4.4k 4.2e-3         9.7k 1.5e-3       0.76
    seed003 25TAC62B (3.75)            (measured at L = 6: 1.4e-3 at f = 1)  1.28
    pair_305_6061 305 in 6061 (4.25)   (measured at L = 4.75: 2.2e-3 at f=1) 0.66

F_REF = 0.55 keeps the worst of them (the 305-size pair in aluminium: the outer fit and the
groove shift of bearing B) below 0.1 % with a factor 1.2 in f to spare.

Check of the rule as built (the chosen mesh against the Richardson value of its x0.5 and x0.25
meshes; largest error of the fit pressures / of the groove-shift vectors; DOF of the chosen mesh):

    target             1e-2               3e-3               1e-3               3e-4
    seed000       4.3k 1.2e-3 2.7e-3  9.8k 3.3e-4 6.7e-4 19.1k 1.4e-4 1.5e-4 37.2k 6.6e-5 9.3e-5
    seed001       2.7k 7.6e-4 4.2e-3  7.8k 1.9e-4 9.7e-4 15.9k 6.9e-5 3.0e-4 31.7k 6.9e-5 3.5e-4
    seed003       3.6k 7.6e-4 4.2e-3  9.1k 2.0e-4 1.1e-3 18.5k 1.0e-4 4.1e-4 35.0k 1.1e-4 3.9e-4
    template      3.4k 5.8e-3 4.5e-3  8.4k 1.8e-3 1.6e-3 16.8k 6.1e-4 5.7e-4 33.4k 2.0e-4 2.1e-4
    pair_305_6061 3.3k 6.5e-3 8.0e-3  8.4k 2.2e-3 2.6e-3 17.1k 7.2e-4 8.8e-4 32.9k 2.3e-4 3.1e-4

(old default sizes 1.0/0.25 mm: seed000 22.3k DOF with dz_A 0.5 % off; the 305-size pair 64.5k.)
Every target from 1e-2 to 1e-3 is met on all five. At 3e-4 the fit pressures are, but groove
shifts shorter than about 1 um (seed001, seed003: 0.4..1.1 um) stop converging at 3..4e-4 of
their length, an absolute 1e-4 um, where the three meshes (not nested: each is meshed anew)
differ by noise rather than by a trend; the pair_305 shift is just above it. Hence the range
TARGET_RANGE = 3e-4..1e-2; the report and `verify --assembly` state the error achieved.

Grooved ring sections (`[mesh] ring_section = "grooved"`, studies/model/stack.py) take the rule at
GROOVED_LEVEL = 0.4 times its level (every size x0.4, the corner size x0.16) and their groove arcs
at half the fit size. At the plain level their groove shifts converge at the same order (1.5..2)
but with a larger constant: pair_305 at f = 1 for 1e-3, 3.9e-3 (dr at 80 C, the outer fits open);
at 1e-2, 2.9e-2 (arc at fit / 2; fit / 10 on the arc only brought it to 1.8e-2: not the chords).
Measured with GROOVED_LEVEL (worst of fit pressures / groove-shift vectors, DOF of the chosen mesh):

    target        seed000            seed001            seed003            template      pair_305
    1e-2          11.7k 3.2e-3       9.5k 4.5e-3        10.9k 1.6e-2 (*)   10.2k 9.6e-3  10.4k 1.0e-2
    1e-3          45.6k 1.6e-4       37.3k 4.8e-4       40.9k 5.5e-4       39.0k 5.2e-4  39.5k 5.8e-4

(*) seed003's groove shifts at 15 C are 0.9 um long: 0.014 um off. So grooved sections cost
2.2-2.4x the DOF of rectangles for the default 0.1 % and meet it on all five (within 0.6x); at the
coarsest target the shorter groove shifts miss it by up to 1.6x.
"""
from __future__ import annotations

from dataclasses import dataclass

from studies.model.config import Assembly
from studies.model.config_schema import MESH_TARGET_RANGE

#: the level f of the rule at target_error = 1e-3 (see the calibration table above)
F_REF = 0.55
#: order of the error in the family factor (measured 1.2..2.1, median 1.5)
ORDER = 1.5
#: sizes per characteristic length at f = 1
SIZE_PER_L, FIT_PER_L, CORNER_PER_L = 3.0, 0.75, 0.05
#: targets the rule was measured over (outside it, give explicit sizes): kept with the other key
#: bounds in config_schema.py (the config checks read it there; one place)
TARGET_RANGE = MESH_TARGET_RANGE
#: the default target: 0.1 %
DEFAULT_TARGET = 1e-3
#: level factor of grooved ring sections (`[mesh] ring_section = "grooved"`; see the docstring)
GROOVED_LEVEL = 0.4


@dataclass(frozen=True)
class MeshSizes:
    """The element sizes of an assembly's mesh (mm) and where they come from."""
    size_mm: float
    fit_size_mm: float
    corner_size_mm: float
    target_error: float | None      # the target the rule sized for; None: every size was given
    length_mm: float                # L of the rule
    level: float                    # f of the rule


def characteristic_length_mm(a: Assembly) -> float:
    """L = min(inner ring section height, outer ring section height, ring width / 4), mm."""
    b = a.bearing
    return min((b.inner_ring_outer_diameter_mm - b.bore_mm) / 2,
               (b.outside_diameter_mm - b.outer_ring_inner_diameter_mm) / 2, b.width_mm / 4)


def level_for_target(target_error: float) -> float:
    """f = F_REF (target / 1e-3)^(1 / ORDER): the rule's level for a relative error."""
    return F_REF * (target_error / DEFAULT_TARGET) ** (1.0 / ORDER)


def mesh_sizes(a: Assembly) -> MeshSizes:
    """The sizes of `a`'s mesh: those given in `[mesh]`, the rest from the rule at its
    target_error (each rule size kept below the given larger ones: corner <= fit <= size)."""
    m = a.mesh
    L = characteristic_length_mm(a)
    f = level_for_target(m.target_error) * (GROOVED_LEVEL if m.ring_section == "grooved" else 1.0)
    size = m.size_mm or min(SIZE_PER_L * L * f, a.bearing.width_mm)
    fit = m.fit_size_mm or min(FIT_PER_L * L * f, L, size)
    corner = m.corner_size_mm or min(CORNER_PER_L * L * f ** 2, fit)
    given = m.size_mm and m.fit_size_mm and m.corner_size_mm
    return MeshSizes(_round(size), _round(fit), _round(corner),
                     None if given else m.target_error, L, f)


def _round(x_mm: float) -> float:
    """4 significant digits: the same sizes (and mesh cache keys) whatever the round-off of L."""
    return float(f"{x_mm:.4g}")
