"""The watch's vectorised polish of extremes (beltcalc/sim/watch/polish.py, ``polish_polynomials``):
the largest value of each Taylor polynomial on its interval, checked against scipy's
bounded Brent search on a dense grid (an independent reference), and its edge cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import minimize_scalar

from beltcalc.sim.switching import TERMS
from beltcalc.sim.watch.polish import polish_polynomials


def reference_max(c: np.ndarray, a: float, b: float) -> float:
    """max of sum c_j s^j on [a, b]: a grid of 20,001 points, then scipy's bounded search
    (to 1e-15 of the interval) around its best point."""
    p = np.polynomial.Polynomial(c)
    s = np.linspace(a, b, 20001)
    y = p(s)
    i = int(np.argmax(y))
    lo, hi = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
    best = float(y[i])
    if hi > lo:
        r = minimize_scalar(lambda x: -p(x), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-15 * (b - a)})
        best = max(best, -float(r.fun))
    return best


def taylor_like(rng: np.random.Generator, count: int) -> np.ndarray:
    """Coefficients of the kind the watch polishes: a signal's Taylor polynomial over one bottom
    step, c_j ~ 4^j / j! (||F~ L|| = 4; the terms shrink from j = 4 on) with random signs, plus a
    large constant part."""
    j = np.arange(TERMS)
    size = 4.0 ** j / np.array([float(math.factorial(int(k))) for k in j])
    C = rng.standard_normal((count, TERMS)) * size
    C[:, 0] += rng.uniform(-50, 50, count)
    return C


def test_polish_finds_the_maximum_of_taylor_polynomials():
    rng = np.random.default_rng(7)
    C = taylor_like(rng, 60)
    a = rng.uniform(-1.0, 0.0, 60)
    b = rng.uniform(0.0, 1.0, 60)
    got = polish_polynomials(C, a, b)
    want = np.array([reference_max(C[r], a[r], b[r]) for r in range(60)])
    scale = np.abs(C).sum(axis=1)           # the rounding of one evaluation is relative to this
    assert_allclose(got / scale, want / scale, rtol=0, atol=1e-14)


def test_polish_matches_the_search_it_replaced_where_the_peak_is_interior():
    # a peak well inside the interval: p(s) = 3 - 40 (s - 0.3)^2 + small higher terms
    c = np.zeros(TERMS)
    c[0], c[1], c[2] = 3 - 40 * 0.09, 40 * 0.6, -40.0
    c[3:8] = 1e-3 * np.arange(1, 6)
    got = polish_polynomials(c[None], np.array([-1.0]), np.array([1.0]))[0]
    assert got == pytest.approx(reference_max(c, -1.0, 1.0), rel=1e-15, abs=1e-15)


def test_polish_at_an_end_and_on_an_empty_interval():
    c = np.zeros(TERMS)
    c[0], c[1] = 1.0, 2.0                     # increasing: the maximum is at b
    got = polish_polynomials(np.vstack([c, c, -c]), np.array([-0.5, 0.2, -0.5]), np.array([0.25, 0.2, 0.25]))
    assert got[0] == pytest.approx(1.5, rel=1e-15)
    assert got[1] == -np.inf                   # empty interval
    assert got[2] == pytest.approx(0.0, abs=1e-15)    # -(1 + 2 s): largest at s = -0.5


def stiff_drive():
    """The sewing drive file: its one mode is stiff (a coarse step of 2^10 bottom steps)."""
    from beltcalc.sim.drivefile import DriveFile, drive_path
    from beltcalc.sim.scenes.drive import _speed

    drive = DriveFile(drive_path("sewing")).build()
    net = drive.network
    names = [_speed(net, n) for n in drive.nodes] + [s for s, _ in drive.torques] + [s for s, _ in drive.motors]
    return net, drive, names


def test_stiff_mode_extremes_agree_with_a_million_samples(monkeypatch):
    # a stiff mode's extremes (a coarse step of 2^10 bottom steps): watched at every bottom
    # step (watch.Watch.walks), they agree with 1,000,001 samples of the run to 1e-8 of each
    # signal's scale and are never inside the sampled range beyond the two runs' rounding.
    # Watched at the coarse step points only (WALK_POINTS = 0), around the best of them by the
    # walk (LADDER_POINTS) or the grid search on the ladder (both 0, polish.zoom_max), they agree with each
    # other, and miss by up to 1.3e-5 of a shaft torque's scale where the load's cycles peak
    # alike and the stiff coupling rings within a coarse step (the candidate is the wrong
    # cycle's): measured, so the reason for the bottom-step watch cannot be lost unseen.
    import beltcalc.sim.watch.blocks as watch
    from beltcalc.sim.core import SolverConfig, simulate

    net, drive, names = stiff_drive()
    window = (0.0, drive.window)

    def run(accept=False):
        # the coarse watches are the degraded configurations measured on purpose: the estimate of
        # the reported figures sees their misses (0.3 rad/s on omega_1's minimum), so accepted
        return simulate(net, drive.t_end, drive.samples, SolverConfig("exact", accept_error=accept),
                        watch=(names, window))

    bottom = run()
    monkeypatch.setattr(watch, "WALK_POINTS", 0)
    coarse = run(True)
    monkeypatch.setattr(watch, "LADDER_POINTS", 0)
    searched = run(True)
    dense = simulate(net, drive.t_end, 100 * drive.samples - 99, SolverConfig("exact", estimate_error=False))
    for name in names:
        for start in window:
            y = dense.signals[name][dense.t >= start]
            scale = max(float(np.max(np.abs(y))), 1e-300)
            a, c, b = bottom.summary(name, start), coarse.summary(name, start), searched.summary(name, start)
            assert a.max == pytest.approx(float(y.max()), rel=0, abs=1e-8 * scale), name
            assert a.min == pytest.approx(float(y.min()), rel=0, abs=1e-8 * scale), name
            assert max(float(y.max()) - a.max, 0.0) == pytest.approx(0.0, abs=1e-9 * scale), name
            assert max(a.min - float(y.min()), 0.0) == pytest.approx(0.0, abs=1e-9 * scale), name
            assert c.max == pytest.approx(b.max, rel=0, abs=1e-8 * scale), name
            assert c.min == pytest.approx(b.min, rel=0, abs=1e-8 * scale), name
            assert c.max == pytest.approx(float(y.max()), rel=0, abs=3e-5 * scale), name
            assert c.min == pytest.approx(float(y.min()), rel=0, abs=3e-5 * scale), name


def test_polish_steps_by_cells_matches_the_search_on_the_whole_step():
    # a sparse run's candidate steps: Newton around the best of COARSE points, then the full
    # search only in the cells whose coarse values plus the rise bound still reach what it
    # found; the same maximum as the search on the whole step (the reference above)
    from beltcalc.sim.watch.polish import COARSE, cell_rises, polish_steps

    rng = np.random.default_rng(11)
    C = taylor_like(rng, 80)
    a = np.zeros(80)
    b = rng.uniform(0.3, 1.0, 80)
    s_c = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, COARSE)[None, :]
    y = np.array([np.polynomial.Polynomial(c)(s) for c, s in zip(C, s_c)])
    j = np.arange(C.shape[1])
    want = np.array([reference_max(C[r], a[r], b[r]) for r in range(80)])
    scale = np.abs(C).sum(axis=1)
    # one rise per step (the coefficients' bound) or one per cell (cell_rises)
    for rise in ((np.abs(C) @ (j * (j - 1.0))) * ((b - a) / (COARSE - 1)) ** 2 / 8, cell_rises(C, s_c)):
        best = np.full(80, -np.inf)
        polish_steps(best, np.arange(80), C, s_c, y, rise, a, b)
        assert_allclose(best / scale, want / scale, rtol=0, atol=1e-14)


def test_cell_rises_bound_every_cell_and_stay_close_to_the_curvature():
    # the per-cell bound of how far a step's polynomial rises above a cell's ends, from its
    # Taylor shift to the cell's midpoint: never below the true rise (read on 2001 points a
    # cell), and within four times the true max |p''| d^2 / 8 (the bound from the step's own
    # coefficients is tens of times larger on the longer steps of an estimate's second run)
    from beltcalc.sim.watch.polish import COARSE, cell_rises

    rng = np.random.default_rng(5)
    j = np.arange(TERMS)
    for stretch in (1.0, 1.5):
        C = taylor_like(rng, 60) * stretch ** j
        a = np.zeros(60)
        b = rng.uniform(0.3, 1.0, 60)
        s_c = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, COARSE)[None, :]
        rises = cell_rises(C, s_c)
        assert rises.shape == (60, COARSE - 1)
        for r in range(60):
            p = np.polynomial.Polynomial(C[r])
            d2 = p.deriv(2)
            for k in range(COARSE - 1):
                s = np.linspace(s_c[r, k], s_c[r, k + 1], 2001)
                above = float(p(s).max()) - max(p(s_c[r, k]), p(s_c[r, k + 1]))
                assert max(above - rises[r, k], 0.0) == pytest.approx(0.0, abs=1e-13 * np.abs(C[r]).sum())
                tight = float(np.abs(d2(s)).max()) * (s_c[r, k + 1] - s_c[r, k]) ** 2 / 8
                assert rises[r, k] == pytest.approx(tight, rel=3.0)


def test_pending_steps_keep_only_what_may_hold_the_extreme():
    # the store of a sparse run's candidate steps: rows whose bound falls below their signal's
    # best are dropped, the others kept with their coefficients (zero-padded to the widest)
    from beltcalc.sim.watch.polish import COARSE, PendingSteps

    store = PendingSteps()
    rng = np.random.default_rng(2)
    who = np.array([0, 1, 1, 2])
    bound = np.array([5.0, 1.0, 3.0, -1.0])
    store.add(who, bound, rng.normal(size=(4, 7)), rng.normal(size=(4, COARSE)), np.ones((4, COARSE - 1)),
              np.zeros(4), np.ones(4))
    store.add(np.array([2]), np.array([0.5]), rng.normal(size=(1, 9)), rng.normal(size=(1, COARSE)),
              np.ones((1, COARSE - 1)), np.zeros(1), np.ones(1))
    store.prune(np.array([4.0, 2.0, 0.0]))
    kept_who, kept_bound, C, *_ = store.rows()
    assert kept_who.tolist() == [0, 1, 2] and kept_bound.tolist() == [5.0, 3.0, 0.5]
    assert C.shape == (3, 9) and np.all(C[:2, 7:] == 0.0)
