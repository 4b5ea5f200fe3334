"""Loading and running drive files: a drive by path or built-in name (:func:`drive_path`,
:func:`drive_names`), :func:`load_drive` with values replaced, and :func:`simulate` of a drive
or a network on the one ODE core."""

from __future__ import annotations

from pathlib import Path

from beltcalc.errors import InputError, did_you_mean
from beltcalc.sim.drivefile.reader import Drive, DriveFile


def drive_names() -> list[str]:
    """Names of the built-in drive files (``catalogs/drives/*.toml``)."""
    from beltcalc.data.catalogs import builtin_dir

    return sorted(p.stem for p in (builtin_dir() / "drives").glob("*.toml"))


def drive_path(ref: str | Path) -> Path:
    """A drive file by path, or a built-in one by name (``sewing``)."""
    from beltcalc.data.catalogs import builtin_dir
    from beltcalc.errors import UnknownNameError
    from beltcalc.units import quote

    def exists(p: Path) -> bool:
        try:
            return p.exists()
        except (OSError, ValueError):      # a name too long for the file system, a NUL character
            return False

    path = Path(ref)
    if exists(path):
        return path
    if path.suffix == ".toml" or len(path.parts) > 1:
        raise UnknownNameError(f"drive file {quote(ref, 200)}: no such file")
    builtin = builtin_dir() / "drives" / f"{ref}.toml"
    if exists(builtin):
        return builtin
    raise UnknownNameError(f"drive {quote(ref)} is neither a file nor a built-in drive; "
                           + did_you_mean(str(ref), drive_names()))


def load_drive(ref: str | Path, catalog=None, **values) -> Drive:
    """Read and build a drive file (a path, or a built-in drive by name); ``values`` replace
    the file's, by address with ``__`` for ``.`` (``load_drive(p, jaw__stiffness=2000.0)``),
    as SI floats or pint quantities.

    >>> from beltcalc.sim.drivefile import undamped_frequencies
    >>> d = load_drive("friswell_geared", input__diameter=0.25)
    >>> round(undamped_frequencies(d.network)[0], 3)
    15.143
    """
    from beltcalc.si import as_si

    f = DriveFile(drive_path(ref))
    units = {p.name: p.unit for p in f.params()}
    given = {}
    for key, value in values.items():
        address = key.replace("__", ".")
        unit = units.get(address, "")
        given[address] = as_si(value, None if "|" in unit or unit in ("int", "text") else unit, address)
    return f.build(given, catalog)


def simulate(target, t_end=None, samples: int | None = None, config=None, **solver):
    """Simulate a :class:`Drive` (its own timing unless given) or a
    :class:`~beltcalc.sim.network.Network` (``t_end`` needed) on the one ODE core
    (:func:`beltcalc.sim.core.simulate`). ``t_end`` may be a pint quantity; ``solver``
    options build a :class:`~beltcalc.sim.core.SolverConfig` (``method="radau"``,
    ``error_tol=1e-8``) unless ``config`` is given.

    >>> r = simulate(load_drive("friswell_5_disks"), samples=201)
    >>> r.method, float(r.t[-1]), r.signals["omega_disk1"].size
    ('exact', 0.1, 201)
    """
    from beltcalc.si import as_si
    from beltcalc.sim.core import SolverConfig
    from beltcalc.sim.core import simulate as run

    cfg = config if config is not None else SolverConfig(**solver)
    if isinstance(target, Drive):
        net = target.network
        t_end = target.t_end if t_end is None else t_end
        samples = target.samples if samples is None else samples
    else:
        net = target
        if t_end is None:
            raise InputError("give t_end to simulate a Network (a Drive has its own)", param="t_end")
    return run(net, as_si(t_end, "s", "t_end"), int(samples or 2001), cfg)
