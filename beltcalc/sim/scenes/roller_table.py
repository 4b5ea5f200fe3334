"""The roller-table drive of [RP] as a network: induction motor -> elastic coupling ->
two-stage gear reducer -> gear output shaft and clutch in series [RP eq. 3] -> driving
sprocket -> chain strands, tension only [RP eq. 8-11] -> roller sprockets (and idler
sprockets) -> each roller: a shaft to its drive end, the tube to its far end, a load torque
at each end. Assembled from the components (Lagrange with Rayleigh dissipation in
:mod:`beltcalc.sim.network`), not typed from the paper's [RP eq. 14-15]. SI floats only.

Routing (``routing``):

- ``serpentine`` ([RP Fig. 1]): one chain from the driving sprocket over roller 1,
  (an idler,) roller 2, ... roller n and back to the driving sprocket;
- ``loops``: roller to roller, each pair of neighbours joined by its own chain loop (a
  tight and a slack strand), the first loop from the driving sprocket to roller 1.

Every strand is pretensioned by ``pretension`` [N]. A strand's mass is split between the
two sprockets it joins (as inertia m L / 2 r^2).

The chain is a catalog chain (``chain``, default 10B-1 in the scene file): its pitch, mass
per metre and breaking load come from ``catalogs/chains.toml`` (:class:`RollerTableScene`
fills ``chain_pitch``, ``chain_mass`` and ``chain_breaking_load`` from it unless they are
given), as the drive files' ``chain_strand`` takes them. Chains publish no stiffness:
``chain_stiffness`` (EA) stays the scene's stated assumption.

The scene ``simulate roller-table`` (``catalogs/scenes/roller_table.toml``) reports per
roller its speed and end torques, per strand its force extremes, time slack and safety,
and the motor's torque and start-up time.

With ``polygon = on`` every strand follows its sprockets' tooth polygons (the polygon action,
:class:`~beltcalc.sim.elements.polygon.PolygonStrand`) and the run is nonlinear (scipy's
Radau, stopped at every seating); the report names the tooth-passing frequency and its nearest
mode either way.

References:

[ISO 10823] ISO 10823:2004, Guidance on the selection of roller chain drives: the polygon
    effect, the tooth-passing frequency z n.
[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission".
[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    induction motor's linearised characteristic [M16 eq. 2].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from beltcalc.formulas.chain import load_split, placement_factor, sprocket_pitch_diameter, torsional_stiffness
from beltcalc.formulas.drive import cylinder_inertia
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.params import Param, Resolved
from beltcalc.report import Row, Section
from beltcalc.sim.network import Network, series_stiffness
from beltcalc.sim.scenes.base import (TIMING, Outcome, Scene, check_timing, motor_checks, resonance_check, scene_values,
                                      settling_check, strand_check, strand_sections, strands_at_end)

ROUTINGS = ("serpentine", "loops")
POLYGON = ("off", "on")
POSITIVE = {
    "chain_pitch": "m", "chain_mass": "kg/m", "chain_breaking_load": "N", "chain_stiffness": "N",
    "strand_length": "m", "drive_strand_length": "m", "sprocket_thickness": "m",
    "roller_diameter": "m", "roller_wall": "m", "roller_length": "m", "steel_density": "kg/m^3",
    "shear_modulus": "Pa", "shaft_diameter": "m", "shaft_length": "m", "motor_inertia": "kg*m^2",
    "rated_torque": "N*m", "breakdown_factor": "", "supply_frequency": "Hz", "ramp_time": "s",
    "coupling_stiffness": "N*m/rad", "coupling_inertia": "kg*m^2", "stage1_ratio": "", "stage2_ratio": "",
    "gear_input_inertia": "kg*m^2", "gear_middle_inertia": "kg*m^2", "gear_output_inertia": "kg*m^2",
    "output_shaft_stiffness": "N*m/rad", "clutch_stiffness": "N*m/rad", "element_width": "m",
}
ANY_SIGN = {"roller_load": "N*m"}   # negative: the transported element overruns the rollers
NONNEGATIVE = {
    "pretension": "N", "chain_damping_time": "s", "damping_time": "s", "coupling_damping": "N*m*s/rad",
    "idler_inertia": "kg*m^2", "load_amplitude": "N*m", "load_frequency": "rad/s",
    "load_start": "s", "element_offset": "m",
}
PLAIN = ("rollers", "drive_teeth", "roller_teeth", "idler_teeth", "pole_pairs", "breakdown_slip", "settle_tolerance")
# what the catalog chain (``chain``) gives unless the caller gives it: parameter -> Chain field
FROM_CHAIN = {"chain_pitch": "pitch", "chain_mass": "mass", "chain_breaking_load": "breaking_load"}
PARAMS = [Param(k, u, k.replace("_", " "), required=k not in FROM_CHAIN)
          for k, u in {**POSITIVE, **NONNEGATIVE, **ANY_SIGN, **{k: "" for k in PLAIN}, "routing": None,
                                                                      "polygon": None}.items()]
PARAMS += [Param("chain", None, "roller chain (catalogs/chains.toml name, e.g. 10B-1): pitch, mass, breaking load")]
PARAMS += TIMING


def catalog_chain(name: str):
    """The chain ``name`` of the built-in catalogs (:class:`beltcalc.data.catalogs.Chain`, SI);
    an unknown name is an error about ``chain`` (``scope="scene"``)."""
    from beltcalc.data.catalogs import load_catalog

    with scene_values(("chain",)):
        return load_catalog().chain(name)


def chain_values(name: str, given=None) -> dict[str, Resolved]:
    """``chain_pitch``, ``chain_mass`` and ``chain_breaking_load`` of the catalog chain
    ``name`` [m, kg/m, N], each with its origin (``catalog: <chain> (<file>)``), except the
    ones in ``given``. A chain whose mass the catalog does not print is an error about
    ``chain_mass``: the scene needs it for the sprockets' inertia.

    >>> v = chain_values("10B-1")
    >>> v["chain_pitch"].value, v["chain_mass"].value, v["chain_breaking_load"].value
    (0.015875, 0.91, 22200.0)
    """
    chain = catalog_chain(name)
    units = {"chain_pitch": "m", "chain_mass": "kg/m", "chain_breaking_load": "N"}
    file = Path(chain.source.path).name
    out = {}
    for key, attr in FROM_CHAIN.items():
        if given and given.get(key) is not None:
            continue
        value = getattr(chain, attr)
        if value is None:
            raise InputError(f"{chain.name} has no {attr} in {file}; give it", param=key, scope="scene")
        out[key] = Resolved(value, f"{value:g} {units[key]}", f"catalog: {chain.name} ({file})")
    return out


@dataclass(frozen=True)
class RollerTableScene(Scene):
    """The roller-table scene: its chain's data from the catalog (:func:`chain_values`)."""

    def resolve(self, ref=None, given=None):
        scene, values = super().resolve(ref, given)
        values.update(chain_values(values["chain"].value, given))
        return scene, values


def check(p: dict) -> None:
    """Refuse parameter values that make no physical sense (errors name the parameter, ``scope="scene"``)."""
    with scene_values(p):
        for key, unit in POSITIVE.items():
            require_positive(key, p[key], unit)
        for key, unit in NONNEGATIVE.items():
            require_range(key, p[key], unit, low=0.0)
        rollers = p["rollers"]
        if rollers != int(rollers) or not 1 <= rollers <= 200:
            raise InputError(f"{rollers:g} rollers is not allowed; it must be a whole number 1..200", param="rollers")
        for key in ("drive_teeth", "roller_teeth", "idler_teeth", "pole_pairs"):
            low = 1 if key == "pole_pairs" else 3
            if p[key] != int(p[key]) or p[key] < low:
                raise InputError(f"{p[key]:g} is not allowed; it must be a whole number >= {low}", param=key)
        if p["routing"] not in ROUTINGS:
            raise InputError(f"{p['routing']!r} is not a routing; use one of {', '.join(ROUTINGS)}", param="routing")
        if p["polygon"] not in POLYGON:
            raise InputError(f"{p['polygon']!r} is not allowed; use one of {', '.join(POLYGON)}", param="polygon")
        require_range("breakdown_slip", p["breakdown_slip"], "", 0.0, 1.0, low_open=True, high_open=True)
        require_range("roller_wall", p["roller_wall"], "m", 0.0, p["roller_diameter"] / 2, low_open=True,
                      high_open=True)
        require_range("element_width", p["element_width"], "m", 0.0, p["roller_length"], low_open=True)
        require_range("roller_load", p["roller_load"], "N*m")     # negative: the element overruns
        require_range("element_offset", p["element_offset"], "m", 0.0,
                      p["roller_length"] - p["element_width"] + 1e-9 * p["roller_length"])


def synchronous_speed(p: dict) -> float:
    """The motor's synchronous speed [rad/s]: 2 pi f / pole pairs."""
    return 2 * math.pi * p["supply_frequency"] / p["pole_pairs"]


def total_ratio(p: dict) -> float:
    """Motor speed / roller speed [-]: the two gear stages and the sprockets."""
    return p["stage1_ratio"] * p["stage2_ratio"] * p["roller_teeth"] / p["drive_teeth"]


def steady_speed(p: dict) -> float:
    r"""Steady roller speed [rad/s] under the mean loads.

    In steady rotation every strand and shaft holds a constant twist, so the motor carries
    the roller loads through the ratios: :math:`M_m = n M_{roller} / i_{tot}`, and the
    linearised characteristic [M16 eq. 2] gives
    :math:`\omega_m = \omega_0 (1 - S_c M_m / (2 M_c))`; the rollers turn at
    :math:`\omega_m / i_{tot}`.
    """
    torque = p["rollers"] * p["roller_load"] / total_ratio(p)
    w0 = synchronous_speed(p)
    mc = p["breakdown_factor"] * p["rated_torque"]
    return w0 * (1 - p["breakdown_slip"] * torque / (2 * mc)) / total_ratio(p)


def roller_inertia(p: dict) -> float:
    """Inertia of one roller tube [kg m^2] (a steel tube of the stated size)."""
    d = p["roller_diameter"]
    return cylinder_inertia(d, d - 2 * p["roller_wall"], p["roller_length"], p["steel_density"])


def sprocket_inertia(p: dict, teeth: int) -> float:
    """A sprocket as a steel disc of its pitch diameter and the stated thickness [kg m^2]."""
    d = sprocket_pitch_diameter(p["chain_pitch"], teeth)
    return cylinder_inertia(d, 0.0, p["sprocket_thickness"], p["steel_density"])


def strands(p: dict) -> list[tuple[str, str, str, float, float]]:
    """The chain routing: (name, from node, to node, length [m], from-radius/to-radius tag)."""
    n = int(p["rollers"])
    rollers = [f"sprocket{k}" for k in range(1, n + 1)]
    pitch, first = p["strand_length"], p["drive_strand_length"]
    out = []
    if p["routing"] == "serpentine":
        path = ["drive"]
        for k, r in enumerate(rollers):
            if k and p["idler_inertia"] > 0:
                path.append(f"idler{k}")
            path.append(r)
        lengths = []
        for a, b in zip(path, path[1:]):
            step = first if a == "drive" else (pitch / 2 if (a.startswith("idler") or b.startswith("idler")) else pitch)
            lengths.append(step)
        back = sum(lengths)      # the return strand runs back along the table
        for (a, b), length in zip(zip(path, path[1:]), lengths):
            out.append((f"{a}-{b}", a, b, length))
        out.append((f"{path[-1]}-drive", path[-1], "drive", back))
    else:
        ends = ["drive"] + rollers
        for k, (a, b) in enumerate(zip(ends, ends[1:])):
            length = first if k == 0 else pitch
            out.append((f"{a}-{b}", a, b, length))
            out.append((f"{b}-{a}", b, a, length))
    return out


def drive_data(p: dict) -> dict:
    """The drive (the structure of a drive file, SI floats) of the scene's parameters ``p``:
    its layout depends on ``rollers`` and ``routing``, so the scene writes it rather than
    reading one file. ``catalogs/drives/roller_table.toml`` is this drive for the default
    parameters (three rollers). The chain strands' mass goes half to each sprocket, as the
    drive-file builder does for every strand.

    The drive names its catalog chain: a sprocket is its ``teeth`` on that ``chain`` and a
    strand takes the chain's mass and breaking load from the catalog, as any drive file
    does; only a value that differs from the catalog's (``chain_pitch``, ``chain_mass``,
    ``chain_breaking_load`` given) is written out."""
    check(p)
    n = int(p["rollers"])
    beta = p["damping_time"]
    chain = catalog_chain(p["chain"])

    def sprocket(teeth: int) -> dict:
        if p["chain_pitch"] == chain.pitch:
            return {"teeth": teeth, "chain": p["chain"]}
        return {"pitch_diameter": sprocket_pitch_diameter(p["chain_pitch"], teeth)}

    pitch_d = {"drive": sprocket(int(p["drive_teeth"]))}
    J = {
        "motor": p["motor_inertia"] + p["coupling_inertia"] / 2,
        "gear": (p["coupling_inertia"] / 2 + p["gear_input_inertia"] + p["gear_middle_inertia"] / p["stage1_ratio"] ** 2
                 + p["gear_output_inertia"] / (p["stage1_ratio"] * p["stage2_ratio"]) ** 2),
        "drive": sprocket_inertia(p, int(p["drive_teeth"])),
    }
    roller = roller_inertia(p)
    for k in range(1, n + 1):
        pitch_d[f"sprocket{k}"] = sprocket(int(p["roller_teeth"]))
        J[f"sprocket{k}"] = sprocket_inertia(p, int(p["roller_teeth"])) * (2 if p["routing"] == "loops" and k < n else 1)
        J[f"end{k}a"] = J[f"end{k}b"] = roller / 2
    routing = strands(p)
    for name, a, b, _ in routing:
        for node in (a, b):
            if node.startswith("idler") and node not in J:
                J[node] = p["idler_inertia"]
                pitch_d[node] = sprocket(int(p["idler_teeth"]))
    nodes = [dict(name=name, inertia=value, **pitch_d.get(name, {})) for name, value in J.items()]

    c23 = series_stiffness(p["output_shaft_stiffness"], p["clutch_stiffness"])
    c_shaft = torsional_stiffness(p["shaft_diameter"], 0.0, p["shaft_length"], p["shear_modulus"])
    c_tube = torsional_stiffness(p["roller_diameter"], p["roller_diameter"] - 2 * p["roller_wall"],
                                 p["roller_length"], p["shear_modulus"])
    ratio = p["stage1_ratio"] * p["stage2_ratio"]
    couplings = [
        dict(name="coupling", between=["motor", "gear"], stiffness=p["coupling_stiffness"],
             damping=p["coupling_damping"]),
        # output shaft + clutch: C (phi_drive - phi_gear / i), the reducer's output angle
        dict(name="clutch", between=["drive", "gear"], stiffness=c23, damping=beta * c23, ratio=1.0 / ratio),
    ]
    for k in range(1, n + 1):
        couplings.append(dict(name=f"shaft{k}", between=[f"sprocket{k}", f"end{k}a"], stiffness=c_shaft,
                              damping=beta * c_shaft))
        couplings.append(dict(name=f"tube{k}", between=[f"end{k}a", f"end{k}b"], stiffness=c_tube,
                              damping=beta * c_tube))
    own = {key: p[f"chain_{key}"] for key in ("mass", "breaking_load") if p[f"chain_{key}"] != getattr(chain, key)}
    polygon = {"polygon": True} if p["polygon"] == "on" else {}
    chain_strands = [dict(name=name, **{"from": a, "to": b}, chain=p["chain"], length=length,
                          pretension=p["pretension"], stiffness=p["chain_stiffness"],
                          damping_time=p["chain_damping_time"], **own, **polygon)
                     for name, a, b, length in routing]
    near, far = load_split(placement_factor(p["element_offset"], p["element_width"], p["roller_length"]),
                           p["element_width"], p["roller_length"])
    loads = []
    t0 = p["load_start"]
    for k in range(1, n + 1):
        for end, share in (("a", near), ("b", far)):
            mean = share * p["roller_load"]
            load = dict(name=f"load_end{k}{end}", node=f"end{k}{end}", torque=0.0 if t0 > 0 else mean,
                        amplitude=share * p["load_amplitude"], frequency=p["load_frequency"], start=t0)
            if t0 > 0:
                load["table"] = [[t0, 0.0], [t0, mean]]
            loads.append(load)
    motor = dict(name="motor", kind="induction", node="motor", rated_torque=p["rated_torque"],
                 breakdown_factor=p["breakdown_factor"], breakdown_slip=p["breakdown_slip"],
                 supply=p["supply_frequency"], pole_pairs=int(p["pole_pairs"]), ramp=p["ramp_time"])
    return {"drive": {"title": "Roller table with chain transmission (Rusek & Popenda)", "t_end": p["t_end"],
                      "samples": int(p["samples"]), "window": p["window"]},
            "node": nodes, "coupling": couplings, "chain_strand": chain_strands, "motor": [motor], "load": loads}


def build(p: dict) -> Network:
    """The network of the scene's parameters ``p`` (SI floats and texts, keys as in
    roller_table.toml), built from :func:`drive_data` by the drive-file builder."""
    from beltcalc.sim.drivefile import DriveFile

    return DriveFile.from_data(drive_data(p), "roller table").network()


def run(values: dict, cfg) -> Outcome:
    """One run: per roller the speed and the torques at both ends over t >= ``window``, per
    strand its force extremes, time slack and safety over the whole run, the motor's torque
    and the start-up time (roller 1 within ``settle_tolerance`` of its speed before the load)."""
    from beltcalc.sim.core import simulate

    samples = check_timing(values)
    net = build(values)
    w0, n = values["window"], int(values["rollers"])
    watched = [f"{kind}{k}" for k in range(1, n + 1) for kind in ("omega_end", "T_shaft", "T_tube")]
    watched = [w + "a" if w.startswith("omega_end") else w for w in watched]
    watched += ["omega_motor", "M_motor"] + [f"F_{s.name}" for s in net.tension_strands]
    # the report: rollers over the window, the motor over the window and its peak over the run,
    # strands over the whole run: the estimate judges these figures
    reported = {name: (w0,) for name in watched}
    reported.update({"omega_motor": (0.0, w0), "M_motor": (0.0, w0)})
    reported.update({f"F_{s.name}": (0.0,) for s in net.tension_strands})
    result = simulate(net, values["t_end"], samples, cfg, watch=(watched, (0.0, w0), reported))
    sections = []
    for k in range(1, n + 1):
        speed = result.summary(f"omega_end{k}a", w0)
        ta, tb = result.summary(f"T_shaft{k}", w0), result.summary(f"T_tube{k}", w0)
        sections.append(Section(("rollers", str(k)), f"roller {k}", [
            Row("speed_mean", "speed mean", speed.mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed ampl.", speed.amplitude, "rad/s"),
            Row("torque_drive_end_mean", "torque drive end mean", ta.mean, "N m"),
            Row("torque_drive_end_amplitude", "ampl.", ta.amplitude, "N m"),
            Row("torque_far_end_mean", "torque far end mean", tb.mean, "N m"),
            Row("torque_far_end_amplitude", "ampl.", tb.amplitude, "N m"),
        ], group=f"rollers, t >= {w0:g} s (torque into the drive end through the journal, and along the tube "
                 "to the far end)", item=str(k)))
    breaking = {s.name: (values["chain_breaking_load"], "breaking load") for s in net.tension_strands}
    sections += strand_sections(net, result, breaking, "chain strands, whole run (tension only; slack = no force)",
                                label="breaking load / max")
    speed, torque = result.summary("omega_motor", w0), result.summary("M_motor", w0)
    whole = result.summary("M_motor", 0.0)
    peak = max(abs(whole.min), abs(whole.max))
    t_end, tol = values["t_end"], values["settle_tolerance"]
    start = min(values["load_start"], t_end) if values["load_start"] > 0 else t_end
    if 0 < values["load_start"] >= t_end:
        result.warnings.append(f"the run ends at {t_end:g} s (`t_end`) before the load lands at "
                               f"{values['load_start']:g} s (`load_start`): every value is without the load")
    target = result.summary("omega_end1a", 0.9 * start, start).mean
    no_load = steady_speed(dict(values, roller_load=0.0))
    settle = None
    if abs(target - no_load) <= tol * abs(no_load):   # roller 1 reached its no-load speed before the load
        settle = result.settle_time("omega_end1a", target, tol * abs(target), 0.0, start)
    sections.append(Section(("motor",), f"motor, t >= {w0:g} s", [
        Row("speed_mean", "speed, mean", speed.mean, "rad/s", "rpm", digits=5),
        Row("torque_mean", "torque, mean", torque.mean, "N m"),
        Row("torque_amplitude", "torque, amplitude", torque.amplitude, "N m"),
        Row("torque_peak", "torque, peak over the run", peak, "N m"),
        Row("startup_time", "start-up time", settle, "s",
            note=f"roller 1 within {values['settle_tolerance']:.0%} of its speed before the load"),
        Row("steady_speed_rollers", "roller speed, static balance", steady_speed(values), "rad/s", digits=5),
    ]))
    if settle is None:
        result.warnings.append(f"roller 1 did not settle within {tol:.0%} of its no-load speed "
                               f"({no_load:.4g} rad/s) before "
                               + ("the load lands" if start < t_end else "the run ends")
                               + ": no start-up time; raise `load_start` or `t_end`")
    sections.append(tooth_section(net, values, result))
    breakdown = values["breakdown_factor"] * values["rated_torque"]
    checks = strand_check(net, result, breaking) + motor_checks(result, "M_motor", breakdown, w0, speed="omega_motor")
    if values["polygon"] == "on":           # the run feels the tooth frequency: judge it against the modes
        checks += resonance_check(net, result, w0)
    checks += settling_check(net, w0, t_end, strands_at_end(net, result))
    return Outcome(net, result, sections, [], checks)


def tooth_section(net, values: dict, result) -> Section:
    """The chain's tooth-passing frequency over the window and its nearest natural frequency.

    Every sprocket on the chain passes teeth at f_z = v / p = z n [ISO 10823 sec. 5], v the
    chain's mean speed (roller 1's sprocket: v = p z n), and its polygon action pulses the
    strands at f_z and its harmonics. The modes are the network's with every strand taut
    (:func:`beltcalc.sim.frequency.poles`); with ``polygon = off`` the run does not feel the
    pulse, the row says where it would fall."""
    from beltcalc.sim.frequency import poles

    speed = abs(result.summary("omega_end1a", values["window"]).mean)
    f_z = values["roller_teeth"] * speed / (2 * math.pi)
    modes = [p for p in poles(net) if p.kind == "oscillatory"]
    rows = [Row("chain_speed", "chain speed, mean", values["chain_pitch"] * f_z, "m/s"),
            Row("tooth_frequency", "tooth-passing frequency z n", f_z, "Hz",
                note="every sprocket of the chain: chain speed / pitch")]
    if modes:
        near = min(modes, key=lambda p: abs(p.frequency - f_z))
        rows += [Row("nearest_mode", "nearest natural frequency", near.frequency, "Hz",
                     note=f"damping ratio {near.damping_ratio:.3g}"),
                 Row("separation", "separation |f_z - f_n| / f_n", abs(f_z - near.frequency) / near.frequency, "1",
                     digits=3, note="the run feels the pulse" if values["polygon"] == "on"
                     else "polygon = off: the run does not feel the pulse; --set polygon=on")]
    return Section(("chain",), f"chain, t >= {values['window']:g} s (polygon action {values['polygon']})", rows)


SCENE = RollerTableScene(
    "roller-table", "roller_table", PARAMS, build, run, "omega_end1a", "pretension=0N:600N:7",
    ("motor_torque_peak_N_m", "motor_speed_mean_rad_per_s", "drive-sprocket1_force_max_N",
     "sprocket3-drive_slack_time_s", "motor_startup_time_s"),
    (("speed [rad/s]", (("omega_end1a", "roller 1"), ("omega_end2a", "roller 2"), ("omega_end3a", "roller 3"))),
     ("motor torque [N m]", (("M_motor", "motor"),)),
     ("strand force [N]", (("F_drive-sprocket1", "drive to roller 1"), ("F_sprocket3-drive", "return")))),
)
