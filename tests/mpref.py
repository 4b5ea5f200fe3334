"""High-precision reference solutions for the error-estimate tests (mpmath, pure Python).

For a smooth linear network (no strands, no time break points) the augmented system
z' = F z, z = [x, g], F = :func:`beltcalc.sim.propagate.augmented_matrix`, has the exact one-step
map P = exp(F dt). Here F is converted to mpmath exactly (every float is a dyadic rational),
P = mpmath.expm(F dt) with dt = mpf(t_end) / (samples - 1), z0 = [x0, g(0)], and
z_{k+1} = P z_k, all at ``digits`` decimal digits. Nothing of beltcalc's propagation
(balancing, blocks, powers by doubling) is used; only F, x0 and g(0) come from the network.

Cost (pure-Python mpmath, no gmpy): about 0.12 ms per step at 40 digits on the 14 x 14
sewing system (11 states + 3 generators), i.e. 1.1-1.4 s for 10001 samples; 60 digits about
1.2x that.
"""

from __future__ import annotations

import mpmath
import numpy as np

from beltcalc.sim.propagate import augmented_matrix


def _check(network) -> None:
    if not network.linear or not network.smooth:
        raise ValueError("mpref handles smooth linear networks only (no strands, no time break points, "
                         "no loads locked to a shaft angle)")


def reference_mp(network, t_end: float, samples: int, digits: int = 40, x0=None) -> list[list]:
    """The states at t_k = k t_end / (samples - 1), k < samples, as mpf values computed at
    ``digits`` decimal digits: a list over samples of lists over states (length
    ``network.size``). ``x0``: the initial state (rest, ``network.initial_state()``, by
    default)."""
    _check(network)
    if samples < 2:
        raise ValueError("at least 2 samples")
    F = augmented_matrix(network)
    x0 = network.initial_state() if x0 is None else np.asarray(x0, dtype=float)
    z0 = np.concatenate([x0, np.atleast_1d(network.generators(0.0))])
    m, size = F.shape[0], network.size
    with mpmath.workdps(digits):
        Fm = mpmath.matrix([[mpmath.mpf(float(v)) for v in row] for row in F])   # exact conversion
        dt = mpmath.mpf(float(t_end)) / (samples - 1)
        P = mpmath.expm(Fm * dt)
        # rows as plain lists without the structural zeros (the generator rows are sparse)
        rows = []
        for i in range(m):
            cols = [j for j in range(m) if P[i, j] != 0]
            rows.append((cols, [P[i, j] for j in cols]))
        z = [mpmath.mpf(float(v)) for v in z0]
        out = [z[:size]]
        for _ in range(samples - 1):
            z = [mpmath.fdot(coef, [z[j] for j in cols]) if cols else mpmath.mpf(0) for cols, coef in rows]
            out.append(z[:size])
    return out


def to_array(values: list[list]) -> np.ndarray:
    """mpf values as from :func:`reference_mp` -> floats, shape (size, samples)."""
    return np.array([[float(v) for v in col] for col in values]).T


def reference(network, t_end: float, samples: int, digits: int = 40, x0=None) -> np.ndarray:
    """The states x at the output times, shape (network.size, samples), as floats (each the
    correctly rounded value of the ``digits``-digit result)."""
    return to_array(reference_mp(network, t_end, samples, digits, x0))


def max_difference(a: list[list], b: list[list], rows, digits: int = 80) -> list:
    """Per row in ``rows``: max over samples of |a - b| (mpf, computed at ``digits``)."""
    with mpmath.workdps(digits):
        return [max(abs(sa[k] - sb[k]) for sa, sb in zip(a, b)) for k in rows]
