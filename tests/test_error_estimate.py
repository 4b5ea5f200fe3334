"""The exact method's error estimate against 40-digit mpmath references (tests/mpref.py).

The true error of a speed signal is max over the run of |beltcalc - reference|; the estimate
(``r.errors[name]``, same unit) must never understate it by more than 10x. Cases: the sewing
scene as printed, with C3 raised 1e6-fold (2.6e8 N m/rad: badly conditioned), and with an
undamped first coupling (d1 = 0), at t_end 1 s and 10001 samples (the scene's own grid; each
reference costs about 1.5 s); the stiff one also at 2001 samples. Run with ``-s`` to see the
estimate/true ratios.
"""

import functools
import math

import mpmath
import numpy as np
import pytest

from beltcalc.errors import SimulationError
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.network import Coupling, Inertia, Network
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.scenes.sewing import build

from mpref import max_difference, reference_mp, to_array

T_END, SAMPLES = 1.0, 10001
# label -> (parameter overrides, samples). The stiff case at 2001 samples (dt = 0.5 ms) has a
# true error 30x larger than at 10001 and the estimate of the pre-rewrite core is 2.8x below it.
CASES = {"normal": ({}, SAMPLES), "stiff": ({"C3": 2.6e8}, SAMPLES), "undamped": ({"d1": 0.0}, SAMPLES),
         "stiff_2001": ({"C3": 2.6e8}, 2001)}
CFG = SolverConfig(method="exact", error_tol=1e-6, accept_error=False, estimate_error=True)


def sewing_params(**over):
    return SCENES["sewing"].values(**over)


def speed_rows(net):
    names = net.state_names()
    return [(k, names[k][0]) for k in range(net.n, 2 * net.n)]


@functools.cache
def sewing_case(label):
    """(label, network, samples, 40-digit reference as mpf, the same as floats), computed once."""
    over, samples = CASES[label]
    net = build(sewing_params(**over))
    ref_mp = reference_mp(net, T_END, samples, digits=40)
    return label, net, samples, ref_mp, to_array(ref_mp)


@pytest.fixture(params=list(CASES))
def case(request):
    return sewing_case(request.param)


# --- the reference itself (these pass against any core) ----------------------------------------
def test_mpref_free_oscillation_closed_form():
    # J phi'' + C phi = 0, C/J = 16 exactly: phi = phi0 cos 4t, omega = -4 phi0 sin 4t
    net = Network([Inertia("1", 0.5)], [Coupling("g", "1", None, 8.0, 0.0)])
    ref = reference_mp(net, 2.0, 201, digits=40, x0=[0.25, 0.0])
    with mpmath.workdps(40):
        worst = max(max(abs(z[0] - mpmath.mpf(0.25) * mpmath.cos(4 * mpmath.mpf(2) * k / 200)),
                        abs(z[1] + mpmath.mpf(0.25) * 4 * mpmath.sin(4 * mpmath.mpf(2) * k / 200)))
                    for k, z in enumerate(ref))
    assert float(worst) == pytest.approx(0.0, abs=1e-35)


def test_mpref_40_digits_agree_with_60(case):
    # relative to each unit's largest value over the run; the stiff case loses about 8 digits
    # in expm's squarings and still agrees to ~1e-32
    label, net, samples, ref40, ref = case
    ref60 = reference_mp(net, T_END, samples, digits=60)
    diff = max_difference(ref40, ref60, range(net.size))
    units = [u for _, u in net.state_names()]
    for k, d in enumerate(diff):
        scale = max(np.abs(ref[j]).max() for j in range(net.size) if units[j] == units[k])
        assert d <= 1e-30 * scale, (label, net.state_names()[k], float(d), scale)


def test_mpref_matches_exact_on_the_printed_scene():
    # the documented level of the exact method on the sewing scene: 1e-8 of the speed scale
    # (measured today: 4e-12)
    _, net, _, _, ref = sewing_case("normal")
    r = simulate(net, T_END, SAMPLES, SolverConfig(method="exact", estimate_error=False))
    rows = [k for k, _ in speed_rows(net)]
    scale = np.abs(ref[rows]).max()
    assert scale == pytest.approx(432.57, rel=1e-4)
    assert np.abs(r.states[rows] - ref[rows]).max() <= 1e-8 * scale
    assert np.abs(r.states - ref).max() <= 1e-8 * np.abs(ref).max()


# --- the estimate ---------------------------------------------------------------------------------
def test_estimate_never_understates_more_than_10x(case):
    label, net, samples, _, ref = case
    r = simulate(net, T_END, samples, CFG)
    rows = speed_rows(net)
    scale = max(np.abs(ref[k]).max() for k, _ in rows)
    print(f"\n{label} ({samples} samples): speed scale {scale:.6g} rad/s; estimate {r.error_estimate:.3g} {r.error_unit} "
          f"on {r.error_signal} ({r.error_relative:.3g} relative); reference: {r.error_reference}")
    low = []
    for k, name in rows:
        true = float(np.abs(r.states[k] - ref[k]).max())
        est = r.errors[name]
        print(f"  {name}: true {true:.3g} rad/s ({true / scale:.3g} rel), estimate {est:.3g}, "
              f"estimate/true {est / true if true else math.inf:.3g}")
        if not (math.isfinite(est) and est * 10 >= true):
            low.append((name, est, true))
    assert not low, f"{label}: the estimate understates more than 10x: {low}"


@pytest.mark.parametrize("label", list(CASES))
def test_estimate_fields(label):
    over, samples = CASES[label]
    net = build(sewing_params(**over))
    r = simulate(net, T_END, samples, CFG)
    rows = speed_rows(net)
    assert set(r.errors) == {name for _, name in rows}
    assert all(isinstance(v, float) and math.isfinite(v) and v > 0 for v in r.errors.values())
    assert r.error_estimate == pytest.approx(max(r.errors.values()), rel=1e-15)
    assert r.errors[r.error_signal] == r.error_estimate
    assert r.error_unit == "rad/s"
    scale = max(float(np.abs(r.states[k]).max()) for k, _ in rows)
    assert r.error_relative == pytest.approx(r.error_estimate / scale, rel=1e-9)
    assert isinstance(r.error_reference, str) and r.error_reference


def stiff():
    return build(sewing_params(**CASES["stiff"][0]))


def test_estimate_above_the_tolerance_fails_in_one_line():
    cfg = SolverConfig(method="exact", error_tol=1e-15, accept_error=False, estimate_error=True)
    with pytest.raises(SimulationError) as info:
        simulate(stiff(), T_END, SAMPLES, cfg)
    text = str(info.value)
    assert "error estimate" in text
    assert "\n" not in text.strip()


def test_estimate_above_the_tolerance_accepted():
    cfg = SolverConfig(method="exact", error_tol=1e-15, accept_error=True, estimate_error=True)
    r = simulate(stiff(), T_END, SAMPLES, cfg)
    assert r.extra.get("error_accepted") is True
    assert r.warnings and r.warnings[0].startswith("accepted with a large error: error estimate")
    assert r.error_relative >= 1e-15


def test_a_watched_second_computation_beside_the_run_gives_the_same_estimate(monkeypatch):
    # from CONCURRENT_SIZE states the estimate's second watched run is forked beside the first:
    # the same computation in another process, so every error and figure is the same, bit for bit
    from beltcalc.sim import core
    from beltcalc.sim.scenes import roller_table

    values = SCENES["roller-table"].values(t_end=1.0, samples=201.0, load_start=0.3, window=0.6)
    monkeypatch.setattr(core, "CONCURRENT_SIZE", 10**9)          # in this process
    here = roller_table.run(values, SolverConfig()).result
    monkeypatch.setattr(core, "CONCURRENT_SIZE", 0)              # forked where it can be
    forked = roller_table.run(values, SolverConfig()).result
    assert here.errors and forked.errors == here.errors
    assert forked.error_signal == here.error_signal
    assert forked.error_estimate == pytest.approx(here.error_estimate, rel=0, abs=0)


def test_the_forked_computation_falls_back_and_can_be_stopped():
    import time

    from beltcalc.sim.core import _beside

    assert _beside(lambda: {"value": 42})() == {"value": 42}
    calls = []

    def fails():
        calls.append(1)          # in the child (not seen here), then here again
        raise ValueError("the second computation failed")
    with pytest.raises(ValueError, match="second computation failed"):
        _beside(fails)()
    assert calls == [1]
    slow = _beside(lambda: time.sleep(60))
    start = time.monotonic()
    getattr(slow, "cancel", lambda: None)()
    assert time.monotonic() - start == pytest.approx(0.0, abs=10.0)
