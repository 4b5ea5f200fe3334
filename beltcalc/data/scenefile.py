"""Scene files (``catalogs/scenes/*.toml``): a ready parameter set for a command, every
value as text with its unit and the reason it has that value.

A scene file has a ``[source]`` table (as a catalog file's), a ``[scene]`` table (``title``,
the ``command`` it is for, optionally a ``base`` scene whose values it inherits and
overrides) and a ``[parameters]`` table of ``name = { value = "50 kg", why = "..." }``. The
keys are :data:`SCENE_FILE`'s (:mod:`beltcalc.data.schema`); the command that uses a scene
converts its values.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from beltcalc.data.catalogs import SOURCE, Source, builtin_dir, file_source
from beltcalc.errors import UnknownNameError, did_you_mean
from beltcalc.data.schema import Named, Record, Section, Text, TomlFile
from beltcalc.data.tomlsafe import MAX_NAME, quote

SCENE = Record({
    "title": Text(help="what the scene is"),
    "command": Text(required=True, help="the command it is for, e.g. motor-size or simulate sewing"),
    "base": Text(name=True, help="a scene whose values it inherits and overrides"),
})
PARAMETER = Record({
    "value": Text(required=True, numbers=True, help="a quantity with its unit, or a name"),
    "why": Text(required=True, help="every scene value says why it has that value"),
})
SCENE_FILE = Record({
    "source": Section(record=SOURCE, required=True, help="[source] with a document"),
    "scene": Section(record=SCENE, required=True, help="[scene] with title and command"),
    "parameters": Named(item=Section(record=PARAMETER, help='{ value = "<quantity or name>", why = "..." }'),
                        required=True,
                        help='[parameters]: name = { value = "...", why = "..." }'),
})


@dataclass(frozen=True)
class SceneFile:
    """A ready parameter set (``catalogs/scenes/*.toml``): values as text with units, each
    with the reason it has that value. The command that uses it converts the values."""

    name: str
    title: str
    command: str
    source: Source
    values: dict[str, tuple[str, str]]  # name -> (value text, why)


def scene_names(command: str | None = None) -> list[str]:
    """Names of the built-in scenes (for ``command`` only, if given)."""
    folder = builtin_dir() / "scenes"
    names = []
    for path in sorted(folder.glob("*.toml")):
        if command is None or load_scene(str(path)).command == command:
            names.append(path.stem)
    return names


def load_scene(ref: str, command: str | None = None) -> SceneFile:
    """A built-in scene by name (``wdu``) or a scene file by path.

    Every parameter is a table ``name = { value = "50 kg", why = "..." }``. A scene may
    name a ``base`` scene in its ``[scene]`` table: it inherits the base's parameters and
    overrides those it gives itself.

    >>> load_scene("wdu").values["mass"][0]
    '50 kg'
    """
    path = Path(ref)

    def exists(p: Path) -> bool:
        try:
            return p.exists()
        except (OSError, ValueError):      # a name too long, a NUL character
            return False
    if not (path.suffix == ".toml" or exists(path)):
        path = builtin_dir() / "scenes" / f"{ref}.toml"
        if not exists(path):
            known = scene_names(command)
            hint = did_you_mean(ref, known, listed=0) if len(ref) <= MAX_NAME else ""
            hint = f"; {hint}" if hint else ""
            raise UnknownNameError(f"unknown scene {quote(ref)}{hint} (built-in: {', '.join(known)}; "
                                   "or give a .toml path)", param="scene")
    file = TomlFile(path, SCENE_FILE, what="scene file")
    head = file.values["scene"]
    if command is not None and head["command"] != command:
        file.fail("scene.command", f"this scene is for `beltcalc {head['command']}`, not `{command}`")
    values = {key: (item["value"], item["why"]) for key, item in file.values["parameters"].items()}
    base = head.get("base")
    if base is not None:
        if base == path.stem:
            file.fail("scene.base", "must name another scene")
        values = {**load_scene(base).values, **values}
    return SceneFile(name=path.stem, title=head.get("title", path.stem), command=head["command"],
                     source=file_source(file), values=values)
