"""The installed wheel works on its own: it carries the catalogs, and the source checkout
is not on the path.

Builds a wheel from this checkout, installs it into a fresh virtual environment without
pip, makes the dependencies (click, numpy, pint, rich and theirs) importable with a
``deps.pth`` file that lists the current interpreter's site-packages folders, and runs
the installed ``beltcalc`` from another folder. A plain path line in a .pth file does not
run the .pth files of that folder, so the editable install of the checkout
(``_editable_impl_beltcalc.pth``) stays out of the new environment.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TIMEOUT = 120  # per subprocess, a guard against a hang; the whole module takes a few seconds


def _clean_env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP", "VIRTUAL_ENV", "BELTCALC_DEBUG")
           and not k.startswith("PIP_")}
    env["PYTHONNOUSERSITE"] = "1"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def _run(args, **kw) -> subprocess.CompletedProcess:
    kw.setdefault("env", _clean_env())
    result = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=TIMEOUT, **kw)
    assert result.returncode == 0, (
        f"{' '.join(map(str, args))} -> {result.returncode}\nstdout:\n{result.stdout}\nstderr:\n{result.stderr}")
    return result


def _pip_version() -> tuple[int, ...] | None:
    try:
        import pip
    except ImportError:
        return None
    return tuple(int(p) for p in pip.__version__.split(".")[:2] if p.isdigit())


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    version = _pip_version()
    if version is None:
        pytest.skip("pip is not installed in this interpreter")
    if version < (22, 3):
        pytest.skip(f"pip {'.'.join(map(str, version))} has no --python (needs pip >= 22.3)")
    pytest.importorskip("hatchling", reason="hatchling (test extra) is needed to build the wheel")
    out = tmp_path_factory.mktemp("wheel")
    _run([sys.executable, "-m", "pip", "wheel", ROOT, "--no-deps", "--no-build-isolation", "--no-index",
          "-q", "-w", out])
    wheels = list(out.glob("beltcalc-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


@pytest.fixture(scope="module")
def venv(wheel, tmp_path_factory) -> Path:
    import click
    import numpy
    import pint
    import rich

    folder = tmp_path_factory.mktemp("venv") / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", folder])
    python = folder / "bin" / "python"
    _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index", "-q", wheel])
    purelib = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"])
                   .stdout.strip())
    assert purelib.is_dir() and folder in purelib.parents, purelib
    deps = sorted({str(Path(m.__file__).resolve().parents[1]) for m in (click, numpy, pint, rich)})
    (purelib / "deps.pth").write_text("\n".join(deps) + "\n")
    return folder


def test_wheel_contains_the_catalogs(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for entry in ("beltcalc/catalogs/belts/breco_at10.toml", "beltcalc/catalogs/threads.toml",
                  "beltcalc/catalogs/motors/yaskawa.toml"):
        assert entry in names
    shipped = {n.removeprefix("beltcalc/") for n in names if n.startswith("beltcalc/catalogs/")}
    in_checkout = {p.relative_to(ROOT).as_posix() for p in (ROOT / "catalogs").rglob("*.toml")}
    assert in_checkout <= shipped


def test_installed_package_comes_from_the_venv(venv, tmp_path):
    code = ("import beltcalc, beltcalc.data.catalogs as c; print(beltcalc.__file__); "
            "print(c.builtin_dir())")
    lines = _run([venv / "bin" / "python", "-c", code], cwd=tmp_path).stdout.splitlines()
    module, catalogs = (Path(line).resolve() for line in lines)
    venv = venv.resolve()
    assert venv in module.parents, module
    assert ROOT not in module.parents, module
    assert venv in catalogs.parents, catalogs
    assert ROOT not in catalogs.parents, catalogs


def test_installed_catalog_list(venv, tmp_path):
    result = _run([venv / "bin" / "beltcalc", "catalog", "list"], cwd=tmp_path)
    assert "BRECO-AT10" in result.stdout
    assert "M10x1" in result.stdout and "SGM7J-04A" in result.stdout
    assert str(ROOT) not in result.stdout


def test_installed_tension_json(venv, tmp_path):
    result = _run([venv / "bin" / "beltcalc", "tension", "--json"], cwd=tmp_path)
    obj = json.loads(result.stdout)
    assert obj["belt"] == "BRECO-AT10"
    assert obj["tension_peak"]["value"] == pytest.approx(505.1, abs=0.05)
    assert obj["bolt_torque"]["value"] == pytest.approx(0.631, abs=5e-4)
    assert result.stderr == ""
