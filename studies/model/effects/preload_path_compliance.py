"""preload_path_compliance: the clamp / nut / spacer path of a position preload is softer than
the assembly model says.

Physics added: an extra axial compliance c_x in series with each bearing's preload path (thread
and clamped-face contact, a ramped or tilted spacer face, a nut that relaxes), on top of the
compliance the model already carries (`[preload] path_compliance`: the FE structure, or rigid).
Springs in series add their compliances, so each bearing's effective axial stiffness becomes

    1 / k_eff = 1 / k_bearing + c_path + c_x,

and a thermal change delta of the groove-centre distance in the preload loop changes the preload
by about delta / (1/k_A + 1/k_B + 2 (c_path + c_x)) (the loop of both bearings and their paths in
series): a softer path makes the preload, and the torque, follow temperature less. The pair's
position-preload equilibrium (`analytic.bearing`, X + c F(X) = X_nom per bearing) is solved with
the summed compliance; no second pair solver. At the reference state the preload is the assembled
one whatever the compliance. A spring preload is not affected (the spring sets the force).

Parameters:
    extra_compliance_um_per_kN  extra axial compliance per bearing, um/kN (1 um/kN = 1e-6 mm/N),
                                bounds [0, 5e4], off 0

Convention: written into `PhysicsInputs.extra_compliance_mm_per_N` (added to any value present);
`studies.model.pipeline.Pipeline.run_from_fe` adds it to the preload-path compliance.

Source / rationale: seed 001 (hybrid flywheel pair, 7 N position preload): the measured torque
changes only +33..50 % at -20 C and -25 % at 60 C, while a rigid (or FE-stiff) preload path
multiplies the preload when cold and unloads the pair when hot; the ratios imply compliance in
the preload path that a solid FE model does not hold (`bearingfem study
seed001`). Compliances of bolted and clamped joints in series: VDI 2230 Part 1 (2015), sec. 5.1.
5e4 um/kN (0.05 mm/N) is as soft as a wave-spring preload and bounds any clamped path.
"""
from __future__ import annotations

from .base import Effect

#: um/kN -> mm/N
UM_PER_KN = 1e-6


class PreloadPathCompliance(Effect):
    name = "preload_path_compliance"
    parameters = ("extra_compliance_um_per_kN",)
    units = {"extra_compliance_um_per_kN": "um/kN"}
    bounds = {"extra_compliance_um_per_kN": (0.0, 5e4)}
    off = {"extra_compliance_um_per_kN": 0.0}
    scale = {"extra_compliance_um_per_kN": 10.0}
    hint = ("measure the preload (or the pair's axial stiffness) at two temperatures: a softer "
            "preload path lowers the preload change per kelvin and the stiffness, but not the "
            "preload at the reference temperature")

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy(extra_compliance_mm_per_N=inputs.extra_compliance_mm_per_N
                           + UM_PER_KN * p["extra_compliance_um_per_kN"])
