"""The seed studies and the validation against published and second-source data. Each reaches the
model only through `studies.model.pipeline` (the one route), the command implementations of
`studies.usecases` or the documented public functions beside them.

`STUDIES` is the one list of study names: `bearingfem study NAME` runs `STUDIES[NAME].run(out,
progress=...)`.
"""
from __future__ import annotations

import importlib

STUDIES = {
    "seed000": "studies.validation.seed000",
    "seed001": "studies.validation.seed001",
    "seed003": "studies.validation.seed003",
    "mesh_convergence": "studies.validation.mesh_convergence",
    "lubricant_viscosity": "studies.validation.lubricant_viscosity",
    "confusion_matrix": "studies.validation.confusion_matrix",
    "ring_sections": "studies.validation.ring_section_compare",
    "heatup": "studies.validation.heatup",
    "tvac": "studies.validation.tvac",
    "friction_validation": "studies.validation.friction_validation",
}


def study_module(name: str):
    """The module of study `name` (a key of STUDIES)."""
    return importlib.import_module(STUDIES[name])
