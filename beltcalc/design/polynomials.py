"""Polynomials as coefficient tuples ``(c0, c1, c2, ...)`` in the local time of a piece:
what the duty cycle's exact torques, powers and energies are made of
(:mod:`beltcalc.design.dutycycle`, :mod:`beltcalc.design.zones`,
:mod:`beltcalc.design.sizing`, :mod:`beltcalc.design.motor_report`).

References
----------
[NR3] W. H. Press, S. A. Teukolsky, W. T. Vetterling, B. P. Flannery, Numerical Recipes,
    3rd ed., Cambridge University Press (2007): the quadratic formula.
"""

from __future__ import annotations

import math

def poly_value(p: tuple[float, ...], t: float) -> float:
    """p(t), by Horner."""
    out = 0.0
    for c in reversed(p):
        out = out * t + c
    return out


def poly_add(*ps: tuple[float, ...]) -> tuple[float, ...]:
    """The sum of the polynomials."""
    n = max(len(p) for p in ps)
    return tuple(sum(p[k] for p in ps if k < len(p)) for k in range(n))


def poly_scale(p: tuple[float, ...], k: float) -> tuple[float, ...]:
    """k p."""
    return tuple(k * c for c in p)


def poly_mul(p: tuple[float, ...], q: tuple[float, ...]) -> tuple[float, ...]:
    """The product p q."""
    out = [0.0] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return tuple(out)


def poly_integral(p: tuple[float, ...], t: float) -> float:
    """Integral of p from 0 to t (exact for a polynomial)."""
    return sum(c * t ** (k + 1) / (k + 1) for k, c in enumerate(p))


def poly_shift(p: tuple[float, ...], t0: float) -> tuple[float, ...]:
    """p(t0 + s) as a polynomial in s (degree <= 2 here)."""
    c = list(p) + [0.0] * (3 - len(p))
    if len(p) > 3:
        raise ValueError("degree > 2")
    return (c[0] + c[1] * t0 + c[2] * t0 * t0, c[1] + 2 * c[2] * t0, c[2])


def roots_inside(p: tuple[float, ...], duration: float) -> list[float]:
    """Real roots of a polynomial of degree <= 2 strictly inside (0, duration), sorted.

    Closed form with the cancellation-free quadratic formula [NR3 eq. 5.6.4]."""
    c = list(p) + [0.0] * (3 - len(p))
    c0, c1, c2 = c[0], c[1], c[2]
    scale = max(abs(c0), abs(c1) * duration, abs(c2) * duration * duration)
    if scale == 0.0:
        return []
    roots: list[float] = []
    if abs(c2) * duration * duration <= 1e-15 * scale:
        if abs(c1) * duration > 1e-15 * scale:
            roots = [-c0 / c1]
    else:
        disc = c1 * c1 - 4 * c2 * c0
        if disc >= 0:
            q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
            roots = [q / c2] + ([c0 / q] if q != 0 else [])
    eps = 1e-12 * duration
    return sorted(r for r in roots if eps < r < duration - eps)


def quad_min(p: tuple[float, ...], duration: float) -> tuple[float, float]:
    """(minimum, where) of a polynomial of degree <= 2 on [0, duration]: ends and vertex."""
    cands = [0.0, duration]
    if len(p) > 2 and p[2] > 0:
        v = -p[1] / (2 * p[2])
        if 0 < v < duration:
            cands.append(v)
    return min((poly_value(p, t), t) for t in cands)
