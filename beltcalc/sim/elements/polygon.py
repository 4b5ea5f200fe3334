r"""The element kind "polygon strand": a chain strand between two sprockets whose length follows
each sprocket's angle through the tooth geometry, the polygon (chordal) action
[ISO 10823 sec. 5], [B56 ch. 4].

A chain seats its rollers on a sprocket's pitch polygon: z vertices on the pitch circle of
radius R = p / (2 sin(pi / z)) [ISO 606 sec. 6]. The free strand is the straight line that
touches both polygons from the outside (the chain's common tangent): it leaves sprocket ``i``
at the seated roller V_i that is highest against the strand's normal, and reaches sprocket
``j`` at V_j. The rollers between them are free links of pitch p, so the strand's elongation
is the distance of the two seated rollers less the free links' length::

    e(phi_i, phi_j) = |V_j - V_i| - p (n_free - n_free,0) - e_0
    n_free = n_0 + k_j - k_i      (k: the index of the seated vertex on each sprocket)

with e_0 such that e = 0 at rest (|V_j - V_i| is taken less the centre distance, in a form
without cancellation, so a force's rounding is that of the strand's own stretch). As sprocket ``i`` turns by one tooth one more roller seats
on it: n_free drops by one and e grows by p, while |V_j - V_i| swings through its polygon
pulse and back. Between two seatings e is smooth; at a seating it is continuous with a
continuous rate (the two rollers' speeds along the strand are equal, omega R cos(pi/z), when
they lie on it together) and a step in its second derivative: the chordal action's
acceleration kick. Over a tooth the chain moves p: the mean radius is p z / (2 pi) = R sinc(pi/z),
not R. As z -> infinity (R held) the polygon becomes the pitch circle, V the tangent point, and
e -> R phi_i - R phi_j, today's strand (:class:`~beltcalc.sim.elements.Strand`), with
differences of order 1 / z^2.

The layout is the one the strand row of every chain strand already means (both sprockets turn
the same way, the chain over both, an open drive): sprocket ``i`` at the origin, ``j`` at the
centre distance sqrt(L^2 + (R_i - R_j)^2) along x, ``L`` the straight length of the free
strand between the pitch circles. The seated roller at rest sits at ``phase_i`` (of ``i``) and
``phase_j`` past the strand's tangent point in the turning direction [rad].

The strand is tension-only as :class:`~beltcalc.sim.elements.Strand` is: with the
pretension F_0 and the stiffness c, damping b::

    F = c (e + F_0 / c) + b e'    while e + F_0 / c > 0 and F > 0, else 0
    Q_i = -F de/dphi_i,  Q_j = -F de/dphi_j      (the generalized forces)

The element stamps the strand's spring on its mean radii (r = p z / (2 pi), the strand a
frequency analysis sees) into the linear matrices and adds the rest as nonlinear terms with
the analytic Jacobian, as the eccentric roller does (:mod:`beltcalc.sim.elements.eccentric`):
the core solves it implicitly, each seating and each slack switch a kink of the right-hand
side its step control resolves; ``tests/test_polygon.py`` checks runs against scipy's Radau
stopped at every seating and switch.

References:

[ISO 10823] ISO 10823:2004, Guidance on the selection of roller chain drives: the polygon
    effect, chain speed between omega R cos(180 deg / z) and omega R.
[B56] R. C. Binder, Mechanics of the Roller Chain Drive, Prentice-Hall (1956) ch. 4: the
    chordal action of a chain on a sprocket, the seated roller's path on the pitch polygon.
[ISO 606] ISO 606:2004, Short-pitch transmission precision roller and bush chains,
    attachments and associated chain sprockets: the pitch diameter d = p / sin(180 deg / z).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.sim.elements import Element

TWO_PI = 2.0 * math.pi
TANGENT_ROUNDS = 8      # most rounds of the supporting-vertex search (a tilt of a few mrad settles in 2)


@dataclass(frozen=True)
class PolygonStrand(Element):
    """Chain strand ``name`` from sprocket node ``i`` to ``j``: pitch ``pitch`` [m], teeth
    ``z_i``, ``z_j``, free length ``length`` [m] between the pitch circles, stiffness
    ``stiffness`` c [N/m], damping ``damping`` b [N s/m], pretension ``preload`` F_0 [N], the
    seated rollers' phases at rest ``phase_i``, ``phase_j`` [rad] (None: ``phase_i`` 0 and
    ``phase_j`` from the span's fraction of a pitch, :func:`span_phase`).

    Outputs: ``F_<name>`` the strand's force [N] (>= 0), ``e_<name>`` its elongation from
    rest without the pretension's stretch [m], ``v_<name>`` the rate de/dt [m/s]."""

    name: str
    i: str
    j: str
    pitch: float
    z_i: int
    z_j: int
    length: float
    stiffness: float
    damping: float = 0.0
    preload: float = 0.0
    phase_i: float | None = None
    phase_j: float | None = None
    _rest: float = field(default=0.0, compare=False, repr=False)

    UNITS: ClassVar[dict] = {"pitch": "m", "length": "m", "stiffness": "N/m", "damping": "N*s/m",
                             "preload": "N", "phase_i": "rad", "phase_j": "rad"}
    #: reported and checked as a chain strand (:func:`beltcalc.sim.scenes.outcome.tension_strands`)
    tension_only: ClassVar[bool] = True

    def __post_init__(self):
        super().__post_init__()
        for key in ("z_i", "z_j"):
            z = getattr(self, key)
            if not (isinstance(z, (int, np.integer)) or (isinstance(z, float) and z.is_integer())) or z < 3:
                raise InputError(f"{z!r} teeth is not allowed; a sprocket needs a whole number >= 3",
                                 param=f"{self.name} {key}")
            object.__setattr__(self, key, int(z))
        require_positive(f"{self.name} pitch", self.pitch, "m")
        require_positive(f"{self.name} length", self.length, "m")
        if self.phase_i is None:
            object.__setattr__(self, "phase_i", 0.0)
        if self.phase_j is None:
            object.__setattr__(self, "phase_j", span_phase(self.length, self.pitch, self.z_j))
        object.__setattr__(self, "_radii", self.radii)
        object.__setattr__(self, "_layout", self.layout)
        object.__setattr__(self, "_mean", self.mean_radii)
        object.__setattr__(self, "_rest", 0.0)
        object.__setattr__(self, "_rest", float(self.elongation(0.0, 0.0)[0]))

    # --- the geometry -----------------------------------------------------------------------------
    @property
    def radii(self) -> tuple[float, float]:
        """The pitch radii R = p / (2 sin(pi / z)), in m [ISO 606 sec. 6]."""
        return (self.pitch / (2 * math.sin(math.pi / self.z_i)), self.pitch / (2 * math.sin(math.pi / self.z_j)))

    @property
    def mean_radii(self) -> tuple[float, float]:
        """The chain moved per radian, averaged over a tooth: p z / (2 pi) [m]."""
        return self.pitch * self.z_i / TWO_PI, self.pitch * self.z_j / TWO_PI

    @property
    def layout(self) -> tuple[float, float]:
        """(centre distance [m], the tangent's normal angle at rest [rad]) of the open drive."""
        ri, rj = self.radii
        d = math.hypot(self.length, ri - rj)
        return d, math.acos((ri - rj) / d)

    def seated(self, phi_i, phi_j):
        """The seated rollers at the angles ``phi_i``, ``phi_j`` (arrays of one shape):
        ``(k_i, k_j, a_i, a_j)``, the vertex indices and their polar angles [rad] about each
        centre, found by raising the common tangent over both polygons until no vertex lies
        above it (each round seats, on each sprocket, the vertex highest along the line's
        normal; the line only rises, so it stops)."""
        ri, rj = self.radii
        d, beta0 = self.layout
        base_i = beta0 + self.phase_i + phi_i
        base_j = beta0 + self.phase_j + phi_j
        beta = np.full(np.broadcast(phi_i, phi_j).shape, beta0)
        k_i = k_j = None
        for _ in range(TANGENT_ROUNDS):
            new_i = np.rint((beta - base_i) * (self.z_i / TWO_PI))
            new_j = np.rint((beta - base_j) * (self.z_j / TWO_PI))
            if k_i is not None and np.array_equal(new_i, k_i) and np.array_equal(new_j, k_j):
                break
            k_i, k_j = new_i, new_j
            a_i = base_i + TWO_PI * k_i / self.z_i
            a_j = base_j + TWO_PI * k_j / self.z_j
            dx = d + rj * np.cos(a_j) - ri * np.cos(a_i)
            dy = rj * np.sin(a_j) - ri * np.sin(a_i)
            beta = np.arctan2(dx, -dy)          # the normal (-dy, dx) / |d|, pointing away from both
        else:
            raise InputError(f"strand {self.name}: the common tangent of the sprockets' pitch polygons did not "
                             f"settle in {TANGENT_ROUNDS} rounds", param="network")
        return k_i, k_j, base_i + TWO_PI * k_i / self.z_i, base_j + TWO_PI * k_j / self.z_j

    def elongation(self, phi_i, phi_j):
        """``(e, e_i, e_j, e_ii, e_ij, e_jj)``: the elongation [m] at the sprocket angles
        ``phi_i``, ``phi_j`` [rad] and its first and second partial derivatives (m/rad, m/rad^2),
        each on the side of a seating the vertices found there take."""
        phi_i, phi_j = np.asarray(phi_i, dtype=float), np.asarray(phi_j, dtype=float)
        k_i, k_j, a_i, a_j = self.seated(phi_i, phi_j)
        return self._on_seats(np.cos(a_i), np.sin(a_i), np.cos(a_j), np.sin(a_j), k_i, k_j, np.hypot)

    def _on_seats(self, ci, si, cj, sj, k_i, k_j, hypot) -> tuple:
        """(e, e_i, e_j, e_ii, e_ij, e_jj) from the seated rollers' polar angles (their cosines and
        sines) and indices: floats or arrays alike (``hypot`` of math or numpy)."""
        ri, rj = self._radii
        d = self._layout[0]
        ex, dy = rj * cj - ri * ci, rj * sj - ri * si
        dx = d + ex
        ell = hypot(dx, dy)
        ux, uy = dx / ell, dy / ell
        # ell - d without the cancellation of two lengths near d (a force's noise otherwise)
        e = (ex * (2 * d + ex) + dy * dy) / (ell + d) + self.pitch * (k_j - k_i) - self._rest
        # d(V)/d(phi) = J r (r = V - centre, J the quarter turn); d(d)/d(phi_i) = -J r_i, d/d(phi_j) = J r_j
        e_i = -ri * (uy * ci - ux * si)           # -u . J r_i,  J r = (-r_y, r_x)
        e_j = rj * (uy * cj - ux * sj)
        e_ii = (ri * ri - e_i * e_i) / ell + ri * (ux * ci + uy * si)
        e_jj = (rj * rj - e_j * e_j) / ell - rj * (ux * cj + uy * sj)
        e_ij = (-(ri * rj) * (ci * cj + si * sj) - e_i * e_j) / ell
        return e, e_i, e_j, e_ii, e_ij, e_jj

    def pulse(self, phi_i, phi_j):
        """The polygon's part of the elongation [m]: e less the mean radii's r_i phi_i - r_j phi_j."""
        mi, mj = self.mean_radii
        return self.elongation(phi_i, phi_j)[0] - (mi * np.asarray(phi_i) - mj * np.asarray(phi_j))

    # --- the network's hooks ------------------------------------------------------------------------
    @property
    def nonlinear_kind(self) -> bool:
        return True

    nonlinear_reason = "a chain strand's length follows the sprockets' tooth polygons (the polygon action)"

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        for end in (self.i, self.j):
            if net.node(end).J == 0 or net.node(end).translation:
                raise InputError(f"strand {self.name} ends on {end}: a chain strand with polygon action needs a "
                                 "sprocket with inertia at each end", param="network")
        require_positive(f"{self.name} stiffness", self.stiffness, "N/m")
        require_range(f"{self.name} damping", self.damping, "N*s/m", low=0.0)
        require_range(f"{self.name} preload", self.preload, "N", low=0.0)

    def deflection(self, net) -> np.ndarray:
        """The row over the coordinates of the mean-radius elongation r_i phi_i - r_j phi_j."""
        mi, mj = self.mean_radii
        return mi * net.node_row(self.i) - mj * net.node_row(self.j)

    def matrices(self, net) -> list:
        return [(self.deflection(net), self.stiffness, self.damping)]

    def _plan(self, net):
        key = ("polygon_strand", self.name)
        plan = net._cache.get(key)
        if plan is None:
            ri, rj = net.node_row(self.i), net.node_row(self.j)
            inv = 1.0 / net.mass
            held = np.ones(net.n)
            for c in net.fixed:
                held[c] = 0.0
            plan = net._cache[key] = (ri, rj, self.deflection(net), inv, held)
        return plan

    def force(self, e, e_i, e_j, w_i, w_j):
        """The strand's force [N] at the elongation ``e`` and rate ``e_i w_i + e_j w_j``
        (tension only), and where it is taut."""
        rate = e_i * w_i + e_j * w_j
        stretch = self.stiffness * e + self.preload
        raw = stretch + self.damping * rate
        taut = (stretch > 0) & (raw > 0)
        return np.where(taut, raw, 0.0), taut

    def seats_at(self, phi_i: float, phi_j: float) -> tuple[int, int]:
        """The seated vertices' indices (k_i, k_j) at one pair of angles (floats; :meth:`seated`)."""
        ri, rj = self._radii
        d, beta0 = self._layout
        zi, zj = self.z_i, self.z_j
        base_i = beta0 + self.phase_i + phi_i
        base_j = beta0 + self.phase_j + phi_j
        beta = beta0
        k_i = k_j = None
        for _ in range(TANGENT_ROUNDS):
            new_i = round((beta - base_i) * zi / TWO_PI)
            new_j = round((beta - base_j) * zj / TWO_PI)
            if new_i == k_i and new_j == k_j:
                return k_i, k_j
            k_i, k_j = new_i, new_j
            a_i, a_j = base_i + TWO_PI * k_i / zi, base_j + TWO_PI * k_j / zj
            beta = math.atan2(d + rj * math.cos(a_j) - ri * math.cos(a_i), ri * math.sin(a_i) - rj * math.sin(a_j))
        self.seated(np.asarray(phi_i), np.asarray(phi_j))     # raises
        return k_i, k_j

    def elongation_at(self, phi_i: float, phi_j: float, seats: tuple[int, int] | None = None) -> tuple[float, ...]:
        """:meth:`elongation` at one pair of angles, in floats (the implicit solver's calls), with
        the rollers ``seats`` = (k_i, k_j) seated (None: those seated there, :meth:`seats_at`;
        given, the smooth branch of those two rollers, also past a seating)."""
        beta0 = self._layout[1]
        k_i, k_j = self.seats_at(phi_i, phi_j) if seats is None else seats
        a_i = beta0 + self.phase_i + phi_i + TWO_PI * k_i / self.z_i
        a_j = beta0 + self.phase_j + phi_j + TWO_PI * k_j / self.z_j
        return self._on_seats(math.cos(a_i), math.sin(a_i), math.cos(a_j), math.sin(a_j), k_i, k_j, math.hypot)

    # --- the smooth pieces between seatings and slack switches (the solvers stop at each) ----------
    pieces: ClassVar[bool] = True

    def _angles(self, net, x) -> tuple[float, float, float, float]:
        (ci, fi), (cj, fj) = self._ends(net)
        n = net.n
        return fi * x.item(ci), fj * x.item(cj), fi * x.item(n + ci), fj * x.item(n + cj)

    def piece_at(self, net, x) -> tuple[int, int, bool]:
        """(k_i, k_j, taut) at the state ``x``: the seated rollers and whether the strand pulls."""
        p_i, p_j, w_i, w_j = self._angles(net, x)
        seats = self.seats_at(p_i, p_j)
        e, e_i, e_j, *_ = self.elongation_at(p_i, p_j, seats)
        stretch = self.stiffness * e + self.preload
        return (*seats, bool(stretch > 0 and stretch + self.damping * (e_i * w_i + e_j * w_j) > 0))

    @staticmethod
    def taut_in(piece) -> bool:
        """Whether the strand pulls on the piece ``piece``."""
        return piece[2]

    def piece_events(self, net, piece) -> list:
        """The surfaces that end the smooth piece ``piece`` = (k_i, k_j, taut), as (function of
        the state, direction): a seating on either sprocket (the strand's line, through the two
        seated rollers, reaches the next roller: its normal leaves the seated vertex's cone
        |beta - a| <= pi / z) and the slack switch (as :meth:`beltcalc.sim.network.StrandModes.events`)."""
        k_i, k_j, taut = piece
        ri, rj = self._radii
        d, beta0 = self._layout

        def cone(x):
            p_i, p_j, _, _ = self._angles(net, x)
            a_i = beta0 + self.phase_i + p_i + TWO_PI * k_i / self.z_i
            a_j = beta0 + self.phase_j + p_j + TWO_PI * k_j / self.z_j
            beta = math.atan2(d + rj * math.cos(a_j) - ri * math.cos(a_i), ri * math.sin(a_i) - rj * math.sin(a_j))
            return (beta - a_i) * self.z_i / TWO_PI, (beta - a_j) * self.z_j / TWO_PI

        def stretch(x):
            p_i, p_j, _, _ = self._angles(net, x)
            return self.stiffness * self.elongation_at(p_i, p_j, (k_i, k_j))[0] + self.preload

        def pull(x):
            p_i, p_j, w_i, w_j = self._angles(net, x)
            e, e_i, e_j, *_ = self.elongation_at(p_i, p_j, (k_i, k_j))
            return self.stiffness * e + self.preload + self.damping * (e_i * w_i + e_j * w_j)

        sign = -1 if taut else 1
        return [(lambda x: 0.5 - cone(x)[0], -1), (lambda x: 0.5 + cone(x)[0], -1),
                (lambda x: 0.5 - cone(x)[1], -1), (lambda x: 0.5 + cone(x)[1], -1),
                (stretch, sign), (pull, sign)]

    def _ends(self, net):
        """((coordinate, factor) of i, of j, of the mean-radius row's ends) worked out once."""
        key = ("polygon_ends", self.name)
        hit = net._cache.get(key)
        if hit is None:
            hit = net._cache[key] = (net.coord(self.i), net.coord(self.j))
        return hit

    def nonlinear(self, net, t, X, out, constrained: bool) -> None:
        n = net.n
        if X.ndim == 1:                 # one state: floats, no arrays
            (ci, fi), (cj, fj) = self._ends(net)
            p_i, p_j = fi * X.item(ci), fj * X.item(cj)
            w_i, w_j = fi * X.item(n + ci), fj * X.item(n + cj)
            piece = net.pieces.get(self.name)
            e, e_i, e_j, *_ = self.elongation_at(p_i, p_j, None if piece is None else piece[:2])
            stretch = self.stiffness * e + self.preload
            f = stretch + self.damping * (e_i * w_i + e_j * w_j)
            if not (piece[2] if piece is not None else (stretch > 0 and f > 0)):
                f = 0.0
            mi, mj = self._mean
            lin = self.stiffness * (mi * p_i - mj * p_j) + self.damping * (mi * w_i - mj * w_j)
            q_i, q_j = -f * e_i + lin * mi, -f * e_j - lin * mj
            if not (constrained and ci in net.fixed):
                out[n + ci] += fi * q_i / net.mass.item(ci)
            if not (constrained and cj in net.fixed):
                out[n + cj] += fj * q_j / net.mass.item(cj)
            return
        ri, rj, g, inv, held = self._plan(net)
        q, w = X[:n], X[n:2 * n]
        p_i, p_j, w_i, w_j = ri @ q, rj @ q, ri @ w, rj @ w
        e, e_i, e_j, *_ = self.elongation(p_i, p_j)
        f, _ = self.force(e, e_i, e_j, w_i, w_j)
        lin = self.stiffness * (g @ q) + self.damping * (g @ w)     # the stamped mean-radius spring
        # generalized forces beyond the stamped spring's -lin g
        gain = inv * held if constrained else inv
        acc = -(np.multiply.outer(ri, f * e_i) + np.multiply.outer(rj, f * e_j)) + np.multiply.outer(g, lin)
        out[n:2 * n] += acc * gain[:, None]

    def jacobian(self, net, x, jac) -> None:
        """d(the nonlinear terms)/d(state) at ``x``, on the side of each seating and of the
        slack switch that the right-hand side takes there."""
        n = net.n
        (ci, fi), (cj, fj) = self._ends(net)
        p_i, p_j = fi * x.item(ci), fj * x.item(cj)
        w_i, w_j = fi * x.item(n + ci), fj * x.item(n + cj)
        piece = net.pieces.get(self.name)
        e, e_i, e_j, e_ii, e_ij, e_jj = self.elongation_at(p_i, p_j, None if piece is None else piece[:2])
        c, b = self.stiffness, self.damping
        stretch = c * e + self.preload
        f = stretch + b * (e_i * w_i + e_j * w_j)
        on = float(piece[2] if piece is not None else (stretch > 0 and f > 0))
        f *= on
        # dF over (phi_i, phi_j, omega_i, omega_j), zero where slack
        dF = (on * (c * e_i + b * (e_ii * w_i + e_ij * w_j)), on * (c * e_j + b * (e_ij * w_i + e_jj * w_j)),
              on * b * e_i, on * b * e_j)
        mi, mj = self._mean
        lin = (c * mi, -c * mj, b * mi, -b * mj)       # d(the stamped spring's force)
        # Q_i = -F e_i + lin mi, Q_j = -F e_j - lin mj over the same four variables
        de_i, de_j = (e_ii, e_ij, 0.0, 0.0), (e_ij, e_jj, 0.0, 0.0)
        cols = ((ci, fi), (cj, fj), (n + ci, fi), (n + cj, fj))
        for row_c, row_f, e_k, de_k, m_k in ((ci, fi, e_i, de_i, mi), (cj, fj, e_j, de_j, -mj)):
            if row_c in net.fixed:
                continue
            scale = row_f / net.mass.item(row_c)
            for (col, col_f), dfv, dev, dl in zip(cols, dF, de_k, lin):
                jac[n + row_c, col] += scale * col_f * (-(dfv * e_k + f * dev) + dl * m_k)

    def outputs(self, net, t, X, accel) -> dict:
        ri, rj, *_ = self._plan(net)
        X = np.asarray(X)
        n = net.n
        q, w = X[:n], X[n:2 * n]
        p_i, p_j, w_i, w_j = ri @ q, rj @ q, ri @ w, rj @ w
        e, e_i, e_j, *_ = self.elongation(p_i, p_j)
        f, _ = self.force(e, e_i, e_j, w_i, w_j)
        return {f"F_{self.name}": (f, "N"), f"e_{self.name}": (e, "m"), f"v_{self.name}": (e_i * w_i + e_j * w_j, "m/s")}

    def excitation(self, result, window: float) -> list[tuple[float, str]]:
        """The tooth-passing frequencies of the strand's two sprockets at their mean speeds over
        the window [Hz] (for the resonance check)."""
        out = []
        for node, z in ((self.i, self.z_i), (self.j, self.z_j)):
            if f"omega_{node}" in result.signals:
                speed = abs(result.summary(f"omega_{node}", window).mean)
                out.append((z * speed / TWO_PI, f"the {z}-tooth sprocket {node} (strand {self.name})"))
        return out


def span_phase(length: float, pitch: float, teeth: int) -> float:
    """The seated roller's angle past the tangent point of the sprocket a strand reaches, at
    rest [rad], where a roller is seated at the tangent point of the sprocket it leaves: the
    span holds ``length / pitch`` links, so the last free roller stops short of the tangent
    point by the fraction f of a pitch, and the roller seated there lies f of a tooth further
    round (to first order in 1 / z; any phase is a chain's, this one a span's own).

    >>> round(span_phase(0.6, 0.015875, 19), 6)      # 37.795 pitches: 0.795 of a tooth
    0.262993
    """
    f = length / pitch - math.floor(length / pitch)
    return TWO_PI * f / teeth


def polygon_strands(net) -> list[PolygonStrand]:
    """The polygon strands of network ``net``."""
    return [el for el in net.elements if isinstance(el, PolygonStrand)]
