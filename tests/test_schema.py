"""The typed schema of the TOML files (beltcalc/data/schema.py): each field type reads what it
should, in each notation, and refuses everything else with one message that says where,
the value and what is allowed. Unit factors are by definition (1 mm = 1e-3 m, 1 rpm =
2 pi / 60 rad/s, 1 kg*cm^2 = 1e-4 kg*m^2)."""

from __future__ import annotations

import math

import pytest

from beltcalc.errors import CatalogError
from beltcalc.data.schema import (CATALOG, QUANTITIES, SI_TEXTS, TEXTS, Choice, Context, Entries, FieldError, Flag, List,
                             Named, Names, Quantity, Record, Section, Table, Text, TomlFile, Whole)

RPM = 2 * math.pi / 60


def refused(field, raw, ctx=Context(TEXTS), at="x") -> FieldError:
    with pytest.raises(FieldError) as info:
        field.read(raw, ctx, at, "x")
    return info.value


def table_ctx(**units) -> Context:
    return Context(CATALOG, units, "belts[0]")


# --- Quantity, catalog notation: a number, its unit in the units table ------------------------
def test_catalog_number_in_its_tables_unit():
    assert Quantity("m").read(25, table_ctx(x="mm"), "w", "x") == pytest.approx(0.025)
    assert Quantity("rad/s").read(3000, table_ctx(x="rpm"), "w", "x") == pytest.approx(3000 * RPM)
    # the unit under another key (F_tspec rows: load's unit is units.F_tspec)
    assert Quantity("N/m", unit_key="F_tspec").read(30, table_ctx(F_tspec="N/cm"), "w", "load") == pytest.approx(3000.0)
    assert Quantity("").read(3, table_ctx(), "w", "x") == 3.0           # a plain number needs no unit


@pytest.mark.parametrize("raw, units, at, words", [
    (25, {}, "belts[0].units.x", ["no unit given"]),
    (25, {"x": 3}, "belts[0].units.x", ["no unit given"]),
    (25, {"x": "kg"}, "belts[0].units.x", ["'kg' is a mass, not a length"]),
    (25, {"x": "furlongz"}, "belts[0].units.x", ["cannot read 'furlongz'"]),
    ("25", {"x": "mm"}, "w", ["'25' is not a number"]),
    (True, {"x": "mm"}, "w", ["True is not a number"]),
    (math.nan, {"x": "mm"}, "w", ["'nan' is not a finite number"]),
    (-math.inf, {"x": "mm"}, "w", ["'-inf' is not a finite number"]),
    (1e300, {"x": "Gm"}, "w", ["1e+300 Gm is too large: above 1e308 m"]),
    (-2, {"x": "mm"}, "w", ["-2 mm is not allowed; it must be > 0 mm"]),
    (0, {"x": "mm"}, "w", ["0 mm is not allowed; it must be > 0 mm"]),
])
def test_catalog_number_refused(raw, units, at, words):
    exc = refused(Quantity("m", low=">0"), raw, table_ctx(**units), "w")
    assert exc.at == at
    for w in words:
        assert w in exc.message


def test_catalog_bounds_low_and_high():
    eff = Quantity("", low=">0", high=1.0)
    assert eff.read(0.9, table_ctx(), "e", "x") == 0.9
    assert refused(eff, 1.5, table_ctx()).message == "1.5 is not allowed; it must be <= 1"
    assert Quantity("kg*m^2", low=">=0").read(0, table_ctx(x="kg*cm^2"), "J", "x") == 0.0
    assert refused(Quantity("kg*m^2", low=">=0"), -1, table_ctx(x="kg*cm^2")).message == \
        "-1 kg*cm^2 is not allowed; it must be >= 0 kg*cm^2"


# --- Quantity, text notations -------------------------------------------------------------------
def test_text_quantities():
    assert Quantity("m").read("250 mm", Context(TEXTS)) == pytest.approx(0.25)
    assert Quantity("").read(2.5, Context(TEXTS)) == 2.5
    either = Quantity("rad/s|m/s")
    assert either.read("3000 rpm", Context(TEXTS)) == pytest.approx(3000 * RPM)       # the value alone
    assert Quantity("rad/s|m/s", keep_unit=True).read("2 m/s", Context(TEXTS)) == (pytest.approx(2.0), "m/s")


@pytest.mark.parametrize("field, raw, message", [
    (Quantity("m"), 25, '25 needs its unit: write it as a text, e.g. "25 mm"'),
    (Quantity("rad/s|m/s"), 3, '3 needs its unit: write it as a text, e.g. "3 rpm" or "3 m/s"'),
    (Quantity("m"), [1], "must be a quantity text such as '5 mm', not [1]"),
    (Quantity(""), True, "must be a number, not True"),
    (Quantity(""), "0.5", "must be a plain number, not the text '0.5': write it without quotes "
                          "(ratios, factors and slips are numbers, docs/drive_files.md)"),
    (Quantity("m"), "5 kg", "'5 kg' is a mass, not a length; give e.g. '5 mm'"),
    (Quantity("m", low=">=0"), "-1 m", "-1 m is not allowed; it must be >= 0 m"),
    (Quantity("", low="!=0", hint="negative: the pair turns the other way"), 0,
     "0 is not allowed; it must not be 0 (negative: the pair turns the other way)"),
])
def test_text_quantity_refused(field, raw, message):
    exc = refused(field, raw, at="gear 'g'.ratio")
    assert exc.message == message and exc.at == "gear 'g'.ratio"
    assert str(exc) == message                       # a drive file adds its own element and key


def test_bare_numbers_are_si_where_the_notation_says():
    assert Quantity("m").read(0.3, Context(SI_TEXTS)) == 0.3
    assert Quantity("rad/s|m/s", keep_unit=True).read(1.5, Context(SI_TEXTS)) == (1.5, "rad/s")   # the first
    assert refused(Quantity("m"), math.inf, Context(SI_TEXTS)).message == "'inf' is not a finite number"
    assert refused(Quantity(""), "0.3", Context(SI_TEXTS)).message.startswith("must be a plain number")
    # cycle files: a bare number is SI and a plain number may be a text
    assert Quantity("m").read(0.3, Context(QUANTITIES)) == 0.3
    assert Quantity("").read("0.25", Context(QUANTITIES)) == 0.25
    assert refused(Quantity(""), "1 m", Context(QUANTITIES)).message == "'1 m' must be a plain number, not a length"


# --- whole numbers, flags, texts, choices, names ------------------------------------------------
def test_whole_number():
    teeth = Whole(low=">0")
    assert teeth.read(20, Context(TEXTS)) == 20
    assert refused(teeth, 1.5).message == "must be a whole number, not 1.5"
    assert refused(teeth, True).message == "must be a whole number, not True"
    assert refused(teeth, 0).message == "0 is not allowed; it must be > 0"


def test_flag():
    assert Flag().read(False, Context(TEXTS)) is False
    assert refused(Flag(), "yes").message == "must be true or false, not 'yes'"
    assert refused(Flag(), 1).message == "must be true or false, not 1"


def test_text():
    assert Text().read("two\nlines", Context(TEXTS)) == "two\nlines"
    assert Text(numbers=True).read(5.0, Context(TEXTS)) == "5.0"
    assert Text().read("", Context(TEXTS)) == ""
    assert refused(Text(), 3).message == "must be a text, not 3"
    assert refused(Text(required=True, help="the maker"), "  ").message == "must not be empty (the maker)"
    assert refused(Text(filled=True), "").message == "must not be empty"
    assert "holds the character U+000A" in refused(Text(name=True), "a\nb").message
    assert "starts or ends with a space" in refused(Text(name=True), "AT10 ").message
    assert "holds the character U+202E" in refused(Text(), "a\u202eb").message
    assert "is too long (at most 100 characters)" in refused(Text(name=True), "x" * 101).message


def test_choice():
    kind = Choice(choices=("move", "dwell"))
    assert kind.read("dwell", Context(TEXTS)) == "dwell"
    assert refused(kind, "jump").message == "'jump' is not allowed; use \"move\" or \"dwell\""
    assert refused(kind, 3).message == "3 is not allowed; use \"move\" or \"dwell\""


def test_names():
    between = Names(count=(1, 2), help="[node, node]")
    assert between.read(["a", "b"], Context(TEXTS)) == ["a", "b"]
    assert refused(between, ["a", "b", "c"]).message == \
        "must be a list of 1 or 2 names ([node, node]), not ['a', 'b', 'c']"
    exc = refused(Names(), ["a", 3])
    assert (exc.at, exc.message) == ("x[1]", "must be a text, not 3")


# --- lists and tables ---------------------------------------------------------------------------
def test_list():
    loads = List(item=Quantity("N", low=">0"), least=1, rising=True, help="breaking loads by strand count")
    assert loads.read([10, 20], table_ctx(x="kN"), "b", "x") == (pytest.approx(1e4), pytest.approx(2e4))
    assert refused(loads, 3, table_ctx(x="kN")).message == \
        "must be a list of 1 or more (breaking loads by strand count), not 3"
    assert refused(loads, [], table_ctx(x="kN")).message.startswith("must be a list of 1 or more")
    exc = refused(loads, [20, 10], table_ctx(x="kN"))
    assert (exc.at, exc.message) == ("x[1]", "must rise, without repeats: 10 after 20")
    exc = refused(loads, [20, -1], table_ctx(x="kN"))             # an item names its place
    assert (exc.at, exc.message) == ("x[1]", "-1 kN is not allowed; it must be > 0 kN")
    grid = List(item=List(item=Quantity("", low=">=0")))
    assert grid.read([[1, 2], [3]], table_ctx(), "g", "x") == ((1.0, 2.0), (3.0,))
    assert refused(grid, [[1], [2, -1]], table_ctx()).at == "x[1][1]"


def test_table_of_pairs():
    torque = Table(columns=(Quantity("s"), Quantity("N*m|N")))
    assert torque.read([["0 s", "1 N*m"], ["0.5 s", "1 N*m"], ["0.5 s", "3 N*m"]], Context(TEXTS)) == \
        ((0.0, 1.0), (0.5, 1.0), (0.5, 3.0))                       # a time may repeat: a jump
    assert refused(torque, [["0 s"]]).message == \
        'must be a list of [time, value] pairs, e.g. [["0 s", "0 N*m"], ["1 s", "5 N*m"]]'
    assert refused(Table(columns=(Quantity("s"), Quantity(""))), []).message == \
        'must be a list of [time, value] pairs, e.g. [["0 s", 0], ["1 s", 5]]'
    assert refused(torque, [["1 s", "0 N*m"], ["0 s", "1 N*m"]]).message == \
        "the times must rise (a time may repeat for a jump)"
    exc = refused(torque, [["0 s", "0 N*m"], ["1 s", "2 kg"]])
    assert exc.at == "x[1][1]" and "'2 kg' is neither a torque nor a force" in exc.message


# --- records: tables of keys --------------------------------------------------------------------
MOTOR = Record({
    "name": Text(name=True, required=True, help="e.g. M1"),
    "series": Text(default=""),
    "speed": Quantity("rad/s", low=">0", help="rated speed"),
    "rated_power": Quantity("W", help="rated power", when="speed"),
})


def test_record_reads_present_keys_and_defaults():
    assert MOTOR.read({"name": "M1"}, Context(TEXTS), "motor[0]") == {"name": "M1", "series": ""}
    got = MOTOR.read({"name": "M1", "speed": "3000 rpm", "rated_power": "400 W"}, Context(TEXTS), "motor[0]")
    assert got == {"name": "M1", "series": "", "speed": pytest.approx(3000 * RPM), "rated_power": 400.0}


@pytest.mark.parametrize("raw, at, message", [
    ({}, "motor[0].name", "missing (e.g. M1)"),
    ({"name": "M1", "sped": "1 rpm"}, "motor[0].sped",
     "unknown key; did you mean speed, series, rated_power? (one of name, series, speed, rated_power)"),
    ({"name": "M1", "speed": "1 rpm"}, "motor[0].rated_power", "missing (rated power; needed with speed)"),
    ({"name": "M1", "speed": "0 rpm"}, "motor[0].speed", "0 rad/s is not allowed; it must be > 0 rad/s"),
])
def test_record_refuses(raw, at, message):
    with pytest.raises(FieldError) as info:
        MOTOR.read(raw, Context(TEXTS), "motor[0]")
    assert (info.value.at, info.value.message) == (at, message)


def test_units_tables_nest_and_name_where_they_stand():
    row = Record({"width": Quantity("m", required=True), "F": Quantity("N")})
    belt = Record({"pitch": Quantity("m", required=True), "widths": Entries(record=row)}, units=True)
    top = Record({"belts": Entries(record=belt)}, units=True)
    data = {"units": {"pitch": "mm", "width": "mm"},
            "belts": [{"pitch": 10, "widths": [{"width": 25}]},
                      {"pitch": 0.5, "units": {"pitch": "in"}, "widths": [{"width": 32, "F": 2}]}]}
    with pytest.raises(FieldError) as info:      # F has no unit: the entry whose units are in force
        top.read(data, Context(CATALOG))
    assert (info.value.at, info.value.message) == ("belts[1].units.F", "no unit given for this key")
    data["belts"][1]["units"]["F"] = "kN"
    got = top.read(data, Context(CATALOG))
    assert got["belts"][0] == {"pitch": pytest.approx(0.01), "widths": [{"width": pytest.approx(0.025)}]}
    assert got["belts"][1]["pitch"] == pytest.approx(0.0127)           # the entry's own unit over the file's
    assert got["belts"][1]["widths"] == [{"width": pytest.approx(0.032), "F": pytest.approx(2000.0)}]
    with pytest.raises(FieldError) as info:
        top.read({"units": "mm"}, Context(CATALOG))
    assert (info.value.at, info.value.message) == ("units", "must be a table of unit texts")


def test_sections_entries_and_named_tables():
    head = Section(record=Record({"title": Text()}), help="[cycle]")
    assert head.read({"title": "t"}, Context(TEXTS), "cycle") == {"title": "t"}
    assert refused(head, 3).message == "must be a table ([cycle]), not 3"
    moves = Entries(record=Record({"t": Quantity("s")}), least=1, most=2)
    assert moves.read([{"t": "1 s"}], Context(TEXTS), "segment", "segment") == [{"t": 1.0}]
    assert refused(moves, []).message == "must be an array of 1 or more tables, not []"
    assert refused(moves, [{}, 3]).message == "must be an array of 1 or more tables, not [{}, 3]"
    exc = refused(moves, [{}, {}, {}], at="segment")
    assert exc.message == "3 [[x]] tables; at most 2"
    exc = refused(moves, [{"t": "1 s"}, {"t": "2 m"}], at="segment")
    assert exc.at == "segment[1].t"
    masses = Named(item=Quantity("kg/m", low=">0"), help="{ strands = mass }")
    assert masses.read({"1": 0.7}, table_ctx(x="kg/m"), "mass", "x") == {"1": pytest.approx(0.7)}
    assert refused(masses, 3, table_ctx(x="kg/m")).message == \
        "must be a table of named values ({ strands = mass }), not 3"
    assert refused(masses, {"1": -1}, table_ctx(x="kg/m"), at="mass").at == "mass.1"


# --- a file ---------------------------------------------------------------------------------------
FILE = Record({"source": Section(record=Record({"document": Text(required=True)}), required=True),
               "widths": Entries(record=Record({"width": Quantity("m", required=True, low=">0")}))}, units=True)


def test_file_values_and_its_one_error_line(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text('units = { width = "mm" }\n[source]\ndocument = "d"\n[[widths]]\nwidth = 25\n')
    assert TomlFile(path, FILE).values["widths"] == [{"width": pytest.approx(0.025)}]
    path.write_text('units = { width = "mm" }\n[source]\ndocument = "d"\n'
                    '[[widths]]\nwidth = 25\n[[widths]]\nwidth = -1\n')
    with pytest.raises(CatalogError) as info:
        TomlFile(path, FILE)
    assert str(info.value) == f"{path}: widths[1].width: -1 mm is not allowed; it must be > 0 mm"
    assert info.value.exit_code == 1
    path.write_text('[[widths]]\nwidth = 25\n')
    with pytest.raises(CatalogError, match=r"mine.toml: source: missing$"):
        TomlFile(path, FILE)
    with pytest.raises(CatalogError, match="cycle file .*nope.toml does not exist"):
        TomlFile(tmp_path / "nope.toml", FILE, what="cycle file")


def test_the_one_error_names_a_hostile_key_on_one_line(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text('[source]\ndocument = "d"\n[[widths]]\nwidth = 1\n' + '"' + "w" * 500 + '" = 1\n')
    with pytest.raises(CatalogError) as info:
        TomlFile(path, FILE)
    assert "w" * 41 not in str(info.value) and "\n" not in str(info.value)
