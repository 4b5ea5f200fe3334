"""The generalised coordinates of a network: every group of nodes joined by rigid gears is one
coordinate (the angle of its first node), and a group without inertia (massless nodes between
springs) is condensed out exactly: its angle follows the springs' static balance,
``q_m = -K_mm^-1 K_mr q_r`` (Guyan's reduction [Guy65], exact without inertia). SI floats
only.

References:

[Guy65] R. J. Guyan, "Reduction of stiffness and mass matrices", AIAA Journal 3 (1965) 380.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import FloatRangeError, InputError, did_you_mean
from beltcalc.sim.elements import check_gear_ratio


@dataclass
class Coordinates:
    """The coordinates of a network: their names (each a gear group's first node with
    inertia), masses, ``T`` (nodes x coordinates: node ``k``'s angle is ``T[k] . q``), the nodes
    condensed out, and ``condensed`` = (D over the groups, R: groups -> coordinates) when any
    are (for :func:`check_condensation`)."""

    coords: list[str]
    mass: np.ndarray
    T: np.ndarray
    massless: set[str]
    condensed: tuple[np.ndarray, np.ndarray] | None = None


def coordinates(nodes: list, gears: list, couplings: list) -> Coordinates:
    """The generalised coordinates of ``nodes`` joined by rigid ``gears``, with the massless
    groups condensed out through the ``couplings``' springs (:class:`Coordinates`)."""
    index = {nd.name: k for k, nd in enumerate(nodes)}
    parent = list(range(len(nodes)))
    factor = [1.0] * len(nodes)          # phi_k = factor[k] * phi_parent[k]

    def find(k):
        f = 1.0
        while parent[k] != k:
            f *= factor[k]
            k = parent[k]
        return k, f

    for g in gears:
        for end in (g.a, g.b):
            if end not in index:
                raise InputError(f"gear {g.name or g.a + '-' + g.b} names an unknown node {end!r}; "
                                 + did_you_mean(str(end), [nd.name for nd in nodes]), param="network")
        check_gear_ratio(g.name, g.ratio)
        (ra, fa), (rb, fb) = find(index[g.a]), find(index[g.b])
        # phi_a = fa R_a, phi_b = fb R_b, and phi_b = phi_a / ratio
        if ra == rb:
            if not math.isclose(fb, fa / g.ratio, rel_tol=1e-9):
                raise InputError(f"rigid gears form a loop with inconsistent ratios at {g.name or g.b!r}: "
                                 f"{g.b} would turn at {fb:.6g} and at {fa / g.ratio:.6g} times "
                                 f"{nodes[ra].name}", param="network")
        elif ra < rb:      # the earlier-listed node stays the root
            parent[rb], factor[rb] = ra, fa / (g.ratio * fb)
        else:
            parent[ra], factor[ra] = rb, g.ratio * fb / fa
    roots, f_of = [], []
    for k in range(len(nodes)):
        r, f = find(k)
        roots.append(r)
        f_of.append(f)
    groups = sorted(set(roots))
    gmass = {r: 0.0 for r in groups}
    for k, nd in enumerate(nodes):
        square = f_of[k] * f_of[k]
        if not math.isfinite(square):
            raise FloatRangeError(f"the rigid gears make node {nd.name} turn {abs(f_of[k]):.3g} times as fast as "
                                  f"{nodes[roots[k]].name}: the square of that ratio, which takes its "
                                  "inertia and springs to one coordinate, overflows a float (beyond 1e308)")
        gmass[roots[k]] += square * nd.J
    heavy = [r for r in groups if gmass[r] > 0]
    light = [r for r in groups if gmass[r] == 0]
    out = Coordinates(coords=[nodes[r].name for r in heavy], mass=np.array([gmass[r] for r in heavy], dtype=float),
                      T=np.zeros((0, 0)), massless={nodes[k].name for k in range(len(nodes)) if roots[k] in light})
    n, L = len(heavy), len(light)
    F = np.zeros((len(nodes), n + L))    # node -> group coordinates (heavy first)
    col = {r: c for c, r in enumerate(heavy + light)}
    for k in range(len(nodes)):
        F[k, col[roots[k]]] = f_of[k]
    if L == 0:
        out.T = F
        return out
    # static condensation of the massless groups through the couplings' springs
    K = np.zeros((n + L, n + L))
    D = np.zeros_like(K)
    for c in couplings:
        for end in (c.i, c.j):
            if end is not None and end not in index:
                raise InputError(f"element {c.name} names an unknown node {end!r}; "
                                 + did_you_mean(str(end), [nd.name for nd in nodes]), param="network")
        g = F[index[c.i]] - (c.U * F[index[c.j]] if c.j is not None else 0.0)
        K += c.C * np.outer(g, g)
        D += c.d * np.outer(g, g)
    Kmm, Kmr = K[n:, n:], K[n:, :n]
    try:
        cond = np.linalg.cond(Kmm)
    except np.linalg.LinAlgError:
        cond = math.inf
    if not cond < 1e12:
        lonely = [nodes[r].name for r in light]
        raise InputError(f"node(s) {', '.join(lonely)} have no inertia and no spring path to one: give "
                         "each node an inertia, or connect it by a coupling to a node that has one",
                         param="network")
    R = np.vstack([np.eye(n), -np.linalg.solve(Kmm, Kmr)])     # group coordinates -> heavy ones
    out.condensed = (D, R)
    out.T = F @ R
    return out


def check_condensation(c: Coordinates, elements) -> None:
    """Refuse a condensation that is not exact: a damper that pulls on a massless group as it
    follows the springs' balance (D_m R = 0 holds for dampers proportional to the springs, or
    none), or an element of ``elements`` with a ``node`` that has no inertia."""
    if c.condensed is None:
        return
    D, R = c.condensed
    n = len(c.coords)
    scale = float(np.abs(D).max()) * float(np.abs(R).max()) if D.size else 0.0
    if scale and float(np.abs(D[n:] @ R).max()) > 1e-9 * scale:
        names = sorted(c.massless)
        raise InputError(f"node(s) {', '.join(names)} have no inertia and dampers not proportional to their "
                         "springs: condensing them would not be exact; give them an inertia, or make each "
                         "damping d = beta C with one beta", param="network")
    for el in elements:
        node = getattr(el, "node", None)
        if node in c.massless:
            raise InputError(f"{type(el).__name__} on {node!r}: a node without inertia cannot carry a load "
                             "or a drive; give it the inertia of its parts", param="network")
