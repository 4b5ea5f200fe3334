"""beltcalc: belt and chain drive trains, from catalog data to numbers you can build from.

The public API (names load on first use, so ``import beltcalc`` stays cheap):

- drive trains: :func:`load_drive` (a drive file, or a built-in one by name),
  :func:`simulate`, :class:`SolverConfig`, :class:`SimResult`, and the element classes
  :class:`Network`, :class:`Inertia`, :class:`Coupling`, :class:`Gear`, :class:`Strand`,
  :class:`Load`, :class:`InductionMotor`, :class:`Prescribed`, :class:`SpeedLoop` (PI, with a torque limit), :class:`Friction` (a clutch,
  brake or bearing friction that sticks),
  :class:`Backlash` (give a network its ``elements()``);
- design: :func:`design_tension` with :class:`TensionInputs`, :func:`size_axis` with
  :class:`SizingInputs`, :func:`static_error` and :func:`along_stroke` (the static positioning
  error of a belt-driven axis, :class:`PositionError`), :func:`load_catalog`.

Values are SI floats; pint quantities are accepted where the library takes SI floats and
converted (or refused with a message naming the field). See the README's "Python" section.

>>> import beltcalc
>>> drive = beltcalc.load_drive("friswell_5_disks")
>>> [round(f, 2) for f in beltcalc.undamped_frequencies(drive.network)]
[81.21, 141.21, 378.95, 536.36]
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_WHERE = {
    "load_drive": "beltcalc.sim.drivefile", "Drive": "beltcalc.sim.drivefile",
    "DriveFile": "beltcalc.sim.drivefile", "undamped_frequencies": "beltcalc.sim.drivefile",
    "simulate": "beltcalc.sim.drivefile",
    "SolverConfig": "beltcalc.sim.core", "SimResult": "beltcalc.sim.result",
    "Network": "beltcalc.sim.network", "Inertia": "beltcalc.sim.elements", "Coupling": "beltcalc.sim.elements",
    "Gear": "beltcalc.sim.elements", "Strand": "beltcalc.sim.elements", "Load": "beltcalc.sim.elements",
    "InductionMotor": "beltcalc.sim.elements", "Prescribed": "beltcalc.sim.elements",
    "SpeedLoop": "beltcalc.sim.elements.switched", "Friction": "beltcalc.sim.elements.switched",
    "Backlash": "beltcalc.sim.elements.backlash",
    "design_tension": "beltcalc.design.tension", "TensionInputs": "beltcalc.design.tension",
    "size_axis": "beltcalc.design.sizing", "SizingInputs": "beltcalc.design.axis_inputs",
    "static_error": "beltcalc.design.positioning", "along_stroke": "beltcalc.design.positioning",
    "PositionError": "beltcalc.design.positioning",
    "load_catalog": "beltcalc.data.catalogs",
    "BeltcalcError": "beltcalc.errors", "InputError": "beltcalc.errors",
}
__all__ = sorted(_WHERE) + ["__version__"]


def __getattr__(name: str):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module 'beltcalc' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__():
    return __all__
