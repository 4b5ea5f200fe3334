"""Test-suite settings."""

from __future__ import annotations

import os

import pytest


@pytest.fixture(autouse=True, scope="session")
def _own_catalog_cache(tmp_path_factory):
    """The parsed built-in catalogs (beltcalc/catalogs.py, ``_builtin_catalog``) go to a folder
    of the test session's own, for every process it starts too: tests that install beltcalc
    into a fresh folder would otherwise leave a cache file per run in the user's cache."""
    before = os.environ.get("BELTCALC_CACHE")
    os.environ["BELTCALC_CACHE"] = str(tmp_path_factory.mktemp("catalog-cache"))
    yield
    if before is None:
        os.environ.pop("BELTCALC_CACHE", None)
    else:
        os.environ["BELTCALC_CACHE"] = before
