"""beltcalc.numerics.scalar: the ports of scipy's brentq and golden section return scipy's
numbers bit for bit (the frequency response's peaks and Q were computed by scipy before)."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from scipy.optimize import brentq as scipy_brentq
from scipy.optimize import minimize_scalar

from beltcalc.numerics.scalar import brentq, golden_minimum, horner


def _outcome(call):
    try:
        return call()
    except (ValueError, RuntimeError) as exc:
        return type(exc).__name__


def test_brentq_is_scipys_on_random_brackets():
    rng = random.Random(1)
    done = 0
    while done < 500:
        c = [rng.uniform(-3, 3) for _ in range(4)]

        def f(x):
            return c[0] + c[1] * x + c[2] * x ** 3 + math.sin(c[3] * x)

        a, b = rng.uniform(-5, 0), rng.uniform(0, 5)
        if f(a) * f(b) >= 0:
            continue
        xtol = rng.choice([2e-12, 1e-14 * b, 1e-6])
        assert brentq(f, a, b, xtol=xtol) == scipy_brentq(f, a, b, xtol=xtol)
        done += 1


@pytest.mark.parametrize("f, a, b", [
    (lambda x: x, 0.0, 1.0),                                   # a root at an end
    (lambda x: x - 1.0, 0.0, 1.0),
    (lambda x: x * x + 1.0, 0.0, 1.0),                         # no sign change: ValueError
    (lambda x: (x - 0.3) * 1e-170, 0.0, 1.0),                  # f(a) f(b) underflows: the signs decide
    (lambda x: math.inf if x < 0.5 else -1.0, 0.0, 1.0),       # |H| infinite on an undamped pole
    (lambda x: math.nan, 0.0, 1.0),                            # NaN: ValueError
    (lambda x: math.tan(x), 1.0, 2.0),                         # a pole, not a root: converges onto it
])
def test_brentq_edge_cases_as_scipy(f, a, b):
    assert _outcome(lambda: brentq(f, a, b)) == _outcome(lambda: scipy_brentq(f, a, b))


def test_brentq_refuses_tolerances_as_scipy():
    for kw in ({"xtol": 0.0}, {"rtol": 1e-17}):
        assert _outcome(lambda: brentq(math.sin, 3.0, 4.0, **kw)) == "ValueError"
    assert _outcome(lambda: brentq(lambda x: x - 0.7, 0.0, 1.0, maxiter=1)) == \
        _outcome(lambda: scipy_brentq(lambda x: x - 0.7, 0.0, 1.0, maxiter=1))


def test_golden_minimum_is_scipys_on_random_brackets():
    rng = random.Random(2)
    done = 0
    while done < 500:
        c, s = rng.uniform(-2, 2), rng.uniform(0.1, 3)

        def f(x):
            return -1.0 / (1 + ((x - c) / s) ** 2) + 0.01 * math.sin(7 * x)

        # numpy scalars as the frequency grid gives them
        xa, xb, xc = np.float64(c - rng.uniform(0.1, 2)), np.float64(c + rng.uniform(-0.05, 0.05)), \
            np.float64(c + rng.uniform(0.1, 2))
        ref = _outcome(lambda: minimize_scalar(f, bracket=(xa, xb, xc), method="golden", options={"xtol": 1e-12}))
        if isinstance(ref, str):
            assert _outcome(lambda: golden_minimum(f, xa, xb, xc, xtol=1e-12)) == ref
            continue
        x, fx = golden_minimum(f, xa, xb, xc, xtol=1e-12)
        assert (float(x), float(fx)) == (float(ref.x), float(ref.fun))
        done += 1


def test_the_response_peaks_are_scipys():
    # the peaks and Q of the sewing drive's response, refined by scipy as before
    from beltcalc.sim import frequency as fr
    from beltcalc.sim.drivefile import DriveFile, drive_path

    net = DriveFile(drive_path("sewing")).network()
    omega = np.linspace(1.0, 3000.0, 800)
    ours = fr.frequency_response(net, ["load:3"], ["omega_3", "omega_5"], omega)

    def scipy_peaks(omega, mag, h):
        out = []
        for k in range(1, mag.size - 1):
            if not (mag[k] > mag[k - 1] and mag[k] >= mag[k + 1]):
                continue
            res = minimize_scalar(lambda w: -h(w), bracket=(omega[k - 1], omega[k], omega[k + 1]), method="golden",
                                  options={"xtol": 1e-12})
            w0, peak = float(res.x), float(-res.fun)
            half = peak / math.sqrt(2)
            lo = next((j for j in range(k, -1, -1) if mag[j] < half), None)
            hi = next((j for j in range(k, mag.size) if mag[j] < half), None)
            q = None
            if lo is not None and hi is not None:
                try:
                    w1 = scipy_brentq(lambda w: h(w) - half, omega[lo], w0, xtol=1e-14 * w0)
                    w2 = scipy_brentq(lambda w: h(w) - half, w0, omega[hi], xtol=1e-14 * w0)
                    q = w0 / (w2 - w1) if w2 > w1 else math.inf
                except ValueError:
                    q = math.inf
            out.append((w0 / (2 * math.pi), peak, q))
        return out

    real = fr._peaks
    try:
        fr._peaks = scipy_peaks
        theirs = fr.frequency_response(net, ["load:3"], ["omega_3", "omega_5"], omega)
    finally:
        fr._peaks = real
    assert ours.peaks == theirs.peaks
    assert sum(len(p) for p in ours.peaks.values()) >= 2


def test_horner_is_numpys_polyval():
    # the watch and the switch location evaluate the step's Taylor polynomial (34 to 62 terms) so
    rng = np.random.default_rng(5)
    for _ in range(200):
        n = int(rng.integers(34, 63))
        c = (rng.standard_normal(n) / np.cumprod(np.arange(1, n + 1)) * 10.0 ** rng.integers(-8, 8)).tolist()
        x = np.linspace(rng.uniform(-1, 0), rng.uniform(0, 1), 257)
        ref = np.polynomial.polynomial.polyval(x, np.array(c))
        assert horner(c, x).tobytes() == ref.tobytes()
        assert [horner(c, float(v)) for v in x] == ref.tolist()
