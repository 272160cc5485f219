"""What each command does (the product's use cases): `report`, `tolerance`, `design`, `bearing`,
`stiffness`, `verify` and the report's parts. Each reaches the model only through
`studies.model.pipeline` (the one route) or the documented public functions beside it; the command
line (`studies.app`) and the Python API (`bearingfem`) both call these modules.
"""
