"""The first layer of bearingfem: what every other package may import, and which imports none of
them (tests/test_imports.py holds this): the version (`infra.version`), atomic output files and
folders with the one sweeper of stale temporaries (`infra.files`), the one in-memory cache helper
(`infra.memo`), signals held back around native calls that must not be interrupted
(`infra.signals`) and the package's own error and warning categories (`infra.errors`).

Why a package of its own: `meshes/` is the first layer that writes files and `fem/` needs the
version, so these cannot live in `bearingfem/` (the Python API, which imports `studies/`; importing
`bearingfem._anything` runs `bearingfem/__init__.py` first) nor in a lower layer.
"""
