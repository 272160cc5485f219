"""The defaults of the commands' settings, defined once: the command line's flags
(studies/app/cli.py) and the Python functions (studies/usecases/api.py, `import bearingfem`) both
read them here, so the same call with defaults gives the same numbers either way. Plain values,
no imports: the command line reads them before it loads numpy.
"""

#: `tolerance --samples`: Monte Carlo samples
TOLERANCE_SAMPLES = 2000
#: `tolerance --seed`: random seed of the Monte Carlo
TOLERANCE_SEED = 1
#: `design --band`: the preload band, fractions of the assembled preload (LOW, HIGH)
DESIGN_BAND = (0.8, 1.2)
#: `bearing --convention`: exact groove-centre geometry ("exact") or ISO/TS 16281 ("iso16281")
BEARING_CONVENTION = "exact"
#: `bearing --control`: raceway control of the quasi-dynamic balls ("outer", "inner", "jones")
BEARING_CONTROL = "outer"
