"""Scene files (beltcalc/data/scenefile.py): the built-in ones, a base scene's values inherited,
and every malformed file refused in one line naming the file and the key."""

from __future__ import annotations

import pytest

from beltcalc.errors import CatalogError, UnknownNameError
from beltcalc.data.scenefile import load_scene, scene_names

HEAD = '[source]\ndocument = "mine"\n[scene]\ntitle = "t"\ncommand = "motor-size"\n'


def test_builtin_scenes_and_their_commands():
    assert scene_names("motor-size") == ["pdd", "wdu"]
    assert set(scene_names()) == {"linear_axis", "pdd", "roller_table", "sewing", "wdu"}
    wdu = load_scene("wdu", command="motor-size")
    assert wdu.values["mass"][0] == "50 kg" and wdu.source.document.startswith("Wojtkowiak")


def test_a_scene_inherits_its_base_and_overrides_it(tmp_path):
    path = tmp_path / "heavier.toml"
    path.write_text(HEAD.replace('command', 'base = "wdu"\ncommand')
                    + '[parameters]\nmass = { value = 80, why = "our axis" }\n')
    scene = load_scene(str(path), command="motor-size")
    assert scene.values["mass"] == ("80", "our axis")              # a number is taken as its text
    assert scene.values["stroke"] == load_scene("wdu").values["stroke"]
    assert scene.title == "t" and scene.name == "heavier"


@pytest.mark.parametrize("body, key, words", [
    ('[parameters]\nmass = { value = "5 kg" }\n', "parameters.mass.why", "missing (every scene value says why"),
    ('[parameters]\nmass = { value = "5 kg", why = " " }\n', "parameters.mass.why", "must not be empty"),
    ('[parameters]\nmass = { value = true, why = "w" }\n', "parameters.mass.value", "must be a text, not True"),
    ('[parameters]\nmass = "5 kg"\n', "parameters.mass", 'must be a table ({ value = "<quantity or name>"'),
    ('[parameters]\nmass = { value = "5 kg", why = "w", unit = "kg" }\n', "parameters.mass.unit", "unknown key"),
    ('colour = "red"\n[parameters]\n', "scene.colour", "unknown key; did you mean"),
    ("", "parameters", "missing"),
    ('[parameters]\n[units]\n', "units", "unknown key"),
])
def test_malformed_scene_file(body, key, words, tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(HEAD + body)
    with pytest.raises(CatalogError) as info:
        load_scene(str(path), command="motor-size")
    assert str(info.value).startswith(f"{path}: {key}: ") and words in str(info.value)
    assert info.value.exit_code == 1


def test_a_scene_for_another_command_or_itself_as_base(tmp_path):
    with pytest.raises(CatalogError, match="this scene is for `beltcalc simulate sewing`, not `motor-size`"):
        load_scene("sewing", command="motor-size")
    path = tmp_path / "loop.toml"
    path.write_text(HEAD.replace('command', 'base = "loop"\ncommand') + '[parameters]\n')
    with pytest.raises(CatalogError, match="scene.base: must name another scene"):
        load_scene(str(path))


def test_unknown_scene_offers_the_closest():
    with pytest.raises(UnknownNameError, match=r"unknown scene 'wdx'; did you mean wdu") as info:
        load_scene("wdx", command="motor-size")
    assert info.value.param == "scene" and info.value.exit_code == 2
