"""What a network's tension-only strands add to it: the rows of their elongations and forces
over ``z = [x, g]``, the switching surfaces of a strand mode, which strands are taut, their
forces, and the sparse stamps a taut strand adds to ``[A | B]`` [RP eq. 8-11].
:class:`~beltcalc.sim.network.Network` has them as methods (:class:`StrandModes`); the
switching core and the scipy methods read them. SI floats only.

References:

[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": the strand's
    elongation, force and taut condition [RP eq. 8-11].
"""

from __future__ import annotations

import numpy as np

from beltcalc.sim.network.assembly import Event, require_finite


class StrandModes:
    """The strand methods of :class:`~beltcalc.sim.network.Network`: they read its
    ``strands``, their rows ``_G`` over the coordinates, ``fixed``, ``mass``, ``n``, ``size``
    and ``generators``."""

    def strand_stamps(self, fixed_rows: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What each strand adds to ``[A | B]`` when taut, as sparse entries ``(owner, row,
        col, value)`` over ``z = [x, g]`` (column ``size`` is the constant generator): its
        stiffness and damping on the two nodes' accelerations (``-M^-1 c g g^T`` and
        ``-M^-1 b g g^T``) and its pretension (``-M^-1 g F0``). Rows of prescribed nodes are
        left out, as :meth:`first_order` zeroes them (kept with ``fixed_rows``: the
        unconstrained system of a drive torque). With these, ``[A | B]`` of any strand
        pattern is the all-slack one plus the stamps of its taut strands: O(strands) work
        per pattern instead of a dense rebuild."""
        n, m = self.n, self.size
        Minv = 1.0 / self.mass
        owner, rows, cols, vals = [], [], [], []
        for k, (s, g) in enumerate(zip(self.strands, self._G)):
            nz = np.nonzero(g)[0]
            for a in nz:
                if a in self.fixed and not fixed_rows:
                    continue
                for b in nz:
                    owner += [k, k]
                    rows += [n + a, n + a]
                    cols += [b, n + b]
                    vals += [-Minv[a] * s.stiffness * g[a] * g[b], -Minv[a] * s.damping * g[a] * g[b]]
                if s.preload:
                    owner.append(k)
                    rows.append(n + a)
                    cols.append(m)
                    vals.append(-Minv[a] * g[a] * s.preload)
        vals = np.array(vals, dtype=float)
        require_finite(vals)
        return (np.array(owner, dtype=np.int64), np.array(rows, dtype=np.int64),
                np.array(cols, dtype=np.int64), vals)

    def strand_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """Rows over z = [x, g] giving every strand's elongation delta [m] and (taut) force F [N]
        of [RP eq. 8-11] (built once)."""
        if self._rows is None:
            n, m = self.n, self.size
            p = self.generators(0.0).size
            delta = np.zeros((len(self.strands), m + p))
            force = np.zeros_like(delta)
            for k, s in enumerate(self.strands):
                delta[k, :n] = self._G[k]
                delta[k, m] = s.preload / s.stiffness
                force[k, :n] = s.stiffness * self._G[k]
                force[k, n:2 * n] = s.damping * self._G[k]
                force[k, m] = s.preload
            self._rows = (delta, force)
        return self._rows

    def events(self, taut: tuple[bool, ...]) -> list[Event]:
        """The switching surfaces of a mode: a taut strand goes slack when its force or its
        elongation falls through zero; a slack one goes taut when its elongation rises
        through zero (its force is then b delta' > 0), or when its force rises through zero
        while it is still elongated."""
        delta, force = self.strand_rows()
        out = []
        for k, on in enumerate(taut[:len(self.strands)]):
            if on:
                out += [Event(k, "force", -1, force[k]), Event(k, "delta", -1, delta[k])]
            else:
                out += [Event(k, "delta", +1, delta[k]), Event(k, "force", +1, force[k])]
        return out

    def taut_after(self, k: int, z: np.ndarray, dz: np.ndarray, ahead: np.ndarray, h: float) -> bool:
        """Whether strand ``k`` is taut just after the state ``z``: elongation and force both
        positive. A value within 1e-6 of what its rate ``dz`` changes in the time ``h`` (a
        located switch sits that close to its surface) is judged by its rate, and a rate that
        small by the state ``ahead`` (a moment later, e.g. from rest)."""
        delta, force = self.strand_rows()

        def positive(row):
            v, rate = row @ z, row @ dz
            if abs(v) > 1e-6 * abs(rate) * h:
                return v > 0
            if abs(rate) * h > 1e-9 * abs(row @ ahead - v) and rate != 0:
                return rate > 0
            # no rate at all (at rest, a strand without pretension): taut unless the state a
            # moment later says it slackens; a chain just touching its sprockets is taut
            return row @ ahead >= v

        return positive(delta[k]) and positive(force[k])

    def taut_of(self, x: np.ndarray, t) -> np.ndarray:
        """Boolean (strands, samples): taut where elongation and force are both positive."""
        X = x if x.ndim == 2 else x[:, None]
        z = np.vstack([X, self.generators(np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],)))])
        delta, force = self.strand_rows()
        return (delta @ z > 0) & (force @ z > 0)

    def strand_forces(self, t, x: np.ndarray) -> dict[str, np.ndarray]:
        """Force in each strand [N]: c delta + b delta' while taut, else 0 [RP eq. 8-11]."""
        if not self.strands:
            return {}
        f = self._forces(np.vstack([x, self.generators(t)]))
        return {s.name: f[k] for k, s in enumerate(self.strands)}

    def _add_strands(self, out: np.ndarray, X: np.ndarray, G: np.ndarray, constrained: bool) -> None:
        """out += the stamps of the strands taut at each sample: every stamp entry
        ``value * z[col]`` where its strand is taut, added into its row in the stamps' order
        (the terms are large and cancel: a strand force is a small difference of stiffness
        times angle, so the order of the sum is kept). Array expressions over blocks of
        samples, one per rank of an entry within its row (a handful)."""
        key = ("stamps", constrained)
        hit = self._cache.get(key)
        if hit is None:
            owner, rows, cols, vals = self.strand_stamps(fixed_rows=not constrained)
            targets = np.flatnonzero(np.bincount(rows))          # the rows stamped, sorted (np.unique
            group = np.searchsorted(targets, rows)               # would import numpy.ma: 5 ms of start-up)
            rank = np.zeros(rows.size, dtype=np.int64)
            seen: dict[int, int] = {}
            for e, r in enumerate(group.tolist()):
                rank[e], seen[r] = seen.get(r, 0), seen.get(r, 0) + 1
            layers = [np.flatnonzero(rank == j) for j in range(int(rank.max()) + 1 if rank.size else 0)]
            hit = self._cache[key] = (targets, [(group[e], owner[e], cols[e], vals[e][:, None]) for e in layers])
        targets, layers = hit
        if not targets.size:
            return
        Z = np.vstack([X, G])
        taut = self._taut_rows(Z)
        N = X.shape[1]
        block = max(256, (1 << 18) // targets.size)
        for a in range(0, N, block):
            b = min(a + block, N)
            part = np.zeros((targets.size, b - a))
            for group, owner, cols, vals in layers:       # entries of distinct rows: no collision
                part[group] += vals * Z[cols, a:b] * taut[owner, a:b]
            out[targets, a:b] += part

    def _taut_rows(self, Z: np.ndarray) -> np.ndarray:
        """Boolean (strands, samples): elongation and force both positive at ``Z = [x, g]``."""
        delta, force = self.strand_rows()
        return (delta @ Z > 0) & (force @ Z > 0)

    def _forces(self, Z: np.ndarray) -> np.ndarray:
        """Strand forces (strands x samples) at ``Z = [x, g]``: c delta + b delta' where the
        elongation and the force are both positive, else 0."""
        delta, force = self.strand_rows()
        f = force @ Z
        f[(delta @ Z <= 0) | (f <= 0)] = 0.0
        return f
