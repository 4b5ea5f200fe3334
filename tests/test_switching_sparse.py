"""The sparse path of the switching core (large networks) against the dense one.

Both propagate the same exact solution: the dense path by ``expm`` of the bottom step and
its doubling orbit, the sparse path by the Taylor sum of sparse products step by step,
with F~ assembled from the strands' stamps. They share no propagator, so agreement of the
switch sequences and of the trajectories checks the sparse assembly and stepping. The
sparse path's own shortcuts are checked against what they replace: the assembly of a
pattern against the dense matrix, the truncated Taylor sums against the full series, the
re-based rotations' integral against its sum written out.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim import switching
from beltcalc.sim.switching import run as run_module, sparse as sparse_module
from beltcalc.sim.propagate import augmented_matrix, orbit
from beltcalc.sim.network import Inertia, Load, Network, Strand
from beltcalc.sim.scenes import roller_table
from test_switching_reference import bounce_sequence, bouncing_net, params


@pytest.mark.parametrize("over", [{}, {"rollers": 5.0, "pretension": 0.0}])
def test_stamps_rebuild_every_strand_pattern(over):
    # [A | B] of a pattern = the all-slack one + the taut strands' stamps, for random patterns
    net = roller_table.build(params(**over))
    owner, rows, cols, vals = net.strand_stamps()
    ns = len(net.strands)
    rng = np.random.default_rng(7)
    base = augmented_matrix(net, (False,) * ns, 4.0)
    for _ in range(6):
        taut = tuple(bool(b) for b in rng.integers(0, 2, ns))
        built = base.copy()
        sel = np.asarray(taut)[owner]
        np.add.at(built, (rows[sel], cols[sel]), vals[sel])
        want = augmented_matrix(net, taut, 4.0)
        assert_allclose(built, want, rtol=0, atol=4e-16 * np.abs(want).max())


def run(net, t, x0, sparse):
    old = run_module.SPARSE_SIZE
    run_module.SPARSE_SIZE = 1 if sparse else 10**9
    try:
        r = switching.Run(net, t, x0, 100_000).run()
    finally:
        run_module.SPARSE_SIZE = old
    return r


@pytest.mark.parametrize("over", [{"pretension": 0.0, "t_end": 1.0},
                                  {"load_amplitude": 70.0, "load_frequency": 50.0, "t_end": 3.6}])
def test_sparse_path_matches_dense_on_the_roller_table(over):
    # zero pretension (the start-up's six switches; later ones inherit the case's genuine
    # sensitivity, docs/switching.md), and a pulsating load (dozens of switches): same switch
    # sequence to 1e-9 s, same speeds to 1e-8 of their scale (measured 3e-9: the two
    # propagators' rounding, carried through the switches)
    p = params(**over)
    net = roller_table.build(p)
    t = np.linspace(0.0, p["t_end"], 801)
    x0 = np.zeros(net.size)
    dense, sparse = run(net, t, x0, False), run(net, t, x0, True)
    assert sparse.cache.parts is not None and dense.cache.parts is None
    assert len(dense.switches) >= 4
    assert [(k, on) for _, k, on in sparse.switches] == [(k, on) for _, k, on in dense.switches]
    assert_allclose([s[0] for s in sparse.switches], [s[0] for s in dense.switches], rtol=0, atol=1e-9)
    n = net.n
    scale = np.abs(dense.out[n:2 * n]).max()
    assert_allclose(sparse.out[n:2 * n], dense.out[n:2 * n], rtol=0, atol=1e-8 * scale)


def test_a_dense_run_of_many_modes_starts_again_sparse(monkeypatch):
    # piecewise_exact gives up the dense path once its modes cost more than DENSE_WORK
    # (counted in modes x states^3, never in time) and runs again sparse: the pulsating load's
    # switches with the limits lowered so that this small table crosses them. Same switches
    # and speeds as the dense run (the sparse path's agreement above); a network below
    # SPARSE_FROM states never switches
    p = params(load_amplitude=70.0, load_frequency=50.0, t_end=3.6)
    net = roller_table.build(p)
    t = np.linspace(0.0, p["t_end"], 801)
    x0 = np.zeros(net.size)
    dense = run(net, t, x0, False)
    size = net.size + len(net.generators(0.0))
    monkeypatch.setattr(run_module, "SPARSE_FROM", size)
    monkeypatch.setattr(run_module, "DENSE_WORK", 3.0 * size ** 3)
    out, _, info = switching.piecewise_exact(net, t, x0, 100_000)
    assert info["path"] == "sparse (after 4 dense modes)"
    assert [(k, on) for _, k, on in info["switches"]] == [(net.strands[k].name, on) for _, k, on in dense.switches]
    n = net.n
    scale = np.abs(dense.out[n:2 * n]).max()
    assert_allclose(out[n:2 * n], dense.out[n:2 * n], rtol=0, atol=1e-8 * scale)
    monkeypatch.setattr(run_module, "SPARSE_FROM", size + 1)
    assert switching.piecewise_exact(net, t, x0, 100_000)[2]["path"] == "dense"


def test_sparse_path_bounces_like_the_closed_form():
    # the bouncing contact (tests/test_switching_reference.py) on the sparse path
    seq = bounce_sequence()
    net, x0 = bouncing_net()
    r = run(net, np.linspace(0.0, 1.0, 201), x0, True)
    assert [on for _, _, on in r.switches] == [on for _, on in seq["switches"]]
    assert_allclose([s[0] for s in r.switches], [s for s, _ in seq["switches"]], rtol=0, atol=1e-9)


def test_sparse_path_without_strand_events_in_a_mode():
    # a network whose strand never takes up in the run: no switch, the free flight exact
    net = Network([Inertia("m", 1.0, translation=True)],
                  [Load("m", mean=1.0), Strand("s", "m", None, 1.0, 1.0, 1e4, 1.0, 0.0)])
    t = np.linspace(0.0, 1.0, 11)
    r = run(net, t, np.array([-0.1, 0.0]), True)
    assert r.switches == []
    assert_allclose(r.out[0], -0.1 - 0.5 * t * t, rtol=1e-13, atol=1e-15)


def test_dense_reach_bound_never_misses_a_step_the_exact_polynomial_flags():
    # Mode.near (the cheap bound) must flag every (event, step) whose exact polynomial can reach
    # zero: states from a pulsating run (taut and slack patterns), every event of the mode, each
    # the start of consecutive bottom steps (the rows near() is given in a block: its
    # second-order part is shared by NEAR_GROUP of them)
    p = params(load_amplitude=70.0, load_frequency=50.0, t_end=3.4)
    net = roller_table.build(p)
    t = np.linspace(0.0, 3.4, 3401)
    r = run(net, t, np.zeros(net.size), False)
    assert len(r.switches) >= 10
    z_all = np.vstack([r.out, net.generators(t)]).T / r.S[None, :]
    checked = 0
    for mode in list(r.cache.modes.values()):
        P = mode.P(mode.K)
        Z = np.vstack([orbit(P, z, 2 * switching.NEAR_GROUP) for z in z_all[::7]])
        tol = switching.ROUND * (mode.absH @ np.abs(Z).T) + 1e-300
        C = mode.coeffs(Z)
        reach = np.abs(C[1:]).sum(axis=0)
        exact = (np.abs(C[0]) <= reach + tol) & (reach + np.abs(C[0]) > tol)
        flagged = mode.near(Z)
        assert not np.any(exact & ~flagged)
        checked += int(exact.sum())
    assert checked > 0


def test_auto_does_not_start_a_radau_fallback_it_cannot_finish(monkeypatch):
    # the fallback is skipped above RADAU_FALLBACK_WORK (strand events x states^2) and the
    # one-line failure says so; here forced on the 3-roller table without pretension
    from beltcalc.errors import SimulationError
    from beltcalc.sim import core

    monkeypatch.setattr(core, "RADAU_FALLBACK_WORK", 0.0)
    net = roller_table.build(params(pretension=0.0))
    with pytest.raises(SimulationError) as err:
        core.simulate(net, 1.0, 201, core.SolverConfig("auto", error_tol=1e-15))
    text = str(err.value)
    assert "\n" not in text and "not radau (" in text and "too long" in text


def test_sampled_derivative_by_stamps_equals_the_per_pattern_matrices():
    # Network.derivative assembles taut strands by their stamps; against A(pattern) x + B g
    # sample by sample (zero pretension: many patterns). Both cancel stiffness terms of ~1e11
    # (angles of hundreds of radians), so they agree to rounding of that size, not of x'
    from beltcalc.sim.core import SolverConfig, simulate

    p = params(pretension=0.0, rollers=5.0)
    net = roller_table.build(p)
    r = simulate(net, 6.0, 1201, SolverConfig("exact", estimate_error=False))
    x, t = r.states, r.t
    taut = net.taut_of(x, t)
    assert len({tuple(c) for c in taut.T}) >= 5
    starts = net.segment_starts(6.0)
    ref = np.empty_like(x)
    for j in range(x.shape[1]):
        seg = int(np.searchsorted(starts, t[j], side="right") - 1)
        A, B = net.first_order(tuple(taut[:, j]), net.piece_time(seg, starts, 6.0))
        ref[:, j] = A @ x[:, j] + B @ net.generators(t[j])
    size = np.abs(net.state_matrix()).max() * np.abs(x).max()
    assert_allclose(net.derivative(t, x), ref, rtol=0, atol=1e-14 * size)


def test_sparse_path_without_scipys_private_kernel(monkeypatch):
    # the CSR kernels are scipy's private csr_matvec(s); without them the public product runs, same result
    seq = bounce_sequence()
    net, x0 = bouncing_net()
    monkeypatch.setattr(sparse_module, "_kernels", None)
    r = run(net, np.linspace(0.0, 1.0, 201), x0, True)
    assert_allclose([s[0] for s in r.switches], [s for s, _ in seq["switches"]], rtol=0, atol=1e-9)


def _sparse_run(net, t):
    old = run_module.SPARSE_SIZE
    run_module.SPARSE_SIZE = 1
    try:
        return switching.Run(net, t, np.zeros(net.size), 100_000)
    finally:
        run_module.SPARSE_SIZE = old


def test_sparse_assembly_is_the_dense_matrix_of_every_pattern():
    # the places of every entry any pattern can have, filled by one weighted count per pattern
    # (slack strands' stamps weighted 0): the balanced augmented matrix and its 1-norm, against
    # the dense assembly of each pattern (random patterns, several time pieces of a pulsating load)
    p = params(rollers=5.0, load_amplitude=70.0, load_frequency=50.0)
    net = roller_table.build(p)
    run = _sparse_run(net, np.linspace(0.0, 3.0, 31))
    parts = run.cache.parts
    rng = np.random.default_rng(3)
    ns = len(net.strands)
    for t_mid in (0.5, 3.5):
        for _ in range(5):
            taut = tuple(bool(b) for b in rng.integers(0, 2, ns))
            (indptr, indices, data), norm = parts.matrix(taut, t_mid)
            got = parts.scipy_matrix(taut, t_mid).toarray()
            want = augmented_matrix(net, taut, t_mid) / run.S[:, None] * run.S[None, :]
            scale = np.abs(want).max()
            assert_allclose(got, want, rtol=0, atol=1e-15 * scale)
            assert norm == pytest.approx(float(np.abs(want).sum(axis=0).max()), rel=1e-14)
    # each event's firing direction and strand as Network.events gives them, in the fixed order
    taut = tuple(bool(b) for b in rng.integers(0, 2, ns))
    mode = run.cache.get(taut, 0, 0.5)
    events = net.events(taut)
    mine = sorted(zip(mode.event_strand.tolist(), [e.kind for e in mode.events], mode.dirs.tolist()))
    assert mine == sorted((e.strand, e.kind, float(e.direction)) for e in events)


def test_sparse_orbit_truncated_terms_and_kept_terms():
    # the orbit sums each step's Taylor series until its tail bound is TAIL of |z|_1 (not the
    # norm's worst-case count of terms): the states agree with the full series to rounding, and
    # the terms it keeps for the watch are the step points' own Taylor terms
    p = params(rollers=5.0, load_amplitude=70.0, load_frequency=50.0)
    net = roller_table.build(p)
    run = _sparse_run(net, np.linspace(0.0, 1.0, 11)).run()
    z = np.concatenate([run.out[:, -1], net.generators(1.0)]) / run.S
    mode = run.cache.get(run.end_taut, 0, 0.5)
    keep = np.empty((40, mode.terms, z.size))
    Z, _, J = mode.orbit(z, 40, integrate=True, keep=keep)
    V = mode.kept(Z[0]).copy()                  # the block's terms (the next orbit drops them)
    assert V.shape[0] == 40
    old = sparse_module.TAIL
    sparse_module.TAIL = 0.0
    try:
        mode._used = mode.terms
        Zf, _, Jf = mode.orbit(z, 40, integrate=True)
    finally:
        sparse_module.TAIL = old
    assert mode._used == mode.terms                           # the full series: every term
    size = np.abs(Zf).sum(axis=1, keepdims=True)
    assert_allclose(Z, Zf, rtol=0, atol=1e-13 * size.max())
    assert_allclose(J, Jf, rtol=0, atol=1e-13 * np.abs(Jf).max())
    taylor = mode.taylor(Z[:-1]).transpose(1, 0, 2)
    assert_allclose(V, taylor, rtol=0, atol=1e-15 * size.max())
    assert np.count_nonzero(np.abs(V).sum(axis=(0, 2))) < mode.terms   # it did stop early


def test_rigid_integrals_sample_by_sample_equal_the_sum_over_rebases():
    # the integral of the rotations taken out, sum_k d_k (t - t_k)+, formed in O(rebases +
    # samples) (a switching run re-bases at every block), against the sum written out
    p = params(rollers=3.0)
    net = roller_table.build(p)
    t = np.linspace(0.0, 2.0, 201)
    run = switching.Run(net, t, np.zeros(net.size), 100_000, integrate=True)
    rng = np.random.default_rng(5)
    tk = np.sort(np.concatenate([rng.uniform(0.0, 2.0, 300), t[[0, 7, 200]]]))
    run.rebases = [(float(a), rng.normal(size=run.rigid.shape[0]) * 6.0) for a in tk]
    run.integrals = np.zeros((net.n, t.size))
    dk = np.array([d for _, d in run.rebases])
    want = dk.T @ np.maximum(t[None, :] - tk[:, None], 0.0)
    assert_allclose(run.rigid_integrals(), want, rtol=1e-13, atol=1e-13 * np.abs(want).max())


def test_scipys_private_kernels_are_checked_before_use():
    # scipy's csr_matvec(s) are used only if they accumulate what the public product gives:
    # a kernel that ignores its output, or takes other arguments, is refused
    from scipy.sparse._sparsetools import csr_matvec, csr_matvecs

    assert sparse_module._kernels_agree(csr_matvec, csr_matvecs) is True
    assert sparse_module._kernels_agree(lambda *a: None, csr_matvecs) is False

    def other_signature(*args):
        raise TypeError("csr_matvec() takes 6 arguments")
    assert sparse_module._kernels_agree(csr_matvec, other_signature) is False
