"""Reading a drive file: :class:`DriveFile` checks its structure (sections, keys, names) on
reading and builds the :class:`Drive` (a :class:`~beltcalc.sim.network.Network` plus its
timing and notes) with any of its values replaced; every section and key comes from the
registry (:mod:`beltcalc.sim.drivefile.registry`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

from beltcalc.errors import BeltcalcError, FloatRangeError, InputError, blame, did_you_mean, float_range
from beltcalc.data.schema import Field, Quantity, Table, Whole
from beltcalc.sim.drivefile.builder import Builder
from beltcalc.sim.drivefile.keys import DriveFileError, DriveParam, Entry, read_drive_toml, text_of
from beltcalc.sim.drivefile.registry import ELEMENTS, kind_of, sections
from beltcalc.data.tomlsafe import shown_path


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
    fatigue: dict = field(default_factory=dict)      # chain strand -> its StrandFatigue (also ``network.fatigue``)
    teeth: dict[str, int] = field(default_factory=dict)  # node -> teeth of its sprocket or toothed pulley
    lengths: dict[str, float] = field(default_factory=dict)  # chain strand -> its free length [m]
    motors: list[tuple[str, str]] = field(default_factory=list)      # (torque signal, node)
    fits: dict[str, tuple[float, str]] = field(default_factory=dict)  # belt span -> (R^2 of its damping fit, the fit)
    inputs: dict = field(default_factory=dict)                       # address -> (SI value, origin)



class DriveFile:
    """A drive file read and checked for structure (sections, keys, names), not yet built.

    >>> from beltcalc.data.catalogs import builtin_dir
    >>> f = DriveFile(builtin_dir() / "drives" / "friswell_5_disks.toml")
    >>> [p.name for p in f.params()][:4]
    ['t_end', 'samples', 'window', 'disk1.inertia']
    """

    def __init__(self, path: str | Path, data: dict | None = None):
        self.path = Path(path)
        self.generated = data is not None       # built in code: bare numbers are SI values
        self._params: list[DriveParam] | None = None
        self._known_names: set[str] | None = None
        self.file_values: dict = {}             # (entry, key) -> what a build reads of the file itself
        self._complete: set[frozenset] = set()  # the sets of addresses whose values leave no key missing
        if data is None:
            data = read_drive_toml(self.path)
        if not data:           # an empty file, or comments only: say what a drive is, not its first missing key
            raise DriveFileError(f"{shown_path(self.path)}: the file holds no drive (no [drive] section, no [[node]], "
                                 "no element); start from the smallest complete one, catalogs/drives/minimal.toml "
                                 "(a motor, a coupling, a belt and a load; it runs as the drive 'minimal'), and see "
                                 "docs/drive_files.md for every key")
        known = sections()
        for key in data:
            if key not in known:
                self.fail(key, "", f"unknown section [{key}] / [[{key}]]; "
                                   + did_you_mean(str(key), known, listed=len(known)))
        head = data.get("drive", {})
        if not isinstance(head, dict):
            self.fail("drive", "", "[drive] must be a table")
        problems: list[tuple[str, str, str]] = []      # (where, key, what): all of them in one message
        self._check_keys(Entry("drive", "drive", 0, head), problems)
        self.head = Entry("drive", "drive", 0, head)
        self.entries: list[Entry] = []
        names: dict[str, str] = {}
        for section, kind in ELEMENTS.items():
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
                if name in names and not (kind.shares_node_name and names[name] == "node"
                                          and raw.get(kind.node_key) == name):
                    problems.append((entry.where, "name", f"repeats the name of a {names[name]}; names are unique"))
                names[name] = section
                self.entries.append(entry)
        if problems:       # with what a build would find missing in the file too, so one try shows all
            self.fail_all(problems + [q for e in self.entries for q in ELEMENTS[e.section].missing(e, set(e.raw))])
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
        that it lacks, and what its kind finds wrong (a motor's key its kind does not have)."""
        keys = kind_of(entry.section).keys
        for key in entry.raw:
            if key not in keys:
                problems.append((entry.where, key, f"unknown key; {did_you_mean(str(key), keys, listed=len(keys))}"))
        for key, spec in keys.items():
            if spec.required and key not in entry.raw and not (key == "name" and entry.section != "node"):
                problems.append((entry.where, key, f"missing ({spec.help})"))
        problems += kind_of(entry.section).problems(entry)

    def check_needed(self, values: dict) -> None:
        """Every key the entries' kinds need (a motor's, by its kind) that neither the file nor
        ``values`` (addresses set) gives: one :class:`DriveFileError` naming them all. Which
        keys are missing depends only on the addresses set: a set that leaves none is kept (a
        study builds the drive thousands of times with the same addresses)."""
        addresses = frozenset(values)
        if addresses in self._complete:
            return
        set_keys: dict[str, set] = {}
        for address in values:
            name, dot, key = address.partition(".")
            if dot:
                set_keys.setdefault(name, set()).add(key)
        problems = []
        for e in self.entries:
            problems += ELEMENTS[e.section].missing(e, set(e.raw) | set_keys.get(e.name, set()))
        if problems:
            self.fail_all(problems)
        if len(self._complete) < 64:
            self._complete.add(addresses)

    # --- parameters -------------------------------------------------------------------------
    def field_of(self, e: Entry, key: str) -> Field:
        """The field of ``key`` of entry ``e``: a quantity of either dimension (a torque or
        a force, ``N*m|N``; a table's values) takes the one of the node it acts on
        (rotating or translating)."""
        spec = kind_of(e.section).keys[key]
        column = spec.columns[1] if isinstance(spec, Table) else spec
        unit = column.unit if isinstance(column, Quantity) else ""
        node_key = kind_of(e.section).node_key
        if "|" not in unit or not node_key or "Hz" in unit.split("|"):
            return spec             # (a frequency in time, rad/s or Hz, is the same on either node)
        node = e.raw.get(node_key)
        if isinstance(node, list):  # between = [node a, node b]: the first
            node = node[0] if node else None
        entry = self.nodes.get(node) if isinstance(node, str) else None
        if entry is None:
            return spec
        column = replace(column, unit=unit.split("|")[1 if "mass" in entry.raw else 0])
        return replace(spec, columns=(spec.columns[0], column)) if isinstance(spec, Table) else column

    def unit(self, e: Entry, key: str) -> str:
        """The unit of the value ``key`` of entry ``e`` as :class:`DriveParam` gives it: a
        quantity's SI unit (of the node it acts on, :meth:`field_of`), ``"int"`` for a whole
        number, ``"text"`` for a text (the scalar keys: those ``--set`` can give)."""
        spec = self.field_of(e, key)
        return spec.unit if isinstance(spec, Quantity) else "int" if isinstance(spec, Whole) else "text"

    def params(self) -> list[DriveParam]:
        """Every addressable value: the timing, then ``ELEMENT.KEY`` of every element, with
        the file's text where the file gives it."""
        if self._params is None:
            self._params = self._list_params()
        return list(self._params)

    def _list_params(self) -> list[DriveParam]:
        head = kind_of("drive").keys
        out = [DriveParam(k, self.unit(self.head, k), text_of(self.head.raw.get(k)), head[k].help)
               for k in ("t_end", "samples", "window")]
        for e in self.entries:
            for key, spec in kind_of(e.section).keys.items():
                if spec.scalar and key not in ("name", "node", "from", "to", "kind"):
                    out.append(DriveParam(f"{e.name}.{key}", self.unit(e, key), text_of(e.raw.get(key)), spec.help))
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
                      inputs=b.used, fatigue=b.fatigue, teeth=b.teeth, lengths=b.lengths)
        if b.rigid:
            drive.notes += self._rigid_notes(values, catalog, net, b.rigid)
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

        self.check_needed(values)
        b = Builder(self, values, catalog, flexible)
        try:
            with float_range(lambda: f"a value of {b.current}"):
                nodes, elements = b.build()
        except FloatRangeError:
            raise
        except BeltcalcError as exc:
            if isinstance(exc, DriveFileError) or exc.scope == "scene":
                raise
            raise DriveFileError(f"{self.path}: {b.current}: {exc.message}") from None
        try:
            with float_range("the drive's model"):
                net = Network(nodes, elements)
                # what a strand's fatigue check needs travels with the network (a scene that
                # writes its drive in code gets only the network)
                net.fatigue = dict(b.fatigue)
                net.first_order()          # every entry of the first-order system is finite (cached)
        except FloatRangeError:
            raise
        except BeltcalcError as exc:
            raise DriveFileError(f"{self.path}: {exc.message}") from None
        return b, net

    def _rigid_notes(self, values: dict, catalog, rigid_net, names: list[str]) -> list[str]:
        """What making couplings rigid costs: the undamped frequencies of the flexible drive
        against the rigid one (the rigid drive has one mode fewer per rigid coupling)."""
        import numpy as np

        flex = self._assemble(values, catalog, flexible=True)[1]
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
