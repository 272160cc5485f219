"""The relations between the keys of an assembly file, checked on the parsed assembly: parts that
overlap or do not touch their seats, impossible bearing geometry, implausible sizes (a typo), the
tolerance classes, grooved ring sections and the mesh sizes. One key's own unit, sign, bounds and
allowed values are the schema's (studies/model/config_schema.py). Each problem is a ConfigError
of one line naming the file and the key."""
from __future__ import annotations

import math

from analytic.bearing.geometry import BearingGeometry, BearingSpec
from analytic.bearing.land import groove_bottom_diameter_mm
from analytic.materials import Material, get_material
from analytic.safety import static_load_rating_C0_N
from studies.model.assembly import Assembly, Lubrication
from studies.model.config_schema import (LAYERS, MATERIAL_T_RANGE_C, MESH_TARGET_RANGE,
                                         TOLERANCE_SURFACES, ConfigError)



def check_assembly(a: Assembly, path: str) -> None:
    """Every relation between keys of an assembly; ConfigError (one line) on the first problem."""
    _check_materials(a, path)
    _check_units(a, path)
    _check_geometry(a, path)
    _check_tolerances(a, path)
    _check_clamps(a, path)
    check_friction(a.lubrication, path)
    if a.lubrication.kind == "oil":      # an oil needs its data: a Walther law (>= 2 points)
        try:
            a.oil().walther()
        except (KeyError, ValueError) as exc:
            raise ConfigError(f"{path}: lubrication.lubricant: {exc.args[0]}") from None


#: below all three at once a [bearing] is no angular-contact ball bearing of any catalogue but a
#: catalogue bearing typed in inches (each length 25.4x too small, the proportions right). An
#: assumption of this project, set about a factor 2 below the smallest miniature angular-contact
#: bearings (balls of about 1 mm, rings of about 2-3 mm width, outside diameters from about
#: 5 mm up); a 25.4x too small catalogue bearing (ISO 15 bores from 10 mm: a 7000 series ring
#: 26 mm x 8 mm with 4.8 mm balls becomes 1.02 mm x 0.31 mm with 0.19 mm balls) falls far below.
INCH_SUSPECT_MM = {"ball_diameter_mm": 0.5, "width_mm": 1.5, "outside_diameter_mm": 25.4}


def _check_clamps(a: Assembly, path: str) -> None:
    """A clamp with a force (clamp = "force") needs the force, frictionless fits (its face is a
    contact like theirs; bonded fits tie every interface) and given part temperatures (the
    transient route keeps the faces tied); its force and stiffness keys mean nothing otherwise."""
    for name in ("nut", "cover"):
        c = getattr(a, name)
        if c.clamp == "force":
            if not c.clamp_force_N > 0:
                raise ConfigError(f'{path}: {name}.clamp_force_N: clamp = "force" needs the '
                                  "clamp force (N, > 0)")
            if a.fits.contact != "frictionless":
                raise ConfigError(f'{path}: {name}.clamp: "force" needs fits.contact = '
                                  f'"frictionless", got "{a.fits.contact}"')
            if a.thermal.mode != "given":
                raise ConfigError(f'{path}: {name}.clamp: "force" is not available with '
                                  'thermal.mode = "transient" (use "rigid" or "compliant")')
        elif c.clamp_force_N > 0 or c.clamp_stiffness_N_per_um > 0:
            key = "clamp_force_N" if c.clamp_force_N > 0 else "clamp_stiffness_N_per_um"
            raise ConfigError(f'{path}: {name}.{key}: only used with clamp = "force", '
                              f'got clamp = "{c.clamp}"')


#: the largest plausible interfacial shear strength of a solid film at zero pressure, MPa: the
#: shear strength of the film cannot exceed its substrate's (a bearing steel's shear yield is
#: about 1000 MPa); MoS2 is 20-25 MPa (Singer et al. 1990, analytic/friction/solid_film.py)
TAU0_MAX_MPA = 1000.0


def check_friction(lub, path: str) -> None:
    """The friction model's keys (analytic/friction/) belong to one kind of lubrication each:
    viscous_model and oil_quantity_mg to an oil, shear_strength and its tau0_MPa, alpha_shear to
    a solid film; oil_quantity_mg only with viscous_model = "starved" or "minimal_oil" (which
    needs it), tau0_MPa and alpha_shear only with shear_strength = "pressure", which needs one
    of them > 0; lubrication_method to an oil, oil_level_mm to an oil bath with viscous_model =
    "skf2004" (the law that has a drag term); tau0_MPa at most TAU0_MAX_MPA (a value in Pa
    caught). lub: an assembly's or a bearing file's `Lubrication`."""
    def bad(key: str, msg: str):
        raise ConfigError(f"{path}: lubrication.{key}: {msg}")
    if lub.kind == "solid_film" and lub.viscous_model != "palmgren":
        bad("viscous_model", f'"{lub.viscous_model}" is an oil model, got kind = "solid_film"')
    if lub.kind == "oil" and lub.shear_strength != "constant":
        bad("shear_strength", f'"{lub.shear_strength}" is a solid-film law, got kind = "oil"')
    if lub.oil_quantity_mg > 0 and lub.viscous_model not in ("starved", "minimal_oil"):
        bad("oil_quantity_mg", f'only used with viscous_model = "starved" or "minimal_oil", got '
                               f'"{lub.viscous_model}"')
    if lub.viscous_model == "minimal_oil" and not lub.oil_quantity_mg > 0:
        bad("viscous_model", '"minimal_oil" needs oil_quantity_mg > 0 (the oil in one bearing)')
    for key in ("tau0_MPa", "alpha_shear"):
        if getattr(lub, key) > 0 and lub.shear_strength != "pressure":
            bad(key, f'only used with shear_strength = "pressure", got "{lub.shear_strength}"')
    if lub.kind == "solid_film" and lub.lubrication_method:
        bad("lubrication_method", f'"{lub.lubrication_method}" says how an oil reaches the '
                                  'bearing, got kind = "solid_film"')
    if lub.oil_level_mm > 0 and lub.lubrication_method != "oil_bath":
        bad("oil_level_mm", 'an oil bath\'s level: only used with lubrication_method = '
                            f'"oil_bath", got "{lub.lubrication_method}"')
    if lub.oil_level_mm > 0 and lub.viscous_model != "skf2004":
        bad("oil_level_mm", 'only used with viscous_model = "skf2004" (its drag term; '
                            f"Palmgren's f0 already carries the bath), got \"{lub.viscous_model}\"")
    if lub.tau0_MPa > TAU0_MAX_MPA:
        bad("tau0_MPa", f"{lub.tau0_MPa:g} MPa is above any solid film's shear strength "
                        f"(MoS2 about 20-25 MPa; limit {TAU0_MAX_MPA:g} MPa): typed in Pa? "
                        f"({lub.tau0_MPa:g} Pa = {lub.tau0_MPa * 1e-6:g} MPa)")
    if lub.shear_strength == "pressure" and not (lub.tau0_MPa > 0 or lub.alpha_shear > 0):
        bad("shear_strength", '"pressure" needs tau0_MPa or alpha_shear > 0 (tau = tau0 + '
                              "alpha p)")


def check_friction_keys_used(lub, path: str) -> None:
    """A friction key typed in a file that the file's own law does not use is refused (one
    line naming the file and the key), as `check_friction` refuses the friction model's own
    keys: a key is judged by its value (a default value is no key given). Checked where a file
    is read (an assembly, a bearing file), not on the variants a command makes of a loaded
    assembly (`report --sensitivity`, `design --vary`: a law swapped in keeps the other law's
    numbers). Not used (docs/cli.md "Friction models and the heat by location"):
    viscous_model "starved" without oil_quantity_mg (the flooded limit, Palmgren's law);
    friction_coefficient with viscous_model "skf2004" (SKF's sliding term G_sl mu_sl replaces
    the load term), with load_term "palmgren" (f1 F dm) or with shear_strength "pressure"
    (tau0 / p_mean + alpha per contact); hysteresis_loss_factor with an oil (a solid film's
    elastic hysteresis); viscous_factor_f0, load_term "palmgren", heat_transfer_W_per_mm2_K,
    permissible_temperature_C and ambient_temperature_C with a solid film (Palmgren's oil
    terms and DIN 732's permissible speed, an oil bearing's)."""
    def bad(key: str, msg: str):
        raise ConfigError(f"{path}: lubrication.{key}: {msg}")
    if lub.friction_coefficient > 0 and lub.kind == "oil":
        if lub.viscous_model == "skf2004":
            bad("friction_coefficient", 'not used with viscous_model = "skf2004" (its sliding '
                                        "term G_sl mu_sl replaces the load term): remove it")
        if lub.load_term == "palmgren":
            bad("friction_coefficient", 'not used with load_term = "palmgren" (f1 F dm): '
                                        "remove it")
    if lub.friction_coefficient > 0 and lub.shear_strength == "pressure":
        bad("friction_coefficient", 'not used with shear_strength = "pressure" (each '
                                    "contact's tau0 / p_mean + alpha): remove it")
    if lub.viscous_model == "starved" and not lub.oil_quantity_mg > 0:
        bad("viscous_model", '"starved" without oil_quantity_mg is Palmgren\'s flooded law: '
                             "give the oil in one bearing (oil_quantity_mg > 0)")
    if lub.kind == "oil" and lub.hysteresis_loss_factor > 0:
        bad("hysteresis_loss_factor", 'a solid film\'s elastic hysteresis, not used with '
                                      'kind = "oil"')
    if lub.kind == "solid_film":
        default = Lubrication(kind="solid_film")
        for key, used in (("viscous_factor_f0", lub.viscous_factor_f0 == 0),
                          ("load_term", lub.load_term == default.load_term),
                          ("heat_transfer_W_per_mm2_K", lub.heat_transfer_W_per_mm2_K == 0),
                          ("permissible_temperature_C",
                           lub.permissible_temperature_C == default.permissible_temperature_C),
                          ("ambient_temperature_C",
                           lub.ambient_temperature_C == default.ambient_temperature_C)):
            if not used:
                bad(key, 'an oil bearing\'s (Palmgren\'s terms, DIN 732), not used with '
                         'kind = "solid_film"')


def _check_units(a: Assembly, path: str) -> None:
    """The whole assembly typed in inches: ball, ring width and outside diameter all
    below `INCH_SUSPECT_MM` -> one line naming inches, before any other geometry check (which
    would otherwise name a consequence: a fit beyond 2 per mille, a preload above C0)."""
    b = a.bearing
    if all(getattr(b, k) < v for k, v in INCH_SUSPECT_MM.items()):
        raise ConfigError(
            f"{path}: bearing.ball_diameter_mm: the assembly looks typed in inches, not mm (ball "
            f"{b.ball_diameter_mm:g} mm, ring width {b.width_mm:g} mm, outside diameter "
            f"{b.outside_diameter_mm:g} mm: below any catalogue angular-contact bearing; "
            f"x 25.4 = {25.4 * b.ball_diameter_mm:.4g}, {25.4 * b.width_mm:.4g}, "
            f"{25.4 * b.outside_diameter_mm:.4g} mm): give every length in mm and fits in um")


def _check_tolerances(a: Assembly, path: str) -> None:
    """A class or explicit limits per surface, not both, and a class the tables carry at the
    surface's nominal diameter (analytic/tolerances.py)."""
    from studies.model.tolerances import deviation_limits_um

    f = a.fits
    for k in TOLERANCE_SURFACES:
        if getattr(f, f"{k}_class") and getattr(f, f"{k}_deviation_um"):
            raise ConfigError(f"{path}: fits.{k}_class: give the class or {k}_deviation_um, not both")
    try:
        deviation_limits_um(a)
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc.args[0]}") from None


def _check_materials(a: Assembly, path: str) -> None:
    keys = dict(a.material_keys().values())
    for key, name in keys.items():
        try:
            get_material(name, a.materials)
        except KeyError as exc:
            raise ConfigError(f"{path}: {key}: {exc.args[0]}") from None


def check_bearing(b: BearingSpec, materials: tuple[Material, ...], path: str) -> BearingGeometry:
    """The checks of a [bearing] table on its own (an assembly's or a single bearing's file)
    beyond its keys' bounds (groove ratios, contact angle: the schema's): land diameters, ring
    width, pitch diameter and ball count.
    Returns the resolved `BearingGeometry`; ConfigError (one line naming file and key)."""
    def need(cond: bool, key: str, msg: str) -> None:
        if not cond:
            raise ConfigError(f"{path}: {key}: {msg}")

    g = BearingGeometry.from_spec(b, materials)
    for side, d in (("inner", b.inner_land_diameter_mm), ("outer", b.outer_land_diameter_mm)):
        if d > 0:        # given: the groove edge lies between the groove bottom and the pitch circle
            bottom = groove_bottom_diameter_mm(g, side)
            lo, hi = sorted((bottom, b.pitch_diameter_mm))
            need(lo < d < hi, f"bearing.{side}_land_diameter_mm",
                 f"{d:g} mm must lie between the groove bottom ({bottom:.3f} mm) and the pitch "
                 f"diameter ({b.pitch_diameter_mm:g} mm)")
    need(b.width_mm >= b.ball_diameter_mm, "bearing.width_mm",
         f"ring width {b.width_mm:g} mm is narrower than its ball ({b.ball_diameter_mm:g} mm)")
    Dw, dm = b.ball_diameter_mm, b.pitch_diameter_mm
    need(b.bore_mm < dm - Dw and dm + Dw < b.outside_diameter_mm, "bearing.pitch_diameter_mm",
         "balls do not fit between bore and outside diameter")
    need(b.ball_count * Dw < math.pi * dm, "bearing.ball_count", "balls overlap on the pitch circle")
    return g


def _check_geometry(a: Assembly, path: str) -> None:
    """Overlaps, rings that do not touch their seats, and impossible bearing geometry."""
    s, h, b = a.shaft, a.housing, a.bearing

    def need(cond: bool, key: str, msg: str) -> None:
        if not cond:
            raise ConfigError(f"{path}: {key}: {msg}")

    need(s.bore_diameter_mm < s.seat_diameter_mm, "shaft.bore_diameter_mm",
         f"bore {s.bore_diameter_mm:g} mm must be smaller than the seat {s.seat_diameter_mm:g} mm")
    need(s.shoulder_diameter_mm > s.seat_diameter_mm, "shaft.shoulder_diameter_mm",
         "must exceed the seat diameter")
    need(abs(b.bore_mm - s.seat_diameter_mm) <= 0.01 * b.bore_mm, "bearing.bore_mm",
         f"inner ring bore {b.bore_mm:g} mm does not sit on the shaft seat {s.seat_diameter_mm:g} mm")
    t_layers = sum(layer.radial_thickness_mm for _, layer in a.layers())
    if not t_layers:
        need(abs(b.outside_diameter_mm - h.bore_diameter_mm) <= 0.01 * b.outside_diameter_mm,
             "bearing.outside_diameter_mm",
             f"outer ring {b.outside_diameter_mm:g} mm does not sit in the housing bore {h.bore_diameter_mm:g} mm")
    else:
        _check_layers(a, need, t_layers)
    seat = a.outer_seat_diameter_mm             # where the outer rings sit
    need(b.bore_mm < b.inner_ring_outer_diameter_mm < b.outer_ring_inner_diameter_mm
         < b.outside_diameter_mm, "bearing.inner_ring_outer_diameter_mm",
         "ring sections must satisfy bore < inner ring OD < outer ring ID < outside diameter")
    need(s.shoulder_diameter_mm < b.outer_ring_inner_diameter_mm, "shaft.shoulder_diameter_mm",
         "shaft shoulder overlaps the outer ring")
    need(h.shoulder_diameter_mm < seat, "housing.shoulder_diameter_mm",
         "must be smaller than the housing bore" if not t_layers
         else "must be smaller than the bearing outside diameter (it holds outer ring A)")
    need(h.shoulder_diameter_mm > b.inner_ring_outer_diameter_mm, "housing.shoulder_diameter_mm",
         "housing shoulder overlaps the inner ring")
    need(h.outer_diameter_mm > h.bore_diameter_mm, "housing.outer_diameter_mm",
         "must exceed the housing bore")
    need(b.inner_ring_outer_diameter_mm >= a.inner_spacer.diameter_mm > s.seat_diameter_mm,
         "inner_spacer.diameter_mm", "must lie between the shaft seat and the inner ring OD")
    need(b.outer_ring_inner_diameter_mm <= a.outer_spacer.diameter_mm < seat,
         "outer_spacer.diameter_mm", "must lie between the outer ring ID and the housing bore"
         if not t_layers else "must lie between the outer ring ID and the bearing OD")
    need(s.seat_diameter_mm < a.nut.diameter_mm < b.outer_ring_inner_diameter_mm,
         "nut.diameter_mm", "must lie between the shaft seat and the outer ring ID")
    need(b.inner_ring_outer_diameter_mm < a.cover.diameter_mm < seat,
         "cover.diameter_mm", "must lie between the inner ring OD and the housing bore"
         if not t_layers else "must lie between the inner ring OD and the bearing OD")
    g = check_bearing(b, a.materials, path)
    # the effective section of a ring holds at least the metal under its groove: a thinner one
    # (a typo, or the ball's diameter for the ring's) also sizes the mesh to that thickness, and
    # the condensation of its fits ran out of memory (a 0.1 mm section: 18 GB, killed)
    for key, d, side in (("bearing.inner_ring_outer_diameter_mm", b.inner_ring_outer_diameter_mm, "inner"),
                         ("bearing.outer_ring_inner_diameter_mm", b.outer_ring_inner_diameter_mm, "outer")):
        bottom = groove_bottom_diameter_mm(g, side)
        need(d >= bottom if side == "inner" else d <= bottom, key,
             f"{d:g} mm leaves the {side} ring thinner than the metal under its groove (groove "
             f"bottom at {bottom:.3f} mm): an effective section lies between the groove bottom and "
             "the land")
    # a typo in one dimension (a housing 1e9 mm wide) would mesh until memory runs out: every
    # length of the stack stays within 20 bearing outside diameters
    big = 20.0 * b.outside_diameter_mm
    for key, val in (("shaft.shoulder_width_mm", s.shoulder_width_mm),
                     ("shaft.extension_mm", s.extension_mm),
                     ("housing.outer_diameter_mm", h.outer_diameter_mm),
                     ("housing.shoulder_width_mm", h.shoulder_width_mm),
                     ("nut.width_mm", a.nut.width_mm), ("cover.width_mm", a.cover.width_mm),
                     ("inner_spacer.length_mm", a.inner_spacer.length_mm),
                     ("outer_spacer.length_mm", a.outer_spacer.length_mm)):
        need(val <= big, key, f"{val:g} mm is more than 20 bearing outside diameters "
                              f"({big:g} mm): a typo?")
    Dw, dm = b.ball_diameter_mm, b.pitch_diameter_mm
    for key, val, d in (("fits.inner_interference_um", a.fits.inner_interference_um, s.seat_diameter_mm),
                        ("fits.outer_interference_um", a.fits.outer_interference_um, h.bore_diameter_mm)):
        # 2 per mille of the diameter is far beyond any bearing fit (ISO 286 n6/P7 at 35 mm:
        # about 40 um) and would yield a hardened ring
        need(abs(val) <= 2.0 * d, key, f"{val:g} um is beyond 2 per mille of the {d:g} mm diameter")
    d = b.outside_diameter_mm
    for name, layer in a.layers():
        d += 2 * layer.radial_thickness_mm
        val = getattr(a.fits, f"{name}_interference_um")
        need(abs(val) <= 2.0 * d, f"fits.{name}_interference_um",
             f"{val:g} um is beyond 2 per mille of the {d:g} mm diameter")
    for name in LAYERS:
        need(getattr(a, name) is not None or getattr(a.fits, f"{name}_interference_um") == 0,
             f"fits.{name}_interference_um", f"given, but the assembly has no [{name}]")
        for m in ("shaft", "bore"):
            for k in (f"{name}_{m}_class", f"{name}_{m}_deviation_um"):
                need(getattr(a, name) is not None or not getattr(a.fits, k), f"fits.{k}",
                     f"given, but the assembly has no [{name}]")
    C0 = static_load_rating_C0_N(b.ball_count, Dw, dm, b.contact_angle_free_deg)
    need(a.preload.assembled_N <= C0, "preload.assembled_N",
         f"{a.preload.assembled_N:g} N exceeds the bearing's static load rating C0 = {C0:.0f} N "
         "(ISO 76): the raceways would be dented at assembly")
    op = a.operating
    lo, hi = MATERIAL_T_RANGE_C
    need(lo <= op.T_min_C < op.T_max_C <= hi, "operating.T_min_C",
         f"the range {op.T_min_C:g}..{op.T_max_C:g} C must be increasing and inside {lo:g}..{hi:g} C")
    _check_mesh(a, need)
    if a.mesh.ring_section == "grooved":
        _check_grooved(a, g, need)


def _check_layers(a: Assembly, need, t_layers: float) -> None:
    """Sleeve / cartridge: the housing bore takes them, each as long as the outer-ring stack
    (it rests on the housing shoulder and the cover clamps it with outer ring B)."""
    b, h = a.bearing, a.housing
    want = b.outside_diameter_mm + 2 * t_layers
    names = " + ".join(n for n, _ in a.layers())
    need(abs(h.bore_diameter_mm - want) <= 1e-6 * want, "housing.bore_diameter_mm",
         f"{h.bore_diameter_mm:g} mm must be the bearing OD + 2 x ({names} radial thickness) = "
         f"{want:g} mm")
    stack = 2 * b.width_mm + a.outer_spacer.length_mm
    for name, layer in a.layers():
        need(abs(layer.length_mm - stack) <= 1e-6 * stack, f"{name}.length_mm",
             f"{layer.length_mm:g} mm must equal the outer-ring stack (2 x bearing width + outer "
             f"spacer = {stack:g} mm): it rests on the housing shoulder and the cover clamps it")


def _check_grooved(a: Assembly, g: BearingGeometry, need) -> None:
    """Grooved ring sections (`[mesh] ring_section = "grooved"`): each groove leaves a ring wall
    under its bottom and ends inside the ring width, and the lands clear the neighbouring parts
    (the land is the ring's radial extent on the ball side)."""
    from analytic.bearing.land import groove_centre_radius_mm, land_angle_deg, land_diameters_mm

    b, s, h = a.bearing, a.shaft, a.housing
    d_i, d_o, _ = land_diameters_mm(b, a.materials)
    for side, wall, name in (("inner", groove_bottom_diameter_mm(g, "inner") - b.bore_mm, "inner"),
                             ("outer", b.outside_diameter_mm - groove_bottom_diameter_mm(g, "outer"),
                              "outer")):
        need(wall > 0, f"bearing.{name}_ring_outer_diameter_mm" if side == "inner"
             else "bearing.outer_ring_inner_diameter_mm",
             f"the {side} groove bottom leaves no ring wall ({wall / 2:.3f} mm) for "
             "mesh.ring_section = \"grooved\"")
        f = g.f_i if side == "inner" else g.f_o
        d_land = d_i if side == "inner" else d_o
        half = f * g.Dw_mm * math.sin(math.radians(land_angle_deg(g, side, d_land)))
        need(half + (f - 0.5) * g.Dw_mm < b.width_mm / 2, f"bearing.{side}_land_diameter_mm",
             f"the {side} groove ({2 * half:.3f} mm wide at the land) does not fit in the ring "
             f"width {b.width_mm:g} mm")
        need(abs(groove_centre_radius_mm(g, side) - d_land / 2) < f * g.Dw_mm,
             f"bearing.{side}_land_diameter_mm", "the land does not meet the groove")
    need(d_i < b.pitch_diameter_mm < d_o, "bearing.inner_land_diameter_mm",
         f"the lands ({d_i:.3f} and {d_o:.3f} mm) must lie either side of the pitch diameter "
         f"({b.pitch_diameter_mm:g} mm)")
    for key, cond, msg in (   # the faces that clamp one ring must not reach the other ring
            ("shaft.shoulder_diameter_mm", s.shoulder_diameter_mm < d_o, "outer ring land"),
            ("nut.diameter_mm", a.nut.diameter_mm < d_o, "outer ring land"),
            ("housing.shoulder_diameter_mm", h.shoulder_diameter_mm > d_i, "inner ring land"),
            ("cover.diameter_mm", a.cover.diameter_mm > d_i, "inner ring land")):
        need(cond, key, f"overlaps the {msg} diameter ({d_i if 'inner' in msg else d_o:.3f} mm) "
                        "of the grooved ring section (or set mesh.ring_section = \"rectangle\")")


def _check_mesh(a: Assembly, need) -> None:
    """Given sizes in order (corner <= fit <= size <= bearing width); a target the size rule was
    measured for (studies/model/mesh_size.py)."""
    m, B = a.mesh, a.bearing.width_mm
    lo, hi = MESH_TARGET_RANGE
    need(lo <= m.target_error <= hi, "mesh.target_error",
         f"{m.target_error:g} is outside {lo:g}..{hi:g} (the range the size rule was measured "
         "over); give explicit sizes for other meshes")
    need(m.size_mm <= B, "mesh.size_mm",
         f"must not exceed the bearing width ({B:g} mm): the rings would not be resolved")
    need(not (m.fit_size_mm and m.size_mm) or m.fit_size_mm <= m.size_mm, "mesh.fit_size_mm",
         "must not exceed mesh.size_mm")
    for big in ("fit_size_mm", "size_mm"):
        need(not (m.corner_size_mm and getattr(m, big)) or m.corner_size_mm <= getattr(m, big),
             "mesh.corner_size_mm", f"must not exceed mesh.{big}")
