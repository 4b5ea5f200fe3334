"""``beltcalc chain``: roller-chain selection, sprocket geometry, chain length, safety.

References:

[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011): the command's default drive, [Shigley Example 17-5].
"""

from __future__ import annotations

import click

from beltcalc.design.checks import percent
from beltcalc.cli.contract import (check_rows, checks_json, echo_inputs, entry, fmt, options_text, out_of_range,
                                   quantity, shown)
from beltcalc.cli.options import catalog_option, output_options, quantity_option
from beltcalc.cli.output import (Row, console, dumps, emit_warnings, print_table, strict_option,
                                 table_csv, write_atomic, wrote)


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@quantity_option("--power", si_unit="W", display="kW", help="Power on the small sprocket [default: 90 hp when --torque is not given].")
@quantity_option("--torque", si_unit="N*m", help="Torque on the small sprocket, instead of --power.")
@quantity_option("--speed", si_unit="rad/s", display="rpm", default="300 rpm", help="Speed of the small sprocket.")
@click.option("--teeth", type=click.IntRange(min=3), default=17, show_default=True, help="Teeth of the small sprocket.")
@click.option("--teeth-large", type=click.IntRange(min=3), default=34, show_default=True,
              help="Teeth of the large sprocket.")
@quantity_option("--service-factor", si_unit="", default="1.3", help="Service factor K_s (load and driver).")
@quantity_option("--design-factor", si_unit="", default="1.5", help="Design factor n_d on the required rating.")
@quantity_option("--center-distance", si_unit="m", display="mm", help="Centre distance [default: --center-pitches x pitch].")
@quantity_option("--center-pitches", si_unit="", default="25", help="Centre distance in chain pitches, C/p.")
@click.option("--links", type=click.IntRange(min=1), default=None,
              help="Chain length in links instead of a centre distance (the centre distance follows); an odd count "
                   "takes an offset link, the rating x 0.65 [default: the even count at or above the centre "
                   "distance's].")
@click.option("--series", type=click.Choice(["all", "A", "B"]), default="all", show_default=True,
              help="ISO 606 series to choose from: A (ANSI) or B (DIN 8187).")
@click.option("--strands", type=click.IntRange(min=1, max=4), default=None, help="Only chains of this many strands.")
@click.option("--chain", "chain_name", default=None, help="Check this chain (e.g. 10B-1, 80-2, 16A-1) instead of choosing.")
@catalog_option
@output_options
@strict_option
@click.pass_context
def chain(ctx, power, torque, speed, teeth, teeth_large, service_factor, design_factor, center_distance, center_pitches,
          links, series, strands, chain_name, catalog_paths, as_json, csv_path, strict):
    """Roller-chain selection by the ACA power-rating formulas, with ISO 606 sprockets.

    With no options: [Shigley Example 17-5] (90 hp at 300 rev/min, 17/34 teeth, K_s = 1.3,
    n_d = 1.5, C/p = 25): 1 strand no. 200, 2 strands no. 160, 3 and 4 strands no. 140;
    3 strands of no. 140 chosen, 76 links.
    """
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.design.chain_select import HORSEPOWER, LUBRICATION, ChainInputs, select_chain

    if links is not None and center_distance is not None:
        raise click.BadParameter("give --links or --center-distance, not both: the link count sets the centre "
                                 "distance", param_hint="--links")
    cat = load_catalog(catalog_paths)
    if chain_name is not None:
        chains = [cat.chain(chain_name)]
    else:
        chains = [c for c in cat.chains.values()
                  if (series == "all" or c.series == series) and (strands is None or c.strands == strands)]
    if power is None and torque is None:
        power = 90 * HORSEPOWER
    inputs = ChainInputs(speed=speed, teeth_small=teeth, teeth_large=teeth_large, power=power, torque=torque,
                         service_factor=service_factor, design_factor=design_factor,
                         center_distance=center_distance, center_pitches=center_pitches, links=links)
    with out_of_range(ctx):
        report = select_chain(inputs, chains, name=chains[0].name if chain_name is not None else None)

    rows = report_rows(report)
    checks = check_rows(report.checks)
    warnings = options_text(report.warnings)
    emit_warnings(warnings, report.checks, strict)       # with --strict, a failing check ends here
    if csv_path is not None:
        write_atomic(csv_path, table_csv(["quantity", "value", "unit"],
                                         ([r.key, "" if r.value is None else repr(r.value), r.unit]
                                          for r in rows + checks)))
        wrote(csv_path)
    if as_json:
        obj = {r.key: quantity(r.value, r.unit) for r in rows}
        inputs = echo_inputs(ctx)
        if "power" not in inputs and torque is None:       # the help's default, 90 hp
            inputs["power"] = entry("90 hp", report.power, "W", "default")
        obj.update(chain=report.chosen.chain.name, rule=report.rule, lubrication=report.lubrication,
                   lubrication_method=LUBRICATION.get(report.lubrication),
                   candidates=[candidate_json(c) for c in report.candidates if c.carries],
                   best_per_strands={str(k): v.chain.name for k, v in sorted(report.best_per_strands.items())},
                   notes=options_text(report.notes), inputs=inputs, checks=checks_json(report.checks), warnings=warnings)
        click.echo(dumps(obj))
        return
    print_candidates(report)
    c = report.chosen.chain
    print_table(f"Chain {c.name} ({c.series} series, pitch {c.pitch * 1e3:g} mm), "
                f"z = {report.teeth[0]}/{report.teeth[1]}", [("drive", shown(rows)), ("checks (utilisation)", shown(checks))],
                notes=[f"rule: {report.rule}", f"data: {c.source.path}", *options_text(report.notes)])


def candidate_json(c) -> dict:
    def q(v, unit):
        return None if v is None else {"value": v, "unit": unit}
    return {"chain": c.chain.name, "strands": c.chain.strands, "pitch": q(c.chain.pitch, "m"),
            "rated_power": q(c.rated_power, "W"), "governing": c.governing, "utilisation": q(c.utilisation, "1"),
            "chain_speed": q(c.chain_speed, "m/s"), "pull": q(c.pull, "N"), "centrifugal_pull": q(c.centrifugal, "N"),
            "safety_factor": q(c.safety_factor, "1")}


def print_candidates(r) -> None:
    from rich.table import Table

    table = Table(title=f"Chains that carry {r.required / 1e3:.4g} kW (n_d K_s P), smallest pitch per strand count",
                  title_justify="left")
    for col in ("strands", "chain", "pitch [mm]", "rated [kW]", "limit", "utilisation", "safety F_B/F"):
        table.add_column(col, justify="right")
    for k, c in sorted(r.best_per_strands.items()):
        sf = fmt(c.safety_factor, 3)
        table.add_row(str(k), c.chain.name, fmt(c.chain.pitch * 1e3, 5),
                      fmt(c.rated_power / 1e3, 4), c.governing, percent(c.utilisation), sf)
    console().print(table)


def report_rows(r) -> list[Row]:
    c, g = r.chosen, r.geometry
    ch = c.chain
    rows = [
        Row("power", "power P", r.power, "W", "kW"),
        Row("torque", "torque on the small sprocket", r.torque, "N m"),
        Row("speed", "small sprocket speed", r.speed, "rad/s", "rpm"),
        Row("required_rating", "required rating n_d K_s P", r.required, "W", "kW"),
        Row("rated_power", f"rated power of {ch.name} ({c.governing})", c.rated_power, "W", "kW",
            note=f"x {c.derating:g}, offset link" if c.derating != 1 else ""),
        Row("utilisation", "utilisation", c.utilisation, "1", "percent", digits=3),
        Row("chain_speed", "chain speed v", c.chain_speed, "m/s"),
        Row("pull", "chain pull F = P / v", c.pull, "N"),
        Row("centrifugal_pull", "centrifugal pull q v^2", c.centrifugal, "N"),
        Row("breaking_load", "breaking load F_B (ISO 606 / ASME B29.1 minimum)", ch.breaking_load, "N", "kN"),
        Row("safety_factor", "safety F_B / (K_s F + q v^2)", c.safety_factor, "1", digits=3, note=">= 6 (Diamond Chain)"),
        Row("galling_speed", "galling speed (Shigley 17-5)", c.galling_speed, "rad/s", "rpm",
            note="the speed the ratings hold to"),
        *lubrication_rows(r),
        Row("pitch_diameter_small", "pitch diameter d1", g.pitch_diameters[0], "m", "mm"),
        Row("pitch_diameter_large", "pitch diameter d2", g.pitch_diameters[1], "m", "mm"),
        Row("tip_diameter_small_min", "tip diameter d1, min (ISO 606)", g.tip_diameters[0][0], "m", "mm"),
        Row("tip_diameter_small_max", "tip diameter d1, max (ISO 606)", g.tip_diameters[0][1], "m", "mm"),
        Row("tip_diameter_large_min", "tip diameter d2, min (ISO 606)", g.tip_diameters[1][0], "m", "mm"),
        Row("tip_diameter_large_max", "tip diameter d2, max (ISO 606)", g.tip_diameters[1][1], "m", "mm"),
        Row("root_diameter_small", "root diameter d1 - d_roller", g.root_diameters[0], "m", "mm"),
        Row("root_diameter_large", "root diameter d2 - d_roller", g.root_diameters[1], "m", "mm"),
        *([] if g.center_distance_asked is None else [
            Row("center_distance_asked", "centre distance asked", g.center_distance_asked, "m", "mm", digits=6),
            Row("links_exact", "chain length for the centre distance", g.links_exact, "1", digits=6,
                note="pitches")]),
        Row("links", "chain length (even)" if g.links % 2 == 0 else "chain length (odd: one offset link)",
            float(g.links), "1", note="links" if g.center_distance_asked is not None else "links, asked (--links)"),
        Row("center_distance", "centre distance for it (back-solved)", g.center_distance, "m", "mm", digits=6),
        Row("center_pitches", "centre distance C / p", g.center_distance / ch.pitch, "1", digits=4,
            note="30-80 (HKK Chain: 30-50 optimum)"),
        Row("wrap_small", "chain wrap, small sprocket", g.wrap_small, "rad", "deg", note=">= 120 deg"),
        Row("speed_ratio", "speed ratio z2 / z1", r.teeth[1] / r.teeth[0], "1", digits=4, note="<= 7"),
        Row("polygon_variation_small", "polygon speed variation, small", g.polygon_variation[0], "1", "percent",
            digits=3, note="1 - cos(180 deg / z)"),
        Row("polygon_variation_large", "polygon speed variation, large", g.polygon_variation[1], "1", "percent",
            digits=3),
    ]
    return rows


def lubrication_rows(r) -> list[Row]:
    """The chain speeds up to which Type A and Type B lubrication do (none when the catalog
    has no limits for the chain); the note marks the type this drive needs."""
    limits = r.chosen.chain.lubrication
    if limits is None:
        return []
    here = "<- this drive"
    return [Row("lubrication_limit_a", "Type A lubrication (manual, drip) up to", limits[0], "m/s",
                note=here if r.lubrication == "A" else ""),
            Row("lubrication_limit_b", "Type B lubrication (oil bath, disc) up to", limits[1], "m/s",
                note=here if r.lubrication == "B" else "above: Type C, oil stream <- this drive"
                if r.lubrication == "C" else "above: Type C, oil stream")]
