"""The switching core's bottom step and the cheap tests in front of the exact polynomial.

* ``step_length``: ``min(8 / ||F~||, 4 / rho)``: a chain whose strand stiffness sets the
  norm steps by the norm, a stiff coupling whose own frequency is near the norm by the
  radius; the spectral radius of the sparse path comes from power steps.
* ``may_fire`` (the Bernstein convex hull) and ``stays_down`` (values and rates on a grid
  with the bound of p'') may rule a candidate out only where ``first_fire`` (sampling,
  refinement, Brent) finds no crossing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from beltcalc.sim import switching
from beltcalc.sim.switching.firing import first_fire, may_fire, stays_down
from beltcalc.sim.switching.parts import SparseParts
from beltcalc.sim.scenes import SCENES, roller_table, sewing
from test_switching_reference import params


def _mode(net):
    t = np.linspace(0.0, 1.0, 11)
    run = switching.Run(net, t, np.zeros(net.size), 100)
    return run, run.cache.get(run.start_taut, 0, 0.5)


def test_a_chain_steps_by_its_norm_and_a_stiff_coupling_by_its_radius():
    # roller table: rho L = 1.3 to 2.5 at the norm's step (the chain strands set the norm);
    # sewing: a coupling 1e6 stiffer, rho near the norm: rho L = RHO
    run, mode = _mode(roller_table.build(params()))
    norm = float(np.abs(mode.Ft).sum(axis=0).max())
    rho = float(np.max(np.abs(np.linalg.eigvals(mode.Ft))))
    assert mode.L == pytest.approx(switching.THETA / norm, rel=1e-15)
    assert 1.0 < rho * mode.L < switching.RHO          # the radius would allow a longer step
    assert mode.terms == switching.terms_for(switching.THETA) == 49

    run, mode = _mode(sewing.build(SCENES["sewing"].values()))
    lam = np.linalg.eigvals(mode.Ft)
    assert mode.K > 0                                   # a stiff mode
    assert float(np.max(np.abs(lam))) * mode.L == pytest.approx(switching.RHO, rel=1e-9)
    assert mode.terms == switching.terms_for(float(np.abs(mode.Ft).sum(axis=0).max()) * mode.L)


def test_terms_meet_the_truncation_bound_and_no_more():
    bound = 4.0 ** switching.TERMS / math.factorial(switching.TERMS)
    for theta in (0.5, 4.0, 5.0, 8.0, 12.0):
        T = switching.terms_for(theta)
        assert theta ** T / math.factorial(T) <= bound or theta <= 4.0
        if theta > 4.0:
            assert theta ** (T - 1) / math.factorial(T - 1) > bound
    assert switching.terms_for(2.0) == switching.TERMS


def test_power_radius_of_a_sparse_chain_and_of_a_rotation():
    from scipy import sparse

    net = roller_table.build(params(rollers=12.0))
    t = np.linspace(0.0, 1.0, 11)
    run = switching.Run(net, t, np.zeros(net.size), 100)
    F = SparseParts(net, run.S).scipy_matrix(run.start_taut, 0.5)
    exact = float(np.max(np.abs(np.linalg.eigvals(F.toarray()))))
    assert switching.power_radius(F) == pytest.approx(exact, rel=0.01)
    # a dominant complex pair of modulus 3 (the growth oscillates) above a real 2.9
    B = np.zeros((5, 5))
    B[:2, :2] = [[0.0, -3.0], [3.0, 0.0]]
    B[2, 2], B[3, 3], B[4, 4] = 2.9, -1.0, 0.5
    Q = np.linalg.qr(np.random.default_rng(1).standard_normal((5, 5)))[0]
    assert switching.power_radius(sparse.csr_matrix(Q @ B @ Q.T)) == pytest.approx(3.0, rel=0.01)
    assert switching.power_radius(sparse.csr_matrix(np.triu(np.ones((4, 4)), 1))) == 0.0   # nilpotent


def _random_polynomials(rng, count, T=49):
    """Taylor-like step polynomials: c_j ~ theta^j / j!, random signs and sizes, some starting
    exactly on the surface (c_0 = 0) with their first few coefficients 0 (a strand at rest)."""
    j = np.arange(T)
    size = 2.0 ** j / np.array([float(math.factorial(int(k))) for k in j])
    C = rng.standard_normal((count, T)) * size * 10.0 ** rng.integers(-6, 2, (count, 1))
    rest = rng.random(count) < 0.3
    C[rest, :rng.integers(1, 5)] = 0.0
    C[rng.random(count) < 0.2, 0] *= 1e-14                 # within rounding of the surface
    return C


def test_the_bernstein_hull_rules_out_only_what_first_fire_refuses():
    rng = np.random.default_rng(11)
    C = _random_polynomials(rng, 600)
    d = rng.choice([-1.0, 1.0], size=len(C))
    tol = 1024 * switching.EPS * np.abs(C).sum(axis=1) * rng.choice([1.0, 1e-290], size=len(C))
    may = may_fire((C * d[:, None]).T[:, None, :], tol[None, :])[0]
    ruled_out = 0
    for k in range(len(C)):
        if may[k]:
            continue
        ruled_out += 1
        for from_start in (False, True):
            for limit in (1.0, 0.4):
                assert first_fire(C[k], d[k], float(tol[k]), from_start, limit) is None, k
    assert ruled_out > 100                                 # it does rule out (the test can fail)


def test_stays_down_rules_out_only_what_first_fire_refuses():
    # the orbit's test in front of first_fire (a polynomial that stays below -tol, or starts
    # within tol and falls all the way, cannot fire): on Taylor-like polynomials and on ones
    # leaving their surface downwards (a strand just decided slack), whatever it rules out
    # first_fire refuses too, from a restart or not, over the whole step or part of it
    rng = np.random.default_rng(17)
    C = _random_polynomials(rng, 600)
    leaving = _random_polynomials(rng, 300)
    leaving[:, 0] = rng.choice([0.0, 1e-17, -1e-17], size=300)
    leaving[:, 1] = -np.abs(leaving[:, 1]) - 1e-3                  # falling from the surface
    C = np.vstack([C, leaving])
    d = rng.choice([-1.0, 1.0], size=len(C))
    tol = 1024 * switching.EPS * np.abs(C).sum(axis=1)
    pc = C * d[:, None]
    down = stays_down(pc, tol)
    for k in np.flatnonzero(down):
        for from_start in (False, True):
            for limit in (1.0, 0.4):
                assert first_fire(C[k], d[k], float(tol[k]), from_start, limit) is None, k
    assert down[:600].sum() > 50 and down[600:].sum() > 50       # it does rule out (the test can fail)
