"""Files a designer gives beltcalc, read through one typed schema: the built-in and the
user's catalogs, duty-cycle files and scene files.

:mod:`~beltcalc.data.tomlsafe` (bounded TOML reading, keys and values shown in messages),
:mod:`~beltcalc.data.schema` (fields with unit, bounds and help; one error naming the file,
the entry and the key), :mod:`~beltcalc.data.catalogs` (belts, pulleys, chains, motors and
their cache), :mod:`~beltcalc.data.cyclefile` (duty cycles), :mod:`~beltcalc.data.scenefile`
(a scene's values).
"""
