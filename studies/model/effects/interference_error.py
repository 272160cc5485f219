"""interference_error: the as-built fits differ from the nominal ones in the assembly config.

Physics added: a constant offset of the diametral interference of the shaft / inner-ring fit
(`inner_um`) and of the outer-ring / housing fit (`outer_um`), at the reference temperature
(positive = more interference, negative = more clearance). The thermal change of the fits is
untouched: the FE adds it on top, so a fit may open or close at a different temperature.

Parameters (diametral, um):
    inner_um  offset of the inner fit, bounds [-20, 20], off 0
    outer_um  offset of the outer fit, bounds [-20, 20], off 0

Convention: written into `PhysicsInputs.interference_inner_um/outer_um` as offsets from the
config's nominal fit (see `studies.model.effects`); existing offsets are added to.

Source / rationale: ISO 286 tolerance grades for bearing seats (IT5 at 30-50 mm: 11 um band) plus
the bearing bore/outside-diameter tolerances (P4/P5: 5-8 um) and form errors give as-built fits that
differ from nominal by up to about +-10 um on mm-size space and spindle bearings; +-20 um bounds a
gross assembly error. Harris & Kotzalas, Rolling Bearing Analysis, Vol. 1 ch. 8 (fits).
"""
from __future__ import annotations

import numpy as np

from .base import Effect


class InterferenceError(Effect):
    name = "interference_error"
    parameters = ("inner_um", "outer_um")
    units = {"inner_um": "um", "outer_um": "um"}
    bounds = {"inner_um": (-20.0, 20.0), "outer_um": (-20.0, 20.0)}
    off = {"inner_um": 0.0, "outer_um": 0.0}
    scale = {"inner_um": 1.0, "outer_um": 1.0}
    hint = ("measure the fits directly (bore/seat diameters after disassembly) or the preload at "
            "the reference temperature; an interference error does not depend on speed or on the "
            "rate of temperature change")

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy(
            interference_inner_um=np.asarray(inputs.interference_inner_um, float) + p["inner_um"],
            interference_outer_um=np.asarray(inputs.interference_outer_um, float) + p["outer_um"])
