"""Fatigue of a loaded part from a sampled force: rainflow counting of the load's cycles,
an S-N (Woehler) curve and Palmgren-Miner damage summation, and the S-N curve of a roller
chain from its maker's allowable (fatigue) load. numpy floats and arrays, SI units.

References:

[ASTM E1049] ASTM E1049-85 (reapproved 2017), Standard Practices for Cycle Counting in
    Fatigue Analysis: reduction to peaks and valleys [ASTM E1049 sec. 3.2.8, 5.4.1] and
    rainflow counting with the three-point rule, half cycles for the residue
    [ASTM E1049 sec. 5.4.4], its worked example [ASTM E1049 Fig. 6].
[Miner45] M. A. Miner, "Cumulative damage in fatigue", J. Appl. Mech. 12 (1945) A159-A164:
    the linear damage sum D = sum n_i / N_i, failure at D = 1 [Miner45 eq. 1].
[FKM12] FKM Guideline, Analytical Strength Assessment of Components, 6th ed., VDMA (2012):
    the S-N curve of non-welded steel components under normal stress, slope k = 5, and the
    Miner variants below its knee (elementary; Haibach's slope 2k - 1) [FKM12 sec. 4.4].
    The slope is taken as the guideline's value as the field knows it; the printed page was
    not at hand in this work.
[Tsubaki chains] U.S. Tsubaki, Roller Chain General Catalog: the maximum allowable load of
    a roller chain, "derived from the lowest fatigue limit" (its glossary).
[Tsubaki glossary] Tsubakimoto Europe, support / general info / glossary (tsubaki.de):
    the maximum allowable load is set at 10 million load repetitions (the European standard:
    3 million).
[Tsubaki guide] Tsubakimoto Chain Co., The Complete Guide to Chain, sec. 2.2.2 (chain-guide.com),
    "Repeated load tension, fatigue failure": the fatigue test pulses between
    P_min = P_max / 11 and P_max (JIS B 1801).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from beltcalc.errors import InputError

#: A chain's fatigue test pulses from P_max / 11 to P_max: the range is 10/11 of the peak
#: [Tsubaki guide sec. 2.2.2].
CHAIN_TEST_RANGE = 10.0 / 11.0
#: The load repetitions at which a chain's maximum allowable load is set [Tsubaki glossary].
CHAIN_ENDURANCE_CYCLES = 1.0e7
#: The S-N slope taken for a chain's link plates (assumed: no maker publishes one): the FKM
#: guideline's slope of non-welded steel components under normal stress [FKM12 sec. 4.4].
CHAIN_SLOPE = 5.0
#: What a range below the knee does (:class:`SNCurve`): none, as the maker states of loads
#: below the allowable load [Tsubaki chains].
CHAIN_ENDURANCE = "cutoff"


@dataclass(frozen=True)
class Cycles:
    """The cycles rainflow counting finds: per counted cycle its ``ranges`` [signal unit],
    ``means`` [signal unit] and ``counts`` (1.0 a full cycle, 0.5 a half cycle)."""

    ranges: np.ndarray
    means: np.ndarray
    counts: np.ndarray

    @property
    def total(self) -> float:
        """The number of cycles counted (half cycles count one half)."""
        return float(np.sum(self.counts))


def turning_points(signal) -> np.ndarray:
    """The peaks and valleys of a sampled ``signal``, its first and last samples kept
    [ASTM E1049 sec. 5.4.1]: runs of equal samples (plateaus) collapse to one, samples on a
    rising or falling flank between two turning points drop out.

    >>> turning_points([0.0, 1.0, 2.0, 2.0, 1.0, 1.0, 3.0, 0.0]).tolist()
    [0.0, 2.0, 1.0, 3.0, 0.0]
    >>> turning_points([1.0, 1.0]).tolist()
    [1.0]
    """
    x = np.asarray(signal, dtype=float).ravel()
    if x.size == 0:
        return x
    if not np.all(np.isfinite(x)):
        raise InputError("the signal to count has a sample that is not a finite number")
    x = x[np.r_[True, np.diff(x) != 0.0]]           # a plateau is one point
    if x.size < 3:
        return x
    rising = np.diff(x) > 0.0
    turn = np.nonzero(rising[1:] != rising[:-1])[0] + 1
    return x[np.r_[0, turn, x.size - 1]]


def rainflow(signal) -> Cycles:
    r"""Rainflow counting of a sampled ``signal`` [ASTM E1049 sec. 5.4.4].

    Reduced to its turning points (:func:`turning_points`), each point is pushed on a stack;
    while the stack holds three or more points, X is the range of the last two and Y the
    range of the two before: X < Y reads the next point; else, where Y holds the start of
    the stack, Y is counted as a half cycle and its first point discarded, otherwise Y is
    counted as one cycle and both its points discarded. At the end each range of the
    residue counts as a half cycle. A cycle's range is ``|a - b|``, its mean ``(a + b) / 2``.

    Parameters
    ----------
    signal : array_like
        The samples, in time order [any unit]

    Returns
    -------
    Cycles
        Ranges and means [the signal's unit], counts (0.5 or 1.0), in the order counted

    Notes
    -----
    A sampled signal counts only what its samples show: a peak between two samples is cut
    to the larger of them. The loop runs over turning points (the counting is sequential);
    a run of 10^6 turning points counts in about a second.

    Examples
    --------
    The example of [ASTM E1049 Fig. 6]:

    >>> c = rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2])
    >>> c.ranges.tolist(), c.counts.tolist()
    ([3.0, 4.0, 4.0, 8.0, 9.0, 8.0, 6.0], [0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 0.5])
    """
    points = turning_points(signal)
    ranges, means, counts = [], [], []
    stack: list[float] = []
    start = 0                      # index in ``stack`` of the point that began the count
    for p in points.tolist():
        stack.append(p)
        while len(stack) - start >= 3:
            x = abs(stack[-1] - stack[-2])
            y = abs(stack[-2] - stack[-3])
            if x < y:
                break
            a, b = stack[-3], stack[-2]
            ranges.append(y)
            means.append(0.5 * (a + b))
            if len(stack) - start == 3:          # Y holds the starting point: a half cycle
                counts.append(0.5)
                start += 1
            else:
                counts.append(1.0)
                del stack[-3:-1]
    rest = stack[start:]
    for a, b in zip(rest, rest[1:]):
        ranges.append(abs(b - a))
        means.append(0.5 * (a + b))
        counts.append(0.5)
    return Cycles(np.array(ranges, dtype=float), np.array(means, dtype=float), np.array(counts, dtype=float))


@dataclass(frozen=True)
class SNCurve:
    r"""An S-N curve in ranges: a range ``range_ref`` [N] lasts ``cycles_ref`` cycles, and

    .. math:: N(\Delta F) = N_D \left(\frac{\Delta F_D}{\Delta F}\right)^k

    above it (slope ``slope`` = k). Below the knee ``endurance`` says what a range does:
    ``"cutoff"`` no damage (Miner's original rule), ``"elementary"`` the same slope
    (Miner elementary), ``"haibach"`` the slope 2k - 1 [FKM12 sec. 4.4]. The mean of a
    cycle is not corrected for: the curve holds for the mean of its test.
    ``origin``: where the curve comes from (``"published"`` or ``"assumed"``), for the
    report.
    """

    range_ref: float
    cycles_ref: float
    slope: float
    endurance: str = "cutoff"
    origin: str = "assumed"

    def __post_init__(self):
        if not (self.range_ref > 0 and self.cycles_ref > 0 and self.slope > 0):
            raise InputError(f"an S-N curve needs a reference range, cycles and slope > 0, got {self.range_ref:g}, "
                             f"{self.cycles_ref:g}, {self.slope:g}")
        if self.endurance not in ("cutoff", "elementary", "haibach"):
            raise InputError(f"an S-N curve's endurance is cutoff, elementary or haibach, not {self.endurance!r}")

    def cycles(self, ranges) -> np.ndarray:
        """The cycles to failure at each range [N] (inf: none below a cutoff, or a zero range).

        >>> SNCurve(100.0, 1e6, 5.0).cycles([200.0, 100.0, 50.0]).tolist()
        [31250.0, 1000000.0, inf]
        >>> SNCurve(100.0, 1e6, 5.0, "haibach").cycles([50.0]).tolist()        # slope 9 below
        [512000000.0]
        """
        r = np.abs(np.asarray(ranges, dtype=float))
        with np.errstate(divide="ignore", over="ignore"):
            ratio = self.range_ref / r
            n = self.cycles_ref * ratio ** self.slope
            below = r < self.range_ref
            if self.endurance == "cutoff":
                n = np.where(below, np.inf, n)
            elif self.endurance == "haibach":
                n = np.where(below, self.cycles_ref * ratio ** (2.0 * self.slope - 1.0), n)
        return np.where(r > 0.0, n, np.inf)


def miner_damage(ranges, means, counts, curve: SNCurve) -> float:
    r"""Palmgren-Miner damage of counted cycles on ``curve`` [Miner45 eq. 1].

    .. math:: D = \sum_i \frac{n_i}{N(\Delta F_i)}

    Parameters
    ----------
    ranges : array_like
        Range of each counted cycle [N]
    means : array_like
        Mean of each counted cycle [N]: not used by a curve without mean correction (as
        :class:`SNCurve`), taken so that a rainflow count passes whole
    counts : array_like
        Cycles of each (0.5 or 1.0 from :func:`rainflow`)
    curve : SNCurve
        The S-N curve

    Returns
    -------
    float
        The damage D [-]; 1 is failure

    Examples
    --------
    Hand calculation: 1000 cycles of 200 N on 100 N / 1e6 cycles / k = 5 use
    1000 / 31250 = 0.032; 10^6 cycles of 50 N below the cutoff nothing.

    >>> miner_damage([200.0, 50.0], [0.0, 0.0], [1000.0, 1e6], SNCurve(100.0, 1e6, 5.0))
    0.032
    """
    r = np.asarray(ranges, dtype=float)
    n = np.asarray(counts, dtype=float)
    if r.shape != n.shape or np.shape(means) != r.shape:
        raise InputError(f"ranges, means and counts must be of one length, got {r.shape}, {np.shape(means)}, "
                         f"{n.shape}")
    return float(np.sum(n / curve.cycles(r)))


def damage_rate(damage: float, duration: float) -> float:
    """Damage per second [1/s] of a window of ``duration`` [s] that repeats.

    >>> damage_rate(0.032, 3600.0) * 3600.0
    0.032
    """
    if duration <= 0:
        raise InputError(f"the window's duration must be > 0 s, got {duration:g} s")
    return damage / duration


def life(rate: float) -> float:
    """The time to D = 1 [s] at the damage rate ``rate`` [1/s]; inf where nothing is damaged
    ([Miner45 eq. 1]).

    >>> life(1e-6), life(0.0)
    (1000000.0, inf)
    """
    return 1.0 / rate if rate > 0 else float("inf")


def chain_sn_curve(allowable: float, origin: str = "assumed") -> SNCurve:
    r"""The S-N curve of a roller chain from its maker's maximum allowable load
    ``allowable`` [N] (the fatigue limit, [Tsubaki chains]): the knee at the test's range
    :math:`\Delta F_D = (10/11) F_{allow}` ([Tsubaki guide sec. 2.2.2], P_min = P_max / 11)
    and :data:`CHAIN_ENDURANCE_CYCLES` cycles ([Tsubaki glossary]), the slope
    :data:`CHAIN_SLOPE` (assumed, [FKM12 sec. 4.4]), no damage below the knee (the maker:
    below the allowable load "fatigue failure will never occur").

    >>> c = chain_sn_curve(11.0e3)
    >>> c.range_ref, c.cycles_ref, c.slope, c.endurance
    (10000.0, 10000000.0, 5.0, 'cutoff')
    """
    if not allowable > 0:
        raise InputError(f"a chain's allowable load must be > 0 N, got {allowable:g} N")
    return SNCurve(CHAIN_TEST_RANGE * allowable, CHAIN_ENDURANCE_CYCLES, CHAIN_SLOPE, CHAIN_ENDURANCE, origin)


@dataclass(frozen=True)
class StrandFatigue:
    """What a chain strand's fatigue check needs: its ``chain`` (catalog name), the maximum
    allowable (dynamic) load ``allowable`` [N] (None: no maker's figure) and where that comes
    from (``origin``)."""

    chain: str
    allowable: float | None
    origin: str
