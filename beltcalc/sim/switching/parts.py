"""A large network's strand patterns as sparse matrices, for the switching core's sparse path
(:class:`beltcalc.sim.switching.sparse.SparseMode`): the balanced ``F~`` of any pattern and
its switching rows, assembled in O(nonzeros) from the network's all-slack matrix and its
strands' stamps.
"""

from __future__ import annotations

import numpy as np

from beltcalc.sim.propagate import augmented_matrix


class SparseParts:
    """The balanced ``F~`` of any strand pattern, and its switching rows, from sparse pieces:
    the all-slack matrix of each time piece plus the stamps of the taut strands
    (:meth:`beltcalc.sim.network.Network.strand_stamps`), scaled by S. Per time piece the
    places of every entry any pattern can have (CSR, built once) and which of them each base
    entry and stamp adds to: a pattern's values are one weighted count over those places
    (the slack strands' stamps weighted 0, their places left as explicit zeros), its norm
    another; a pattern's event rows are gathered from the rows of every strand, as arrays."""

    def __init__(self, network, S: np.ndarray):
        from scipy import sparse

        self.network, self.S, self.sparse = network, S, sparse
        self.owner, self.r, self.c, v = network.strand_stamps()
        self.v = v / S[self.r] * S[self.c]
        self.none = tuple(False for _ in network.strands)
        self.ns = len(network.strands)
        self._base: dict = {}
        delta, force = network.strand_rows()
        # every mode's event rows, two per strand in a fixed order (force, delta): a pattern
        # changes only their directions (taut: both falling; slack: both rising), which
        # Network.events gives per strand state
        both = np.empty((2 * self.ns, S.size))
        both[0::2], both[1::2] = force, delta
        self.H = sparse.csr_matrix(both * S[None, :])
        self.H.sort_indices()
        self.absH = abs(self.H)
        on, off = network.events((True,) * self.ns), network.events(self.none)
        self._events = {}
        self._dirs = []
        for state in (on, off):
            table = {(e.strand, e.kind): e for e in state}
            events = [table[(k, kind)] for k in range(self.ns) for kind in ("force", "delta")]
            self._events[state is on] = events
            self._dirs.append(np.array([e.direction for e in events], dtype=float))
        self.event_strand = np.repeat(np.arange(self.ns), 2)

    def events(self, taut: tuple[bool, ...]) -> list:
        """The events of the pattern ``taut`` in the fixed order (force, delta) per strand,
        each as :meth:`Network.events` gives it for the strand's own state."""
        on, off = self._events[True], self._events[False]
        return [(on if taut[k] else off)[i] for i, k in enumerate(self.event_strand)]

    def directions(self, taut: tuple[bool, ...]) -> np.ndarray:
        """Each event's firing direction in the pattern ``taut`` (the fixed order)."""
        return np.where(np.repeat(np.asarray(taut, dtype=bool), 2), self._dirs[0], self._dirs[1])

    def _structure(self, t_mid: float):
        """(indptr, indices, place of each base entry and stamp, base values): the CSR places
        of every entry of the time piece holding ``t_mid`` in any strand pattern."""
        hit = self._base.get(t_mid)
        if hit is None:
            F = augmented_matrix(self.network, self.none, t_mid) / self.S[:, None] * self.S[None, :]
            r, c = np.nonzero(F)
            m = self.S.size
            rows, cols = np.concatenate([r, self.r]), np.concatenate([c, self.c])
            key = rows * m + cols
            places, where = np.unique(key, return_inverse=True)     # row-major: CSR order
            indptr = np.zeros(m + 1, dtype=np.int32)
            np.cumsum(np.bincount(places // m, minlength=m), out=indptr[1:])
            hit = self._base[t_mid] = (indptr, (places % m).astype(np.int32), where, F[r, c], r.size)
        return hit

    def matrix(self, taut: tuple[bool, ...], t_mid: float):
        """((indptr, indices, data), ||F~||_1): F~ of the pattern ``taut`` on the time piece
        holding ``t_mid`` as CSR arrays on the piece's places (a slack strand's own places
        hold zeros)."""
        indptr, indices, where, base, nb = self._structure(t_mid)
        weights = np.concatenate([base, self.v * np.asarray(taut, dtype=float)[self.owner]])
        data = np.bincount(where, weights=weights, minlength=indices.size)
        norm = float(np.bincount(indices, weights=np.abs(data), minlength=self.S.size).max())
        return (indptr, indices, data), norm

    def scipy_matrix(self, taut: tuple[bool, ...], t_mid: float):
        """F~ of the pattern as a scipy CSR matrix."""
        (indptr, indices, data), _ = self.matrix(taut, t_mid)
        m = self.S.size
        return self.sparse.csr_matrix((data, indices, indptr), shape=(m, m))
