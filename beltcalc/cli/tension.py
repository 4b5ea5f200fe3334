"""``beltcalc tension``: belt substitute model, pretension, bolt torque, span frequency.

References (in the options' help and the table's notes):

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
[VDI 2230] VDI 2230 Part 1 (2015), Systematic calculation of highly stressed bolted joints.
"""

from __future__ import annotations

import click

from beltcalc.design.checks import percent
from beltcalc.cli.contract import (check_rows, checks_json, echo_inputs, entry, options_text, out_of_range, quantity,
                                   shown)
from beltcalc.cli.options import catalog_option, output_options, quantity_option
from beltcalc.cli.output import (Row, dumps, emit_warnings, print_table, rows_csv, strict_option, write_atomic,
                                 wrote)


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--belt", default="BRECO-AT10", show_default=True,
              help="Belt profile from the catalogs (`beltcalc catalog list`), e.g. AT10, BRECO-T20.")
@quantity_option("--width", si_unit="m", display="mm", default="25 mm", help="Belt width (a catalog width).")
@click.option("--select-width", is_flag=True,
              help="Pick the narrowest catalog width whose F_Tadm covers safety factor x F_t,peak.")
@quantity_option("--safety-factor", si_unit="", default="1.0", help="Safety factor for --select-width.")
@quantity_option("--center-distance", si_unit="m", display="mm", default="1245 mm", help="Pulley center distance a (span length).")
@quantity_option("--mass", si_unit="kg", default="50 kg", help="Moving mass (carriage).")
@quantity_option("--accel", si_unit="m/s^2", default="10 m/s^2", help="Peak carriage acceleration.")
@quantity_option("--tension-accel", si_unit="m/s^2", default="0.1 m/s^2", help="Acceleration of the tensioning motion.")
@quantity_option("--tension-speed", si_unit="m/s", default="5 mm/s", help="Speed of the tensioning motion.")
@quantity_option("--damping", si_unit="N*s/m",
                 help="Belt damping b_TB. Default: fitted to the catalog's F_tspec(n), else the catalog's value.")
@quantity_option("--pulley-diameter", si_unit="m", display="mm", default="128 mm", help="Pulley pitch diameter D for the damping fit.")
@click.option("--substitute-mass-model", type=click.Choice(["eq7", "rayleigh"]), default="eq7",
              show_default=True, help="m_TB by [W21 eq. 7], or the Rayleigh m_belt/3.")
@quantity_option("--stiffness", si_unit="N/m", help="Belt stiffness k_TB, instead of C_spec / a.")
@quantity_option("--f-tadm", si_unit="N", help="Allowable belt tension F_Tadm, instead of the catalog's.")
@quantity_option("--c-spec", si_unit="N", help="Specific belt stiffness C_spec, instead of the catalog's.")
@quantity_option("--belt-weight", si_unit="kg/m", help="Belt mass per length w_spec, instead of the catalog's.")
@click.option("--thread", default="M10x1", show_default=True, help="Tensioner bolt thread from the catalogs.")
@quantity_option("--mu", si_unit="", default="0.2", help="Thread friction coefficient, in (0, 1).")
@quantity_option("--bearing-friction", si_unit="", default="0",
                 help="Friction coefficient under the bolt head [VDI 2230]; 0 leaves the term out.")
@quantity_option("--bearing-diameter", si_unit="m", display="mm", help="Effective friction diameter D_Km under the bolt head.")
@quantity_option("--span-length", si_unit="m", display="mm", help="Free span length for the span frequency [default: center distance].")
@catalog_option
@output_options
@strict_option
@click.pass_context
def tension(ctx, belt, width, select_width, safety_factor, center_distance, mass, accel, tension_accel,
            tension_speed, damping, pulley_diameter, substitute_mass_model, stiffness, f_tadm, c_spec,
            belt_weight, thread, mu, bearing_friction, bearing_diameter, span_length, catalog_paths,
            as_json, csv_path, strict):
    """Belt tension of a timing-belt linear axis, and the bolt torque that sets it.

    With no options: the WDU axis of Wojtkowiak et al., Energies 14 (2021) 317 (AT10 25 mm,
    a = 1245 mm, 50 kg at 10 m/s^2): F_t,peak = 505.1 N, x_max = 1.14 mm, 0.63 N m.
    """
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.errors import require_positive
    from beltcalc.design.tension import TensionInputs, design_tension, select_width as pick_width

    _require_companions(ctx, bearing_friction, bearing_diameter)
    require_positive("safety_factor", safety_factor, "")     # checked also without --select-width
    cat = load_catalog(catalog_paths)
    belt_entry = cat.belt(belt)
    thread_entry = cat.thread(thread)
    inputs = TensionInputs(
        center_distance=center_distance, width=width, mass=mass, accel=accel,
        tension_accel=tension_accel, tension_speed=tension_speed, mu=mu,
        pulley_diameter=pulley_diameter, damping=damping, span_length=span_length,
        substitute_mass_model=substitute_mass_model, stiffness=stiffness, f_tadm=f_tadm,
        c_spec=c_spec, belt_weight=belt_weight, bearing_friction=bearing_friction,
        bearing_diameter=bearing_diameter or 0.0,
    )
    with out_of_range(ctx):
        if select_width:
            report = pick_width(inputs, belt_entry, thread_entry, safety_factor)
        else:
            report = design_tension(inputs, belt_entry, thread_entry)

    sections = report_rows(report)
    rows = [row for _, section in sections for row in section]
    warnings = options_text(report.warnings)
    emit_warnings(warnings, report.checks, strict)       # with --strict, a failing check ends here
    if csv_path is not None:
        write_atomic(csv_path, rows_csv(rows))
        wrote(csv_path)
    if as_json:
        click.echo(dumps(json_object(ctx, report, rows, belt_entry, warnings)))
        return
    title = (f"Belt tension: {report.belt} {report.width * 1e3:g} mm, "
             f"a = {center_distance * 1e3:g} mm, thread {report.thread}")
    notes = [f"b_TB: {report.damping_source}"]
    if not report.bolt.bearing_torque:
        notes.append(f"bolt torque: {bolt_note(report.tension_peak)}")
    if report.selection_rule:
        tried = ", ".join(f"{w * 1e3:g} mm ({'pass' if ok else 'too narrow'}: {percent(u)} of F_Tadm)"
                          for w, u, ok in report.widths_tried)
        notes.append(f"width selection: chose {report.width * 1e3:g} mm; tried {tried}; "
                     f"rule: {report.selection_rule}")
    notes += [f"check {c.name}: {c.rule}" for c in report.checks if c.verdict == "FAIL"]
    print_table(title, [(name, shown(rows)) for name, rows in sections], notes=options_text(notes))


def bolt_note(force: float) -> str:
    """What the bolt torque leaves out when no bearing-face friction is given."""
    example = force * 0.15 * 0.015 / 2    # [VDI 2230] term with the README's example mu_K, D_Km
    return ("thread friction only (eq. 13 of the paper); tightening a bolt also turns its head or nut on its "
            "bearing face, F mu_K D_Km / 2 more (VDI 2230): give --bearing-friction and --bearing-diameter "
            f"(e.g. 0.15 and 15 mm add {example:.3g} N m here)")


def _require_companions(ctx, bearing_friction, bearing_diameter) -> None:
    """The bearing-face term needs both options: one without the other is a usage error."""
    from beltcalc.cli.contract import origin

    if bearing_friction and bearing_diameter is None:
        raise click.UsageError("--bearing-friction needs --bearing-diameter, the effective friction diameter "
                               "D_Km under the bolt head (e.g. --bearing-diameter 15mm)")
    if bearing_diameter is not None and origin(ctx, "bearing_friction") == "default":
        raise click.UsageError("--bearing-diameter needs --bearing-friction, the friction coefficient mu_K "
                               "under the bolt head (e.g. --bearing-friction 0.15)")


def json_object(ctx, r, rows, belt, warnings) -> dict:
    """The JSON of a tension report: every row as ``{"value", "unit"}`` (a value that
    cannot be given is null with a reason, a value that needs one with a note), the inputs
    with their origin, the checks and the warnings."""
    obj = {row.key: quantity(row.value, row.unit) for row in rows if not row.key.startswith("check_")}
    if not r.bolt.bearing_torque:
        obj["bearing_torque"]["reason"] = "no bearing-face friction given (--bearing-friction, --bearing-diameter)"
        obj["bolt_torque"]["note"] = bolt_note(r.tension_peak)
    inputs = echo_inputs(ctx, skip=("safety_factor",) if not r.selection_rule else ())
    cat = f"catalog: {belt.name} ({belt.source.document})"
    for name, value, unit in (("f_tadm", r.allowable_tension, "N"), ("c_spec", r.c_spec, "N"),
                              ("belt_weight", r.belt_weight, "kg/m")):
        if name not in inputs and value is not None:
            inputs[name] = entry(f"{value:.6g} {unit}", value, unit, cat)
    if "damping" not in inputs:
        where = cat if r.damping_fit is None else f"catalog: fitted to {belt.name}'s F_tspec(n) table"
        inputs["damping"] = entry(f"{r.damping:.6g} N*s/m", r.damping, "N*s/m", where)
    obj.update(belt=r.belt, thread=r.thread, substitute_mass_model=r.substitute_mass_model,
               damping_source=r.damping_source)
    if r.selection_rule:
        obj["width_selection"] = {
            "rule": r.selection_rule, "chosen": {"value": r.width, "unit": "m"},
            "tried": [{"width": {"value": w, "unit": "m"}, "utilisation": {"value": u, "unit": "1"}, "passed": ok}
                      for w, u, ok in r.widths_tried]}
    obj.update(inputs=inputs, checks=checks_json(r.checks), warnings=warnings)
    return obj


def report_rows(r) -> list[tuple[str, list[Row]]]:
    """The tension report as table sections (SI values, display units)."""
    mass_note = "eq. 7" if r.substitute_mass_model == "eq7" else "Rayleigh m_belt/3"
    failing = {c.key for c in r.checks if c.verdict == "FAIL"}
    failed = failing.__contains__
    belt = [
        Row("width", "belt width", r.width, "m", "mm"),
        Row("teeth", "teeth on the span z", r.teeth, "1", digits=5, note="eq. 14"),
        Row("belt_mass", "belt mass on the span", r.belt_mass, "kg", "g",
            note="eq. 15" + ("; FAIL: heavier than the carriage" if failed("belt_mass") else "")),
        Row("substitute_mass", "substitute mass m_TB", r.substitute_mass, "kg", "g", note=mass_note),
        Row("stiffness", "stiffness k_TB", r.stiffness, "N/m", "N/mm",
            note="C_spec / a, eq. 16" if r.c_spec is not None else "given (--stiffness)"),
        Row("damping", "damping b_TB", r.damping, "N s/m", note="see below"),
    ]
    if r.damping_fit is not None:
        belt.append(Row("damping_fit_r_squared", "damping fit R^2", r.damping_fit.r_squared, "1", digits=3,
                        note="FAIL: poor fit (see checks)" if failed("damping_fit") else ""))
    tension = [
        Row("tension_peak", "peak belt force F_t,peak", r.tension_peak, "N", note="eq. 10-11"),
        Row("pretension_displacement", "pretension displacement x_max", r.pretension_displacement,
            "m", "mm", note="eq. 12"),
        Row("allowable_tension", "allowable tension F_Tadm", r.allowable_tension, "N"),
        Row("utilisation", "utilisation F_t,peak / F_Tadm", r.utilisation, "1", "percent", digits=3,
            note="OVERLOADED" if r.utilisation > 1 else ""),
    ]
    bolt = [
        Row("lead_angle", "lead angle gamma", r.bolt.lead_angle, "rad", "deg", digits=3),
        Row("friction_angle", "friction angle rho'", r.bolt.friction_angle, "rad", "deg", digits=3),
        Row("thread_torque", "thread torque", r.bolt.thread_torque, "N m", digits=3, note="eq. 13"),
        Row("bearing_torque", "bearing-face torque", r.bolt.bearing_torque if r.bolt.bearing_torque else None,
            "N m", digits=3, note="VDI 2230" if r.bolt.bearing_torque else "not given (--bearing-friction)"),
        Row("bolt_torque", "bolt torque", r.bolt.torque, "N m", digits=3,
            note="thread + bearing face" if r.bolt.bearing_torque
            else "thread only: WITHOUT bearing-face friction (see below)"),
    ]
    check = [
        Row("span_length", "span length L", r.span_length, "m", "mm"),
        Row("span_frequency", "span frequency f", r.span_frequency, "Hz", digits=4,
            note="sonic tension meter, at F_t,peak"),
    ]
    return [("belt", belt), ("tension", tension), ("bolt tensioner", bolt), ("tension check", check),
            ("checks (utilisation)", check_rows(r.checks))]
