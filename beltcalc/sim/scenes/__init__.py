"""Scenes: a drive train from parameters (SI) and what a run of it reports.

:data:`SCENES` maps each built-in scene's name (the ``beltcalc simulate`` command) to its
:class:`~beltcalc.sim.scenes.base.Scene`; :mod:`beltcalc.sim.scenes.base` runs one.
"""

from beltcalc.sim.scenes import linear_axis, roller_table, sewing

SCENES = {s.name: s for s in (sewing.SCENE, roller_table.SCENE, linear_axis.SCENE)}
