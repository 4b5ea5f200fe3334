"""Energy balance of the sewing scene, integrated exactly.

The work of the motor minus the work of the loads must equal the change of kinetic plus
potential energy plus the energy dissipated in the couplings. Every power here is a
quadratic form of the augmented state z = [x, g] (z' = F z), so its integral over one
output step is z_k^T W z_k with W = integral_0^dt e^(F^T s) S e^(F s) ds, computed exactly
(Van Loan 1978, on a sub-step small enough that e^(-F^T h) does not overflow, then doubled:
W(2h) = W(h) + e^(F^T h) W(h) e^(F h)). No quadrature error enters the balance.
"""

import numpy as np
import pytest
from scipy.linalg import expm

from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.propagate import augmented_matrix
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.scenes.sewing import build


def step_gramian(F, S, dt, halvings=8):
    p = F.shape[0]
    h = dt / 2 ** halvings
    E = expm(np.block([[-F.T, S], [np.zeros((p, p)), F]]) * h)
    phi = E[p:, p:]
    W = phi.T @ E[:p, p:]
    for _ in range(halvings):
        W = W + phi.T @ W @ phi
        phi = phi @ phi
    return W


def sym(p, i, j, value):
    S = np.zeros((p, p))
    S[i, j] += value / 2
    S[j, i] += value / 2
    return S


def test_energy_balance_sewing_exact():
    values = SCENES["sewing"].values()
    net = build(values)
    t_end, samples = 0.5, 5001
    r = simulate(net, t_end, samples, SolverConfig("exact", estimate_error=False))
    F = augmented_matrix(net)
    p, n, m = F.shape[0], net.n, net.size
    x = r.states
    z = np.vstack([x, net.generators(r.t)])
    g0, s1, c1 = m, m + 1, m + 2
    w = net.frequencies()[0]
    # motor power M * omega_1
    S_motor = sym(p, 2 * n, n + net.index["1"], 1.0)
    # load power (mean g0 + amp sin(w t)) * omega_k, sin(w t) = s1 (phase 0)
    S_load = np.zeros((p, p))
    for ld in net.loads:
        assert ld.omega == pytest.approx(w) and ld.phase == 0.0
        k = n + net.index[ld.node]
        S_load += sym(p, g0, k, ld.mean) + sym(p, s1, k, ld.amplitude)
    # dissipation omega^T D omega
    S_diss = np.zeros((p, p))
    S_diss[n:2 * n, n:2 * n] = net.D
    dt = r.t[1] - r.t[0]
    work = {}
    for name, S in (("motor", S_motor), ("load", S_load), ("diss", S_diss)):
        W = step_gramian(F, S, dt)
        work[name] = float(np.einsum("ik,ij,jk->", z[:, :-1], W, z[:, :-1]))
    kin, pot = net.energy(x[:, [0, -1]])
    stored = (kin[1] + pot[1]) - (kin[0] + pot[0])
    assert c1 == s1 + 1
    # work in = stored + dissipated + work against the loads, to 1e-8 of the motor's work
    assert work["motor"] - work["load"] - work["diss"] == pytest.approx(stored, abs=1e-8 * work["motor"])
    # the balance is not trivial: every term is a real share of the motor's work
    for part in (stored, work["load"], work["diss"]):
        assert part > 1e-3 * work["motor"]


def test_gramian_against_quadrature_on_a_slow_system():
    # a slow 2x2 rotation: the exact Gramian matches a fine trapezoid rule
    F = np.array([[0.0, 1.0], [-4.0, -0.1]])
    S = np.array([[1.0, 0.2], [0.2, 0.5]])
    dt = 0.3
    ts = np.linspace(0, dt, 20001)
    vals = np.array([expm(F.T * t) @ S @ expm(F * t) for t in ts])
    np.testing.assert_allclose(step_gramian(F, S, dt), np.trapezoid(vals, ts, axis=0), rtol=1e-7)
