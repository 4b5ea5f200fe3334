"""The peak motor torque a belt drive is checked against, from a ``motor-size`` run: a
sizing in this process, its ``--json`` output, or a scene or cycle file sized here, referred
to the driving pulley.

References:

[C04] R. Crowder, Electric Drives and Electromechanical Systems, Newnes (2006): through a
    gearbox of ratio i the pulley shaft gets i T_M [C04 eq. 3.9-3.10] (lossless).
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the peak motor torque of a duty cycle [W21 eq. 26-28] as
    ``beltcalc motor-size`` computes it (:mod:`beltcalc.design.sizing`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import InputError


@dataclass(frozen=True)
class MotorPeak:
    """The peak torque of a ``motor-size`` run and what refers it to its driving pulley (SI).

    ``torque`` T_M [N m] at the motor shaft (the reported motor's), ``gear_ratio`` i (motor
    speed / pulley speed), ``pulley_diameter`` [m] of that run's driving pulley, ``source``
    what was run (the scene or file, the motor)."""

    torque: float
    gear_ratio: float
    pulley_diameter: float
    source: str

    @property
    def pulley_torque(self) -> float:
        """Torque on the driving pulley [N m]: :math:`T_P = i T_M` [C04 eq. 3.9-3.10], lossless."""
        return self.gear_ratio * self.torque


def motor_peak_from_sizing(sizing, source: str) -> MotorPeak:
    """The :class:`MotorPeak` of a :class:`beltcalc.design.sizing.CycleSizing`: the reported
    motor's peak torque, the gearbox ratio and the pulley diameter it was sized with."""
    if sizing.shown is None:
        raise InputError(f"{source}: no motor fits ({sizing.choice.reason}), so there is no peak torque; "
                         "give the torque (`torque`) instead", param="motor_size")
    return MotorPeak(sizing.shown.duty.peak_torque, sizing.drive.gearbox.ratio, sizing.axis.pulley_diameter,
                     f"{source}, motor {sizing.shown.motor.name}")


def motor_peak_from_json(obj, source: str) -> MotorPeak:
    """The :class:`MotorPeak` of what ``beltcalc motor-size --json`` printed (``obj``, the
    parsed JSON): its ``peak_torque``, ``gear_ratio`` and ``pulley_diameter`` as
    ``{"value", "unit"}`` in N*m, 1 and m.

    >>> q = lambda v, u: {"value": v, "unit": u}
    >>> p = motor_peak_from_json({"peak_torque": q(2.0, "N*m"), "gear_ratio": q(20.0, "1"),
    ...                           "pulley_diameter": q(0.125, "m"), "reported_motor": "M1"}, "run.json")
    >>> p.pulley_torque, p.source
    (40.0, 'run.json, motor M1')
    """
    values = []
    for key, unit in (("peak_torque", "N*m"), ("gear_ratio", "1"), ("pulley_diameter", "m")):
        q = obj.get(key) if isinstance(obj, dict) else None
        v = q.get("value") if isinstance(q, dict) and q.get("unit") == unit else None
        if isinstance(v, int) and not isinstance(v, bool):
            v = float(v) if abs(v) < 2 ** 1023 else math.inf          # a JSON integer beyond a float
        if not isinstance(v, float) or not math.isfinite(v) or v <= 0:
            raise InputError(f"{source}: no finite {key} > 0 in {unit}; give the JSON output of a motor-size run in which "
                             "a motor fits", param="motor_size")
        values.append(float(v))
    motor = obj.get("reported_motor") or obj.get("selected_motor")
    return MotorPeak(*values, f"{source}, motor {motor}" if isinstance(motor, str) else source)


def motor_size_peak(ref: str, catalog) -> MotorPeak:
    """The peak torque of a ``motor-size`` run, from ``ref``: a ``.json`` file that
    ``beltcalc motor-size ... --json`` wrote (any of its options, duty-cycle files and
    gearboxes), or a motor-size scene (built-in name such as ``wdu``, or a scene ``.toml``)
    sized here as ``beltcalc motor-size --scene REF`` sizes it with no other option, over
    ``catalog``'s belts and motors.

    >>> from beltcalc.data.catalogs import load_catalog
    >>> p = motor_size_peak("wdu", load_catalog())
    >>> round(p.torque, 4), p.gear_ratio, round(p.pulley_diameter, 6), p.source
    (2.1014, 20.0, 0.127324, 'motor-size scene wdu, motor SGM7J-06A')
    """
    if str(ref).lower().endswith(".json"):
        import json
        from pathlib import Path

        from beltcalc.units import quote

        try:
            text = Path(ref).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError, ValueError) as exc:     # ValueError: a NUL in the name
            raise InputError(f"cannot read {quote(ref)} ({type(exc).__name__})", param="motor_size") from None
        try:
            obj = json.loads(text)
        except (ValueError, RecursionError):
            raise InputError(f"{quote(ref)} is not JSON", param="motor_size") from None
        return motor_peak_from_json(obj, quote(ref))
    from beltcalc.data.scenefile import load_scene
    from beltcalc.errors import BeltcalcError
    from beltcalc.params import resolve
    from beltcalc.design.sizing import size_cycle
    from beltcalc.design.axis_inputs import PARAMS, SizingInputs

    try:
        scene = load_scene(ref, command="motor-size")
        values = resolve(scene, PARAMS)
        inp = SizingInputs.from_values({k: v.value for k, v in values.items()})
        sizing = size_cycle(inp, catalog.belt(values["belt"].value), list(catalog.motors.values()))
    except BeltcalcError as exc:       # about the scene's run, not this drive's parameters
        why = exc.message if exc.param == "scene" else str(exc)
        raise type(exc)(f"motor-size scene {ref}: {why}", param="motor_size") from None
    return motor_peak_from_sizing(sizing, f"motor-size scene {ref}")
