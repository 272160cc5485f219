"""Benchmarks (`bearingfem bench`): timings and memory on this machine, printed, never asserted."""
