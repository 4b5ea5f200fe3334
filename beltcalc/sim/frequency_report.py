"""What the frequency-domain commands ask of a drive beyond :mod:`beltcalc.sim.frequency`:
the drive with values set, every pole with its mode shape as one JSON-ready list, the
inputs, outputs and frequency range a response takes when none are named, and the speed
range of a Campbell diagram (the reference node's speed when the motor turns at its
synchronous speed). SI floats only; nothing here prints, parses options or writes files.

Poles and shapes come from the state matrix the time simulation propagates (strands taut):
the same model in both domains.

References:

[ISO 10823] ISO 10823:2004, Guidance on the selection of roller chain drives: the polygon
    effect at the tooth-passing frequency z n.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from beltcalc.errors import InputError, UnknownNameError, UsageError, did_you_mean, require_positive
from beltcalc.sim import frequency as fr

RUN_UP_MARGIN = 1.2          # default Campbell speed range: this times the motor's synchronous speed
BAND = (0.1, 10.0)           # default response range: these times the lowest and highest mode frequency
UNDAMPED = 1e-9              # damping ratio below which a mode counts as undamped (|H| unbounded there)


def load(ref: str | Path, values: dict | None = None, catalog=None):
    """The drive file ``ref`` (a path or a built-in name) built with ``values``
    ({``ELEMENT.KEY``: SI value}) over the file's own: a
    :class:`~beltcalc.sim.drivefile.Drive`.

    >>> load("sewing", {"23.stiffness": 190.0}).network.couplings[1].C
    190.0
    """
    from beltcalc.sim.drivefile import DriveFile, drive_path

    return DriveFile(drive_path(ref)).build(values, catalog)


def chosen_mode(drive, named: dict[str, str]) -> tuple[tuple, str]:
    """(mode, where it comes from) of a drive with clutches, brakes, friction or limited
    drives, for the frequency domain: the states ``named`` ({element: state name}), the others
    as the drive's own run ends (an exact run over its ``t_end``, no error estimate: the mode
    at the end, not the figures)."""
    from beltcalc.sim.core import SolverConfig, simulate

    net = drive.network
    ns = len(net.strands)
    pattern = list(net.taut)
    origin = "named" if named else ""
    rest = [el for el in net.switched if el.name not in named]
    if rest:
        result = simulate(net, drive.t_end, 2, SolverConfig("exact", estimate_error=False))
        history = result.extra["switched"]
        end = list(history["start"])
        for _, j, state in history["log"]:
            end[j] = state
        for j, el in enumerate(net.switched):
            pattern[ns + j] = end[j]
        origin = f"at the end of the run, t = {drive.t_end:g} s" + ("; the rest named" if named else "")
    for j, el in enumerate(net.switched):
        if el.name in named:
            pattern[ns + j] = el.STATES.index(named[el.name])
    return tuple(pattern), origin


# --- modes ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Modes:
    """Every pole of a drive (:func:`beltcalc.sim.frequency.poles` order: rigid-body, then the
    oscillatory modes by frequency, then the real poles by time constant), the shape of each
    oscillatory mode (``shapes[k]`` for the k-th oscillatory pole) and the undamped natural
    frequencies [Hz] (M^-1 K: no damping, motors free)."""

    poles: list
    shapes: list
    undamped: list[float]

    def oscillatory(self) -> list:
        """The oscillatory poles, mode 1 first."""
        return [p for p in self.poles if p.kind == "oscillatory"]

    def to_list(self, shapes: bool = True) -> list[dict]:
        """Every pole as a JSON-ready dict (:func:`pole_dict`), oscillatory ones numbered as
        modes 1, 2, ...; with ``shapes`` each mode's shape too."""
        out, k = [], 0
        for p in self.poles:
            shape = None
            if p.kind == "oscillatory":
                shape = self.shapes[k] if shapes and k < len(self.shapes) else None
                k += 1
            out.append(pole_dict(p, k if p.kind == "oscillatory" else None, shape))
        return out


def modes(net, shapes: bool = True) -> Modes:
    """The :class:`Modes` of a network (strands taut); ``shapes`` False leaves the mode
    shapes out (no eigenvectors: a large network's poles alone cost less).

    >>> m = modes(load("sewing").network)
    >>> [p.kind for p in m.poles].count("real"), round(m.oscillatory()[0].frequency, 4)
    (8, 17.3634)
    """
    from beltcalc.sim.drivefile import undamped_frequencies

    return Modes(fr.poles(net), fr.mode_shapes(net) if shapes else [], undamped_frequencies(net))


def _q(value: float | None, unit: str) -> dict | None:
    if value is None:
        return None
    value = float(value) + 0.0                     # -0.0 (an undamped mode's rounding) as 0
    return {"value": value if math.isfinite(value) else None, "unit": unit}


def pole_dict(pole, mode: int | None = None, shape=None) -> dict:
    """One pole as ``{"kind", "s_real", "s_imag", ...}`` with SI values as ``{"value",
    "unit"}``: an oscillatory one (``mode`` its number) with ``frequency`` (undamped
    natural, |s| / 2 pi), ``damped_frequency`` [Hz] and ``damping_ratio``, and with
    ``shape`` its node amplitudes and phases and strain-energy shares; a real one with its
    ``time_constant`` [s] (negative: unstable); a rigid-body one with no more.

    >>> pole_dict(fr.Pole(-2.0 + 0j, "real", time_constant=0.5))["time_constant"]
    {'value': 0.5, 'unit': 's'}
    """
    out = {"kind": pole.kind, "s_real": _q(pole.s.real, "1/s"), "s_imag": _q(pole.s.imag, "1/s")}
    if pole.kind == "oscillatory":
        out.update(mode=mode, frequency=_q(pole.frequency, "Hz"), damped_frequency=_q(pole.damped_frequency, "Hz"),
                   damping_ratio=_q(pole.damping_ratio, "1"))
        if shape is not None:
            out["shape"] = {
                "nodes": {n: {"amplitude": _q(a, "1"), "phase": _q(math.radians(shape.phase[n]), "rad")}
                          for n, a in shape.amplitude.items()},
                "strain_energy": {e: _q(share, "1") for e, share in shape.energy.items()},
                "largest_strain_energy": ({"element": shape.dominant, "share": _q(shape.energy[shape.dominant], "1")}
                                          if shape.dominant else None),
            }
    elif pole.kind == "real":
        out["time_constant"] = _q(pole.time_constant, "s")
    return out


# --- frequency response -----------------------------------------------------------------------------
def default_inputs(net) -> list[str]:
    """A load on the last node that can take one (it has inertia and moves freely).

    >>> default_inputs(load("sewing").network)
    ['load:5']
    """
    free = [nd.name for nd in net.nodes
            if nd.name not in net._massless and net.coord(nd.name)[0] not in net.fixed]
    if not free:
        raise InputError("no node of this drive can take a load (each has no inertia or a prescribed motion); "
                         "name the `input`", param="input")
    return [f"load:{free[-1]}"]


def default_outputs(net) -> list[str]:
    """The speed of every node (``omega_<node>``, ``v_<node>`` for a translating one)."""
    return [("v_" if nd.translation else "omega_") + nd.name for nd in net.nodes]


def frequency_band(net) -> tuple[float, float]:
    """The default range of a response [Hz]: :data:`BAND` times the lowest and the highest
    oscillatory mode's natural frequency (without one, the corner frequencies 1 / (2 pi tau)
    of the stable real poles).

    >>> [round(f, 4) for f in frequency_band(load("sewing").network)]
    [1.7363, 173.6338]
    """
    ps = fr.poles(net)
    f = [p.frequency for p in ps if p.kind == "oscillatory"]
    if not f:
        f = [1.0 / (2 * math.pi * p.time_constant) for p in ps if p.kind == "real" and p.time_constant > 0]
    if not f:
        raise InputError("the drive has no mode and no stable real pole to set a frequency range: give `f_min` and "
                         "`f_max`", param=None)
    return BAND[0] * min(f), BAND[1] * max(f)


def frequency_grid(f_min: float, f_max: float | None, points: int, spacing: str = "log") -> np.ndarray:
    """``points`` frequencies [Hz] from ``f_min`` to ``f_max``, log- or linearly spaced; one
    point is ``f_min`` alone (``f_max`` None or equal).

    >>> frequency_grid(1.0, 100.0, 3).tolist()
    [1.0, 10.0, 100.0]
    """
    if spacing not in ("log", "linear"):
        raise UsageError(f"spacing {spacing!r}; it is 'log' or 'linear'", param="spacing")
    if not (isinstance(points, int) and 1 <= points <= 100_000):
        raise UsageError(f"{points!r} points; give 1..100000", param="points")
    if not (math.isfinite(f_min) and f_min >= 0):
        raise InputError(f"{f_min:g} Hz; a frequency must be >= 0 Hz", param="f_min")
    if f_min == 0 and spacing == "log":
        raise UsageError("0 Hz cannot start a log-spaced range; start above 0 Hz or space the points linearly",
                         param="f_min")
    if points == 1:
        if f_max is not None and f_max != f_min:
            raise UsageError(f"one point is evaluated at `f_min` ({f_min:g} Hz) alone; leave `f_max` out or give "
                             "more `points`", param="f_max")
        return np.array([f_min])
    if f_max is None or not (math.isfinite(f_max) and f_max > f_min):
        shown = "none" if f_max is None else f"{f_max:g} Hz"
        raise UsageError(f"{shown}; it must be above `f_min` ({f_min:g} Hz)", param="f_max")
    if spacing == "log":
        return np.geomspace(f_min, f_max, points)
    return np.linspace(f_min, f_max, points)


def _range(net, f_min: float | None, f_max: float | None, points: int) -> tuple[float, float | None]:
    """``f_min`` and ``f_max`` with the missing ones from :func:`frequency_band`."""
    if f_min is not None and (f_max is not None or points == 1):
        return f_min, f_max
    lo, hi = frequency_band(net)
    if f_min is None and f_max is None:
        return lo, (hi if points > 1 else None)
    if f_min is None:
        if not lo < f_max:
            raise UsageError(f"the default `f_min`, {lo:.4g} Hz ({BAND[0]:g} x the lowest mode), is not below "
                             f"`f_max` ({f_max:g} Hz): give `f_min`", param=None)
        return lo, f_max
    if not hi > f_min:
        raise UsageError(f"the default `f_max`, {hi:.4g} Hz ({BAND[1]:g} x the highest mode), is not above "
                         f"`f_min` ({f_min:g} Hz): give `f_max`", param=None)
    return f_min, hi


def check_names(net, inputs: list[str], outputs: list[str]) -> None:
    """Refuse an input or output that the drive does not have (a usage error, with the
    names it has), or cannot take (a load on a node without inertia: about the ``input``).
    """
    for names, find, param in ((inputs, fr.input_column, "input"), (outputs, fr.output_row, "output")):
        for name in names:
            try:
                find(net, name)
            except InputError as exc:
                if exc.param == param:
                    raise UnknownNameError(exc.message, param=param) from None
                raise InputError(exc.message, param=param) from None


def response(net, inputs: list[str] | None = None, outputs: list[str] | None = None, f_min: float | None = None,
             f_max: float | None = None, points: int = 2000, spacing: str = "log"):
    """The frequency response (:func:`beltcalc.sim.frequency.frequency_response`) from
    ``inputs`` to ``outputs`` (default :func:`default_inputs`, :func:`default_outputs`) at
    ``points`` frequencies from ``f_min`` to ``f_max`` [Hz] (default
    :func:`frequency_band`). Refused where an undamped mode lies in the range: |H| is
    unbounded there and a peak has no Q.

    >>> r = response(load("sewing").network, outputs=["omega_3"], points=400)
    >>> (f, peak, q), = r.peaks[("omega_3", "load:5")]
    >>> round(f, 2), round(q, 2)
    (16.93, 1.61)
    """
    inputs = list(inputs) if inputs else default_inputs(net)
    outputs = list(outputs) if outputs else default_outputs(net)
    check_names(net, inputs, outputs)
    f = frequency_grid(*_range(net, f_min, f_max, points), points, spacing)
    if f[0] == 0.0 and any(p.kind == "rigid" for p in fr.poles(net)):
        raise InputError("0 Hz: the drive has a rigid-body mode, so its response at 0 Hz is unbounded; start above "
                         "0 Hz", param="f_min")
    undamped = [p.frequency for p in fr.poles(net)
                if p.kind == "oscillatory" and p.damping_ratio < UNDAMPED and f[0] <= p.frequency <= f[-1]]
    if undamped:
        shown = ", ".join(f"{x:.5g}" for x in undamped)
        raise InputError(f"the drive has undamped modes at {shown} Hz inside the range: |H| is unbounded there and a "
                         "peak has no Q; give the drive damping, or a range clear of them", param=None)
    omega = 2 * math.pi * f
    if omega.size == 1:                     # frequency_response wants two points; no peak in one
        r = fr.frequency_response(net, inputs, outputs, np.repeat(omega, 2))
        r.omega, r.H = omega, r.H[:1]
        r.peaks = {key: [] for key in r.peaks}
        return r
    return fr.frequency_response(net, inputs, outputs, omega)


# --- Campbell diagram ---------------------------------------------------------------------------------
def speed_ratio(net, node: str, to: str) -> float:
    """omega_node / omega_to when the drive turns as a rigid body (no coupling or taut
    strand strained): from the null space of M^-1/2 K M^-1/2. Refused where no rigid-body
    motion joins the two nodes in one ratio.

    >>> round(speed_ratio(load("friswell_geared").network, "gear3", "gear1"), 12)
    0.625
    """
    s = 1.0 / np.sqrt(net.mass)
    w2, V = np.linalg.eigh(net.K * s[:, None] * s[None, :])
    floor = 1e-9 * max(1.0, float(np.max(np.abs(w2)))) if w2.size else 0.0
    N = s[:, None] * V[:, np.abs(w2) <= floor]            # rigid-body motions over the coordinates
    a, b = net.node_row(node) @ N, net.node_row(to) @ N
    bb = float(b @ b)
    ratio = float(a @ b) / bb if bb > 0 else math.nan
    if not (bb > 0 and np.linalg.norm(a - ratio * b) <= 1e-9 * max(np.linalg.norm(a), np.linalg.norm(b))):
        raise InputError(f"node {node!r} does not turn in one fixed ratio with node {to!r} (no rigid-body motion "
                         "joins them); give `speed_max`", param="reference")
    return ratio


@dataclass(frozen=True)
class Campbell:
    """A Campbell diagram: the ``reference`` node whose speed Omega [rad/s] is the abscissa
    (an order k excites k Omega / 2 pi [Hz]), the ``orders`` (``sources``: what excites each,
    one text per order), the speed range, the
    reference's speed when the first induction motor turns at its synchronous speed
    (``operating_speed``, None without one; ``motor`` its name), the oscillatory modes
    (:class:`~beltcalc.sim.frequency.Pole`, mode 1 first) and the crossings."""

    reference: str
    orders: list[float]
    speed_min: float
    speed_max: float
    operating_speed: float | None
    motor: str | None
    modes: list
    crossings: list
    sources: list[str] = field(default_factory=list)


def tooth_orders(drive, reference: str) -> list[tuple[float, str]]:
    """The tooth-passing orders of the drive's sprockets and toothed pulleys, counted on the
    reference node: z times the node's speed ratio to it (a chain's polygon action and a
    toothed belt's mesh excite at z n [ISO 10823 sec. 5]); nodes of one order share a line,
    named by all of them. A node that turns in no fixed ratio with the reference is left out.

    >>> [(round(k, 6), s) for k, s in tooth_orders(load("roller_table"), "motor")]
    [(0.76, 'teeth: drive, sprocket1, sprocket2, sprocket3 (19)'), (0.757905, 'teeth: idler1, idler2 (15)')]
    """
    net = drive.network
    out: list[tuple[float, list[str], int]] = []
    for node, z in getattr(drive, "teeth", {}).items():
        if node not in net._node or net.node(node).translation:
            continue
        try:
            k = float(f"{z * abs(speed_ratio(net, node, reference)):.12g}")   # the solve's rounding off
        except InputError:
            continue
        same = next((o for o in out if math.isclose(o[0], k, rel_tol=1e-9) and o[2] == z), None)
        if same is None:
            out.append((k, [node], z))
        else:
            same[1].append(node)
    return [(k, f"teeth: {', '.join(nodes)} ({z})") for k, nodes, z in out]


def load_orders(net, reference: str, operating: float | None) -> list[float]:
    """The excitation orders of the drive's own loads, counted on the reference node: a load
    locked to a node's angle (``order``) times that node's speed ratio to the reference; a
    sine in time at w, at the operating speed Omega of the reference: w / Omega.

    >>> net = load("sewing").network              # loads at the main shaft's steady speed
    >>> [round(k, 6) for k in load_orders(net, "1", 314.159265)]
    [0.725298]
    """
    out = []
    for ld in net.loads:
        if not ld.amplitude:
            continue
        try:
            k = ld.order * abs(speed_ratio(net, ld.node, reference)) if ld.in_angle else (
                ld.omega / operating if operating and ld.omega else None)
        except InputError:
            k = None
        if k and not any(math.isclose(k, x, rel_tol=1e-9) for x in out):
            out.append(k)
    return out


def campbell(drive, orders=None, speed_max: float | None = None, speed_min: float = 0.0,
             reference: str | None = None) -> Campbell:
    """The :class:`Campbell` diagram of a :class:`~beltcalc.sim.drivefile.Drive`:
    ``reference`` defaults to the node of its first motor (else its first node),
    ``speed_max`` [rad/s] to :data:`RUN_UP_MARGIN` times the reference's speed when the
    first induction motor turns at its synchronous speed (the largest of its start table),
    ``orders`` to 1, 2, 3, the orders of the drive's own loads (:func:`load_orders`) and its
    sprockets' and toothed pulleys' tooth orders (:func:`tooth_orders`).

    >>> c = campbell(load("sewing"))
    >>> c.reference, round(c.speed_max, 3), [(round(x.speed, 3), round(x.order, 6)) for x in c.crossings]
    ('1', 376.991, [(36.366, 3.0), (54.549, 2.0), (109.097, 1.0), (150.417, 0.725298)])
    """
    from beltcalc.sim.elements import InductionMotor

    net = drive.network
    default = orders is None
    orders = [1.0, 2.0, 3.0] if default else [float(k) for k in orders]
    if not orders:
        raise UsageError("no orders; name at least one", param="orders")
    for k in orders:
        if not (math.isfinite(k) and k > 0):
            raise InputError(f"order {k:g}; orders must be > 0", param="orders")
    if reference is None:
        reference = drive.motors[0][1] if drive.motors else net.nodes[0].name
    if reference not in net._node:
        raise UnknownNameError(f"{reference!r} is not a node of this drive; "
                               + did_you_mean(reference, (nd.name for nd in net.nodes)), param="reference")
    if net.node(reference).translation:
        raise UsageError(f"node {reference!r} translates; the reference of a Campbell diagram turns", param="reference")
    motor = next((m for m in net.motors if isinstance(m, InductionMotor)), None)
    operating = None
    if motor is not None:
        sync = max([motor.sync_speed] + [v for _, v in motor.sync_table])
        try:
            operating = sync * abs(speed_ratio(net, reference, motor.node))
        except InputError:
            if speed_max is None:
                raise
    if speed_max is None:
        if operating is None:
            raise UsageError("the drive has no induction motor whose synchronous speed would set the range: give "
                             "`speed_max`", param=None)
        speed_max = RUN_UP_MARGIN * operating
    require_positive("speed_max", speed_max, "rad/s")
    if not (math.isfinite(speed_min) and 0 <= speed_min < speed_max):
        raise InputError(f"{speed_min:g} rad/s; it must be >= 0 rad/s and below `speed_max` ({speed_max:g} rad/s)",
                         param="speed_min")
    sources = ["harmonic of the reference's speed" if default else "given"] * len(orders)
    if default:
        extra = [(k, "a load of the drive") for k in load_orders(net, reference, operating)]
        for k, source in extra + tooth_orders(drive, reference):
            hit = next((m for m, x in enumerate(orders) if math.isclose(k, x, rel_tol=1e-9)), None)
            if hit is None:
                orders.append(k)
                sources.append(source)
            else:
                sources[hit] += f"; {source}"
    crossings = fr.campbell(net, orders, speed_max, speed_min)
    osc = [p for p in fr.poles(net) if p.kind == "oscillatory"]
    return Campbell(reference, orders, speed_min, speed_max, operating, motor.name if motor else None, osc, crossings,
                    sources)
