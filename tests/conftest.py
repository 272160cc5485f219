"""Shared test setup. Small dense solves (contact condensation) are 20x slower with threaded
OpenBLAS on 2 cores, so the tests run single-threaded BLAS like the CLI does."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("BEARINGFEM_CACHE", os.path.join(os.path.dirname(__file__), "..", ".cache"))
