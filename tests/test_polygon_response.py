"""``beltcalc response --polygon`` (:mod:`beltcalc.sim.polygon_response`) against the nonlinear
polygon strand run in time to its steady state, through the commands a user types; the mean
force of the balance at the given speed against its closed form; the strands it refuses.
(tests/test_polygon.py checks the harmonics of the pulse against a least-squares fit and the
frequency solve against the same linear forcing integrated by Radau.)"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

STEADY = Path(__file__).parent / "data" / "chain_polygon_steady.toml"
P10B = 0.015875          # 10B-1 pitch [m]
W, DRAG = 15.0, 1.2      # the driver's prescribed speed [rad/s] and the driven sprocket's drag [N m s/rad]
PERIODS, PER = 14, 64    # the file's t_end in tooth periods, and samples per period


def cli(*args: str):
    """The command a user types, in process: (exit code, stdout, stderr)."""
    from click.testing import CliRunner

    from beltcalc.cli.main import cli as main

    res = CliRunner().invoke(main, [str(a) for a in args])
    return res.exit_code, res.stdout, res.stderr


def test_the_polygon_response_against_the_nonlinear_run_in_steady_state(tmp_path):
    """``simulate drive chain_polygon_steady.toml`` (one polygon strand, the driver prescribed at
    15 rad/s, the driven sprocket against a viscous drag: the strand stays taut) Fourier-analysed
    over its last five tooth periods, against ``response ... --polygon tight --speed 15rad/s
    --harmonics 5``.

    The mean force is the balance at that speed, d omega_j / r_j (closed form, r the mean radius
    p z / 2 pi; the run's mean differs by the mean of the ripples' products, second order). The
    harmonics: the frequency solve holds the strand's lever arms and stiffness at their means,
    while in the run they swing over a tooth period by about 1 - cos(pi / z) of themselves (the
    polygon's chordal rise, 2.2 % at 15 teeth), and that swing times the first harmonic's
    response feeds the others: each harmonic within 1.5 (1 - cos(pi / z_j)) of the first's
    amplitude (measured: 2.2 % at most, the strand force's second), the first within a quarter of
    it in amplitude and phase (measured 0.14 %). The run's own error (its estimate, 2.5e-7 rad/s)
    is far below both. Without the lever arms' swing under the mean force the first harmonic of
    the force would be 45 % off: the check sees that term."""
    out = tmp_path / "run.csv"
    code, stdout, stderr = cli("simulate", "drive", STEADY, "--json", "--csv", out)
    assert code == 0, stderr
    run = json.loads(stdout)
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == PERIODS * PER + 1
    code, stdout, stderr = cli("response", STEADY, "--polygon", "tight", "--speed", f"{W}rad/s", "--harmonics", 5,
                               "--output", "omega_driven", "--output", "F_tight", "--json")
    assert code == 0, stderr
    p = json.loads(stdout)["polygon"]
    r_i, r_j = P10B * 19 / (2 * math.pi), P10B * 15 / (2 * math.pi)
    omega_j = W * r_i / r_j
    assert p["tooth_frequency"]["value"] == pytest.approx(19 * W / (2 * math.pi), rel=1e-12)
    assert p["mean_force"]["value"] == pytest.approx(DRAG * omega_j / r_j, rel=1e-9)
    assert p["mean_force_origin"].startswith("the static balance turning at --speed")
    F = np.array([float(r["F_tight_N"]) for r in rows])
    assert F[-5 * PER - 1:-1].mean() == pytest.approx(DRAG * omega_j / r_j, rel=2e-4)
    bound = 1 - math.cos(math.pi / 15)
    assert run["error_estimate"]["value"] < 1e-5
    for column, name in (("omega_driven_rad_per_s", "omega_driven"), ("F_tight_N", "F_tight")):
        y = np.array([float(r[column]) for r in rows])[-5 * PER - 1:-1]
        spec = 2 * np.fft.rfft(y) / y.size
        got = spec[5 * np.arange(1, 6)]
        want = np.array([h["outputs"][name]["amplitude"]["value"] * np.exp(1j * h["outputs"][name]["phase"]["value"])
                         for h in p["harmonics"]])
        assert abs(got[0] - want[0]) <= bound / 4 * abs(want[0]), name
        assert np.all(np.abs(got - want) <= 1.5 * bound * abs(want[0])), (name, np.abs(got - want) / abs(want[0]))
        assert p["bound"][name]["value"] == pytest.approx(np.abs(want).sum(), rel=1e-12)
        if name == "F_tight":
            from beltcalc.sim.frequency_report import load
            from beltcalc.sim.polygon_response import polygon_response

            bare = polygon_response(load(STEADY), "tight", W, 1, ["F_tight"], mean_force=0.0).outputs["F_tight"][0]
            assert abs(got[0] - bare) > 0.3 * abs(want[0])


def test_a_plain_chain_strand_gets_the_same_excitation(tmp_path):
    """The same drive with ``polygon = false``: the strand's geometry from its nodes' teeth and
    pitch radii (p = 2 R sin(pi / z)), the same tooth frequency and length pulse, the mean force
    of its own stamped spring (pitch radii: d omega_j / R_j)."""
    plain = tmp_path / "plain.toml"
    plain.write_text(STEADY.read_text().replace("polygon = true", "polygon = false"))
    args = ("--speed", f"{W}rad/s", "--harmonics", 3, "--output", "F_tight", "--json")
    a = json.loads(cli("response", STEADY, "--polygon", "tight", *args)[1])["polygon"]
    code, stdout, stderr = cli("response", plain, "--polygon", "tight", *args)
    assert code == 0, stderr
    b = json.loads(stdout)["polygon"]
    assert b["tooth_frequency"]["value"] == pytest.approx(a["tooth_frequency"]["value"], rel=1e-12)
    assert [h["pulse"]["value"] for h in b["harmonics"]] == pytest.approx([h["pulse"]["value"] for h in a["harmonics"]],
                                                                          rel=1e-9)
    R_j = P10B / (2 * math.sin(math.pi / 15))
    # the plain strand's drive turns at the pitch-radius ratio R_i / R_j
    omega_j = W * (P10B / (2 * math.sin(math.pi / 19))) / R_j
    assert b["mean_force"]["value"] == pytest.approx(DRAG * omega_j / R_j, rel=1e-9)


@pytest.mark.parametrize("drive, strand, message", [
    ("conveyor", "upper", "--polygon: upper is not a chain strand"),
    (None, "tight", "--polygon: strand tight: the pitch radii of driver (19 teeth) and driven (15 teeth) give two"),
])
def test_strands_without_a_polygon_geometry_are_one_line_errors(tmp_path, drive, strand, message):
    """A belt span (a belt has no chordal action) and a chain strand whose nodes' pitch diameters
    give two pitches: exit 1 (the drive cannot have it), one line naming ``--polygon``."""
    if drive is None:
        drive = tmp_path / "odd.toml"
        text = STEADY.read_text().replace("polygon = true", "polygon = false")
        drive.write_text(text.replace('teeth = 15\nchain = "10B-1"', 'teeth = 15\npitch_diameter = "80 mm"'))
    code, stdout, stderr = cli("response", drive, "--polygon", strand, "--speed", "10rad/s")
    assert code == 1 and stdout == ""
    assert message in stderr and "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1, stderr
