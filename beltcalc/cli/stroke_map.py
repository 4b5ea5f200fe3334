"""``beltcalc modes DRIVE --along-stroke N``: the resonance map of a belt axis along its stroke
(:func:`beltcalc.sim.stroke_map.stroke_map`), rendered: a table (position, the first modes'
frequencies), the lowest first frequency and where, ``--json`` (SI values as ``{"value",
"unit"}``), ``--csv`` (one row per position) and ``--plot`` (frequency against position, the
``--band`` shaded). Only the options are read and the answer rendered here."""

from __future__ import annotations

import math

import click
import numpy as np

from beltcalc.cli.output import console, format_number, table_csv
from beltcalc.report import denoise

SHOWN = 3          # the modes the table and the plot show (the JSON and the CSV hold every one)


def check_drive(net) -> None:
    """Refuse, as a usage error about ``--along-stroke``, a drive without exactly one carriage belt."""
    from beltcalc.sim.elements.carriage_belt import carriage_belts

    belts = carriage_belts(net)
    if not belts:
        raise click.BadParameter("the drive has no carriage belt (a [[carriage_belt]] whose spans follow a "
                                 "carriage): a map along the stroke needs one", param_hint="--along-stroke")
    if len(belts) > 1:
        raise click.BadParameter(f"the drive has {len(belts)} carriage belts ({', '.join(b.name for b in belts)}); "
                                 "the map takes a drive with one", param_hint="--along-stroke")


def _q(value, unit: str) -> dict:
    return {"value": None if value is None or not math.isfinite(value) else float(value) + 0.0, "unit": unit}


def _list(values, unit: str) -> dict:
    return {"value": [None if not math.isfinite(v) else float(v) + 0.0 for v in values], "unit": unit}


def _inside(s, band) -> list[int]:
    """The modes (numbers) whose frequency lies inside ``band`` at some position."""
    if band is None:
        return []
    f = s.frequency
    return [k + 1 for k in range(s.modes) if bool(((f[:, k] >= band[0]) & (f[:, k] <= band[1])).any())
            or (k == 0 and band[0] <= s.lowest <= band[1])]


def warnings(s, band) -> list[str]:
    """What a designer must know: a mode inside the excitation band."""
    out = []
    for k in _inside(s, band):
        f = s.frequency[:, k - 1]
        where = np.append(s.positions[(f >= band[0]) & (f <= band[1])],
                          [s.lowest_at] if k == 1 and band[0] <= s.lowest <= band[1] else [])
        out.append(f"mode {k} lies inside the excitation band {band[0]:.4g} to {band[1]:.4g} Hz with the carriage "
                   f"between {where.min() * 1e3:.4g} and {where.max() * 1e3:.4g} mm")
    return out


def to_dict(d, s, band) -> dict:
    """The JSON object: the positions and spans [m], the belt's stiffness [N/m], each mode's
    frequency [Hz], damping ratio and shape per position, the lowest first frequency and where,
    the first frequency at the travel's ends, the band."""
    modes = []
    for k in range(s.modes):
        mode = {"mode": k + 1, "frequency": _list(s.frequency[:, k], "Hz"),
                "damping_ratio": _list(s.damping_ratio[:, k], "1")}
        if s.amplitude is not None:
            mode["shape"] = {"nodes": {n: {"amplitude": _list(s.amplitude[:, k, j], "1"),
                                           "phase": _list(s.phase[:, k, j], "rad")}
                                       for j, n in enumerate(s.nodes)}}
        modes.append(mode)
    low, high = s.travel
    out = {"drive": d.title, "file": d.path, **({"mode": d.mode} if d.mode else {}), "belt": s.belt,
           "travel": {"low": _q(low, "m"), "high": _q(high, "m")},
           "positions": _list(s.positions, "m"), "span1": _list(s.span1, "m"), "span2": _list(s.span2, "m"),
           "belt_stiffness": _list(s.stiffness, "N/m"), "modes": modes,
           "lowest": {"frequency": _q(s.lowest, "Hz"), "position": _q(s.lowest_at, "m"),
                      "evaluations": s.evaluations},
           "ends": {"low": {"position": _q(low, "m"), "frequency": _q(s.ends[0], "Hz")},
                    "high": {"position": _q(high, "m"), "frequency": _q(s.ends[1], "Hz")}},
           "band": None if band is None else {"low": _q(band[0], "Hz"), "high": _q(band[1], "Hz"),
                                              "modes_inside": _inside(s, band)},
           "warnings": warnings(s, band)}
    return out


def to_csv(s) -> str:
    """One row per position: position, spans [m], belt stiffness [N/m], then each mode's
    frequency [Hz] and damping ratio (empty where a position has fewer modes)."""
    header = ["position_m", "span1_m", "span2_m", "belt_stiffness_N_per_m"]
    for k in range(1, s.modes + 1):
        header += [f"f{k}_Hz", f"damping_ratio{k}"]
    rows = []
    for i in range(s.positions.size):
        row = [float(s.positions[i]), float(s.span1[i]), float(s.span2[i]), float(s.stiffness[i])]
        for k in range(s.modes):
            row += [float(s.frequency[i, k]), float(s.damping_ratio[i, k]) + 0.0]
        rows.append(row)
    return table_csv(header, rows)


def _text(value: float, digits: int = 4) -> str:
    return "-" if value is None or not math.isfinite(value) else format_number(float(value) + 0.0, digits)


def _mm(x: float) -> str:
    """A position [m] in mm, the grid's rounding (0.30000000000000004 m) left out."""
    return _text(round(float(x) * 1e3, 9))


def show(d, s, band) -> None:
    """The table (position, belt stiffness, the first modes) and the lowest point, the ends and the
    band (its warnings: :func:`warnings`, on stderr)."""
    from rich.markup import escape
    from rich.table import Table

    out = console()
    low, high = s.travel
    t = Table(title=escape(f"{d.title}: modes along the stroke of carriage belt {s.belt!r}, held at "
                           f"{s.positions.size} positions from {_mm(low)} to {_mm(high)} mm"), title_justify="left")
    shown = min(SHOWN, s.modes)
    cols = ["position mm", "belt k N/m", "mode 1 Hz", "damping ratio 1"] + [f"mode {k} Hz" for k in
                                                                           range(2, shown + 1)]
    for col in cols:
        t.add_column(col, justify="right")
    for i in range(s.positions.size):
        t.add_row(_mm(s.positions[i]), _text(s.stiffness[i]), _text(s.frequency[i, 0]),
                  _text(denoise(s.damping_ratio[i, 0]), 3), *(_text(s.frequency[i, k]) for k in range(1, shown)))
    out.print(t)
    where = ("the low end" if s.lowest_at == low else "the high end" if s.lowest_at == high else "inside the travel")
    lines = [f"lowest first frequency: {_text(s.lowest)} Hz at x = {_mm(s.lowest_at)} mm ({where})",
             f"first frequency at the ends: {_text(s.ends[0])} Hz at x = {_mm(low)} mm, "
             f"{_text(s.ends[1])} Hz at x = {_mm(high)} mm"]
    if s.modes > shown:
        lines.append(f"{s.modes} modes in all: --json or --csv for every one")
    if band is not None:
        lines.append(f"excitation band {band[0]:.4g} to {band[1]:.4g} Hz: the lowest first frequency is "
                     f"{_text(s.lowest / band[1], 3)} x its top")
    for line in lines:
        out.print(line, markup=False, highlight=False, soft_wrap=True)
