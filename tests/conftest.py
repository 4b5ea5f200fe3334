"""Test-suite settings."""

from __future__ import annotations

import os

import pytest

if os.environ.get("PYTEST_XDIST_WORKER"):
    # one BLAS thread per test process (set before numpy loads): pytest-xdist runs a process per
    # core, and two BLAS threads per process spin against each other (the console script does
    # the same, beltcalc/cli/main.py)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")


@pytest.fixture(autouse=True, scope="session")
def _own_catalog_cache(tmp_path_factory):
    """The parsed built-in catalogs (beltcalc/data/catalogs.py, ``_builtin_catalog``) go to a folder
    of the test session's own, for every process it starts too: tests that install beltcalc
    into a fresh folder would otherwise leave a cache file per run in the user's cache."""
    before = os.environ.get("BELTCALC_CACHE")
    os.environ["BELTCALC_CACHE"] = str(tmp_path_factory.mktemp("catalog-cache"))
    yield
    if before is None:
        os.environ.pop("BELTCALC_CACHE", None)
    else:
        os.environ["BELTCALC_CACHE"] = before


@pytest.fixture(autouse=True, scope="session")
def _shared_runs(tmp_path_factory, request):
    """pytest-xdist's workers keep the long runs several test modules read (clichecks.shared_run)
    in the session's common temporary folder: each runs once per session, not once per worker."""
    import clichecks

    if hasattr(request.config, "workerinput"):       # a pytest-xdist worker
        clichecks.SHARED_DIR = tmp_path_factory.getbasetemp().parent / "shared-runs"
    yield
