"""What the network's assembly is made of: the :class:`Piece` elements write their inputs
into, the :class:`Event` of a strand's switching surface, the guards against entries beyond
the float range, and the series stiffness of two springs. SI floats only.

References:

[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": a clutch and a
    shaft in series [RP eq. 3].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import FloatRangeError, require_positive


def series_stiffness(c1: float, c2: float) -> float:
    r"""Stiffness of two springs in series, eliminating the massless node between them [N m/rad].

    .. math:: c_{1-2} = \frac{c_1 c_2}{c_1 + c_2}

    [RP eq. 3] (clutch and shaft in series). Exact for springs without dampers; a damper on
    the massless node would leave a first-order element instead.

    >>> series_stiffness(300.0, 600.0)
    200.0
    """
    require_positive("c1", c1, "N*m/rad")
    require_positive("c2", c2, "N*m/rad")
    return c1 * c2 / (c1 + c2)


@dataclass(frozen=True)
class Event:
    """A switching surface of the current mode: ``row @ z`` (z = [x, g]) crossing zero in
    ``direction`` (+1 rising, -1 falling) may switch strand ``strand``."""

    strand: int
    kind: str       # "delta" (elongation) or "force"
    direction: int
    row: np.ndarray


def add_outer(M: np.ndarray, g: np.ndarray, c: float) -> None:
    """M += c g g^T on the nonzero entries of g only (a coupling touches two coordinates)."""
    if c:
        idx = np.flatnonzero(g)
        v = g[idx]
        M[idx[:, None], idx] += c * (v[:, None] * v)       # np.ix_ and np.outer, without their overhead


class Piece:
    """What elements write into ``[A | B]`` of ``x' = A x + B g`` on one time piece (the one
    holding ``t_mid``): torques ``a + c t`` and sinusoids on a node (taken to its coordinate
    through the node's factor), and rows of their own states."""

    def __init__(self, net, A: np.ndarray, B: np.ndarray, t_mid: float):
        self.net, self.A, self.B, self.t_mid = net, A, B, t_mid
        self.Minv = 1.0 / net.mass
        self.ramp = 1 if net.ramp else None
        self._first = 1 + int(net.ramp)
        self._freqs = net.frequencies()

    def torque(self, node: str, a: float, c: float = 0.0) -> None:
        """A torque (force on a translating node) ``a + c t`` [N m] acting on ``node``."""
        k, f = self.net.coord(node)
        n = self.net.n
        self.B[n + k, 0] += f * a * self.Minv[k]
        if c:
            self.B[n + k, self.ramp] += f * c * self.Minv[k]

    def generalized(self, g: np.ndarray, a: float, c: float = 0.0) -> None:
        """A generalised force ``(a + c t) g`` on the coordinates (g a row over them: the
        torque ``a + c t`` acting on the deflection ``g . q``, e.g. a friction torque)."""
        n = self.net.n
        k = np.flatnonzero(g)
        self.B[n + k, 0] += g[k] * a * self.Minv[k]
        if c:
            self.B[n + k, self.ramp] += g[k] * c * self.Minv[k]

    def sine(self, node: str, omega: float, s: float, c: float) -> None:
        """A torque ``s sin(omega t) + c cos(omega t)`` [N m] on ``node``."""
        k, f = self.net.coord(node)
        q = self._first + 2 * next(i for i, w in enumerate(self._freqs) if math.isclose(w, omega))
        self.B[self.net.n + k, q] += f * s * self.Minv[k]
        self.B[self.net.n + k, q + 1] += f * c * self.Minv[k]

    def state(self, element) -> int:
        """Index of an element's own (first) state."""
        return self.net.state_index[id(element)]


def require_finite(*arrays: np.ndarray, net=None) -> None:
    """Refuse a first-order system with an entry beyond the float range: a stiffness,
    damping or load divided by a mass or inertia overflows (e.g. 1e308 N m/rad on 1e-5
    kg m^2) and no solver can do anything with it. With ``net`` (the arrays ``A``, ``B`` of
    :meth:`Network.first_order`) the message names the coordinate and the term."""
    with np.errstate(invalid="ignore"):
        if all(np.isfinite(a).all() for a in arrays):
            return
    what = "a stiffness, damping or load over a mass or inertia"
    if net is not None and len(arrays) == 2:
        A, B = arrays
        n = net.n
        bad = np.argwhere(~np.isfinite(A))
        if bad.size:
            row, col = (int(v) for v in bad[0])
            if n <= row < 2 * n:
                c = net.coords[row - n]
                unit = "m" if net.node(c).translation else "rad"
                term = ("stiffness" if col < n else "damping" if col < 2 * n else "a motor's or an element's term")
                what = f"the {term} on {c} over its {'mass' if unit == 'm' else 'inertia'}"
        elif (~np.isfinite(B)).any():
            row = int(np.argwhere(~np.isfinite(B))[0][0])
            if n <= row < 2 * n:
                what = f"a load on {net.coords[row - n]} over its inertia"
    raise FloatRangeError(f"the drive's equations of motion overflow a float: {what} is beyond 1e308 in SI "
                          "units; check the values and their units")


_FIELDS: dict[type, tuple[tuple[str, object], ...]] = {}     # element kind -> its fields' (name, default)


def _fields_of(el) -> tuple[tuple[str, object], ...]:
    import dataclasses

    return tuple((f.name, f.default) for f in dataclasses.fields(el)) if dataclasses.is_dataclass(el) else ()


def require_finite_elements(elements) -> None:
    """Refuse an element with a value beyond the float range (a stiffness G pi d^4 / 32 L of a
    shaft a millionth of a micrometre long): each float field of each element kind."""
    for el in elements:
        fields = _FIELDS.get(type(el))
        if fields is None:
            fields = _FIELDS[type(el)] = _fields_of(el)
        for key, default in fields:
            v = getattr(el, key)
            if isinstance(v, float) and not math.isfinite(v) and not (v == math.inf == default):  # inf: "none"
                kind = type(el).__name__.lower()
                name = getattr(el, "name", "") or f"on {getattr(el, 'node', '')}"
                unit = getattr(el, "UNITS", {}).get(key) or "in SI units"
                what = {"C": "stiffness C", "d": "damping d", "J": "inertia J", "U": "ratio U",
                        "omega": "frequency omega"}.get(key, key)
                raise FloatRangeError(f"the {what} of {kind} {name} overflows a float "
                                      f"({'not a number' if math.isnan(v) else 'beyond 1e308 ' + unit})")
