"""The inputs of a belt axis's motor sizing: the parameters a scene file (``wdu.toml``) gives
(:data:`PARAMS`, shared with the linear-axis scene), where each comes from in the paper
(:func:`where`), and :class:`SizingInputs`, which :mod:`beltcalc.design.sizing` sizes.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from beltcalc.params import Param
from beltcalc.si import convert_fields


# The parameters of a belt axis and its move, as a scene file (wdu.toml) gives them.
PARAMS = [
    Param("belt", None, "Belt profile (gives the substitute belt mass m_TB)."),
    Param("width", "m", "Belt width (a catalog width)."),
    Param("center_distance", "m", "Pulley center distance."),
    Param("mass", "kg", "Moving mass (carriage)."),
    Param("pulley_teeth", "int", "Teeth of the drive and idler pulleys (d0 = z P / pi)."),
    Param("pulley_diameter", "m", "Pulley pitch diameter D, instead of the teeth.", required=False),
    Param("pulley_width", "m", "Pulley body width (for its inertia)."),
    Param("pulley_bore", "m", "Pulley bore (for its inertia)."),
    Param("pulley_density", "kg/m^3", "Pulley material density (for its inertia)."),
    Param("pulley_inertia", "kg*m^2", "Drive pulley inertia J_P1, instead of the computed one.", required=False),
    Param("idler_inertia", "kg*m^2", "Idler pulley inertia J_P2, instead of the computed one.", required=False),
    Param("coupling_inertia", "kg*m^2", "Coupling inertia J_C (drive-pulley shaft)."),
    Param("gearbox_inertia", "kg*m^2", "Gearbox inertia at the motor shaft J_G."),
    Param("load_inertia", "kg*m^2", "Rotating load on the idler shaft J_RL.", required=False),
    Param("gear_ratio", "", "Gearbox ratio i = motor speed / pulley speed (1: direct drive)."),
    Param("belt_ratio", "", "Belt transmission ratio n = D2 / D1."),
    Param("resistance", "N", "External resistance force F_R against the motion."),
    Param("guide_friction", "", "Guide friction coefficient (ball 0.002-0.003, roller 0.001-0.002)."),
    Param("guide_damping", "N*s/m", "Guide viscous damping b_LG."),
    Param("bearing_damping", "N*m*s/rad", "Viscous damping b_B of each pulley shaft."),
    Param("motor_efficiency", "", "Motor efficiency (gives b_M = (1 - eta) T_n / omega_n)."),
    Param("speed", "rad/s|m/s", "Maximum speed: at the motor (3000rpm) or the carriage (2m/s)."),
    Param("accel", "rad/s^2|m/s^2", "Acceleration: at the motor (500rad/s^2) or the carriage (10m/s^2)."),
    Param("stroke", "m", "Carriage travel of one move."),
    Param("dwell", "s", "Standstill after each move."),
    Param("inertia_ratio_limit", "", "Largest load/motor inertia ratio allowed."),
    Param("peak_margin", "", "Margin on the peak torque: peak * (1 + margin) <= T_max."),
]


# Where each value of PARAMS is measured: the motor's side of the gearbox or the carriage's
# (the belt, pulleys and guides turn or move with the carriage, after the gearbox).
WHERE = {
    "belt": "carriage side: the belt between the pulleys",
    "width": "carriage side: belt width",
    "center_distance": "carriage side: drive to idler pulley",
    "mass": "carriage side: the carriage",
    "pulley_teeth": "carriage side: drive and idler pulleys, after the gearbox",
    "pulley_diameter": "carriage side: drive pulley, after the gearbox",
    "pulley_width": "carriage side: pulley bodies",
    "pulley_bore": "carriage side: pulley bodies",
    "pulley_density": "carriage side: pulley bodies",
    "pulley_inertia": "carriage side: drive-pulley shaft (gearbox output)",
    "idler_inertia": "carriage side: idler shaft",
    "coupling_inertia": "carriage side: drive-pulley shaft (gearbox output)",
    "gearbox_inertia": "motor side: at the gearbox input",
    "load_inertia": "carriage side: idler shaft",
    "gear_ratio": "motor speed / drive-pulley speed",
    "belt_ratio": "carriage side: idler / drive pulley diameter",
    "resistance": "carriage side: force on the carriage",
    "guide_friction": "carriage side: carriage guide",
    "guide_damping": "carriage side: carriage guide",
    "bearing_damping": "carriage side: each pulley shaft",
    "motor_efficiency": "motor side: the motor",
    "speed": ("motor side: motor shaft", "carriage side: carriage"),
    "accel": ("motor side: motor shaft", "carriage side: carriage"),
    "stroke": "carriage side: carriage travel per move",
    "dwell": "the cycle: standstill after each move",
    "inertia_ratio_limit": "motor side: load / rotor inertia at the motor shaft",
    "peak_margin": "motor side: on the motor's peak torque",
}


def where(name: str, value: object = None) -> str:
    """Where the value ``name`` of :data:`PARAMS` is measured (:data:`WHERE`); a speed or
    an acceleration by its unit (``value`` is ``(float, unit)``: rad/s at the motor, m/s at
    the carriage).

    >>> where("gearbox_inertia"), where("speed", (2.0, "m/s"))
    ('motor side: at the gearbox input', 'carriage side: carriage')
    """
    w = WHERE[name]
    if isinstance(w, tuple):
        unit = value[1] if isinstance(value, tuple) else ""
        return w[0] if unit.startswith("rad") else w[1]
    return w


@dataclass(frozen=True)
class SizingInputs:
    """Everything ``beltcalc motor-size`` needs, SI. ``speed``/``accel`` carry their kind:
    ``speed_unit`` "rad/s" (motor) or "m/s" (carriage), ``accel_unit`` "rad/s^2" or
    "m/s^2". ``pulley_diameter`` / ``pulley_inertia`` / ``idler_inertia`` = None are
    computed from the pulley teeth and geometry."""

    mass: float
    width: float
    center_distance: float
    pulley_teeth: int
    pulley_width: float
    pulley_bore: float
    pulley_density: float
    coupling_inertia: float
    gearbox_inertia: float
    gear_ratio: float
    belt_ratio: float
    resistance: float
    guide_friction: float
    guide_damping: float
    bearing_damping: float
    motor_efficiency: float
    speed: float
    speed_unit: str
    accel: float
    accel_unit: str
    stroke: float
    dwell: float
    inertia_ratio_limit: float = 10.0
    peak_margin: float = 0.0
    substitute_mass_model: str = "eq7"
    pulley_diameter: float | None = None
    pulley_inertia: float | None = None
    idler_inertia: float | None = None
    load_inertia: float = 0.0

    def __post_init__(self):
        # pint quantities: the units of PARAMS; speed and accel in the SI unit of their kind
        units = {p.name: p.unit for p in PARAMS if p.unit not in (None, "int") and "|" not in p.unit}
        convert_fields(self, {**units, "speed": self.speed_unit, "accel": self.accel_unit,
                              "inertia_ratio_limit": "", "peak_margin": ""})

    @classmethod
    def from_values(cls, values: Mapping[str, object], substitute_mass_model: str = "eq7") -> SizingInputs:
        """The inputs from the SI values of :data:`PARAMS` (``belt`` and other keys are not
        read); ``speed`` and ``accel`` are ``(value, unit)`` as :class:`~beltcalc.params.Param`
        reads them."""
        fields = {p.name: values[p.name] for p in PARAMS if p.name in values and p.name != "belt"}
        speed, speed_unit = fields.pop("speed")
        accel, accel_unit = fields.pop("accel")
        return cls(**fields, speed=speed, speed_unit=speed_unit, accel=accel, accel_unit=accel_unit,
                   substitute_mass_model=substitute_mass_model)
