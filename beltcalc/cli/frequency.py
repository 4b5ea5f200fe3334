"""``beltcalc modes``, ``response``, ``campbell``: the frequency domain of a drive.

Each command takes a drive file (a path, or a built-in drive by name; default ``sewing``),
``--set ELEMENT.KEY=QUANTITY`` values, and calls the library once
(:mod:`beltcalc.sim.frequency_report` over :mod:`beltcalc.sim.frequency`); here only the
options are read and the answer rendered: a table, ``--json`` (SI values as ``{"value",
"unit"}``), ``--csv`` (written atomically) or ``--plot`` (PNG, PDF or SVG by the file's suffix).
"""

from __future__ import annotations

import math

import click

from beltcalc.cli.main import OPTION_NAMES, SCENE_OPTION
from beltcalc.cli.options import DriveRef, FrequencyParam, OutputPath, catalog_option, output_options, quantity_option
from beltcalc.cli.output import (console, dumps, format_number, inputs_json, require_matplotlib, save_figure, table_csv,
                                 write_atomic, wrote)


INPUTS = "beltcalc.inputs"     # ctx.meta key: the drive's inputs with their origin (the JSON's `inputs`)


def drive_options(func):
    """The argument and options the three commands share: ``[DRIVE]``, ``--set``,
    ``--catalog``, ``--plot``, ``--json``, ``--csv``."""
    for opt in reversed([
        click.argument("drive", default="sewing", required=False, metavar="[DRIVE]", type=DriveRef()),
        click.option("--set", "assignments", multiple=True, metavar="ELEMENT.KEY=QUANTITY",
                     help="Change a value of the drive file, e.g. --set 23.stiffness=190N*m/rad (repeatable)."),
        catalog_option,
        click.option("--plot", "plot_path", type=OutputPath(), default=None,
                     help="Write a plot: PNG, PDF or SVG, by the file's suffix (needs matplotlib)."),
        output_options,
    ]):
        func = opt(func)
    return func


def _drive(ref: str, assignments, catalog_paths, plot_path, names: dict | None = None):
    """The drive ``ref`` with the ``--set`` values; errors about its values name ``--set``."""
    from beltcalc.params import parse_assignments
    from beltcalc.sim import frequency_report as fq
    from beltcalc.sim.scenes.drive import drive_scene

    meta = click.get_current_context().meta
    meta[SCENE_OPTION] = lambda name: f"--set {name}"
    meta[OPTION_NAMES] = names or {}
    if plot_path is not None:
        require_matplotlib()
    catalog = None
    if catalog_paths:
        from beltcalc.data.catalogs import load_catalog

        catalog = load_catalog(catalog_paths)
    spec = drive_scene(ref, catalog)
    given = parse_assignments([p for p in spec.params if "." in p.name], assignments)
    d = fq.load(spec.file, given, catalog)
    meta[INPUTS] = inputs_json(spec.params, spec.resolve(spec.file, given)[1])
    return d


def _floats(values) -> list:
    """JSON numbers; a value that is not finite as null."""
    return [float(v) if math.isfinite(v) else None for v in values]


def _q(value, unit: str) -> dict:
    return {"value": None if value is None or not math.isfinite(value) else float(value), "unit": unit}


def _text(value: float | None, digits: int = 4) -> str:
    return "-" if value is None or not math.isfinite(value) else format_number(value + 0.0, digits)


def _duration(t: float) -> str:
    """A time constant in s, ms, us or ns, four digits."""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("us", 1e-6)):
        if abs(t) >= scale:
            return f"{format_number(t / scale, 4)} {unit}"
    return f"{format_number(t / 1e-9, 4)} ns"


def _rpm(speed: float) -> float:
    return speed * 60.0 / (2 * math.pi)


def _save(fig, path) -> None:
    fig.tight_layout()
    save_figure(fig, path)


def _figure(rows: int, cols: int, size: tuple[float, float], **kw):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(rows, cols, figsize=size, squeeze=False, **kw)


def _emit(csv_path, plot_path, as_json, csv_text, plot, to_dict, show) -> None:
    """Every command's answer: the CSV file, the plot, then the JSON object or the tables (each
    a function of nothing: the library has answered already)."""
    if csv_path is not None:
        write_atomic(csv_path, csv_text())
        wrote(csv_path)
    if plot_path is not None:
        plot(plot_path)
        wrote(plot_path)
    if as_json:
        obj = to_dict()
        obj.setdefault("warnings", [])
        obj["inputs"] = click.get_current_context().meta.get(INPUTS, {})
        click.echo(dumps(obj))
    else:
        show()


# --- modes -------------------------------------------------------------------------------------------
def print_poles(m, title: str) -> None:
    """Every pole of :class:`~beltcalc.sim.frequency_report.Modes` as one table: rigid-body
    modes, oscillatory modes (natural and damped frequency, damping ratio), real poles
    (time constant)."""
    from rich.markup import escape
    from rich.table import Table

    t = Table(title=escape(title), title_justify="left")
    for col in ("#", "kind", "natural frequency Hz", "damped frequency Hz", "damping ratio", "time constant"):
        t.add_column(col, justify="left" if col == "kind" else "right")
    for k, p in enumerate(m.to_list(shapes=False), 1):
        if p["kind"] == "oscillatory":
            t.add_row(str(k), f"mode {p['mode']}", _text(p["frequency"]["value"]),
                      _text(p["damped_frequency"]["value"]), _text(_clean(p["damping_ratio"]["value"]), 3), "-")
        elif p["kind"] == "real":
            t.add_row(str(k), "real", "-", "-", "-", _duration(p["time_constant"]["value"]))
        else:
            t.add_row(str(k), "rigid body", "0", "-", "-", "-")
    console().print(t)


def _clean(x: float) -> float:
    """Rounding noise off a displayed figure (an undamped mode's 1e-17 damping ratio, a node
    at rest's phase)."""
    return round(x, 9) + 0.0


def _print_shapes(m) -> None:
    from rich.table import Table

    out = console()
    for k, (p, s) in enumerate(zip(m.oscillatory(), m.shapes), 1):
        energy = ("strain energy: " + ", ".join(f"{e} ({format_number(100 * share, 3)} %)" for e, share in _shares(s))
                  if s.dominant else "no spring strained")
        out.print(f"mode {k}: {_text(p.frequency)} Hz, damping ratio {_text(_clean(p.damping_ratio), 3)}; {energy}",
                  markup=False, highlight=False, soft_wrap=True)
        t = Table()
        t.add_column("node")
        t.add_column("amplitude (relative)", justify="right")
        t.add_column("phase deg", justify="right")
        for node, a in s.amplitude.items():
            still = _clean(a) == 0
            t.add_row(node, format_number(_clean(a), 4), "-" if still else format_number(_clean(s.phase[node]), 4))
        out.print(t)


SHARE_SHOWN = 0.10    # a mode's elements named with their share of its strain energy: those above 10 %


def _shares(shape) -> list[tuple[str, float]]:
    """The elements of a mode ``shape`` that hold over :data:`SHARE_SHOWN` of its strain energy,
    largest first (the ones to stiffen); where none does, the largest alone."""
    big = sorted(((e, v) for e, v in shape.energy.items() if v > SHARE_SHOWN), key=lambda ev: -ev[1])
    return big or [(shape.dominant, shape.energy[shape.dominant])]


def _print_modes(d, m) -> None:
    print_poles(m, f"{d.title}: every pole (motor states included, strands taut)")
    shown = ", ".join(format_number(f, 4) for f in m.undamped) or "none"
    console().print(f"undamped natural frequencies (no damping, motors free): {shown} Hz", markup=False,
                    highlight=False, soft_wrap=True)
    _print_shapes(m)


def _modes_csv(m, nodes: list[str]) -> str:
    header = ["pole", "kind", "mode", "s_real_per_s", "s_imag_per_s", "frequency_Hz", "damped_frequency_Hz",
              "damping_ratio", "time_constant_s", "largest_strain_energy", "largest_strain_energy_share"]
    header += [f"amplitude_{n}" for n in nodes] + [f"phase_{n}_deg" for n in nodes]
    rows = []

    def value(p, key):
        return "" if p.get(key) is None or p[key]["value"] is None else repr(p[key]["value"])

    for k, p in enumerate(m.to_list(), 1):
        shape = p.get("shape") or {}
        big = shape.get("largest_strain_energy") or {}
        row = [k, p["kind"], p.get("mode") or "", value(p, "s_real"), value(p, "s_imag"), value(p, "frequency"),
               value(p, "damped_frequency"), value(p, "damping_ratio"), value(p, "time_constant"),
               big.get("element", ""), repr(big["share"]["value"]) if big else ""]
        nodes_ = shape.get("nodes", {})
        row += [repr(nodes_[n]["amplitude"]["value"]) if n in nodes_ else "" for n in nodes]
        row += [repr(math.degrees(nodes_[n]["phase"]["value"])) if n in nodes_ else "" for n in nodes]   # JSON: rad
        rows.append(row)
    return table_csv(header, rows)


def _plot_modes(m, nodes: list[str], title: str, path) -> None:
    shapes = list(zip(m.oscillatory(), m.shapes))
    if not shapes:
        fig, axes = _figure(1, 1, (6, 2))
        axes[0, 0].text(0.5, 0.5, "no oscillatory mode", ha="center", va="center")
        axes[0, 0].set_axis_off()
        _save(fig, path)
        return
    cols = 1 if len(shapes) <= 4 else 2
    rows = math.ceil(len(shapes) / cols)
    fig, axes = _figure(rows, cols, (max(6.0, 0.5 * len(nodes)) * cols, 2.2 * rows))
    x = range(len(nodes))
    for k, ((p, s), ax) in enumerate(zip(shapes, axes.flat), 1):
        amp = [s.amplitude[n] for n in nodes]
        against = [abs(s.phase[n]) > 90 for n in nodes]
        ax.bar(x, amp, color=["tab:orange" if a else "tab:blue" for a in against])
        ax.set_xticks(list(x), nodes, fontsize=7, rotation=45 if len(nodes) > 8 else 0)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("amplitude", fontsize=8)
        where = "; " + ", ".join(f"{e} {100 * v:.0f} %" for e, v in _shares(s)) if s.dominant else ""
        ax.set_title(f"mode {k}: {p.frequency:.4g} Hz, zeta {_clean(p.damping_ratio):.3g}{where}", fontsize=8)
    for ax in list(axes.flat)[len(shapes):]:
        ax.set_axis_off()
    fig.suptitle(f"{title}: mode shapes (orange: against the largest)", fontsize=9)
    _save(fig, path)


@click.command("modes")
@drive_options
def modes(drive, assignments, catalog_paths, plot_path, as_json, csv_path):
    """Every pole of a drive (a drive file, or a built-in drive by name: conveyor, sewing
    [default], roller_table, linear_axis, friswell_5_disks, friswell_geared): rigid-body modes,
    oscillatory modes (natural and damped frequency, damping ratio), real poles (time
    constant); the undamped natural frequencies; and each mode's shape: every node's amplitude
    and phase against the largest, and every element that holds over 10 % of its strain energy
    (the ones to stiffen), largest first. Strands taut, motor states included."""
    from beltcalc.sim import frequency_report as fq

    d = _drive(drive, assignments, catalog_paths, plot_path)
    m = fq.modes(d.network)
    nodes = [nd.name for nd in d.network.nodes]
    _emit(csv_path, plot_path, as_json, lambda: _modes_csv(m, nodes), lambda path: _plot_modes(m, nodes, d.title, path),
          lambda: {"drive": d.title, "file": d.path, "modes": m.to_list(),
                   "undamped_frequencies": {"value": _floats(m.undamped), "unit": "Hz"}},
          lambda: _print_modes(d, m))


# --- frequency response ---------------------------------------------------------------------------------
def _pairs(r):
    from beltcalc.sim.frequency_report import ratio_unit

    for i, y in enumerate(r.outputs):
        for j, u in enumerate(r.inputs):
            yield y, u, ratio_unit(r.units[i], r.input_units[j])


def _tag(unit: str) -> str:
    return unit.replace("(", "").replace(")", "").replace("/", "_per_").replace(" ", "_").replace("^", "")


def _response_json(d, r) -> dict:
    import numpy as np

    out = {"drive": d.title, "file": d.path, "excitations": r.inputs, "outputs": r.outputs,
           "frequency": {"value": _floats(r.omega / (2 * math.pi)), "unit": "Hz"}, "responses": []}
    for y, u, unit in _pairs(r):
        out["responses"].append({
            "output": y, "input": u,
            "magnitude": {"value": _floats(r.magnitude(y, u)), "unit": unit},
            "phase": {"value": _floats(np.radians(r.phase(y, u))), "unit": "rad"},      # SI; the table: deg
            "peaks": [{"frequency": _q(f, "Hz"), "magnitude": _q(mag, unit),
                       "q": _q(q, "1") if q is not None else None} for f, mag, q in r.peaks[(y, u)]],
        })
    return out


def _response_csv(r) -> str:
    f = r.omega / (2 * math.pi)
    header, cols = ["f_Hz", "omega_rad_per_s"], [f, r.omega]
    for y, u, unit in _pairs(r):
        pair = f"{y}_from_{u.replace(':', '_')}"
        header += [f"mag_{pair}_{_tag(unit)}", f"phase_{pair}_deg"]
        cols += [r.magnitude(y, u), r.phase(y, u)]
    return table_csv(header, ([repr(float(c[k])) for c in cols] for k in range(f.size)))


def _print_response(d, r, spacing: str) -> None:
    import numpy as np
    from rich.markup import escape
    from rich.table import Table

    f = r.omega / (2 * math.pi)
    out = console(140)
    span = f"at {_text(f[0])} Hz" if f.size == 1 else f"{_text(f[0])} to {_text(f[-1])} Hz, {f.size} points, {spacing}"
    out.print(f"{d.title}: frequency response H(jw) (strands taut), {span}", markup=False, highlight=False,
              soft_wrap=True)
    t = Table(title="resonance peaks of |H|", title_justify="left")
    for col in ("output", "input", "frequency Hz", "|H|", "unit", "Q"):
        t.add_column(col, justify="left" if col in ("output", "input", "unit") else "right")
    for y, u, unit in _pairs(r):
        peaks = r.peaks[(y, u)]
        if not peaks:
            t.add_row(y, u, "-", "-", unit, "no peak inside the range")
        for fp, mag, q in peaks:
            t.add_row(y, u, _text(fp), _text(mag), unit, _text(q, 3))
    out.print(t)
    picks = sorted(set(np.round(np.linspace(0, f.size - 1, min(f.size, 8))).astype(int).tolist()))
    t = Table(title="magnitude and phase at some of the frequencies [Hz]", title_justify="left")
    for col in ("output", "input", ""):
        t.add_column(col, no_wrap=True)
    for k in picks:
        t.add_column(_text(f[k]), justify="right")
    for y, u, unit in _pairs(r):
        mag, ph = r.magnitude(y, u), r.phase(y, u)
        t.add_row(y, u, escape(f"|H| [{unit}]"), *(_text(mag[k]) for k in picks))
        t.add_row("", "", escape("phase [deg]"), *(_text(ph[k]) for k in picks))
    out.print(t)
    out.print("every frequency: --csv, --json or --plot (a Bode plot)", markup=False, highlight=False,
              soft_wrap=True)


def _plot_response(d, r, path) -> None:
    f = r.omega / (2 * math.pi)
    fig, axes = _figure(2, 1, (8, 6), sharex=True)
    mag_ax, ph_ax = axes[:, 0]
    for y, u, unit in _pairs(r):
        line, = mag_ax.loglog(f, r.magnitude(y, u), "-" if f.size > 1 else "o", label=f"{y} / {u} [{unit}]")
        peaks = r.peaks[(y, u)]
        if peaks:
            mag_ax.plot([p[0] for p in peaks], [p[1] for p in peaks], "o", color=line.get_color(), fillstyle="none")
        ph_ax.semilogx(f, r.phase(y, u), "-" if f.size > 1 else "o", color=line.get_color())
    mag_ax.set_ylabel("|H|")
    mag_ax.legend(fontsize=7)
    mag_ax.set_title(f"{d.title}: frequency response (circles: resonance peaks)", fontsize=9)
    ph_ax.set_ylabel("phase [deg]")
    ph_ax.set_xlabel("frequency [Hz]")
    for ax in (mag_ax, ph_ax):
        ax.grid(True, which="both", alpha=0.3)
    _save(fig, path)


@click.command("response")
@drive_options
@click.option("--input", "inputs", multiple=True, metavar="load:NODE|supply:MOTOR",
              help="An input: a load torque (force) on a node, or a motor's supply (its synchronous speed) "
                   "(repeatable) [default: a load on the last node with inertia].")
@click.option("--output", "outputs", multiple=True, metavar="SIGNAL",
              help="An output: omega_NODE, v_NODE, accel_NODE, phi_NODE, T_COUPLING, F_STRAND, M_MOTOR "
                   "(repeatable) [default: every node's speed].")
@click.option("--from", "f_from", type=FrequencyParam(), default=None,
              help="Lowest frequency: 1Hz, or angular: 6.3rad/s (rad/s, rpm and 1/s are divided by 2 pi) "
                   "[default: 0.1 x the lowest mode].")
@click.option("--to", "f_to", type=FrequencyParam(), default=None,
              help="Highest frequency [default: 10 x the highest mode].")
@click.option("--points", type=click.IntRange(1, 100_000), default=2000, show_default=True,
              help="Frequencies (1: --from alone).")
@click.option("--spacing", type=click.Choice(["log", "linear"]), default="log", show_default=True)
def response(drive, assignments, catalog_paths, plot_path, as_json, csv_path, inputs, outputs, f_from, f_to, points,
             spacing):
    """The frequency response H(jw) of a drive (default: the sewing drive) from each input to each
    output: magnitude in the output's unit per the input's unit, and phase, computed exactly
    (no time simulation); the resonance peaks with their frequency, magnitude and Q (half-power
    bandwidth). --plot writes a Bode plot."""
    from beltcalc.sim import frequency_report as fq

    d = _drive(drive, assignments, catalog_paths, plot_path, {"f_min": "--from", "f_max": "--to"})
    r = fq.response(d.network, list(inputs), list(outputs), f_from, f_to, points, spacing)
    _emit(csv_path, plot_path, as_json, lambda: _response_csv(r), lambda path: _plot_response(d, r, path),
          lambda: _response_json(d, r), lambda: _print_response(d, r, spacing))


# --- Campbell diagram -------------------------------------------------------------------------------------
def _orders(text: str) -> list[float]:
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise click.BadParameter(f"{text!r}: give numbers separated by commas, e.g. 1,2,4",
                                 param_hint="--orders") from None
    if not all(math.isfinite(v) for v in values):
        raise click.BadParameter(f"{text!r}: every order must be a finite number", param_hint="--orders")
    return values


def _campbell_json(d, c) -> dict:
    op = c.operating_speed
    return {
        "drive": d.title, "file": d.path, "reference": c.reference, "orders": c.orders,
        "speed_min": _q(c.speed_min, "rad/s"), "speed_max": _q(c.speed_max, "rad/s"),
        "operating_speed": _q(op, "rad/s") if op is not None else None, "motor": c.motor,
        "modes": [{"mode": k, "frequency": _q(p.frequency, "Hz"), "damping_ratio": _q(p.damping_ratio + 0.0, "1")}
                  for k, p in enumerate(c.modes, 1)],
        "crossings": [{"speed": _q(x.speed, "rad/s"), "order": x.order, "mode": x.mode,
                       "frequency": _q(x.frequency, "Hz"), "damping_ratio": _q(x.damping_ratio + 0.0, "1"),
                       "speed_per_operating_speed": _q(x.speed / op, "1") if op else None}
                      for x in c.crossings],
    }


def _campbell_csv(c) -> str:
    op = c.operating_speed
    header = ["speed_rad_per_s", "speed_rpm", "order", "mode", "frequency_Hz", "damping_ratio",
              "speed_per_operating_speed"]
    return table_csv(header, ([repr(x.speed), repr(_rpm(x.speed)), repr(x.order), x.mode, repr(x.frequency),
                               repr(x.damping_ratio + 0.0), repr(x.speed / op) if op else ""] for x in c.crossings))


def _print_campbell(d, c) -> None:
    from rich.table import Table

    out = console()
    op = c.operating_speed
    orders = ", ".join(format_number(k, 4) for k in c.orders)
    out.print(f"{d.title}: Campbell diagram, speed of node {c.reference} from {_text(c.speed_min)} to "
              f"{_text(c.speed_max)} rad/s ({_text(_rpm(c.speed_max))} rpm), orders {orders}",
              markup=False, highlight=False, soft_wrap=True)
    t = Table(title="crossings of order lines and modes", title_justify="left")
    cols = ["speed rad/s", "speed rpm"] + (["x operating speed"] if op else []) + \
        ["order", "mode", "frequency Hz", "damping ratio"]
    for col in cols:
        t.add_column(col, justify="right")
    for x in c.crossings:
        t.add_row(_text(x.speed), _text(_rpm(x.speed)), *([_text(x.speed / op, 3)] if op else []),
                  format_number(x.order, 4), str(x.mode), _text(x.frequency), _text(_clean(x.damping_ratio), 3))
    out.print(t)
    modes = ", ".join(f"{k}: {_text(p.frequency)} Hz (damping ratio {_text(_clean(p.damping_ratio), 3)})"
                      for k, p in enumerate(c.modes, 1)) or "none"
    notes = [f"modes: {modes}"]
    if not c.crossings:
        notes.append("no order line crosses a mode inside the speed range")
    if op:
        notes.append(f"operating speed: at the synchronous speed of motor {c.motor!r}, node {c.reference} turns at "
                     f"{_text(op)} rad/s ({_text(_rpm(op))} rpm)")
    for note in notes:
        out.print(note, markup=False, highlight=False, soft_wrap=True)


def _plot_campbell(d, c, path) -> None:
    save_figure(campbell_figure(d, c), path)


def campbell_figure(d, c):
    """The Campbell diagram as a matplotlib figure: modes as horizontal lines, orders as rays
    from the origin, the crossings marked; each line labelled at the right edge (orders to 4
    significant digits), the labels of each edge moved apart where they would overlap
    (:func:`spread`) and left out where the height holds no more."""
    fig, axes = _figure(1, 1, (8, 5))
    ax = axes[0, 0]
    top_speed = _rpm(c.speed_max)
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
    ax.plot([_rpm(x.speed) for x in c.crossings], crossed, "o", color="tab:red", label="crossings")
    if c.operating_speed:
        ax.axvline(_rpm(c.operating_speed), color="black", ls=":", lw=1, label="operating (synchronous) speed")
    ax.set_xlim(_rpm(c.speed_min), top_speed * 1.08)
    ax.set_ylim(0, f_top)
    ax.set_xlabel(f"speed of node {c.reference} [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{d.title}: Campbell diagram", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()       # the axes' final size: the labels are moved apart in its pixels
    for texts in (mode_labels, order_labels):     # each edge's labels: modes left of it, orders right
        _unstack(fig, ax, texts)
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


@click.command("campbell")
@drive_options
@click.option("--orders", "orders_text", default=None, metavar="K,K,...",
              help="Excitation orders: an order k at a shaft speed Omega excites k Omega / 2 pi "
                   "[default: 1,2,3 and the orders of the drive's own loads].")
@quantity_option("--speed-max", si_unit="rad/s",
                 help="Highest speed of the reference node, e.g. 3000rpm [default: 1.2 x the induction motor's "
                      "synchronous speed, at the reference].")
@quantity_option("--speed-min", si_unit="rad/s", default="0rad/s", help="Lowest speed of the reference node.")
@click.option("--reference", default=None, metavar="NODE",
              help="The node whose speed the orders count [default: the first motor's node, else the first node].")
def campbell(drive, assignments, catalog_paths, plot_path, as_json, csv_path, orders_text, speed_max, speed_min,
             reference):
    """The Campbell diagram of a drive (default: the sewing drive): where the excitation orders
    cross its modes as the reference node runs up, each crossing with its speed (rad/s, rpm, and
    against the operating speed), order, mode, frequency and the mode's damping ratio."""
    from beltcalc.sim import frequency_report as fq

    orders = None if orders_text is None else _orders(orders_text)
    d = _drive(drive, assignments, catalog_paths, plot_path)
    c = fq.campbell(d, orders, speed_max, speed_min, reference)
    _emit(csv_path, plot_path, as_json, lambda: _campbell_csv(c), lambda path: _plot_campbell(d, c, path),
          lambda: _campbell_json(d, c), lambda: _print_campbell(d, c))
