"""Drive files: a designer's own drive train as TOML, read into a :class:`Drive` (a
:class:`~beltcalc.sim.network.Network` plus its timing and notes).

A drive file lists nodes (inertias, translating masses) and the elements between them:
couplings, rigid gears, shafts from geometry, belt spans from a belt catalog entry, chain
strands from ``catalogs/chains.toml``, motors (induction, prescribed motion, speed loop,
torque table) and loads. Every value is a quantity string with its unit (plain numbers for
ratios, counts and factors), converted to SI once, here. The format is in
``docs/drive_files.md``; an example is ``catalogs/drives/conveyor.toml``.

Every value of every element is addressable as ``ELEMENT.KEY`` (``jaw.stiffness``,
``upper.pretension``; the timing as ``t_end``, ``samples``, ``window``): :meth:`DriveFile.params`
lists them and :meth:`DriveFile.build` takes new values for any of them, so ``--set`` and
``--sweep`` reach every number in the file.

A malformed file is one :class:`DriveFileError` naming the file, the element and the key
(exit 1); nothing is half-built.

Each element kind owns its section, its keys and its build: one class (``kinds.py``,
``motors.py`` of this package) and one line of the ``ELEMENTS`` registry (``registry.py``),
from which the reader (``reader.py``), the builder (``builder.py``), the writer
(``write.py``) and the docs' key tables (``docs.py``) take them.
"""

from beltcalc.sim.drivefile.api import drive_names, drive_path, load_drive, simulate
from beltcalc.sim.drivefile.keys import DriveFileError, DriveParam, Entry
from beltcalc.sim.drivefile.motors import MAX_RATED_SLIP, pole_pairs_from_speed
from beltcalc.sim.drivefile.reader import Drive, DriveFile, undamped_frequencies
from beltcalc.sim.drivefile.registry import ELEMENTS, KEYS, KIND_KEYS, KINDS, SECTIONS
from beltcalc.sim.drivefile.write import to_toml

__all__ = ["ELEMENTS", "KEYS", "KINDS", "KIND_KEYS", "MAX_RATED_SLIP", "SECTIONS", "Drive", "DriveFile",
           "DriveFileError", "DriveParam", "Entry", "drive_names", "drive_path", "load_drive",
           "pole_pairs_from_speed", "simulate", "to_toml", "undamped_frequencies"]
