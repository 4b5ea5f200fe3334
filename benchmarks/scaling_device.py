"""Issue 34's scaling tables on a larger machine, as one prepared command.

The machine it is meant for has 16 cores and a Python (3.12) with numpy, scipy, click and
rich, but not pint or Dask, and no network. So this script has two steps:

* here, with the network: ``python benchmarks/scaling_device.py fetch`` downloads the wheels of
  what that Python lacks (:data:`MISSING`, at the versions installed here) into ``.wheels/``
  (git-ignored; about 4 MiB);
* there, in a copy of this checkout with ``.wheels/``: ``python3 benchmarks/scaling_device.py run
  --out DIR`` installs them into a temporary folder when ``import dask`` fails, then runs
  ``benchmarks/studies.py --only-scaling --workers 1,2,4,8,16 --repeats 1 --conveyor-per-worker
  --conveyor-runs 250`` (the sewing study's 50,000 runs on every count; the conveyor's 250 runs
  a worker, 4,000 on 16, the issue's figure) and writes its tables to ``DIR/scaling.md``.
  About 6 minutes on 16 cores: the in-process conveyor runs alone take about a minute.

``run --quick`` is a check of the whole path on a small machine (``--workers 1,2``; 5,000 sewing
runs, 120 conveyor runs a worker: about 1.5 minutes on 2 cores).
"""

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WHEELS = ROOT / ".wheels"
# what the machine's Python lacks of this project's dependencies and Dask's (its image holds
# numpy, scipy, click, rich, cloudpickle, fsspec, jinja2, msgpack, packaging, psutil, pyyaml,
# sortedcontainers, toolz, urllib3 and typing_extensions)
MISSING = ("pint", "flexcache", "flexparser", "platformdirs", "dask", "distributed", "partd", "locket", "tblib",
           "zict", "tornado", "importlib_metadata", "zipp", "lazy_importer")   # (the last three: Dask's on Python < 3.12)


def fetch(python_version: str) -> None:
    """The wheels of :data:`MISSING` for ``python_version`` on x86-64 Linux, each at the version
    installed here, into :data:`WHEELS`."""
    from importlib.metadata import version

    pins = [f"{name}=={version(name)}" for name in MISSING]
    subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", "--only-binary=:all:",
                    "--python-version", python_version, "--implementation", "cp",
                    "--platform", "manylinux2014_x86_64", "--platform", "manylinux_2_17_x86_64", "--platform", "any",
                    "-d", str(WHEELS), *pins], check=True)
    print(f"{len(list(WHEELS.glob('*.whl')))} wheels in {WHEELS}")


def run(out: Path, quick: bool) -> int:
    """The scaling tables (``benchmarks/studies.py --only-scaling``) into ``out/scaling.md``."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    paths = [str(ROOT)]
    probe = subprocess.run([sys.executable, "-c", "import pint, dask, distributed"], capture_output=True)
    if probe.returncode != 0:
        target = tempfile.mkdtemp(prefix="beltcalc-deps-")
        subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-index", "--no-deps", "--target",
                        target, *map(str, sorted(WHEELS.glob("*.whl")))], check=True)
        paths.append(target)
    env["PYTHONPATH"] = os.pathsep.join(paths + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    args = (["--workers", "1,2", "--sewing-runs", "5000", "--conveyor-runs", "120"] if quick else
            ["--workers", "1,2,4,8,16", "--conveyor-runs", "250"])
    print(f"{os.cpu_count()} CPUs, Python {sys.version.split()[0]}", flush=True)
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "studies.py"), "--only-scaling", "--repeats", "1",
                           "--conveyor-per-worker", *args], env=env, capture_output=True, text=True)
    sys.stdout.write(done.stdout)
    sys.stderr.write(done.stderr)
    out.mkdir(parents=True, exist_ok=True)
    (out / "scaling.md").write_text(f"{os.cpu_count()} CPUs, Python {sys.version.split()[0]}\n\n{done.stdout}")
    return done.returncode


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="step", required=True)
    f = sub.add_parser("fetch", help="download the wheels the other machine lacks (here, with the network)")
    f.add_argument("--python-version", default="3.12", help="that machine's Python [default: 3.12]")
    r = sub.add_parser("run", help="install them if needed and write the scaling tables (there)")
    r.add_argument("--out", type=Path, default=Path(os.environ.get("OUT", ".")), help="folder of scaling.md [$OUT]")
    r.add_argument("--quick", action="store_true", help="a check of the path on a small machine")
    args = ap.parse_args()
    if args.step == "fetch":
        fetch(args.python_version)
    else:
        sys.exit(run(args.out, args.quick))


if __name__ == "__main__":
    main()
