"""Input shaping of positioning moves: the ZV, ZVD and EI shapers of a vibration mode, the
residual vibration they leave, and a move convolved with them.

A shaper is a sequence of impulses, amplitudes A_i (summing to 1) at times t_i (t_1 = 0),
designed at the natural frequency f [Hz] and damping ratio zeta of one mode. A command
convolved with it (every phase of the move repeated at each t_i, scaled by A_i) excites the
mode as the impulses do: an impulse sequence that leaves no vibration of a second-order
system leaves none after any move shaped with it. The move lasts ``duration`` (= t_n)
longer. Everything here is SI floats: frequencies in Hz, times in s, and the phases of
:mod:`beltcalc.formulas.profiles` (rad, rad/s, rad/s^2, rad/s^3 at the motor shaft).

References
----------
[SS90] N. C. Singer, W. P. Seering, "Preshaping command inputs to reduce system vibration",
    J. Dyn. Sys., Meas., Control 112 (1990) 76-82: the residual vibration of an impulse
    sequence on a damped second-order system and the zero-vibration (ZV) and
    zero-vibration-derivative (ZVD) sequences.
[SSS94] W. Singhose, W. Seering, N. Singer, "Residual vibration reduction using vector
    diagrams to generate shaped inputs", J. Mech. Design 116 (1994) 654-659: the
    extra-insensitive (EI) shaper, vibration Vtol (not zero) at the modelling frequency
    and zero at one frequency below and one above it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.formulas.profiles import Phase, SCurve, Trapezoid


@dataclass(frozen=True)
class Shaper:
    """An impulse sequence: ``amplitudes`` A_i (summing to 1) at ``times`` t_i [s]
    (t_1 = 0, ascending), designed for the mode of natural frequency ``frequency`` [Hz] and
    damping ratio ``zeta``; ``vtol`` is the EI shaper's vibration tolerance (a fraction;
    None for ZV and ZVD)."""

    name: str
    amplitudes: tuple[float, ...]
    times: tuple[float, ...]
    frequency: float
    zeta: float
    vtol: float | None = None

    @property
    def duration(self) -> float:
        """The time the shaper adds to a move, t_n [s]."""
        return self.times[-1]


def convolve(first: Shaper, second: Shaper) -> Shaper:
    r"""The shaper of two modes: the convolution of two impulse sequences, amplitudes
    :math:`A_i B_j` at times :math:`t_i + \tau_j` (equal times merged). Its residual
    vibration at any frequency is the product of the two shapers' [SS90], so it leaves none
    at either design frequency; it lasts as long as both together. ``frequency`` and
    ``zeta`` are the first's; the name joins both (``zv*zv``).

    >>> s = convolve(zv(10.0), zv(20.0))
    >>> s.amplitudes, s.times
    ((0.25, 0.25, 0.25, 0.25), (0.0, 0.025, 0.05, 0.075))
    """
    pairs: dict[float, float] = {}
    for a, t in zip(first.amplitudes, first.times):
        for b, u in zip(second.amplitudes, second.times):
            key = round(t + u, 15)
            pairs[key] = pairs.get(key, 0.0) + a * b
    times = tuple(sorted(pairs))
    return Shaper(f"{first.name}*{second.name}", tuple(pairs[t] for t in times), times, first.frequency, first.zeta,
                  first.vtol)


def _check_mode(frequency: float, zeta: float) -> tuple[float, float]:
    """The damped period T_d [s] and K = exp(-zeta pi / sqrt(1 - zeta^2)) of a mode."""
    require_positive("frequency", frequency, "Hz")
    require_range("zeta", zeta, "", 0.0, 1.0, high_open=True)
    root = math.sqrt(1.0 - zeta * zeta)
    return 1.0 / (frequency * root), math.exp(-zeta * math.pi / root)


def zv(frequency: float, zeta: float = 0.0) -> Shaper:
    r"""The zero-vibration (ZV) shaper of a mode: two impulses half a damped period apart.

    .. math::
        A = \left[\frac{1}{1+K}, \frac{K}{1+K}\right], \quad t = [0, T_d/2], \quad
        K = e^{-\zeta\pi/\sqrt{1-\zeta^2}}, \quad T_d = \frac{1}{f\sqrt{1-\zeta^2}}

    Parameters
    ----------
    frequency : float
        Natural frequency of the mode f, [Hz]
    zeta : float
        Damping ratio of the mode, in [0, 1)

    Notes
    -----
    [SS90], two impulses: zero residual vibration at the design frequency only.

    Examples
    --------
    >>> s = zv(10.0)
    >>> s.amplitudes, s.times
    ((0.5, 0.5), (0.0, 0.05))
    """
    td, k = _check_mode(frequency, zeta)
    return Shaper("zv", (1.0 / (1.0 + k), k / (1.0 + k)), (0.0, 0.5 * td), frequency, zeta)


def zvd(frequency: float, zeta: float = 0.0) -> Shaper:
    r"""The zero-vibration-derivative (ZVD) shaper: three impulses over one damped period,
    zero vibration and zero slope of the vibration over frequency at the design.

    .. math::
        A = \frac{[1, 2K, K^2]}{(1+K)^2}, \quad t = [0, T_d/2, T_d]

    Notes
    -----
    [SS90], three impulses (the ZV sequence convolved with itself).

    Examples
    --------
    >>> s = zvd(10.0)
    >>> s.amplitudes, s.times
    ((0.25, 0.5, 0.25), (0.0, 0.05, 0.1))
    """
    td, k = _check_mode(frequency, zeta)
    n = (1.0 + k) ** 2
    return Shaper("zvd", (1.0 / n, 2.0 * k / n, k * k / n), (0.0, 0.5 * td, td), frequency, zeta)


def _response(amplitudes, times, ratio, zeta: float, omega: float):
    """The complex residual-vibration sum G = sum A_i exp(s (t_i - t_n)), s = omega ratio
    (zeta + i sqrt(1 - zeta^2)), over the frequency ratios ``ratio`` (any shape): |G| is
    V of :func:`residual_vibration` (its exponents are <= 0, so nothing overflows)."""
    s = omega * np.asarray(ratio, dtype=float)[..., None] * complex(zeta, math.sqrt(1.0 - zeta * zeta))
    a, t = np.asarray(amplitudes, dtype=float), np.asarray(times, dtype=float)
    return (a * np.exp(s * (t - t[-1]))).sum(axis=-1)


def _ei_equations(x: np.ndarray, vtol: float, zeta: float) -> np.ndarray:
    """The six EI conditions on x = (A1, A2, t2, t3, r_lo, r_hi) for omega = 1 rad/s (times
    in s, frequencies as ratios to it): G = 0 at r_lo and at r_hi (real and imaginary
    parts), |G(1)|^2 = Vtol^2, d|G|^2/dr = 0 at r = 1."""
    a1, a2, t2, t3, lo, hi = x
    amps, times = (a1, a2, 1.0 - a1 - a2), np.array([0.0, t2, t3])
    g = _response(amps, times, [lo, hi, 1.0], zeta, 1.0)
    s = complex(zeta, math.sqrt(1.0 - zeta * zeta))
    dg = (np.asarray(amps) * s * (times - t3) * np.exp(s * (times - t3))).sum()
    return np.array([g[0].real, g[0].imag, g[1].real, g[1].imag,
                     abs(g[2]) ** 2 - vtol * vtol, 2.0 * (g[2].conjugate() * dg).real])


def _ei_newton(x: np.ndarray, vtol: float, zeta: float) -> np.ndarray | None:
    """Newton's method on :func:`_ei_equations` from ``x`` (central-difference Jacobian, the
    step halved until the residual falls); None where it does not converge."""
    with np.errstate(over="ignore", invalid="ignore"):
        f = _ei_equations(x, vtol, zeta)
        for _ in range(60):
            norm = np.max(np.abs(f))
            if norm < 1e-14:
                return x
            jac = np.empty((6, 6))
            for k in range(6):
                step = np.zeros(6)
                step[k] = 1e-7 * max(1.0, abs(x[k]))
                jac[:, k] = (_ei_equations(x + step, vtol, zeta) - _ei_equations(x - step, vtol, zeta)) / (2 * step[k])
            try:
                dx = np.linalg.solve(jac, -f)
            except np.linalg.LinAlgError:
                return None
            for _ in range(30):
                f_new = _ei_equations(x + dx, vtol, zeta)
                if np.max(np.abs(f_new)) < norm:
                    break
                if norm < 1e-12:          # no step lowers it: converged to rounding
                    return x
                dx = 0.5 * dx
            x, f = x + dx, f_new
            if not np.all(np.isfinite(f)):
                return None
            if np.max(np.abs(dx)) < 1e-15 * max(1.0, np.max(np.abs(x))):
                break
    return x if np.max(np.abs(f)) < 1e-12 else None


def _ei_fit(vtol: float, zeta: float) -> np.ndarray:
    """A start for :func:`_ei_newton` at omega = 1 rad/s: Singhose's curve fits of the damped
    EI shaper (amplitudes, and t_2 in damped periods, the last impulse at one), the zeros of
    the undamped shaper."""
    v, z = vtol, zeta
    a1 = (0.24968 + 0.24961 * v) + ((0.80008 + 1.23328 * v) + (0.49599 + 3.17316 * v) * z) * z
    a3 = (0.25149 + 0.21474 * v) + ((-0.83249 + 1.41498 * v) + (0.85181 - 4.90094 * v) * z) * z
    t2 = 0.4999 + (((0.46159 + 8.57843 * v) * v)
                   + (((4.26169 - 108.644 * v) * v) + ((1.75601 + 336.989 * v) * v) * z) * z) * z
    period = 2.0 * math.pi / math.sqrt(1.0 - z * z)
    r_lo = (2.0 / math.pi) * math.asin(math.sqrt(1.0 / (1.0 + v)))
    return np.array([a1, 1.0 - a1 - a3, t2 * period, period, r_lo, 2.0 - r_lo])


def ei(frequency: float, zeta: float = 0.0, vtol: float = 0.05) -> Shaper:
    r"""The extra-insensitive (EI) shaper: three impulses leaving the vibration ``vtol`` at
    the design frequency, at the peak of a hump between two frequencies of zero vibration
    (one below, one above), which widens the band of low vibration.

    Undamped (exact, [SSS94]):

    .. math::
        A = \left[\frac{1+V_{tol}}{4}, \frac{1-V_{tol}}{2}, \frac{1+V_{tol}}{4}\right],
        \quad t = [0, T/2, T]

    Damped, the defining conditions solved exactly (Newton's method from Singhose's curve
    fits, or from the undamped sequence continued in zeta where that fails): with
    :math:`V(\omega)` of :func:`residual_vibration`,
    :math:`V(\omega_{lo}) = V(\omega_{hi}) = 0` (both components of the sum),
    :math:`V(\omega_m) = V_{tol}` and :math:`\partial V / \partial \omega (\omega_m) = 0`,
    for A_1, A_2 (A_3 = 1 - A_1 - A_2), t_2, t_3, :math:`\omega_{lo}`, :math:`\omega_{hi}`.

    Parameters
    ----------
    frequency : float
        Natural frequency of the mode f, [Hz]
    zeta : float
        Damping ratio of the mode, in [0, 1)
    vtol : float
        Vibration tolerance V_tol at the design frequency, a fraction of the unshaped
        vibration in (0, 1) (0.05: 5 %)

    Notes
    -----
    [SSS94] introduce the EI shaper: V = Vtol at the modelling frequency and V = 0 at one
    frequency below and one above it; the undamped sequence above meets that with the
    hump's peak at the design. Singhose's curve fits of the damped sequence in zeta and Vtol
    (reproduced, e.g., in Klipper's ``shaper_defs.py``) fix the last impulse at T_d; here the
    last time is free and the peak stays at the design frequency, so V <= Vtol holds on the
    whole band between the two ends at Vtol (with t_3 = T_d the hump overshoots Vtol, by 0.3 to
    0.6 % of it at zeta = 0.2 and Vtol 5 to 30 %). The fits' amplitudes agree with these to 1e-3 and their times to
    1.5 % of T_d for zeta <= 0.2, Vtol = 5 % (the last impulse comes here a little before
    T_d). Where no sequence of positive impulses meets the
    conditions (heavy damping with a large ``vtol``), :class:`InputError` says so.

    Examples
    --------
    >>> s = ei(10.0)
    >>> [round(a, 6) for a in s.amplitudes], s.times
    ([0.2625, 0.475, 0.2625], (0.0, 0.05, 0.1))
    """
    td, _ = _check_mode(frequency, zeta)
    require_range("vtol", vtol, "", 0.0, 1.0, low_open=True, high_open=True)
    if zeta == 0.0:
        a = (0.25 * (1.0 + vtol), 0.5 * (1.0 - vtol), 0.25 * (1.0 + vtol))
        return Shaper("ei", a, (0.0, 0.5 * td, td), frequency, zeta, vtol)
    r_lo = (2.0 / math.pi) * math.asin(math.sqrt(1.0 / (1.0 + vtol)))  # undamped zeros: 1 -+ (1 - r_lo)
    x = np.array([0.25 * (1.0 + vtol), 0.5 * (1.0 - vtol), math.pi, 2.0 * math.pi, r_lo, 2.0 - r_lo])
    z_done, step = 0.0, min(zeta, 0.05)
    guess = _ei_newton(_ei_fit(vtol, zeta), vtol, zeta)
    if guess is not None:
        x, z_done = guess, zeta
    while x is not None and z_done < zeta:       # continued in zeta, the step halved where it fails
        z = min(zeta, z_done + step)
        # the start: the last solution, its times stretched as the damped period 2 pi / sqrt(1 - z^2)
        stretch = math.sqrt((1.0 - z_done * z_done) / (1.0 - z * z))
        x_new = _ei_newton(x * np.array([1.0, 1.0, stretch, stretch, 1.0, 1.0]), vtol, z)
        if x_new is not None:
            x, z_done, step = x_new, z, min(2.0 * step, 0.05)
        elif step > 1e-3:
            step *= 0.5
        else:
            x = None
    amps = None if x is None else (x[0], x[1], 1.0 - x[0] - x[1])
    if amps is None or min(amps) <= 0 or not (0 < x[2] < x[3]) or not (x[4] < 1.0 < x[5]) \
            or np.max(np.abs(_response(amps, [0.0, x[2], x[3]], np.linspace(x[4], x[5], 201), zeta, 1.0))) \
            > vtol * (1.0 + 1e-9):         # the hump between the zeros peaks at the design, at vtol
        raise InputError(f"no extra-insensitive shaper of positive impulses for zeta = {zeta:g} with "
                         f"`vtol` = {vtol:g}: lower `vtol` or use zvd", param="zeta")
    scale = 1.0 / (2.0 * math.pi * frequency)          # the times above are for omega = 1 rad/s
    return Shaper("ei", tuple(float(a) for a in amps), (0.0, float(x[2] * scale), float(x[3] * scale)),
                  frequency, zeta, vtol)


#: The shapers by name, each a function of (frequency, zeta[, vtol]) giving a :class:`Shaper`.
SHAPERS = {"zv": zv, "zvd": zvd, "ei": ei}


def residual_vibration(shaper: Shaper, frequency, zeta: float | None = None):
    r"""Residual vibration V of a mode of ``frequency`` [Hz] and damping ``zeta`` after the
    shaper's impulses, as a fraction of the vibration one unit impulse leaves (0.05: 5 %):
    vectorised over ``frequency``, its sensitivity curve.

    .. math::
        V = e^{-\zeta\omega t_n}\sqrt{\Big(\sum_i A_i e^{\zeta\omega t_i}\cos\omega_d t_i\Big)^2
        + \Big(\sum_i A_i e^{\zeta\omega t_i}\sin\omega_d t_i\Big)^2},
        \quad \omega = 2\pi f, \quad \omega_d = \omega\sqrt{1-\zeta^2}

    Parameters
    ----------
    shaper : Shaper
        The impulse sequence
    frequency : float or array_like
        Natural frequency of the mode f (the actual one, which may differ from the design), [Hz]
    zeta : float, optional
        Damping ratio of the mode in [0, 1); the shaper's design damping when None

    Returns
    -------
    float or numpy.ndarray
        V, the shape of ``frequency``

    Notes
    -----
    The residual vibration of [SS90]; computed as :math:`|\sum_i A_i e^{s (t_i - t_n)}|`,
    :math:`s = \zeta\omega + i\omega_d`, the same number without exponentials that overflow.
    A shaped move leaves V times the vibration the unshaped move leaves (the convolution).

    Examples
    --------
    >>> s = zv(10.0)
    >>> round(residual_vibration(s, 10.0), 12), round(float(residual_vibration(s, 11.0)), 4)
    (0.0, 0.1564)
    """
    zeta = shaper.zeta if zeta is None else zeta
    require_range("zeta", zeta, "", 0.0, 1.0, high_open=True)
    f = np.asarray(frequency, dtype=float)
    if not np.all(np.isfinite(f) & (f > 0)):
        bad = f[~(np.isfinite(f) & (f > 0))].flat[0]
        require_positive("frequency", float(bad), "Hz")
    v = np.abs(_response(shaper.amplitudes, shaper.times, f, zeta, 2.0 * math.pi))
    return float(v) if v.ndim == 0 else v


def _crossing(v, lo: float, hi: float, level: float) -> float:
    """The ratio in [lo, hi] where ``v`` (of a ratio) crosses ``level``, by bisection."""
    below = v(lo) <= level
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if (v(mid) <= level) == below:
            lo = mid
        else:
            hi = mid
    return float(0.5 * (lo + hi))


def insensitivity(shaper: Shaper, level: float | None = None, zeta: float | None = None) -> tuple[float, float]:
    r"""The band of frequencies (low, high), as ratios to the design frequency, in which the
    residual vibration stays at or below ``level`` (a fraction; the shaper's ``vtol``, else
    0.05, when None). ``high - low`` is the shaper's insensitivity at that level.

    The band runs from the lowest zero (or least) of the vibration near the design
    frequency down, and from the highest up, to where V reaches ``level``: for the EI
    shaper it holds the hump between its two zeros, whose peak is ``vtol`` at the design.

    Notes
    -----
    Undamped, ZV: :math:`V = |\cos(\pi r / 2)|`, so the band at 5 % is
    :math:`1 \pm (2/\pi)\arcsin 0.05` (width 0.064); ZVD: :math:`V = \cos^2(\pi r / 2)`,
    width 0.287; EI at Vtol = 5 %: width 0.399 (the 0.06, 0.29 and 0.40 the input-shaping
    literature quotes).
    Found on a grid of ratios 0.01 to 3 refined by bisection to rounding.

    Examples
    --------
    >>> [round(r, 4) for r in insensitivity(zv(10.0), 0.05)]
    [0.9682, 1.0318]
    """
    level = (shaper.vtol if shaper.vtol is not None else 0.05) if level is None else level
    require_range("level", level, "", 0.0, 1.0, low_open=True, high_open=True)

    def v(r):
        return residual_vibration(shaper, r * shaper.frequency, zeta)

    grid = np.linspace(0.01, 3.0, 2991)                 # steps of 1e-3, 1.0 on it
    vals = v(grid)
    near = (grid >= 0.4) & (grid <= 1.6)             # where the zeros of ZV, ZVD and EI lie
    i_lo = int(np.argmin(np.where(near & (grid <= 1.0), vals, np.inf)))
    i_hi = int(np.argmin(np.where(near & (grid >= 1.0), vals, np.inf)))
    if min(vals[i_lo], vals[i_hi]) > level:
        raise InputError(f"{level:g} is below the least vibration the shaper leaves near its design "
                         f"frequency ({min(vals[i_lo], vals[i_hi]):.3g})", param="level")
    down = next((k for k in range(i_lo, -1, -1) if vals[k] > level), None)
    up = next((k for k in range(i_hi, len(grid)) if vals[k] > level), None)
    low = 0.0 if down is None else _crossing(v, grid[down], grid[down + 1], level)
    high = math.inf if up is None else _crossing(v, grid[up - 1], grid[up], level)
    return low, high


# -- a move convolved with a shaper ----------------------------------------------------------------

def _piece(phases, starts, tau: float, v_end: float):
    """(speed, acceleration, jerk) polynomial of the move around its time ``tau`` [s]: the
    phase holding ``tau`` as (speed0, accel, jerk, start), or constant speed before the
    move (at the first phase's speed0) and after it (at ``v_end``)."""
    if tau < starts[0]:
        return phases[0].speed0, 0.0, 0.0, tau
    for ph, t0 in zip(phases, starts):
        if tau < t0 + ph.duration:
            return ph.speed0, ph.accel, ph.jerk, t0
    return v_end, 0.0, 0.0, tau


def shape_phases(phases, shaper: Shaper) -> tuple[Phase, ...]:
    r"""The move ``phases`` convolved with ``shaper``: the acceleration
    :math:`a_s(t) = \sum_i A_i\, a(t - t_i)`, again piecewise linear in time, as phases
    (one per interval between the move's phase boundaries shifted by every t_i), named
    ``"shaped 1"``, ``"shaped 2"``, ...

    The shaped move lasts ``shaper.duration`` longer; it starts at the first phase's speed0
    and ends at the last phase's end speed, and its speed is
    :math:`\omega_s(t) = \sum_i A_i\, \omega(t - t_i)` (the move held at its start speed
    before it and at its end speed after it). A rest-to-rest move keeps its angle; one that
    starts at :math:`\omega_0` or ends at :math:`\omega_1` covers
    :math:`\theta + \sum_i A_i (\omega_0 t_i + \omega_1 (t_n - t_i))`. Speed, acceleration
    and jerk stay within the move's own bounds (the A_i are positive and sum to 1).
    Boundaries closer than 1e-12 of the move's time are merged (no phase of zero duration),
    and a phase is split where its acceleration crosses zero, so that every phase's speed
    has its extremes at its ends (``peak_speed`` of a profile reads them).

    Parameters
    ----------
    phases : sequence of Phase
        The move, phases of constant jerk (:class:`beltcalc.formulas.profiles.Phase`)
    shaper : Shaper
        The impulse sequence

    Examples
    --------
    >>> from beltcalc.formulas.profiles import trapezoid
    >>> p = shape_phases(trapezoid(100.0, 1000.0, 50.0).phases, zv(10.0))
    >>> [round(ph.duration, 4) for ph in p], [round(ph.accel, 1) for ph in p]
    ([0.05, 0.05, 0.05, 0.35, 0.05, 0.05, 0.05], [500.0, 1000.0, 500.0, 0.0, -500.0, -1000.0, -500.0])
    >>> round(sum(ph.angle for ph in p), 12)
    50.0
    """
    phases = [ph for ph in phases if ph.duration > 0]
    if not phases:
        return ()
    starts = np.concatenate([[0.0], np.cumsum([ph.duration for ph in phases])])
    end, v_end = float(starts[-1]), phases[-1].speed1
    amps, times = shaper.amplitudes, shaper.times
    total = end + shaper.duration
    edges = np.unique(np.add.outer(np.asarray(times), starts).ravel())
    keep = [edges[0]]
    for e in edges[1:]:
        if e - keep[-1] > 1e-12 * total:
            keep.append(e)
    keep[-1] = max(keep[-1], edges[-1])
    starts = [float(t) for t in starts[:-1]]
    out = []
    for b0, b1 in zip(keep[:-1], keep[1:]):
        mid = 0.5 * (b0 + b1)
        w = acc = jerk = 0.0
        for a_i, t_i in zip(amps, times):
            w0, a0, j0, t0 = _piece(phases, starts, mid - t_i, v_end)
            tau = b0 - t_i - t0          # from the piece's start to this phase's start
            w += a_i * (w0 + a0 * tau + 0.5 * j0 * tau * tau)
            acc += a_i * (a0 + j0 * tau)
            jerk += a_i * j0
        d = float(b1 - b0)
        cut = -acc / jerk if jerk != 0.0 else 0.0      # the acceleration's zero inside: a phase boundary
        if 1e-12 * total < cut < d - 1e-12 * total:
            first = Phase("", cut, float(w), float(acc), float(jerk))
            out += [first, Phase("", d - cut, first.speed1, 0.0, float(jerk))]
        else:
            out.append(Phase("", d, float(w), float(acc), float(jerk)))
    return tuple(replace(ph, name=f"shaped {k}") for k, ph in enumerate(out, start=1))


def shaped_profile(profile: Trapezoid, shaper: Shaper) -> SCurve:
    """A :class:`beltcalc.formulas.profiles.Trapezoid` or ``SCurve`` with its move shaped
    (:func:`shape_phases`), as an ``SCurve`` (a trapezoid becomes the ``SCurve`` of
    infinite jerk that :func:`beltcalc.formulas.profiles.scurve` makes of it), so that
    ``peak_speed`` reads the shaped phases.

    The trailing ``"dwell"`` phase absorbs the shaper's duration where it is at least as
    long (the cycle time stays); a shorter dwell is kept whole and the cycle lengthens by
    ``shaper.duration``. ``dwell`` is the new standstill, ``peak_accel`` the shaped
    move's peak acceleration (at most the original's); ``speed``, ``accel``, ``jerk`` stay
    the limits the move was planned with, which the shaped move keeps.

    Examples
    --------
    >>> from beltcalc.formulas.profiles import trapezoid
    >>> p = shaped_profile(trapezoid(100.0, 1000.0, 50.0, dwell=0.2), zv(10.0))
    >>> round(p.cycle_time, 12), round(p.dwell, 12), p.phases[-1].name
    (0.8, 0.15, 'dwell')
    """
    if not isinstance(profile, SCurve):
        profile = SCurve(profile.speed, profile.accel, profile.stroke, profile.dwell, profile.phases,
                         profile.triangular, jerk=math.inf, peak_accel=profile.accel)
    phases = list(profile.phases)
    dwell = 0.0
    while phases and phases[-1].name == "dwell":
        dwell += phases.pop().duration
    move = shape_phases(phases, shaper)
    if dwell >= shaper.duration:
        dwell -= shaper.duration
    tail = (Phase("dwell", dwell, 0.0, 0.0),) if dwell > 1e-12 * sum(p.duration for p in move) else ()
    peak = max((max(abs(p.accel), abs(p.accel1)) for p in move), default=0.0)
    return replace(profile, phases=move + tail, dwell=dwell if tail else 0.0, peak_accel=peak)
