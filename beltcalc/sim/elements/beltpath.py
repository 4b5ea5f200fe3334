r"""The path of a closed belt around circles, and the eccentric tension roller on it.

A belt runs around a loop of circles (pulleys, rollers), each with a centre and a *signed*
radius: positive where the belt wraps the circle counter-clockwise as it travels (the
circle on its left: a pulley inside the loop), negative where it wraps it clockwise (an
idler pressing on the belt's back from outside the loop). Between two circles the belt is
the common tangent with those orientations; on each circle it is an arc. Everything here is
exact plane geometry; the derivation and the figure in words are in
``docs/eccentric_roller.md`` (and DESIGN.md section 2.6).

Spans. For circles i -> j with centres c_i, c_j and signed radii rho_i, rho_j, let
``d = c_j - c_i``, ``D = |d|``, ``e = d / D``, ``e_perp`` = e turned +90 deg, and
``drho = rho_j - rho_i``. The span has length ``l = sqrt(D^2 - drho^2)`` and direction
``u = (l e - drho e_perp) / D``; with ``n`` = u turned +90 deg it leaves circle i at
``c_i - rho_i n`` and reaches circle j at ``c_j - rho_j n`` (the centre lies a signed
radius to the left of the travel direction).

Length gradient. Moving one circle's centre changes the loop length by
``dL/dc_k = u_in - u_out`` (the directions of the span arriving at and leaving circle k):
the arcs take up exactly the tangent points' motion. For an idler wrapped by an angle
beta, ``|u_in - u_out| = 2 sin(beta / 2)``.

The eccentric roller ([M16 Fig. 2]; their [M16 eq. 3-4] are garbled, so the
model is derived here, not typed): a disc of radius r3 turning about a pivot P offset by
Delta from its centre, ``C(theta) = P + Delta (cos theta, sin theta)``, rolling on the
slack span, so ``theta = theta_0 - r1 phi_1 / r3`` (a back-side idler turns clockwise while
the motor pulley turns counter-clockwise). The loop length ``L(theta)`` then varies by
``delta(theta) = L(theta) - L(theta_0)``; see :func:`eccentric_ratio` for the ratio it gives.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import InputError


@dataclass(frozen=True)
class Circle:
    """A pulley or roller on the belt loop: centre (m) and signed radius rho (m; > 0: the belt
    wraps it counter-clockwise, the circle inside the loop; < 0: clockwise, an idler on the
    belt's back)."""

    x: float
    y: float
    rho: float

    @property
    def center(self) -> np.ndarray:
        return np.array([self.x, self.y])


@dataclass(frozen=True)
class Span:
    """The straight belt from one circle to the next: start and end points, unit direction,
    length."""

    start: np.ndarray
    end: np.ndarray
    u: np.ndarray
    length: float


@dataclass(frozen=True)
class Loop:
    """A closed belt path: the spans (span k leaves circle k for circle k + 1), the arc angle
    on each circle (rad, in its wrap direction: span k - 1 arrives, span k leaves) and the
    total length (m)."""

    circles: tuple[Circle, ...]
    spans: tuple[Span, ...]
    wraps: tuple[float, ...]

    @property
    def length(self) -> float:
        return sum(s.length for s in self.spans) + sum(abs(c.rho) * w for c, w in zip(self.circles, self.wraps))

    def gradient(self, k: int) -> np.ndarray:
        """dL/dc_k: the loop length's change per metre of motion of circle k's centre,
        ``u_in - u_out``."""
        return self.spans[k - 1].u - self.spans[k].u


def span(a: Circle, b: Circle) -> Span:
    """The common tangent from circle ``a`` to circle ``b`` with the wrap directions of their
    signed radii (module docstring). Refused where it does not exist (circles overlapping for
    an outer tangent, or too close for a crossed one)."""
    d = b.center - a.center
    D = float(np.hypot(*d))
    drho = b.rho - a.rho
    if not D > abs(drho):
        raise InputError(f"no belt span from the circle at ({a.x:g}, {a.y:g}) m to the one at ({b.x:g}, {b.y:g}) m: "
                         f"their centres are {D:.4g} m apart, less than {abs(drho):.4g} m", param="geometry")
    e = d / D
    e_perp = np.array([-e[1], e[0]])
    length = math.sqrt(D * D - drho * drho)
    u = (length * e - drho * e_perp) / D
    n = np.array([-u[1], u[0]])
    return Span(a.center - a.rho * n, b.center - b.rho * n, u, length)


def loop(circles: tuple[Circle, ...] | list[Circle]) -> Loop:
    """The closed belt path around ``circles`` in travel order (at least two)."""
    circles = tuple(circles)
    if len(circles) < 2:
        raise InputError("a belt loop needs at least two circles", param="geometry")
    spans = tuple(span(circles[k], circles[(k + 1) % len(circles)]) for k in range(len(circles)))
    wraps = []
    for k, c in enumerate(circles):
        arrive, leave = spans[k - 1].end - c.center, spans[k].start - c.center
        turn = math.atan2(arrive[0] * leave[1] - arrive[1] * leave[0], float(arrive @ leave))
        if c.rho < 0:
            turn = -turn
        wraps.append(turn % (2 * math.pi))      # in the wrap direction, in [0, 2 pi)
    return Loop(circles, spans, tuple(wraps))


@dataclass(frozen=True)
class Eccentric:
    """The sewing drive's belt with its eccentric tension roller, SI: motor pulley (pitch
    radius r1, centre at the origin), driven rim (r2, centre at (a, 0)), the roller (radius r3)
    on the slack span, turning about the pivot (px, py) with eccentricity delta; theta0 is the
    roller's angle when phi_1 = 0. The tight span runs along the top from the rim to the motor
    pulley (the motor pulls it), the slack span under the drive from the motor pulley over the
    roller's back to the rim."""

    r1: float
    r2: float
    a: float
    r3: float
    px: float
    py: float
    delta: float
    theta0: float = 0.0

    def circles(self, theta: float) -> tuple[Circle, Circle, Circle]:
        """Travel order (counter-clockwise around the loop): motor pulley, roller, rim."""
        cx = self.px + self.delta * math.cos(theta)
        cy = self.py + self.delta * math.sin(theta)
        return (Circle(0.0, 0.0, self.r1), Circle(cx, cy, -self.r3), Circle(self.a, 0.0, self.r2))

    def theta(self, phi1: float) -> float:
        """The roller's angle: it rolls on the slack span, which moves r1 phi_1 (a back-side
        idler turns the other way round)."""
        return self.theta0 - self.r1 * phi1 / self.r3

    def path(self, theta: float) -> Loop:
        return loop(self.circles(theta))

    def length(self, theta: float) -> float:
        """The loop length L(theta) [m]."""
        return self.path(theta).length

    def length_rate(self, theta: float) -> float:
        """dL/dtheta [m/rad] = (u_in - u_out) . dC/dtheta on the roller."""
        g = self.path(theta).gradient(1)
        return float(g @ np.array([-math.sin(theta), math.cos(theta)]) * self.delta)

    def length_curvature(self, theta: float, h: float = 1e-4) -> float:
        """d^2L/dtheta^2 [m/rad^2], by a central difference of the exact rate (the analytic
        Jacobian's second-order term; its error is O(h^2) of a smooth periodic function)."""
        return (self.length_rate(theta + h) - self.length_rate(theta - h)) / (2 * h)


def eccentric_ratio(geo: Eccentric, theta: float) -> float:
    r"""The instantaneous speed ratio U12 = phidot_1 / phidot_2 at roller angle ``theta``.

    Both spans are springs of stiffness k per metre of stretch. With x = r1 phi_1 - r2 phi_2
    the tight span is stretched by x and the slack span (with the wraps it feeds) by
    delta(theta) - x, so the transmitted force is T_t - T_s = k (2 x - delta). Held constant
    (a quasi-static drive), ``2 (r1 phidot_1 - r2 phidot_2) = delta'(theta) theta'`` with
    ``theta' = -r1 phidot_1 / r3``:

    .. math:: U_{12} = \frac{r_2 / r_1}{1 + \delta'(\theta) / (2 r_3)}

    (docs/eccentric_roller.md, eq. E5). Without eccentricity (delta' = 0) it is r2 / r1.
    """
    return (geo.r2 / geo.r1) / (1.0 + geo.length_rate(theta) / (2 * geo.r3))
