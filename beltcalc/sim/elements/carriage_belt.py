r"""The element kind "carriage belt": a timing belt that drives a carriage along a linear axis,
its two spans' lengths following the carriage (the span stiffness of [W21 eq. 5] per span, the
two spans acting in parallel on the carriage).

The belt leaves pulley node ``i`` (pitch radius ``r``: metres of belt per radian) in span 1 to
the carriage (translating node ``j``, position x from its start); span 2 runs on from the
carriage round the idler back to the pulley. Moving the carriage by x lengthens span 1 and
shortens span 2::

    L1(x) = L1_0 + x,    L2(x) = L2_0 - x
    k_s = C_spec / L_s,  b_s = b_spec / L_s          (s = 1, 2; [W21 eq. 5] on the span's length now)
    u = r phi_i - x,     u' = r omega_i - v          (the belt at the pulley ahead of the carriage)
    F_2 = F_0 + k_2 u + b_2 u'   (span 2 pulls the carriage forward)
    F_1 = F_0 - k_1 u - b_1 u'   (span 1 holds it back)
    F = F_2 - F_1 = (k_1 + k_2) u + (b_1 + b_2) u'   on the carriage;   -r F on the pulley

The strain of each span is taken on its length now: to first order in the strain (1e-3 in a
timing belt) this is the span's material law whatever belt material has passed over the
pulley. Without a pretension (``pretension=None``) both spans are two-way springs and the forces
are changes from an unknown pretension (the paper's substitute belt). With one each span is
tension-only, as a chain strand is: it pulls only while it is stretched (F_0 + k e > 0) and
its force is positive, else it is slack and carries nothing. With ``L2_0`` None the belt has
span 1 only (the paper's one span k_TB = C_spec / a).

The element stamps its stiffness and damping at the carriage's start (x = 0) into the linear
matrices and adds the rest as nonlinear terms with their analytic Jacobian, so the core solves
a moving belt implicitly (Radau; ``docs/belt_axis.md`` says why that is right and how it is
checked). Held (``moving=False``, :meth:`at`) it *is* the linear spring of its position.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the belt's stiffness k = C_spec / L [W21 eq. 5]."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from beltcalc.errors import InputError, SimulationError, require_positive, require_range
from beltcalc.sim.elements import Element


@dataclass(frozen=True)
class CarriageBelt(Element):
    """Belt ``name`` from pulley node ``i`` (``r`` metres of belt a radian) to the carriage
    ``j`` (a translating node), span 1 ``L1`` [m] and the return span 2 ``L2`` [m] (None: none)
    at the carriage's start, specific stiffness ``C_spec`` [N] and damping ``b_spec`` [N s]
    (k = C_spec / L, b = b_spec / L per span), the spans' ``pretension`` F_0 [N] (None: two-way
    spans), the carriage's ``stroke`` [m] (its travel from the start, for the resonance map and
    the run's check; None: as far as the spans allow), and ``moving`` (False: the spans held at
    their lengths at the start, a linear spring).

    Outputs: ``F_<name>`` the belt's force on the carriage [N], ``T_<name>`` the torque on the
    pulley against its motion r F [N m], ``k_<name>`` the belt's stiffness at the carriage now
    [N/m], ``L1_<name>``/``L2_<name>`` the spans' lengths [m]; with a pretension
    ``F_<name>_1``/``F_<name>_2`` the spans' forces [N] (>= 0)."""

    name: str
    i: str
    j: str
    r: float
    C_spec: float
    b_spec: float
    L1: float
    L2: float | None = None
    pretension: float | None = None
    stroke: float | None = None
    moving: bool = True

    UNITS: ClassVar[dict] = {"r": "m", "C_spec": "N", "b_spec": "N*s", "L1": "m", "L2": "m", "pretension": "N",
                             "stroke": "m"}
    ORDER: ClassVar[int] = 10

    nonlinear_reason = "a carriage belt's spans change length as the carriage moves"

    @property
    def nonlinear_kind(self) -> bool:
        return self.moving or self.pretension is not None

    # --- geometry ------------------------------------------------------------------------------
    def lengths(self, x):
        """(L1, L2) at carriage position(s) ``x`` [m] (L2 inf without a return span)."""
        x = np.asarray(x, dtype=float)
        if not self.moving:
            x = np.zeros_like(x)
        l2 = np.inf if self.L2 is None else self.L2 - x
        return self.L1 + x, l2

    def travel(self) -> tuple[float, float]:
        """The carriage's positions (low, high) [m] the map covers: 0 to the stroke (negative:
        the carriage moves towards the pulley), or, without one, from 5 % of span 1 short of the
        pulley to 5 % of span 2 short of the idler."""
        if self.stroke is not None:
            return (min(0.0, self.stroke), max(0.0, self.stroke))
        high = 0.95 * self.L2 if self.L2 is not None else 4.0 * self.L1
        return -0.95 * self.L1, high

    def stiffness_at(self, x):
        """(k, b): the belt's stiffness [N/m] and damping [N s/m] at the carriage at ``x`` [m],
        both spans taut: C_spec (1/L1 + 1/L2), b_spec (1/L1 + 1/L2) ([W21 eq. 5] per span, in parallel)."""
        l1, l2 = self.lengths(x)
        s = 1.0 / l1 + 1.0 / l2
        return self.C_spec * s, self.b_spec * s

    def at(self, x: float) -> "CarriageBelt":
        """The belt held with the carriage at ``x`` [m]: the linear spring of that position
        (spans two-way; its modes are the network's there)."""
        l1, l2 = self.lengths(x)
        return replace(self, L1=float(l1), L2=None if self.L2 is None else float(l2), pretension=None,
                       stroke=None, moving=False)

    # --- hooks ---------------------------------------------------------------------------------
    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        net.require_inertia(self.i, f"belt {self.name}")
        net.require_inertia(self.j, f"belt {self.name}")
        if not net.node(self.j).translation:
            raise InputError(f"belt {self.name} drives {self.j!r}, a rotating node; a carriage belt's carriage "
                             "is a translating node (give it a mass)", param="network")
        if net.node(self.i).translation:
            raise InputError(f"belt {self.name} leaves {self.i!r}, a translating node; its pulley turns "
                             "(give it an inertia)", param="network")
        require_positive(f"{self.name} r", self.r, "m")
        require_positive(f"{self.name} specific_stiffness", self.C_spec, "N")
        require_range(f"{self.name} specific_damping", self.b_spec, "N*s", low=0.0)
        require_positive(f"{self.name} span", self.L1, "m")
        if self.L2 is not None:
            require_positive(f"{self.name} return_span", self.L2, "m")
        if self.pretension is not None:
            require_range(f"{self.name} pretension", self.pretension, "N", low=0.0)
            if self.L2 is None:
                raise InputError(f"belt {self.name} has a pretension but no return span: a pretensioned belt "
                                 "runs back round an idler (give return_span), or leave out the pretension",
                                 param=f"{self.name} pretension")
        if self.stroke is not None:
            low, high = self.travel()
            if not (self.L1 + low > 0 and (self.L2 is None or self.L2 - high > 0)):
                raise InputError(f"a stroke of {self.stroke * 1e3:g} mm takes the carriage onto a pulley: it must "
                                 f"stay within -{self.L1 * 1e3:g} mm (span) and "
                                 + (f"{self.L2 * 1e3:g} mm (return span)" if self.L2 is not None else "any length"),
                                 param=f"{self.name} stroke")

    def deflection(self, net) -> np.ndarray:
        """The row g over the coordinates with u = r phi_i - x_j = g . q."""
        return self.r * net.node_row(self.i) - net.node_row(self.j)

    def matrices(self, net) -> list:
        k0, b0 = self.stiffness_at(0.0)
        return [(self.deflection(net), float(k0), float(b0))]

    def _states(self, net, X):
        g = self.deflection(net)
        n = net.n
        cj, fj = net.coord(self.j)
        return g @ X[:n], g @ X[n:2 * n], fj * X[cj]

    def spans(self, X, net):
        """Each span's force at the states ``X`` (columns) and what the Jacobian needs:
        ``(F_1, F_2, taut_1, taut_2, (k_1, k_2, b_1, b_2), (u, u', x, L1, L2))``."""
        u, du, x = self._states(net, X)
        l1, l2 = self.lengths(x)
        if np.any(l1 <= 0) or (self.L2 is not None and np.any(l2 <= 0)):
            raise self._onto_pulley(float(np.atleast_1d(x)[np.argmin(np.minimum(l1, l2))]))
        k1, k2 = self.C_spec / l1, self.C_spec / l2
        b1, b2 = self.b_spec / l1, self.b_spec / l2
        f0 = self.pretension or 0.0
        spring1, spring2 = f0 - k1 * u, f0 + k2 * u
        raw1, raw2 = spring1 - b1 * du, spring2 + b2 * du
        if self.pretension is None:
            taut1 = taut2 = np.ones(np.shape(u), dtype=bool)
            f1, f2 = raw1, raw2
        else:
            taut1 = (spring1 > 0) & (raw1 > 0)
            taut2 = (spring2 > 0) & (raw2 > 0)
            f1, f2 = raw1 * taut1 + 0.0, raw2 * taut2 + 0.0
        return f1, f2, taut1, taut2, (k1, k2, b1, b2), (u, du, x, l1, l2)

    def _onto_pulley(self, x: float) -> SimulationError:
        return SimulationError(f"belt {self.name}: the carriage at x = {x * 1e3:.6g} mm reaches a pulley (span 1 "
                               f"{self.L1 * 1e3:g} mm + x, span 2 "
                               + (f"{self.L2 * 1e3:g} mm - x)" if self.L2 is not None else "none)"))

    def force(self, net, X):
        """The belt's force on the carriage F = F_2 - F_1 [N] at the states ``X`` (both spans
        two-way without a pretension; each tension-only with one)."""
        f1, f2, *_ = self.spans(X, net)
        return f2 - f1

    def _plan(self, net):
        """What the right-hand side needs of ``net``, worked out once per network: the
        deflection row g, the carriage's (coordinate, factor), the stamped k0, b0, and per
        coordinate the factor that turns a force on the carriage into its acceleration
        (-r on the pulley's, +1 on the carriage's, over the coordinate's mass), with and
        without the prescribed coordinates."""
        key = ("carriage_belt", self.name)
        plan = net._cache.get(key)
        if plan is None:
            g = self.deflection(net)
            n = net.n
            gain = np.zeros(n)
            for node, lever in ((self.i, -self.r), (self.j, 1.0)):
                row = net.node_row(node)
                gain += row * lever
            gain /= net.mass
            free = gain.copy()
            for c in net.fixed:
                gain[c] = 0.0
            k0, b0 = (float(v) for v in self.stiffness_at(0.0))
            plan = net._cache[key] = (g, *net.coord(self.j), k0, b0, gain, free)
        return plan

    def nonlinear(self, net, t, X, out, constrained: bool) -> None:
        if not self.nonlinear_kind:
            return
        g, cj, fj, k0, b0, gain, free = self._plan(net)
        n = net.n
        if X.ndim == 1:             # one state (the implicit solver's calls): floats, no arrays
            u, du, x = float(g @ X[:n]), float(g @ X[n:2 * n]), fj * float(X[cj])
            rest = self._force_at(u, du, x) - (k0 * u + b0 * du)
            out[n:2 * n] += (gain if constrained else free) * rest
            return
        u, du, _ = self._states(net, X)
        rest = self.force(net, X) - (k0 * u + b0 * du)     # beyond the stamped spring
        out[n:2 * n] += np.outer(gain if constrained else free, rest)

    def _force_at(self, u: float, du: float, x: float) -> float:
        """:meth:`force` at one state, in floats."""
        l1 = self.L1 + x if self.moving else self.L1
        if self.L2 is None:
            l2 = math.inf
        else:
            l2 = self.L2 - x if self.moving else self.L2
        if l1 <= 0 or l2 <= 0:
            raise self._onto_pulley(x)
        f0 = self.pretension or 0.0
        f1 = f0 - (self.C_spec * u + self.b_spec * du) / l1
        f2 = f0 + (self.C_spec * u + self.b_spec * du) / l2
        if self.pretension is not None:
            f1 = f1 if (f0 - self.C_spec * u / l1 > 0 and f1 > 0) else 0.0
            f2 = f2 if (f0 + self.C_spec * u / l2 > 0 and f2 > 0) else 0.0
        return f2 - f1

    def jacobian(self, net, x, jac) -> None:
        """d(the nonlinear terms)/d(state) at ``x``, on the side of each span's switch that
        :meth:`spans` takes there (the right-hand side's own branch)."""
        if not self.nonlinear_kind:
            return
        g, cj, fj, k0, b0, gain, _ = self._plan(net)
        n = net.n
        u, du, xc = float(g @ x[:n]), float(g @ x[n:2 * n]), fj * float(x[cj])
        l1 = self.L1 + xc if self.moving else self.L1
        l2 = math.inf if self.L2 is None else (self.L2 - xc if self.moving else self.L2)
        if l1 <= 0 or l2 <= 0:
            raise self._onto_pulley(xc)
        k1, b1, k2, b2 = self.C_spec / l1, self.b_spec / l1, self.C_spec / l2, self.b_spec / l2
        moving = 1.0 if self.moving else 0.0
        # the spans' forces over (u, u', x): F_1 = F0 - k1 u - b1 u', F_2 = F0 + k2 u + b2 u',
        # dk1/dx = -C / L1^2, dk2/dx = +C / L2^2 (the same for b): d(k1 u)/dx = -k1 u / L1
        d1 = (-k1, -b1, moving * (k1 * u + b1 * du) / l1)
        d2 = (k2, b2, moving * (k2 * u + b2 * du) / l2 if self.L2 is not None else 0.0)
        on1 = on2 = 1.0
        if self.pretension is not None:
            f0 = self.pretension
            on1 = float(f0 - k1 * u > 0 and f0 - k1 * u - b1 * du > 0)
            on2 = float(f0 + k2 * u > 0 and f0 + k2 * u + b2 * du > 0)
        dF = [on2 * a2 - on1 * a1 for a1, a2 in zip(d1, d2)]
        row = np.zeros(2 * n)
        row[:n] = (dF[0] - k0) * g
        row[n:] = (dF[1] - b0) * g
        row[cj] += dF[2] * fj
        jac[n:2 * n, :2 * n] += np.outer(gain, row)

    def outputs(self, net, t, X, accel) -> dict:
        X = np.asarray(X)
        f1, f2, *_, (u, du, x, l1, l2) = self.spans(X, net)
        F = self.force(net, X)
        k, _ = self.stiffness_at(x)
        out = {f"F_{self.name}": (F, "N"), f"T_{self.name}": (self.r * F, "N m"),
               f"k_{self.name}": (np.broadcast_to(k, np.shape(F)).copy(), "N/m"),
               f"L1_{self.name}": (np.broadcast_to(l1, np.shape(F)).copy(), "m")}
        if self.L2 is not None:
            out[f"L2_{self.name}"] = (np.broadcast_to(l2, np.shape(F)).copy(), "m")
        if self.pretension is not None:
            out[f"F_{self.name}_1"] = (f1, "N")
            if self.L2 is not None:
                out[f"F_{self.name}_2"] = (f2, "N")
        return out


def carriage_belts(net) -> list[CarriageBelt]:
    """The carriage belts of network ``net``."""
    return [el for el in net.elements if isinstance(el, CarriageBelt)]


def held_at(net, positions: dict[str, float]):
    """The network ``net`` with each carriage belt named in ``positions`` held with its
    carriage there [m] (:meth:`CarriageBelt.at`): the linear network whose modes are the
    axis's at that position."""
    swapped = [el.at(positions[el.name]) if isinstance(el, CarriageBelt) and el.name in positions else el
               for el in net.elements]
    return type(net)(list(net.nodes), list(net.gears) + list(net.strands) + swapped)
