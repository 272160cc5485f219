"""Shared test setup. Small dense solves (contact condensation) are 20x slower with threaded
OpenBLAS on 2 cores, so the tests run single-threaded BLAS like the CLI does."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("BEARINGFEM_CACHE", os.path.join(os.path.dirname(__file__), "..", ".cache"))


# --- requirement traceability (studies/usecases/requirements.py) --------------------------------
# Every test tagged `@pytest.mark.requirement("R-...")` carries its ids in its report; the main
# process (not an xdist worker) records the outcome of each such test in the pytest cache
# (merged with earlier runs: the last outcome of every test), where `bearingfem verify` reads it.
_REQUIREMENT_OUTCOMES: dict = {}


def pytest_collection_modifyitems(config, items):
    for item in items:
        for mark in item.iter_markers("requirement"):
            for rid in mark.args:
                item.user_properties.append(("requirement", rid))


def pytest_runtest_logreport(report):
    ids = [v for k, v in report.user_properties if k == "requirement"]
    if not ids:
        return
    rec = _REQUIREMENT_OUTCOMES.setdefault(report.nodeid, {"requirements": sorted(set(ids)),
                                                           "outcome": "passed"})
    if report.failed:
        rec["outcome"] = "failed"
    elif report.skipped and rec["outcome"] != "failed":
        rec["outcome"] = "skipped"


def pytest_sessionfinish(session):
    import datetime
    import json

    from studies.usecases.requirements import RESULTS_RELPATH

    if hasattr(session.config, "workerinput") or not _REQUIREMENT_OUTCOMES:
        return
    path = session.config.rootpath / RESULTS_RELPATH
    try:
        old = json.loads(path.read_text())["tests"]
    except (OSError, ValueError, KeyError, TypeError):
        old = {}
    when = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    for rec in _REQUIREMENT_OUTCOMES.values():
        rec["when"] = when
    old.update(_REQUIREMENT_OUTCOMES)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps({"tests": old}, indent=1, sort_keys=True) + "\n")
    tmp.replace(path)
