"""beltcalc.numerics.expm.expm against scipy.linalg.expm and exact answers, and
beltcalc.numerics.balance.balance against LAPACK's dgebal.

The tolerance is relative in the 1-norm, 1e-13 max(1, ||A||_1): two backward-stable
evaluations differ by about cond_exp(A) u, and cond_exp(A) >= ||A|| (Higham, *Functions of
Matrices*, 2008, Lemma 10.15), so the norm factor is the least a fair comparison allows.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numpy.testing import assert_allclose, assert_array_equal
from scipy.linalg._matfuncs_expm import pick_pade_structure

from beltcalc.numerics.expm import expm
from beltcalc.numerics.expm_degree import degree_and_scaling

NORMS = (1e-8, 1e-5, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0, 2.0, 3.0, 10.0, 100.0, 1e3)


def _rel1(E: np.ndarray, S: np.ndarray) -> float:
    return float(np.abs(E - S).sum(axis=-2).max() / np.abs(S).sum(axis=-2).max())


def _close_to_scipy(A: np.ndarray) -> None:
    S = scipy.linalg.expm(A)
    tol = 1e-13 * max(1.0, float(np.abs(A).sum(axis=-2).max()))
    assert _rel1(expm(A), S) == pytest.approx(0.0, abs=tol)


def _random(rng, n: int, norm: float) -> np.ndarray:
    A = rng.standard_normal((n, n))
    return A * (norm / np.abs(A).sum(axis=0).max())


def test_random_sizes_and_norms_match_scipy_and_hit_every_degree():
    rng = np.random.default_rng(20261123)
    seen = set()
    for n in range(1, 41):
        for norm in NORMS:
            A = _random(rng, n, norm)
            if norm >= 100.0:           # e^A overflows for some random A of norm 1e3: skip those
                if not np.isfinite(scipy.linalg.expm(A)).all():
                    continue
            _close_to_scipy(A)
            if n > 1:
                work = np.zeros((5, n, n))
                work[0] = A
                m_ref, s_ref = pick_pade_structure(work)
                m, s, _ = degree_and_scaling(A[None], np.empty((1, 5, n, n)))
                assert (int(m[0]), int(s[0])) == (m_ref, s_ref)
                seen.add(int(m[0]))
    assert seen == {3, 5, 7, 9, 13}


def test_zero_and_empty_and_scalar():
    assert_array_equal(expm(np.zeros((4, 4))), np.eye(4))
    assert expm(np.zeros((0, 0))).shape == (0, 0)
    assert expm(np.zeros((3, 0, 0))).shape == (3, 0, 0)
    assert_allclose(expm(np.array([[0.7]])), [[np.exp(0.7)]], rtol=1e-15)


def test_nilpotent_exact():
    N = np.array([[0.0, 1.0, 2.0], [0.0, 0.0, 3.0], [0.0, 0.0, 0.0]])
    exact = np.eye(3) + N + N @ N / 2.0
    assert_allclose(expm(N), exact, rtol=1e-15, atol=0)
    P = np.array([[1.0, -1.0], [1.0, -1.0]])  # P^2 = 0, full (not triangular)
    assert_array_equal(P @ P, np.zeros((2, 2)))
    assert_allclose(expm(P), np.eye(2) + P, rtol=0, atol=1e-15)


@pytest.mark.parametrize("w", [1e-6, 0.3, 2.0, 40.0, 1e3])
def test_rotation_generator(w):
    c, s = np.cos(w), np.sin(w)
    assert_allclose(expm(np.array([[0.0, -w], [w, 0.0]])), [[c, -s], [s, c]], rtol=0,
                    atol=1e-15 * max(1.0, w))


def test_diagonal_and_triangular():
    d = np.array([-3.0, 0.0, 1e-9, 2.5, 7.0])
    assert_allclose(expm(np.diag(d)), np.diag(np.exp(d)), rtol=1e-15)
    rng = np.random.default_rng(3)
    for norm in (0.01, 1.0, 50.0):
        T = np.triu(_random(rng, 6, norm))
        _close_to_scipy(T)
        _close_to_scipy(T.T.copy())
        assert_array_equal(np.tril(expm(T), -1), 0.0)


def test_badly_scaled_and_non_normal():
    rng = np.random.default_rng(5)
    for _ in range(5):
        D = np.diag(10.0 ** rng.uniform(-4, 4, 8))
        A = np.linalg.solve(D, _random(rng, 8, 2.0)) @ D
        _close_to_scipy(A)
    J = np.diag(np.full(9, -1.0)) + np.diag(np.full(8, 30.0), 1)   # strongly non-normal
    _close_to_scipy(J)
    _close_to_scipy(J + 1e-3 * rng.standard_normal((9, 9)))


def test_stack_mixed_norms_equals_entries():
    rng = np.random.default_rng(7)
    A = np.stack([_random(rng, 7, norm) for norm in NORMS[:-1]]
                 + [np.zeros((7, 7)), np.diag(np.arange(7.0)), np.triu(_random(rng, 7, 20.0))])
    E = expm(A)
    for k in range(A.shape[0]):
        assert_allclose(E[k], expm(A[k]), rtol=1e-14, atol=1e-14 * np.abs(E[k]).max())
        _close_to_scipy(A[k])
    assert expm(A.reshape(3, 5, 7, 7)).shape == (3, 5, 7, 7)


def test_project_matrices():
    for name, F in _project_matrices().items():
        A = F * 1e-4
        _close_to_scipy(A)
        stack = np.stack([A * f for f in (1e-3, 0.1, 1.0, 3.0)])
        assert _rel1(expm(stack), scipy.linalg.expm(stack)) == pytest.approx(
            0.0, abs=1e-13 * 3.0 * np.abs(A).sum(axis=0).max()), name


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_refuses_non_finite(bad):
    A = np.eye(3)
    A[1, 2] = bad
    with pytest.raises(ValueError):
        expm(A)


def test_refuses_non_square():
    with pytest.raises(ValueError):
        expm(np.zeros((2, 3)))
    with pytest.raises(ValueError):
        expm(np.zeros(3))


def test_import_does_not_load_scipy():
    code = "import sys, beltcalc.numerics.expm, beltcalc.numerics.balance; print(any(m.split('.')[0] == 'scipy' for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@settings(max_examples=30, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 6), st.integers(1, 6)).map(lambda t: (t[0], t[0])),
              elements=st.floats(-2.0, 2.0, allow_nan=False, width=64)))
def test_inverse_property(A):
    n = A.shape[0]
    assert_allclose(expm(A) @ expm(-A), np.eye(n), rtol=0,
                    atol=1e-12 * max(1.0, float(np.abs(A).sum(axis=0).max())) ** 2)


# --- balance: LAPACK dgebal (job 'S') ------------------------------------------------------------

def _project_matrices():
    from beltcalc.sim.propagate import augmented_matrix
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes.drive import drive_scene

    out = {}
    for name, scene in SCENES.items():
        out[name] = augmented_matrix(scene.build(dict(scene.values())))
    conveyor = drive_scene("conveyor")
    out["conveyor"] = augmented_matrix(conveyor.build(conveyor.values()))
    return out


def _dgebal(F: np.ndarray) -> np.ndarray:
    from scipy.linalg.lapack import dgebal

    return dgebal(F, scale=1, permute=0)[3]


@pytest.mark.parametrize("name", ["sewing", "roller-table", "linear-axis", "conveyor"])
def test_balance_equals_lapack_on_the_project_matrices(name):
    from beltcalc.numerics.balance import balance

    F = _project_matrices()[name]
    assert_array_equal(balance(F), _dgebal(F))


@pytest.mark.parametrize("seed", range(40))
def test_balance_equals_lapack_on_badly_scaled_matrices(seed):
    from beltcalc.numerics.balance import balance

    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 30))
    A = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-6, 6, (n, 1)) * 10.0 ** rng.uniform(-6, 6, (1, n))
    A[rng.random((n, n)) < 0.3] = 0.0                       # sparse, as the drives' matrices are
    d = balance(A)
    assert_array_equal(d, _dgebal(A))
    assert_array_equal(np.log2(d), np.round(np.log2(d)))     # powers of two
    Ab = A / d[:, None] * d[None, :]
    assert_array_equal(Ab / d[None, :] * d[:, None], A)      # the similarity is exact


def test_balance_takes_stacks_and_refuses_non_finite():
    from beltcalc.numerics.balance import balance

    mats = list(_project_matrices().values())[:1] * 2
    rng = np.random.default_rng(7)
    mats.append(rng.standard_normal(mats[0].shape) * 10.0 ** rng.uniform(-4, 4, (mats[0].shape[0], 1)))
    stack = np.stack(mats)
    assert_array_equal(balance(stack), np.stack([_dgebal(m) for m in mats]))
    assert balance(np.zeros((0, 0))).shape == (0,)
    assert_array_equal(balance(np.zeros((3, 3))), np.ones(3))
    with pytest.raises(ValueError, match="non-finite"):
        balance(np.array([[1.0, np.nan], [0.0, 1.0]]))


def test_a_stack_is_balanced_as_each_matrix_alone():
    # from STACK_FROM matrices on, every matrix's row i at once (closed-form doubling loops):
    # the same scales as the one-matrix loop and as LAPACK, on mixed, sparse and extreme ones
    from beltcalc.numerics import balance as balancing

    rng = np.random.default_rng(3)
    mats = []
    for k in range(60):
        n = 9
        A = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-8, 8, (n, 1)) * 10.0 ** rng.uniform(-8, 8, (1, n))
        A[rng.random((n, n)) < 0.3] = 0.0
        mats.append(A)
    mats.append(np.diag([1e-300, 1.0, 1e300, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]) + 1e-200)   # near the guards
    mats.append(np.zeros((9, 9)))
    stack = np.stack(mats)
    assert stack.shape[0] >= balancing.STACK_FROM
    got = balancing.balance(stack)
    assert_array_equal(got[:-2], np.stack([balancing._balance_one(m.copy()) for m in mats[:-2]]))
    assert_array_equal(got, np.stack([_dgebal(m) for m in mats]))
    assert_array_equal(got[-2], balancing.balance(mats[-2]))          # the extreme one, alone


def test_expm_with_the_public_solve_where_numpys_private_gufunc_is_gone(monkeypatch):
    # expm uses numpy's private solve gufunc when it is where it was and solves as the public
    # np.linalg.solve; a numpy that moves or changes it gets the public function, same result
    from beltcalc.numerics import expm as expm_module

    rng = np.random.default_rng(7)
    A = _random(rng, 12, 30.0)
    fast = expm(A)
    monkeypatch.setattr(expm_module, "_solve", np.linalg.solve)
    assert_allclose(expm(A), fast, rtol=1e-13, atol=1e-13 * float(np.abs(fast).max()))


def test_private_solve_is_refused_when_it_answers_otherwise(monkeypatch):
    # a gufunc that no longer solves (here: returns its right-hand side) is not used
    import numpy.linalg._umath_linalg as um

    from beltcalc.numerics import expm as expm_module

    monkeypatch.setattr(um, "solve", lambda a, b: b, raising=False)
    assert expm_module._private_solve() is np.linalg.solve
