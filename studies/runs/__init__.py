"""Study scripts, verification and benchmarks: the top floor. Each reaches the model only through
`studies.model.pipeline` (the one route) or the documented public functions beside it.

`STUDIES` is the one list of study names: `bearingfem study NAME` runs `STUDIES[NAME].run(out,
progress=...)`.
"""
from __future__ import annotations

import importlib

STUDIES = {
    "seed000": "studies.runs.seed000",
    "seed001": "studies.runs.seed001",
    "seed003": "studies.runs.seed003",
    "mesh_convergence": "studies.runs.mesh_convergence",
    "lubricant_viscosity": "studies.runs.lubricant_viscosity",
    "confusion_matrix": "studies.runs.confusion_matrix",
    "ring_sections": "studies.runs.ring_section_compare",
    "heatup": "studies.runs.heatup",
    "tvac": "studies.runs.tvac",
}


def study_module(name: str):
    """The module of study `name` (a key of STUDIES)."""
    return importlib.import_module(STUDIES[name])
