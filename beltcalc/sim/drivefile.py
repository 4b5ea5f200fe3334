"""Drive files: a designer's own drive train as TOML, read into a :class:`Drive` (a
:class:`~beltcalc.sim.network.Network` plus its timing and notes).

A drive file lists nodes (inertias, translating masses) and the elements between them:
couplings, rigid gears, shafts from geometry, belt spans from a belt catalog entry, chain
strands from ``catalogs/chains.toml``, motors (induction, prescribed motion, speed loop,
torque table) and loads. Every value is a quantity string with its unit (plain numbers for
ratios, counts and factors), converted to SI once, here. The format is in
``docs/drive_files.md``; an example is ``catalogs/drives/conveyor.toml``.

Every value of every element is addressable as ``ELEMENT.KEY`` (``jaw.stiffness``,
``upper.pretension``; the timing as ``t_end``, ``samples``, ``window``): :meth:`DriveFile.params`
lists them and :meth:`DriveFile.build` takes new values for any of them, so ``--set`` and
``--sweep`` reach every number in the file.

A malformed file is one :class:`DriveFileError` naming the file, the element and the key
(exit 1); nothing is half-built.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from beltcalc.catalogs import read_toml, shown_path
from beltcalc.checks import percent
from beltcalc.errors import BeltcalcError, CatalogError, FloatRangeError, InputError, blame, did_you_mean, float_range

SECTIONS = ("drive", "node", "coupling", "shaft", "gear", "belt_span", "chain_strand", "motor", "load")


class DriveFileError(CatalogError):
    """A drive file that cannot be read or built: the message names the file, the element
    and the key (exit 1)."""


@dataclass(frozen=True)
class Key:
    """A key a section accepts. ``unit``: SI unit (``""`` a plain number, ``"a|b"`` either
    dimension), ``"int"``, ``"bool"``, ``"text"``, ``"names"`` (node names), or ``"table:X,Y"``
    (a list of [X, Y] quantity pairs)."""

    unit: str
    help: str
    required: bool = False
    low: str = ""          # "": any value; ">0" positive; ">=0" not negative; "!=0" not zero

    @property
    def scalar(self) -> bool:
        """Whether ``--set ELEMENT.KEY=...`` can give it."""
        return self.unit not in ("names", "bool") and not self.unit.startswith("table:")


TORQUE = "N*m|N"
KEYS: dict[str, dict[str, Key]] = {
    "drive": {
        "title": Key("text", "title of the report"),
        "t_end": Key("s", "simulated time", True, low=">0"),
        "samples": Key("int", "output samples (>= 2)"),
        "window": Key("s", "start of the steady window for means and amplitudes", low=">=0"),
    },
    "node": {
        "name": Key("text", "unique name", True),
        "inertia": Key("kg*m^2", "rotating inertia (0: massless, condensed out)", low=">=0"),
        "mass": Key("kg", "a translating mass instead of an inertia", low=">=0"),
        "teeth": Key("int", "teeth of the pulley or sprocket (pitch diameter from the belt or chain)"),
        "belt": Key("text", "belt profile of the pulley (catalog name), for its pitch diameter"),
        "chain": Key("text", "chain of the sprocket (catalog name), for its pitch diameter"),
        "pitch_diameter": Key("m", "pitch diameter where strands leave the node", low=">0"),
    },
    "coupling": {
        "name": Key("text", "unique name"),
        "between": Key("names", "[node, node] (one node: to the frame)", True),
        "stiffness": Key("N*m/rad|N/m", "spring C", True, low=">=0"),
        "damping": Key("N*m*s/rad|N*s/m", "damper d", low=">=0"),
        "ratio": Key("", "U: the torque is C (phi_a - U phi_b) + d (omega_a - U omega_b)", low=">0"),
        "rigid": Key("bool", "join the two nodes rigidly (phi_b = phi_a / U); the error of doing so is printed"),
        "eccentricity": Key("m", "an eccentric tension roller on the belt's slack span: the pivot's offset Delta "
                                 "from the roller's centre (docs/eccentric_roller.md); 0: none", low=">=0"),
        "roller_radius": Key("m", "the tension roller's radius r3", low=">0"),
        "pulley_radius": Key("m", "pitch radius r1 of the first node's pulley (r2 = ratio x r1) [default: the "
                                  "node's pitch diameter / 2]", low=">0"),
        "center_distance": Key("m", "centre distance a of the two pulleys", low=">0"),
        "pivot_x": Key("m", "the roller's pivot, along the line from the first pulley to the second"),
        "pivot_y": Key("m", "the roller's pivot, across that line (negative: under the slack span)"),
        "roller_angle": Key("rad", "the eccentric's angle theta_0 when the first node's angle is 0"),
    },
    "shaft": {
        "name": Key("text", "unique name"),
        "between": Key("names", "[node, node]", True),
        "diameter": Key("m", "outer diameter", True, low=">0"),
        "bore": Key("m", "bore diameter (0: solid)", low=">=0"),
        "length": Key("m", "length between the nodes", True, low=">0"),
        "material": Key("text", "material of catalogs/materials.toml (G and density)"),
        "shear_modulus": Key("Pa", "G, instead of a material's", low=">0"),
        "density": Key("kg/m^3", "density, for the shaft's own inertia (half to each node)", low=">=0"),
        "damping": Key("N*m*s/rad", "damper d", low=">=0"),
        "damping_time": Key("s", "stiffness-proportional damping d = beta C", low=">=0"),
    },
    "gear": {
        "name": Key("text", "unique name"),
        "between": Key("names", "[node a, node b]", True),
        "ratio": Key("", "speed of a / speed of b (phi_b = phi_a / ratio; negative: the pair reverses, as "
                         "an external gear pair does)", True, low="!=0"),
    },
    "belt_span": {
        "name": Key("text", "unique name"),
        "from": Key("text", "node it leaves (its pitch circle, or a translating node)", True),
        "to": Key("text", "node it reaches", True),
        "belt": Key("text", "belt profile (catalog name)", True),
        "width": Key("m", "belt width (a catalog width)", True, low=">0"),
        "length": Key("m", "free span length", True, low=">0"),
        "pretension": Key("N", "pretension F_0", low=">=0"),
        "damping": Key("N*s/m", "b; otherwise fitted to the catalog's F_tspec(n) as `beltcalc tension` does", low=">=0"),
        "tension_only": Key("bool", "true (default): the span goes slack; false: a two-way spring"),
    },
    "chain_strand": {
        "name": Key("text", "unique name"),
        "from": Key("text", "node (sprocket) it leaves", True),
        "to": Key("text", "node (sprocket) it reaches", True),
        "chain": Key("text", "chain (catalogs/chains.toml name, e.g. 10B-1)", True),
        "length": Key("m", "free strand length", True, low=">0"),
        "pretension": Key("N", "pretension F_0", low=">=0"),
        "stiffness": Key("N", "EA: the force per unit strain (chains publish none: the file must say)", True, low=">0"),
        "mass": Key("kg/m", "mass per length, instead of the catalog's", low=">=0"),
        "breaking_load": Key("N", "breaking load, instead of the catalog's", low=">0"),
        "damping": Key("N*s/m", "b", low=">=0"),
        "damping_time": Key("s", "stiffness-proportional damping b = beta c", low=">=0"),
    },
    "motor": {
        "name": Key("text", "unique name"),
        "kind": Key("text", "induction, prescribed, speed_loop or torque", True),
        "node": Key("text", "node it drives", True),
        "rated_torque": Key("N*m", "induction: rated torque (or rated_power and rated_speed)", low=">0"),
        "rated_power": Key("W", "induction: rated power", low=">0"),
        "rated_speed": Key("rad/s", "induction: rated speed", low=">0"),
        "breakdown_factor": Key("", "induction: breakdown torque / rated torque", low=">0"),
        "breakdown_slip": Key("", "induction: breakdown slip", low=">0"),
        "supply": Key("Hz", "induction: supply frequency", low=">0"),
        "pole_pairs": Key("int", "induction: pole pairs [default: inferred from rated_speed and supply]"),
        "ramp": Key("s", "induction: inverter ramp from 0 to the supply frequency (0: none)", low=">=0"),
        "speed": Key("rad/s|m/s", "prescribed: initial speed"),
        "accel": Key("table:s,rad/s^2|m/s^2", "prescribed: acceleration table [[t, a], ...]"),
        "distance": Key("rad|m", "prescribed: a move of this distance (motor-size profile)"),
        "max_speed": Key("rad/s|m/s", "prescribed: the move's speed limit", low=">0"),
        "max_accel": Key("rad/s^2|m/s^2", "prescribed: the move's acceleration limit", low=">0"),
        "jerk": Key("rad/s^3|m/s^3", "prescribed: jerk limit (S-curve); none: trapezoid", low=">0"),
        "start": Key("s", "prescribed: the move starts here", low=">=0"),
        "gain": Key("N*m*s/rad|N*s/m", "speed_loop: proportional gain", low=">=0"),
        "reference": Key("table:s,rad/s|m/s", "speed_loop: speed reference [[t, speed], ...]"),
        "feedforward": Key("table:s,N*m|N", "speed_loop: feed-forward torque [[t, torque], ...]"),
        "torque": Key("table:s,N*m|N", "torque: drive torque [[t, torque], ...]"),
    },
    "load": {
        "name": Key("text", "unique name"),
        "node": Key("text", "node it acts on", True),
        "torque": Key(TORQUE, "constant part, against the motion"),
        "amplitude": Key(TORQUE, "amplitude of the sine"),
        "frequency": Key("rad/s|Hz", "frequency of the sine in time", low=">=0"),
        "order": Key("", "instead of frequency: the sine locked to the node's angle, sin(order phi)", low=">0"),
        "phase": Key("rad", "phase of the sine"),
        "start": Key("s", "the sine acts from here on (torque from 0; a later step: table)", low=">=0"),
        "table": Key("table:s,N*m|N", "tabulated part [[t, torque], ...]"),
    },
}
KINDS = ("induction", "prescribed", "speed_loop", "torque")
# the keys of each motor kind (beside name, kind, node)
KIND_KEYS = {"induction": {"rated_torque", "rated_power", "rated_speed", "breakdown_factor", "breakdown_slip",
                           "supply", "pole_pairs", "ramp"},
             "prescribed": {"speed", "accel", "distance", "max_speed", "max_accel", "jerk", "start"},
             "speed_loop": {"gain", "reference", "feedforward"}, "torque": {"torque"}}

# The largest rated slip an induction motor's rated speed may give: NEMA design D, the
# high-slip motors, run at 5-8 % or 8-13 % slip at rated load; designs A-C and E below 5 %
# (EASA Electrical Engineering Handbook, "General Speed-Torque Characteristics, Three-Phase
# Induction Motors", after NEMA MG 10 table 2-1; its 15-25 % class of design D was never made
# and was deleted from NEMA MG 1-2003). 15 %: design D's 13 % with a margin.
MAX_RATED_SLIP = 0.15


def pole_pairs_from_speed(rated_speed: float, supply: float) -> tuple[int, float]:
    r"""The pole pairs of an induction motor from its rated speed and its supply, and the
    rated slip they give: the largest p whose synchronous speed is above the rated speed.

    .. math:: \omega_0 = 2 \pi f / p > \omega_n, \quad s_n = 1 - \omega_n / \omega_0

    Parameters
    ----------
    rated_speed : float
        Rated speed omega_n, [rad/s]
    supply : float
        Supply frequency f, [Hz]

    Returns
    -------
    tuple[int, float]
        (p, s_n); p = 0 when the rated speed is at or above the synchronous speed of one
        pole pair (then s_n <= 0)

    Notes
    -----
    Whether s_n is plausible is the caller's check (:data:`MAX_RATED_SLIP`).

    Examples
    --------
    >>> p, s = pole_pairs_from_speed(1400 * math.pi / 30, 50.0)     # 1400 rpm at 50 Hz: 1500 rpm, 4 poles
    >>> p, round(s, 4)
    (2, 0.0667)
    """
    ratio = 2 * math.pi * supply / rated_speed       # synchronous speed of one pole pair / rated speed
    p = max(math.ceil(ratio) - 1, 0)
    if p >= 1 and not 2 * math.pi * supply / p > rated_speed:   # rounding at a whole ratio
        p -= 1
    if p < 1:
        return 0, 1 - rated_speed / (2 * math.pi * supply)
    return p, 1 - rated_speed * p / (2 * math.pi * supply)


@dataclass(frozen=True)
class Entry:
    """One element of the file: its section, name, index in the section and raw values."""

    section: str
    name: str
    index: int
    raw: dict

    @property
    def where(self) -> str:
        return f"{self.section} {self.name!r}"


@dataclass(frozen=True)
class DriveParam:
    """A value of the file that ``--set``/``--sweep`` can address: ``ELEMENT.KEY`` (or a
    timing name), its SI unit (as :class:`Key`), the file's text (None: not given) and help."""

    name: str
    unit: str
    text: str | None
    help: str


@dataclass
class Drive:
    """A built drive: the network, its timing, and what the report follows."""

    title: str
    path: str
    network: object
    t_end: float
    samples: int
    window: float
    notes: list[str] = field(default_factory=list)
    nodes: list[str] = field(default_factory=list)
    torques: list[tuple[str, str]] = field(default_factory=list)     # (signal, label) of couplings/shafts
    spans: dict[str, float] = field(default_factory=dict)            # two-way span -> lever r [m]
    limits: dict[str, tuple[float, str]] = field(default_factory=dict)  # strand -> (force limit [N], its name)
    motors: list[tuple[str, str]] = field(default_factory=list)      # (torque signal, node)
    fits: dict[str, tuple[float, str]] = field(default_factory=dict)  # belt span -> (R^2 of its damping fit, the fit)
    inputs: dict = field(default_factory=dict)                       # address -> (SI value, origin)


def _read_toml(path: Path) -> dict:
    """The drive file ``path`` read by :func:`beltcalc.catalogs.read_toml` (bounded size and
    depth: a file nested 5,000 levels deep is one line, not a RecursionError), every
    failure a :class:`DriveFileError` naming the file."""
    try:
        return read_toml(path, "drive file")
    except CatalogError as exc:
        if not os.path.lexists(path):
            raise DriveFileError(f"{shown_path(path)}: no such drive file") from None
        raise DriveFileError(exc.message) from None


class DriveFile:
    """A drive file read and checked for structure (sections, keys, names), not yet built.

    >>> from beltcalc.catalogs import builtin_dir
    >>> f = DriveFile(builtin_dir() / "drives" / "friswell_5_disks.toml")
    >>> [p.name for p in f.params()][:4]
    ['t_end', 'samples', 'window', 'disk1.inertia']
    """

    def __init__(self, path: str | Path, data: dict | None = None):
        self.path = Path(path)
        self.generated = data is not None       # built in code: bare numbers are SI values
        self._params: list[DriveParam] | None = None
        self._known_names: set[str] | None = None
        self._values: dict = {}                 # (entry, key) -> what a build reads of the file itself
        if data is None:
            data = _read_toml(self.path)
        if not data:           # an empty file, or comments only: say what a drive is, not its first missing key
            raise DriveFileError(f"{shown_path(self.path)}: the file holds no drive (no [drive] section, no [[node]], "
                                 "no element); start from the smallest complete one, catalogs/drives/minimal.toml "
                                 "(a motor, a coupling, a belt and a load; it runs as the drive 'minimal'), and see "
                                 "docs/drive_files.md for every key")
        for key in data:
            if key not in SECTIONS:
                self.fail(key, "", f"unknown section [{key}] / [[{key}]]; "
                                   + did_you_mean(str(key), SECTIONS, listed=len(SECTIONS)))
        head = data.get("drive", {})
        if not isinstance(head, dict):
            self.fail("drive", "", "[drive] must be a table")
        problems: list[tuple[str, str, str]] = []      # (where, key, what): all of them in one message
        self._check_keys(Entry("drive", "drive", 0, head), problems)
        self.head = Entry("drive", "drive", 0, head)
        self.entries: list[Entry] = []
        names: dict[str, str] = {}
        for section in SECTIONS[1:]:
            items = data.get(section, [])
            if not isinstance(items, list) or not all(isinstance(i, dict) for i in items):
                self.fail(section, "", f"write each {section} as [[{section}]]")
            for k, raw in enumerate(items, 1):
                name = raw.get("name", f"{section}{k}")
                if not isinstance(name, str) or not name.strip() or "." in name or "=" in name:
                    problems.append((f"{section} {k}", "name", "must be a text without '.' or '='"))
                    continue
                entry = Entry(section, name, k, raw)
                self._check_keys(entry, problems)
                # names are unique, but a motor may take the name of the node it drives
                if name in names and not (section == "motor" and names[name] == "node" and raw.get("node") == name):
                    problems.append((entry.where, "name", f"repeats the name of a {names[name]}; names are unique"))
                names[name] = section
                self.entries.append(entry)
        if problems:       # with what a build would find missing in the file too, so one try shows all
            self.fail_all(problems + [q for e in self.entries for q in self._kind_missing(e, set(e.raw))])
        self.nodes = {e.name: e for e in self.entries if e.section == "node"}
        if not self.nodes:
            self.fail("node", "", "a drive needs at least one [[node]]")
        self.names = names

    @classmethod
    def from_data(cls, data: dict, name: str) -> "DriveFile":
        """A drive described in code (the parsed-TOML structure: ``{"drive": {...}, "node":
        [...], ...}``) with SI floats allowed for every quantity; ``name`` stands for the
        file in messages. Scenes whose layout depends on their parameters build this way.

        >>> f = DriveFile.from_data({"drive": {"t_end": 1.0}, "node": [{"name": "a", "inertia": 2.0}]}, "demo")
        >>> f.build().network.mass.tolist()
        [2.0]
        """
        return cls(Path(name), data)

    def fail(self, where: str, key: str, message: str):
        """Raise the one-line error of this file."""
        at = f"{where}: {key}" if key else where
        raise DriveFileError(f"{self.path}: {at}: {message}")

    def fail_all(self, problems: list[tuple[str, str, str]]):
        """Raise one error for all ``problems`` (where, key, what): one line, each problem
        as :meth:`fail` says it."""
        if len(problems) == 1:
            self.fail(*problems[0])
        text = "; ".join(f"{where}: {key}: {what}" if key else f"{where}: {what}" for where, key, what in problems)
        raise DriveFileError(f"{self.path}: {len(problems)} problems: {text}")

    def _check_keys(self, entry: Entry, problems: list) -> None:
        """Append to ``problems`` every unknown key of ``entry``, every key its section needs
        that it lacks, and for a motor every key its kind does not have."""
        keys = KEYS[entry.section]
        for key in entry.raw:
            if key not in keys:
                problems.append((entry.where, key, f"unknown key; {did_you_mean(str(key), keys, listed=len(keys))}"))
        for key, spec in keys.items():
            if spec.required and key not in entry.raw and not (key == "name" and entry.section != "node"):
                problems.append((entry.where, key, f"missing ({spec.help})"))
        kind = entry.raw.get("kind") if entry.section == "motor" else None
        if kind is not None and kind not in KINDS:
            problems.append((entry.where, "kind", f"{kind!r} is not a kind; {did_you_mean(str(kind), KINDS)}"))
        elif kind is not None:
            allowed = KIND_KEYS[kind]
            for key in entry.raw:
                if key in keys and key not in allowed | {"name", "kind", "node"}:
                    problems.append((entry.where, key, f"not a key of a {kind} motor (it has "
                                                       f"{', '.join(sorted(allowed))})"))

    def _kind_missing(self, e: Entry, given: set) -> list[tuple[str, str, str]]:
        """What a motor of ``e``'s kind needs and ``given`` (its keys in the file and set)
        lacks, as (where, key, what)."""
        kind = e.raw.get("kind") if e.section == "motor" else None
        if kind not in KINDS:
            return []
        help_of = KEYS["motor"]
        need = {"induction": ("supply", "breakdown_factor", "breakdown_slip"), "speed_loop": ("gain", "reference"),
                "torque": ("torque",), "prescribed": ("max_speed", "max_accel") if "distance" in given else ()}[kind]
        out = [(e.where, key, f"missing ({help_of[key].help})") for key in need if key not in given]
        if kind == "induction":
            if "rated_torque" not in given and not {"rated_power", "rated_speed"} <= given:
                out.append((e.where, "rated_torque", "missing: give rated_torque, or rated_power and rated_speed"))
            if "pole_pairs" not in given and "rated_speed" not in given:
                out.append((e.where, "pole_pairs", "missing: give it, or rated_speed to infer it from the supply"))
        return out

    def check_motors(self, values: dict) -> None:
        """Every key the motors' kinds need that neither the file nor ``values`` (addresses
        set) gives: one :class:`DriveFileError` naming them all."""
        problems = []
        for e in self.entries:
            if e.section == "motor":
                given = set(e.raw) | {a.split(".", 1)[1] for a in values if a.startswith(f"{e.name}.")}
                problems += self._kind_missing(e, given)
        if problems:
            self.fail_all(problems)

    # --- parameters -------------------------------------------------------------------------
    def unit(self, e: Entry, key: str) -> str:
        """The SI unit of ``key`` of entry ``e``: a key of either dimension (a torque or a
        force, ``N*m|N``) takes the one of the node it acts on (rotating or translating)."""
        unit = KEYS[e.section][key].unit
        if "|" not in unit or e.section not in ("coupling", "load", "motor") or "Hz" in unit.split("|"):
            return unit             # (a frequency in time, rad/s or Hz, is the same on either node)
        node = e.raw.get("between", [None])[0] if e.section == "coupling" else e.raw.get("node")
        entry = self.nodes.get(node) if isinstance(node, str) else None
        if entry is None:
            return unit
        translating = "mass" in entry.raw
        head, _, tail = unit.rpartition(",") if unit.startswith("table:") else ("", "", unit)
        pick = tail.split("|")[1 if translating else 0]
        return f"{head}," + pick if head else pick

    def params(self) -> list[DriveParam]:
        """Every addressable value: the timing, then ``ELEMENT.KEY`` of every element, with
        the file's text where the file gives it."""
        if self._params is None:
            self._params = self._list_params()
        return list(self._params)

    def _list_params(self) -> list[DriveParam]:
        out = [DriveParam(k, KEYS["drive"][k].unit, _text(self.head.raw.get(k)), KEYS["drive"][k].help)
               for k in ("t_end", "samples", "window")]
        for e in self.entries:
            for key, spec in KEYS[e.section].items():
                if spec.scalar and key not in ("name", "node", "from", "to", "kind"):
                    out.append(DriveParam(f"{e.name}.{key}", self.unit(e, key), _text(e.raw.get(key)), spec.help))
        return out

    # --- building -----------------------------------------------------------------------------
    def build(self, values: dict | None = None, catalog=None) -> Drive:
        """The drive with ``values`` ({address: SI float, (float, unit), int or text}) instead
        of the file's. Every value is converted and checked; the first problem is one
        :class:`DriveFileError` naming the element and key."""
        values = self._known(values)
        try:
            b, net = self._assemble(values, catalog)
        except FloatRangeError as exc:
            raise self._blame(exc, values, catalog) from None
        t_end, samples, window = b.timing()
        drive = Drive(title=b.head_text("title") or self.path.stem, path=str(self.path), network=net, t_end=t_end,
                      samples=samples, window=window, notes=b.notes, nodes=[n.name for n in net.nodes],
                      torques=b.torques, spans=b.spans, limits=b.limits, motors=b.motor_signals, fits=b.fits,
                      inputs=b.used)
        if b.rigid:
            drive.notes += _rigid_notes(self, values, catalog, net, b.rigid)
        return drive

    def _blame(self, exc: FloatRangeError, values: dict, catalog) -> BeltcalcError:
        """An overflow of the drive built with ``values``: about the value set (``--set``)
        that makes it (:func:`beltcalc.errors.blame`), else about the file."""
        units = {p.name: p.unit for p in self.params()}

        def probe(name):
            self._assemble({k: v for k, v in values.items() if k != name}, catalog)

        def show(name):
            v = values[name]
            v, unit = v if isinstance(v, tuple) else (v, units.get(name, ""))
            unit = "" if unit in ("", "1", None) or "|" in unit else f" {unit}"
            return f"{v:g}{unit}" if isinstance(v, (int, float)) else repr(v)

        found = blame(exc, values, probe, show)
        return found if found.param is not None else DriveFileError(f"{self.path}: {exc.message}")

    def network(self, values: dict | None = None, catalog=None):
        """Only the :class:`~beltcalc.sim.network.Network` of the drive (no timing, no notes):
        what a scene that writes its drive in code runs."""
        return self._assemble(self._known(values), catalog)[1]

    def _known(self, values: dict | None) -> dict:
        values = dict(values or {})
        if self._known_names is None:
            self._known_names = {p.name for p in self.params()}
        known = self._known_names
        for name in values:
            if name not in known:
                raise InputError(f"{name!r} is not a value of this drive file ({self.path.name}); "
                                 + did_you_mean(str(name), [p.name for p in self.params()]), param=name,
                                 scope="scene")
        return values

    def _assemble(self, values: dict, catalog, flexible: bool = False):
        """(the builder, the network) of ``values``; ``flexible`` keeps rigid couplings elastic."""
        from beltcalc.sim.network import Network

        self.check_motors(values)
        b = _Builder(self, values, catalog, flexible)
        try:
            with float_range(lambda: f"a value of {b.current}"):
                parts = b.elements()
        except FloatRangeError:
            raise
        except BeltcalcError as exc:
            if isinstance(exc, DriveFileError) or exc.scope == "scene":
                raise
            raise DriveFileError(f"{self.path}: {b.current}: {exc.message}") from None
        try:
            with float_range("the drive's model"):
                net = Network(parts["nodes"], parts["couplings"], parts["loads"], parts["motors"] or None,
                              prescribed=parts["prescribed"], strands=parts["strands"],
                              speed_loops=parts["speed_loops"], gears=parts["gears"],
                              elements=parts.get("elements", []))
                net.first_order()          # every entry of the first-order system is finite (cached)
        except FloatRangeError:
            raise
        except BeltcalcError as exc:
            raise DriveFileError(f"{self.path}: {exc.message}") from None
        return b, net


@lru_cache(maxsize=1)
def _builtin_catalog():
    """The built-in catalogs, read once per process (a sweep builds its drive many times)."""
    from beltcalc.catalogs import load_catalog

    return load_catalog()


def _few(names: list[str], shown: int = 6) -> str:
    """``a, b, c`` or ``a, b, ... and 12 more``."""
    if len(names) <= shown:
        return ", ".join(names)
    return ", ".join(names[:shown]) + f" and {len(names) - shown} more"


def _text(value) -> str | None:
    if value is None:
        return None
    return str(value)


_MISSING = object()          # a key the file does not give


class _Builder:
    """Turns the entries into elements, converting each value once (SI floats)."""

    def __init__(self, drive_file: DriveFile, values: dict, catalog, flexible: bool = False):
        self.f, self.values, self.flexible = drive_file, values, flexible
        self._catalog = catalog
        self.current = "drive"
        self.notes: list[str] = []
        self.torques: list[tuple[str, str]] = []
        self.spans: dict[str, float] = {}
        self.limits: dict[str, tuple[float, str]] = {}
        self.fits: dict[str, tuple[float, str]] = {}   # belt span -> (R^2, the fit), as `tension` checks it
        self.motor_signals: list[tuple[str, str]] = []
        self.rigid: list[str] = []
        self.used: dict = {}
        self.weighed: list[str] = []            # strands whose mass went to their end nodes
        self.unweighed: list[str] = []          # strands whose catalog has no mass
        self.node_entries = {e.name: e for e in drive_file.entries if e.section == "node"}

    @property
    def catalog(self):
        if self._catalog is None:
            self._catalog = _builtin_catalog()
        return self._catalog

    # --- values ---------------------------------------------------------------------------
    def get(self, e: Entry, key: str, default=None):
        """The SI value of ``key`` of entry ``e`` (an override first), or ``default``; a
        value out of its key's range is refused, naming the file's element and key (or the
        address, when the value was set). What the file itself gives (its unit, address and
        checked value) is worked out on the first build and kept on the drive file: a study
        builds the drive thousands of times with a few values changed."""
        hit = self.f._values.get((id(e), key))
        if hit is None:
            spec = KEYS[e.section][key]
            unit = self.f.unit(e, key)
            value = _MISSING
            if key in e.raw:
                try:
                    value = _convert(e.raw[key], Key(unit, spec.help), si_numbers=self.f.generated)
                except (ValueError, TypeError) as exc:
                    self.f.fail(e.where, key, str(exc))
                problem = _out_of_range(value, spec, unit)
                if problem:
                    self.f.fail(e.where, key, problem)
            hit = self.f._values[(id(e), key)] = (spec, unit, key if e.section == "drive" else f"{e.name}.{key}",
                                                  value)
        spec, unit, address, value = hit
        if address in self.values:
            value = self.values[address]
            value = value[0] if isinstance(value, tuple) else value
            self.used[address] = (value, "set")
            problem = _out_of_range(value, spec, unit)
            if problem:
                raise InputError(problem, param=address, scope="scene")
            return value
        if value is _MISSING:
            return default
        if spec.scalar:
            self.used[address] = (value, "file")
        return value

    def get_unit(self, e: Entry, key: str):
        """(SI value, unit) of a key with alternative dimensions, or (None, None)."""
        spec = KEYS[e.section][key]
        address = f"{e.name}.{key}"
        if address in self.values:
            v = self.values[address]
            return v if isinstance(v, tuple) else (v, spec.unit.split("|")[0])
        if key not in e.raw:
            return None, None
        try:
            return _convert(e.raw[key], spec, keep_unit=True, si_numbers=self.f.generated)
        except (ValueError, TypeError) as exc:
            self.f.fail(e.where, key, str(exc))

    def need(self, e: Entry, key: str):
        value = self.get(e, key)
        if value is None:
            self.f.fail(e.where, key, f"missing ({KEYS[e.section][key].help})")
        return value

    def node_name(self, e: Entry, key: str) -> str:
        name = e.raw.get(key)
        if not isinstance(name, str):
            self.f.fail(e.where, key, "must name a node")
        if name not in self.node_entries:
            self.f.fail(e.where, key, f"{name!r} is not a node of this drive; "
                                      + did_you_mean(name, sorted(self.node_entries)))
        return name

    def between(self, e: Entry, count: tuple[int, ...]) -> list[str]:
        ends = e.raw.get("between")
        if not isinstance(ends, list) or len(ends) not in count or not all(isinstance(x, str) for x in ends):
            self.f.fail(e.where, "between", f"must list {' or '.join(map(str, count))} node names")
        for name in ends:
            if name not in self.node_entries:
                self.f.fail(e.where, "between", f"{name!r} is not a node of this drive; "
                                                + did_you_mean(name, sorted(self.node_entries)))
        return ends

    def head_text(self, key: str):
        return self.get(self.f.head, key)

    def timing(self) -> tuple[float, int, float]:
        h = self.f.head
        self.current = "drive"
        t_end = self.need(h, "t_end")
        samples = self.get(h, "samples", 2001)
        window = self.get(h, "window", 0.0)
        if not (t_end > 0 and math.isfinite(t_end)):
            self.f.fail("drive", "t_end", f"{t_end:g} s; it must be > 0 s")
        if samples != int(samples) or not 2 <= samples <= 10_000_000:
            self.f.fail("drive", "samples", f"{samples}; it must be a whole number 2..10,000,000")
        if not 0 <= window < t_end:
            self.f.fail("drive", "window", f"{window:g} s is not inside the run (0..{t_end:g} s)")
        return t_end, int(samples), window

    # --- elements -------------------------------------------------------------------------
    def elements(self) -> dict:
        parts = {k: [] for k in ("nodes", "couplings", "loads", "motors", "prescribed", "strands",
                                 "speed_loops", "gears")}
        self.inertia: dict[str, float] = {}      # node -> its inertia, with the shares of shafts and strands
        self.radius: dict[str, float] = {}
        for e in self.f.entries:
            self.current = e.where
            getattr(self, f"_{e.section}")(e, parts)
        from beltcalc.sim.network import Inertia

        parts["nodes"] = [Inertia(n.name, self.inertia[n.name], n.translation) for n in parts["nodes"]]
        if self.weighed:
            self.notes.append(f"strand masses: half of each strand's mass to each end node ({_few(self.weighed)})")
        if self.unweighed:
            self.notes.append(f"strand masses not counted (the catalog has none; give mass): {_few(self.unweighed)}")
        return parts

    def _node(self, e: Entry, parts) -> None:
        from beltcalc.sim.network import Inertia

        inertia, mass = self.get(e, "inertia"), self.get(e, "mass")
        if (inertia is None) == (mass is None):
            self.f.fail(e.where, "inertia", "give exactly one of inertia (rotating) or mass (translating)")
        value = inertia if mass is None else mass
        if not (value >= 0 and math.isfinite(value)):
            self.f.fail(e.where, "inertia" if mass is None else "mass", f"{value:g} is not allowed; it must be >= 0")
        parts["nodes"].append(Inertia(e.name, value, translation=mass is not None))
        self.inertia[e.name] = value
        d = self.get(e, "pitch_diameter")
        teeth = self.get(e, "teeth")
        if d is None and teeth is not None:
            belt, chain = e.raw.get("belt"), e.raw.get("chain")
            if (belt is None) == (chain is None):
                self.f.fail(e.where, "teeth", "give the belt or the chain that runs on it (for the pitch diameter)")
            if belt is not None:
                from beltcalc.belt import pulley_pitch_diameter

                d = pulley_pitch_diameter(teeth, self.lookup(e, "belt", "belt").pitch)
            else:
                from beltcalc.chain import sprocket_pitch_diameter

                d = sprocket_pitch_diameter(self.lookup(e, "chain", "chain").pitch, teeth)
        if d is not None:
            if not d > 0:
                self.f.fail(e.where, "pitch_diameter", f"{d:g} m; it must be > 0 m")
            self.radius[e.name] = d / 2

    def lookup(self, e: Entry, key: str, kind: str):
        name = self.get(e, key)
        try:
            return getattr(self.catalog, kind)(name)
        except BeltcalcError as exc:
            self.f.fail(e.where, key, exc.message)

    def _coupling(self, e: Entry, parts) -> None:
        from beltcalc.sim.network import Coupling, Gear

        ends = self.between(e, (1, 2))
        C, d = self.need(e, "stiffness"), self.get(e, "damping", 0.0)
        U = self.get(e, "ratio", 1.0)
        j = ends[1] if len(ends) == 2 else None
        if e.raw.get("rigid") is True and not self.flexible:
            if j is None:
                self.f.fail(e.where, "rigid", "a rigid coupling to the frame would hold the node still; "
                                              "use a prescribed motor of speed 0")
            parts["gears"].append(Gear(ends[0], j, U, name=e.name))
            self.rigid.append(e.name)
            return
        if (self.get(e, "eccentricity", 0.0) or 0.0) > 0:    # else the roller's keys change nothing
            self._eccentric(e, parts, ends, j, C, d, U)
            return
        parts["couplings"].append(Coupling(e.name, ends[0], j, C, d, U))
        self.torques.append((f"T_{e.name}", e.name))

    def _eccentric(self, e: Entry, parts, ends, j, C, d, U) -> None:
        """A belt coupling with an eccentric tension roller (:class:`~beltcalc.sim.eccentric.EccentricBelt`)."""
        from beltcalc.sim.beltpath import Eccentric
        from beltcalc.sim.eccentric import EccentricBelt

        if j is None:
            self.f.fail(e.where, "eccentricity", "a tension roller needs a belt between two nodes")
        if e.raw.get("rigid") is True:
            self.f.fail(e.where, "rigid", "a coupling with an eccentric tension roller cannot be rigid")
        r1 = self.get(e, "pulley_radius", self.radius.get(ends[0]))
        if r1 is None:
            self.f.fail(e.where, "pulley_radius", f"give it, or a pitch diameter on node {ends[0]!r}")
        geo = Eccentric(r1=r1, r2=U * r1, a=self.need(e, "center_distance"), r3=self.need(e, "roller_radius"),
                        px=self.need(e, "pivot_x"), py=self.need(e, "pivot_y"), delta=self.need(e, "eccentricity"),
                        theta0=self.get(e, "roller_angle", 0.0))
        parts.setdefault("elements", []).append(EccentricBelt(e.name, ends[0], j, C, d, geo))
        self.torques.append((f"T_{e.name}", e.name))

    def _shaft(self, e: Entry, parts) -> None:
        from beltcalc.chain import torsional_stiffness
        from beltcalc.sim.network import Coupling

        a, b = self.between(e, (2,))
        D, bore, L = self.need(e, "diameter"), self.get(e, "bore", 0.0), self.need(e, "length")
        G, rho = self.get(e, "shear_modulus"), self.get(e, "density")
        material = self.get(e, "material")
        if material is not None:
            props = _materials(self.f, e).get(material)
            if props is None:
                self.f.fail(e.where, "material", f"{material!r} is not in catalogs/materials.toml "
                                                 f"({', '.join(_materials(self.f, e))})")
            G = props["shear_modulus"] if G is None else G
            rho = props["density"] if rho is None else rho
        if G is None:
            self.f.fail(e.where, "shear_modulus", "give the material or the shear modulus")
        C = torsional_stiffness(D, bore, L, G)
        beta = self.get(e, "damping_time")
        d = self.get(e, "damping", 0.0) if beta is None else beta * C
        parts["couplings"].append(Coupling(e.name, a, b, C, d))
        self.torques.append((f"T_{e.name}", e.name))
        if rho:
            from beltcalc.drive import cylinder_inertia

            J = cylinder_inertia(D, bore, L, rho)
            for node in (a, b):
                self.inertia[node] += J / 2
            self.notes.append(f"shaft {e.name}: C = {C:.5g} N m/rad; its own inertia {J:.4g} kg m^2, half to "
                              f"{a} and half to {b}")

    def _gear(self, e: Entry, parts) -> None:
        from beltcalc.sim.network import Gear

        a, b = self.between(e, (2,))
        parts["gears"].append(Gear(a, b, self.need(e, "ratio"), name=e.name))

    def _end_radius(self, e: Entry, key: str) -> tuple[str, float]:
        node = self.node_name(e, key)
        if self.node_entries[node].raw.get("mass") is not None:
            return node, 1.0
        r = self.radius.get(node)
        if r is None:
            self.f.fail(e.where, key, f"node {node!r} has no pitch diameter: give it teeth and the belt/chain, "
                                      "or pitch_diameter")
        return node, r

    def _belt_span(self, e: Entry, parts) -> None:
        from beltcalc import belt as bm
        from beltcalc.sim.network import Coupling, Strand

        (i, r_i), (j, r_j) = self._end_radius(e, "from"), self._end_radius(e, "to")
        belt = self.lookup(e, "belt", "belt")
        width, length = self.need(e, "width"), self.need(e, "length")
        try:
            row = belt.width_row(width)
        except BeltcalcError as exc:
            self.f.fail(e.where, "width", exc.message)
        if row.C_spec is None:
            self.f.fail(e.where, "belt", f"{belt.name} has no C_spec for {width * 1e3:g} mm in its catalog")
        k = bm.belt_stiffness(row.C_spec, length)
        b = self.get(e, "damping")
        if b is None:
            b, why = self._belt_damping(e, belt, width, length, i if r_i != 1.0 else j)
            self.notes.append(f"belt span {e.name}: k = C_spec / L = {k:.5g} N/m, b = {b:.4g} N s/m {why}")
        F0 = self.get(e, "pretension", 0.0)
        self._strand_mass(e, (i, r_i), (j, r_j), row.w_spec, length)
        if row.F_Tadm:
            self.limits[e.name] = (row.F_Tadm, "F_Tadm")
        if e.raw.get("tension_only", True) is False:
            # one two-way spring k = C_spec / L (the substitute model, Wojtkowiak et al. eq. 5):
            # C (phi_i - U phi_j) with C = k r_i^2, U = r_j / r_i: the torque r_i F
            parts["couplings"].append(Coupling(e.name, i, j, k * r_i ** 2, b * r_i ** 2, r_j / r_i))
            self.spans[e.name] = r_i
            return
        parts["strands"].append(Strand(e.name, i, j, r_i, r_j, k, b, F0))

    def _belt_damping(self, e: Entry, belt, width: float, length: float, pulley: str) -> tuple[float, str]:
        """b_TB as `beltcalc tension` finds it: fitted to F_tspec(n) on the pulley the span
        leaves (Wojtkowiak et al. 2021, section 3.2), or the catalog's value."""
        from beltcalc import belt as bm

        if belt.F_tspec and pulley in self.radius:
            D = 2 * self.radius[pulley]
            z = max(1, round(math.pi * D / belt.pitch))
            z_e = bm.teeth_in_mesh(z, z, belt.pitch, length, belt.z_e_max)
            fit = bm.damping_from_tooth_load(belt.F_tspec, D, width, z_e)
            how = f"fitted to the catalog's F_tspec(n) on {pulley}, D = {D * 1e3:.4g} mm, z_e = {z_e:g}"
            self.fits[e.name] = (fit.r_squared, how)
            return fit.damping, f"({how}, R^2 = {fit.r_squared:.3f})"
        if belt.damping is not None:
            return belt.damping, f"(catalog value: {belt.damping_source or belt.source})"
        self.f.fail(e.where, "damping", f"{belt.name} has no F_tspec(n) table and no damping value; give damping")

    def _chain_strand(self, e: Entry, parts) -> None:
        from beltcalc.chain import strand_stiffness
        from beltcalc.sim.network import Strand

        (i, r_i), (j, r_j) = self._end_radius(e, "from"), self._end_radius(e, "to")
        chain = self.lookup(e, "chain", "chain")
        length = self.need(e, "length")
        c = strand_stiffness(self.need(e, "stiffness"), length)
        beta = self.get(e, "damping_time")
        b = self.get(e, "damping", 0.0) if beta is None else beta * c
        parts["strands"].append(Strand(e.name, i, j, r_i, r_j, c, b, self.get(e, "pretension", 0.0)))
        self.limits[e.name] = (self.get(e, "breaking_load", chain.breaking_load), "breaking load")
        self._strand_mass(e, (i, r_i), (j, r_j), self.get(e, "mass", chain.mass), length)

    def _strand_mass(self, e: Entry, end_i, end_j, per_length: float | None, length: float) -> None:
        """Half the strand's mass m L moves with each end: inertia m L r^2 / 2 on a pulley or
        sprocket of pitch radius r, mass m L / 2 on a translating node (Rusek & Popenda's
        lumping of the chain's mass into the sprockets)."""
        if per_length is None:
            self.unweighed.append(e.name)
            return
        for node, r in (end_i, end_j):
            translating = self.node_entries[node].raw.get("mass") is not None
            share = per_length * length / 2 * (1.0 if translating else r ** 2)
            self.inertia[node] += share
        self.weighed.append(e.name)

    def _motor(self, e: Entry, parts) -> None:
        from beltcalc.sim.network import InductionMotor, Load, Prescribed, SpeedLoop

        kind, node = self.need(e, "kind"), self.node_name(e, "node")
        if kind not in KINDS:           # (the file's own kind is checked on reading; this is a kind set)
            self.f.fail(e.where, "kind", f"{kind!r} is not a kind; {did_you_mean(str(kind), KINDS)}")
        if kind == "induction":
            speed = self.get(e, "rated_speed")
            torque = self.get(e, "rated_torque")
            if torque is None:
                torque = self.need(e, "rated_power") / speed
            f = self.need(e, "supply")
            pairs = self._pole_pairs(e, self.get(e, "pole_pairs"), speed, f)
            w0 = 2 * math.pi * f / pairs
            ramp = self.get(e, "ramp", 0.0)
            table = ((0.0, 0.0), (ramp, w0)) if ramp else ()
            parts["motors"].append(InductionMotor(node, self.need(e, "breakdown_factor") * torque,
                                                  self.need(e, "breakdown_slip"), w0, 2 * math.pi * f,
                                                  sync_table=table, name=e.name))
            self.motor_signals.append((f"M_{e.name}", node))
        elif kind == "prescribed":
            parts["prescribed"].append(Prescribed(node, self.get(e, "speed", 0.0), self._move(e)))
            self.motor_signals.append((f"T_drive_{node}", node))
        elif kind == "speed_loop":
            ref = self.get(e, "reference")
            if ref is None:
                self.f.fail(e.where, "reference", "a speed loop needs its speed reference table")
            parts["speed_loops"].append(SpeedLoop(node, self.need(e, "gain"), ref, self.get(e, "feedforward", ())))
            self.motor_signals.append((f"T_drive_{node}", node))
        else:
            table = self.need(e, "torque")
            parts["loads"].append(Load(node, table=tuple((t, -v) for t, v in table)))

    def _pole_pairs(self, e: Entry, pairs, rated_speed, supply: float) -> int:
        """The motor's pole pairs: as given, checked against the rated speed and the supply
        when the file gives both (a rated slip in (0, :data:`MAX_RATED_SLIP`]); else inferred
        from them (:func:`pole_pairs_from_speed`), and a note says so."""
        if pairs is not None and pairs < 1:
            self.f.fail(e.where, "pole_pairs", f"{pairs}; it must be >= 1")
        if rated_speed is None:
            return pairs
        rpm = rated_speed * 30 / math.pi
        if pairs is None:
            p, slip = pole_pairs_from_speed(rated_speed, supply)
            if p < 1 or slip > MAX_RATED_SLIP:
                sync = f"{2 * math.pi * supply / p * 30 / math.pi:.6g} rpm with {p} pole pairs" if p else "none"
                self.f.fail(e.where, "rated_speed", f"{rpm:.6g} rpm fits no pole count at the supply {supply:.6g} Hz "
                                                    f"(the synchronous speed just above it: {sync}; rated slip "
                                                    f"{percent(slip, 1)}, an induction motor's is 0..{MAX_RATED_SLIP:.0%}): "
                                                    "check rated_speed and supply (the rated speed at that "
                                                    "frequency), or give pole_pairs")
            self.notes.append(f"motor {e.name}: pole_pairs = {p}, inferred from rated_speed {rpm:.6g} rpm and "
                              f"supply {supply:.6g} Hz (synchronous {2 * math.pi * supply / p * 30 / math.pi:.6g} "
                              f"rpm, rated slip {slip:.2%})")
            return p
        sync = 2 * math.pi * supply / pairs
        slip = 1 - rated_speed / sync
        if not 0 < slip <= MAX_RATED_SLIP:
            self.f.fail(e.where, "pole_pairs", f"{pairs} pole pairs at the supply {supply:.6g} Hz turn at "
                                               f"{sync * 30 / math.pi:.6g} rpm synchronous; the rated_speed "
                                               f"{rpm:.6g} rpm gives a rated slip of {percent(slip, 1)}, outside "
                                               f"0..{MAX_RATED_SLIP:.0%} (NEMA design D, the high-slip motors: "
                                               "up to 13 %): check pole_pairs, rated_speed and supply")
        return pairs

    def _move(self, e: Entry) -> tuple:
        accel = self.get(e, "accel")
        distance = self.get(e, "distance")
        if accel is not None and distance is not None:
            self.f.fail(e.where, "distance", "give an accel table or a move (distance, max_speed, max_accel), not both")
        if distance is None:
            return tuple(accel or ())
        from beltcalc import profiles

        speed, acc = self.need(e, "max_speed"), self.need(e, "max_accel")
        jerk = self.get(e, "jerk")
        profile = (profiles.scurve(speed, acc, jerk, distance) if jerk is not None
                   else profiles.trapezoid(speed, acc, distance))
        t = self.get(e, "start", 0.0)
        table = []
        for ph in profile.phases:
            if ph.duration > 0:
                table += [(t, ph.accel), (t + ph.duration, ph.accel1)]
                t += ph.duration
        table.append((t, 0.0))
        kind = "S-curve" if jerk is not None else "trapezoid"
        self.notes.append(f"motor {e.name}: {kind} move of {distance:g} over {t - self.get(e, 'start', 0.0):.4g} s "
                          f"(peak speed {profile.peak_speed:.4g})")
        return tuple(table)

    def _load(self, e: Entry, parts) -> None:
        from beltcalc.sim.network import Load

        node = self.node_name(e, "node")
        freq = self.get_unit(e, "frequency")
        omega = 0.0
        if freq[0] is not None:
            omega = freq[0] * (2 * math.pi if freq[1] == "Hz" else 1.0)
        order = self.get(e, "order")
        if order is not None and freq[0]:
            self.f.fail(e.where, "order", "give frequency (in time) or order (in the shaft angle), not both")
        parts["loads"].append(Load(node, self.get(e, "torque", 0.0), self.get(e, "amplitude", 0.0), omega,
                                   self.get(e, "phase", 0.0), in_angle=order is not None,
                                   table=tuple(self.get(e, "table", ())), start=self.get(e, "start", 0.0),
                                   order=1.0 if order is None else order))


def _out_of_range(value, spec: Key, unit: str) -> str:
    """Why ``value`` is outside its key's range, or ``""``."""
    if not spec.low or not isinstance(value, (int, float)) or isinstance(value, bool):
        return ""
    bad = {">0": value <= 0, ">=0": value < 0, "!=0": value == 0}[spec.low]
    if not bad:
        return ""
    u = "" if unit in ("", "int") else " " + unit.split("|")[0]
    if spec.low == "!=0":
        return f"{value:g}{u} is not allowed; it must not be 0{u} (negative: the pair turns the other way)"
    return f"{value:g}{u} is not allowed; it must be {spec.low[0:-1]} 0{u}"


def _convert(raw, spec: Key, keep_unit: bool = False, si_numbers: bool = False):
    """A raw TOML value as its SI value (ValueError with the reason otherwise). A bare number
    is a plain number; for a quantity of a dimension it is refused (a file writes the unit),
    unless ``si_numbers`` (a drive built in code, in SI)."""
    from beltcalc.units import QuantityError, example_unit, parse_quantity, parse_quantity_any

    unit = spec.unit
    if unit == "text":
        if not isinstance(raw, str):
            raise ValueError(f"must be a text, not {raw!r}")
        return raw
    if unit == "bool":
        if not isinstance(raw, bool):
            raise ValueError(f"must be true or false, not {raw!r}")
        return raw
    if unit == "int":
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise ValueError(f"must be a whole number, not {raw!r}")
        return raw
    if unit.startswith("table:"):
        x_unit, y_unit = unit[6:].split(",")
        if not isinstance(raw, list) or not raw or not all(isinstance(p, list) and len(p) == 2 for p in raw):
            raise ValueError("must be a list of [time, value] pairs, e.g. [[\"0 s\", \"0 N*m\"], [\"1 s\", \"5 N*m\"]]")
        out = []
        for t, v in raw:
            out.append((_convert(t, Key(x_unit, ""), si_numbers=si_numbers),
                        _convert(v, Key(y_unit, ""), si_numbers=si_numbers)))
        times = [t for t, _ in out]
        if any(b < a for a, b in zip(times, times[1:])):
            raise ValueError("the times must rise (a time may repeat for a jump)")
        return tuple(out)
    if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
        raise ValueError(f"must be a quantity text such as '5 {example_unit(unit.split('|')[0])}', not {raw!r}")
    if isinstance(raw, str) and unit in ("", "1"):
        raise ValueError(f"must be a plain number, not the text {raw!r}: write it without quotes "
                         "(ratios, factors and slips are numbers, docs/drive_files.md)")
    if not isinstance(raw, str) and unit not in ("", "1"):
        if si_numbers:
            value = float(raw)
            return (value, unit.split("|")[0]) if keep_unit and "|" in unit else value
        example = raw if isinstance(raw, int) or math.isfinite(raw) else 1.0    # "inf s" is refused too
        texts = " or ".join(f'"{example:g} {example_unit(u)}"' for u in unit.split("|"))
        raise ValueError(f"{raw!r} needs its unit: write it as a text, e.g. {texts}")
    try:
        if isinstance(raw, str):
            got = _quantity(raw, unit)
        else:
            got = parse_quantity_any(raw, tuple(unit.split("|"))) if "|" in unit else parse_quantity(raw, unit)
        if "|" in unit:
            value, u = got
            return (value, u) if keep_unit else value
        return got
    except QuantityError as exc:
        raise ValueError(str(exc)) from None


@lru_cache(maxsize=4096)
def _quantity(raw: str, unit: str):
    """The text ``raw`` read as a quantity of ``unit`` (:func:`~beltcalc.units.parse_quantity`; of
    one of ``a|b``: (value, unit), :func:`~beltcalc.units.parse_quantity_any`). Each text
    is read by pint once per process: a build reads every value of the file, and a run
    builds its drive several times (the rigid notes, the error estimate, a sweep's points).
    A refusal is not kept: it is raised again, the same, on every call."""
    from beltcalc.units import parse_quantity, parse_quantity_any

    if "|" in unit:
        return parse_quantity_any(raw, tuple(unit.split("|")))
    return parse_quantity(raw, unit)


def _materials(f: DriveFile, e: Entry) -> dict:
    """catalogs/materials.toml: {name: {"shear_modulus": Pa, "density": kg/m^3}} (shared:
    read only)."""
    from beltcalc.catalogs import builtin_dir

    return _material_table(str(builtin_dir() / "materials.toml"))


@lru_cache(maxsize=2)
def _material_table(path: str) -> dict:
    """The material table at ``path`` in SI floats, read and converted once per process."""
    from beltcalc.units import parse_quantity

    data = _read_toml(Path(path))
    out = {}
    for name, props in data.get("materials", {}).items():
        out[name] = {"shear_modulus": parse_quantity(props["shear_modulus"], "Pa"),
                     "density": parse_quantity(props["density"], "kg/m^3")}
    return out


def _rigid_notes(f: DriveFile, values: dict, catalog, rigid_net, names: list[str]) -> list[str]:
    """What making couplings rigid costs: the undamped frequencies of the flexible drive
    against the rigid one (the rigid drive has one mode fewer per rigid coupling)."""
    import numpy as np

    flex = f._assemble(values, catalog, flexible=True)[1]
    f_flex, f_rigid = undamped_frequencies(flex), undamped_frequencies(rigid_net)
    removed = len(f_flex) - len(f_rigid)
    kept = f_flex[:len(f_rigid)]
    shift = float(np.max(np.abs(np.array(f_rigid) - kept) / kept)) if len(f_rigid) else 0.0
    gone = ", ".join(f"{v:.4g} Hz" for v in f_flex[len(f_rigid):]) or "none"
    return [f"rigid: {', '.join(names)} made rigid; the flexible drive's highest {removed} mode(s) ({gone}) are "
            f"removed and the others move by at most {shift:.2%} (undamped, strands taut)"]


def undamped_frequencies(net) -> list[float]:
    """The undamped natural frequencies [Hz] of a network's elastic modes, lowest first
    (strands taut, motors and prescribed nodes left free; rigid-body modes left out):
    the square roots of the eigenvalues of M^-1 K.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0), Inertia("b", 1.0)], [Coupling("c", "a", "b", 2.0, 0.0)])
    >>> [round(f * 2 * math.pi, 12) for f in undamped_frequencies(net)]
    [2.0]
    """
    import numpy as np

    s = 1.0 / np.sqrt(net.mass)
    w2 = np.linalg.eigvalsh(net.K * s[:, None] * s[None, :])
    floor = 1e-9 * max(1.0, float(np.max(np.abs(w2)))) if w2.size else 0.0
    return sorted(float(math.sqrt(v)) / (2 * math.pi) for v in w2 if v > floor)


def to_toml(data: dict, header: str = "") -> str:
    """A drive described in code (:meth:`DriveFile.from_data`, SI floats) as drive-file text:
    every quantity written with its SI unit (exact: ``repr`` of the float), ``header`` as
    comment lines on top. Reading the text back builds the same drive.

    >>> print(to_toml({"drive": {"t_end": 1.0}, "node": [{"name": "a", "inertia": 0.5}]}))
    [drive]
    t_end = "1.0 s"
    <BLANKLINE>
    [[node]]
    name = "a"
    inertia = "0.5 kg*m^2"
    <BLANKLINE>
    """
    import json

    f = DriveFile.from_data(data, "<data>")

    def value(raw, unit: str) -> str:
        if isinstance(raw, bool):
            return "true" if raw else "false"
        if unit in ("text", "names"):
            return json.dumps(raw)
        if unit.startswith("table:"):
            x, y = unit[6:].split(",")
            return "[" + ", ".join(f"[{value(t, x)}, {value(v, y)}]" for t, v in raw) + "]"
        if unit in ("", "int") or isinstance(raw, str):
            return json.dumps(raw) if isinstance(raw, str) else repr(raw)
        return json.dumps(f"{float(raw)!r} {unit.split('|')[0]}")

    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    if lines:
        lines.append("")
    lines.append("[drive]")
    lines += [f"{k} = {value(v, KEYS['drive'][k].unit)}" for k, v in f.head.raw.items()]
    for e in f.entries:
        lines += ["", f"[[{e.section}]]"]
        lines += [f"{k} = {value(v, f.unit(e, k))}" for k, v in e.raw.items()]
    return "\n".join(lines) + "\n"


def drive_names() -> list[str]:
    """Names of the built-in drive files (``catalogs/drives/*.toml``)."""
    from beltcalc.catalogs import builtin_dir

    return sorted(p.stem for p in (builtin_dir() / "drives").glob("*.toml"))


def drive_path(ref: str | Path) -> Path:
    """A drive file by path, or a built-in one by name (``sewing``)."""
    from beltcalc.catalogs import builtin_dir
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
