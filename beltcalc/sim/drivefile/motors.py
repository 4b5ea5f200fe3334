"""The motors of drive files: the ``[[motor]]`` section (:class:`MotorKind`) and its kinds,
each a class that declares its keys, what it needs and how it builds: ``induction`` (the
first-order characteristic of :class:`~beltcalc.sim.elements.InductionMotor`),
``prescribed`` (an imposed speed: a table or a ``motor-size`` move), ``speed_loop``
(feed-forward and a proportional speed loop) and ``torque`` (a torque table). A new kind of
motor is one class here and one line of :attr:`MotorKind.kinds`."""

from __future__ import annotations

import math
from typing import ClassVar

from beltcalc.design.checks import percent
from beltcalc.errors import did_you_mean
from beltcalc.data.schema import Field, Quantity, Table, Text, Whole
from beltcalc.sim.drivefile.keys import TORQUE, Entry
from beltcalc.sim.drivefile.kinds import Kind


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


class MotorType:
    """A kind of motor (``kind = "..."``): its ``keys`` (beside ``name``, ``kind``, ``node``),
    those it ``need`` s, and :meth:`build` on its node."""

    kind: ClassVar[str]
    keys: ClassVar[dict[str, Field]]
    need: ClassVar[tuple[str, ...]] = ()

    @classmethod
    def missing(cls, given: set) -> list[tuple[str, str]]:
        """(key, what) of every key this kind needs that ``given`` lacks."""
        return [(key, f"missing ({cls.kind}: {cls.keys[key].help})") for key in cls.need if key not in given]

    @classmethod
    def build(cls, b, e: Entry, node: str) -> None:
        """Add the motor of entry ``e`` on ``node`` to the builder ``b``."""
        raise NotImplementedError


class InductionKind(MotorType):
    """An induction motor from its rating plate: :class:`~beltcalc.sim.elements.InductionMotor`."""

    kind = "induction"
    keys = {
        "rated_torque": Quantity("N*m", help="rated torque (or rated_power and rated_speed)", low=">0"),
        "rated_power": Quantity("W", help="rated power", low=">0"),
        "rated_speed": Quantity("rad/s", help="rated speed", low=">0"),
        "breakdown_factor": Quantity("", help="breakdown torque / rated torque", low=">0"),
        "breakdown_slip": Quantity("", help="breakdown slip", low=">0"),
        "supply": Quantity("Hz", help="supply frequency", low=">0"),
        "pole_pairs": Whole(help="pole pairs [default: inferred from rated_speed and supply]"),
        "ramp": Quantity("s", help="inverter ramp from 0 to the supply frequency (0: none)", low=">=0"),
    }
    need = ("supply", "breakdown_factor", "breakdown_slip")

    @classmethod
    def missing(cls, given: set) -> list[tuple[str, str]]:
        out = super().missing(given)
        if "rated_torque" not in given and not {"rated_power", "rated_speed"} <= given:
            out.append(("rated_torque", "missing: give rated_torque, or rated_power and rated_speed"))
        if "pole_pairs" not in given and "rated_speed" not in given:
            out.append(("pole_pairs", "missing: give it, or rated_speed to infer it from the supply"))
        return out

    @classmethod
    def build(cls, b, e: Entry, node: str) -> None:
        from beltcalc.sim.elements import InductionMotor

        speed = b.get(e, "rated_speed")
        torque = b.get(e, "rated_torque")
        if torque is None:
            torque = b.need(e, "rated_power") / speed
        f = b.need(e, "supply")
        pairs = cls.pole_pairs(b, e, b.get(e, "pole_pairs"), speed, f)
        w0 = 2 * math.pi * f / pairs
        ramp = b.get(e, "ramp", 0.0)
        table = ((0.0, 0.0), (ramp, w0)) if ramp else ()
        b.add(InductionMotor(node, b.need(e, "breakdown_factor") * torque, b.need(e, "breakdown_slip"), w0,
                             2 * math.pi * f, sync_table=table, name=e.name))
        b.motor_signals.append((f"M_{e.name}", node))

    @classmethod
    def pole_pairs(cls, b, e: Entry, pairs, rated_speed, supply: float) -> int:
        """The motor's pole pairs: as given, checked against the rated speed and the supply
        when the file gives both (a rated slip in (0, :data:`MAX_RATED_SLIP`]); else inferred
        from them (:func:`pole_pairs_from_speed`), and a note says so."""
        if pairs is not None and pairs < 1:
            b.fail(e, "pole_pairs", f"{pairs}; it must be >= 1")
        if rated_speed is None:
            return pairs
        rpm = rated_speed * 30 / math.pi
        if pairs is None:
            p, slip = pole_pairs_from_speed(rated_speed, supply)
            if p < 1 or slip > MAX_RATED_SLIP:
                sync = f"{2 * math.pi * supply / p * 30 / math.pi:.6g} rpm with {p} pole pairs" if p else "none"
                b.fail(e, "rated_speed", f"{rpm:.6g} rpm fits no pole count at the supply {supply:.6g} Hz "
                                         f"(the synchronous speed just above it: {sync}; rated slip "
                                         f"{percent(slip, 1)}, an induction motor's is 0..{MAX_RATED_SLIP:.0%}): "
                                         "check rated_speed and supply (the rated speed at that "
                                         "frequency), or give pole_pairs")
            b.notes.append(f"motor {e.name}: pole_pairs = {p}, inferred from rated_speed {rpm:.6g} rpm and "
                           f"supply {supply:.6g} Hz (synchronous {2 * math.pi * supply / p * 30 / math.pi:.6g} "
                           f"rpm, rated slip {slip:.2%})")
            return p
        sync = 2 * math.pi * supply / pairs
        slip = 1 - rated_speed / sync
        if not 0 < slip <= MAX_RATED_SLIP:
            b.fail(e, "pole_pairs", f"{pairs} pole pairs at the supply {supply:.6g} Hz turn at "
                                    f"{sync * 30 / math.pi:.6g} rpm synchronous; the rated_speed "
                                    f"{rpm:.6g} rpm gives a rated slip of {percent(slip, 1)}, outside "
                                    f"0..{MAX_RATED_SLIP:.0%} (NEMA design D, the high-slip motors: "
                                    "up to 13 %): check pole_pairs, rated_speed and supply")
        return pairs


class PrescribedKind(MotorType):
    """An imposed speed: :class:`~beltcalc.sim.elements.Prescribed`, from an acceleration table
    or a move."""

    kind = "prescribed"
    keys = {
        "speed": Quantity("rad/s|m/s", help="initial speed"),
        "accel": Table(columns=(Quantity("s"), Quantity("rad/s^2|m/s^2")), help="acceleration table [[t, a], ...]"),
        "distance": Quantity("rad|m", help="a move of this distance (motor-size profile)"),
        "max_speed": Quantity("rad/s|m/s", help="the move's speed limit", low=">0"),
        "max_accel": Quantity("rad/s^2|m/s^2", help="the move's acceleration limit", low=">0"),
        "jerk": Quantity("rad/s^3|m/s^3", help="jerk limit (S-curve); none: trapezoid", low=">0"),
        "start": Quantity("s", help="the move starts here", low=">=0"),
    }

    @classmethod
    def missing(cls, given: set) -> list[tuple[str, str]]:
        need = ("max_speed", "max_accel") if "distance" in given else ()
        return [(key, f"missing ({cls.kind}: {cls.keys[key].help})") for key in need if key not in given]

    @classmethod
    def build(cls, b, e: Entry, node: str) -> None:
        from beltcalc.sim.elements import Prescribed

        b.add(Prescribed(node, b.get(e, "speed", 0.0), cls.move(b, e)))
        b.motor_signals.append((f"T_drive_{node}", node))

    @classmethod
    def move(cls, b, e: Entry) -> tuple:
        """The acceleration table of the motor: the file's ``accel``, or the profile of a move
        (``distance``, ``max_speed``, ``max_accel``, ``jerk``: the profiles of ``motor-size``)."""
        accel = b.get(e, "accel")
        distance = b.get(e, "distance")
        if accel is not None and distance is not None:
            b.fail(e, "distance", "give an accel table or a move (distance, max_speed, max_accel), not both")
        if distance is None:
            return tuple(accel or ())
        from beltcalc.formulas import profiles

        speed, acc = b.need(e, "max_speed"), b.need(e, "max_accel")
        jerk = b.get(e, "jerk")
        profile = (profiles.scurve(speed, acc, jerk, distance) if jerk is not None
                   else profiles.trapezoid(speed, acc, distance))
        t = b.get(e, "start", 0.0)
        table = []
        for ph in profile.phases:
            if ph.duration > 0:
                table += [(t, ph.accel), (t + ph.duration, ph.accel1)]
                t += ph.duration
        table.append((t, 0.0))
        kind = "S-curve" if jerk is not None else "trapezoid"
        b.notes.append(f"motor {e.name}: {kind} move of {distance:g} over {t - b.get(e, 'start', 0.0):.4g} s "
                       f"(peak speed {profile.peak_speed:.4g})")
        return tuple(table)


class SpeedLoopKind(MotorType):
    """Feed-forward and a PI speed loop with a torque limit:
    :class:`~beltcalc.sim.elements.switched.SpeedLoop`."""

    kind = "speed_loop"
    keys = {
        "gain": Quantity("N*m*s/rad|N*s/m", help="proportional gain", low=">=0"),
        "reference": Table(columns=(Quantity("s"), Quantity("rad/s|m/s")), help="speed reference [[t, speed], ...]"),
        "feedforward": Table(columns=(Quantity("s"), Quantity(TORQUE)), help="feed-forward torque [[t, torque], ...]"),
        "ki": Quantity("N*m/rad|N/m", help="integral gain (torque per integrated speed error) [default: 0, P only]",
                       low=">=0"),
        "torque_limit": Quantity(TORQUE, help="the drive's torque (current) limit; the integrator is held while "
                                              "it saturates [default: none]", low=">0"),
    }
    need = ("gain", "reference")

    @classmethod
    def build(cls, b, e: Entry, node: str) -> None:
        from beltcalc.sim.elements.switched import SpeedLoop

        ref = b.get(e, "reference")
        if ref is None:
            b.fail(e, "reference", "a speed loop needs its speed reference table")
        b.add(SpeedLoop(node, b.need(e, "gain"), ref, b.get(e, "feedforward", ()), b.get(e, "ki", 0.0),
                        b.get(e, "torque_limit", math.inf)))
        b.motor_signals.append((f"T_drive_{node}", node))


class TorqueKind(MotorType):
    """A drive torque table: a :class:`~beltcalc.sim.elements.Load` of the opposite sign."""

    kind = "torque"
    keys = {
        "torque": Table(columns=(Quantity("s"), Quantity(TORQUE)), help="drive torque [[t, torque], ...]"),
    }
    need = ("torque",)

    @classmethod
    def build(cls, b, e: Entry, node: str) -> None:
        from beltcalc.sim.elements import Load

        table = b.need(e, "torque")
        b.add(Load(node, table=tuple((t, -v) for t, v in table)))


def motor_keys(kinds: dict[str, type[MotorType]]) -> dict[str, Field]:
    """The keys of ``[[motor]]``: name, kind, node, then every kind's own, each with its help
    led by the kind's name (``induction: supply frequency``)."""
    from dataclasses import replace

    names = list(kinds)
    keys = {
        "name": Text(help="unique name"),
        "kind": Text(help=f"{', '.join(names[:-1])} or {names[-1]}", required=True),
        "node": Text(help="node it drives", required=True),
    }
    for kind, cls in kinds.items():
        for key, spec in cls.keys.items():
            if key in keys:
                raise ValueError(f"motor kind {kind} repeats the key {key!r}")
            keys[key] = replace(spec, help=f"{kind}: {spec.help}")
    return keys


class MotorKind(Kind):
    """``[[motor]]``: a motor of one of the ``kinds`` on the node it drives."""

    section = "motor"
    node_key = "node"
    shares_node_name = True
    #: the kinds of motor, by the name a file gives as ``kind``
    kinds: ClassVar[dict[str, type[MotorType]]] = {
        k.kind: k for k in (InductionKind, PrescribedKind, SpeedLoopKind, TorqueKind)}
    keys = motor_keys(kinds)

    @classmethod
    def problems(cls, e: Entry) -> list[tuple[str, str, str]]:
        """A kind that is none, and every key of the section its kind does not have."""
        names = tuple(cls.kinds)
        kind = e.raw.get("kind")
        if kind is not None and kind not in names:
            return [(e.where, "kind", f"{kind!r} is not a kind; {did_you_mean(str(kind), names)}")]
        if kind is None:
            return []
        allowed = set(cls.kinds[kind].keys)
        return [(e.where, key, f"not a key of a {kind} motor (it has {', '.join(sorted(allowed))})")
                for key in e.raw if key in cls.keys and key not in allowed | {"name", "kind", "node"}]

    @classmethod
    def missing(cls, e: Entry, given: set) -> list[tuple[str, str, str]]:
        kind = e.raw.get("kind")
        if kind not in tuple(cls.kinds):
            return []
        return [(e.where, key, what) for key, what in cls.kinds[kind].missing(given)]

    @classmethod
    def build(cls, b, e: Entry) -> None:
        kind, node = b.need(e, "kind"), b.node_name(e, "node")
        names = tuple(cls.kinds)
        if kind not in names:           # (the file's own kind is checked on reading; this is a kind set)
            b.fail(e, "kind", f"{kind!r} is not a kind; {did_you_mean(str(kind), names)}")
        cls.kinds[kind].build(b, e, node)
