"""Duty cycles of a belt axis at the motor shaft: several moves and dwells, each with its
payload, external force and direction, on an inclined or vertical axis with an optional
counterweight and holding brake, through a gearbox with an efficiency that depends on the
direction of power flow. Torque, power and energy are exact piecewise polynomials of time.

Within a phase of constant jerk (the S-curve of [BM08 sec. 3.4]) the speed is a polynomial
of degree <= 2 and so is every torque; the pieces are cut where the load torque changes sign
(the gearbox's efficiency changes with the direction of power flow) and where the motor
torque changes sign (braking starts or ends), so that every integral below (T^2, T omega,
the braking power) is the integral of a polynomial over an interval: exact, no samples
(:mod:`beltcalc.design.polynomials`). Regeneration (:mod:`beltcalc.design.regeneration`) and
torque-speed zones (:mod:`beltcalc.design.zones`) read the :class:`CycleDuty` made here.
Peaks are taken at both ends of every piece (left and right limits, because the acceleration
of a trapezoid jumps at the phase ends) and at the vertex of each quadratic.

Conventions (SI): the axis coordinate x runs along the guide; ``incline`` is the angle of
+x above the horizontal (90 deg: +x is straight up). A move with ``direction`` +1 runs in
+x. The motor speed omega > 0 moves the carriage in +x. Torques are those the motor must
produce (its electromagnetic torque, the motor's own losses included).

References
----------
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: [W21 eq. 17-29] (errata: DESIGN.md 2.5).
[C04] R. Crowder, Electric Drives and Electromechanical Systems, Newnes (2006): reflected
    inertia M D^2/4 and torque F D/2 [C04 eq. 3.21-3.27]; a gearbox of efficiency eta
    passes T_out = eta i T_in when driving; a back-driven gearbox passes
    T_in = eta_b T_out / i (power flows from the load to the motor) [C04 eq. 3.9-3.10].
[BM08] L. Biagiotti, C. Melchiorri, Trajectory Planning for Automatic Machines and Robots,
    Springer (2008): the S-curve (see :mod:`beltcalc.formulas.profiles`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.formulas.drive import G0, BeltAxis
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.formulas.profiles import Phase, Trapezoid
from beltcalc.design.polynomials import poly_add, poly_integral, poly_mul, poly_scale, poly_shift, poly_value, roots_inside


# --- the axis and the cycle ------------------------------------------------------------------

@dataclass(frozen=True)
class Gearbox:
    """Gearbox between motor and drive pulley, SI. ``ratio`` i = input / output speed;
    ``inertia`` at its input [kg m^2]; ``efficiency`` when the motor drives,
    ``efficiency_back`` when the load drives the motor (power flows backwards);
    ``max_input_speed`` [rad/s], ``rated_torque`` (continuous, RMS) and ``peak_torque``
    at the output [N m]; None = not given (not checked). ``name`` and ``source`` from a
    catalog entry."""

    ratio: float = 1.0
    inertia: float = 0.0
    efficiency: float = 1.0
    efficiency_back: float | None = None
    max_input_speed: float | None = None
    rated_torque: float | None = None
    peak_torque: float | None = None
    name: str = ""
    source: str = ""

    def __post_init__(self):
        require_positive("gear_ratio", self.ratio, "")
        squared = self.ratio * self.ratio          # the inertia and damping go through i^2
        if not (0.0 < squared < math.inf and 1.0 / squared < math.inf):
            raise InputError(f"{self.ratio:g}: its square leaves the range of a float; a gear ratio must lie "
                             "within 1e-150..1e150", param="gear_ratio")
        require_range("gear_efficiency", self.efficiency, "", 0.0, 1.0, low_open=True)
        if self.efficiency_back is not None:
            require_range("gear_efficiency_back", self.efficiency_back, "", 0.0, 1.0, low_open=True)

    @property
    def eta_back(self) -> float:
        return self.efficiency if self.efficiency_back is None else self.efficiency_back


@dataclass(frozen=True)
class Mounting:
    """How the axis is mounted: ``incline`` [rad] of +x above the horizontal (-pi/2..pi/2),
    ``counterweight`` [kg] hung on a rope over the drive so that it balances m g sin(incline)
    (it adds its inertia; its own guide friction is not modelled), ``brake``: a holding
    brake holds the axis in every dwell (the motor gives no torque there)."""

    incline: float = 0.0
    counterweight: float = 0.0
    brake: bool = False

    def __post_init__(self):
        require_range("incline", self.incline, "rad", -math.pi / 2, math.pi / 2)
        require_range("counterweight", self.counterweight, "kg", low=0.0)


@dataclass(frozen=True)
class Segment:
    """One segment of a cycle: a move (``profile``: magnitudes of speed at the motor shaft,
    without its dwell) or a dwell (``duration``). ``direction`` +1 / -1 along x;
    ``payload`` [kg] carried on the carriage in this segment; ``force`` [N]: in a move a
    process force against the motion, in a dwell a static force on the carriage towards
    -x that the drive holds (negative: towards +x)."""

    name: str
    kind: str                      # "move" | "dwell"
    profile: Trapezoid | None = None
    duration: float = 0.0
    direction: int = 1
    payload: float = 0.0
    force: float = 0.0

    def __post_init__(self):
        if self.kind not in ("move", "dwell"):
            raise InputError(f"segment {self.name!r}: kind {self.kind!r}; use move or dwell", param="cycle")
        if self.direction not in (1, -1):
            raise InputError(f"segment {self.name!r}: direction {self.direction!r}; use +1 or -1", param="cycle")
        require_range("payload", self.payload, "kg", low=0.0)
        if not math.isfinite(self.force):
            raise InputError(f"segment {self.name!r}: force {self.force!r} N is not finite", param="cycle")
        if self.kind == "move":
            if self.profile is None:
                raise InputError(f"segment {self.name!r}: a move needs a profile", param="cycle")
            if self.force < 0:
                raise InputError(f"segment {self.name!r}: {self.force:g} N; a process force against the "
                                 "motion must be >= 0 N", param="cycle")
        else:
            require_positive("dwell", self.duration, "s")

    @property
    def phases(self) -> tuple[Phase, ...]:
        if self.kind == "dwell":
            return (Phase("dwell", self.duration, 0.0, 0.0),)
        return tuple(p for p in self.profile.phases if p.name != "dwell")

    @property
    def time(self) -> float:
        return sum(p.duration for p in self.phases)


def single_move(profile: Trapezoid) -> tuple[Segment, ...]:
    """Today's cycle: one forward move of ``profile`` and its dwell (if any)."""
    segs = [Segment("move", "move", profile=profile)]
    if profile.dwell > 0:
        segs.append(Segment("dwell", "dwell", duration=profile.dwell))
    return tuple(segs)


@dataclass(frozen=True)
class AxisDrive:
    """Everything at the motor shaft except the motor: the belt axis (without its gearbox
    ratio/inertia, which come from ``gearbox``), the mounting and the gearbox."""

    axis: BeltAxis
    mounting: Mounting = Mounting()
    gearbox: Gearbox | None = None

    def __post_init__(self):
        if self.gearbox is None:   # the axis's own ratio and inertia, ideal
            object.__setattr__(self, "gearbox", Gearbox(self.axis.gear_ratio, self.axis.gearbox_inertia))
        elif (self.gearbox.ratio, self.gearbox.inertia) != (self.axis.gear_ratio, self.axis.gearbox_inertia):
            raise ValueError("the axis's gear_ratio/gearbox_inertia must be the gearbox's")

    def load_side(self, seg: Segment) -> tuple[float, float, float, float]:
        r"""(J_L, b_L, T_F, T_S) of the load side reflected to the gearbox input in ``seg``.

        .. math::
            J_L = \frac{1}{i^2}\Big(J_C + J_{P1} + \frac{J_{P2} + J_{RL}}{n^2}
                  + (m + m_p + m_{TB} + m_{cw}) \frac{D^2}{4}\Big), \quad
            b_L = \frac{1}{i^2}\Big(b_B (1 + n^{-2}) + b_{LG} \frac{D^2}{4}\Big)

            T_F = \big(F_R + F_{seg} + \mu (m + m_p) g \cos\alpha\big) \frac{D}{2 i}, \quad
            T_S = (m + m_p - m_{cw}) g \sin\alpha \frac{D}{2 i}

        T_F acts against the motion, T_S (gravity) always towards -x. [W21 eq. 18, 23, 27]
        with [C04 eq. 3.22-3.24]; gravity and the normal force on an incline:
        F = m g sin(alpha), N = m g cos(alpha).
        """
        ax, gb, mt = self.axis, self.gearbox, self.mounting
        i2, r = gb.ratio ** 2, ax.pulley_diameter / 2.0
        n2 = ax.belt_ratio ** 2
        m = ax.mass + seg.payload
        j = (ax.coupling_inertia + ax.pulley_inertia + (ax.idler_inertia + ax.load_inertia) / n2
             + (m + ax.substitute_mass + mt.counterweight) * r * r) / i2
        b = (ax.bearing_damping * (1 + 1 / n2) + ax.guide_damping * r * r) / i2
        lever = r / gb.ratio
        friction = (ax.resistance + seg.force * (seg.kind == "move")
                    + ax.guide_friction * m * G0 * math.cos(mt.incline)) * lever
        static = (m - mt.counterweight) * G0 * math.sin(mt.incline) * lever
        if seg.kind == "dwell":
            static += seg.force * lever
        return j, b, friction, static

    def load_inertia(self, segments) -> float:
        """The largest load inertia at the motor shaft over the cycle (gearbox included) [kg m^2]."""
        return self.gearbox.inertia + max(self.load_side(s)[0] for s in segments)


@dataclass(frozen=True)
class CyclePiece:
    """A stretch of the cycle where every quantity is one polynomial of the local time
    s in [0, duration]: speed ``w``, load torque at the gearbox input ``t_load`` (ideal,
    before the efficiency), motor torque ``torque``. ``start`` is the time in the cycle."""

    segment: int
    phase: str
    start: float
    duration: float
    w: tuple[float, ...]
    t_load: tuple[float, ...]
    torque: tuple[float, ...]

    def power(self) -> tuple[float, ...]:
        return poly_mul(self.torque, self.w)


@dataclass(frozen=True)
class PhaseDuty:
    """One phase of the cycle: its time and its torque (the table of "time at each torque")."""

    segment: int
    segment_name: str
    name: str
    start: float
    duration: float
    speed0: float
    speed1: float
    torque0: float   # right limit at the start [N m]
    torque1: float   # left limit at the end [N m]
    peak: float      # largest |T| inside [N m]
    rms: float       # RMS over the phase [N m]
    extreme: float = math.nan   # the torque where |T| is largest, signed: the phase's peak as it acts [N m]


@dataclass(frozen=True)
class SegmentDuty:
    name: str
    kind: str
    start: float
    duration: float
    peak_torque: float
    rms_torque: float          # over the segment's own time
    sq_integral: float         # integral of T^2 [N^2 m^2 s]
    energy_motoring: float     # integral of max(T w, 0) [J]
    energy_braking: float      # integral of max(-T w, 0) [J]
    peak_speed: float


@dataclass(frozen=True)
class BrakingEvent:
    """A stretch of negative motor power (the drive takes energy back)."""

    start: float
    end: float
    energy: float       # [J], > 0
    peak_power: float   # [W], > 0


@dataclass(frozen=True)
class CycleDuty:
    """Torque, power and energy of a cycle at the motor shaft, SI, exact."""

    pieces: tuple[CyclePiece, ...]
    phases: tuple[PhaseDuty, ...]
    segments: tuple[SegmentDuty, ...]
    events: tuple[BrakingEvent, ...]
    cycle_time: float
    peak_torque: float
    peak_time: float
    rms_torque: float
    peak_speed: float
    mean_speed: float           # mean |omega| over the cycle [rad/s]
    peak_power: float
    braking_torque: float       # largest torque while the power is negative, signed (0 if none) [N m]
    energy_motoring: float
    braking_energy: float
    peak_braking_power: float
    load_peak_torque: float     # largest |T_load| at the gearbox input (ideal) [N m]
    load_rms_torque: float
    holding_torque: float       # largest |T| while at rest (0 with a brake) [N m]

    def torque_at(self, t: float, side: str = "right") -> float:
        """Motor torque at time ``t`` [N m]; at a phase end ``side`` picks the limit."""
        for p in self.pieces:
            end = p.start + p.duration
            if p.start <= t < end or (side == "left" and p.start < t <= end):
                return poly_value(p.torque, t - p.start)
        return poly_value(self.pieces[-1].torque, self.pieces[-1].duration)


def cycle_duty(drive: AxisDrive, segments, motor_inertia: float = 0.0, motor_damping: float = 0.0) -> CycleDuty:
    r"""The motor torque over a cycle, and its peak, RMS, power and energies, exact.

    .. math::
        T_L = J_L \dot\omega + b_L \omega + T_F\,\mathrm{sgn}\,\omega + T_S

        T = (J_M + J_G) \dot\omega + b_M \omega +
            \begin{cases} T_L/\eta & T_L \omega > 0 \text{ (motor drives)} \\
                          \eta_b T_L & T_L \omega < 0 \text{ (load drives)} \\
                          T_L & \omega = 0 \text{ (holding; 0 with a brake)} \end{cases}

        T_{rms} = \sqrt{\frac{1}{t_{cyc}} \sum \int T^2 dt}, \quad
        E_{brake} = \int \max(-T \omega, 0)\,dt

    Parameters
    ----------
    drive : AxisDrive
        Axis, mounting and gearbox
    segments : sequence of Segment
        The cycle
    motor_inertia : float
        Rotor inertia J_M [kg m^2]
    motor_damping : float
        Motor loss as viscous damping b_M [N m s/rad]

    Notes
    -----
    [W21 eq. 26-28] with the errata of DESIGN.md 2.5; gearbox efficiency as
    [C04 eq. 3.9-3.10]. The speed and torque of each piece are polynomials of degree <= 2, the
    integrals of T^2 and T omega are computed from their coefficients (exact up to
    rounding). The holding torque at rest is taken through the gearbox without
    efficiency (a static gearbox neither helps nor hinders; conservative for a hold that
    the gearbox's friction would help).

    Examples
    --------
    A vertical axis at rest holds m g D/2 / i: 10 kg, D = 0.1 m, i = 5:
    10 * 9.80665 * 0.05 / 5 = 0.980665 N m.

    >>> ax = BeltAxis(mass=10.0, substitute_mass=0.0, pulley_diameter=0.1, pulley_inertia=0.0,
    ...               idler_inertia=0.0, gear_ratio=5.0)
    >>> d = cycle_duty(AxisDrive(ax, Mounting(incline=math.pi / 2), Gearbox(ratio=5.0)),
    ...                [Segment("rest", "dwell", duration=1.0)])
    >>> round(d.holding_torque, 6), round(d.rms_torque, 6)
    (0.980665, 0.980665)
    """
    require_range("motor_inertia", motor_inertia, "kg*m^2", low=0.0)
    require_range("motor_damping", motor_damping, "N*m*s/rad", low=0.0)
    segments = tuple(segments)
    if not segments:
        raise InputError("a cycle needs at least one segment", param="cycle")
    gb, brake = drive.gearbox, drive.mounting.brake
    j_motor = motor_inertia + gb.inertia
    pieces: list[CyclePiece] = []
    phase_rows: list[PhaseDuty] = []
    t0 = 0.0
    for k, seg in enumerate(segments):
        j_l, b_l, t_f, t_s = drive.load_side(seg)
        s = float(seg.direction)
        for ph in seg.phases:
            tau = ph.duration
            if tau <= 0:
                continue
            w = (s * ph.speed0, s * ph.accel, s * 0.5 * ph.jerk)
            wd = (s * ph.accel, s * ph.jerk)
            moving = seg.kind == "move"
            t_load = poly_add(poly_scale(wd, j_l), poly_scale(w, b_l), (s * t_f * moving + t_s,))
            motor_own = poly_add(poly_scale(wd, j_motor), poly_scale(w, motor_damping))
            cuts = [0.0, *roots_inside(t_load, tau), tau] if moving else [0.0, tau]
            first = len(pieces)
            for a, b in zip(cuts, cuts[1:]):
                wl, tl, mo = poly_shift(w, a), poly_shift(t_load, a), poly_shift(motor_own, a)
                mid = 0.5 * (b - a)
                flow = poly_value(tl, mid) * poly_value(wl, mid)
                if not moving:
                    factor = 0.0 if brake else 1.0
                elif flow > 0:
                    factor = 1.0 / gb.efficiency
                elif flow < 0:
                    factor = gb.eta_back
                else:
                    factor = 1.0
                torque = poly_add(mo, poly_scale(tl, factor))
                # cut again where the motor torque changes sign (braking starts or ends)
                sub = [0.0, *roots_inside(torque, b - a), b - a] if moving else [0.0, b - a]
                for c, d in zip(sub, sub[1:]):
                    pieces.append(CyclePiece(k, ph.name, t0 + a + c, d - c, poly_shift(wl, c), poly_shift(tl, c),
                                        poly_shift(torque, c)))
            mine = pieces[first:]
            sq = sum(poly_integral(poly_mul(p.torque, p.torque), p.duration) for p in mine)
            peak, piece, where = -1.0, mine[0], 0.0
            for p in mine:          # the piece and the time of the largest |T|: its signed torque
                size, at = _abs_peak(p.torque, p.duration)
                if size > peak:
                    peak, piece, where = size, p, at
            phase_rows.append(PhaseDuty(
                segment=k, segment_name=seg.name, name=ph.name, start=t0, duration=tau,
                speed0=w[0], speed1=poly_value(w, tau), torque0=poly_value(mine[0].torque, 0.0),
                torque1=poly_value(mine[-1].torque, mine[-1].duration),
                peak=peak, rms=math.sqrt(sq / tau), extreme=poly_value(piece.torque, where)))
            t0 += tau
    cycle = t0
    return _summarise(tuple(pieces), tuple(phase_rows), segments, cycle)


def _abs_peak(p: tuple[float, ...], duration: float) -> tuple[float, float]:
    """(max |p|, where) on [0, duration]: ends (left/right limits) and the vertex."""
    cands = [0.0, duration]
    if len(p) > 2 and p[2] != 0:
        v = -p[1] / (2 * p[2])
        if 0 < v < duration:
            cands.append(v)
    return max((abs(poly_value(p, t)), t) for t in cands)


def _summarise(pieces, phase_rows, segments, cycle) -> CycleDuty:
    sq_total = 0.0
    sq_load = 0.0
    peak, peak_t = 0.0, 0.0
    peak_power = -math.inf
    braking_torque = 0.0
    e_mot = e_brk = 0.0
    peak_brake_p = 0.0
    load_peak = 0.0
    angle = 0.0
    holding = 0.0
    events: list[list[float]] = []
    seg_acc = {k: [0.0, 0.0, 0.0, 0.0, 0.0] for k in range(len(segments))}  # sq, peak, e+, e-, w
    for p in pieces:
        tq, w, dur = p.torque, p.w, p.duration
        sq = poly_integral(poly_mul(tq, tq), dur)
        sq_total += sq
        sq_load += poly_integral(poly_mul(p.t_load, p.t_load), dur)
        pk, where = _abs_peak(tq, dur)
        if pk > peak:
            peak, peak_t = pk, p.start + where
        load_peak = max(load_peak, _abs_peak(p.t_load, dur)[0])
        pw = poly_mul(tq, w)   # sign-definite on a piece (cut at the zeros of T; w keeps its sign)
        e = poly_integral(pw, dur)
        if e < 0 and pk > abs(braking_torque):   # the largest torque while braking, with its sign
            braking_torque = math.copysign(pk, poly_value(tq, 0.5 * dur))
        pmax = max(poly_value(pw, 0.0), poly_value(pw, dur), *([poly_value(pw, t) for t in _vertices(pw, dur)]))
        pmin = min(poly_value(pw, 0.0), poly_value(pw, dur), *([poly_value(pw, t) for t in _vertices(pw, dur)]))
        peak_power = max(peak_power, pmax)
        wmax = max(abs(poly_value(w, 0.0)), abs(poly_value(w, dur)))
        acc = seg_acc[p.segment]
        acc[0] += sq
        acc[1] = max(acc[1], pk)
        acc[4] = max(acc[4], wmax)
        angle += abs(poly_integral(w, dur))
        if w == (0.0, 0.0, 0.0) or all(c == 0 for c in w):
            holding = max(holding, pk)
        if e >= 0:
            e_mot += e
            acc[2] += e
        else:
            e_brk -= e
            acc[3] -= e
            peak_brake_p = max(peak_brake_p, -pmin)
            if events and abs(events[-1][1] - p.start) <= 1e-12 * max(cycle, 1.0):
                events[-1][1] = p.start + dur
                events[-1][2] -= e
                events[-1][3] = max(events[-1][3], -pmin)
            else:
                events.append([p.start, p.start + dur, -e, -pmin])
    seg_rows = []
    t = 0.0
    for k, seg in enumerate(segments):
        sq, pk, ep, en, wmax = seg_acc[k]
        dur = seg.time
        seg_rows.append(SegmentDuty(seg.name, seg.kind, t, dur, pk, math.sqrt(sq / dur), sq, ep, en, wmax))
        t += dur
    # an event that wraps around the cycle's end joins the first one
    if len(events) > 1 and events[0][0] <= 1e-12 * cycle and abs(events[-1][1] - cycle) <= 1e-12 * cycle:
        last = events.pop()
        events[0] = [last[0], events[0][1], events[0][2] + last[2], max(events[0][3], last[3])]
    return CycleDuty(
        pieces=pieces, phases=phase_rows, segments=tuple(seg_rows),
        events=tuple(BrakingEvent(a, b, e, p) for a, b, e, p in events), cycle_time=cycle,
        peak_torque=peak, peak_time=peak_t, rms_torque=math.sqrt(sq_total / cycle),
        peak_speed=max(r.peak_speed for r in seg_rows), mean_speed=angle / cycle,
        peak_power=max(peak_power, 0.0), braking_torque=braking_torque, energy_motoring=e_mot,
        braking_energy=e_brk, peak_braking_power=peak_brake_p, load_peak_torque=load_peak,
        load_rms_torque=math.sqrt(sq_load / cycle), holding_torque=holding,
    )


def _vertices(p: tuple[float, ...], duration: float) -> list[float]:
    """Interior stationary points of a polynomial of degree <= 4 on (0, duration)."""
    deriv = tuple(k * c for k, c in enumerate(p))[1:]
    while deriv and deriv[-1] == 0:
        deriv = deriv[:-1]
    if len(deriv) <= 1:
        return []
    if len(deriv) <= 3:
        return roots_inside(deriv, duration)
    import numpy as np  # degree 3 derivative: companion-matrix roots

    return [float(r.real) for r in np.roots(deriv[::-1])
            if abs(r.imag) <= 1e-9 * duration and 0 < r.real < duration]
