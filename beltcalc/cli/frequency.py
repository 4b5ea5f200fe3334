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
from beltcalc.cli.options import (BandParam, DriveRef, FrequencyParam, OutputPath, catalog_option, output_options,
                                  quantity_option)
from beltcalc.cli.output import (console, dumps, emit_warnings, format_number, inputs_json, require_matplotlib,
                                 table_csv, write_atomic, write_figure, wrote)
from beltcalc.plots import campbell_figure, modes_figure, response_figure
from beltcalc.report import denoise, rpm


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
        click.option("--mode", "modes_named", multiple=True, metavar="ELEMENT=STATE",
                     help="The mode of a clutch, brake, friction or limited drive to analyse, e.g. "
                          "--mode limiter=forward (repeatable; states: stuck, forward, backward, free; a drive: "
                          "free, high, low). Default: each one's mode at the end of the drive's run."),
        output_options,
    ]):
        func = opt(func)
    return func


def _drive(ref: str, assignments, catalog_paths, plot_path, names: dict | None = None, modes_named=()):
    """The drive ``ref`` with the ``--set`` values; errors about its values name ``--set``. A
    drive with clutches, brakes, friction or limited drives is taken in one mode
    (:meth:`beltcalc.sim.network.Network.frozen`): those ``--mode`` names, the others as the
    drive's run ends; ``d.mode`` says which (None: no such element)."""
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
    d.mode = None
    if d.network.switched or modes_named:
        pattern, origin = fq.chosen_mode(d, _named_modes(d.network, modes_named))
        d.mode = f"{d.network.describe(pattern)} ({origin})"
        d.network = d.network.frozen(pattern)
    return d


def _named_modes(net, given) -> dict[str, str]:
    """``--mode ELEMENT=STATE`` values, checked against the drive's elements and their states."""
    out = {}
    names = {el.name: el for el in net.switched}
    for item in given:
        name, _, state = item.partition("=")
        if name not in names:
            have = ", ".join(names) or "none in this drive"
            raise click.BadParameter(f"{name!r} is not a clutch, brake, friction or limited drive of the drive "
                                     f"(these are: {have})", param_hint="--mode")
        if state not in names[name].STATES:
            raise click.BadParameter(f"{state!r} is not a state of {name}; use one of "
                                     f"{', '.join(names[name].STATES)}", param_hint="--mode")
        out[name] = state
    return out


def _with_mode(d, obj: dict) -> dict:
    """The JSON object with the drive's mode (where it has elements with modes) after its file."""
    if not d.mode:
        return obj
    out = {}
    for key, value in obj.items():
        out[key] = value
        if key == "file":
            out["mode"] = d.mode
    out.setdefault("mode", d.mode)
    return out


def _mode_note(d) -> None:
    if d.mode:
        console().print(f"in the mode: {d.mode}", markup=False, highlight=False, soft_wrap=True)


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
                      _text(p["damped_frequency"]["value"]), _text(denoise(p["damping_ratio"]["value"]), 3), "-")
        elif p["kind"] == "real":
            t.add_row(str(k), "real", "-", "-", "-", _duration(p["time_constant"]["value"]))
        else:
            t.add_row(str(k), "rigid body", "0", "-", "-", "-")
    console().print(t)


def _print_shapes(m) -> None:
    from rich.table import Table

    out = console()
    for k, (p, s) in enumerate(zip(m.oscillatory(), m.shapes), 1):
        energy = ("strain energy: " + ", ".join(f"{e} ({format_number(100 * share, 3)} %)" for e, share in s.shares())
                  if s.dominant else "no spring strained")
        out.print(f"mode {k}: {_text(p.frequency)} Hz, damping ratio {_text(denoise(p.damping_ratio), 3)}; {energy}",
                  markup=False, highlight=False, soft_wrap=True)
        t = Table()
        t.add_column("node")
        t.add_column("amplitude (relative)", justify="right")
        t.add_column("phase deg", justify="right")
        for node, a in s.amplitude.items():
            still = denoise(a) == 0
            t.add_row(node, format_number(denoise(a), 4), "-" if still else format_number(denoise(s.phase[node]), 4))
        out.print(t)


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


@click.command("modes")
@drive_options
@click.option("--along-stroke", "along_stroke", type=click.IntRange(2, 2000), default=None, metavar="N",
              help="Map the modes along the stroke of the drive's carriage belt: N evenly spaced carriage "
                   "positions (2..2000, both ends included), the lowest first frequency and where.")
@click.option("--band", type=BandParam(), default=None,
              help="With --along-stroke: the move's excitation band LOW:HIGH, e.g. 0:12Hz (roughly up to 1 / the "
                   "acceleration time), shaded on the plot and checked against the modes [default: none].")
def modes(drive, assignments, catalog_paths, plot_path, modes_named, as_json, csv_path, along_stroke, band):
    """Every pole of a drive (a drive file, or a built-in drive by name: conveyor, sewing
    [default], roller_table, linear_axis, linear_axis_moving, friswell_5_disks, friswell_geared):
    rigid-body modes, oscillatory modes (natural and damped frequency, damping ratio), real
    poles (time constant); the undamped natural frequencies; and each mode's shape: every
    node's amplitude and phase against the largest, and every element that holds over 10 % of
    its strain energy (the ones to stiffen), largest first. Strands taut, motor states
    included.

    With --along-stroke N, a drive with a carriage belt: its modes with the carriage held at N
    positions along the stroke (frequencies, damping ratios, shapes), the lowest first
    frequency and where."""
    from beltcalc.sim import frequency_report as fq

    if band is not None and along_stroke is None:
        raise click.BadParameter("a band is checked against the map along the stroke: give --along-stroke N too",
                                 param_hint="--band")
    d = _drive(drive, assignments, catalog_paths, plot_path, {"positions": "--along-stroke"}, modes_named)
    if along_stroke is not None:
        _stroke(d, along_stroke, band, plot_path, as_json, csv_path)
        return
    m = fq.modes(d.network)
    nodes = [nd.name for nd in d.network.nodes]
    _emit(csv_path, plot_path, as_json, lambda: _modes_csv(m, nodes),
          lambda path: write_figure(modes_figure(m, nodes, d.title), path),
          lambda: {"drive": d.title, "file": d.path, **({"mode": d.mode} if d.mode else {}), "modes": m.to_list(),
                   "undamped_frequencies": {"value": _floats(m.undamped), "unit": "Hz"}},
          lambda: (_mode_note(d), _print_modes(d, m)))


def _stroke(d, positions: int, band, plot_path, as_json, csv_path) -> None:
    """``modes --along-stroke``: the map of :func:`beltcalc.sim.stroke_map.stroke_map`, rendered by
    :mod:`beltcalc.cli.stroke_map`."""
    from beltcalc.cli import stroke_map as view
    from beltcalc.plots import stroke_map_figure
    from beltcalc.sim.stroke_map import stroke_map

    view.check_drive(d.network)
    s = stroke_map(d.network, positions)
    _emit(csv_path, plot_path, as_json, lambda: view.to_csv(s),
          lambda path: write_figure(stroke_map_figure(s, d.title, band, view.SHOWN), path),
          lambda: view.to_dict(d, s, band), lambda: (_mode_note(d), view.show(d, s, band)))
    emit_warnings(view.warnings(s, band))


# --- frequency response ---------------------------------------------------------------------------------
def _tag(unit: str) -> str:
    return unit.replace("(", "").replace(")", "").replace("/", "_per_").replace(" ", "_").replace("^", "")


def _response_json(d, r) -> dict:
    import numpy as np

    out = {"drive": d.title, "file": d.path, "excitations": r.inputs, "outputs": r.outputs,
           "frequency": {"value": _floats(r.omega / (2 * math.pi)), "unit": "Hz"}, "responses": []}
    for y, u, unit in r.pairs():
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
    for y, u, unit in r.pairs():
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
    for y, u, unit in r.pairs():
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
    for y, u, unit in r.pairs():
        mag, ph = r.magnitude(y, u), r.phase(y, u)
        t.add_row(y, u, escape(f"|H| [{unit}]"), *(_text(mag[k]) for k in picks))
        t.add_row("", "", escape("phase [deg]"), *(_text(ph[k]) for k in picks))
    out.print(t)
    out.print("every frequency: --csv, --json or --plot (a Bode plot)", markup=False, highlight=False,
              soft_wrap=True)


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
@click.option("--polygon", "polygon", default=None, metavar="STRAND",
              help="Instead: the steady response to chain strand STRAND's polygon action (its length pulse and "
                   "lever-arm swing at the tooth frequency and its harmonics), at --speed.")
@quantity_option("--speed", si_unit="rad/s", help="With --polygon: the speed of the strand's `from` sprocket, e.g. "
                                                  "60rpm [default: none; required with --polygon].")
@click.option("--harmonics", type=click.IntRange(1, 50), default=3, show_default=True,
              help="With --polygon: harmonics of the tooth frequency.")
def response(drive, assignments, catalog_paths, plot_path, modes_named, as_json, csv_path, inputs, outputs, f_from,
             f_to, points, spacing, polygon, speed, harmonics):
    """The frequency response H(jw) of a drive (default: the sewing drive) from each input to each
    output: magnitude in the output's unit per the input's unit, and phase, computed exactly
    (no time simulation); the resonance peaks with their frequency, magnitude and Q (half-power
    bandwidth). --plot writes a Bode plot. With --polygon STRAND --speed W: the steady amplitude
    of each output under that chain strand's polygon action, harmonic by harmonic."""
    from beltcalc.sim import frequency_report as fq

    if polygon is not None or speed is not None:
        return _polygon(drive, assignments, catalog_paths, plot_path, modes_named, as_json, csv_path, outputs,
                        polygon, speed, harmonics, bool(inputs or f_from or f_to))
    d = _drive(drive, assignments, catalog_paths, plot_path, {"f_min": "--from", "f_max": "--to"}, modes_named)
    r = fq.response(d.network, list(inputs), list(outputs), f_from, f_to, points, spacing)
    _emit(csv_path, plot_path, as_json, lambda: _response_csv(r),
          lambda path: write_figure(response_figure(r, d.title), path),
          lambda: _with_mode(d, _response_json(d, r)), lambda: (_mode_note(d), _print_response(d, r, spacing)))


def _polygon(drive, assignments, catalog_paths, plot_path, modes_named, as_json, csv_path, outputs, strand, speed,
             harmonics, others) -> None:
    """``response --polygon STRAND --speed W``: :func:`beltcalc.sim.polygon_response.polygon_response`."""
    import numpy as np

    from beltcalc.sim.polygon_response import polygon_response

    if strand is None or speed is None:
        raise click.UsageError("--polygon and --speed go together: name the chain strand and its sprocket's speed")
    if others or plot_path:
        raise click.UsageError("--polygon takes --output, --harmonics, --json and --csv; not --input, --from, --to "
                               "or --plot")
    d = _drive(drive, assignments, catalog_paths, None, modes_named=modes_named)
    r = polygon_response(d, strand, speed, harmonics, list(outputs) or None)

    def to_dict():
        return {"drive": d.title, "file": d.path, "polygon": {
            "strand": r.strand, "speed": _q(r.speed, "rad/s"), "tooth_frequency": _q(r.tooth_frequency, "Hz"),
            "mean_force": _q(r.mean_force, "N"), "mean_force_origin": r.mean_force_origin,
            "harmonics": [{"harmonic": k + 1, "frequency": _q(f, "Hz"), "pulse": _q(abs(r.pulse[k]), "m"),
                           "outputs": {y: {"amplitude": _q(abs(v[k]), r.units[y]),
                                           "phase": _q(float(np.angle(v[k])), "rad")} for y, v in r.outputs.items()}}
                          for k, f in enumerate(r.frequencies)],
            "bound": {y: _q(r.bound(y), r.units[y]) for y in r.outputs}}}

    def to_csv():
        header = ["harmonic", "f_Hz", "pulse_m"] + [f"{col}_{y}_{_tag(r.units[y]) if col == 'amp' else 'rad'}"
                                                    for y in r.outputs for col in ("amp", "phase")]
        return table_csv(header, ([str(k + 1), repr(float(f)), repr(float(abs(r.pulse[k])))]
                                  + [repr(float(x)) for y in r.outputs for x in (abs(r.outputs[y][k]),
                                                                                np.angle(r.outputs[y][k]))]
                                  for k, f in enumerate(r.frequencies)))

    def show():
        from rich.table import Table

        out = console(140)
        out.print(f"{d.title}: the polygon action of strand {r.strand}, its `from` sprocket at {_text(r.speed)} rad/s "
                  f"({_text(rpm(r.speed))} rpm): tooth frequency {_text(r.tooth_frequency)} Hz, mean force "
                  f"{_text(r.mean_force)} N ({r.mean_force_origin})", markup=False, highlight=False, soft_wrap=True)
        t = Table(title="steady amplitude per harmonic (strands taut)", title_justify="left")
        for col in ["output", "unit"] + [f"{k + 1}: {_text(f)} Hz" for k, f in enumerate(r.frequencies)] + ["sum"]:
            t.add_column(col, justify="left" if col in ("output", "unit") else "right")
        t.add_row("length pulse", "m", *(_text(abs(e)) for e in r.pulse), "")
        for y, v in r.outputs.items():
            t.add_row(y, r.units[y], *(_text(abs(x)) for x in v), _text(r.bound(y)))
        out.print(t)
        out.print("sum: the harmonics' amplitudes added, an upper bound of the ripple (half peak-to-peak)",
                  markup=False, highlight=False, soft_wrap=True)

    _emit(csv_path, None, as_json, to_csv, None, lambda: _with_mode(d, to_dict()), lambda: (_mode_note(d), show()))


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
        "order_sources": [{"order": k, "source": src} for k, src in zip(c.orders, c.sources)],
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
    return table_csv(header, ([repr(x.speed), repr(rpm(x.speed)), repr(x.order), x.mode, repr(x.frequency),
                               repr(x.damping_ratio + 0.0), repr(x.speed / op) if op else ""] for x in c.crossings))


def _print_campbell(d, c) -> None:
    from rich.table import Table

    out = console()
    op = c.operating_speed
    orders = ", ".join(format_number(k, 4) for k in c.orders)
    out.print(f"{d.title}: Campbell diagram, speed of node {c.reference} from {_text(c.speed_min)} to "
              f"{_text(c.speed_max)} rad/s ({_text(rpm(c.speed_max))} rpm), orders {orders}",
              markup=False, highlight=False, soft_wrap=True)
    t = Table(title="crossings of order lines and modes", title_justify="left")
    cols = ["speed rad/s", "speed rpm"] + (["x operating speed"] if op else []) + \
        ["order", "mode", "frequency Hz", "damping ratio"]
    for col in cols:
        t.add_column(col, justify="right")
    for x in c.crossings:
        t.add_row(_text(x.speed), _text(rpm(x.speed)), *([_text(x.speed / op, 3)] if op else []),
                  format_number(x.order, 4), str(x.mode), _text(x.frequency), _text(denoise(x.damping_ratio), 3))
    out.print(t)
    modes = ", ".join(f"{k}: {_text(p.frequency)} Hz (damping ratio {_text(denoise(p.damping_ratio), 3)})"
                      for k, p in enumerate(c.modes, 1)) or "none"
    notes = [f"modes: {modes}"]
    named = [f"{format_number(k, 4)}: {src}" for k, src in zip(c.orders, c.sources) if "teeth" in src or "load" in src]
    if named:
        notes.append("orders of the drive's own: " + "; ".join(named))
    if not c.crossings:
        notes.append("no order line crosses a mode inside the speed range")
    if op:
        notes.append(f"operating speed: at the synchronous speed of motor {c.motor!r}, node {c.reference} turns at "
                     f"{_text(op)} rad/s ({_text(rpm(op))} rpm)")
    for note in notes:
        out.print(note, markup=False, highlight=False, soft_wrap=True)


@click.command("campbell")
@drive_options
@click.option("--orders", "orders_text", default=None, metavar="K,K,...",
              help="Excitation orders: an order k at a shaft speed Omega excites k Omega / 2 pi "
                   "[default: 1,2,3, the orders of the drive's own loads and every sprocket's and toothed "
                   "pulley's tooth order, z times its speed ratio].")
@quantity_option("--speed-max", si_unit="rad/s",
                 help="Highest speed of the reference node, e.g. 3000rpm [default: 1.2 x the induction motor's "
                      "synchronous speed, at the reference].")
@quantity_option("--speed-min", si_unit="rad/s", default="0rad/s", help="Lowest speed of the reference node.")
@click.option("--reference", default=None, metavar="NODE",
              help="The node whose speed the orders count [default: the first motor's node, else the first node].")
def campbell(drive, assignments, catalog_paths, plot_path, modes_named, as_json, csv_path, orders_text, speed_max,
             speed_min, reference):
    """The Campbell diagram of a drive (default: the sewing drive): where the excitation orders
    cross its modes as the reference node runs up, each crossing with its speed (rad/s, rpm, and
    against the operating speed), order, mode, frequency and the mode's damping ratio."""
    from beltcalc.sim import frequency_report as fq

    orders = None if orders_text is None else _orders(orders_text)
    d = _drive(drive, assignments, catalog_paths, plot_path, modes_named=modes_named)
    c = fq.campbell(d, orders, speed_max, speed_min, reference)
    _emit(csv_path, plot_path, as_json, lambda: _campbell_csv(c),
          lambda path: write_figure(campbell_figure(c, d.title), path),
          lambda: _with_mode(d, _campbell_json(d, c)), lambda: (_mode_note(d), _print_campbell(d, c)))
