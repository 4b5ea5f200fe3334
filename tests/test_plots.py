"""The library's figures (beltcalc/plots.py) and ``SimResult.plot``: the panels and lines a
run's figure holds, a PNG written as one, and matplotlib loaded only when a figure is drawn."""

from __future__ import annotations

import subprocess
import sys

import pytest

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result():
    import beltcalc

    return beltcalc.simulate(beltcalc.load_drive("minimal"))


def test_a_result_plots_every_node_speed_by_default(result):
    pytest.importorskip("matplotlib")
    fig = result.plot()
    (ax,) = fig.axes                                   # one unit, one panel
    assert ax.get_ylabel() == "[rad/s]" and ax.get_xlabel() == "time [s]"
    assert [ln.get_label() for ln in ax.get_lines()] == ["omega_rotor", "omega_pulley1", "omega_pulley2"]
    line = ax.get_lines()[2]
    assert list(line.get_xdata()) == list(result.t) and list(line.get_ydata()) == list(result["omega_pulley2"])


def test_a_result_plots_one_panel_per_unit_with_the_window_shaded(result):
    pytest.importorskip("matplotlib")
    fig = result.plot(["omega_rotor", "M_motor", "T_jaw", "F_tight"], window=2.0)
    assert [ax.get_ylabel() for ax in fig.axes] == ["[rad/s]", "[N m]", "[N]"]
    assert [[ln.get_label() for ln in ax.get_lines()] for ax in fig.axes] == [["omega_rotor"], ["M_motor", "T_jaw"],
                                                                             ["F_tight"]]
    (span,) = fig.axes[0].patches                      # the steady window, from 2 s to the end
    x0, x1 = span.get_x(), span.get_x() + span.get_width()
    assert (x0, x1) == pytest.approx((2.0, float(result.t[-1])))
    assert "steady window" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_a_result_refuses_a_signal_it_does_not_have(result):
    from beltcalc.errors import UnknownNameError

    pytest.importorskip("matplotlib")
    with pytest.raises(UnknownNameError, match=r"no signal 'omega_rotr' in this result; did you mean omega_rotor"):
        result.plot(["omega_rotr"])


def test_a_result_writes_a_png(result, tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "speeds.png"
    fig = result.plot(path=path)
    assert path.read_bytes()[:8] == PNG
    assert len(fig.axes) == 1


def test_a_plot_path_without_a_known_suffix_is_an_output_error(result, tmp_path):
    from beltcalc.errors import OutputError

    pytest.importorskip("matplotlib")
    with pytest.raises(OutputError, match=r"a plot is written as \.png, \.pdf or \.svg .*not '\.jpg'"):
        result.plot(path=tmp_path / "speeds.jpg")
    assert not (tmp_path / "speeds.jpg").exists()


def test_importing_plots_loads_no_matplotlib_scipy_or_pint():
    code = ("import sys, beltcalc.plots; "
            "print(sorted(m for m in ('matplotlib', 'scipy', 'pint') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_a_result_plot_leaves_pyplot_and_the_backend_alone():
    # a notebook user's backend is never switched: the figure is made outside pyplot
    pytest.importorskip("matplotlib")
    code = ("import sys, beltcalc; r = beltcalc.simulate(beltcalc.load_drive('minimal')); fig = r.plot(); "
            "print('matplotlib.pyplot' in sys.modules, type(fig).__name__, len(fig.axes))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "Figure", "1"]
