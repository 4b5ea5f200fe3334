"""beltcalc.sim.drivefile reads each quantity text with pint once per process: a second build
of a drive reads no text, gives the same numbers, and a refused text is refused again, the same,
on every build (a refusal is not kept)."""

import math
import textwrap

import pytest

import beltcalc.units
from beltcalc.data.catalogs import builtin_dir
from beltcalc.sim.drivefile import DriveFile, DriveFileError
from beltcalc.sim.drivefile.kinds import material_table, materials
from test_drivefile import BASE


def _counting(monkeypatch):
    calls = []
    real = beltcalc.units.parse_quantity

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(beltcalc.units, "parse_quantity", counted)
    return calls


def test_a_second_build_reads_no_text_and_gives_the_same_drive(monkeypatch):
    f = DriveFile(builtin_dir() / "drives" / "conveyor.toml")
    first = f.build()
    calls = _counting(monkeypatch)
    second = f.build()
    assert [args for args in calls if isinstance(args[0], str)] == []      # numbers (a gear ratio) are not texts
    assert second.inputs == first.inputs
    assert second.notes == first.notes
    assert (second.network.M == first.network.M).all()


def test_the_material_table_is_read_once():
    material_table.cache_clear()
    table = materials()
    assert table["steel"] == {"shear_modulus": 75e9, "density": 7850.0}       # catalogs/materials.toml
    assert materials() is table


def test_a_refused_text_is_refused_again_on_every_build(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text(BASE + textwrap.dedent("""
        [[coupling]]
        name = "c"
        between = ["a", "b"]
        stiffness = "5 kg"
        """))
    messages = []
    for _ in range(2):
        with pytest.raises(DriveFileError) as info:
            DriveFile(path).build()
        messages.append(str(info.value))
    assert messages[0] == messages[1]
    assert "'5 kg' is a mass" in messages[0]


def test_a_key_missing_from_the_file_is_missing_on_every_build_that_does_not_set_it(tmp_path):
    # which keys are missing depends only on the addresses set: a set that gives every key is
    # kept, and a build with another set is checked again
    from test_drivefile_rules import INDUCTION

    path = tmp_path / "d.toml"
    path.write_text(INDUCTION.format(extra="").replace('supply = "50 Hz"\n', ""))
    f = DriveFile(path)
    for _ in range(2):
        net = f.network({"m.supply": 50.0})
        assert net.motors[0].supply == pytest.approx(2 * math.pi * 50.0)
        for values in ({}, {"m.breakdown_slip": 0.25}):
            with pytest.raises(DriveFileError, match=r"motor 'm': supply: missing \(induction: supply frequency\)"):
                f.network(values)
