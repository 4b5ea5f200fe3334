"""What a user sees of a result (issue 30, items 6 and 7), each through the command where the
user meets it: ``--plot`` writes the format its suffix names (beltcalc/cli/output.py
``plot_format``, ``write_figure``); a table never cuts a number (``fit_table``); limit lines
differ by style and carry a label; Campbell labels do not overlap (beltcalc/plots.py); a study's
key and its label name the same quantity (sim/scenes/base.py ``column_rows``); ``modes`` names
every element that holds over 10 % of a mode's strain energy; Dask's own log lines stay off
stderr, and a script without a main guard runs a study on a local cluster (sim/study/cluster.py)."""

from __future__ import annotations

import io
import json
import math
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import ok, one_error_line, table_rows

mpl = pytest.importorskip("matplotlib")
mpl.use("Agg")

VARY = ("--vary", "C4=normal(260N*m/rad,5%)")


def run(*args: str, env: dict | None = None):
    return CliRunner(env=env).invoke(cli, list(args))


def half_unit(text: str) -> float:
    """Half a unit of the last digit of a number as printed (the table's own rounding).

    >>> half_unit("3.006e-08"), half_unit("-441.0"), half_unit("3717")
    (5e-12, 0.05, 0.5)
    """
    mantissa, _, exponent = text.lower().partition("e")
    return 0.5 * 10.0 ** (int(exponent or 0) - len(mantissa.partition(".")[2]))


def shown(text: str, value: float) -> bool:
    """``text`` is ``value`` to the digits it shows."""
    return float(text) == pytest.approx(value, rel=0, abs=half_unit(text) * (1 + 1e-9))


@pytest.fixture
def figures(monkeypatch):
    """Every matplotlib figure a command saves, kept for the test to read."""
    from matplotlib.figure import Figure

    kept, save = [], Figure.savefig

    def keep(self, *args, **kwargs):
        kept.append(self)
        return save(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    return kept


# --- --plot: the format its suffix names --------------------------------------------------------

MAGIC = {"png": (b"\x89PNG\r\n\x1a\n",), "pdf": (b"%PDF-",), "svg": (b"<?xml", b"<svg")}
PLOTS = [
    (("modes", "conveyor"), "out.png"),
    (("modes", "conveyor"), "out.pdf"),
    (("modes", "conveyor"), "out.svg"),
    (("modes", "conveyor"), "OUT.PDF"),             # the suffix in any case
    (("response", "conveyor", "--points", "50"), "bode.pdf"),
    (("campbell", "conveyor"), "campbell.svg"),
    (("simulate", "linear-axis"), "axis.pdf"),
    (("simulate", "sewing", "--steady-state-only", "--sweep", "C4=100N*m/rad:300N*m/rad:2"), "sweep.svg"),
    (("simulate", "sewing", *VARY, "--runs", "20", "--workers", "1"), "study.pdf"),
    (("motor-size",), "profile.pdf"),
    (("motor-size", "--sweep", "accel=100rad/s^2:1000rad/s^2:3"), "sweep.svg"),
]


@pytest.mark.parametrize("args, name", PLOTS, ids=[f"{'-'.join(a[:2])}-{n}" for a, n in PLOTS])
def test_plot_writes_the_format_its_suffix_names(args, name, tmp_path):
    path = tmp_path / name
    result = ok(run(*args, "--plot", str(path)))
    assert result.stderr.splitlines()[-1] == f"wrote {path}"
    head = path.read_bytes()[:64]
    assert head.startswith(MAGIC[name.rsplit(".", 1)[1].lower()]), head
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]      # no temporary left


@pytest.mark.parametrize("args, name", [
    (("modes", "conveyor"), "out.jpg"),
    (("simulate", "sewing"), "out.eps"),
    (("campbell",), "out"),                             # no suffix: no format named
    (("motor-size",), "profile.png.txt"),
])
def test_plot_refuses_another_suffix_in_one_line_before_any_work(args, name, tmp_path):
    line = one_error_line(run(*args, "--plot", str(tmp_path / name)), 2, "--plot", name, ".png, .pdf or .svg")
    assert ("not '.jpg'" in line) if name.endswith(".jpg") else True
    assert list(tmp_path.iterdir()) == []


def test_a_device_without_a_suffix_gets_png():
    from beltcalc.cli.output import plot_format

    assert plot_format("/dev/null") == "png"
    with pytest.raises(ValueError, match=r"'plot' has no suffix: a plot is written as \.png, \.pdf or \.svg"):
        plot_format("plot")


# --- tables: a number is never cut -----------------------------------------------------------------

def header_cells(text: str, title: str) -> list[str]:
    lines = text[text.index(title):].splitlines()
    head = next(line for line in lines if line.startswith("┃"))
    return [c.strip() for c in head.strip("┃").split("┃")]


def test_response_tables_never_cut_a_number_on_an_80_column_terminal():
    # the magnitude table is about 150 columns wide: it used to print "3.006e-…" at 140
    text = ok(run("response", "conveyor", env={"COLUMNS": "80"})).stdout
    obj = json.loads(ok(run("response", "conveyor", "--json")).stdout)
    assert "…" not in text
    freq = obj["frequency"]["value"]
    pairs = [(r["output"], r["input"]) for r in obj["responses"]]
    by_pair = {(r["output"], r["input"]): r for r in obj["responses"]}

    # resonance peaks: frequency, |H| and Q of every peak, in the JSON's order
    peaks = [(r["output"], r["input"], p) for r in obj["responses"] for p in r["peaks"]]
    rows = table_rows(text, "resonance peaks of |H|")
    assert len(rows) == len(peaks) > 10
    for (y, u, p), (ty, tu, f, mag, _, q) in zip(peaks, rows):
        assert (ty, tu) == (y, u)
        assert shown(f, p["frequency"]["value"]) and shown(mag, p["magnitude"]["value"]) and shown(q, p["q"]["value"])

    # magnitude and phase at some of the frequencies: each heading a frequency of the JSON, each cell its value
    title = "magnitude and phase at some of the frequencies"
    heads = header_cells(text, title)[3:]
    assert len(heads) == 8
    picks = []
    for h in heads:
        k = min(range(len(freq)), key=lambda i: abs(freq[i] - float(h)))
        assert shown(h, freq[k])
        picks.append(k)
    rows = table_rows(text, title)
    assert len(rows) == 2 * len(pairs)
    checked = 0
    for (y, u), mag_row, phase_row in zip(pairs, rows[::2], rows[1::2]):
        assert mag_row[:2] == [y, u] and phase_row[2] == "phase [deg]"
        mag, phase = by_pair[(y, u)]["magnitude"]["value"], by_pair[(y, u)]["phase"]["value"]
        for k, a, b in zip(picks, mag_row[3:], phase_row[3:]):
            assert shown(a, mag[k]), (y, u, freq[k], a, mag[k])
            assert shown(b, math.degrees(phase[k])), (y, u, freq[k], b, phase[k])
            checked += 2
    assert checked == 2 * 8 * len(pairs)


def test_a_table_on_a_narrow_console_wraps_its_text_and_keeps_its_numbers_whole():
    from rich.table import Table

    from beltcalc.cli.output import _console_class

    table = Table(title="narrow")
    for col in ("quantity", "value", "unit", "note"):
        table.add_column(col, justify="right" if col == "value" else "left")
    numbers = ["3.006e-05", "-1234567", "0.0001234", "12.5%", "-"]
    for x in numbers:
        table.add_row("torque, peak (dynamic) of the motor", x, "N m", "at t = 0.1 s (left limit: the end of a phase)")
    buf = io.StringIO()
    out = _console_class()(width=40, file=buf, soft_wrap=False, emoji=False, color_system=None)
    out.print(table)
    text = buf.getvalue()
    assert out.width == 40                                           # as it was, after
    values = [row[1] for row in table_rows(text, "narrow") if row[1]]
    assert values == numbers                                         # each whole, on its row's first line
    assert "…" not in text
    assert max(map(len, text.splitlines())) > 40                     # printed wider than the console


# --- limit lines: their own style, and a label ------------------------------------------------------

def test_simulate_plot_draws_the_peak_and_rms_limits_in_styles_of_their_own(figures, tmp_path):
    result = ok(run("simulate", "linear-axis", "--json", "--plot", str(tmp_path / "axis.png")))
    checks = {c["key"]: c for c in json.loads(result.stdout)["checks"]}
    fig, = figures
    ax = next(a for a in fig.axes if a.get_ylabel() == "motor torque [N m]")
    hlines = [ln for ln in ax.get_lines() if len(set(ln.get_ydata())) == 1 and len(ln.get_ydata()) == 2]
    named = {ln.get_label(): ln for ln in hlines if not ln.get_label().startswith("_")}
    assert set(named) == {"motor peak torque limit (+-)", "motor RMS torque limit (+-)"}
    peak, rms = named["motor peak torque limit (+-)"], named["motor RMS torque limit (+-)"]
    assert peak.get_ydata()[0] == pytest.approx(checks["motor_peak_torque"]["limit"]["value"], rel=1e-12)   # 6.69 N m
    assert rms.get_ydata()[0] == pytest.approx(checks["motor_rms_torque"]["limit"]["value"], rel=1e-12)     # 1.91 N m
    assert (peak.get_color(), peak.get_linestyle()) != (rms.get_color(), rms.get_linestyle())
    assert peak.get_color() != rms.get_color() and peak.get_linestyle() != rms.get_linestyle()
    # each limit's mirror at -level is drawn alike, without a second legend entry
    for ln in (peak, rms):
        mirror, = [m for m in hlines if m.get_ydata()[0] == pytest.approx(-ln.get_ydata()[0], rel=1e-12)]
        assert (mirror.get_color(), mirror.get_linestyle()) == (ln.get_color(), ln.get_linestyle())
        assert mirror.get_label().startswith("_")
    assert {t.get_text() for t in ax.get_legend().get_texts()} >= set(named)


def test_study_plot_draws_two_limits_of_one_output_in_styles_of_their_own(figures, tmp_path):
    ok(run("simulate", "sewing", *VARY, "--runs", "20", "--workers", "1", "--limit", "main_torque_amplitude_N_m<=0.2N*m",
           "--limit", "main_torque_amplitude_N_m>=40N*mm", "--plot", str(tmp_path / "study.png")))
    fig, = figures
    ax = next(a for a in fig.axes if a.get_xlabel().startswith("main shaft (3): transmitted torque, amplitude"))
    vlines = [ln for ln in ax.get_lines() if len(set(ln.get_xdata())) == 1]
    assert sorted(ln.get_label() for ln in vlines) == ["limit <= 0.2", "limit >= 0.04"]
    assert sorted(ln.get_xdata()[0] for ln in vlines) == pytest.approx([0.04, 0.2], rel=1e-12)
    a, b = vlines
    assert a.get_color() != b.get_color() and a.get_linestyle() != b.get_linestyle()
    assert {t.get_text() for t in ax.get_legend().get_texts()} == {"limit <= 0.2", "limit >= 0.04"}


# --- Campbell labels ---------------------------------------------------------------------------------

def test_campbell_labels_are_rounded_and_do_not_overlap(figures, tmp_path):
    # three order lines within 5 % of each other end 0.6 Hz apart, about 2 px on the plot
    result = ok(run("campbell", "conveyor", "--orders", "1,1.02,1.05,2,0.199899", "--json",
                    "--plot", str(tmp_path / "c.png")))
    obj = json.loads(result.stdout)
    fig, = figures
    ax, = fig.axes
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()         # the figure was closed once saved
    labels = [t for t in ax.texts if t.get_visible()]
    orders = sorted(t.get_text().strip() for t in labels if "order" in t.get_text())
    assert orders == ["order 0.1999", "order 1", "order 1.02", "order 1.05", "order 2"]
    f_top = ax.get_ylim()[1]
    modes = [m for m in obj["modes"] if m["frequency"]["value"] <= f_top]
    assert len([t for t in labels if "mode" in t.get_text()]) == len(modes) == 3
    boxes = [t.get_window_extent(renderer) for t in labels]
    height = max(b.height for b in boxes)
    for side in ("left", "right"):                 # order labels right of the edge, mode labels left of it
        ys = sorted(b.y0 for t, b in zip(labels, boxes) if t.get_horizontalalignment() == side)
        gap = min(b - a for a, b in zip(ys, ys[1:]))
        assert gap >= height or gap == pytest.approx(height, rel=1e-9), (side, gap, height)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a, b)
    # the lowest of the crowded labels stays at its line's end: order 1 at the top speed, in Hz
    one = next(t for t in labels if t.get_text().strip() == "order 1")
    assert one.get_position()[1] == pytest.approx(obj["speed_max"]["value"] / (2 * math.pi), rel=1e-9)


# --- study keys and labels -----------------------------------------------------------------------------

def test_a_study_key_and_its_label_name_the_same_quantity():
    from beltcalc.sim.result import unit_tag

    study = json.loads(ok(run("simulate", "sewing", *VARY, "--runs", "20", "--workers", "1", "--json")).stdout)
    single = json.loads(ok(run("simulate", "sewing", "--json")).stdout)
    labels = {c["key"]: c["label"] for c in study["columns"]}
    outputs = study["outputs"]
    for key in outputs:
        assert key.startswith("steady_") == ("steady" in labels[key]), (key, labels[key])
    # each key's nominal value is the single run's figure it names: the window's, or the steady state's
    where = {"main": ("shafts", "main"), "bottom": ("shafts", "bottom"), "motor": ("motor",),
             "steady_main": ("steady_state", "main_shaft"), "steady_bottom": ("steady_state", "bottom_shaft"),
             "steady_motor": ("steady_state", "motor_steady")}
    compared = 0
    for prefix, path in where.items():
        section = single
        for part in path:
            section = section[part]
        for row, q in section.items():
            key = f"{prefix}_{row}_{unit_tag(q['unit'].replace('*', ' '))}"
            assert outputs[key]["nominal"]["value"] == pytest.approx(q["value"], rel=1e-12), key
            compared += 1
    assert compared == len(outputs) == 26
    # the window's and the steady state's amplitudes differ by more than the tolerance above:
    # a key naming the other one fails
    window = outputs["main_speed_amplitude_rad_per_s"]["nominal"]["value"]
    steady = outputs["steady_main_speed_amplitude_rad_per_s"]["nominal"]["value"]
    assert window != pytest.approx(steady, rel=1e-8)


# --- modes: every element over 10 % ----------------------------------------------------------------------

@pytest.mark.parametrize("drive", ["conveyor", "sewing", "friswell_5_disks"])
def test_modes_names_every_element_over_ten_percent_of_the_strain_energy(drive):
    text = ok(run("modes", drive)).stdout
    obj = json.loads(ok(run("modes", drive, "--json")).stdout)
    shapes = [m["shape"] for m in obj["modes"] if m["kind"] == "oscillatory"]
    lines = re.findall(r"^mode (\d+): .*?; strain energy: (.*)$", text, re.MULTILINE)
    assert [int(k) for k, _ in lines] == list(range(1, len(shapes) + 1))
    for (_, listed), shape in zip(lines, shapes):
        named = re.findall(r"(\S+) \(([\d.]+) %\)", listed)
        shares = {e: q["value"] for e, q in shape["strain_energy"].items()}
        big = [e for e, s in sorted(shares.items(), key=lambda es: -es[1]) if s > 0.10] or [max(shares, key=shares.get)]
        assert [e for e, _ in named] == big
        for e, pct in named:
            assert shown(pct, 100 * shares[e])


def test_modes_names_both_belt_spans_of_the_conveyors_second_mode():
    # the conveyor's mode 2 keeps 34 % of its energy in each belt span (docs/frequency_domain.md)
    text = ok(run("modes", "conveyor")).stdout
    line = next(ln for ln in text.splitlines() if ln.startswith("mode 2:"))
    assert "upper (34.4 %), lower (34.4 %)" in line


# --- a quiet Dask -------------------------------------------------------------------------------------------

SCRIPT = """\
from beltcalc.sim.core import SolverConfig
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.study.execution import DASK_MIN_RUNS
from beltcalc.sim.study.sweeps import grid_scene

spec = SCENES["sewing"]
_, resolved = spec.resolve("sewing", {})
values = {k: v.value for k, v in resolved.items()}
points = [200.0 + i for i in range(DASK_MIN_RUNS + 1)]
sweep = grid_scene(spec, values, [("C4", points)], SolverConfig(), workers=2, steady_state_only=True)
print(len(sweep.runs), sum(r.error is None for r in sweep.runs), sweep.how)
"""


@pytest.mark.slow
def test_a_script_without_a_main_guard_runs_a_study_on_a_local_cluster(tmp_path):
    # spawn runs a script again in each worker process: unguarded, the study used to start again
    # in each ("Nanny failed to start", pages of multiprocessing errors)
    pytest.importorskip("distributed")
    script = tmp_path / "my_study.py"
    script.write_text(SCRIPT)
    res = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    assert res.stdout.split() == ["201", "201", "dask", "local", "cluster,", "2", "workers"]


def test_a_guarded_script_and_the_top_level_of_an_unguarded_one_are_told_apart(tmp_path):
    body = textwrap.dedent("""\
        import json
        from beltcalc.sim.study.cluster import unguarded_script

        def where():
            return unguarded_script()

        top = where()
        if __name__ == "__main__":
            print(json.dumps([top, where()]))
        """)
    script = tmp_path / "s.py"
    script.write_text(body)
    res = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout) == [True, False]
    res = subprocess.run([sys.executable, "-c", "from beltcalc.sim.study.cluster import unguarded_script as u; print(u())"],
                         capture_output=True, text=True, timeout=60)
    assert res.stdout.strip() == "False"                 # no script file: nothing is run again


@pytest.mark.slow
def test_a_study_on_two_workers_prints_no_dask_log_line(tmp_path):
    pytest.importorskip("distributed")
    beltcalc = Path(sys.executable).with_name("beltcalc")
    out = tmp_path / "rows.csv"
    res = subprocess.run([str(beltcalc), "simulate", "sewing", "--steady-state-only", *VARY, "--runs", "201",
                          "--workers", "2", "--json", "--csv", str(out)], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["execution"] == "dask local cluster, 2 workers"
    assert res.stderr.splitlines() == [f"wrote {out}"]


def test_a_local_cluster_that_does_not_start_is_one_line_saying_what_to_do(monkeypatch):
    distributed = pytest.importorskip("distributed")
    import logging

    def no_cluster(*args, **kwargs):
        raise RuntimeError("Nanny failed to start.")

    monkeypatch.setattr(distributed, "LocalCluster", no_cluster)
    before = {name: logging.getLogger(name).level for name in ("distributed", "distributed.client", "tornado")}
    line = one_error_line(run("simulate", "sewing", "--steady-state-only", *VARY, "--runs", "201", "--workers", "2"),
                          1, "the local Dask cluster of 2 workers did not start (RuntimeError: Nanny failed to start.)",
                          'if __name__ == "__main__":', "--workers 1")
    assert "`" not in line
    # Dask's loggers are back at their levels
    assert {name: logging.getLogger(name).level for name in before} == before
