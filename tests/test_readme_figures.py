"""Every physics figure README.md and the docs pages (docs/**/*.md) quote, re-run from the
command that gives it.

Each entry of ``FIGURES`` is ``Figure(command, quote, figure, value, page=...)``:

* ``quote`` is text that stands in ``page`` (whitespace runs compared as one space), so an edit
  of the page's figure or of the words around it fails the test; ``on(page, [...])`` names the
  page of a group of entries, and an entry quoted elsewhere names its own (a figure that moves
  to another page moves its entry's page with it: the failure says where the quote now stands);
* ``figure`` is the number as the page prints it, inside ``quote``: its last digit sets the
  tolerance (half a unit of it, the page's own rounding);
* ``value(out)`` is the same quantity from the command's ``--json`` output (``COMMANDS``,
  run in-process through click's CliRunner, once each), in the page's unit, so a changed
  result fails the test.

Timings and speed ratios are not re-measured here: docs/performance.md names the benchmark file
each comes from, and the tests at the end check that it quotes those stored files
(``benchmarks/results/``) and that the files' error and step counts still come out of the code
(re-running the cheap rows). A last test fails when a table of a command's results
(``RESULT_TABLES``) gains a row with a number that no entry quotes.

Where a page's command takes over 10 s, a faster way to the same number is used (the chain
belt's first frequency without its time run) or the figure is marked slow (20 rollers).
"""

from __future__ import annotations

import json
import math
import re
import statistics
from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path
from typing import Callable

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import shared_run

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def squeeze(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def pages() -> list[str]:
    """README.md and every docs page, as paths from the repository's root."""
    return ["README.md"] + sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md"))


@cache
def page_text(page: str) -> str:
    """The page's text, whitespace runs as one space."""
    return squeeze((ROOT / page).read_text(encoding="utf-8"))


def readme() -> str:
    return page_text("README.md")


# -- the commands whose JSON the figures come from -------------------------------------------

# 20 rollers carrying the 120 N m of the default three (the default 40 N m a roller stalls the motor:
# docs/scenes.md says so in words)
ROLLER_20 = ("simulate", "roller-table", "--set", "rollers=20", "--set", "roller_load=6N*m")
DAMPED = ("--set", "d3=0.0052N*m*s/rad", "--set", "d4=0.006N*m*s/rad", "--set", "load_frequency=2000rad/s")
VERTICAL = ("motor-size", "--incline", "90deg", "--cycle", "catalogs/cycles/pick_place_vertical.toml",
            "--dc-bus-capacitance", "1000uF", "--dc-bus-voltage", "325V", "--chopper-voltage", "380V")
SPANS_400 = ("--set", "upper.length=400mm", "--set", "lower.length=400mm")
COMMANDS: dict[str, tuple[str, ...]] = {
    "tension": ("tension",),
    "tension rayleigh": ("tension", "--substitute-mass-model", "rayleigh"),
    "tension 5000 kg": ("tension", "--mass", "5000kg"),
    "tension T20": ("tension", "--belt", "BRECO-T20"),
    "tension width": ("tension", "--select-width", "--safety-factor", "1"),
    "tension width die": ("tension", "--mass", "90kg", "--center-distance", "795mm", "--select-width",
                          "--safety-factor", "1"),
    "motor-size": ("motor-size",),
    "motor-size pdd": ("motor-size", "--scene", "pdd"),
    "motor-size jerk": ("motor-size", "--jerk", "200m/s^3"),
    "motor-size vertical": VERTICAL,
    "friswell geared": ("simulate", "drive", "friswell_geared", "--modes"),
    "modes": ("modes",),
    "modes C4=50": ("modes", "--set", "45.stiffness=50N*m/rad"),
    "modes friswell": ("modes", "friswell_5_disks"),
    "modes friswell k4": ("modes", "friswell_5_disks", "--set", "k4.stiffness=11kN*m/rad"),
    "modes conveyor": ("modes", "conveyor"),
    "modes conveyor 400": ("modes", "conveyor", *SPANS_400),
    "modes stroke": ("modes", "linear_axis_moving", "--along-stroke", "50", "--band", "0:10Hz"),
    "response": ("response",),
    "response conveyor": ("response", "conveyor"),
    "campbell": ("campbell",),
    "campbell conveyor": ("campbell", "conveyor"),
    "campbell conveyor 400": ("campbell", "conveyor", *SPANS_400),
    "sewing": ("simulate", "sewing"),
    "sewing C4=50": ("simulate", "sewing", "--set", "C4=50N*m/rad"),
    "sewing 4rad/s": ("simulate", "sewing", "--set", "load_frequency=4rad/s"),
    "sewing C4 sweep": ("simulate", "sewing", "--steady-state-only", "--sweep", "C4=50N*m/rad:310N*m/rad:14"),
    "sewing C2 sweep": ("simulate", "sewing", "--steady-state-only", "--sweep", "C2=50N*m/rad:705N*m/rad:14"),
    "sewing damped sweep": ("simulate", "sewing", "--steady-state-only", *DAMPED, "--sweep", "C4=50N*m/rad:310N*m/rad:14"),
    "roller-table": ("simulate", "roller-table"),
    "roller-table slack": ("simulate", "roller-table", "--set", "pretension=0N"),
    "roller-table slack 20 s": ("simulate", "roller-table", "--set", "pretension=0N", "--t-end", "20s",
                                "--window", "15s"),
    "roller-table overrun": ("simulate", "roller-table", "--set", "roller_load=-40N*m"),
    "roller-table 20": ROLLER_20,
    "roller-table 12B-1": ("simulate", "roller-table", "--set", "chain=12B-1"),
    "linear-axis": ("simulate", "linear-axis"),
    "linear-axis rayleigh": ("simulate", "linear-axis", "--substitute-mass-model", "rayleigh"),
    "linear-axis speed-loop": ("simulate", "linear-axis", "--drive", "speed-loop"),
    "linear-axis moving": ("simulate", "linear-axis", "--set", "spans=moving", "--set", "cycle=out-and-back"),
    "linear-axis moving zv end": ("simulate", "linear-axis", "--set", "spans=moving", "--set", "cycle=out-and-back",
                                  "--set", "shaper=zv", "--set", "shaper_at=end"),
    "linear-axis moving zv": ("simulate", "linear-axis", "--set", "spans=moving", "--set", "cycle=out-and-back",
                              "--set", "shaper=zv"),
    "linear-axis moving zvd": ("simulate", "linear-axis", "--set", "spans=moving", "--set", "cycle=out-and-back",
                               "--set", "shaper=zvd"),
    "belt-drive": ("belt-drive",),
    "belt-drive carriage": ("belt-drive", "--carriage-length", "200mm", "--stroke", "800mm",
                            "--clamp-allowance", "50mm"),
    "belt-drive endless": ("belt-drive", "--belt", "Elatech-AT5", "--layout", "endless", "--teeth", "20",
                           "--teeth-large", "40", "--center-distance", "300mm", "--torque", "3N*m",
                           "--speed", "1500rpm", "--width", "25mm"),
    "belt-drive motor-size": ("belt-drive", "--from-motor-size", "wdu"),
    "chain": ("chain",),
    "chain 16B 650.4": ("chain", "--chain", "16B-1", "--power", "2kW", "--speed", "300rpm", "--center-distance",
                        "650.4mm"),
    "chain 16B 77 links": ("chain", "--chain", "16B-1", "--power", "2kW", "--speed", "300rpm", "--links", "77"),
    "chain 16B 78 links": ("chain", "--chain", "16B-1", "--power", "2kW", "--speed", "300rpm", "--links", "78"),
    "chain 40-1 12000": ("chain", "--chain", "40-1", "--power", "0.05kW", "--speed", "12000rpm"),
    "chain 06B 20000": ("chain", "--power", "0.05kW", "--speed", "20000rpm", "--teeth", "11", "--teeth-large", "60"),
    "chain B": ("chain", "--series", "B", "--power", "5kW", "--speed", "1000rpm", "--teeth", "19",
                "--teeth-large", "38", "--center-distance", "500mm"),
    "minimal": ("simulate", "drive", "minimal"),
}
SLOW = {"roller-table 20"}           # about 10-25 s: the one run over 10 s


def linear_axis_chain() -> dict:
    """`beltcalc simulate linear-axis --belt-model chain` takes 10-25 s for its time run; its
    first natural frequency is the network's, without the run: the same function, fast."""
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes.linear_axis import first_frequency

    scene = SCENES["linear-axis"]
    return {"first_frequency": first_frequency(scene.build(scene.values(belt_model="chain")))}


def sewing_rigid_train() -> dict:
    """The README's hand estimate: the loads' amplitudes over the train's inertia reflected to
    the main shaft times the load frequency, from the sewing drive's own values."""
    from beltcalc.sim.scenes import SCENES

    v = SCENES["sewing"].values()
    ratio = 1.375                                   # U12, catalogs/drives/sewing.toml
    inertia = v["J1"] * ratio ** 2 + v["J2"] + v["J3"] + v["J4"] + v["J5"]
    return {"inertia": inertia, "amplitude": (0.175 + 0.14) / (inertia * 228.0)}


def sewing_couplings() -> dict:
    """The toothed belt C4's damper against its spring at the load frequency, and its natural
    frequency between the two inertias it joins (the sewing scene's values)."""
    from beltcalc.sim.scenes import SCENES

    v = SCENES["sewing"].values()
    w = val(output("sewing")["steady_state"]["main_shaft"]["speed_mean"])
    return {"damper": v["d4"] * w, "spring": v["C4"],
            "natural": math.sqrt(v["C4"] * (1 / v["J4"] + 1 / v["J5"]))}


def roller_sprocket() -> dict:
    from beltcalc.formulas.chain import sprocket_pitch_diameter
    from beltcalc.sim.scenes import SCENES

    v = SCENES["roller-table"].values()
    return {"diameter": sprocket_pitch_diameter(v["chain_pitch"], int(v["roller_teeth"])), "teeth": v["roller_teeth"]}


def linear_axis_spans() -> dict:
    """k / k_TB with both belt paths, as the linear axis prints it beside each frequency."""
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes.linear_axis import prepare_scene, span_rows

    values = SCENES["linear-axis"].values()
    rows = span_rows(prepare_scene(values)[0], values)
    return {r.key.rsplit("_", 1)[1]: float(re.search(r"k = ([0-9.]+) k_TB", r.note)[1]) for r in rows}


PYTHON: dict[str, Callable[[], dict]] = {"linear-axis chain": linear_axis_chain,
                                         "sewing rigid train": sewing_rigid_train,
                                         "sewing couplings": sewing_couplings,
                                         "roller sprocket": roller_sprocket,
                                         "linear-axis spans": linear_axis_spans}


@cache
def output(command: str) -> dict:
    if command in PYTHON:
        return PYTHON[command]()
    result = shared_run(*COMMANDS[command], "--json")     # once per session (test_checks reads it too)
    assert result.exit_code == 0, f"beltcalc {' '.join(COMMANDS[command])} --json: {result.output[-2000:]}"
    return json.loads(result.stdout)


# -- reading the JSON ----------------------------------------------------------------------

def val(x) -> float:
    """A JSON number, bare or as {"value", "unit"}."""
    return float(x["value"] if isinstance(x, dict) else x)


def dig(d, path: str):
    """``d`` at ``path``: keys split by '/', list indices as integers."""
    for key in path.split("/"):
        if isinstance(d, dict) and isinstance(d.get("value"), list):
            d = d["value"]                          # a list with one unit
        d = d[int(key)] if isinstance(d, list) else d[key]
    return d


def STRAND_SAFETY(d: dict) -> float:
    """The strand check's value: the chain's breaking-load safety F_B / F of the most loaded strand."""
    return val(next(c for c in d["checks"] if c["key"] == "strand_strength")["value"])


def J(path: str, scale: float = 1.0) -> Callable[[dict], float | str]:
    """The number at ``path`` times ``scale``; a name as it is."""
    def get(d):
        x = dig(d, path)
        return x if isinstance(x, str) else val(x) * scale
    return get


def mode(d: dict, number: int) -> dict:
    """Oscillatory mode ``number`` (1-based) of a modes list."""
    return [m for m in d["modes"] if m["kind"] == "oscillatory"][number - 1]


def real_poles(d: dict) -> list[float]:
    return sorted((val(m["time_constant"]) for m in d["modes"] if m["kind"] == "real"), reverse=True)


def rotor_inertias(d: dict) -> list[float]:
    """The rotor inertia of every motor motor-size's table lists, from the catalog [kg m^2]."""
    from beltcalc import load_catalog

    cat = load_catalog()
    return [cat.motor(m["name"]).J for m in d["motors"]]


def motor(d: dict, name: str) -> dict:
    return next(m for m in d["motors"] if m["name"] == name)


def sweep(d: dict, key: str, row: int) -> float:
    """Column ``key`` (a column key or label) of a sweep's row ``row``."""
    keys = [c.get("key") for c in d["columns"]]
    if key not in keys:
        keys = [c.get("label") for c in d["columns"]]
    return val(d["rows"][row][keys.index(key)])


def peak(d: dict, output_name: str, near: float) -> dict:
    """The response peak of ``output_name`` nearest ``near`` Hz."""
    peaks = [p for r in d["responses"] if r["output"] == output_name for p in r["peaks"]]
    return min(peaks, key=lambda p: abs(val(p["frequency"]) - near))


def crossing(d: dict, order: float, mode_number: int) -> dict:
    return next(c for c in d["crossings"] if abs(val(c["order"]) - order) < 1e-3 and c["mode"] == mode_number)


def share(d: dict, number: int, element: str) -> float:
    return val(mode(d, number)["shape"]["strain_energy"][element])


def utilisation(d: dict, name: str) -> float:
    """The utilisation of the design check ``name`` ("tension member")."""
    return val(next(c for c in d["checks"] if name in (c.get("name"), c.get("check")))["utilisation"])


def smallest(d: dict, strands: int) -> str:
    """The chain of smallest pitch with ``strands`` strands among those that carry the load."""
    return min((c for c in d["candidates"] if c["strands"] == strands), key=lambda c: val(c["pitch"]))["chain"]


RPM = 60 / (2 * math.pi)
CM2 = 1e4                   # kg m^2 -> kg cm^2
MM = 1e3


NUMBER = re.compile(r"[-+]?[0-9][0-9,]*(\.[0-9]+)?(e[-+]?[0-9]+)?")


@dataclass(frozen=True)
class Figure:
    """``figure`` a number (compared to half a unit of its last digit, or ``tol``) or a name
    (``value`` gives the same text)."""

    command: str
    quote: str
    figure: str
    value: Callable[[dict], float | str]
    tol: float | None = None
    bound: bool = False         # the figure is an upper bound ("within 1e-10")
    low: float = 0.0            # a bound's lower limit ("between 6e-8 and 7e-8")
    page: str | None = None     # the file that quotes it ("README.md", "docs/scenes.md"); set by on()

    @property
    def number(self) -> bool:
        return NUMBER.fullmatch(self.figure.lower()) is not None

    def tolerance(self) -> float:
        """Half a unit of the figure's last printed digit."""
        if self.tol is not None:
            return self.tol
        mantissa, _, exponent = self.figure.lower().replace(",", "").partition("e")
        decimals = len(mantissa.partition(".")[2])
        return 0.5 * 10.0 ** (int(exponent or 0) - decimals)

    @property
    def id(self) -> str:
        return f"{self.command}: {self.figure} in '{self.quote[:40]}'"


F = Figure


def on(page: str, figures: list[Figure]) -> list[Figure]:
    """``figures`` quoted in ``page``, where an entry names no page of its own."""
    assert (ROOT / page).is_file(), page
    return [f if f.page else replace(f, page=page) for f in figures]
FIGURES = on("docs/tension.md", [
    # beltcalc tension: the worked example, Wojtkowiak et al. 2021
    F("tension", "| peak belt force F_t,peak | 505.1 N | 505.1 N |", "505.1", J("tension_peak")),
    F("tension", "| pretension displacement x_max | 1.143 mm |", "1.143", J("pretension_displacement", MM)),
    F("tension", "| lead angle / friction angle | 1.95 deg / 13.0 deg |", "1.95", J("lead_angle", 180 / math.pi)),
    F("tension", "| lead angle / friction angle | 1.95 deg / 13.0 deg |", "13.0",
      J("friction_angle", 180 / math.pi)),
    F("tension", "| bolt torque | 0.631 N m | 0.63 N m |", "0.631", J("bolt_torque")),
    F("tension rayleigh", "F_t,peak is 505.105 N with `beltcalc tension --substitute-mass-model rayleigh`",
      "505.105", J("tension_peak")),
    F("tension", "--substitute-mass-model rayleigh` against 505.100 N", "505.100", J("tension_peak")),
    F("tension rayleigh", "For the tension the difference is below 0.01 N here", "0.01",
      lambda d: abs(val(d["tension_peak"]) - val(output("tension")["tension_peak"])), bound=True),
    F("tension width", "(`beltcalc tension --select-width --safety-factor 1`: 16 mm at 36 % of", "16",
      J("width", MM)),
    F("tension width", "--safety-factor 1`: 16 mm at 36 % of F_Tadm", "36", J("utilisation", 100)),
    F("tension width die", "with `--mass 90kg --center-distance 795mm`: 16 mm at 65 %", "16", J("width", MM)),
    F("tension width die", "--center-distance 795mm`: 16 mm at 65 %", "65", J("utilisation", 100)),
]) + on("docs/motor_sizing.md", [
    # beltcalc motor-size: the WDU scene
    F("motor-size", "| motion | 3000 rpm, 3142 rad/s^2 |", "3000", J("motor_speed", RPM)),
    F("motor-size", "| motion | 3000 rpm, 3142 rad/s^2 |", "3142", J("motor_accel")),
    F("motor-size", "| reflected inertia | carriage 5.07 kg cm^2,", "5.07", J("inertia_carriage", CM2)),
    F("motor-size", "kg cm^2, pulleys 0.10, gearbox", "0.10", J("inertia_pulleys", CM2)),
    F("motor-size", "pulleys 0.10, gearbox 0.10, rotor", "0.10", J("inertia_gearbox", CM2)),
    F("motor-size", "gearbox 0.10, rotor 0.80, total", "0.80", J("inertia_motor", CM2)),
    F("motor-size", "rotor 0.80, total 6.07 kg cm^2 |", "6.07", J("reflected_inertia", CM2)),
    F("motor-size", "| load / motor inertia | 6.59 |", "6.59", J("inertia_ratio")),
    F("motor-size", "| torque | accelerate 1.91 -> 2.10 N m,", "1.91", J("phases/0/torque0")),
    F("motor-size", "| torque | accelerate 1.91 -> 2.10 N m,", "2.10", J("phases/0/torque1")),
    F("motor-size", "2.10 N m, cruise 0.19, decelerate", "0.19", J("torque_cruise")),
    F("motor-size", "decelerate -1.71 -> -1.90, dwell 0 |", "-1.71", J("phases/2/torque0")),
    F("motor-size", "decelerate -1.71 -> -1.90, dwell 0 |", "-1.90", J("phases/2/torque1")),
    F("motor-size", "decelerate -1.71 -> -1.90, dwell 0 |", "0", J("torque_dwell")),
    F("motor-size", "each phase's row is its peak, signed (decelerate -1.90 N m)", "-1.90", J("torque_decelerate")),
    F("motor-size", "| peak / RMS torque | 2.10 / 0.69 N m |", "2.10", J("peak_torque")),
    F("motor-size", "| peak / RMS torque | 2.10 / 0.69 N m |", "0.69", J("rms_torque")),
    F("motor-size", "against T_max 6.69 and T_n 1.91 N m: RMS is 36 % of rated |", "6.69",
      J("zone/limit")),
    F("motor-size", "against T_max 6.69 and T_n 1.91 N m: RMS is 36 % of rated |", "1.91",
      lambda d: val(motor(d, "SGM7J-06A")["rms_limit"])),
    F("motor-size", "against T_max 6.69 and T_n 1.91 N m: RMS is 36 % of rated |", "36",
      lambda d: val(motor(d, "SGM7J-06A")["utilisation"]) * 100),
    F("motor-size", "| braking | -1.90 N m, 27.9 J per cycle |", "-1.90", J("braking_torque")),
    F("motor-size", "| braking | -1.90 N m, 27.9 J per cycle |", "27.9", J("braking_energy")),
    F("motor-size", "| energy | eq. 29: 66.0 J; exact integral of T omega: 32.0 J |", "66.0", J("accel_energy")),
    F("motor-size", "| energy | eq. 29: 66.0 J; exact integral of T omega: 32.0 J |", "32.0",
      J("accel_energy_exact")),
    F("motor-size", "SGM7J-02A, SGMAH-04A and SGM7J-04A carry the torque but fail the inertia ratio (20,", "20",
      lambda d: val(motor(d, "SGM7J-02A")["inertia_ratio"])),
    F("motor-size", "fail the inertia ratio (20, 30.5 and 10.8)", "30.5",
      lambda d: val(motor(d, "SGMAH-04A")["inertia_ratio"])),
    F("motor-size", "fail the inertia ratio (20, 30.5 and 10.8)", "10.8",
      lambda d: val(motor(d, "SGM7J-04A")["inertia_ratio"])),
    F("motor-size", "SGM7J-06A is the smallest that passes all four", "SGM7J-06A", J("selected_motor")),
    F("motor-size", "none that passes does here (36 %)", "36", lambda d: val(motor(d, "SGM7J-06A")["utilisation"]) * 100),
    F("motor-size pdd", "the smallest passing motor, SGM7J-08A, runs at 60 %", "SGM7J-08A", J("selected_motor")),
    F("motor-size pdd", "the smallest passing motor, SGM7J-08A, runs at 60 %", "60",
      lambda d: val(motor(d, d["selected_motor"])["utilisation"]) * 100),
    # --gear-ratio 1 exits 1 (no motor fits); its figures from the default run's, with i^2
    F("motor-size", "the 50 kg carriage on a 127 mm pulley reflects 0.2 kg m^2", "0.2",
      lambda d: val(d["inertia_carriage"]) * val(d["gear_ratio"]) ** 2),
    F("motor-size", "on a 127 mm pulley reflects", "127", J("pulley_diameter", MM)),
    F("motor-size", "a 40-tooth AT10 pulley (d0 = 127.3 mm, the paper's D = 128 mm)", "127.3", J("pulley_diameter", MM)),
    F("motor-size", "about 290 times the rotor inertia of the largest catalog motor", "290",
      lambda d: val(d["inertia_carriage"]) * val(d["gear_ratio"]) ** 2 / max(rotor_inertias(d)), tol=5),
    F("motor-size", "and 51,000 times that of the smallest", "51,000",
      lambda d: val(d["inertia_carriage"]) * val(d["gear_ratio"]) ** 2 / min(rotor_inertias(d)), tol=500),
    F("motor-size jerk", "`beltcalc motor-size --jerk 200m/s^3` gives peak 2.054 N m", "2.054", J("peak_torque")),
    F("motor-size jerk", "v - a T_j/2 = 2250 rpm), RMS 0.624 N m", "2250", J("zone/speed", RPM)),
    F("motor-size jerk", "RMS 0.624 N m, cycle 1.65 s", "0.624", J("rms_torque")),
    F("motor-size jerk", "cycle 1.65 s, braking 26.7 J", "1.65", J("cycle_time")),
    F("motor-size jerk", "braking 26.7 J, zone margin 4.64 N m", "26.7", J("braking_energy")),
    F("motor-size jerk", "zone margin 4.64 N m, SGM7J-06A.", "4.64", J("zone_margin")),
    F("motor-size jerk", "zone margin 4.64 N m, SGM7J-06A.", "SGM7J-06A", J("selected_motor")),
    F("motor-size vertical", "--chopper-voltage 380V`): peak 3.153 N m (lifting the 10 kg part, 2625 rpm)",
      "3.153", J("peak_torque")),
    F("motor-size vertical", "(lifting the 10 kg part, 2625 rpm)", "2625", J("zone/speed", RPM)),
    F("motor-size vertical", "RMS 1.834 N m (the holding torque 1.873 N m", "1.834", J("rms_torque")),
    F("motor-size vertical", "(the holding torque 1.873 N m with the part counts)", "1.873", J("holding_torque")),
    F("motor-size vertical", "braking 176 J per cycle, of which the capacitors take 19.4 J", "176",
      J("braking_energy")),
    F("motor-size vertical", "of which the capacitors take 19.4 J", "19.4", J("dc_bus_energy")),
    F("motor-size vertical", "a resistor rated 373 W (Yaskawa's W_K = E_K / (0.2 T),", "373", J("resistor_rating")),
    F("motor-size vertical", "section 4), 74.7 W on average, 645 W peak", "74.7", J("resistor_power")),
    F("motor-size vertical", "74.7 W on average, 645 W peak, at most 224 ohm", "645", J("resistor_peak_power")),
    F("motor-size vertical", "645 W peak, at most 224 ohm", "224", J("resistance_max")),
    F("motor-size vertical", "SGM7J-06A at 96 % of its rated torque", "SGM7J-06A", J("selected_motor")),
    F("motor-size vertical", "SGM7J-06A at 96 % of its rated torque", "96",
      lambda d: val(motor(d, d["selected_motor"])["utilisation"]) * 100),
]) + on("docs/frequency_domain.md", [
    # simulate drive, modes, response, campbell
    F("friswell geared", "--modes # Friswell's geared system: 10.304, 20.479, 24.423 Hz", "10.304",
      lambda d: val(mode(d, 1)["frequency"]), page="docs/drive_files.md"),
    F("friswell geared", "Friswell's geared system: 10.304, 20.479, 24.423 Hz", "20.479",
      lambda d: val(mode(d, 2)["frequency"]), page="docs/drive_files.md"),
    F("friswell geared", "Friswell's geared system: 10.304, 20.479, 24.423 Hz", "24.423",
      lambda d: val(mode(d, 3)["frequency"]), page="docs/drive_files.md"),
    F("modes", "has one oscillatory mode, 17.36 Hz with damping ratio 0.302", "17.36",
      lambda d: val(mode(d, 1)["frequency"])),
    F("modes", "has one oscillatory mode, 17.36 Hz with damping ratio 0.302", "0.302",
      lambda d: val(mode(d, 1)["damping_ratio"])),
    F("modes", "and 8 real poles from 23.3 ms down to 1.65 us", "8", lambda d: len(real_poles(d))),
    F("modes", "and 8 real poles from 23.3 ms down to 1.65 us", "23.3", lambda d: real_poles(d)[0] * 1e3),
    F("modes", "and 8 real poles from 23.3 ms down to 1.65 us", "1.65", lambda d: real_poles(d)[-1] * 1e6),
    F("modes", "eigenvalues near -6e5 1/s, the explicit methods are held to steps", "-6e5",
      lambda d: -1 / real_poles(d)[-1], page="docs/performance.md"),
    F("modes", "motors free: 118, 281, 605, 858 Hz for sewing", "118", J("undamped_frequencies/0")),
    F("modes", "motors free: 118, 281, 605, 858 Hz for sewing", "281", J("undamped_frequencies/1")),
    F("modes", "motors free: 118, 281, 605, 858 Hz for sewing", "605", J("undamped_frequencies/2")),
    F("modes", "motors free: 118, 281, 605, 858 Hz for sewing", "858", J("undamped_frequencies/3")),
    F("modes friswell", "`beltcalc modes friswell_5_disks`: k4 holds 98.9 % of mode 1", "98.9",
      lambda d: share(d, 1, "k4") * 100),
    F("modes friswell k4", "`--set k4.stiffness=11kN*m/rad`, gives +4.8 %, predicted +4.9 %", "4.8",
      lambda d: (val(mode(d, 1)["frequency"]) / val(mode(output("modes friswell"), 1)["frequency"]) - 1) * 100),
    F("modes friswell", "gives +4.8 %, predicted +4.9 %", "4.9", lambda d: share(d, 1, "k4") * 0.1 / 2 * 100),
    F("modes conveyor", "(`beltcalc modes conveyor`: 24.17 Hz) keeps 34 % of its energy", "24.17",
      lambda d: val(mode(d, 2)["frequency"])),
    F("modes conveyor", "24.17 Hz) keeps 34 % of its energy in each belt span", "34",
      lambda d: share(d, 2, "upper") * 100),
    F("modes conveyor", "24.17 Hz) keeps 34 % of its energy in each belt span", "34",
      lambda d: share(d, 2, "lower") * 100),
    F("modes conveyor 400", "`--set upper.length=400mm --set lower.length=400mm`) move it to 27.4 Hz", "27.4",
      lambda d: val(mode(d, 2)["frequency"])),
    F("modes conveyor", "mode 4 (191 Hz) is 98 % the jaw coupling's", "191", lambda d: val(mode(d, 4)["frequency"])),
    F("modes conveyor", "mode 4 (191 Hz) is 98 % the jaw coupling's", "98", lambda d: share(d, 4, "jaw") * 100),
    F("modes conveyor", "(the conveyor's chain mode, 38.9 Hz,", "38.9", lambda d: val(mode(d, 3)["frequency"])),
    F("modes stroke", "`beltcalc modes linear_axis_moving --along-stroke 50` gives 48.82 Hz with the carriage at its "
      "start", "48.82", J("ends/low/frequency")),
    F("modes stroke", "start (x = 0, span 1 122.5 mm), falling", "122.5", J("span1/0", 1e3)),
    F("modes stroke", "the lowest first frequency, 20.64 Hz at x = 1000 mm,", "20.64", J("lowest/frequency")),
    F("modes stroke", "the lowest first frequency, 20.64 Hz at x = 1000 mm,", "1000", J("lowest/position", 1e3)),
    F("modes stroke", "L1 = L2 would lie at x = 1222.5 mm, beyond", "1222.5",
      lambda d: (val(d["span2"]["value"][0]) - val(d["span1"]["value"][0])) / 2 * 1e3),
    F("modes stroke", "`--band 0:10Hz` puts that lowest frequency at 2.06 x the band's top", "2.06",
      lambda d: val(d["lowest"]["frequency"]) / val(d["band"]["high"])),
    F("response conveyor", "Q 23 on the rotor's speed: `beltcalc response conveyor`", "23",
      lambda d: val(peak(d, "omega_rotor", 38.9)["q"])),
    F("response", "(sewing, `beltcalc response`: 16.9 Hz, Q 1.61 on the main shaft's speed omega_3)", "16.9",
      lambda d: val(peak(d, "omega_3", 17.0)["frequency"])),
    F("response", "(sewing, `beltcalc response`: 16.9 Hz, Q 1.61 on the main shaft's speed omega_3)", "1.61",
      lambda d: val(peak(d, "omega_3", 17.0)["q"])),
    F("campbell conveyor", "the conveyor's mode 2 meets order 1 at 1450 rpm (`beltcalc campbell conveyor`), 0.967 x",
      "1450", lambda d: val(crossing(d, 1, 2)["speed"]) * RPM),
    F("campbell conveyor", "(`beltcalc campbell conveyor`), 0.967 x the synchronous 1500 rpm", "0.967",
      lambda d: val(crossing(d, 1, 2)["speed_per_operating_speed"])),
    F("campbell conveyor 400", "put the crossing at 1642 rpm, 1.09 x)", "1642",
      lambda d: val(crossing(d, 1, 2)["speed"]) * RPM),
    F("campbell conveyor 400", "put the crossing at 1642 rpm, 1.09 x)", "1.09",
      lambda d: val(crossing(d, 1, 2)["speed_per_operating_speed"])),
    F("campbell", "the sewing loads at the main shaft's 227.9 rad/s are order 0.7253 of the motor", "0.7253",
      lambda d: min((val(c["order"]) for c in d["crossings"]), key=lambda o: abs(o - 0.7253))),
    F("campbell", "cross its 17.4 Hz mode at 1436 rpm: `beltcalc campbell`", "1436",
      lambda d: val(crossing(d, 0.7253, 1)["speed"]) * RPM),
    F("campbell", "cross its 17.4 Hz mode at 1436 rpm: `beltcalc campbell`", "17.4",
      lambda d: val(crossing(d, 0.7253, 1)["frequency"])),
]) + on("docs/scenes.md", [
    # simulate sewing
    F("sewing", "the sewing loads at the main shaft's 227.9 rad/s", "227.9",
      J("steady_state/main_shaft/speed_mean"), page="docs/frequency_domain.md"),
    F("sewing", "(18 periods from 0.50365 s by default;", "18",
      lambda d: next(val(c["value"]) for c in d["checks"] if c["key"] == "window_periods")),
    F("sewing", "load frequency = the steady main-shaft speed, 227.9 rad/s)", "227.9",
      J("steady_state/main_shaft/speed_mean")),
    F("sewing", "1e-6 of the bottom shaft's speed amplitude at the default C4", "1e-6",
      lambda d: J("shafts/bottom/speed_amplitude")(d) / J("steady_state/bottom_shaft/speed_amplitude")(d) - 1),
    F("sewing C4=50", "and 5e-4 at C4 = 50 N m/rad (`--set C4=50N*m/rad`)", "5e-4",
      lambda d: J("shafts/bottom/speed_amplitude")(d) / J("steady_state/bottom_shaft/speed_amplitude")(d) - 1),
    F("modes C4=50", "where a slow real pole (0.12 s: `beltcalc modes --set 45.stiffness=50N*m/rad`)", "0.12",
      lambda d: real_poles(d)[0]),
    F("sewing C4=50", "up to 5.4e-4 on the bottom shaft's speed amplitude, 1.8e-5 on its acceleration", "5.4e-4",
      lambda d: J("shafts/bottom/speed_amplitude")(d) / J("steady_state/bottom_shaft/speed_amplitude")(d) - 1,
      page="docs/performance.md"),
    F("sewing C4=50", "up to 5.4e-4 on the bottom shaft's speed amplitude, 1.8e-5 on its acceleration", "1.8e-5",
      lambda d: J("shafts/bottom/accel_amplitude")(d) / J("steady_state/bottom_shaft/accel_amplitude")(d) - 1,
      page="docs/performance.md"),
    F("sewing C4=50", "1.8e-5 on its acceleration and 4.3e-5 on its torque, largest at C4 = 50", "4.3e-5",
      lambda d: J("shafts/bottom/torque_amplitude")(d) / J("steady_state/bottom_shaft/torque_amplitude")(d) - 1,
      page="docs/performance.md"),
    F("sewing C4 sweep", "| bottom-shaft speed amplitude | 84 -> 25 1/s | 1.8719 -> 1.8726 rad/s |", "1.8719",
      lambda d: sweep(d, "steady_bottom_speed_amplitude_rad_per_s", 0)),
    F("sewing C4 sweep", "| bottom-shaft speed amplitude | 84 -> 25 1/s | 1.8719 -> 1.8726 rad/s |", "1.8726",
      lambda d: sweep(d, "steady_bottom_speed_amplitude_rad_per_s", -1)),
    F("sewing C4 sweep", "| 305 -> 31 1/s^2 | 426.52 -> 426.68 rad/s^2 |", "426.52",
      lambda d: sweep(d, "steady_bottom_accel_amplitude_rad_per_s2", 0)),
    F("sewing C4 sweep", "| 305 -> 31 1/s^2 | 426.52 -> 426.68 rad/s^2 |", "426.68",
      lambda d: sweep(d, "steady_bottom_accel_amplitude_rad_per_s2", -1)),
    F("sewing C4 sweep", "| 0.22 -> 0.045 N m | 0.07009 -> 0.07017 N m |", "0.07009",
      lambda d: sweep(d, "steady_bottom_torque_amplitude_N_m", 0)),
    F("sewing C4 sweep", "| 0.22 -> 0.045 N m | 0.07009 -> 0.07017 N m |", "0.07017",
      lambda d: sweep(d, "steady_bottom_torque_amplitude_N_m", -1)),
    F("sewing C2 sweep", "| main-shaft speed amplitude | 115 -> 28 1/s | 1.8636 -> 1.8637 rad/s |", "1.8636",
      lambda d: sweep(d, "steady_main_speed_amplitude_rad_per_s", 0)),
    F("sewing C2 sweep", "| main-shaft speed amplitude | 115 -> 28 1/s | 1.8636 -> 1.8637 rad/s |", "1.8637",
      lambda d: sweep(d, "steady_main_speed_amplitude_rad_per_s", -1)),
    F("modes", "finds one oscillatory mode (17.4 Hz, damping ratio 0.30:", "17.4",
      lambda d: val(mode(d, 1)["frequency"])),
    F("modes", "finds one oscillatory mode (17.4 Hz, damping ratio 0.30:", "0.30",
      lambda d: val(mode(d, 1)["damping_ratio"])),
    F("modes", "the whole train) and 8 real poles; every coupling mode", "8", lambda d: len(real_poles(d))),
    F("sewing couplings", "w d = 6 x 228 = 1370 N m/rad against C = 260", "1370", J("damper"), tol=5),
    F("sewing couplings", "w d = 6 x 228 = 1370 N m/rad against C = 260", "260", J("spring")),
    F("sewing couplings", "(d w = 1370 N m/rad against C = 260 at the load frequency)", "1370", J("damper"), tol=5,
      page="docs/frequency_domain.md"),
    F("sewing couplings", "natural frequency (about 2700 rad/s for C4)", "2700", J("natural"), tol=50),
    F("sewing rigid train", "train's inertia reflected to the main shaft (9.4e-4 kg m^2)", "9.4e-4", J("inertia")),
    F("sewing rigid train", "0.315 / (9.4e-4 x 228) = 1.5 rad/s", "1.5", J("amplitude")),
    F("sewing", "close to the simulated 1.87 (the motor adds the rest)", "1.87",
      J("steady_state/bottom_shaft/speed_amplitude")),
    F("sewing 4rad/s", "`--set load_frequency=4rad/s` gives 1.75 rad/s on the bottom shaft in the exact steady "
      "state", "1.75", J("steady_state/bottom_shaft/speed_amplitude")),
    F("sewing 4rad/s", "so the window rows read 1.467 rad/s, of part of a cycle", "1.467",
      J("shafts/main/speed_amplitude")),
    F("sewing 4rad/s", "its 0.5 s window holds less than one 1.57 s load period", "1.57",
      lambda d: next(float(m[1]) for w in d["warnings"] if (m := re.search(r"one load period \(([0-9.]+) s\)", w)))),
    F("sewing damped sweep", "shaft's amplitude in steady state only from 0.137 to 0.127 rad/s", "0.137",
      lambda d: sweep(d, "steady_bottom_speed_amplitude_rad_per_s", 0)),
    F("sewing damped sweep", "shaft's amplitude in steady state only from 0.137 to 0.127 rad/s", "0.127",
      lambda d: sweep(d, "steady_bottom_speed_amplitude_rad_per_s", -1)),
    F("sewing damped sweep", "shaft's amplitude in steady state only from 0.137 to 0.127 rad/s, 7 %", "7",
      lambda d: (1 - sweep(d, "steady_bottom_speed_amplitude_rad_per_s", -1)
                 / sweep(d, "steady_bottom_speed_amplitude_rad_per_s", 0)) * 100),
    F("sewing damped sweep", "while the main shaft's rises from 0.189 to 0.212 rad/s", "0.189",
      lambda d: sweep(d, "steady_main_speed_amplitude_rad_per_s", 0)),
    F("sewing damped sweep", "while the main shaft's rises from 0.189 to 0.212 rad/s", "0.212",
      lambda d: sweep(d, "steady_main_speed_amplitude_rad_per_s", -1)),
    # simulate roller-table
    F("roller sprocket", "19-tooth sprockets (d = p / sin(180 deg / z) = 96.45 mm)", "96.45", J("diameter", MM)),
    F("roller sprocket", "19-tooth sprockets (d = p / sin(180 deg / z) = 96.45 mm)", "19", J("teeth")),
    # An error estimate to one significant digit, held to half a unit of it: its digits are
    # rounding (the difference of two partitions), which another BLAS kernel moves. The roller
    # table's: 7.4e-9 N m under OpenBLAS Prescott, 8.5e-9 under Haswell, on the least or the
    # largest value of a shaft's torque (which figure is largest changes with the kernel too).
    # The slack start's: 1.24e-4 N, 2.78e-8 of the scale, on every kernel.
    F("roller-table", "With no options (3 rollers; error estimate 1e-8 N m, on a torque it reports, 1 strand switch",
      "1e-8", J("error_estimate")),
    F("roller-table", "With no options (3 rollers; error estimate 1e-8 N m, on a torque it reports, 1 strand switch",
      "1", J("events")),
    F("roller-table", "error estimate 1e-8 N m, on a torque it reports", "torque", lambda d: (
        "torque" if " of T_" in d["error_signal"] and d["error_estimate"]["unit"] == "N*m" else
        f"{d['error_signal']} [{d['error_estimate']['unit']}]")),
    F("roller-table slack", "the chain starts slack everywhere: 258 switches in the start-up", "258", J("events")),
    F("roller-table slack", "(estimate 9e-6 N, on the largest force of a strand, 2e-9 of its scale)", "9e-6",
      J("error_estimate")),
    F("roller-table slack", "(estimate 9e-6 N, on the largest force of a strand, 2e-9 of its scale)", "2e-9",
      J("error_relative")),
    F("roller-table slack", "(estimate 9e-6 N, on the largest force of a strand, 2e-9 of its scale)", "largest", lambda d: (
        "largest" if d["error_signal"].startswith("max of F_") and d["error_estimate"]["unit"] == "N" else
        f"{d['error_signal']} [{d['error_estimate']['unit']}]")),
    F("roller-table slack 20 s", "balance (6.1035588 rad/s with `--set pretension=0N --t-end 20s --window 15s`",
      "6.1035588", J("motor/steady_speed_rollers")),
    F("roller-table slack 20 s", "--t-end 20s --window 15s`, within 1e-10 of it)", "1e-10",
      lambda d: max(abs(val(r["speed_mean"]) - val(d["motor"]["steady_speed_rollers"])) for r in d["rollers"].values())
      / val(d["motor"]["steady_speed_rollers"]), bound=True),
    F("roller-table", "| roller speed, mean | 6.1036 rad/s |", "6.1036",
      lambda d: sum(val(r["speed_mean"]) for r in d["rollers"].values()) / len(d["rollers"])),
    F("roller-table", "has decayed; the static balance gives 6.1036 |", "6.1036", J("motor/steady_speed_rollers")),
    F("roller-table", "| torque into each roller's drive end, mean | 40.00 N m |", "40.00",
      J("rollers/1/torque_drive_end_mean")),
    F("roller-table", "| torque into each roller's drive end, mean | 40.00 N m |", "40.00",
      J("rollers/3/torque_drive_end_mean")),
    F("roller-table", "| torque along the tube to the far end, mean | 20.00 N m |", "20.00",
      J("rollers/2/torque_far_end_mean")),
    F("roller-table", "| drive strand force, min / max | 240 / 4196 N | breaking load / max = 5.3 |", "240",
      J("strands/drive-sprocket1/force_min")),
    F("roller-table", "| drive strand force, min / max | 240 / 4196 N | breaking load / max = 5.3 |", "4196",
      J("strands/drive-sprocket1/force_max")),
    F("roller-table", "| drive strand force, min / max | 240 / 4196 N | breaking load / max = 5.3 |", "5.3",
      J("strands/drive-sprocket1/safety")),
    F("roller-table", "| return strand | slack for 3.98 s |", "3.98", J("strands/sprocket3-drive/slack_time")),
    F("roller-table", "| motor torque, mean | 4.800 N m |", "4.800", J("motor/torque_mean")),
    F("roller-table", "| motor torque, peak over the run | 8.31 N m |", "8.31", J("motor/torque_peak")),
    F("roller-table", "| start-up time | 1.99 s |", "1.99", J("motor/startup_time")),
    # the chain's breaking-load safety against `chain`'s rule of 6 (issue 28): the default fails it
    F("roller-table", "The drive strand's peak, 4196 N when the element lands", "4196",
      J("strands/drive-sprocket1/force_max")),
    F("roller-table", "a breaking-load safety of 22.2 kN / 4196 N = 5.29 on the 10B-1", "22.2",
      J("inputs/chain_breaking_load", 1e-3)),
    F("roller-table", "a breaking-load safety of 22.2 kN / 4196 N = 5.29 on the 10B-1", "5.29", STRAND_SAFETY),
    F("roller-table", "`strand breaking-load safety FAILS: 5.291 must be >= 6`", "5.291", STRAND_SAFETY),
    F("roller-table", "names the breaking load the strand needs (25.18 kN)", "25.18",
      lambda d: 6 * val(d["strands"]["drive-sprocket1"]["force_max"]) / 1e3),
    F("roller-table 12B-1", "`--set chain=12B-1` (28.9 kN, 19.05 mm pitch", "28.9",
      J("inputs/chain_breaking_load", 1e-3)),
    F("roller-table 12B-1", "19.05 mm pitch: larger sprockets, a peak of 3398 N) passes with 8.50", "19.05",
      J("inputs/chain_pitch", 1e3)),
    F("roller-table 12B-1", "19.05 mm pitch: larger sprockets, a peak of 3398 N) passes with 8.50", "3398",
      J("strands/drive-sprocket1/force_max")),
    F("roller-table 12B-1", "19.05 mm pitch: larger sprockets, a peak of 3398 N) passes with 8.50", "8.50",
      STRAND_SAFETY),
    F("roller-table overrun", "the drive strand goes slack for 3.99 s", "3.99", J("strands/drive-sprocket1/slack_time")),
    F("roller-table overrun", "the return strand carries the force (4.3 kN)", "4.3",
      J("strands/sprocket3-drive/force_max", 1e-3)),
    F("roller-table overrun", "the motor brakes at -4.8 N m", "-4.8", J("motor/torque_mean")),
    F("roller-table 20",
      "--set rollers=20 --set roller_load=6N*m # any number 1..200 (20 carrying the load of 3: 37 switches)", "37",
      J("events")),
    # simulate linear-axis
    # (2.8e-13 to 2.9e-13 over four OpenBLAS kernel families)
    F("linear-axis", "error estimate 3e-13 m/s on the carriage speed", "3e-13", J("error_estimate")),
    F("linear-axis", "| belt force, min / max | -983 / 999 N |", "-983", J("belt/force_min")),
    F("linear-axis", "| belt force, min / max | -983 / 999 N |", "999", J("belt/force_max")),
    F("linear-axis", "| pretension F_t,peak (as `beltcalc tension`) | 505.1 N |", "505.1", J("belt/pretension")),
    F("linear-axis", "| pretension - max \\|force\\| | -494 N |", "-494", J("belt/pretension_margin")),
    F("linear-axis", "| first natural frequency (motor held) | 14.96 Hz |", "14.96", J("belt/first_frequency")),
    F("linear-axis", "| following error, max during the move | 2.26 mm |", "2.26",
      J("carriage/following_error_max", MM)),
    F("linear-axis", "| residual vibration after the move | 0.64 mm |", "0.64", J("carriage/residual_amplitude", MM)),
    F("linear-axis", "| settling time to 0.05 mm | - | not within the 1 s after the move |", "-",
      lambda d: "-" if d["carriage"]["settling_time"]["value"] is None else "settled"),
    F("linear-axis", "| motor torque, peak: dynamic / rigid | 3.66 / 2.10 N m | the belt's oscillation adds 74 % |",
      "3.66", J("motor/torque_peak")),
    F("linear-axis", "| motor torque, peak: dynamic / rigid | 3.66 / 2.10 N m | the belt's oscillation adds 74 % |",
      "2.10", J("motor/torque_peak_rigid")),
    F("linear-axis", "| motor torque, peak: dynamic / rigid | 3.66 / 2.10 N m | the belt's oscillation adds 74 % |",
      "74", lambda d: (J("motor/torque_peak")(d) / J("motor/torque_peak_rigid")(d) - 1) * 100),
    F("linear-axis", "| motor torque, RMS: dynamic / rigid | 1.76 / 0.69 N m |", "1.76", J("motor/torque_rms")),
    F("linear-axis", "| motor torque, RMS: dynamic / rigid | 1.76 / 0.69 N m |", "0.69", J("motor/torque_rms_rigid")),
    F("linear-axis speed-loop", "the motor gives way (peak 2.82 N m, RMS 0.74 N m,", "2.82", J("motor/torque_peak")),
    F("linear-axis speed-loop", "the motor gives way (peak 2.82 N m, RMS 0.74 N m,", "0.74", J("motor/torque_rms")),
    F("linear-axis speed-loop", "settled to 0.05 mm 0.14 s after the move)", "0.14", J("carriage/settling_time")),
    F("linear-axis speed-loop", "and the belt force stays at 771 N", "771", J("belt/force_max")),
    F("linear-axis chain", "| chain, eq. 1 (124 units) | - | 14.95285 Hz | - |", "14.95285", J("first_frequency")),
    F("linear-axis", "| substitute, eq. 7 (default) | 0.57 g | 14.95992 Hz | +4.7e-4 |", "14.95992",
      J("belt/first_frequency")),
    F("linear-axis", "| substitute, eq. 7 (default) | 0.57 g | 14.95992 Hz | +4.7e-4 |", "4.7e-4",
      lambda d: J("belt/first_frequency")(d) / output("linear-axis chain")["first_frequency"] - 1),
    F("tension", "| substitute, eq. 7 (default) | 0.57 g | 14.95992 Hz |", "0.57", J("substitute_mass", 1e3)),
    F("tension rayleigh", "| substitute, Rayleigh m_belt / 3 | 47.3 g | 14.95293 Hz | +6e-6 |", "47.3",
      J("substitute_mass", 1e3)),
    F("linear-axis rayleigh", "| substitute, Rayleigh m_belt / 3 | 47.3 g | 14.95293 Hz | +6e-6 |", "14.95293",
      J("belt/first_frequency")),
    F("linear-axis rayleigh", "| substitute, Rayleigh m_belt / 3 | 47.3 g | 14.95293 Hz | +6e-6 |", "6e-6",
      lambda d: J("belt/first_frequency")(d) / output("linear-axis chain")["first_frequency"] - 1),
    F("linear-axis rayleigh", "correction (81 times closer here)", "81",
      lambda d: (J("belt/first_frequency")(output("linear-axis")) / output("linear-axis chain")["first_frequency"] - 1)
      / (J("belt/first_frequency")(d) / output("linear-axis chain")["first_frequency"] - 1)),
    F("linear-axis spans", "against 14.96 Hz (k = 10.7 / 2.6 / 1.9 k_TB)", "10.7", J("start")),
    F("linear-axis spans", "against 14.96 Hz (k = 10.7 / 2.6 / 1.9 k_TB)", "2.6", J("mid")),
    F("linear-axis spans", "against 14.96 Hz (k = 10.7 / 2.6 / 1.9 k_TB)", "1.9", J("end")),
    F("tension", "The difference is m_belt / (6 m) = 5e-4", "5e-4", lambda d: val(d["belt_mass"]) / (6 * 50.0)),
    F("linear-axis", "stroke: 48.8 / 24.1 / 20.6 Hz against 14.96 Hz", "48.8", J("belt/first_frequency_spans_start")),
    F("linear-axis", "stroke: 48.8 / 24.1 / 20.6 Hz against 14.96 Hz", "24.1", J("belt/first_frequency_spans_mid")),
    F("linear-axis", "stroke: 48.8 / 24.1 / 20.6 Hz against 14.96 Hz", "20.6", J("belt/first_frequency_spans_end")),
    F("linear-axis", "stroke: 48.8 / 24.1 / 20.6 Hz against 14.96 Hz", "14.96", J("belt/first_frequency")),
]) + on("docs/design_checks.md", [
    # belt-drive, chain
    F("belt-drive", "| belt between the clamps, 2a + pi d (no carriage given) | 2890 mm, 289 teeth |", "2890",
      J("belt_length", MM)),
    F("belt-drive", "| belt between the clamps, 2a + pi d (no carriage given) | 2890 mm, 289 teeth |", "289",
      J("belt_teeth")),
    F("belt-drive", "| peripheral force F_U = m a | 500 N |", "500", J("peripheral_force")),
    F("belt-drive", "(Elatech p. 55) | 500 N, span frequency 26.60 Hz |", "500", J("pretension")),
    F("belt-drive", "(Elatech p. 55) | 500 N, span frequency 26.60 Hz |", "26.60", J("span_frequency")),
    F("belt-drive", "| the paper's F_t,peak (eq. 10-12), beside it | 505.1 N, 26.73 Hz |", "505.1", J("paper_tension")),
    F("belt-drive", "| the paper's F_t,peak (eq. 10-12), beside it | 505.1 N, 26.73 Hz |", "26.73",
      J("span_frequency_paper")),
    F("belt-drive", "| tension member F_U + F_v <= F_Tadm (2200 N) | 45.5 %, pass |", "2200", J("allowable_tension")),
    F("belt-drive", "| tension member F_U + F_v <= F_Tadm (2200 N) | 45.5 %, pass |", "45.5",
      lambda d: utilisation(d, "tension member") * 100),
    F("belt-drive", "| shaft load (worst carriage position) | 1500 N |", "1500", J("shaft_load_small")),
    F("belt-drive", "| tooth shear | n/a: AT10 has no F_tspec table (give `--f-tspec`) |", "n/a",
      lambda d: next(c for c in d["checks"] if "tooth shear" in (c.get("name"), c.get("check")))["verdict"]),
    F("belt-drive carriage", "# belt to cut 2790 mm, spans 122.5/922.5 mm", "2790", J("belt_length", MM)),
    F("belt-drive carriage", "# belt to cut 2790 mm, spans 122.5/922.5 mm", "122.5", J("span_min", MM)),
    F("belt-drive carriage", "# belt to cut 2790 mm, spans 122.5/922.5 mm", "922.5", J("span_max", MM)),
    F("belt-drive endless", "The endless example: belt 750.84 mm = 150.17 teeth", "750.84", J("belt_length", MM)),
    F("belt-drive endless", "The endless example: belt 750.84 mm = 150.17 teeth", "150.17", J("belt_teeth")),
    F("belt-drive endless", "stock 150 teeth at a = 299.577 mm or 151", "150", J("stock_shorter_teeth")),
    F("belt-drive endless", "stock 150 teeth at a = 299.577 mm or 151", "299.577",
      J("stock_shorter_center_distance", MM)),
    F("belt-drive endless", "151 teeth at a = 302.081 mm (back-solved exactly)", "151", J("stock_longer_teeth")),
    F("belt-drive endless", "151 teeth at a = 302.081 mm (back-solved exactly)", "302.081",
      J("stock_longer_center_distance", MM)),
    F("belt-drive endless", "z_e = 9.66; F_tspec(1500 rpm) = 24.16 N/cm", "9.66", J("teeth_in_mesh")),
    F("belt-drive endless", "z_e = 9.66; F_tspec(1500 rpm) = 24.16 N/cm", "24.16", J("specific_tooth_load", 1e-2)),
    F("belt-drive endless", "capacity 583.6 N against F_U c2 = 188.5 N x 1.4: 45 %", "583.6", J("tooth_capacity")),
    F("belt-drive endless", "capacity 583.6 N against F_U c2 = 188.5 N x 1.4: 45 %", "188.5", J("peripheral_force")),
    F("belt-drive endless", "capacity 583.6 N against F_U c2 = 188.5 N x 1.4: 45 %", "1.4", J("service_factor")),
    F("belt-drive endless", "capacity 583.6 N against F_U c2 = 188.5 N x 1.4: 45 %", "45", lambda d: utilisation(d, "tooth shear") * 100),
    F("chain", "1 strand no. 200, 2 strands no. 160,", "200", lambda d: float(smallest(d, 1).split("-")[0])),
    F("chain", "2 strands no. 160, 3 and 4 strands no. 140;", "160", lambda d: float(smallest(d, 2).split("-")[0])),
    F("chain", "3 and 4 strands no. 140;", "140", lambda d: float(smallest(d, 3).split("-")[0])),
    F("chain", "3 and 4 strands no. 140;", "140", lambda d: float(smallest(d, 4).split("-")[0])),
    F("chain", "it picks 140-3 (smallest pitch, then fewest strands), 76 links, a = 1115.9 mm", "140-3",
      J("chain")),
    F("chain", "it picks 140-3 (smallest pitch, then fewest strands), 76 links, a = 1115.9 mm", "76", J("links")),
    F("chain", "it picks 140-3 (smallest pitch, then fewest strands), 76 links, a = 1115.9 mm", "1115.9",
      J("center_distance", MM)),
    # issue 28: the endless pretension, the chain's plausibility checks, links
    F("belt-drive endless", "F_v = c2 F_U / 2 = 131.95 N keeps", "131.95", J("pretension")),
    F("belt-drive endless", "taut up to the design load: 37.70 N at F_U, 0 N at c2 F_U", "37.70", J("slack_side")),
    F("belt-drive endless", "taut up to the design load: 37.70 N at F_U, 0 N at c2 F_U", "0", J("slack_side_design")),
    F("chain", "Its C/p = 25.10 is below", "25.10", J("center_pitches")),
    F("chain", "no. 140's galling speed (929.3 rpm here)", "929.3", J("galling_speed", RPM)),
    F("chain", "ratio 2, chain wrap 167.7 deg", "167.7", J("wrap_small", 180 / math.pi)),
    F("chain 16B 650.4", "650.4 mm of 16B on 17/34 teeth needs 77.00 pitches of chain", "77.00", J("links_exact")),
    F("chain 16B 650.4", "78 links, which moves C to 663.19 mm", "78", J("links")),
    F("chain 16B 650.4", "78 links, which moves C to 663.19 mm", "663.19", J("center_distance", MM)),
    F("chain 16B 77 links", "put C at 650.42 mm and rate 16B-1 at 7.01 kW", "650.42", J("center_distance", MM)),
    F("chain 16B 77 links", "put C at 650.42 mm and rate 16B-1 at 7.01 kW", "7.01", J("rated_power", 1e-3)),
    F("chain 16B 78 links", "7.01 kW instead of 10.79 kW", "10.79", J("rated_power", 1e-3)),
    F("chain 40-1 12000", "(43 m/s; galling speed 7647 rpm on 17", "43", J("chain_speed")),
    F("chain 40-1 12000", "(43 m/s; galling speed 7647 rpm on 17", "7647", J("galling_speed", RPM)),
    F("chain 06B 20000", "lubrication data, galling speed 16249 rpm)", "16249", J("galling_speed", RPM)),
    F("chain B", "08B-3 is chosen (11.5 kW rated, 85 %)", "11.5", J("rated_power", 1e-3)),
    F("chain B", "08B-3 is chosen (11.5 kW rated, 85 %)", "08B-3", J("chain")),
    F("chain B", "08B-3 is chosen (11.5 kW rated, 85 %)", "85", J("utilisation", 100)),
    F("chain B", "108 links, safety factor 27", "108", J("links")),
    F("chain B", "108 links, safety factor 27", "27", J("safety_factor")),
    F("chain B", "The second line: 12B-1, 10B-2 or 08B-3 carry it", "12B-1", lambda d: smallest(d, 1)),
    F("chain B", "The second line: 12B-1, 10B-2 or 08B-3 carry it", "10B-2", lambda d: smallest(d, 2)),
    F("chain B", "The second line: 12B-1, 10B-2 or 08B-3 carry it", "08B-3", lambda d: smallest(d, 3)),
    F("belt-drive motor-size", "For the WDU axis: T_M = 2.1014 N m (SGM7J-06A) through the 20:1 gearbox", "2.1014",
      J("motor_peak_torque")),
    F("belt-drive motor-size", "For the WDU axis: T_M = 2.1014 N m (SGM7J-06A) through the 20:1 gearbox", "20",
      J("gear_ratio")),
    F("belt-drive motor-size", "gives F_U = 660.2 N, above m a = 500 N", "660.2", J("peripheral_force")),
    F("chain", "Example 17-5's 140-3 runs at 3.778 m/s: Type B (Type A up to 0.584 m/s,", "3.778", J("chain_speed")),
    F("chain", "Example 17-5's 140-3 runs at 3.778 m/s: Type B (Type A up to 0.584 m/s,", "B", J("lubrication")),
    F("chain", "Type B (Type A up to 0.584 m/s, Type B up to 5.59 m/s)", "0.584", J("lubrication_limit_a")),
    F("chain", "Type B (Type A up to 0.584 m/s, Type B up to 5.59 m/s)", "5.59", J("lubrication_limit_b")),
]) + on("docs/output.md", [
    # the percentage rule: a percentage up to 999 %, the factor beyond; R^2 a plain number
    F("tension", "(`beltcalc tension`: utilisation F_t,peak / F_Tadm 23.0 %)", "23.0", J("utilisation", 100)),
    F("tension 5000 kg", "`beltcalc tension --mass 5000kg` loads the belt to `x23` of", "23", J("utilisation")),
    F("tension T20", "(`beltcalc tension --belt BRECO-T20`: damping fit R^2 0.151)", "0.151",
      J("damping_fit_r_squared")),
])


# the belt axis as it moves: the WDU axis with both spans following the carriage, out and back
FIGURES += on("docs/belt_axis.md", [
    F("linear-axis moving", "| first frequency, carriage at the start (span 1 122.5 mm) | 48.82 Hz |", "48.82",
      J("belt/first_frequency_spans_start")),
    F("linear-axis moving", "| first frequency, carriage at the start (span 1 122.5 mm) | 48.82 Hz |", "122.5",
      lambda d: 1245.0 / 2 - 1000.0 / 2),
    F("linear-axis moving", "| first frequency, carriage at the end (span 1 1122.5 mm): the lowest on the stroke | "
      "20.64 Hz |", "20.64", J("belt/first_frequency_spans_end")),
    F("linear-axis moving", "| first frequency, carriage at the end (span 1 1122.5 mm): the lowest on the stroke | "
      "20.64 Hz |", "1122.5", lambda d: 1245.0 / 2 + 1000.0 / 2),
    F("linear-axis moving", "| residual vibration after the move out, unshaped | 0.333 mm |", "0.333",
      J("carriage/residual_amplitude", MM)),
    F("linear-axis moving", "| residual vibration after the move back, unshaped | 0.186 mm |", "0.186",
      J("carriage/residual_amplitude_back", MM)),
    F("linear-axis moving", "| settling into 0.05 mm after the move out, unshaped | not within the dwell |",
      "not within the dwell",
      lambda d: "not within the dwell" if d["carriage"]["settling_time"]["value"] is None else "settled"),
    F("linear-axis moving", "| settling into 0.05 mm after the move back, unshaped | 0.62 s |", "0.62",
      J("carriage/settling_time_back")),
    F("linear-axis moving zv end", "| residual after the move out, ZV for the mode where it stops only | 0.162 mm |",
      "0.162", J("carriage/residual_amplitude", MM)),
    F("linear-axis moving zv", "| residual after the move out, ZV for both ends (convolved) | 0.024 mm |", "0.024",
      J("carriage/residual_amplitude", MM)),
    F("linear-axis moving zvd", "| residual after the move out, ZVD for both ends | 0.0071 mm |", "0.0071",
      J("carriage/residual_amplitude", MM)),
    F("linear-axis moving zvd", "| time ZVD for both ends adds to each move | 68.9 ms |", "68.9",
      J("carriage/shaper_time", MM)),
    F("linear-axis moving", "| motor torque peak, dynamic: unshaped / ZVD | 3.58 / 2.04 N m |", "3.58",
      J("motor/torque_peak")),
    F("linear-axis moving zvd", "| motor torque peak, dynamic: unshaped / ZVD | 3.58 / 2.04 N m |", "2.04",
      J("motor/torque_peak")),
    F("linear-axis moving", "| static deflection under 50 N, carriage at the start / end | 0.0106 / 0.0595 mm |",
      "0.0106", J("static/static_error_start", MM)),
    F("linear-axis moving", "| static deflection under 50 N, carriage at the start / end | 0.0106 / 0.0595 mm |",
      "0.0595", J("static/static_error_end", MM)),
    F("linear-axis moving", "| static deflection under 50 N, carriage at the start / end | 0.0106 / 0.0595 mm |",
      "50", J("inputs/static_force")),
    F("linear-axis moving", "| pretension that keeps both spans taut under +-50 N | 47.7 N |", "47.7",
      J("static/static_pretension_needed")),
])


# the README's tour: rows of each command's printed table, as the README shows them
FIGURES += on("README.md", [
    F("linear-axis moving", "so its first mode falls from 48.8 Hz at the start of the WDU stroke to 20.6 Hz", "48.8",
      J("belt/first_frequency_spans_start")),
    F("linear-axis moving", "so its first mode falls from 48.8 Hz at the start of the WDU stroke to 20.6 Hz", "20.6",
      J("belt/first_frequency_spans_end")),
])
FIGURES += on("README.md", [
    F("tension", "│ peak belt force F_t,peak │ 505.1 │ N │", "505.1", J("tension_peak")),
    F("tension", "│ pretension displacement x_max │ 1.143 │ mm │", "1.143", J("pretension_displacement", MM)),
    F("tension", "│ stiffness k_TB │ 441.8 │ N/mm │", "441.8", J("stiffness", 1e-3)),
    F("tension", "│ utilisation F_t,peak / F_Tadm │ 23.0 │ % │", "23.0", J("utilisation", 100)),
    F("tension", "│ thread torque │ 0.631 │ N m │", "0.631", J("bolt_torque")),
    F("motor-size", "│ reflected inertia J_red │ 6.071 │ kg cm^2 │", "6.071", J("reflected_inertia", CM2)),
    F("motor-size", "│ load / motor inertia │ 6.59 │", "6.59", J("inertia_ratio")),
    F("motor-size", "│ peak torque │ 2.10 │ N m │ T_max 6.69 N m │", "2.10", J("peak_torque")),
    F("motor-size", "│ RMS torque │ 0.691 │ N m │ limit 1.91 N m: 36% of T_n │", "0.691", J("rms_torque")),
    F("motor-size", "│ braking energy per cycle │ 27.9 │ J │", "27.9", J("braking_energy")),
    F("motor-size", "recommended: SGM7J-06A: smallest motor that passes", "SGM7J-06A", J("selected_motor")),
    F("belt-drive", "│ belt between the clamps (pitch line) │ 2890 │ mm │", "2890", J("belt_length", MM)),
    F("belt-drive", "│ span frequency at F_v │ 26.60 │ Hz │", "26.60", J("span_frequency")),
    F("belt-drive", "│ tension member: F_U + F_v <= F_Tadm │ 45.5 │ % │ pass │", "45.5",
      lambda d: utilisation(d, "tension member") * 100),
    F("chain", "│ chain speed v │ 3.778 │ m/s │", "3.778", J("chain_speed")),
    F("chain", "│ chain length (even) │ 76 │ │ links │", "76", J("links")),
    F("chain", "│ centre distance for it (back-solved) │ 1115.88 │ mm │", "1115.88", J("center_distance", MM)),
    F("minimal", "│ torque, mean │ 4.000 │ N m │", "4.000", J("motors/M_motor/torque_mean")),
    F("minimal", "│ torque, peak over the run │ 7.359 │ N m │", "7.359", J("motors/M_motor/torque_peak")),
    F("minimal", "│ speed, mean │ 152.10 │ rad/s │", "152.10", J("motors/M_motor/speed_mean")),
    F("minimal", "│ strand switches │ 0 │", "0", J("events")),
    F("minimal", "│ tight │ 300 │ 369.3 │ 0 │ 5.96 │", "369.3", J("strands/tight/force_max")),
    F("minimal", "│ tight │ 300 │ 369.3 │ 0 │ 5.96 │", "5.96", J("strands/tight/safety")),
    F("minimal", "│ slack │ 230.7 │ 300 │ 0 │ 7.33 │", "230.7", J("strands/slack/force_min")),
    F("sewing", "│ speed, amplitude │ 1.872 │ rad/s │", "1.872", J("shafts/bottom/speed_amplitude")),
    F("sewing", "│ transmitted torque, amplitude │ 0.07015 │ N m │", "0.07015", J("shafts/bottom/torque_amplitude")),
    F("roller-table", "│ torque, mean │ 4.800 │ N m │", "4.800", J("motor/torque_mean")),
    F("roller-table", "│ start-up time │ 1.988 │ s │", "1.988", J("motor/startup_time")),
    F("linear-axis", "│ belt force, max │ 998.6 │ N │", "998.6", J("belt/force_max")),
    F("linear-axis", "│ first natural frequency │ 14.96 │ Hz │", "14.96", J("belt/first_frequency")),
    F("linear-axis", "│ torque, peak (dynamic) │ 3.664 │ N m │", "3.664", J("motor/torque_peak")),
    F("linear-axis", "│ torque, peak (motor-size, rigid) │ 2.101 │ N m │", "2.101", J("motor/torque_peak_rigid")),
    F("modes conveyor", "│ 3 │ mode 2 │ 24.17 │ 24.06 │ 0.0948 │", "24.17", lambda d: val(mode(d, 2)["frequency"])),
    F("modes conveyor", "│ 3 │ mode 2 │ 24.17 │ 24.06 │ 0.0948 │", "0.0948", lambda d: val(mode(d, 2)["damping_ratio"])),
    F("modes conveyor", "│ 4 │ mode 3 │ 38.87 │", "38.87", lambda d: val(mode(d, 3)["frequency"])),
    F("modes conveyor", "strain energy: upper (34.4 %), lower", "34.4", lambda d: share(d, 2, "upper") * 100),
    F("modes conveyor", "lower (34.4 %), chain_tight", "34.4", lambda d: share(d, 2, "lower") * 100),
    F("modes conveyor", "chain_tight (11.8 %), chain_return", "11.8", lambda d: share(d, 2, "chain_tight") * 100),
    F("modes conveyor", "chain_return (11.8 %)", "11.8", lambda d: share(d, 2, "chain_return") * 100),
    F("response conveyor", "│ omega_rotor │ load:drum2 │ 38.77 │ 0.2820 │ rad/s/(N m) │ 22.8 │", "38.77",
      lambda d: val(peak(d, "omega_rotor", 38.9)["frequency"])),
    F("response conveyor", "│ omega_rotor │ load:drum2 │ 38.77 │ 0.2820 │ rad/s/(N m) │ 22.8 │", "22.8",
      lambda d: val(peak(d, "omega_rotor", 38.9)["q"])),
    F("campbell conveyor", "│ 151.9 │ 1450 │ 0.967 │ 1 │ 2 │ 24.17 │", "151.9", lambda d: val(crossing(d, 1, 2)["speed"])),
])


def params(slow: bool):
    return [pytest.param(f, id=f.id, marks=[pytest.mark.slow] if f.command in SLOW else [])
            for f in FIGURES if (f.command in SLOW) == slow]


def check(figure: Figure) -> None:
    assert figure.figure in figure.quote, f"{figure.figure!r} is not in its own quote"
    quote = squeeze(figure.quote)
    if quote not in page_text(figure.page):
        elsewhere = [p for p in pages() if quote in page_text(p)]
        raise AssertionError(f"{figure.page} no longer says: {figure.quote!r}"
                             + (f" (it stands in {', '.join(elsewhere)}: move the entry's page)" if elsewhere else ""))
    got = figure.value(output(figure.command))
    if not figure.number:
        assert got == figure.figure, f"README.md says {figure.figure} ({figure.quote!r}); the command gives {got}"
        return
    expected = float(figure.figure.replace(",", ""))
    if figure.bound:
        assert figure.low <= got <= expected, (f"README.md says within {figure.figure} ({figure.quote!r}); "
                                               f"got {got:.3g}")
        return
    assert got == pytest.approx(expected, abs=figure.tolerance() * (1 + 1e-9)), (
        f"README.md says {figure.figure} ({figure.quote!r}); `beltcalc {' '.join(COMMANDS.get(figure.command, ()))}`"
        f" gives {got:.6g}")


@pytest.mark.parametrize("figure", params(slow=False))
def test_readme_figure(figure):
    check(figure)


@pytest.mark.parametrize("figure", params(slow=True))
def test_readme_figure_slow(figure):
    check(figure)


def test_every_command_is_used_and_tolerances_are_read():
    used = {f.command for f in FIGURES + BENCHMARK_FIGURES}
    assert used == set(COMMANDS) | set(PYTHON)
    assert F("x", "1.143", "1.143", len).tolerance() == pytest.approx(5e-4)
    assert F("x", "2.3e-8", "2.3e-8", len).tolerance() == pytest.approx(5e-10)
    assert F("x", "4196", "4196", len).tolerance() == pytest.approx(0.5)
    assert F("x", "-1.90", "-1.90", len).tolerance() == pytest.approx(5e-3)


# -- the benchmark results the README quotes ------------------------------------------------

def results_table(name: str) -> dict[str, dict]:
    """The first table of ``benchmarks/results/work_precision_<name>.md``, keyed "method rtol"
    ("exact -" for exact): wall_ms, rhs_calls, steps, error (None where the run failed)."""
    rows = {}
    for line in (RESULTS / f"work_precision_{name}.md").read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[0] not in ("method", "---"):
            method, rtol, wall, calls, steps, error, _ = cells
            rows[f"{method} {rtol}"] = {"wall_ms": None if wall == "-" else float(wall), "rhs_calls": int(calls),
                                        "steps": int(steps), "error": None if error == "-" else float(error)}
        elif rows and not line.strip():
            break
    return rows


def ratio(d: dict, key: str) -> float:
    return d[key]["wall_ms"] / d["exact -"]["wall_ms"]


_STEPS = "the exact run takes about 53,000 steps of about 130 us on average chosen from the dynamics"
for _scene in ("sewing", "roller_table", "linear_axis"):
    PYTHON[f"results {_scene}"] = (lambda s: lambda: results_table(s))(_scene)

R = "results sewing"
_RK45 = "| RK45, rtol 1e-6 | 1e-5 | 29.2 s, about 183,000 steps, 1.3 million RHS calls | 48424 |"
_DOP = "| DOP853, rtol 1e-6 | 1.8e-4 | 26.2 s, about 95,000 steps, 1.2 million RHS calls | 43449 |"
BENCHMARK_FIGURES = on("docs/performance.md", [
    # the sewing table: benchmarks/results/work_precision_sewing.md
    F(R, "| exact (expm, blocks) | 6.5e-8 (its estimate) | 0.603 ms | 1 |", "6.5e-8", J("exact -/error")),
    F(R, "| exact (expm, blocks) | 6.5e-8 (its estimate) | 0.603 ms | 1 |", "0.603", J("exact -/wall_ms")),
    F(R, "| odeint (LSODA, Dfun), rtol 1e-10 | 3.2e-7 | 79 ms | 132 |", "3.2e-7", J("odeint 1e-10/error")),
    F(R, "| odeint (LSODA, Dfun), rtol 1e-10 | 3.2e-7 | 79 ms | 132 |", "79", J("odeint 1e-10/wall_ms")),
    F(R, "| odeint (LSODA, Dfun), rtol 1e-10 | 3.2e-7 | 79 ms | 132 |", "132", lambda d: ratio(d, "odeint 1e-10")),
    F(R, "| solve_ivp LSODA, rtol 1e-10 | 2.8e-7 | 359 ms | 595 |", "2.8e-7", J("lsoda 1e-10/error")),
    F(R, "| solve_ivp LSODA, rtol 1e-10 | 2.8e-7 | 359 ms | 595 |", "359", J("lsoda 1e-10/wall_ms")),
    F(R, "| solve_ivp LSODA, rtol 1e-10 | 2.8e-7 | 359 ms | 595 |", "595", lambda d: ratio(d, "lsoda 1e-10")),
    F(R, "| solve_ivp BDF, rtol 1e-10 | 5.4e-7 | 1.74 s | 2886 |", "5.4e-7", J("bdf 1e-10/error")),
    F(R, "| solve_ivp BDF, rtol 1e-10 | 5.4e-7 | 1.74 s | 2886 |", "1.74", J("bdf 1e-10/wall_ms", 1e-3)),
    F(R, "| solve_ivp BDF, rtol 1e-10 | 5.4e-7 | 1.74 s | 2886 |", "2886", lambda d: ratio(d, "bdf 1e-10"), tol=5),
    F(R, "| solve_ivp Radau, rtol 1e-10 | 4.3e-9 | 5.9 s | 9834 |", "4.3e-9", J("radau 1e-10/error")),
    F(R, "| solve_ivp Radau, rtol 1e-10 | 4.3e-9 | 5.9 s | 9834 |", "5.9", J("radau 1e-10/wall_ms", 1e-3)),
    F(R, "| solve_ivp Radau, rtol 1e-10 | 4.3e-9 | 5.9 s | 9834 |", "9834", lambda d: ratio(d, "radau 1e-10"), tol=10),
    # step and call counts as "about": the stored run's, which another BLAS kernel moves
    F(R, _RK45, "1e-5", J("rk45 1e-06/error")),
    F(R, _RK45, "29.2", J("rk45 1e-06/wall_ms", 1e-3)),
    F(R, _RK45, "183,000", J("rk45 1e-06/steps"), tol=500),
    F(R, _RK45, "1.3", J("rk45 1e-06/rhs_calls", 1e-6)),
    F(R, _RK45, "48424", lambda d: ratio(d, "rk45 1e-06"), tol=50),
    F(R, _DOP, "1.8e-4", J("dop853 1e-06/error")),
    F(R, _DOP, "26.2", J("dop853 1e-06/wall_ms", 1e-3)),
    F(R, _DOP, "95,000", J("dop853 1e-06/steps"), tol=500),
    F(R, _DOP, "1.2", J("dop853 1e-06/rhs_calls", 1e-6)),
    F(R, _DOP, "43449", lambda d: ratio(d, "dop853 1e-06"), tol=50),
    F(R, "The exact method is 132 times faster than the fastest scipy route (odeint)", "132",
      lambda d: ratio(d, "odeint 1e-10")),
    F(R, "at an error estimate 5 times smaller", "5", lambda d: d["odeint 1e-10"]["error"] / d["exact -"]["error"]),
    # every scene: benchmarks/results/work_precision_<scene>.md
    F(R, "| sewing (10,001 over 1 s) | 6.5e-8 rad/s, 0.603 ms | odeint rtol 1e-10, 79 ms | 132 |", "6.5e-8",
      J("exact -/error")),
    F(R, "| sewing (10,001 over 1 s) | 6.5e-8 rad/s, 0.603 ms | odeint rtol 1e-10, 79 ms | 132 |", "0.603",
      J("exact -/wall_ms")),
    F(R, "| sewing (10,001 over 1 s) | 6.5e-8 rad/s, 0.603 ms | odeint rtol 1e-10, 79 ms | 132 |", "79",
      J("odeint 1e-10/wall_ms")),
    F(R, "| sewing (10,001 over 1 s) | 6.5e-8 rad/s, 0.603 ms | odeint rtol 1e-10, 79 ms | 132 |", "132",
      lambda d: ratio(d, "odeint 1e-10")),
    F(R, "RK45 needs about 183,000 steps, 1.3 million calls |", "183,000", J("rk45 1e-06/steps"), tol=500),
    F(R, "RK45 needs about 183,000 steps, 1.3 million calls |", "1.3", J("rk45 1e-06/rhs_calls", 1e-6)),
    F("results roller_table", "| roller table (7001 over 7 s, 1 switch) | 1.5e-8 rad/s, 71.4 ms |", "1.5e-8",
      J("exact -/error")),
    F("results roller_table", "| roller table (7001 over 7 s, 1 switch) | 1.5e-8 rad/s, 71.4 ms |", "71.4",
      J("exact -/wall_ms")),
    F("results roller_table", "| odeint rtol 1e-9, 2.080 s; Radau rtol 1e-8, 3.530 s | 29 |", "2.080",
      J("odeint 1e-09/wall_ms", 1e-3)),
    F("results roller_table", "| odeint rtol 1e-9, 2.080 s; Radau rtol 1e-8, 3.530 s | 29 |", "3.530",
      J("radau 1e-08/wall_ms", 1e-3)),
    F("results roller_table", "| odeint rtol 1e-9, 2.080 s; Radau rtol 1e-8, 3.530 s | 29 |", "29",
      lambda d: ratio(d, "odeint 1e-09")),
    F("results roller_table", "Radau and BDF at rtol 1e-10 run out of 2 million calls", "2",
      lambda d: (d["radau 1e-10"]["error"] is None and d["bdf 1e-10"]["error"] is None) * d["bdf 1e-10"]["rhs_calls"]
      * 1e-6),
    F("results roller_table", _STEPS, "53,000", J("exact -/steps"), tol=1000),
    F("results roller_table", _STEPS, "130", lambda d: 7.0 / d["exact -"]["steps"] * 1e6, tol=5),
    F("results roller_table", "two exact runs of 7 s, about 53,000 bottom steps of about 130 us", "53,000",
      J("exact -/steps"), tol=1000),
    F("results roller_table", "two exact runs of 7 s, about 53,000 bottom steps of about 130 us", "130",
      lambda d: 7.0 / d["exact -"]["steps"] * 1e6, tol=5),
    F("results linear_axis", "| linear axis (21,001 over 2.1 s) | 2.8e-13 m/s, 7.66 ms | LSODA rtol 1e-10, 514 ms | 67 |",
      "2.8e-13", J("exact -/error")),
    F("results linear_axis", "| linear axis (21,001 over 2.1 s) | 2.8e-13 m/s, 7.66 ms | LSODA rtol 1e-10, 514 ms | 67 |",
      "7.66", J("exact -/wall_ms")),
    F("results linear_axis", "| linear axis (21,001 over 2.1 s) | 2.8e-13 m/s, 7.66 ms | LSODA rtol 1e-10, 514 ms | 67 |",
      "514", J("lsoda 1e-10/wall_ms")),
    F("results linear_axis", "| linear axis (21,001 over 2.1 s) | 2.8e-13 m/s, 7.66 ms | LSODA rtol 1e-10, 514 ms | 67 |",
      "67", lambda d: ratio(d, "lsoda 1e-10")),
    F("results linear_axis", "RK45 and DOP853 (run at rtol 1e-3 and 1e-6 only) reach 6.5e-5 and 8.4e-6", "6.5e-5",
      J("rk45 1e-06/error")),
    F("results linear_axis", "RK45 and DOP853 (run at rtol 1e-3 and 1e-6 only) reach 6.5e-5 and 8.4e-6", "8.4e-6",
      J("dop853 1e-06/error")),
    F("results linear_axis", "one solve 8 ms in `benchmarks/results/work_precision_linear_axis.md`", "8",
      J("exact -/wall_ms"), page="docs/scenes.md"),
    # the sewing error estimate's parts, from the library
    # the partitions' difference is rounding alone on this one-piece run: 4.5e-10 to 3.6e-9
    # over four OpenBLAS kernel families, so a bound (the floor is eps ||F~|| t_end times the
    # scale: the same to 12 digits on every kernel)
    F("sewing estimate", "(rounding alone here, below 1e-8 rad/s; its digits change with the BLAS kernel)", "1e-8",
      J("partition"), bound=True),
    F("sewing estimate", "balanced matrix (6.2e-8 rad/s on a scale of 433 rad/s; between 6e-8 and 7e-8 rad/s in all)",
      "6.2e-8", J("floor")),
    F("sewing estimate", "balanced matrix (6.2e-8 rad/s on a scale of 433 rad/s; between 6e-8 and 7e-8 rad/s in all)",
      "433", J("scale")),
    F("sewing estimate", "balanced matrix (6.2e-8 rad/s on a scale of 433 rad/s; between 6e-8 and 7e-8 rad/s in all)",
      "7e-8", J("error"), bound=True, low=6e-8),
])


def sewing_estimate() -> dict:
    """The exact method's error estimate of omega_3 on the sewing scene, in its two parts."""
    from beltcalc.sim.core import SolverConfig, conditioning, simulate
    from beltcalc.sim.scenes import SCENES

    scene = SCENES["sewing"]
    values = scene.values()
    net = scene.build(dict(values))
    t_end, samples = scene.timing(dict(values))
    r = simulate(net, t_end, samples, SolverConfig("exact", accept_error=True))
    floor = conditioning(net, t_end) * r.error_scale
    return {"error": r.errors["omega_3"], "floor": floor, "partition": r.errors["omega_3"] - floor,
            "scale": r.error_scale}


PYTHON["sewing estimate"] = sewing_estimate


def roller_scaling() -> dict:
    """benchmarks/results/roller_scaling.md by roller count: its cells as text."""
    header = ["rollers", "states", "switches", "exact", "estimated", "estimate", "radau", "ratio", "difference"]
    rows = markdown_rows((RESULTS / "roller_scaling.md").read_text(encoding="utf-8"), "| rollers |")
    return {r.strip("|").split("|")[0].strip(): dict(zip(header, (c.strip() for c in r.strip("|").split("|"))))
            for r in rows}


def cell(rollers: str, column: str, scale: float = 1.0) -> Callable[[dict], float]:
    return lambda d: float(d[rollers][column].split()[0]) * scale


def relative(rollers: str) -> Callable[[dict], float]:
    return lambda d: float(re.search(r"\(([^)]+)\)", d[rollers]["estimate"])[1])


PYTHON["results roller_scaling"] = roller_scaling
S = "results roller_scaling"
BENCHMARK_FIGURES += on("docs/performance.md", [
    F(S, "At 1 and 3 rollers exact beats Radau by 128x and 206x", "128", cell("1", "ratio")),
    F(S, "At 1 and 3 rollers exact beats Radau by 128x and 206x", "206", cell("3", "ratio")),
    F(S, "7,833 switches at 100 rollers take 73.7 s", "7,833", cell("100", "switches")),
    F(S, "7,833 switches at 100 rollers take 73.7 s", "73.7", cell("100", "exact")),
    F(S, "(84.9 s with the estimate), 9,538 at 200 rollers", "84.9", cell("100", "estimated")),
    F(S, "9,538 at 200 rollers 139 s (169 s with the estimate", "9,538", cell("200", "switches")),
    F(S, "9,538 at 200 rollers 139 s (169 s with the estimate", "139", cell("200", "exact")),
    F(S, "9,538 at 200 rollers 139 s (169 s with the estimate", "169", cell("200", "estimated")),
    F(S, "The 200-roller row's estimate is 9.7e-4 N m, 2e-5 of the scale", "9.7e-4", cell("200", "estimate")),
    F(S, "The 200-roller row's estimate is 9.7e-4 N m, 2e-5 of the scale", "2e-5", relative("200")),
    F(S, "at 100 rollers it is 4.5e-5 N m, 3e-7 of the scale", "4.5e-5", cell("100", "estimate")),
    F(S, "at 100 rollers it is 4.5e-5 N m, 3e-7 of the scale", "3e-7", relative("100")),
    F(S, "solves a second time: 0.314 s and 0.488 s end to end at 7001 samples", "0.314", cell("3", "exact"),
      page="docs/scenes.md"),
    F(S, "solves a second time: 0.314 s and 0.488 s end to end at 7001 samples", "0.488", cell("3", "estimated"),
      page="docs/scenes.md"),
])


# -- benchmarks/results/studies.md (issue 17, item 7): the README's studies table ---------------------

def studies_results() -> dict:
    """benchmarks/results/studies.md as numbers: the solver-only time (wall, CPU), per path the
    per-run wall and CPU and their ratios, the memory growth per (study, runs), per execution
    the per-run time once running, the 2-over-1 speed-up and the 10^6 extrapolations [min]."""
    text = (RESULTS / "studies.md").read_text(encoding="utf-8")
    num = r"([0-9][0-9,]*\.?[0-9]*)"
    out = {"solver_wall": float(re.search(r"median " + num + r" ms; its CPU", text)[1]),
           "solver_cpu": float(re.search(r"`core._exact`\) " + num + r" ms", text)[1])}
    study = None
    for line in text.splitlines():
        if line.startswith("### sewing") or line.startswith("### conveyor"):
            study = line.split()[1].rstrip(",")
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0].startswith("batched exact propagation") or cells[0].startswith("one by one (the scene"):
            key = "batched" if cells[0].startswith("batched") else "single"
            out[key] = [float(c.rstrip("x")) for c in cells[1:5]]
        elif cells[0] in ("time run", "steady state") and len(cells) == 5:
            out[f"{cells[0]} {cells[1]}"] = float(cells[3])
        elif study and len(cells) == 13 and cells[0][:1].isdigit():
            w = cells[0].split()[0]
            out[f"{study} {w}"] = {"included": float(cells[4].rstrip("x")), "excluded": float(cells[5].rstrip("x")),
                                   "share": None if cells[8] == "-" else float(cells[8].rstrip("%")),
                                   "busy": float(cells[9].rstrip("%")), "same": cells[10]}
            if cells[11] != "-":          # every repeat against its in-process run: the range
                each = [float(x) for x in re.findall(r"([0-9.]+)x \(", cells[11])]
                cpu = [float(x) for x in cells[12].split(",")]
                out[f"{study} {w}"].update({"paired_min": min(each), "paired_max": max(each),
                                            "cpu_min": min(cpu), "cpu_max": max(cpu)})
        elif cells[0].startswith("batched, ") and cells[-1].endswith(" min"):
            out[cells[0]] = float(cells[-1].split()[0])
    return out


PYTHON["results studies"] = studies_results
ST = "results studies"
_COST = ("| per-run cost / solver-only time of one exact run (0.260 ms wall, 0.251 ms CPU) | batched 3.02x wall, 3.12x "
         "CPU (0.78 ms, 0.78 ms a run); one by one 10.3x, 10.8x | <= 3x: not met in this run (2.89x-3.62x CPU over its "
         "five rounds) |")
_RSS = "| peak RSS growth from 10^3 runs | time run +4.3 MiB at 10^4; steady state +0.0 MiB at 10^5 | flat |"
_SEW = ("| sewing, 50,000 runs (batched): 2 local Dask workers against this process | 1.80x end to end, 1.89x "
        "without the cluster's start (each repeat, paired: 1.87x-1.89x); workers busy 99 %; client CPU 1.40 % of the "
        "workers'; statistics bit for bit | >= 1.9x: not met (1.87x-1.89x; the machine's ceiling is about 1.9x, "
        "below), nor end to end; <= 2 %: met |")
_CONV = ("| conveyor drive file, 400 runs (one by one): 2 workers against this process | 1.84x end to end, 1.90x "
         "without the start (each repeat, paired: 1.90x-1.95x); client CPU 0.55 % of the workers'; statistics bit for "
         "bit | >= 1.9x without the start: met in each repeat; not end to end |")
_MILLION = "| 10^6 runs of this study, extrapolated | 12.0 min in one process, 6.4 min on 2 workers | |"
_CEILING = "workers spend 3.5-4.6 % more CPU per run than this process, the conveyor's single runs 1.5-3.8 %"

BENCHMARK_FIGURES += on("docs/performance.md", [
    F(ST, _COST, "0.260", J("solver_wall")),
    F(ST, _COST, "0.251", J("solver_cpu")),
    F(ST, _COST, "3.02", J("batched/2")),
    F(ST, _COST, "3.12", J("batched/3")),
    F(ST, _COST, "0.78", J("batched/0")),
    F(ST, _COST, "0.78", J("batched/1")),
    F(ST, _COST, "10.3", J("single/2")),
    F(ST, _COST, "10.8", J("single/3")),
    F(ST, _RSS, "4.3", J("time run 10,000")),
    F(ST, _RSS, "0.0", J("steady state 100,000")),
    F(ST, _SEW, "1.80", J("sewing 2/included")),
    F(ST, _SEW, "1.89", J("sewing 2/excluded")),
    F(ST, _SEW, "1.87", J("sewing 2/paired_min")),
    F(ST, _SEW, "99", J("sewing 2/busy")),
    F(ST, _SEW, "1.40", J("sewing 2/share")),
    F(ST, _CONV, "1.84", J("conveyor 2/included")),
    F(ST, _CONV, "1.90", J("conveyor 2/excluded")),
    F(ST, _CONV, "1.95", J("conveyor 2/paired_max")),
    F(ST, _CONV, "0.55", J("conveyor 2/share")),
    F(ST, _CEILING, "3.5", lambda r: round((r["sewing 2"]["cpu_min"] - 1) * 100, 1)),
    F(ST, _CEILING, "4.6", lambda r: round((r["sewing 2"]["cpu_max"] - 1) * 100, 1)),
    F(ST, _CEILING, "1.5", lambda r: round((r["conveyor 2"]["cpu_min"] - 1) * 100, 1)),
    F(ST, _CEILING, "3.8", lambda r: round((r["conveyor 2"]["cpu_max"] - 1) * 100, 1)),
    F(ST, _MILLION, "12.0", J("batched, in this process")),
    F(ST, _MILLION, "6.4", J("batched, 2 local workers")),
])


# -- benchmarks/results/startup.md and the end-to-end table (issue 17, items 1, 5, 6) -------------

def startup_results() -> dict:
    """benchmarks/results/startup.md as numbers: the cold/warm rows by their first words
    ("exact", "one", "whole"; "of which" as "solve", "a new array" as "touch": cold, warm), each command's CPU, floor and ratio, the floors'
    range, the ratio range of the commands without a simulation and of the help pages, and
    the simulate() time and scipy import of the breakdown."""
    out: dict = {"commands": {}}
    for line in (RESULTS / "startup.md").read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        first = {"of": "solve", "a": "touch"}.get(cells[0].split()[0], cells[0].split()[0]) if cells[0] else ""
        if len(cells) == 4 and first in ("exact", "one", "whole", "solve", "touch") and cells[1][0].isdigit():
            out[first] = {"cold": float(cells[1]), "warm": float(cells[2])}
        elif len(cells) == 6 and cells[0].startswith("`beltcalc") and ".." in cells[4]:     # the start-up table
            out["commands"][cells[0].strip("`")] = {"cpu": float(cells[1]), "floor": float(cells[2]),
                                                    "ratio": float(cells[3])}
        elif len(cells) == 6 and cells[0] == "`beltcalc simulate sewing`":                 # where it goes
            out["sewing simulate_ms"] = float(cells[3])
        elif len(cells) == 6 and cells[0] == "`beltcalc simulate drive conveyor`" and ".." not in cells[4]:
            out["conveyor simulate_ms"] = float(cells[3])
        elif len(cells) == 6 and cells[0] == "`beltcalc simulate roller-table`" and ".." not in cells[4]:
            out["roller-table simulate_ms"] = float(cells[3])
    cmds = out["commands"]
    plain = ["tension", "motor-size", "belt-drive", "chain", "catalog list", "modes", "response", "campbell"]
    helps = [c for c in cmds if c.endswith("--help")]
    out["plain min"] = min(cmds[f"beltcalc {c}"]["ratio"] for c in plain)
    out["plain max"] = max(cmds[f"beltcalc {c}"]["ratio"] for c in plain)
    out["help min"] = min(cmds[c]["ratio"] for c in helps)
    out["help max"] = max(cmds[c]["ratio"] for c in helps)
    out["floor"] = statistics.median(v["floor"] for v in cmds.values()) / 1e3
    out["sewing"] = cmds["beltcalc simulate sewing"]["ratio"]
    out["conveyor"] = cmds["beltcalc simulate drive conveyor"]["ratio"]
    out["roller-table"] = cmds["beltcalc simulate roller-table"]["ratio"]
    out["roller_table drive"] = cmds["beltcalc simulate drive roller_table"]["ratio"]
    out["linear-axis"] = cmds["beltcalc simulate linear-axis"]["ratio"]
    drives = [cmds[f"beltcalc simulate drive {d}"]["ratio"]
              for d in ("sewing", "linear_axis", "friswell_5_disks", "friswell_geared")]
    out["drives min"], out["drives max"] = min(drives), max(drives)
    return out


def end_to_end(name: str) -> dict:
    """The last table of work_precision_<name>.md: solver-only and end-to-end ms per row."""
    rows = {}
    text = (RESULTS / f"work_precision_{name}.md").read_text(encoding="utf-8")
    for line in text.split("Solver only and end to end", 1)[1].splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[0] not in ("method", "---"):
            rows[f"{cells[0]} {cells[1]}"] = {"solver": float(cells[2]), "whole": float(cells[3])}
    return rows


PYTHON["results startup"] = startup_results
PYTHON["results e2e sewing"] = lambda: end_to_end("sewing")
SU, E2E = "results startup", "results e2e sewing"
_EX, _BUILD, _ODE = "exact, with its error estimate -", "exact, with its estimate and the network's build -", "odeint 1e-10"
BENCHMARK_FIGURES += on("docs/performance.md", [
    F(SU, "cached unit registry (about 0.28 s here)", "0.28", J("floor")),
    F(SU, "`catalog list`, `modes`, `response`, `campbell`): 0.93x to 1.08x the floor", "0.93", J("plain min")),
    F(SU, "`catalog list`, `modes`, `response`, `campbell`): 0.93x to 1.08x the floor", "1.08", J("plain max")),
    F(SU, "help pages 0.13x to 0.82x", "0.13", J("help min")),
    F(SU, "help pages 0.13x to 0.82x", "0.82", J("help max")),
    F(SU, "`simulate sewing`: 1.02x.", "1.02", J("sewing")),
    F(SU, "the simulation is 2 ms of it", "2", J("sewing simulate_ms")),
    F(SU, "`simulate linear-axis` 1.20x; the drive files", "1.20", J("linear-axis")),
    F(SU, "and `friswell_geared` 1.01x to 1.21x", "1.01", J("drives min")),
    F(SU, "and `friswell_geared` 1.01x to 1.21x", "1.21", J("drives max")),
    F(SU, "at the target (1.3x): `simulate drive conveyor` 1.28x", "1.28", J("conveyor")),
    F(SU, "`simulate roller-table` 1.30x (1.27x to 1.34x; it was 1.56x)", "1.30", J("roller-table")),
    F(SU, "its drive file `roller_table` 1.32x", "1.32", J("roller_table drive")),
    F(SU, "The roller table's calculation is about 65 ms of CPU cold", "65", J("roller-table simulate_ms"), tol=5),
    F(SU, "a fresh process costs 1.512 ms of CPU, against 0.270 ms warm", "1.512", J("exact/cold")),
    F(SU, "a fresh process costs 1.512 ms of CPU, against 0.270 ms warm", "0.270", J("exact/warm")),
    F(SU, "the first `expm` (0.361 ms against 0.067 ms", "0.361", J("one/cold")),
    F(SU, "the first `expm` (0.361 ms against 0.067 ms", "0.067", J("one/warm")),
    F(SU, "numpy's first LAPACK call (0.107 ms against 0.013 ms)", "0.107", J("solve/cold")),
    F(SU, "numpy's first LAPACK call (0.107 ms against 0.013 ms)", "0.013", J("solve/warm")),
    F(SU, "(0.486 ms for a new array of its size against 0.029 ms", "0.486", J("touch/cold")),
    F(SU, "(0.486 ms for a new array of its size against 0.029 ms", "0.029", J("touch/warm")),
    F(SU, "error estimate) costs 2.803 ms cold and 1.513 ms warm", "2.803", J("whole/cold")),
    F(SU, "error estimate) costs 2.803 ms cold and 1.513 ms warm", "1.513", J("whole/warm")),
    F(E2E, "propagation 0.707 ms, the whole `simulate()` call 1.900 ms", "0.707", J(f"{_EX}/solver")),
    F(E2E, "propagation 0.707 ms, the whole `simulate()` call 1.900 ms", "1.900", J(f"{_EX}/whole")),
    F(E2E, "(3.19 ms with the network's build from the scene's values)", "3.19", J(f"{_BUILD}/whole")),
    F(E2E, "79.3 ms for its solve and 80.9 ms for the whole call", "79.3", J(f"{_ODE}/solver")),
    F(E2E, "79.3 ms for its solve and 80.9 ms for the whole call", "80.9", J(f"{_ODE}/whole")),
    F(E2E, "43 times faster end to end, 25 times", "43", lambda d: d[_ODE]["whole"] / d[_EX]["whole"]),
    F(E2E, "43 times faster end to end, 25 times", "25", lambda d: d[_ODE]["whole"] / d[_BUILD]["whole"]),
])


@pytest.mark.parametrize("figure", [pytest.param(f, id=f.id) for f in BENCHMARK_FIGURES])
def test_readme_quotes_the_stored_benchmarks(figure):
    check(figure)


def test_without_a_gearbox_no_motor_fits():
    """docs/motor_sizing.md: `beltcalc motor-size --gear-ratio 1` ... no motor passes, and the
    command says so and exits 1."""
    assert "no motor passes, and the command says so and exits 1" in page_text("docs/motor_sizing.md")
    result = CliRunner().invoke(cli, ["motor-size", "--gear-ratio", "1"])
    assert result.exit_code == 1 and "no motor fits" in result.output


def assert_within_factor(got: float, stored: float, factor: float) -> None:
    """``got`` within ``factor`` of ``stored`` either way (both > 0): an error or an error
    estimate, whose digits below its order of magnitude are rounding."""
    assert got > 0 and stored > 0, (got, stored)
    assert math.log(got / stored) == pytest.approx(0.0, abs=math.log(factor)), (
        f"{got:.3g} is not within a factor of {factor:g} of the stored {stored:.3g}")


def markdown_rows(text: str, header: str) -> list[str]:
    """The body rows of the Markdown table whose header line starts with ``header``."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(header))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append(line.strip())
    return rows


def test_readme_roller_scaling_table_is_the_stored_one():
    header = "| rollers | states | switches |"
    readme_rows = markdown_rows((ROOT / "docs" / "performance.md").read_text(encoding="utf-8"), header)
    stored = markdown_rows((RESULTS / "roller_scaling.md").read_text(encoding="utf-8"), header)
    assert readme_rows and readme_rows == stored


def test_readme_steady_sweep_figures_are_the_stored_ones():
    stored = squeeze((RESULTS / "steady_sweep.md").read_text(encoding="utf-8"))
    text = page_text("docs/performance.md")
    for quote, stored_text in [("costs 0.75 ms a point", "| 0.754 |"), ("with its error estimate) 8.14 ms", "| 8.14 |"),
                               ("8.14 ms: 11 times faster", "Speed-up: 11x"),
                               ("up to 5.4e-4 on the bottom shaft's speed amplitude", "speed amplitude 0.00054"),
                               ("1.8e-5 on its acceleration", "accel amplitude 1.8e-05"),
                               ("4.3e-5 on its torque", "torque amplitude 4.3e-05")]:
        assert quote in text
        assert stored_text in stored


@pytest.mark.parametrize("rollers", [1, 3, 10])
def test_roller_scaling_rows_come_out_of_the_code(rollers):
    """The stored table's states, switches and error estimate (its benchmark's run: the scene's
    run as the command makes it, exact, the window watched)."""
    from beltcalc.sim.core import SolverConfig
    from beltcalc.sim.scenes import SCENES, roller_table

    rows = {int(r.strip("|").split("|")[0]): [c.strip() for c in r.strip("|").split("|")]
            for r in markdown_rows((RESULTS / "roller_scaling.md").read_text(encoding="utf-8"), "| rollers |")}
    row = rows[rollers]
    # the benchmark's run: the scene's default 7 s at 7001 samples, as its title says
    assert (RESULTS / "roller_scaling.md").read_text(encoding="utf-8").startswith(
        "# Roller-table scaling (7001 samples over 7 s")
    values = SCENES["roller-table"].values(rollers=float(rollers), roller_load=120.0 / rollers, t_end=7.0,
                                           samples=7001.0)
    out = roller_table.run(values, SolverConfig("exact", max_events=1_000_000, accept_error=True))
    # states and strand switches are counts of the model and of its physics (a strand going
    # slack), the same on every kernel
    assert (out.net.size, out.result.extra.get("events")) == (int(row[1]), int(row[2]))
    # the estimate's digits are rounding (two partitions' difference): 4.3e-8 to 5.6e-8 at 10
    # rollers over four OpenBLAS kernel families on the code of an older table (0778056), up to
    # 1.4x apart: held within a factor of 2 of the stored figure, in the stored unit
    stored, unit = row[5].split(" (")[0].split(" ", 1)
    assert out.result.error_unit.replace("*", " ") == unit
    assert_within_factor(out.result.error_estimate, float(stored), 2.0)


WORK_PRECISION_ROWS = [("sewing", "sewing", "exact", None), ("sewing", "sewing", "odeint", 1e-10),
                       ("sewing", "sewing", "lsoda", 1e-10), ("linear-axis", "linear_axis", "exact", None),
                       ("linear-axis", "linear_axis", "lsoda", 1e-10), ("linear-axis", "linear_axis", "rk45", 1e-6),
                       ("roller-table", "roller_table", "exact", None),
                       ("roller-table", "roller_table", "odeint", 1e-9)]


@pytest.mark.parametrize("scene_name, file, method, rtol", WORK_PRECISION_ROWS)
def test_stored_work_precision_rows_come_out_of_the_code(scene_name, file, method, rtol):
    """Steps, right-hand-side calls and error of cheap rows of the stored tables, re-run as
    :func:`beltcalc.sim.study.workprecision.work_precision` runs them."""
    from beltcalc.sim.core import SolverConfig, simulate
    from beltcalc.sim.scenes import SCENES

    scene = SCENES[scene_name]
    values = scene.values()
    net = scene.build(dict(values))
    t_end, samples = scene.timing(dict(values))
    checked = simulate(net, t_end, samples, SolverConfig("exact", accept_error=True))
    stored = results_table(file)[f"{method} {'-' if rtol is None else f'{rtol:.0e}'}"]
    if method == "exact":
        r = simulate(net, t_end, samples, SolverConfig("exact", estimate_error=False))
        error = checked.errors[scene.signal]
    else:
        r = simulate(net, t_end, samples, SolverConfig(method, rtol=rtol, atol=rtol / 100, max_rhs_calls=2_000_000,
                                                       estimate_error=False))
        error = float(abs(r[scene.signal] - checked[scene.signal]).max())
    # An adaptive method's steps follow its error norms, which another BLAS kernel rounds
    # otherwise: odeint on the roller table took 16,641 to 16,868 steps over four OpenBLAS
    # kernel families here, 18,100 where the table was made (8 % apart), LSODA on the linear
    # axis 5,231 to 5,614 against 5,664, its calls up to 11 % apart: to 20 %. The exact
    # method's steps follow from ||F~|| and the strands' switches, held the same way.
    assert r.steps == pytest.approx(stored["steps"], rel=0.2)
    assert r.rhs_calls == pytest.approx(stored["rhs_calls"], rel=0.2)
    # The error: a scipy method's against the exact run, moved by its steps (sewing's LSODA
    # 1.9e-7 to 3.3e-7 over the kernels); the exact method's is its estimate, rounding in its
    # last digits: within a factor of 2 of the stored figure either way
    assert_within_factor(error, stored["error"], 2.0)


# sections whose tables hold no result of a command (or belong to another test)
NOT_FIGURES = ("Exit codes", "Output contract", "Checks and warnings", "Catalogs", "Units")
# the pages whose tables hold results of commands, each whole (None) or only the section (a
# "## " heading) that holds them; the other pages' tables are formulas, keys and sources
RESULT_TABLES = {"README.md": None, "docs/tension.md": None, "docs/scenes.md": None, "docs/performance.md": None,
                 "docs/frequency_domain.md": None, "docs/studies.md": None, "docs/output.md": None,
                 "docs/catalogs.md": None, "docs/python.md": None,
                 "docs/motor_sizing.md": "## Using the command", "docs/design_checks.md": "## Using the commands",
                 "docs/drive_files.md": "## Running a drive file", "docs/belt_axis.md": "## The WDU axis"}


def result_lines(page: str) -> list[str]:
    """The lines of ``page`` that RESULT_TABLES holds to the figure check."""
    lines = (ROOT / page).read_text(encoding="utf-8").splitlines()
    section = RESULT_TABLES[page]
    if section is None:
        return lines
    start = lines.index(section)
    end = next((k for k in range(start + 1, len(lines)) if lines[k].startswith("## ")), len(lines))
    return lines[start:end]


def test_every_table_row_with_a_number_is_checked():
    """A new figure in a table of a command's results needs its entry here: every table row
    that holds a digit carries a quote of FIGURES or BENCHMARK_FIGURES (the roller-scaling table
    is compared with its stored file whole; headers and sections in NOT_FIGURES aside), on the
    pages of RESULT_TABLES."""
    quotes = [squeeze(f.quote) for f in FIGURES + BENCHMARK_FIGURES]
    scaling = markdown_rows((RESULTS / "roller_scaling.md").read_text(encoding="utf-8"), "| rollers |")
    missing = []
    for page in RESULT_TABLES:
        section, previous = "", ""
        for line in result_lines(page):
            if line.startswith("#"):
                section = line
            header = line.startswith("|") and not previous.startswith("|")
            previous = line
            if (not line.startswith("|") or line.startswith("|---") or header or not re.search(r"[0-9]", line)
                    or any(name in section for name in NOT_FIGURES) or line.strip() in scaling):
                continue
            row = squeeze(line)
            if not any(q in row or row in q for q in quotes):
                missing.append(f"{page}: {line}")
    assert not missing, "table rows with figures no test checks:\n" + "\n".join(missing)


def test_every_page_with_results_is_held_to_the_check():
    """A docs page is either in RESULT_TABLES or holds no table row with a figure that a
    command gives (a page of formulas, keys and sources: listed here)."""
    formulas = {"docs/architecture.md", "docs/switching.md", "docs/eccentric_roller.md", "docs/output-files.md",
                "docs/equations.md", "docs/friction_and_limits.md",
                "docs/positioning.md",
                "docs/input_shaping.md",     # its table: tests/test_shapers.py checks it against the code
                "docs/chain_dynamics.md"}    # its roller table: the stored benchmark, tests/test_polygon.py checks it
    # the docs site's home and its API pages (a ``::: module`` line each: the docstrings)
    formulas |= {"docs/index.md"} | {p for p in pages() if p.startswith("docs/api/")}
    assert set(pages()) == set(RESULT_TABLES) | formulas
