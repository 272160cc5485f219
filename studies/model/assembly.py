"""The assembly's sections as frozen dataclasses (the data a loaded TOML file becomes): each
field declares its key (unit, allowed values, default: studies/model/config_schema.py). Loading
and the checks across keys: studies/model/config.py and studies/model/config_checks.py, which both
read these classes (this module imports neither)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from analytic.bearing.geometry import BearingSpec
from analytic.lubrication import Lubricant, get_lubricant
from analytic.materials import Material, get_material
from studies.model.provenance import Origin
from studies.model.config_schema import (LAYERS, MATERIAL_T_RANGE_C, MESH_TARGET_RANGE, SIGNED,
                                         ZERO_OK, Range, choice, choice_or_number, limits,
                                         material, number, table as _field_table, text)

_MM = "mm"


@dataclass(frozen=True, kw_only=True)
class Shaft:
    material: str = material()
    seat_diameter_mm: float = number(_MM, note="equals bearing.bore_mm (within 1 %)")
    bore_diameter_mm: float = number(_MM, "0 for a solid shaft", sign=ZERO_OK, default=0.0,
                                     note="below the seat")
    shoulder_diameter_mm: float = number(_MM, note="above the seat, below the outer ring's inner "
                                                   "diameter")
    shoulder_width_mm: float = number(_MM)
    extension_mm: float = number(_MM, "free shaft length beyond the nut", sign=ZERO_OK, default=0.0)


@dataclass(frozen=True, kw_only=True)
class Housing:
    material: str = material()
    bore_diameter_mm: float = number(_MM, note="equals bearing.outside_diameter_mm (within 1 %); "
                                               "with a sleeve or cartridge: the bearing OD + 2 x "
                                               "their radial thicknesses")
    outer_diameter_mm: float = number(_MM, note="above the bore")
    shoulder_diameter_mm: float = number(_MM, "inner diameter of the housing shoulder",
                                         note="below the bore, above the inner ring's outer "
                                              "diameter")
    shoulder_width_mm: float = number(_MM)


@dataclass(frozen=True, kw_only=True)
class Clamp:
    """Nut (on the shaft) or cover (on the housing): a ring clamping the stack end."""
    material: str = material()
    diameter_mm: float = number(_MM, "nut: outer diameter; cover: inner diameter",
                                note="nut: between the shaft seat and the outer ring ID; cover: "
                                     "between the inner ring OD and the housing bore")
    width_mm: float = number(_MM)
    clamp: str = choice("rigid", "compliant", "force", default="rigid",
                        doc='"force": a preloaded clamp (nut or bolted cover) tightened to '
                            'clamp_force_N at T_ref, its face a contact that opens when the '
                            'force is used up, a spring of clamp_stiffness_N_per_um in series; '
                            '"rigid" and "compliant" are its two limits: "rigid" ties the face '
                            'axially (infinitely stiff, never opens: it may pull the stack), '
                            '"compliant" leaves it untied (no force, no stiffness)')
    clamp_force_N: float = number("N", "the clamp force at T_ref, at rest (clamp = \"force\")",
                                  sign=ZERO_OK, default=0.0,
                                  note='> 0 with clamp = "force", which needs frictionless fits')
    clamp_stiffness_N_per_um: float = number(
        "N/um", "the clamp's own spring (thread or bolts) in series with the clamped face "
        '(clamp = "force")', sign=ZERO_OK, default=0.0,
        default_text="0 = from the part's section (VDI 2230 engaged thread and nut)")


@dataclass(frozen=True, kw_only=True)
class Spacer:
    material: str = material()
    diameter_mm: float = number(_MM, "inner spacer: outer diameter; outer spacer: inner diameter",
                                note="inner: between the shaft seat and the inner ring OD; outer: "
                                     "between the outer ring ID and the housing bore")
    length_mm: float = number(_MM)


@dataclass(frozen=True, kw_only=True)
class Layer:
    """A sleeve or a cartridge (optional `[sleeve]`, `[cartridge]`): a plain cylinder between the
    outer rings and the housing (the sleeve inside, the cartridge outside when both are given),
    as long as the outer-ring stack, resting on the housing shoulder and clamped by the cover,
    at the housing temperature. Its fit on the outside: `[fits] sleeve_interference_um` /
    `cartridge_interference_um`; the outer rings' fit (`outer_interference_um`) is then in the
    sleeve (or cartridge)."""
    material: str = material()
    radial_thickness_mm: float = number(_MM, note="housing.bore_diameter_mm must be the bearing "
                                                  "OD + 2 x (sleeve + cartridge thickness)")
    length_mm: float = number(_MM, note="= 2 x bearing.width_mm + outer_spacer.length_mm")


_FIT = "diametral; + interference, - clearance"
_PER_MILLE = "|x| <= 2 per mille of the diameter"


@dataclass(frozen=True, kw_only=True)
class Fits:
    inner_interference_um: float = number("um", f"{_FIT}: inner rings on the shaft", sign=SIGNED,
                                          note=_PER_MILLE)
    outer_interference_um: float = number("um", f"{_FIT}: outer rings in the housing (or the "
                                                "sleeve)", sign=SIGNED, note=_PER_MILLE)
    contact: str = choice("frictionless", "bonded", default="frictionless",
                          doc='"bonded": tied, tension allowed')
    sleeve_interference_um: float = number("um", f"{_FIT}: the sleeve in the next layer out (or "
                                                 "the housing)", sign=SIGNED, default=0.0,
                                           note=f"only with a [sleeve]; {_PER_MILLE}")
    cartridge_interference_um: float = number("um", f"{_FIT}: the cartridge in the housing",
                                              sign=SIGNED, default=0.0,
                                              note=f"only with a [cartridge]; {_PER_MILLE}")
    # tolerances (docs/cli.md "tolerance"): an ISO class or explicit (lower, upper) limit
    # deviations in um per surface; "" / () = none. Deviations add to the nominal interference.
    inner_shaft_class: str = text('ISO 286 shaft class: f g h js k m n p, grade 4..7 (e.g. '
                                  '"k5"); "" = none', default="",
                                  note="the class or inner_shaft_deviation_um, not both")
    inner_ring_bore_class: str = text('ISO 492 class: Normal, P6, P5, P4, P2; "" = none',
                                      default="", note="the class or inner_ring_bore_deviation_um, "
                                                       "not both")
    outer_housing_class: str = text('ISO 286 hole class: G H JS J K M N, grade 4..7 (e.g. "J6"); '
                                    '"" = none', default="",
                                    note="the class or outer_housing_deviation_um, not both")
    outer_ring_od_class: str = text('ISO 492 class; "" = none', default="",
                                    note="the class or outer_ring_od_deviation_um, not both")
    inner_shaft_deviation_um: tuple = limits("limit deviations of the shaft seat")
    inner_ring_bore_deviation_um: tuple = limits("limit deviations of the inner ring bore")
    outer_housing_deviation_um: tuple = limits("limit deviations of the housing bore")
    outer_ring_od_deviation_um: tuple = limits("limit deviations of the outer ring OD")
    # the sleeve's and cartridge's fits (docs/cli.md "Sleeve and cartridge"): the layer's outside
    # diameter (`<layer>_shaft`, the inside member of its fit) and the bore it sits in
    # (`<layer>_bore`: the cartridge's or the housing's); ISO 286 classes at the fit's diameter
    sleeve_shaft_class: str = text('ISO 286 shaft class of the sleeve OD; "" = none', default="",
                                   note="only with a [sleeve]; the class or "
                                        "sleeve_shaft_deviation_um, not both")
    sleeve_bore_class: str = text('ISO 286 hole class of the bore the sleeve sits in; "" = none',
                                  default="", note="only with a [sleeve]; the class or "
                                                   "sleeve_bore_deviation_um, not both")
    cartridge_shaft_class: str = text('ISO 286 shaft class of the cartridge OD; "" = none',
                                      default="", note="only with a [cartridge]; the class or "
                                                       "cartridge_shaft_deviation_um, not both")
    cartridge_bore_class: str = text('ISO 286 hole class of the housing bore the cartridge sits '
                                     'in; "" = none', default="",
                                     note="only with a [cartridge]; the class or "
                                          "cartridge_bore_deviation_um, not both")
    sleeve_shaft_deviation_um: tuple = limits("limit deviations of the sleeve OD",
                                              note="only with a [sleeve]")
    sleeve_bore_deviation_um: tuple = limits("limit deviations of the bore the sleeve sits in",
                                             note="only with a [sleeve]")
    cartridge_shaft_deviation_um: tuple = limits("limit deviations of the cartridge OD",
                                                 note="only with a [cartridge]")
    cartridge_bore_deviation_um: tuple = limits("limit deviations of the housing bore the "
                                                "cartridge sits in", note="only with a [cartridge]")
    distribution: str = choice("uniform", "normal", default="uniform",
                               doc='of a deviation: "uniform" within the limits or "normal" '
                                   '(limits at +-3 sigma)')


@dataclass(frozen=True, kw_only=True)
class Preload:
    kind: str = choice("position", "spring", doc='"position": rigid offset set at assembly')
    assembled_N: float = number("N", "set at T_ref_C", sign=ZERO_OK,
                                note="at most the static load rating C0 (ISO 76)")
    path_compliance: str = choice("fe", "rigid", default="fe",
                                  doc='"fe": the axial compliance of spacers, nut and housing from '
                                      'the FE in series with the bearings; "rigid": none')


@dataclass(frozen=True, kw_only=True)
class Lubrication:
    kind: str = choice("solid_film", "oil")
    lubricant: str = text("oil: a library oil (analytic/lubrication.py) or one of the file's "
                               "[lubricants.NAME]", default="")
    friction_coefficient: float = number("-", "oil: Coulomb load term mu F dm/2; solid film: mu "
                                              "of the film", sign=ZERO_OK, default=0.0,
                                         bounds=Range(hi=1.0, error="must not exceed 1"))
    viscous_factor_f0: float = number("-", "Palmgren f0 (oil)", sign=ZERO_OK, default=0.0)
    speed_rpm: float = number("rpm", "the default speed when the conditions give none",
                              sign=ZERO_OK, default=0.0)
    hysteresis_loss_factor: float = number("-", "solid film: elastic hysteresis loss factor "
                                                "alpha_h", sign=ZERO_OK, default=0.0)
    load_term: str = choice("coulomb", "palmgren", default="coulomb",
                            doc='oil: "coulomb" (mu F dm/2) or "palmgren" (f1 F dm)')
    viscous_model: str = choice(
        "palmgren", "skf2004", "ehl_rolling", "starved", "minimal_oil", default="palmgren",
        doc='oil: "palmgren" (f0 (nu n)^(2/3) dm^3), "skf2004" (SKF four-component model: '
            'rolling, sliding, drag; replaces the load term too), "ehl_rolling" (EHL rolling '
            'resistance per contact on the ball loads), "starved" (Palmgren weakened by the '
            'oil quantity), "minimal_oil" (Palmgren weakened by the oil quantity spread over the '
            'wetted surfaces: follows the oil from a few mg to flooded); analytic/friction/')
    oil_quantity_mg: float = number("mg", 'oil: the oil in one bearing (viscous_model = '
                                          '"starved" or "minimal_oil")', sign=ZERO_OK, default=0.0,
                                    default_text="0 = flooded (Palmgren)")
    lubrication_method: str = choice(
        "", "oil_bath", "oil_jet", "oil_air", "grease", "minimal_oil", default="",
        default_text='"" = not stated (skf2004: the oil-jet / oil-bath K_rs)',
        doc='oil: how the oil reaches the bearing; skf2004: its replenishment constant K_rs '
            '(3e-8 oil bath and jet, 6e-8 oil-air, grease and minimal oil)')
    oil_level_mm: float = number("mm", 'oil: an oil bath\'s level above the lowest point of the '
                                       'outer raceway (skf2004: its drag term)', sign=ZERO_OK,
                                 default=0.0, default_text="0 = no bath",
                                 note='only with lubrication_method = "oil_bath" and viscous_model '
                                      '= "skf2004"')
    shear_strength: str = choice("constant", "pressure", default="constant",
                                 doc='solid film: "constant" (friction_coefficient) or '
                                     '"pressure" (tau = tau0 + alpha p over the Hertz ellipse)')
    tau0_MPa: float = number("MPa", 'solid film: interfacial shear strength at zero pressure '
                                    '(shear_strength = "pressure")', sign=ZERO_OK, default=0.0)
    alpha_shear: float = number("-", 'solid film: pressure coefficient of the shear strength '
                                     '(shear_strength = "pressure")', sign=ZERO_OK, default=0.0,
                                bounds=Range(hi=1.0, error="must not exceed 1"))
    # thermal speed limits (analytic/thermal_speed.py; ISO 15312:2018, DIN 732:2010)
    reference_f0r: float = number("-", "ISO 15312 oil-bath f0r of the bearing type; 0: 2.0, "
                                       "Palmgren's oil-bath f0 of a ball bearing (warned): set "
                                       "the maker's", sign=ZERO_OK, default=0.0,
                                  default_text="0 = 2.0 (warned)")
    reference_f1r: float = number("-", "ISO 15312 f1r; 0: Palmgren's angular-contact f1 at "
                                       "P1r = 0.05 C0", sign=ZERO_OK, default=0.0,
                                  default_text="0 = 0.001 (0.05)^0.33")
    heat_transfer_W_per_mm2_K: float = number(
        "W/(mm^2 K)", "DIN 732 k_q of the seat surface pi B (D + d); 0: q_r / 50 K of the "
                      "ISO 15312 reference (3.2e-4 up to 50 000 mm^2; warned)",
        sign=ZERO_OK, default=0.0, default_text="0 = q_r / 50 K (warned)")
    permissible_temperature_C: float = number("C", "DIN 732: the bearing temperature allowed "
                                                   "(70: the ISO 15312 reference)", sign=SIGNED,
                                              default=70.0)
    ambient_temperature_C: float = number("C", "DIN 732: where the bearing's heat goes (20: the "
                                               "ISO 15312 reference)", sign=SIGNED, default=20.0)


@dataclass(frozen=True, kw_only=True)
class Limits:
    max_contact_pressure_MPa: float = number("MPa", "the per-row check of simulate",
                                             infinite_ok=True, default=math.inf,
                                             default_text="none: the ISO 76 static limit, "
                                                          "4200 MPa")
    min_static_safety: float = number("-", "the per-row check of simulate", sign=ZERO_OK,
                                      default=0.0, default_text="0 = 3 (GB/T 28878.2 B.4)")


@dataclass(frozen=True, kw_only=True)
class Operating:
    """The temperature range the assembly must work over (the default conditions of `report`)."""
    T_min_C: float = number("C", "coldest operating temperature", sign=SIGNED, default=-40.0,
                            bounds=Range(*MATERIAL_T_RANGE_C), note="below T_max_C")
    T_max_C: float = number("C", "hottest operating temperature", sign=SIGNED, default=80.0,
                            bounds=Range(*MATERIAL_T_RANGE_C), note="above T_min_C")
    speed_max_rpm: float = number("rpm", "highest shaft speed (report: fit loosening, speed "
                                         "effects)", sign=ZERO_OK, default=0.0,
                                  default_text="0 = [lubrication] speed_rpm")
    ball_model: str = choice("static", "quasi_dynamic", default="static",
                             doc='"static": quasi-static balls; "quasi_dynamic": each ball in its '
                                 'own equilibrium at the row\'s speed (centrifugal force, '
                                 'gyroscopic moment; analytic/bearing/dynamic.py)')
    raceway_control: str = choice("outer", "inner", "jones", default="outer",
                                  doc='quasi_dynamic: raceway control, "jones" per ball (Jones\'s '
                                      'criterion)')

    def max_speed_rpm(self, lubrication_speed_rpm: float) -> float:
        """The highest speed the assembly runs at (rpm): speed_max_rpm, else the given speed."""
        return self.speed_max_rpm if self.speed_max_rpm > 0 else float(lubrication_speed_rpm)


@dataclass(frozen=True, kw_only=True)
class Mesh:
    """Element sizes in mm; 0 = chosen for `target_error` by studies/model/mesh_size.py (given
    sizes win, the others follow the rule)."""
    size_mm: float = number(_MM, "bulk element size", sign=ZERO_OK, default=0.0,
                            default_text="0 = from the target", note="at most the bearing width")
    fit_size_mm: float = number(_MM, "size along fits and raceways", sign=ZERO_OK, default=0.0,
                                default_text="0 = from the target", note="at most size_mm")
    corner_size_mm: float = number(_MM, "size where fits and clamped faces end", sign=ZERO_OK,
                                   default=0.0, default_text="0 = from the target",
                                   note="at most fit_size_mm")
    target_error: float = number("-", "relative discretisation error of fit pressures and "
                                      "groove-centre shifts the sizes left at 0 are chosen for",
                                 default=1e-3, bounds=Range(*MESH_TARGET_RANGE),
                                 note="the range the size rule was measured over "
                                      "(studies/model/mesh_size.py)")
    ring_section: str = choice("grooved", "rectangle", default="rectangle",
                               doc='"rectangle": the effective ring sections of [bearing]; '
                                   '"grooved": rings with their raceway grooves and lands '
                                   '(studies/model/stack.py)')


@dataclass(frozen=True, kw_only=True)
class Thermal:
    """How the part temperatures of a row are found: given by the conditions, or computed by the
    transient conduction FE of the stack (studies/model/transient_route.py)."""
    mode: str = choice("given", "transient", default="given",
                       doc='"given": part temperatures from the conditions; "transient": computed '
                           'by the transient conduction FE from time_s and the environment')
    films: tuple = _field_table("W/m2K", "transient: film coefficient per face group "
                                "([thermal.films]; a name may be a pattern such as raceway_*, an "
                                "exact name wins; docs/cli.md lists the groups)",
                                default=(), default_text="none: adiabatic")
    sink_C: float = number("C", "transient: radiation sink when the conditions give no "
                                "T_sink_C", sign=SIGNED, infinite_ok=True, default=math.inf,
                           default_text="none: the environment (T_ambient_C)")
    emissivity: float = number("-", "transient: of every exterior face but the raceways "
                                    "(radiation to the sink)", sign=ZERO_OK, default=0.0,
                               bounds=Range(hi=1.0, error="must lie in 0..1, got {v:g}"))
    gas: str = choice("air", "vacuum", default="air",
                      doc='transient: the gas in the gaps of fits and spacer bores: "air" (gas '
                          'conduction across them) or "vacuum" (none: an open fit conducts nothing)')
    fit_conductance: object = choice_or_number(
        "pressure", unit="W/m2K", default="pressure",
        doc='transient: thermal contact conductance of every fit; "pressure": from the fit '
            'pressure each step (Yovanovich; an open fit: gas gap)')

    def films_W_m2K(self) -> dict[str, float]:
        return dict(self.films)


@dataclass(frozen=True)
class Assembly:
    name: str
    arrangement: str                 # "DB" or "DF"
    T_ref_C: float
    shaft: Shaft
    housing: Housing
    nut: Clamp
    cover: Clamp
    inner_spacer: Spacer
    outer_spacer: Spacer
    bearing: BearingSpec
    fits: Fits
    preload: Preload
    lubrication: Lubrication
    limits: Limits = field(default_factory=Limits)
    mesh: Mesh = field(default_factory=Mesh)
    operating: Operating = field(default_factory=Operating)
    thermal: Thermal = field(default_factory=Thermal)
    source: str = ""
    sleeve: Layer | None = None
    cartridge: Layer | None = None
    materials: tuple[Material, ...] = ()   # the config's own [materials.NAME] tables
    lubricants: tuple[Lubricant, ...] = ()  # the config's own [lubricants.NAME] tables
    #: the file it was read from (`studies.model.provenance.Origin`; None when built in memory);
    #: not part of its value: equal stacks are equal whatever file they came from
    origin: Origin | None = field(default=None, compare=False, repr=False)

    def oil(self) -> Lubricant | None:
        """The oil of `[lubrication] lubricant` (the file's own table first, then the library);
        None for a solid film."""
        if self.lubrication.kind != "oil":
            return None
        return get_lubricant(self.lubrication.lubricant, self.lubricants)

    def layers(self) -> list[tuple[str, Layer]]:
        """The sleeve and cartridge present, from the inside out: (name, layer)."""
        return [(n, getattr(self, n)) for n in LAYERS if getattr(self, n) is not None]

    @property
    def outer_seat_diameter_mm(self) -> float:
        """Diameter of the outer rings' fit (mm): the housing bore, or with a sleeve or a
        cartridge the bearing outside diameter (their bore)."""
        return self.bearing.outside_diameter_mm if self.layers() else self.housing.bore_diameter_mm

    def fit_diameter_mm(self, fit: str) -> float:
        """Nominal diameter (mm) of a fit: inner (the shaft seat), outer (`outer_seat_diameter_mm`),
        sleeve / cartridge (the layer's outside: the bearing OD plus twice the thickness of it and
        of the layers inside it)."""
        if fit == "inner":
            return self.shaft.seat_diameter_mm
        if fit == "outer":
            return self.outer_seat_diameter_mm
        d = self.bearing.outside_diameter_mm
        for name, layer in self.layers():
            d += 2 * layer.radial_thickness_mm
            if name == fit:
                return d
        raise ValueError(f"the assembly has no {fit} fit")

    def mean_fit_um(self, fit: str) -> float:
        """Diametral interference (um) of one fit (inner, outer, sleeve, cartridge) of the mean
        assembly: its [fits] value plus, where tolerances are given, every deviation at the
        middle of its band (`mean_fits_um` for the inner and outer fits)."""
        from studies.model.tolerances import mid_band_fit_offsets_um

        return getattr(self.fits, f"{fit}_interference_um") + mid_band_fit_offsets_um(self)[fit]

    def mean_fits_um(self) -> tuple[float, float]:
        """Diametral interference (inner, outer) in um of the mean assembly: the [fits] values
        plus, where tolerances are given, every deviation at the middle of its band. This is
        the fit `simulate`, `report` and the studies use (studies/model/tolerances.py)."""
        from studies.model.tolerances import mid_band_offsets_um

        mid_i, mid_o = mid_band_offsets_um(self)
        return self.fits.inner_interference_um + mid_i, self.fits.outer_interference_um + mid_o

    def material_keys(self) -> dict[str, tuple[str, str]]:
        """Per part (shaft, housing, nut, cover, inner_spacer, outer_spacer, inner_ring,
        outer_ring, ball, the sleeve / cartridge present): the file's key naming its material and
        the name given there."""
        parts = {"shaft": self.shaft, "housing": self.housing, "nut": self.nut,
                 "cover": self.cover, "inner_spacer": self.inner_spacer,
                 "outer_spacer": self.outer_spacer, **dict(self.layers())}
        return {**{p: (f"{p}.material", t.material) for p, t in parts.items()},
                "inner_ring": ("bearing.ring_material", self.bearing.ring_material),
                "outer_ring": ("bearing.ring_material", self.bearing.ring_material),
                "ball": ("bearing.ball_material", self.bearing.ball_material)}

    def material(self, part: str) -> Material:
        """Material of a part (`material_keys`' parts)."""
        return get_material(self.material_keys()[part][1], self.materials)
