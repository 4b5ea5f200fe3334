"""The product path's hard cases (DESIGN.md sections 3.0 and 4; issue 26, item 8): the commands a
user types, ``beltcalc simulate ... --json`` (click's CliRunner on ``beltcalc.cli.main:cli``),
each against a reference that owes nothing to beltcalc's solvers, at a tolerance derived from
the run's own error estimate.

The tolerance. A run reports ``error_relative``: its largest estimated error relative to the
scale of the signal's unit (for a watched exact run, of the figures it reports: window means,
least and largest values, each relative to the largest |value| over the run of the watched
signals of its unit, core.py ``_figure_errors``; for a Radau run, of the speeds). So a figure
X of unit u is claimed to within ``error_relative x S_u``, S_u that scale, taken here from the
reference (or, where there is none, from the run's own CSV), and the same rule is applied to
every unit. Issue 26 asks that the estimate cover the true error of every figure the command
reports (DESIGN.md 3.0 allowed 10x; the rounding of a geared rotation's integral in a torque's
mean and a scipy run's torques judged by its speeds alone were 3.2x and 4.2x, both fixed), so
every comparison is

    |beltcalc - reference| <= error_relative x S_u + e_ref (+ the CSV's rounding),

e_ref the reference's own error (the difference of the reference at two tolerances). That one
inequality checks both the result and that its estimate covers the true error. ``pytest -s``
prints each comparison with its ratio (|diff| - e_ref - rounding) / (error_relative x S_u).

References (stored ones were made by ``python tests/reference/make_references.py``, which
imports nothing of beltcalc: scipy's ``solve_ivp(method="Radau")`` with the constant Jacobian
of each strand pattern, the equations assembled there from the drive's components, the
tension-only strands switched by terminal events written there; see its docstring):

1. roller table, 3 rollers: ``roller3.json/.npz`` (Radau, rtol 1e-11 and 1e-10, events),
   through the scene and through its drive file; 30 rollers sharing the load: ``roller30``
   (Radau on ``roller30.toml``, the drive the scene builds, 40 minutes to make). 50 rollers:
   structural checks that can fail
   (exit 0; roller means at 3001 and 12001 samples agree to 1e-6 of the speed; the motor's
   momentum balance over the window, inertias by hand; strand forces >= 0); 200 rollers: one
   shorter run, the same checks but the sample counts (``many_args``: the three rollers' load
   shared by all).
2. zero pretension (``roller0``, 263 switches; the roller means against the static balance,
   by hand) and a pulsating load that slackens and takes up strands 125 times in 0.6 s
   (``pulse``).
3. stiffness ratio 1e6 (``stiff.toml``): Radau in twist coordinates (``stiff``).
4. a sparse-path drive (37 rollers, 301 states): the watched extremes against a dense CSV
   (8001 samples).
5. a linear drive file (``two_inertia.toml``): its steady state by complex phasors, here.
6. the sewing scene's eccentric tension roller: Radau on the geometry written out in the
   reference script (``sewing_ecc``).
"""

from __future__ import annotations

import cmath
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli

REF = Path(__file__).resolve().parent / "reference"
ROOT = REF.parent.parent
COVER = 1.0                       # issue 26: the estimate covers the true error of every reported figure
CSV_ROUND = 5e-10                 # the CSV writes 10 significant digits: half a unit of the 10th, relative


# --- running the commands ---------------------------------------------------------------------
def beltcalc_json(*args: str) -> dict:
    """``beltcalc <args> --json`` in this process; exit 0 and one JSON object on stdout."""
    res = CliRunner().invoke(cli, [*args, "--json"])
    assert res.exit_code == 0, (res.exit_code, res.output[-3000:], res.exception)
    return json.loads(res.stdout)


def read_csv(path: Path, columns) -> pd.DataFrame:
    return pd.read_csv(path, usecols=["t_s", *columns])


def val(node: dict) -> float:
    return node["value"]


def rel(run: dict) -> float:
    """The run's estimate relative to its unit's scale (what it claims for every figure)."""
    return val(run["error_relative"])


def tol(run: dict, scale: float, ref_err: float = 0.0, value: float | None = None) -> float:
    """The run's claimed error of a figure of scale ``scale``, plus the reference's own
    error, plus the CSV's rounding of ``value`` when it was read from the CSV."""
    return COVER * rel(run) * scale + ref_err + (CSV_ROUND * abs(value) if value is not None else 0.0)


def check(name, got, want, allowed, report, extra=0.0):
    """One comparison: |got - want| <= allowed. ``extra``: the part of ``allowed`` that is not
    the run's estimate (the reference's own error, the CSV's rounding), left out of the
    measured ratio to the estimate that the report prints."""
    diff = abs(got - want)
    report.append((name, got, want, diff, allowed, extra))
    assert diff <= allowed, f"{name}: {got!r} against {want!r}: |diff| {diff:.3g} > allowed {allowed:.3g}"


def print_report(title, run, report, scales):
    """What each comparison measured (pytest -s shows it): the difference, what is allowed, and
    (|diff| - the reference's error and the CSV's rounding) / (error_relative x S_u): the true
    error in units of the run's estimate (<= 1: the estimate covers it)."""
    ratio = [max(d - x, 0.0) / max(rel(run) * sc, 1e-300) for (_, _, _, d, _, x), sc in zip(report, scales)]
    k = int(np.argmax(ratio))
    print(f"\n{title}: error_relative {rel(run):.3g}, estimate {val(run['error_estimate']):.3g} "
          f"{run['error_estimate']['unit']} ({run['error_signal']}); wall {val(run['wall_time']):.1f} s; "
          f"worst true error / estimate = {ratio[k]:.3g} ({report[k][0]})")
    for (n, g, w, d, a, x), r in zip(report, ratio):
        print(f"  {n:50s} {g:+.12g} ref {w:+.12g} |diff| {d:.3g} allowed {a:.3g} ratio {r:.3g}")


def load_reference(name: str):
    doc = json.loads((REF / f"{name}.json").read_text())
    arrays = np.load(REF / f"{name}.npz")
    return doc, arrays


def ref_value(doc, key):
    v = doc["values"][key]
    return v["value"], v["referr"]


# --- the roller table: what the scene reports against the stored Radau reference -------------
ROLLER_STRANDS3 = ["drive-sprocket1", "sprocket1-idler1", "idler1-sprocket2", "sprocket2-idler2",
                   "idler2-sprocket3", "sprocket3-drive"]


def roller_scales(doc, n_rollers, strands):
    """S_u of the roller-table scene's watched signals over the run, from the reference:
    rad/s: omega_end<k>a and omega_motor; N m: T_shaft<k>, T_tube<k>, M_motor; N: the strands."""
    v = lambda k: abs(doc["values"][k]["value"])
    rad = max(v(f"runmax_omega_{x}") for x in ["motor"] + [f"end{k}a" for k in range(1, n_rollers + 1)])
    rad = max(rad, max(v(f"runmin_omega_{x}") for x in ["motor"] + [f"end{k}a" for k in range(1, n_rollers + 1)]))
    torques = ["M_motor"] + [f"T_shaft{k}" for k in range(1, n_rollers + 1)] + [f"T_tube{k}" for k in
                                                                              range(1, n_rollers + 1)]
    nm = max(max(v(f"runmax_{x}"), v(f"runmin_{x}")) for x in torques)
    newton = max(v(f"max_F_{s}") for s in strands)
    return {"rad/s": rad, "N*m": nm, "N": newton}


def compare_figure(run, doc, S, report, scales, name, got, key, unit, amplitude=False):
    """One reported figure against the reference's ``key`` (``amplitude``: half its max - min),
    at the run's estimate on the unit's scale ``S[unit]`` plus the reference's own error."""
    if amplitude:
        (hi, e1), (lo, e2) = ref_value(doc, f"max_{key}"), ref_value(doc, f"min_{key}")
        want, e = (hi - lo) / 2, (e1 + e2) / 2
    else:
        want, e = ref_value(doc, key)
    scales.append(S[unit])
    check(name, got, want, tol(run, S[unit], e), report, e)


def compare_roller_table(run, doc, arrays, csv, title, n_rollers=3, strands=ROLLER_STRANDS3):
    S = roller_scales(doc, n_rollers, strands)
    report, scales = [], []

    def cmp(name, got, key, unit, amplitude=False):
        compare_figure(run, doc, S, report, scales, name, got, key, unit, amplitude)

    for k in range(1, n_rollers + 1):
        r = run["rollers"][str(k)]
        cmp(f"roller {k} speed mean", val(r["speed_mean"]), f"mean_omega_end{k}a", "rad/s")
        cmp(f"roller {k} speed amplitude", val(r["speed_amplitude"]), f"omega_end{k}a", "rad/s", True)
        cmp(f"roller {k} drive-end torque mean", val(r["torque_drive_end_mean"]), f"mean_T_shaft{k}", "N*m")
        cmp(f"roller {k} drive-end torque ampl.", val(r["torque_drive_end_amplitude"]), f"T_shaft{k}", "N*m", True)
        cmp(f"roller {k} far-end torque mean", val(r["torque_far_end_mean"]), f"mean_T_tube{k}", "N*m")
        cmp(f"roller {k} far-end torque ampl.", val(r["torque_far_end_amplitude"]), f"T_tube{k}", "N*m", True)
    for s in strands:
        cmp(f"strand {s} force max", val(run["strands"][s]["force_max"]), f"max_F_{s}", "N")
        cmp(f"strand {s} force min", val(run["strands"][s]["force_min"]), f"min_F_{s}", "N")
    m = run["motor"]
    cmp("motor speed mean", val(m["speed_mean"]), "mean_omega_motor", "rad/s")
    cmp("motor torque mean", val(m["torque_mean"]), "mean_M_motor", "N*m")
    cmp("motor torque amplitude", val(m["torque_amplitude"]), "M_motor", "N*m", True)
    peak, e = ref_value(doc, "runmax_M_motor")
    low, e2 = ref_value(doc, "runmin_M_motor")
    scales.append(S["N*m"])
    check("motor torque peak", val(m["torque_peak"]), max(abs(peak), abs(low)), tol(run, S["N*m"], max(e, e2)),
          report, max(e, e2))
    # the time series of the CSV at the reference's stored times
    t = arrays["t"]
    idx = np.searchsorted(csv["t_s"].to_numpy(), t - 1e-9)
    assert np.abs(csv["t_s"].to_numpy()[idx] - t).max() < 1e-9
    series = [("omega_motor", "omega_motor_rad_per_s", "rad/s"), ("M_motor", "M_motor_N_m", "N*m")]
    series += [(f"omega_end{k}a", f"omega_end{k}a_rad_per_s", "rad/s") for k in range(1, n_rollers + 1)]
    series += [(f"F_{s}", f"F_{s}_N", "N") for s in strands]
    for key, col, unit in series:
        got = csv[col].to_numpy()[idx]
        want, e = arrays[key], arrays[key + "_referr"]
        diff = np.abs(got - want)
        allowed = COVER * rel(run) * S[unit] + e + CSV_ROUND * np.abs(want)
        k = int(np.argmax(diff / allowed))
        scales.append(S[unit])
        check(f"CSV {key} at t = {t[k]:.3f} s (worst of {t.size})", float(got[k]), float(want[k]),
              float(allowed[k]), report, float(allowed[k] - COVER * rel(run) * S[unit]))
    print_report(title, run, report, scales)
    return report


def roller_inputs_match(run, meta):
    """The scene's echoed inputs are the reference's (else the reference is for another drive)."""
    inputs = run["inputs"]
    assert val(inputs["rollers"]) == meta["rollers"]
    assert val(inputs["pretension"]) == pytest.approx(meta["pretension_N"], rel=1e-15)
    assert val(inputs["t_end"]) == pytest.approx(meta["t_end_s"], rel=1e-15)
    assert val(inputs["window"]) == pytest.approx(meta["window_s"], rel=1e-15)
    assert val(inputs["samples"]) == meta["samples"]
    assert val(inputs["load_amplitude"]) == pytest.approx(meta.get("load_amplitude_N_m", 0.0), abs=1e-15)
    assert val(inputs["load_frequency"]) == pytest.approx(meta.get("load_frequency_rad_per_s", 0.0), abs=1e-15)
    for key in ("roller_load", "chain_stiffness", "chain_damping_time", "chain_mass", "chain_pitch",
                "load_start", "ramp_time"):
        assert key in inputs
    assert val(inputs["chain_mass"]) == 0.91 and val(inputs["chain_pitch"]) == 0.015875   # as the reference


def roller_run(tmp_path, *args):
    path = tmp_path / "run.csv"
    run = beltcalc_json("simulate", "roller-table", *args, "--csv", str(path))
    return run, path


# 1. the roller table at three rollers ------------------------------------------------------------
@pytest.mark.slow
def test_roller_table_3_rollers_against_radau_with_events(tmp_path):
    # Reference: roller3 (Radau rtol 1e-11, events; 1 switch, the return strand slackens
    # when the element lands at 3 s). Default scene: 6 s, window 4.5 s, 6001 samples.
    doc, arrays = load_reference("roller3")
    run, path = roller_run(tmp_path)
    roller_inputs_match(run, doc["meta"])
    assert run["method"] == "exact"
    csv = read_csv(path, _roller_columns(3, ROLLER_STRANDS3))
    compare_roller_table(run, doc, arrays, csv, "roller table, 3 rollers")


def _roller_columns(n, strands):
    return (["omega_motor_rad_per_s", "M_motor_N_m"] + [f"omega_end{k}a_rad_per_s" for k in range(1, n + 1)]
            + [f"F_{s}_N" for s in strands])


def test_roller_table_drive_file_against_the_same_reference():
    # The built-in drive file catalogs/drives/roller_table.toml is the scene's default drive:
    # `simulate drive roller_table` reports every node, coupling (clutch included) and strand,
    # against the same reference (roller3).
    doc, _ = load_reference("roller3")
    run = beltcalc_json("simulate", "drive", "roller_table")
    v = lambda k: abs(doc["values"][k]["value"])
    nodes, couplings = list(run["nodes"]), list(run["couplings"])
    S = {"rad/s": max(max(v(f"runmax_omega_{x}"), v(f"runmin_omega_{x}")) for x in nodes),
         "N*m": max(max(v(f"runmax_T_{x}"), v(f"runmin_T_{x}")) for x in couplings + []),
         "N": max(v(f"max_F_{s}") for s in run["strands"])}
    S["N*m"] = max(S["N*m"], v("runmax_M_motor"), v("runmin_M_motor"))
    report, scales = [], []

    def cmp(name, got, key, unit):
        want, e = ref_value(doc, key)
        scales.append(S[unit])
        check(name, got, want, tol(run, S[unit], e), report, e)

    for x in nodes:
        for what, key in (("mean", "mean_omega"), ("min", "min_omega"), ("max", "max_omega")):
            cmp(f"{x} speed {what}", val(run["nodes"][x][f"speed_{what}"]), f"{key}_{x}", "rad/s")
    for x in couplings:
        for what, key in (("mean", "mean_T"), ("min", "min_T"), ("max", "max_T")):
            cmp(f"{x} torque {what}", val(run["couplings"][x][f"torque_{what}"]), f"{key}_{x}", "N*m")
    for x in run["strands"]:
        cmp(f"strand {x} force max", val(run["strands"][x]["force_max"]), f"max_F_{x}", "N")
        cmp(f"strand {x} force min", val(run["strands"][x]["force_min"]), f"min_F_{x}", "N")
    cmp("motor torque mean", val(run["motors"]["M_motor"]["torque_mean"]), "mean_M_motor", "N*m")
    print_report("drive file roller_table", run, report, scales)


# 2. zero pretension and a pulsating load ----------------------------------------------------------
def static_roller_speed(inputs: dict) -> float:
    """Rollers' speed in steady rotation [rad/s], by hand: every strand and shaft holds a
    constant twist, so the motor carries n M_roller / i (i = 5 x 5 x 19/19 = 25) and its
    linearised characteristic gives w_m = w_0 (1 - S_c M_m / (2 M_c)) (Mamatova et al. eq. 2);
    the rollers turn at w_m / i. Default scene: 6.10356 rad/s."""
    v = lambda k: val(inputs[k])
    i_tot = v("stage1_ratio") * v("stage2_ratio") * v("roller_teeth") / v("drive_teeth")
    w0 = 2 * math.pi * v("supply_frequency") / v("pole_pairs")
    Mm = v("rollers") * v("roller_load") / i_tot
    Mc = v("breakdown_factor") * v("rated_torque")
    return w0 * (1 - v("breakdown_slip") * Mm / (2 * Mc)) / i_tot


@pytest.mark.slow
def test_zero_pretension_against_radau_and_the_static_balance(tmp_path):
    # Reference: roller0 (Radau rtol 1e-11, events). 9 s, window 7.5 s: the load step at 3 s
    # leaves a transient (slowest pole -3.23 1/s) that is down to ~1e-9 of the speed at 7.5 s
    # (tests/test_switching_reference.py), so the window means are the static balance.
    doc, arrays = load_reference("roller0")
    run, path = roller_run(tmp_path, "--set", "pretension=0N", "--t-end", "9s", "--window", "7.5s",
                           "--samples", "9001")
    roller_inputs_match(run, doc["meta"])
    assert run["events"] >= 100 and doc["switches"] >= 100          # it does slacken, many times
    csv = read_csv(path, _roller_columns(3, ROLLER_STRANDS3))
    report = compare_roller_table(run, doc, arrays, csv, "roller table, zero pretension")
    static = static_roller_speed(run["inputs"])
    assert static == pytest.approx(6.1035588, abs=5e-8)              # tests/test_cli_roller_table.py
    assert val(run["motor"]["steady_speed_rollers"]) == pytest.approx(static, rel=1e-14)
    S = roller_scales(doc, 3, ROLLER_STRANDS3)["rad/s"]
    for k in (1, 2, 3):
        # the reference's own window mean is the balance to ~1e-9 (the transient's remainder)
        ref_mean, _ = ref_value(doc, f"mean_omega_end{k}a")
        assert ref_mean == pytest.approx(static, rel=1e-8)
        check(f"roller {k} mean = static balance", val(run["rollers"][str(k)]["speed_mean"]), static,
              tol(run, S, abs(ref_mean - static)), report, abs(ref_mean - static))


@pytest.mark.slow
def test_pulsating_load_slackening_strands_against_radau(tmp_path):
    # Reference: pulse (Radau rtol 1e-11, events): 70 N m per roller at 50 rad/s from 3 s on
    # top of the 40 N m, default 300 N pretension; the strands slacken and take up again
    # every load period (125 switches in 0.6 s). Roller 3's speed peaks twice 0.4 ms apart
    # near 3.503 s, 3.4e-4 rad/s apart: both the watch and the reference must find the higher.
    doc, arrays = load_reference("pulse")
    meta = doc["meta"]
    run, path = roller_run(tmp_path, "--set", "load_amplitude=70N*m", "--set", "load_frequency=50rad/s",
                           "--t-end", f"{meta['t_end_s']}s", "--window", f"{meta['window_s']}s",
                           "--samples", str(meta["samples"]))
    roller_inputs_match(run, meta)
    assert run["events"] >= 100 and doc["switches"] >= 100
    csv = read_csv(path, _roller_columns(3, ROLLER_STRANDS3))
    compare_roller_table(run, doc, arrays, csv, "roller table, pulsating load")


# 3. stiffness ratio 1e6 ---------------------------------------------------------------------------
def test_stiffness_ratio_1e6_against_radau_in_twist_coordinates(tmp_path):
    # stiff.toml: motor -> 2e3 N m/rad jaw -> hub -> 2e9 N m/rad coupling -> drum (96 N m + 10 N m
    # sin 30 t). Reference: stiff (Radau in twist coordinates, the stiff twist ~5e-8 rad a state
    # with atol 5e-20 rad; rtol 1e-10, e_ref against 1e-9).
    doc, arrays = load_reference("stiff")
    path = tmp_path / "stiff.csv"
    run = beltcalc_json("simulate", "drive", str(REF / "stiff.toml"), "--csv", str(path))
    csv = pd.read_csv(path)
    # S_u over the run from the reference: every node speed, every coupling torque and the motor's
    v = lambda k: abs(doc["values"][k]["value"])
    S = {"rad/s": max(max(v(f"runmax_omega_{x}"), v(f"runmin_omega_{x}")) for x in ("rotor", "hub", "drum")),
         "N*m": max(max(v(f"runmax_{x}"), v(f"runmin_{x}")) for x in ("T_jaw", "T_stiff", "M_motor"))}
    report, scales = [], []

    def cmp(name, got, key, unit, amplitude=False):
        compare_figure(run, doc, S, report, scales, name, got, key, unit, amplitude)

    for c in ("stiff", "jaw"):
        fig = run["couplings"][c]
        cmp(f"T_{c} mean", val(fig["torque_mean"]), f"mean_T_{c}", "N*m")
        cmp(f"T_{c} amplitude", val(fig["torque_amplitude"]), f"T_{c}", "N*m", True)
        cmp(f"T_{c} min", val(fig["torque_min"]), f"min_T_{c}", "N*m")
        cmp(f"T_{c} max", val(fig["torque_max"]), f"max_T_{c}", "N*m")
    for node in ("rotor", "hub", "drum"):
        fig = run["nodes"][node]
        cmp(f"{node} speed mean", val(fig["speed_mean"]), f"mean_omega_{node}", "rad/s")
        cmp(f"{node} speed min", val(fig["speed_min"]), f"min_omega_{node}", "rad/s")
        cmp(f"{node} speed max", val(fig["speed_max"]), f"max_omega_{node}", "rad/s")
    cmp("motor torque mean", val(run["motors"]["M_motor"]["torque_mean"]), "mean_M_motor", "N*m")
    # the stiff coupling's torque over the whole run, every sample
    t = arrays["t"]
    assert np.abs(csv["t_s"].to_numpy() - t).max() < 1e-12
    for key, col, unit in (("T_stiff", "T_stiff_N_m", "N*m"), ("T_jaw", "T_jaw_N_m", "N*m"),
                           ("omega_drum", "omega_drum_rad_per_s", "rad/s")):
        got, want, e = csv[col].to_numpy(), arrays[key], arrays[key + "_referr"]
        allowed = COVER * rel(run) * S[unit] + e + CSV_ROUND * np.abs(want)
        k = int(np.argmax(np.abs(got - want) / allowed))
        scales.append(S[unit])
        check(f"CSV {key} at t = {t[k]:.3f} s (worst of {t.size})", float(got[k]), float(want[k]),
              float(allowed[k]), report, float(allowed[k] - COVER * rel(run) * S[unit]))
    print_report("stiffness ratio 1e6", run, report, scales)


# 5. a linear drive file's steady state by complex phasors ---------------------------------------
def phasor_steady_state(drive: dict):
    """The periodic steady state of two_inertia.toml after its ramp, by hand.

    J1 phi1'' = M - T,  J2 phi2'' = T - (L0 + A sin W t),  T = C (phi1 - phi2) + d (phi1' - phi2'),
    M' = g (w0 - phi1') - a M,  g = 2 M_c w_c / w0,  a = w_c S_c  (Mamatova et al. 2016, eq. 2).
    Mean: every speed w0 - a L0 / g, T = M = L0. Ripple x(t) = Im(X e^(i W t)) with
      (C + i W d - J1 W^2) P1 - (C + i W d) P2 - Mh = 0
      -(C + i W d) P1 + (C + i W d - J2 W^2) P2 = -A
      i W g P1 + (i W + a) Mh = 0
    """
    J1, J2, C, d = drive["J1"], drive["J2"], drive["C"], drive["d"]
    Mc, Sc, wc, w0, L0, A, W = (drive[k] for k in ("Mc", "Sc", "wc", "w0", "L0", "A", "W"))
    g, a = 2 * Mc * wc / w0, wc * Sc
    z = C + 1j * W * d
    mat = np.array([[z - J1 * W ** 2, -z, -1.0], [-z, z - J2 * W ** 2, 0.0], [1j * W * g, 0.0, 1j * W + a]])
    P1, P2, Mh = np.linalg.solve(mat, np.array([0.0, -A, 0.0], dtype=complex))
    mean = w0 - a * L0 / g
    return {"w1": (mean, 1j * W * P1), "w2": (mean, 1j * W * P2), "T": (L0, z * (P1 - P2)), "M": (L0, Mh),
            "poles": np.linalg.eigvals(np.array([
                [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [-C / J1, C / J1, -d / J1, d / J1, 1 / J1],
                [C / J2, -C / J2, d / J2, -d / J2, 0], [0, 0, -g, 0, -a]]))}


def test_linear_drive_file_steady_state_against_phasors(tmp_path):
    text = (REF / "two_inertia.toml").read_text()
    f = tomllib.loads(text)
    num = lambda s: float(s.split()[0])
    (rotor, drum), (shaft,), (motor,), (load,) = f["node"], f["coupling"], f["motor"], f["load"]
    drive = {"J1": num(rotor["inertia"]), "J2": num(drum["inertia"]), "C": num(shaft["stiffness"]),
             "d": num(shaft["damping"]), "Mc": motor["breakdown_factor"] * num(motor["rated_torque"]),
             "Sc": motor["breakdown_slip"], "wc": 2 * math.pi * num(motor["supply"]),
             "L0": num(load["torque"]), "A": num(load["amplitude"]), "W": num(load["frequency"])}
    drive["w0"] = drive["wc"] / motor["pole_pairs"]
    ss = phasor_steady_state(drive)
    t_w, t_e, ramp = num(f["drive"]["window"]), num(f["drive"]["t_end"]), num(motor["ramp"])
    W = drive["W"]
    path = tmp_path / "two.csv"
    run = beltcalc_json("simulate", "drive", str(REF / "two_inertia.toml"), "--csv", str(path))
    csv = pd.read_csv(path)
    S = {"rad/s": float(np.abs(csv[["omega_rotor_rad_per_s", "omega_drum_rad_per_s"]].to_numpy()).max()),
         "N*m": float(np.abs(csv[["T_shaft_N_m", "M_motor_N_m"]].to_numpy()).max())}
    # what is left of the start at the window: the slowest pole, from a deviation of at most
    # 2 w0 (generous) at the end of the ramp
    sigma = max(p.real for p in ss["poles"] if abs(p) > 1e-9)
    assert sigma == pytest.approx(-26.41, abs=0.01)            # the rigid rotation on the motor characteristic
    left = 2 * drive["w0"] * math.exp(sigma * (t_w - ramp))
    assert left < 1e-3 * COVER * rel(run) * S["rad/s"]          # negligible beside what is compared

    def window(mean, X):
        """Mean, least and largest of mean + Im(X e^(i W t)) over [t_w, t_e] (> 1 period)."""
        assert (t_e - t_w) * W > 2 * math.pi
        m = mean + (X * (cmath.exp(1j * W * t_e) - cmath.exp(1j * W * t_w)) / (1j * W)).imag / (t_e - t_w)
        return m, mean - abs(X), mean + abs(X)

    report, scales = [], []

    def cmp(name, got, want, unit):
        scales.append(S[unit])
        check(name, got, want, tol(run, S[unit]), report)

    for node, key in (("rotor", "w1"), ("drum", "w2")):
        m, lo, hi = window(*ss[key])
        fig = run["nodes"][node]
        cmp(f"{node} speed window mean", val(fig["speed_mean"]), m, "rad/s")
        cmp(f"{node} speed amplitude", val(fig["speed_amplitude"]), abs(ss[key][1]), "rad/s")
        cmp(f"{node} speed min", val(fig["speed_min"]), lo, "rad/s")
        cmp(f"{node} speed max", val(fig["speed_max"]), hi, "rad/s")
        st = run["steady_state"]["nodes"][node]            # the frequency-domain answer beside it
        assert val(st["speed_mean"]) == pytest.approx(ss[key][0], rel=1e-12)
        assert val(st["speed_amplitude"]) == pytest.approx(abs(ss[key][1]), rel=1e-9)
    m, lo, hi = window(*ss["T"])
    fig = run["couplings"]["shaft"]
    cmp("shaft torque window mean", val(fig["torque_mean"]), m, "N*m")
    cmp("shaft torque amplitude", val(fig["torque_amplitude"]), abs(ss["T"][1]), "N*m")
    cmp("shaft torque min", val(fig["torque_min"]), lo, "N*m")
    cmp("shaft torque max", val(fig["torque_max"]), hi, "N*m")
    m, lo, hi = window(*ss["M"])
    fig = run["motors"]["M_motor"]
    cmp("motor torque window mean", val(fig["torque_mean"]), m, "N*m")
    cmp("motor torque amplitude", val(fig["torque_amplitude"]), abs(ss["M"][1]), "N*m")
    # and every sample of the window in the CSV
    t = csv["t_s"].to_numpy()
    late = t >= t_w - 1e-12
    for col, key, unit in (("omega_drum_rad_per_s", "w2", "rad/s"), ("T_shaft_N_m", "T", "N*m")):
        mean, X = ss[key]
        want = mean + (X * np.exp(1j * W * t[late])).imag
        got = csv[col].to_numpy()[late]
        allowed = COVER * rel(run) * S[unit] + CSV_ROUND * np.abs(want)
        k = int(np.argmax(np.abs(got - want) / allowed))
        scales.append(S[unit])
        check(f"CSV {col} at t = {t[late][k]:.3f} s", float(got[k]), float(want[k]), float(allowed[k]), report,
              float(allowed[k] - COVER * rel(run) * S[unit]))
    print_report("two inertias, phasors", run, report, scales)


# 1. (continued) many rollers: structural checks that can fail ------------------------------------
def roller_table_inertias(inputs: dict):
    """Per node of the serpentine roller table: inertia [kg m^2] with half of each chain
    strand's mass (m L r^2 / 2 on each sprocket, Rusek & Popenda's lumping), and its turn per
    radian of the motor in rigid rotation, u. By hand from the scene's echoed inputs: a roller
    is a steel tube pi rho L (D^4 - d^4) / 32, half at each end; a sprocket a steel disc of its
    pitch diameter p / sin(180 deg / z) and the sprocket thickness; the motor carries half the
    coupling, the gear input the other half and the reducer's shafts reflected by their
    ratios; the serpentine chain runs drive, sprocket 1, idler 1, sprocket 2, ..., sprocket n
    and back (catalogs/scenes/roller_table.toml; beltcalc/sim/scenes/roller_table.py says the
    same in words). ``test_roller_inertias_by_hand_match_the_drive_file`` holds this to the
    built-in drive file at three rollers."""
    v = lambda k: val(inputs[k])
    assert inputs["routing"]["text"] == "serpentine" and v("idler_inertia") > 0
    n, rho_s, thick = int(v("rollers")), v("steel_density"), v("sprocket_thickness")
    pitch_d = lambda z: v("chain_pitch") / math.sin(math.pi / z)
    disc = lambda d: math.pi * rho_s * thick * d ** 4 / 32
    D, wall, L = v("roller_diameter"), v("roller_wall"), v("roller_length")
    roller = math.pi * rho_s * L * (D ** 4 - (D - 2 * wall) ** 4) / 32
    i1, i2 = v("stage1_ratio"), v("stage2_ratio")
    J = {"motor": v("motor_inertia") + v("coupling_inertia") / 2,
         "gear": (v("coupling_inertia") / 2 + v("gear_input_inertia") + v("gear_middle_inertia") / i1 ** 2
                  + v("gear_output_inertia") / (i1 * i2) ** 2),
         "drive": disc(pitch_d(v("drive_teeth")))}
    r = {"drive": pitch_d(v("drive_teeth")) / 2}
    for k in range(1, n + 1):
        J[f"sprocket{k}"] = disc(pitch_d(v("roller_teeth")))
        r[f"sprocket{k}"] = pitch_d(v("roller_teeth")) / 2
        J[f"end{k}a"] = J[f"end{k}b"] = roller / 2
    for k in range(1, n):
        J[f"idler{k}"] = v("idler_inertia")
        r[f"idler{k}"] = pitch_d(v("idler_teeth")) / 2
    bare = dict(J)
    path = ["drive"] + [x for k in range(1, n + 1) for x in ((f"idler{k - 1}",) if k > 1 else ()) + (f"sprocket{k}",)]
    lengths = [v("drive_strand_length") if a == "drive" else
               (v("strand_length") / 2 if "idler" in a + b else v("strand_length")) for a, b in zip(path, path[1:])]
    spans = list(zip(path, path[1:], lengths)) + [(path[-1], "drive", sum(lengths))]
    for a, b, length in spans:
        for node in (a, b):
            J[node] += v("chain_mass") * length * r[node] ** 2 / 2
    u = {"motor": 1.0, "gear": 1.0, "drive": 1.0 / (i1 * i2)}
    for node in r:
        u[node] = u["drive"] * r["drive"] / r[node]
    for k in range(1, n + 1):
        u[f"end{k}a"] = u[f"end{k}b"] = u[f"sprocket{k}"]
    return J, u, bare


def test_roller_inertias_by_hand_match_the_drive_file():
    inputs = beltcalc_json("simulate", "roller-table", "--list-params")
    inputs = inputs.get("parameters", inputs)
    if isinstance(inputs, list):
        inputs = {p["name"]: p for p in inputs}
    _, u, bare = roller_table_inertias(inputs)
    data = tomllib.loads((ROOT / "catalogs/drives/roller_table.toml").read_text())
    file = {nd["name"]: float(nd["inertia"].split()[0]) for nd in data["node"]}
    assert set(file) == set(bare)
    for node, J in file.items():
        assert bare[node] == pytest.approx(J, rel=1e-12), node
    assert u["end3b"] == pytest.approx(1 / 25, rel=1e-15)


def momentum_balance(run, csv, inputs, report, scales):
    """The motor's momentum balance over the window, exact for any drive of rigid-rotation
    factors u (every coupling and strand does no work on u):

        mean(M) - sum_k u_k mean(load_k) = sum_k u_k J_k (omega_k(t_end) - omega_k(t_window)) / T_w

    i.e. "the mean motor torque times the ratio equals the sum of the mean load torques" plus
    what the window's speed change stores. Loads: roller_load per roller from load_start on."""
    J, u, _ = roller_table_inertias(inputs)
    t = csv["t_s"].to_numpy()
    t_w, t_e = val(inputs["window"]), t[-1]
    assert val(inputs["load_start"]) <= t_w
    a, b = int(np.argmin(np.abs(t - t_w))), len(t) - 1
    assert abs(t[a] - t_w) < 1e-9
    store = sum(u[k] * J[k] * (csv[f"omega_{k}_rad_per_s"].iloc[b] - csv[f"omega_{k}_rad_per_s"].iloc[a])
                for k in J) / (t_e - t_w)
    n = int(val(inputs["rollers"]))
    loads = n * val(inputs["roller_load"]) * u["end1a"]
    S = roller_run_scales(csv, n)
    ujw = sum(u[k] * J[k] * (abs(csv[f"omega_{k}_rad_per_s"].iloc[b]) + abs(csv[f"omega_{k}_rad_per_s"].iloc[a]))
              for k in J) / (t_e - t_w)
    allowed = (COVER * rel(run) * (S["N*m"] + 2 * S["rad/s"] * sum(u[k] * J[k] for k in J) / (t_e - t_w))
               + CSV_ROUND * ujw)
    scales.append(S["N*m"])
    check(f"{n} rollers: mean motor torque = loads / ratio + stored", val(run["motor"]["torque_mean"]),
          loads + store, allowed, report, CSV_ROUND * ujw)
    return loads, store


def roller_run_scales(csv, n):
    """S_u of the scene's watched signals over the run, from the run's own CSV (no reference)."""
    rad = ["omega_motor_rad_per_s"] + [f"omega_end{k}a_rad_per_s" for k in range(1, n + 1)]
    nm = ["M_motor_N_m"] + [f"T_shaft{k}_N_m" for k in range(1, n + 1)] + [f"T_tube{k}_N_m" for k in range(1, n + 1)]
    force = [c for c in csv.columns if c.startswith("F_")]
    m = lambda cols: float(np.abs(csv[cols].to_numpy()).max())
    return {"rad/s": m(rad), "N*m": m(nm), "N": m(force)}


def many_rollers(run, csv, run_other, title):
    """Exit 0 (beltcalc_json), the roller means of two sample counts, the momentum balance,
    strand forces >= 0."""
    inputs = run["inputs"]
    n = int(val(inputs["rollers"]))
    S = roller_run_scales(csv, n)
    report, scales = [], []
    assert len(run["rollers"]) == n and len(run["strands"]) == 2 * n
    if run_other is not None:
        for k in range(1, n + 1):
            a = val(run["rollers"][str(k)]["speed_mean"])
            b = val(run_other["rollers"][str(k)]["speed_mean"])
            assert a == pytest.approx(b, rel=1e-6), (k, a, b)        # the "done when"
            scales.append(S["rad/s"])
            check(f"roller {k} mean, two sample counts", a, b,
                  COVER * (rel(run) + rel(run_other)) * S["rad/s"], report)
    loads, store = momentum_balance(run, csv, inputs, report, scales)
    for s, fig in run["strands"].items():
        lo = val(fig["force_min"])
        assert lo >= -COVER * rel(run) * S["N"], (s, lo)             # tension only
        assert val(fig["force_max"]) >= lo
    print_report(f"{title} (loads / ratio {loads:.6g} N m, stored {store:+.6g} N m)", run, report, scales)


def _many_columns(n):
    nodes = ["motor", "gear", "drive"] + [f"sprocket{k}" for k in range(1, n + 1)]
    nodes += [f"end{k}{e}" for k in range(1, n + 1) for e in "ab"] + [f"idler{k}" for k in range(1, n)]
    cols = [f"omega_{x}_rad_per_s" for x in nodes] + ["M_motor_N_m"]
    cols += [f"T_shaft{k}_N_m" for k in range(1, n + 1)] + [f"T_tube{k}_N_m" for k in range(1, n + 1)]
    return cols


def _strand_columns(path):
    return [c for c in pd.read_csv(path, nrows=0).columns if c.startswith("F_")]


def many_args(n: int, samples: int, t_end: float = 3.0, load_start: float = 1.0, window: float = 2.0) -> list[str]:
    """The many-roller runs: the load of the default three rollers (40 N m each) shared by n
    rollers (at 40 N m a roller the motor stalls past 2 rollers: the stall check refuses the
    run), landing at ``load_start``, the window from ``window`` to ``t_end``."""
    return ["--set", f"rollers={n}", "--set", f"roller_load={120.0 / n!r}N*m", "--set",
            f"load_start={load_start!r}s", "--t-end", f"{t_end!r}s", "--window", f"{window!r}s",
            "--samples", str(samples)]


@pytest.mark.slow
def test_50_rollers_sample_counts_balance_and_tension_only(tmp_path):
    # 50 rollers (201 nodes, 403 states: the sparse path, which crashed from 37 rollers on):
    # the roller means of 3001 and 12001 samples agree to 1e-6 (issue 26), the motor's balance
    run, path = roller_run(tmp_path, *many_args(50, 3001, t_end=2.0, load_start=0.6, window=1.2))
    other = beltcalc_json("simulate", "roller-table", *many_args(50, 12001, t_end=2.0, load_start=0.6, window=1.2))
    csv = read_csv(path, _many_columns(50) + _strand_columns(path))
    many_rollers(run, csv, other, "50 rollers")


@pytest.mark.slow
def test_30_rollers_against_radau_with_events(tmp_path):
    # Reference: roller30 (Radau rtol 1e-11, events, on roller30.toml: the drive the scene builds
    # at 30 rollers sharing the three rollers' load; 121 nodes, 243 states). Every roller's means
    # and amplitudes, every strand's extremes, the motor, and the CSV at the stored times, each to
    # the run's own estimate.
    doc, arrays = load_reference("roller30")
    meta = doc["meta"]
    run, path = roller_run(tmp_path, *many_args(30, meta["samples"], t_end=meta["t_end_s"],
                                                load_start=meta["load_start_s"], window=meta["window_s"]))
    inputs = run["inputs"]
    assert val(inputs["rollers"]) == 30 and val(inputs["roller_load"]) == pytest.approx(meta["roller_load_N_m"],
                                                                                        rel=1e-15)
    assert run["method"] == "exact"
    strands = list(run["strands"])
    assert len(strands) == 2 * 30
    csv = read_csv(path, _roller_columns(30, strands))
    compare_roller_table(run, doc, arrays, csv, "roller table, 30 rollers", n_rollers=30, strands=strands)


@pytest.mark.slow
def test_200_rollers_balance_and_tension_only(tmp_path):
    # the roller count's upper limit (801 nodes, 1,605 states), one short run (the load lands
    # in the start-up): exit 0, the motor's momentum balance over the window, strand forces >= 0
    run, path = roller_run(tmp_path, *many_args(200, 101, t_end=1.0, load_start=0.3, window=0.6))
    csv = read_csv(path, _many_columns(200) + _strand_columns(path))
    many_rollers(run, csv, None, "200 rollers")


# 4. a sparse-path drive file: watched extremes against dense samples -----------------------------
def _toml(data: dict) -> str:
    """A drive file's text (strings, numbers, lists, tables of arrays) from ``data``."""
    def value(x):
        if isinstance(x, str):
            return json.dumps(x)
        if isinstance(x, bool):
            return "true" if x else "false"
        if isinstance(x, (int, float)):
            return repr(x)
        return "[" + ", ".join(value(y) for y in x) + "]"
    out = []
    for section, body in data.items():
        items = body if isinstance(body, list) else [body]
        for item in items:
            out.append(f"[[{section}]]" if isinstance(body, list) else f"[{section}]")
            out += [f"{k} = {value(v)}" for k, v in item.items()]
            out.append("")
    return "\n".join(out)


def serpentine_drive(n: int, ramp: str, load_at: float, t_end: str, window: str, samples: int,
                     end_load: float = 2.0) -> str:
    """The built-in roller table's drive file (catalogs/drives/roller_table.toml, 3 rollers)
    grown to ``n`` rollers as a designer would write it: the same node, coupling, strand and
    load entries per roller, the serpentine chain drive, sprocket 1, idler 1, ..., sprocket n,
    back to the drive (its length the sum of the others), with a shorter ramp and an earlier
    load so that the run is short, and ``end_load`` N m on each roller end (the file's 20 N m
    on each of 2n ends would stall the motor past 2 rollers: beyond its breakdown torque)."""
    base = tomllib.loads((ROOT / "catalogs/drives/roller_table.toml").read_text())
    node = {nd["name"]: nd for nd in base["node"]}
    coup = {c["name"]: c for c in base["coupling"]}
    strand = {s["name"]: s for s in base["chain_strand"]}
    load = base["load"][0]
    nodes = [node["motor"], node["gear"], node["drive"]]
    couplings = [coup["coupling"], coup["clutch"]]
    strands, loads = [], []
    for k in range(1, n + 1):
        nodes += [dict(node["sprocket1"], name=f"sprocket{k}"), dict(node["end1a"], name=f"end{k}a"),
                  dict(node["end1b"], name=f"end{k}b")]
        couplings += [dict(coup["shaft1"], name=f"shaft{k}", between=[f"sprocket{k}", f"end{k}a"]),
                      dict(coup["tube1"], name=f"tube{k}", between=[f"end{k}a", f"end{k}b"])]
        for end in "ab":
            loads.append(dict(load, name=f"load_end{k}{end}", node=f"end{k}{end}", start=f"{load_at} s",
                              table=[[f"{load_at} s", "0 N*m"], [f"{load_at} s", f"{end_load!r} N*m"]]))
        if k < n:
            nodes.append(dict(node["idler1"], name=f"idler{k}"))
    path = ["drive"] + [x for k in range(1, n + 1) for x in ((f"idler{k - 1}",) if k > 1 else ()) + (f"sprocket{k}",)]
    total = 0.0
    for a, b in zip(path, path[1:]):
        proto = strand["drive-sprocket1"] if a == "drive" else strand["sprocket1-idler1"]
        strands.append(dict(proto, name=f"{a}-{b}", **{"from": a, "to": b}))
        total += float(proto["length"].split()[0])
    strands.append(dict(strand["sprocket3-drive"], name=f"{path[-1]}-drive", length=f"{total!r} m",
                        **{"from": path[-1], "to": "drive"}))
    motor = dict(base["motor"][0], ramp=ramp)
    drive = dict(base["drive"], title=f"roller table, {n} rollers", t_end=t_end, window=window, samples=samples)
    return _toml({"drive": drive, "node": nodes, "coupling": couplings, "chain_strand": strands,
                  "motor": [motor], "load": loads})


@pytest.mark.slow
def test_sparse_path_watched_extremes_against_dense_samples(tmp_path):
    # 37 rollers: 150 nodes, 301 states, the sparse path (from 300 states), and the first
    # roller count that used to crash. 0.3 s ramp, the element lands at 0.5 s, window 0.6-0.8 s.
    # The watch's least and largest values must be at least as extreme as the dense samples'
    # (less the estimate) and no further out than the samples can hide (|second
    # difference| / 4 over the window: a peak between samples is at most |x''| dt^2 / 8 above
    # the nearest one, twice that for safety at kinks) plus the estimate.
    n, samples = 37, 8001
    file = tmp_path / "rollers37.toml"
    file.write_text(serpentine_drive(n, "0.3 s", 0.5, "0.8 s", "0.6 s", samples))
    path = tmp_path / "dense.csv"
    run = beltcalc_json("simulate", "drive", str(file), "--csv", str(path))
    watched_nodes = ["motor"] + [f"end{k}a" for k in (1, 10, 20, 37)] + [f"sprocket{k}" for k in (1, 37)]
    strands = ["drive-sprocket1", "sprocket1-idler1", "idler18-sprocket19", "sprocket37-drive"]
    cols = [f"omega_{x}_rad_per_s" for x in watched_nodes] + [f"F_{s}_N" for s in strands]
    csv = read_csv(path, cols)
    t = csv["t_s"].to_numpy()
    assert t.size == samples
    every = pd.read_csv(path, nrows=0).columns
    assert sum(c.startswith("omega_") for c in every) == 150           # 301 states with the motor torque
    full = pd.read_csv(path, usecols=[c for c in every if c.startswith("omega_") or c.startswith("F_")])
    S = {"rad/s": float(np.abs(full[[c for c in full.columns if c.startswith("omega_")]].to_numpy()).max()),
         "N": float(np.abs(full[[c for c in full.columns if c.startswith("F_")]].to_numpy()).max())}
    del full
    t_w = 0.6
    lines = []

    def bracket(name, watch, x, sign, scale):
        """sign = +1: the watch's largest value against the dense samples' largest, -1: least."""
        dense = float(sign * (sign * x).max())
        hide = float(np.abs(np.diff(x, 2)).max()) / 4          # what the samples can hide
        e = tol(run, scale, value=dense)
        out = sign * (watch - dense)                            # > 0: the watch is further out
        lines.append(f"  {name:44s} watch {watch:+.12g} dense {dense:+.12g} out by {out:+.3g} "
                     f"(allowed -{e:.3g} .. {hide + e:.3g}; {out / (rel(run) * scale):+.3g} x rel x scale)")
        assert -e <= out <= hide + e, lines[-1]

    for node in watched_nodes:
        x = csv[f"omega_{node}_rad_per_s"].to_numpy()[t >= t_w - 1e-12]
        fig = run["nodes"][node]
        bracket(f"{node} speed max", val(fig["speed_max"]), x, +1, S["rad/s"])
        bracket(f"{node} speed min", val(fig["speed_min"]), x, -1, S["rad/s"])
    for s in strands:
        x = csv[f"F_{s}_N"].to_numpy()
        fig = run["strands"][s]
        bracket(f"strand {s} force max", val(fig["force_max"]), x, +1, S["N"])
        bracket(f"strand {s} force min", val(fig["force_min"]), x, -1, S["N"])
    print(f"\nsparse path, {n} rollers, {samples} samples: error_relative {rel(run):.3g} "
          f"({run['error_signal']}), wall {val(run['wall_time']):.1f} s, {run['events']} switches")
    print("\n".join(lines))



# 6. the sewing scene's eccentric tension roller ---------------------------------------------------
def whole_periods_start(t_end: float, window: float, omega: float) -> float:
    """The scene's window: the latest start >= ``window`` from which [start, t_end] holds whole
    load periods (catalogs/scenes/sewing.toml: one load cycle per main-shaft turn)."""
    period = 2 * math.pi / omega
    k = math.floor((t_end - window) / period + 1e-9)
    return t_end - k * period


@pytest.mark.slow
def test_sewing_eccentric_roller_against_radau(tmp_path):
    # Reference: sewing_ecc (Radau rtol 1e-10, e_ref against 1e-9; the belt path L(theta) of the
    # three circles and the span forces E4-E7 of docs/eccentric_roller.md written out in
    # make_references.py, its slope checked there against a difference of the length).
    # For this nonlinear drive the scene reports trapezoid means and sampled extremes over its
    # window (whole load periods from 0.5 s): the reference's figures are taken alike from its
    # states at the same 10001 sample times.
    doc, arrays = load_reference("sewing_ecc")
    p, figs = doc["meta"]["params"], doc["window"]
    assert whole_periods_start(1.0, 0.5, p["w_load"]) == pytest.approx(doc["meta"]["window_start_s"], abs=1e-15)
    from clichecks import sewing_eccentric_run

    res, path = sewing_eccentric_run()                  # shared with tests/test_eccentric.py
    assert res.exit_code == 0, res.output[-3000:]
    run = json.loads(res.stdout)
    assert val(run["inputs"]["roller_eccentricity"]) == pytest.approx(p["delta"], rel=1e-15)
    units = {"omega_1": "rad/s", "omega_3": "rad/s", "omega_5": "rad/s", "accel_3": "rad/s^2",
             "accel_5": "rad/s^2", "T_23": "N*m", "T_45": "N*m", "M_motor": "N*m"}
    S = {}
    for key, unit in units.items():
        S[unit] = max(S.get(unit, 0.0), figs[key]["runmax"])
    report, scales = [], []

    def cmp(name, got, key, what):
        f = figs[key]
        want = f["mean"] if what == "mean" else (f["max"] - f["min"]) / 2
        scales.append(S[units[key]])
        check(name, got, want, tol(run, S[units[key]], f["referr"]), report, f["referr"])

    for shaft, node, torque in (("main", "3", "T_23"), ("bottom", "5", "T_45")):
        fig = run["shafts"][shaft]
        cmp(f"{shaft} shaft speed mean", val(fig["speed_mean"]), f"omega_{node}", "mean")
        cmp(f"{shaft} shaft speed amplitude", val(fig["speed_amplitude"]), f"omega_{node}", "amplitude")
        cmp(f"{shaft} shaft accel. amplitude", val(fig["accel_amplitude"]), f"accel_{node}", "amplitude")
        cmp(f"{shaft} shaft torque mean", val(fig["torque_mean"]), torque, "mean")
        cmp(f"{shaft} shaft torque amplitude", val(fig["torque_amplitude"]), torque, "amplitude")
    cmp("motor speed mean", val(run["motor"]["speed_mean"]), "omega_1", "mean")
    cmp("motor torque mean", val(run["motor"]["torque_mean"]), "M_motor", "mean")
    cmp("motor torque amplitude", val(run["motor"]["torque_amplitude"]), "M_motor", "amplitude")
    csv = pd.read_csv(path, usecols=["t_s", "omega_3_rad_per_s", "omega_5_rad_per_s", "T_23_N_m"])
    t = arrays["t"]
    idx = np.searchsorted(csv["t_s"].to_numpy(), t - 1e-9)
    assert np.abs(csv["t_s"].to_numpy()[idx] - t).max() < 1e-9
    for key, col in (("omega_3", "omega_3_rad_per_s"), ("omega_5", "omega_5_rad_per_s"), ("T_23", "T_23_N_m")):
        got, want = csv[col].to_numpy()[idx], arrays[key]
        allowed = COVER * rel(run) * S[units[key]] + figs[key]["referr"] + CSV_ROUND * np.abs(want)
        k = int(np.argmax(np.abs(got - want) / allowed))
        scales.append(S[units[key]])
        check(f"CSV {key} at t = {t[k]:.4f} s (worst of {t.size})", float(got[k]), float(want[k]),
              float(allowed[k]), report, float(allowed[k] - COVER * rel(run) * S[units[key]]))
    print_report("sewing, eccentric roller 2 mm", run, report, scales)


