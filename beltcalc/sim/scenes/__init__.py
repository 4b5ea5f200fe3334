"""Scenes: functions that build a :class:`~beltcalc.sim.network.Network` from parameters (SI)."""
