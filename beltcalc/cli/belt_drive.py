"""``beltcalc belt-drive``: belt length, centre distance, teeth in mesh and the capacity checks.

References (in the options' help):

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
[Tsubaki belts] Tsubakimoto Chain, technical data, synchronous belts.
"""

from __future__ import annotations

import click

from beltcalc.design.checks import percent
from beltcalc.cli.contract import checks_json, echo_inputs, entry, options_text, out_of_range, quantity, shown
from beltcalc.cli.options import catalog_option, output_options, quantity_option
from beltcalc.cli.output import Row, dumps, emit_warnings, print_table, strict_option, table_csv, write_atomic, wrote


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--belt", default="BRECO-AT10", show_default=True, help="Belt profile from the catalogs.")
@quantity_option("--width", si_unit="m", display="mm", default="25 mm", help="Belt width (a catalog width).")
@click.option("--select-width", is_flag=True, help="Check every catalog width, narrowest first; keep the first that passes.")
@click.option("--layout", type=click.Choice(["linear", "endless"]), default="linear", show_default=True,
              help="linear: belt clamped to a carriage, equal pulleys; endless: two-pulley drive.")
@click.option("--teeth", type=click.IntRange(min=3), default=40, show_default=True,
              help="Teeth of the (small, driving) pulley.")
@click.option("--teeth-large", type=click.IntRange(min=3), default=None,
              help="Teeth of the large pulley (endless drives) [default: = --teeth].")
@quantity_option("--center-distance", si_unit="m", display="mm", default="1245 mm", help="Pulley centre distance a.")
@quantity_option("--force", si_unit="N", help="Peripheral force F_U (instead of --torque or --mass x --accel).")
@quantity_option("--torque", si_unit="N*m", help="Torque on the driving pulley, e.g. motor-size's peak torque: F_U = 2 T / d1.")
@click.option("--from-motor-size", "motor_size", metavar="SCENE|FILE.json", default=None,
              help="F_U = 2 i T_M / d1 from motor-size's peak torque T_M and gear ratio i: a motor-size scene "
                   "(wdu, pdd, a scene .toml) sized with its own values, or the JSON that "
                   "'beltcalc motor-size ... --json' wrote (any of its options, --cycle files, gearboxes).")
@quantity_option("--mass", si_unit="kg", default="50 kg", help="Moving mass of a linear axis: F_U = m a + F_R.")
@quantity_option("--accel", si_unit="m/s^2", default="10 m/s^2", help="Peak acceleration of the moving mass.")
@quantity_option("--friction-force", si_unit="N", default="0 N", help="Running resistance F_R of the carriage.")
@quantity_option("--speed", si_unit="rad/s|m/s",
                 help="Running speed: pulley speed (1500rpm) or belt speed (2m/s); sets F_tspec(n).")
@quantity_option("--pretension", si_unit="N", help="Installation tension F_v [default: the manufacturers' rule].")
@quantity_option("--service-factor", si_unit="", help="Service factor c2 [default: from the Tsubaki tables].")
@click.option("--load", type=click.Choice(["smooth", "moderate", "heavy"]), default="moderate", show_default=True,
              help="Kind of load for the service factor [Tsubaki belts table 1].")
@quantity_option("--hours", si_unit="", default="8", help="Operating hours per day (service factor).")
@quantity_option("--peak-ratio", si_unit="", default="2", help="Motor peak output / rated output (service factor).")
@quantity_option("--starts-per-day", si_unit="", default="10", help="Starts and stops per day (service factor).")
@click.option("--idler", type=click.Choice(["none", "slack_inside", "slack_outside", "tight_inside", "tight_outside"]),
              default="none", show_default=True, help="Idler position (service factor).")
@quantity_option("--speed-up", si_unit="", default="1", help="Speed-increase ratio (service factor).")
@quantity_option("--stroke", si_unit="m", display="mm", help="Stroke of a linear axis [default: the whole free travel].")
@quantity_option("--carriage-length", si_unit="m", display="mm", default="0 mm", help="Carriage length between the belt clamps.")
@quantity_option("--clamp-allowance", si_unit="m", display="mm", default="0 mm", help="Belt length held in each clamp.")
@quantity_option("--tension-accel", si_unit="m/s^2", default="0.1 m/s^2",
                 help="Tensioning acceleration [W21 eq. 10].")
@quantity_option("--tension-speed", si_unit="m/s", default="5 mm/s", help="Tensioning speed [W21 eq. 10].")
@quantity_option("--f-tspec", si_unit="N/m", help="Specific tooth load at the running speed (e.g. 36.4N/cm), instead of the catalog table.")
@catalog_option
@output_options
@strict_option
@click.pass_context
def belt_drive(ctx, belt, width, select_width, layout, teeth, teeth_large, center_distance, force, torque, motor_size,
               mass, accel,
               friction_force, speed, pretension, service_factor, load, hours, peak_ratio, starts_per_day, idler,
               speed_up, stroke, carriage_length, clamp_allowance, tension_accel, tension_speed, f_tspec,
               catalog_paths, as_json, csv_path, strict):
    """Geometry and the checks a designer signs off for a timing-belt drive.

    With no options: the WDU linear axis of Wojtkowiak et al., Energies 14 (2021) 317 (AT10
    25 mm, a = 1245 mm, 40-tooth pulleys, 50 kg at 10 m/s^2): F_U = 500 N, installation
    tension 500 N by the manufacturers' rule beside the paper's 505.1 N, belt 2.89 m.
    """
    from beltcalc.design.belt_drive import BeltDriveInputs, check_belt_drive, select_belt_width
    from beltcalc.design.motor_peak import motor_size_peak
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.cli.main import OPTION_NAMES

    ctx.meta.setdefault(OPTION_NAMES, {}).update(RENAMED)
    if motor_size is not None:
        for name, value in (("--force", force), ("--torque", torque)):
            if value is not None:
                raise click.BadParameter(f"give {name} or --from-motor-size, not both", param_hint="--from-motor-size")
    cat = load_catalog(catalog_paths)
    peak = None
    if motor_size is not None:
        with out_of_range(ctx):
            peak = motor_size_peak(motor_size, cat)
    belt_entry = cat.belt(belt)
    factors = cat.service_factor_table("synchronous_belt")
    pulley_speed = belt_speed = None
    if speed is not None:
        value, unit = speed
        pulley_speed, belt_speed = (value, None) if unit == "rad/s" else (None, value)
    inputs = BeltDriveInputs(
        layout=layout, teeth=teeth, teeth_large=teeth_large, center_distance=center_distance, width=width,
        force=force, torque=torque, motor_size=peak, mass=mass, accel=accel, friction_force=friction_force,
        pulley_speed=pulley_speed, belt_speed=belt_speed, pretension=pretension, service_factor=service_factor,
        load=load, hours=hours, peak_ratio=peak_ratio, starts_per_day=starts_per_day, idler=idler,
        speed_up_ratio=speed_up, stroke=stroke, carriage_length=carriage_length, clamp_allowance=clamp_allowance,
        tension_accel=tension_accel, tension_speed=tension_speed, f_tspec=f_tspec,
    )
    with out_of_range(ctx):
        report = (select_belt_width if select_width else check_belt_drive)(inputs, belt_entry, factors)

    sections = report_rows(report)
    rows = [row for _, section in sections for row in section]
    warnings = options_text(report.warnings)
    emit_warnings(warnings, report.checks, strict)       # with --strict, a failing check ends here
    if csv_path is not None:
        write_atomic(csv_path, csv_text(rows))
        wrote(csv_path)
    if as_json:
        obj = {r.key: quantity(r.value, r.unit) for r in rows if not r.key.startswith("check_")}
        obj.update({"belt": report.belt, "layout": report.layout, "force_source": report.force_source,
                    "service_factor_source": report.service.text, "pretension_source": report.pretension_source})
        if report.selection is not None:
            obj["width_selection"] = selection_json(report.selection)
        inputs = echo_inputs(ctx)
        if "service_factor" not in inputs:
            inputs["service_factor"] = entry(f"{report.service.value:g}", report.service.value, "1",
                                             f"catalog: {report.service.text}")
        if report.f_tadm is not None:
            inputs["f_tadm"] = entry(f"{report.f_tadm:g} N", report.f_tadm, "N",
                                     f"catalog: {belt_entry.name} ({belt_entry.source.document})")
        obj.update(inputs=inputs, checks=checks_json(report.checks), notes=options_text(report.notes),
                   warnings=warnings)
        click.echo(dumps(obj))
        return
    title = (f"Belt drive ({report.layout}): {report.belt} {report.width * 1e3:g} mm, "
             f"z = {report.teeth[0]}/{report.teeth[1]}, a = {center_distance * 1e3:g} mm")
    print_table(title, [(name, shown(rows)) for name, rows in sections], notes=options_text(notes(report)))


#: Library parameters whose option has another name (errors and warnings name the option).
RENAMED = {"motor_size": "--from-motor-size", "speed_up_ratio": "--speed-up"}


def csv_text(rows) -> str:
    """quantity,value,unit rows; a check that is n/a has an empty value."""
    return table_csv(["quantity", "value", "unit"],
                     ([r.key, "" if r.value is None else repr(r.value), r.unit] for r in rows))


def selection_json(sel) -> dict:
    return {"rule": sel.rule, "chosen": {"value": sel.chosen, "unit": "m"},
            "tried": [{"width": {"value": t.width, "unit": "m"}, "worst_check": t.worst,
                       "utilisation": {"value": t.utilisation, "unit": "1"}, "passed": t.passed} for t in sel.tried]}


def notes(r) -> list[str]:
    out = [f"F_U: {r.force_source}", f"service factor c2: {r.service.text}", f"F_v: {r.pretension_source}"]
    for c in r.checks:
        if c.verdict == "n/a":
            out.append(f"{c.key}: not checked - {c.reason}")
    out += r.notes
    if r.selection is not None:
        tried = ", ".join(f"{t.width * 1e3:g} mm ({'pass' if t.passed else 'FAIL'}: {t.worst} {percent(t.utilisation)})"
                          for t in r.selection.tried)
        out.append(f"width selection: chose {r.selection.chosen * 1e3:g} mm; tried {tried}; rule: {r.selection.rule}")
    return out


def report_rows(r) -> list[tuple[str, list[Row]]]:
    """The belt-drive report as table sections (SI values, display units)."""
    geo = [
        Row("width", "belt width", r.width, "m", "mm"),
        Row("pitch_diameter_small", "pitch diameter d1", r.diameters[0], "m", "mm"),
        Row("pitch_diameter_large", "pitch diameter d2", r.diameters[1], "m", "mm"),
        Row("wrap_small", "wrap angle, small pulley", r.wrap[0], "rad", "deg"),
        Row("wrap_large", "wrap angle, large pulley", r.wrap[1], "rad", "deg"),
    ]
    if r.linear is not None:
        g = r.linear
        geo += [
            Row("belt_pitch_length", "belt between the clamps (pitch line)", g.pitch_length, "m", "mm",
                note="2a + pi d - l_c"),
            Row("belt_length", "belt to cut (with clamp allowances)", g.belt_length, "m", "mm"),
            Row("belt_teeth", "teeth between the clamps", r.belt_teeth, "1", digits=6),
            Row("return_span", "return span", g.return_span, "m", "mm"),
            Row("span_min", "carriage span at a stroke end, short", g.span_min, "m", "mm"),
            Row("span_max", "carriage span at a stroke end, long", g.span_max, "m", "mm"),
        ]
    else:
        geo += [
            Row("belt_length", "belt pitch length L (exact)", r.belt_length, "m", "mm", note="Shigley eq. 17-1"),
            Row("belt_teeth", "belt teeth L / P", r.belt_teeth, "1", digits=6),
            Row("span", "free span length", r.span, "m", "mm"),
        ]
        for side, teeth, a in zip(("shorter", "longer"), r.stock, r.stock_center_distance):
            if teeth is not None:
                geo.append(Row(f"stock_{side}_teeth", f"stock belt, {side}: teeth", float(teeth), "1"))
                geo.append(Row(f"stock_{side}_center_distance", "  centre distance for it (back-solved)", a,
                               "m", "mm", digits=7))
    geo += [Row("teeth_in_mesh", "teeth in mesh z_e", r.teeth_in_mesh, "1", digits=4,
                note="capped at z_e max" if r.teeth_in_mesh < r.teeth_in_mesh_uncapped else "")]
    forces = []
    if r.motor_size is not None:
        m = r.motor_size
        forces += [Row("motor_peak_torque", "motor-size's peak torque T_M", m.torque, "N m", note=m.source),
                   Row("gear_ratio", "gear ratio i", m.gear_ratio, "1"),
                   Row("pulley_torque", "pulley torque i T_M", m.pulley_torque, "N m")]
    forces += [
        Row("peripheral_force", "peripheral force F_U", r.force, "N"),
        Row("service_factor", "service factor c2", r.service.value, "1", digits=3),
    ]
    if r.speed is not None:
        forces += [Row("pulley_speed", "pulley speed n1", r.speed, "rad/s", "rpm"),
                   Row("belt_speed", "belt speed v", r.belt_speed, "m/s")]
    if r.specific_load is not None:
        forces += [Row("specific_tooth_load", "F_tspec at n1", r.specific_load, "N/m", "N/cm"),
                   Row("tooth_capacity", "tooth capacity F_tspec b z_e", r.tooth_capacity, "N")]
    forces += [
        Row("tight_side", "tight side (worst case)", r.tight, "N"),
        Row("slack_side", "slack side", r.slack, "N"),
        *([] if r.slack_design is None else
          [Row("slack_side_design", "slack side at c2 F_U", r.slack_design, "N",
               note="F_v - c2 F_U / 2; below 0 the span goes slack")]),
        Row("shaft_load_small", "shaft load F_W, small pulley", r.shaft_loads[0], "N"),
        Row("shaft_load_large", "shaft load F_W, large pulley", r.shaft_loads[1], "N"),
    ]
    if r.f_tadm is not None:
        forces.append(Row("allowable_tension", "allowable tension F_Tadm", r.f_tadm, "N"))
    install = [
        Row("pretension", "installation tension F_v", r.pretension, "N"),
        Row("pretension_rule", "manufacturers' rule", r.pretension_rule, "N",
            note="F_v >= F_U" if r.layout == "linear" else "F_v >= c2 F_U / 2"),
    ]
    if r.paper_tension is not None:
        install.append(Row("paper_tension", "paper's F_t,peak (eq. 10-12)", r.paper_tension, "N"))
    if r.span_frequency_rule is not None:
        install.append(Row("span_frequency", "span frequency at F_v", r.span_frequency_rule, "Hz",
                           note=f"span {r.span * 1e3:g} mm"))
    if r.span_frequency_paper is not None:
        install.append(Row("span_frequency_paper", "span frequency at F_t,peak", r.span_frequency_paper, "Hz"))
    checks = []
    for c in r.checks:
        util = c.utilisation
        note = (options_text([f"n/a ({c.reason})"])[0] if c.verdict == "n/a" else
                options_text([f"UNVERIFIED ({c.unverified})"])[0] if c.verdict == "unverified" else c.verdict)
        checks.append(Row(f"check_{c.key}", f"{c.name}: {c.rule.split(' (')[0]}", util, "1", "percent", digits=3,
                          note=note))
    return [("geometry", geo), ("forces", forces), ("installation tension", install),
            ("checks (utilisation)", checks)]
