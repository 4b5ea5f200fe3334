r"""The element kind "eccentric belt": a belt drive whose ratio varies with an eccentric tension
roller on its slack span ([M16 Fig. 2] and [M16 eq. 1]; the model derived in
``docs/eccentric_roller.md``, not typed from their garbled [M16 eq. 3-4]).

Two elastic spans of stiffness k = C / (2 r1^2) (damping b = d / (2 r1^2)) join the motor
pulley ``i`` (radius r1) and the driven rim ``j`` (radius r2); the roller's path stretch
delta(phi_i) = L(theta(phi_i)) - L(theta_0) enters the slack span. With x = r1 phi_i - r2 phi_j
and the pretension F_0 the spans carry (E6-E8)::

    F_t = F_0 + k x + b xdot                       (tight span)
    F_s = F_0 + k (delta - x) + b (deltadot - xdot)   (slack span, over the roller)
    Q_i = -r1 F_t + (r1 - delta_phi) F_s,    Q_j = r2 (F_t - F_s)

Without a pretension (``pretension=None``, the paper's linear belt) both spans are two-way
springs and F_0 = 0: the forces are the changes from an unknown pretension, and a span may
push. With one, each span is tension-only as a chain strand is (:mod:`beltcalc.sim.switching`):
it pulls only while it is stretched (F_0 + k e > 0) and its force is positive, else it is
slack and carries nothing; the pretension also turns the eccentric (its term F_0 delta_phi).

The element stamps the constant-ratio part (a coupling C (phi_i - U phi_j) + d (omega_i - U
omega_j), U = r2/r1) into the linear matrices and adds the rest as nonlinear terms, so without
eccentricity it *is* the constant-ratio coupling and the network stays linear (the spans are not
clipped then); with it, the core solves it implicitly (Radau) with the analytic Jacobian. A
span's slack switch is a kink of the right-hand side (unloading) or a jump of its damper's force
(take-up): Radau's step control resolves each (there is no event for it; the tests check the
result against a solver stopped at every switch).

The loop length L(theta) is a smooth periodic function of the roller angle: it is sampled
exactly (:mod:`beltcalc.sim.elements.beltpath`) at ``HARMONICS`` x 4 angles and held as its Fourier
series, so L, L' and L'' cost a few vector operations over any number of states.
:func:`refuse` turns away a geometry the model cannot hold (the pivot outside the roller, the
roller on a pulley or through the tight span, the belt leaving the roller), each with its cause.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    eccentric tension roller.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import ClassVar, Mapping

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.sim.elements.beltpath import Circle, Eccentric, span
from beltcalc.sim.elements import Element

HARMONICS = 64     # Fourier terms of L(theta); the coefficients fall geometrically (checked on build)

#: the roller's values by the names a drive file gives them (a scene passes its own names)
KEYS = {"r1": "pulley_radius", "r3": "roller_radius", "a": "center_distance", "px": "pivot_x", "py": "pivot_y",
        "delta": "eccentricity"}


@dataclass(frozen=True)
class EccentricBelt(Element):
    """Belt ``name`` from pulley node ``i`` (pitch radius ``r1``) to rim node ``j`` (``r2``),
    torsional stiffness ``C`` and damping ``d`` as seen at ``i`` (the paper's C1, d), the roller
    ``geometry`` (:class:`~beltcalc.sim.elements.beltpath.Eccentric`; its r1, r2 are the pulleys'), and
    the spans' ``pretension`` F_0 [N] (None: two-way spans without one, the paper's belt).
    Outputs: ``T_<name>`` the torque on ``i`` against its motion [N m], ``U_<name>`` the
    instantaneous ratio (E5), ``dF_<name>_tight`` / ``dF_<name>_slack`` the spans' force change
    from the pretension [N], and with a pretension ``F_<name>_tight`` / ``F_<name>_slack``
    their forces [N] (>= 0)."""

    name: str
    i: str
    j: str
    C: float
    d: float
    geometry: Eccentric
    pretension: float | None = None
    _series: tuple = field(default=(), compare=False, repr=False)

    UNITS: ClassVar[dict] = {"C": "N*m/rad", "d": "N*m*s/rad", "pretension": "N"}

    def __post_init__(self):
        super().__post_init__()
        g = self.geometry
        if g.delta > 0 and (not self._series or self._series[4] != g):     # kept by with_pretension
            refuse(g)
            object.__setattr__(self, "_series", _fourier(g))

    def with_pretension(self, pretension: float | None) -> "EccentricBelt":
        """The same belt with spans pretensioned by ``pretension`` [N] (tension-only), its
        tabulated path kept."""
        return replace(self, pretension=pretension)

    @property
    def ratio(self) -> float:
        return self.geometry.r2 / self.geometry.r1

    @property
    def k(self) -> float:
        return self.C / (2 * self.geometry.r1 ** 2)

    @property
    def b(self) -> float:
        return self.d / (2 * self.geometry.r1 ** 2)

    @property
    def nonlinear_kind(self) -> bool:
        return self.geometry.delta > 0

    nonlinear_reason = "an eccentric tension roller makes the belt ratio vary with the shaft angle"

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        net.require_inertia(self.i, f"belt {self.name}")
        net.require_inertia(self.j, f"belt {self.name}")
        require_range(self.name, self.C, "N*m/rad", low=0.0)
        require_range(self.name, self.d, "N*m*s/rad", low=0.0)
        if self.pretension is not None:
            require_range(f"pretension_{self.name}", self.pretension, "N", low=0.0)
        g = self.geometry
        for what, v in (("r1", g.r1), ("r2", g.r2), ("r3", g.r3)):
            require_positive(f"{what}_{self.name}", v, "m")
        require_range(f"delta_{self.name}", g.delta, "m", low=0.0, high=g.r3, high_open=True)

    def matrices(self, net) -> list:
        row = net.node_row(self.i) - self.ratio * net.node_row(self.j)
        return [(row, self.C, self.d)]

    # --- the roller's stretch delta(phi_i) and its derivatives ---------------------------------
    def stretch(self, phi_i):
        """(delta, delta_phi, delta_phiphi) at the pulley angle(s) ``phi_i`` [m, m/rad, m/rad^2]."""
        g = self.geometry
        if not self._series:
            z = np.zeros_like(np.asarray(phi_i, dtype=float))
            return z, z, z
        theta = g.theta(np.asarray(phi_i, dtype=float))
        L, L1, L2 = _evaluate(self._series, theta)
        s = -g.r1 / g.r3                      # dtheta/dphi_i
        return L - self._series[3], s * L1, s * s * L2

    def _states(self, net, X):
        ci, fi = net.coord(self.i)
        cj, fj = net.coord(self.j)
        n = net.n
        return (ci, fi, cj, fj, fi * X[ci], fj * X[cj], fi * X[n + ci], fj * X[n + cj])

    def spans(self, net, X):
        """Each span's force at the states ``X`` (columns) [N], and the pieces the right-hand
        side, its Jacobian and the outputs need: ``(F_t, F_s, raw_t, raw_s, taut_t, taut_s,
        kin)`` with ``raw`` the Kelvin-Voigt force of a taut span (E8), ``taut`` where it pulls
        (always, without a pretension) and ``kin = (delta, delta_phi, delta_phiphi, deltadot,
        omega_i)``."""
        ci, fi, cj, fj, p1, p2, w1, w2 = self._states(net, X)
        g, k, b = self.geometry, self.k, self.b
        delta, dphi, dpp = self.stretch(p1)
        x, xdot = g.r1 * p1 - g.r2 * p2, g.r1 * w1 - g.r2 * w2
        ddot = dphi * w1
        f0 = self.pretension or 0.0
        spring_t, spring_s = f0 + k * x, f0 + k * (delta - x)      # k x the span's stretch from its free length
        raw_t, raw_s = spring_t + b * xdot, spring_s + b * (ddot - xdot)
        if self.pretension is None or not self._series:     # two-way (without eccentricity: the linear coupling)
            taut_t = taut_s = True
            f_t, f_s = raw_t, raw_s
        else:                                     # tension-only: stretched and pulling, else slack
            taut_t = (spring_t > 0) & (raw_t > 0)
            taut_s = (spring_s > 0) & (raw_s > 0)
            f_t, f_s = raw_t * taut_t + 0.0, raw_s * taut_s + 0.0      # (+ 0.0: a slack span's 0 is not -0)
        return f_t, f_s, raw_t, raw_s, taut_t, taut_s, (delta, dphi, dpp, ddot, w1)

    def forces(self, net, X):
        """The nonlinear remainder of the generalized forces on i and j [N m]: Q_i, Q_j (E6-E8)
        minus the constant-ratio coupling's -2 r1 (k x + b xdot), 2 r2 (k x + b xdot)."""
        g, k, b = self.geometry, self.k, self.b
        f_t, f_s, raw_t, raw_s, _, _, (delta, dphi, _, ddot, _) = self.spans(net, X)
        roll = k * delta + b * ddot
        cut = (raw_t - f_t) - (raw_s - f_s)              # what slack spans do not carry
        return g.r1 * (roll + cut) - dphi * f_s, -g.r2 * (roll + cut)

    def nonlinear(self, net, t, X, out, constrained: bool) -> None:
        if not self._series:
            return
        ci, fi, cj, fj = *net.coord(self.i), *net.coord(self.j)
        r_i, r_j = self.forces(net, X)
        n = net.n
        if not (constrained and ci in net.fixed):
            out[n + ci] += fi * r_i / net.mass[ci]
        if not (constrained and cj in net.fixed):
            out[n + cj] += fj * r_j / net.mass[cj]

    def jacobian(self, net, x, jac) -> None:
        """d(the remainder)/d(state) at ``x``, on the side of each span's switch that
        :meth:`spans` takes there (the right-hand side's own branch)."""
        if not self._series:
            return
        ci, fi, cj, fj = *net.coord(self.i), *net.coord(self.j)
        g, k, b = self.geometry, self.k, self.b
        r1, r2 = g.r1, g.r2
        f_t, f_s, _, _, taut_t, taut_s, kin = self.spans(net, x)
        _, dp, dpp, _, w1 = (float(v) for v in kin)
        f_s = float(f_s)
        # partials over (phi_i, phi_j, omega_i, omega_j), node variables
        roll = np.array([k * dp + b * dpp * w1, 0.0, b * dp, 0.0])
        d_t = np.array([k * r1, -k * r2, b * r1, -b * r2])
        d_s = np.array([k * (dp - r1) + b * dpp * w1, k * r2, b * (dp - r1), b * r2])
        cut = (0.0 if taut_t else 1.0) * d_t - (0.0 if taut_s else 1.0) * d_s
        ri = r1 * (roll + cut) - dp * (d_s if taut_s else 0.0)
        ri[0] -= dpp * f_s
        rj = -r2 * (roll + cut)
        n = net.n
        cols = (ci, cj, n + ci, n + cj)
        facs = (fi, fj, fi, fj)
        for row_c, row_f, partials in ((ci, fi, ri), (cj, fj, rj)):
            if row_c in net.fixed:
                continue
            for col, f, v in zip(cols, facs, partials):
                jac[n + row_c, col] += row_f * v * f / net.mass[row_c]

    def excitation(self, result, window: float) -> list[tuple[float, str]]:
        """The roller's ripple as a periodic excitation: once per roller turn, r1/r3 times the
        pulley's mean speed over the window [Hz] (for the resonance check)."""
        if not self._series or f"omega_{self.i}" not in result.signals:
            return []
        speed = abs(result.summary(f"omega_{self.i}", window).mean)
        return [(self.geometry.r1 / self.geometry.r3 * speed / (2 * math.pi), f"the tension roller of {self.name}")]

    def outputs(self, net, t, X, dX) -> dict:
        X = np.asarray(X)
        g = self.geometry
        f_t, f_s, *_, (_, dphi, _, _, _) = self.spans(net, X)
        p1 = self._states(net, X)[4]
        torque = g.r1 * (f_t - f_s) + f_s * dphi      # -Q_i
        ratio = self.ratio / (1.0 - dphi / (2 * g.r1)) if self._series else \
            np.full(np.shape(p1), self.ratio)
        f0 = self.pretension or 0.0
        out = {f"T_{self.name}": (torque, "N m"), f"U_{self.name}": (ratio, "1"),
               f"dF_{self.name}_tight": (f_t - f0, "N"), f"dF_{self.name}_slack": (f_s - f0, "N")}
        if self.pretension is not None:
            out[f"F_{self.name}_tight"] = (f_t, "N")
            out[f"F_{self.name}_slack"] = (f_s, "N")
        return out

    # --- the quasi-static swing of the spans' forces ----------------------------------------------
    def swing(self, speed: float, delta: float | None = None, samples: int = 180) -> tuple[float, float]:
        r"""(min, max) over a roller turn of the spans' common force change [N], quasi-static:
        both spans taut, the transmitted force held, the pulley at ``speed`` [rad/s]:

        .. math:: \Delta F = \tfrac12 \left(k\,\delta(\theta) + b\,\delta_\varphi(\theta)\,\omega_1\right)

        (F_t + F_s = 2 F_0 + k delta + b deltadot, E8). ``delta``: at another eccentricity
        than the belt's [m]. From the exact belt path at ``samples`` roller angles."""
        g = self.geometry if delta is None else replace(self.geometry, delta=delta)
        if g.delta == 0:
            return 0.0, 0.0
        theta = 2 * math.pi * np.arange(samples) / samples
        L0 = g.length(g.theta0)
        change = np.empty(samples)
        for m, t in enumerate(theta):
            path = g.path(t)
            rate = float(path.gradient(1) @ np.array([-math.sin(t), math.cos(t)])) * g.delta     # L'(theta)
            change[m] = self.k * (path.length - L0) - self.b * g.r1 / g.r3 * rate * speed
        return float(change.min()) / 2, float(change.max()) / 2

    def slackening_eccentricity(self, level: float, speed: float) -> float | None:
        """The least eccentricity [m] at which a span whose force is ``level`` [N] without the
        roller's swing goes slack, quasi-statically (``level + swing_min = 0``, :meth:`swing`);
        0 where ``level <= 0``; None where it stays taut up to where the belt leaves the roller."""
        if level <= 0:
            return 0.0
        top = contact_limit(self.geometry) * (1 - 1e-6)
        if top <= 0 or level + self.swing(speed, top)[0] > 0:
            return None
        from scipy.optimize import brentq

        return brentq(lambda e: level + self.swing(speed, e)[0], 0.0, top, xtol=1e-3 * top)


# --- the geometry the model can hold ---------------------------------------------------------------
def _side(g: Eccentric, tight: bool) -> tuple[np.ndarray, np.ndarray]:
    """(a point on, the unit normal into the loop of) the straight belt between the two pulleys
    alone: the slack span (motor pulley -> rim, under the drive) or the tight one (rim -> motor
    pulley)."""
    motor, rim = Circle(0.0, 0.0, g.r1), Circle(g.a, 0.0, g.r2)
    s = span(rim, motor) if tight else span(motor, rim)
    return s.start, np.array([-s.u[1], s.u[0]])


def contact_limit(g: Eccentric) -> float:
    """The largest eccentricity [m] at which the roller keeps the belt at every angle: the
    roller (radius r3) must reach past the straight slack span, ``h(P) - Delta + r3 > 0``
    with h(P) the pivot's height over the span, into the loop. At the limit the belt's wrap
    on the roller falls to zero once a turn; beyond it the belt leaves the roller."""
    point, normal = _side(g, tight=False)
    return float((np.array([g.px, g.py]) - point) @ normal) + g.r3


def _gaps(g: Eccentric) -> list[tuple[float, str]]:
    """(clearance [m], what it is) of each way the roller can fail at its worst angle: on a
    pulley, through the tight span, clear of the slack span (> 0: it holds)."""
    pivot = np.array([g.px, g.py])
    out = []
    for label, centre, radius in (("motor pulley", np.zeros(2), g.r1), ("driven rim", np.array([g.a, 0.0]), g.r2)):
        gap = float(np.hypot(*(pivot - centre))) - g.delta - radius - g.r3
        out.append((gap, f"the roller nearly touches the {label}"))
    point, normal = _side(g, tight=True)
    out.append((float((pivot - point) @ normal) - g.delta - g.r3, "the roller nearly reaches the tight span"))
    out.append((contact_limit(g) - g.delta, "the belt nearly leaves the roller once a turn"))
    return out


def refuse(g: Eccentric, names: Mapping[str, str] = KEYS) -> None:
    """Refuse a roller geometry the model cannot hold, each with its true cause
    (:class:`~beltcalc.errors.InputError` naming the value by ``names``, :data:`KEYS` by
    default): the radii and the centre distance not positive or the pulleys overlapping, the
    eccentricity not below the roller radius (an eccentric's pivot lies inside its roller),
    the roller on a pulley or through the tight span at some angle (the pivot), the roller
    clear of the belt at every angle (the pivot) or for part of its turn (the eccentricity:
    the belt's wrap on it would fall to zero)."""
    mm = 1e3
    for key, v in (("r1", g.r1), ("r3", g.r3), ("a", g.a)):
        require_positive(names[key], v, "m")
    require_range(names["delta"], g.delta, "m", low=0.0)
    if not g.a > g.r1 + g.r2:
        raise InputError(f"the pulleys overlap: {g.a * mm:g} mm between their centres is not allowed; it must be "
                         f"> r1 + r2 = {(g.r1 + g.r2) * mm:.4g} mm", param=names["a"])
    if not g.delta < g.r3:
        raise InputError(f"the eccentricity {g.delta * mm:g} mm is not allowed; it must be < {g.r3 * mm:g} mm, the "
                         f"roller radius (an eccentric's pivot lies inside its roller)",
                         param=names["delta"])
    where = f"the pivot at ({g.px * mm:g}, {g.py * mm:g}) mm"
    (motor, _), (rim, _), (tight, _), _ = _gaps(g)
    for gap, label, radius in ((motor, "motor pulley", g.r1), (rim, "driven rim", g.r2)):
        if not gap > 0:
            raise InputError(f"{where} puts the roller on the {label} ({-gap * mm:.3g} mm overlap at its closest "
                             f"turn): the roller's centre must stay more than r3 + r = {(g.r3 + radius) * mm:.4g} mm "
                             "from the pulley's at every turn (its distance from the pivot less the eccentricity); "
                             "move the pivot", param=names["px"])
    if not tight > 0:
        raise InputError(f"{where} lifts the roller through the tight span ({-tight * mm:.3g} mm at its highest "
                         "turn): it must stay under it; lower the pivot", param=names["py"])
    limit = contact_limit(g)
    if not limit > 0:
        raise InputError(f"{where} leaves the roller clear of the belt: even without eccentricity its rim stays "
                         f"{-limit * mm:.3g} mm under the slack span; raise the pivot to within r3 = {g.r3 * mm:g} mm "
                         "of the span", param=names["py"])
    if not g.delta < limit:
        raise InputError(f"the eccentricity {g.delta * mm:g} mm is not allowed at {where}; it must be < "
                         f"{limit * mm:.4g} mm: beyond it the roller drops clear of the slack span for part of its "
                         "turn and the belt leaves it (its wrap angle on the roller falls to zero)",
                         param=names["delta"])


def _fourier(g: Eccentric) -> tuple:
    """L(theta) as its Fourier series (mean, cosine and sine coefficients), L(theta0) and the
    geometry, from exact samples; refused when the series has not converged (a belt that nearly leaves the
    roller: its wrap angle near zero makes L kink) or the wrap is not the roller's."""
    m = 4 * HARMONICS
    theta = 2 * math.pi * np.arange(m) / m
    paths = [g.path(t) for t in theta]
    wraps = np.array([p.wraps[1] for p in paths])
    if not (np.all(wraps > 0) and np.all(wraps < math.pi)):    # refuse() keeps this from happening
        raise InputError(f"the belt leaves the roller at some angle (its wrap angle there: "
                         f"{math.degrees(float(wraps.min() if wraps.min() <= 0 else wraps.max())):.3g} deg); "
                         "lower the eccentricity or raise the pivot", param="eccentricity")
    samples = np.array([p.length for p in paths])
    c = np.fft.rfft(samples) / m
    a0 = c[0].real
    a = 2 * c[1:HARMONICS + 1].real
    bb = -2 * c[1:HARMONICS + 1].imag
    tail = np.abs(c[HARMONICS:]).max() * 2
    if tail > 1e-13 * max(abs(a0), 1e-300):
        gap, what = min(_gaps(g))
        raise InputError(f"the belt path around the eccentric roller varies too sharply to tabulate (Fourier tail "
                         f"{tail:.2g} m): {what} ({gap * 1e3:.3g} mm to spare; least wrap angle on the roller "
                         f"{math.degrees(float(wraps.min())):.3g} deg); move the pivot or lower the eccentricity",
                         param="eccentricity")
    return a0, a, bb, float(_evaluate((a0, a, bb), np.asarray(g.theta0))[0]), g


def _evaluate(series: tuple, theta):
    """L, L', L'' of the Fourier series at ``theta`` (any shape)."""
    a0, a, b = series[:3]
    theta = np.asarray(theta, dtype=float)
    k = np.arange(1, a.size + 1)
    arg = np.multiply.outer(theta, k)
    c, s = np.cos(arg), np.sin(arg)
    L = a0 + c @ a + s @ b
    L1 = s @ (-a * k) + c @ (b * k)
    L2 = -(c @ (a * k * k) + s @ (b * k * k))
    return L, L1, L2
