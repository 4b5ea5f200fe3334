"""Figures of the library's results: each builder returns a matplotlib ``Figure`` drawn from
library objects and SI data (shown in the units its axes name), and :func:`save_figure`
writes one as PNG, PDF or SVG by the file's suffix.

matplotlib (``pip install "beltcalc[plot]"``) is imported inside the functions only, and
figures are made outside pyplot (no display needed, no backend switched, nothing to close):
``import beltcalc.plots`` loads neither matplotlib nor
scipy nor pint. The command line's ``--plot`` draws with these builders
(:meth:`beltcalc.sim.result.SimResult.plot` too).

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the energy of the acceleration phase [W21 eq. 29].
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from beltcalc.errors import OutputError
from beltcalc.report import denoise, format_number, rpm, unit_label

PLOT_FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}   # a file's suffix -> its format

# (color, line style) of a plot's limit lines, one each: two limits on one panel (a motor's
# peak and RMS torque) never look alike
LIMIT_STYLES = (("tab:red", "--"), ("tab:purple", ":"), ("tab:brown", "-."), ("tab:olive", (0, (6, 2, 1, 2, 1, 2))),
                ("tab:pink", (0, (1, 3))))


def _new_figure(size: tuple[float, float]):
    """A matplotlib ``Figure`` of ``size`` inches, outside pyplot: no backend is chosen or
    switched (a notebook keeps its own) and no global registry holds it."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size)
    FigureCanvasAgg(fig)           # a renderer for text extents (Campbell's labels), as pyplot's Agg gave
    return fig


def _subplots(rows: int, cols: int, size: tuple[float, float], **kw):
    fig = _new_figure(size)
    return fig, fig.subplots(rows, cols, squeeze=False, **kw)


def plot_format(path, in_place: bool | None = None) -> str:
    """The format a figure is written in to ``path``: the one its suffix names (``.png``,
    ``.pdf``, ``.svg``, in any case); a path with no suffix written in place (``in_place``;
    None: one that exists and is neither a regular file nor a folder, a device or a FIFO such
    as ``/dev/stdout``) gets PNG. Another suffix, or none, is an
    :class:`~beltcalc.errors.OutputError` saying what is allowed.

    >>> plot_format("out.PDF"), plot_format("a/b.svg"), plot_format("/dev/null")
    ('pdf', 'svg', 'png')
    >>> plot_format("out.jpg")
    Traceback (most recent call last):
    ...
    beltcalc.errors.OutputError: 'out.jpg': a plot is written as .png, .pdf or .svg (the suffix names the format), not '.jpg'
    """
    from beltcalc.units import quote

    suffix = Path(path).suffix
    if suffix.lower() in PLOT_FORMATS:
        return PLOT_FORMATS[suffix.lower()]
    allowed = "a plot is written as .png, .pdf or .svg (the suffix names the format)"
    if suffix:
        raise OutputError(f"{quote(str(path), 200)}: {allowed}, not {quote(suffix, 40)}")
    if in_place is None:
        in_place = os.path.exists(path) and not (os.path.isfile(path) or os.path.isdir(path))
    if in_place:
        return "png"
    raise OutputError(f"{quote(str(path), 200)} has no suffix: {allowed}")


def save_figure(fig, path, dpi: int = 110, fmt: str | None = None, write=None) -> None:
    """Write the figure ``fig`` to ``path`` in the format ``fmt`` (default: the one its suffix
    names, :func:`plot_format`) at ``dpi`` dots per inch. ``write(path, fill)`` puts the file in
    place, ``fill(tmp)`` writing its bytes to ``tmp`` (the command line's one writer, atomic);
    default: saved to ``path`` itself."""
    fmt = plot_format(path) if fmt is None else fmt
    if write is None:
        fig.savefig(path, dpi=dpi, format=fmt)
    else:
        write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=fmt))


def limit_style(k: int) -> dict:
    """Keyword arguments of matplotlib's ``axhline``/``axvline`` for the ``k``-th limit line
    of a panel (:data:`LIMIT_STYLES`, cycling).

    >>> limit_style(0), limit_style(1)["ls"]
    ({'color': 'tab:red', 'ls': '--', 'lw': 1.0}, ':')
    """
    color, ls = LIMIT_STYLES[k % len(LIMIT_STYLES)]
    return {"color": color, "ls": ls, "lw": 1.0}


# --- time series and sweeps --------------------------------------------------------------------------
def panels_figure(xlabel: str, panels, size: tuple[float, float], ylabel_size=None, limits=None, span=None):
    """A figure of ``panels`` (ylabel, [(x, y, style, legend or None)]) stacked over one x
    axis, each ``size`` (width, height) [in]; ``limits[k]`` are the limit lines (level,
    legend, at +-level) of panel k, each of its own color and line style (:func:`limit_style`)
    and named in the legend; ``span`` a shaded (start, end) of the x axis (the steady window)."""
    fig, axes = _subplots(len(panels), 1, (size[0], size[1] * len(panels)), sharex=True)
    for k, (ax, (ylabel, lines)) in enumerate(zip(axes[:, 0], panels)):
        for x, y, style, label in lines:
            ax.plot(x, y, style, label=label)
        for j, (level, label, both) in enumerate(limits[k] if limits else ()):
            ax.axhline(level, label=label, **limit_style(j))
            if both:
                ax.axhline(-level, **limit_style(j))
        if span is not None:
            ax.axvspan(*span, color="0.5", alpha=0.12, lw=0, label="steady window" if k == 0 else None)
        ax.set_ylabel(ylabel, fontsize=ylabel_size)
        if any(label for *_, label in lines) or (limits and limits[k]) or (span is not None and k == 0):
            ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel(xlabel)
    fig.tight_layout()
    return fig


def signals_figure(result, signals: list[str], window: float | None = None):
    """The ``signals`` of a :class:`~beltcalc.sim.result.SimResult` over time, in SI: one panel
    per unit (in the order the units first come), one line per signal; ``window`` [s] the
    start of a steady window, shaded to the run's end."""
    panels: dict[str, list] = {}
    for name in signals:
        panels.setdefault(result.units[name], []).append((result.t, result[name], "-", name))
    return panels_figure("time [s]", [(f"[{unit_label(unit)}]", lines) for unit, lines in panels.items()], (8, 2.7),
                         span=None if window is None else (window, float(result.t[-1])))


def scene_figure(scene, outcome, window: float | None = None):
    """A scene's run: the panels of its ``plot`` (ylabel, [(signal, legend)]) over time, each
    in the unit its label names (``[mm]``), with the limit of every check of ``outcome`` that
    bounds a plotted signal (at +-limit where the signal changes sign) and the steady window
    from ``window`` [s] shaded."""
    from beltcalc.units import convert

    result = outcome.result
    panels, limits = [], []
    for ylabel, lines in scene.plot:
        shown = [s for s, _ in lines if s in result.signals]
        unit = ylabel[ylabel.rfind("[") + 1:-1] if ylabel.endswith("]") else ""
        unit = unit.replace(" ", "*")

        def to_panel(value, si, unit=unit):
            return value if not unit or si == unit else convert(value, si, unit)

        panels.append((ylabel, [(result.t, to_panel(result[s], result.units[s]), "-", label)
                                for s, label in lines if s in result.signals]))
        here: dict[float, list] = {}        # one line per level, naming every check at it
        for c in outcome.checks:
            hit = [s for s in c.signals if s in shown]
            if c.limit is None or not hit:
                continue
            # a safety factor's check bounds its signals at ``level`` (in their unit), not at its limit
            level = float(to_panel(c.limit, c.unit) if c.level is None else to_panel(c.level, result.units[hit[0]]))
            both = any(float(to_panel(result[s], result.units[s]).min()) < -0.1 * level for s in hit)
            names, was = here.get(level, ([], False))
            here[level] = (names + [c.name], was or both)
        limits.append([(level, " / ".join(names) + " limit" + (" (+-)" if both else ""), both)
                       for level, (names, both) in here.items()])
    return panels_figure("time [s]", panels, (8, 2.7), limits=limits,
                         span=None if window is None else (window, float(result.t[-1])))


def sweep_figure(columns, table, swept: int = 1):
    """A sweep: one panel per column of ``columns`` (:class:`~beltcalc.report.Column`) past
    the ``swept`` ones, against the first swept value, in display units; ``table`` its rows
    in SI (None where a run gave none); with several swept values, one line per combination
    of the others (at most 8)."""
    from beltcalc.units import convert

    groups: dict[tuple, list] = {}
    for r in table:
        groups.setdefault(tuple(r[1:swept]), []).append(r)
    if len(groups) > 8:
        keep = list(groups)[:: -(-len(groups) // 8)]
        groups = {k: groups[k] for k in keep}

    def legend(k):
        return ", ".join(f"{c.label} = {format_number(convert(v, c.unit, c.display), 4)} {unit_label(c.display)}"
                         for c, v in zip(columns[1:swept], k)) or None

    panels = [(f"{c.label}\n[{unit_label(c.display)}]",
               [([convert(r[0], columns[0].unit, columns[0].display) for r in rows],
                 [None if r[i] is None else convert(r[i], c.unit, c.display) for r in rows], "o-", legend(k))
                for k, rows in groups.items()])
              for i, c in enumerate(columns) if i >= swept]
    return panels_figure(f"{columns[0].label} [{unit_label(columns[0].display)}]", panels, (7, 2.4), ylabel_size=7)


# --- frequency domain ---------------------------------------------------------------------------------
def modes_figure(modes, nodes: list[str], title: str):
    """Bars of each oscillatory mode's shape of :class:`~beltcalc.sim.frequency_report.Modes`:
    every node of ``nodes``' amplitude (orange where it moves against the largest), the mode's
    frequency, damping ratio and the elements holding its strain energy; ``title`` the drive's."""
    shapes = list(zip(modes.oscillatory(), modes.shapes))
    if not shapes:
        fig, axes = _subplots(1, 1, (6, 2))
        axes[0, 0].text(0.5, 0.5, "no oscillatory mode", ha="center", va="center")
        axes[0, 0].set_axis_off()
        fig.tight_layout()
        return fig
    cols = 1 if len(shapes) <= 4 else 2
    rows = math.ceil(len(shapes) / cols)
    fig, axes = _subplots(rows, cols, (max(6.0, 0.5 * len(nodes)) * cols, 2.2 * rows))
    x = range(len(nodes))
    for k, ((p, s), ax) in enumerate(zip(shapes, axes.flat), 1):
        amp = [s.amplitude[n] for n in nodes]
        against = [abs(s.phase[n]) > 90 for n in nodes]
        ax.bar(x, amp, color=["tab:orange" if a else "tab:blue" for a in against])
        ax.set_xticks(list(x), nodes, fontsize=7, rotation=45 if len(nodes) > 8 else 0)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("amplitude", fontsize=8)
        where = "; " + ", ".join(f"{e} {100 * v:.0f} %" for e, v in s.shares()) if s.dominant else ""
        ax.set_title(f"mode {k}: {p.frequency:.4g} Hz, zeta {denoise(p.damping_ratio):.3g}{where}", fontsize=8)
    for ax in list(axes.flat)[len(shapes):]:
        ax.set_axis_off()
    fig.suptitle(f"{title}: mode shapes (orange: against the largest)", fontsize=9)
    fig.tight_layout()
    return fig


def response_figure(response, title: str):
    """The Bode plot of a :class:`~beltcalc.sim.frequency.Response`: |H| and phase [deg] of
    every pair over frequency [Hz], the resonance peaks circled; ``title`` the drive's."""
    f = response.omega / (2 * math.pi)
    fig, axes = _subplots(2, 1, (8, 6), sharex=True)
    mag_ax, ph_ax = axes[:, 0]
    for y, u, unit in response.pairs():
        line, = mag_ax.loglog(f, response.magnitude(y, u), "-" if f.size > 1 else "o", label=f"{y} / {u} [{unit}]")
        peaks = response.peaks[(y, u)]
        if peaks:
            mag_ax.plot([p[0] for p in peaks], [p[1] for p in peaks], "o", color=line.get_color(), fillstyle="none")
        ph_ax.semilogx(f, response.phase(y, u), "-" if f.size > 1 else "o", color=line.get_color())
    mag_ax.set_ylabel("|H|")
    mag_ax.legend(fontsize=7)
    mag_ax.set_title(f"{title}: frequency response (circles: resonance peaks)", fontsize=9)
    ph_ax.set_ylabel("phase [deg]")
    ph_ax.set_xlabel("frequency [Hz]")
    for ax in (mag_ax, ph_ax):
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    return fig


def campbell_figure(campbell, title: str):
    """The Campbell diagram of a :class:`~beltcalc.sim.frequency_report.Campbell`: modes as
    horizontal lines, orders as rays from the origin, the crossings marked, speed in rpm;
    each line labelled at the right edge (orders to 4 significant digits), the labels of each
    edge moved apart where they would overlap (:func:`spread`) and left out where the height
    holds no more; ``title`` the drive's."""
    c = campbell
    fig, axes = _subplots(1, 1, (8, 5))
    ax = axes[0, 0]
    top_speed = rpm(c.speed_max)
    lines = [k * c.speed_max / (2 * math.pi) for k in c.orders]
    crossed = [x.frequency for x in c.crossings]
    f_top = 1.25 * max(lines + crossed + ([c.modes[0].frequency] if c.modes else []))
    mode_labels, order_labels = [], []
    for k, p in enumerate(c.modes, 1):
        if p.frequency <= f_top:
            ax.axhline(p.frequency, color="tab:blue", lw=1)
            mode_labels.append(ax.text(top_speed, p.frequency, f" mode {k}: {p.frequency:.4g} Hz", va="bottom",
                                       ha="right", fontsize=7))
    for k, f_end in zip(c.orders, lines):
        ax.plot([0, top_speed], [0, f_end], "--", color="gray", lw=1)
        order_labels.append(ax.text(top_speed, min(f_end, f_top), f" order {k:.4g}", va="bottom", ha="left",
                                    fontsize=7))
    ax.plot([rpm(x.speed) for x in c.crossings], crossed, "o", color="tab:red", label="crossings")
    if c.operating_speed:
        ax.axvline(rpm(c.operating_speed), color="black", ls=":", lw=1, label="operating (synchronous) speed")
    ax.set_xlim(rpm(c.speed_min), top_speed * 1.08)
    ax.set_ylim(0, f_top)
    ax.set_xlabel(f"speed of node {c.reference} [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{title}: Campbell diagram", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()       # the axes' final size: the labels are moved apart in its pixels
    for texts in (mode_labels, order_labels):     # each edge's labels: modes left of it, orders right
        _unstack(fig, ax, texts)
    return fig


def stroke_map_figure(smap, title: str, band: tuple[float, float] | None = None, modes: int = 3):
    """The resonance map of a :class:`~beltcalc.sim.stroke_map.StrokeMap`: the natural
    frequency of each of its first ``modes`` modes against the carriage's position [mm], the
    lowest first frequency marked, and an excitation ``band`` (low, high) [Hz] shaded (None:
    none); below it the static deflection per newton on the carriage, 1 / k; ``title`` the
    drive's."""
    import numpy as np

    fig, axes = _subplots(2, 1, (8, 6.5))
    ax = axes[0, 0]
    x = smap.positions * 1e3
    for k in range(min(modes, smap.modes)):
        ax.plot(x, smap.frequency[:, k], "-" if x.size > 2 else "o-", lw=1.5, label=f"mode {k + 1}")
    ax.plot([smap.lowest_at * 1e3], [smap.lowest], "o", color="tab:red", fillstyle="none", clip_on=False,
            label=f"lowest: {smap.lowest:.4g} Hz at {smap.lowest_at * 1e3:.4g} mm")
    if band is not None:
        ax.axhspan(band[0], band[1], color="tab:orange", alpha=0.2, lw=0,
                   label=f"excitation band {band[0]:.4g} to {band[1]:.4g} Hz")
    top = float(np.nanmax(smap.frequency[:, :min(modes, smap.modes)]))
    ax.set_ylim(0, 1.1 * max(top, band[1] if band is not None else 0.0))
    ax.set_xlim(float(x[0]), float(x[-1]))
    ax.set_ylabel("natural frequency [Hz]")
    ax.set_title(f"{title}: modes along the stroke", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    # the static positioning error per newton on the carriage: the belt's compliance 1 / k
    low = axes[1, 0]
    low.plot(x, 1e6 / smap.stiffness, "-", lw=1.5, color="tab:green")
    low.set_xlim(float(x[0]), float(x[-1]))
    low.set_ylim(0, None)
    low.set_ylabel("static deflection [um/N]")
    low.set_xlabel(f"carriage position x [mm] (carriage belt {smap.belt!r}: span 1 = {smap.span1[0] * 1e3:.4g} mm + x)")
    low.set_title("static positioning error per newton on the carriage: 1 / k, both spans (docs/positioning.md)",
                  fontsize=9)
    fig.tight_layout()
    return fig


def _unstack(fig, ax, texts) -> None:
    """Move the labels ``texts`` (one edge's, bottom-aligned) apart to at least one text height
    (in the figure's pixels) inside the axes' height; hide those that do not fit."""
    if not texts:
        return
    renderer = fig.canvas.get_renderer()
    gap = 1.15 * max(t.get_window_extent(renderer).height for t in texts)
    to_px, to_data = ax.transData, ax.transData.inverted()
    (_, low), (_, high) = ax.transAxes.transform((0, 0)), ax.transAxes.transform((0, 1))
    ys = [to_px.transform(t.get_position())[1] for t in texts]
    for t, y in zip(texts, spread(ys, gap, low, high - gap)):
        if y is None:
            t.set_visible(False)
        else:
            t.set_y(to_data.transform((0, y))[1])


def spread(ys: list[float], gap: float, low: float, high: float) -> list[float | None]:
    """Positions as near ``ys`` as keep each at least ``gap`` from its neighbours, inside
    ``[low, high]``, in the order of ``ys``; None for those there is no room for (the lowest:
    the room holds ``(high - low) / gap + 1`` of them).

    >>> spread([5.0, 5.5, 20.0, 6.0], 2.0, 0.0, 100.0)
    [5.0, 7.0, 20.0, 9.0]
    >>> spread([99.0, 99.5], 2.0, 0.0, 100.0)
    [98.0, 100.0]
    >>> spread([1.0, 1.1, 1.2], 2.0, 0.0, 2.0)
    [None, 0.0, 2.0]
    """
    order = sorted(range(len(ys)), key=ys.__getitem__)
    room = int((high - low) // gap) + 1 if high >= low else 0
    order = order[max(len(order) - room, 0):]          # the lowest labels go first
    out: list[float | None] = [None] * len(ys)
    below = -math.inf
    for i in order:                                    # upward: each at least gap above the last
        out[i] = below = max(ys[i], low, below + gap)
    above = math.inf
    for i in reversed(order):                          # downward: under the top, gap below the next
        out[i] = above = min(out[i], high, above - gap)
    return out


# --- motor sizing -------------------------------------------------------------------------------------
def profile_figure(sizing):
    """A :class:`~beltcalc.design.sizing.CycleSizing`'s motor over the cycle: torque [N m] and
    speed [rpm] over time (left), with the motor's rated and peak torque, and the cycle's
    points over its torque-speed zones (right). A sizing with no motor shown is an
    :class:`~beltcalc.errors.InputError`."""
    from beltcalc.design.motor_report import profile_samples, zone_plot_data
    from beltcalc.errors import InputError

    s = sizing
    if s.shown is None:
        raise InputError("no motor fits, so there is no torque profile to plot; choose one by name (`motor`)",
                         param="plot")
    data = list(zip(*profile_samples(s)))
    m = s.shown.motor
    fig = _new_figure((12, 6))
    grid = fig.add_gridspec(2, 2, width_ratios=(3, 2))
    a1 = fig.add_subplot(grid[0, 0])
    a2 = fig.add_subplot(grid[1, 0], sharex=a1)
    a3 = fig.add_subplot(grid[:, 1])
    a1.plot(data[0], data[3], label="motor torque")
    for level, style, name in ((m.T_n, "--", "rated"), (m.T_max, ":", "peak")):
        a1.axhline(level, ls=style, color="k", lw=0.8, label=f"{m.name} {name} {level:g} N m")
        a1.axhline(-level, ls=style, color="k", lw=0.8)
    a1.set_ylabel("torque [N m]")
    a1.legend(fontsize=8)
    a2.plot(data[0], [w * 30 / math.pi for w in data[1]])
    a2.set_ylabel("motor speed [rpm]")
    a2.set_xlabel("time [s]")
    zone = zone_plot_data(s)
    for key, color, alpha, label in (
            ("intermittent", "tab:orange", 0.15, "intermittent zone" + (" (assumed)" if zone["intermittent_assumed"]
                                                                         else "")),
            ("continuous", "tab:green", 0.25, "continuous zone" if zone["continuous_from_catalog"]
             else "rated torque T_n (the RMS limit)")):
        w, t = zip(*zone[key])
        a3.fill_between(w, t, color=color, alpha=alpha, lw=0)
        a3.plot(w, t, color=color, lw=1.2, label=label)
    w, t = zip(*zone["points"])
    a3.plot(w, t, ".", ms=3, color="tab:blue", label="cycle (|speed|, |torque|)")
    a3.plot(*zone["rms"], "s", color="tab:green", mec="k", label="RMS torque at the mean speed")
    if zone["worst"] is not None:
        a3.plot(*zone["worst"], "x", color="tab:red", ms=9, mew=2, label="smallest margin to the zone")
    a3.set_xlabel("motor speed [rpm]")
    a3.set_ylabel("|torque| [N m]")
    a3.set_xlim(left=0)
    a3.set_ylim(bottom=0)
    a3.legend(fontsize=8, loc="upper right")
    a3.set_title(f"{m.name}: torque-speed zones", fontsize=10)
    fig.suptitle(f"motor-size: {m.name}, RMS {s.shown.duty.rms_torque:.3g} N m")
    fig.tight_layout()
    return fig


def motor_sweep_figure(name: str, unit: str, table, motor=None):
    """A motor-size sweep of ``name`` [``unit``, SI]: peak torque (with ``motor``'s T_max)
    and the acceleration energy, by [W21 eq. 29] and integrated, over the swept value;
    ``table`` the rows of :func:`beltcalc.design.motor_report.sweep_table`."""
    x = [r[0] for r in table]
    fig, axes = _subplots(2, 1, (8, 6), sharex=True)
    a1, a2 = axes[:, 0]
    a1.plot(x, [r[3] for r in table], "o-", label="peak torque")
    if motor:
        a1.axhline(motor.T_max, ls=":", color="k", label=f"{motor.name} T_max")
    a1.set_ylabel("torque [N m]")
    a1.legend(fontsize=8)
    a2.plot(x, [r[5] for r in table], "o-", label="E = T_max w t_a (eq. 29)")
    a2.plot(x, [r[6] for r in table], "s-", label="integral T w dt")
    a2.set_ylabel("acceleration energy [J]")
    a2.set_xlabel(f"{name} [{unit}]")
    a2.legend(fontsize=8)
    fig.tight_layout()
    return fig


# --- studies ------------------------------------------------------------------------------------------
def study_figure(summary, columns: dict, limits, varied: int, preferred=()):
    """A tolerance study (:func:`beltcalc.sim.study.tolerance.tolerance_study`'s summary):
    histograms of up to four outputs (the ``limits``' columns, then the ``preferred`` column
    keys that vary, then the others that do), each with its limits and beside a tornado chart
    of its standardised regression coefficients; ``columns`` key -> Column of the outputs,
    ``varied`` the number of varied inputs (the sample's first columns)."""
    import numpy as np

    from beltcalc.units import convert

    keys = list(columns)
    live = [k for k in keys if (summary.outputs.get(k, {}).get("sd") or 0) > 0]
    chosen = [lim.key for lim in limits] + [k for k in preferred if k in live] + live
    chosen = list(dict.fromkeys(k for k in chosen if k in columns))[:4] or keys[:1]
    fig, axes = _subplots(len(chosen), 2, (10, 2.6 * len(chosen)))
    for (ax_h, ax_t), key in zip(axes, chosen):
        col, e = columns[key], summary.outputs.get(key, {})
        unit = col.display or col.unit or "1"
        y = summary.sample[:, varied + keys.index(key)]
        y = y[np.isfinite(y)]
        if unit != (col.unit or "1") and (col.unit or "1") != "1":
            y = np.array([convert(v, col.unit, unit) for v in y]) if y.size else y
        ax_h.hist(y, bins=40, color="tab:blue", alpha=0.8)
        for j, lim in enumerate(lim for lim in limits if lim.key == key):
            level = lim.bound if unit == (col.unit or "1") else convert(lim.bound, col.unit, unit)
            ax_h.axvline(level, label=f"limit {lim.op} {level:.6g}", **limit_style(j))
            ax_h.legend(fontsize=8)
        ax_h.set_xlabel(f"{col.label} [{unit_label(unit)}]", fontsize=8)
        ax_h.set_ylabel("runs")
        infl = [i for i in e.get("influence", []) if i["src"] is not None][::-1]
        ax_t.barh([i["input"] for i in infl], [i["src"] for i in infl],
                  color=["tab:red" if i["src"] < 0 else "tab:green" for i in infl])
        ax_t.axvline(0, color="0.3", lw=0.8)
        ax_t.set_xlim(-1.05, 1.05)
        ax_t.set_xlabel("standardised regression coefficient", fontsize=8)
        ax_t.set_title(f"what moves it (R^2 of the linear fit {e['r2']:.2f})" if e.get("r2") is not None
                       else "what moves it", fontsize=8)
    fig.tight_layout()
    return fig
