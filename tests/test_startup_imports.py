"""Start-up (issue 17, item 6): what each command's defaults import, in a fresh process.

A command imports what its run uses and nothing else: no plotting, data frames, Dask
beyond what pint itself loads, no scipy solver it does not call. benchmarks/startup.py
measures the CPU against the pint floor; these tests only guard the imports (no timing).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

NEVER = ("matplotlib", "pandas", "pyarrow", "distributed", "dask.array", "dask.dataframe", "scipy.integrate")

CHILD = r"""
import contextlib, io, json, sys
from beltcalc.cli.main import cli
with contextlib.redirect_stdout(io.StringIO()):
    code = cli.main(sys.argv[1:], prog_name="beltcalc", standalone_mode=False)
print(json.dumps({"code": code, "modules": sorted(sys.modules)}), file=sys.stderr)
"""


def _loaded(*args: str) -> set[str]:
    done = subprocess.run([sys.executable, "-c", CHILD, *args], capture_output=True, text=True, check=True)
    out = json.loads(done.stderr.strip().splitlines()[-1])
    assert out["code"] in (0, None), done.stderr
    return set(out["modules"])


def _under(loaded: set[str], *prefixes: str) -> set[str]:
    return {m for m in loaded if any(m == p or m.startswith(p + ".") for p in prefixes)}


@pytest.fixture(scope="module")
def pint_floor() -> set[str]:
    """What ``import pint`` loads by itself (with dask installed: dask.base)."""
    done = subprocess.run([sys.executable, "-c", "import pint, sys; print(' '.join(sorted(sys.modules)))"],
                          capture_output=True, text=True, check=True)
    return set(done.stdout.split())


@pytest.mark.parametrize("args", [("tension",), ("catalog", "list"), ("chain",), ("belt-drive",), ("motor-size",),
                                  ("modes",), ("campbell",), ("response",), ("simulate", "sewing", "--help"),
                                  ("simulate", "roller-table", "--help")])
def test_a_command_without_a_simulation_imports_no_scipy_module(args, pint_floor):
    # the frequency domain included: its rows come from the network, its peaks from
    # beltcalc.numerics.scalar, not from the time-domain core, scipy.linalg or scipy.optimize
    loaded = _loaded(*args)
    assert not _under(loaded, *NEVER) - pint_floor
    assert not _under(loaded, "scipy.linalg", "scipy.optimize", "scipy.sparse", "scipy.special") - pint_floor
    assert not _under(loaded, "dask") - pint_floor


def test_simulate_sewing_imports_no_scipy_module(pint_floor):
    # the exact method's expm and balancing are beltcalc.numerics' (numpy only)
    loaded = _loaded("simulate", "sewing")
    assert not _under(loaded, *NEVER, "scipy.linalg", "scipy.optimize", "scipy.sparse") - pint_floor
    # only its own scene: not the linear axis's sizing and duty cycles, not the roller table
    assert not {"beltcalc.sim.scenes.linear_axis", "beltcalc.sim.scenes.roller_table", "beltcalc.design.sizing",
                "beltcalc.design.dutycycle"} & loaded


def test_a_drive_with_strands_imports_no_scipy_module(pint_floor):
    # the switching core locates strand switches with beltcalc.numerics.scalar's port of scipy's
    # brentq and the watch polishes extremes with numpy alone (beltcalc.sim.watch.polish); expm
    # and balancing are beltcalc.numerics'
    loaded = _loaded("simulate", "drive", "conveyor")
    assert not _under(loaded, *NEVER, "scipy.linalg", "scipy.optimize", "scipy.sparse") - pint_floor


def test_the_scene_registry_imports_a_scene_on_first_look_up():
    code = ("import sys\nfrom beltcalc.sim.scenes import SCENES\nbefore = set(sys.modules)\n"
            "names = list(SCENES)\ns = SCENES['sewing']\n"
            "print(names, 'beltcalc.sim.scenes.sewing' in before, 'beltcalc.sim.scenes.sewing' in sys.modules, "
            "'beltcalc.sim.scenes.linear_axis' in sys.modules, s.name)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["['sewing',", "'roller-table',", "'linear-axis']", "False", "True", "False", "sewing"]


def test_the_registry_takes_an_entry_set_in_place_of_a_scene():
    from dataclasses import replace

    from beltcalc.sim.scenes import SCENES, _Scenes

    scenes = _Scenes({"sewing": "beltcalc.sim.scenes.sewing"})
    other = replace(SCENES["sewing"], name="another")
    scenes["sewing"] = other
    scenes["extra"] = other
    assert scenes["sewing"] is other and list(scenes) == ["sewing", "extra"] and len(scenes) == 2
    del scenes["extra"]
    assert "extra" not in scenes
    with pytest.raises(KeyError):
        scenes["missing"]


def test_the_console_script_collects_garbage_while_the_command_runs():
    # main() pauses the collector only while the command's module is imported
    code = ("import gc, sys\nimport beltcalc.data.catalogs as c\nreal = c.load_catalog\nseen = []\n"
            "def spy(*a, **k):\n    seen.append(gc.isenabled())\n    return real(*a, **k)\n"
            "c.load_catalog = spy\nfrom beltcalc.cli import main as m\nsys.argv = ['beltcalc', 'catalog', 'list']\n"
            "try:\n    m.main()\nexcept SystemExit as e:\n    code = e.code\n"
            "print('RESULT', code, seen, gc.isenabled(), file=sys.stderr)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stderr.split("RESULT", 1)[1].split() == ["0", "[True]", "True"]


def test_the_console_script_lets_malloc_keep_freed_memory(monkeypatch):
    # once a command is loaded: glibc's mmap threshold 32 MB and trim threshold 256 MB (block
    # temporaries are reused instead of faulted in again); a user's MALLOC_* setting wins
    import ctypes

    from beltcalc.cli import main

    calls = []

    class Libc:
        def mallopt(self, option, value):
            calls.append((option, value))
            return 1

    monkeypatch.setattr(ctypes, "CDLL", lambda name: Libc())
    for env, want in (({}, [(-3, 32 << 20), (-1, 256 << 20)]), ({"MALLOC_ARENA_MAX": "2"}, [])):
        calls.clear()
        monkeypatch.setattr(main, "_keep_freed_memory_done", False)
        for key in [k for k in main.os.environ if k.startswith("MALLOC_")]:
            monkeypatch.delenv(key)
        for key, value in env.items():
            monkeypatch.setenv(key, value)
        main._keep_freed_memory()
        main._keep_freed_memory()                    # once per process
        assert calls == want
