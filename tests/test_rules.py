"""The registry of rules (beltcalc/design/checks.py ``RULES``, issue 28 item 4): one definition of
each limit with its source, used by every command that meets the quantity: `chain` and a
simulated chain strand (F_B / F >= 6, Diamond Chain), `tension` and a drive file's fitted belt
damping (R^2 >= 0.9), `belt-drive`, `tension` and a belt strand (F <= F_Tadm)."""

from __future__ import annotations

import ast
import json
import math
import re
from pathlib import Path
from types import SimpleNamespace as NS

import pytest
from click.testing import CliRunner

from beltcalc.data.catalogs import load_catalog
from beltcalc.design.chain_select import RPM, ChainInputs, chain_checks, check_chain
from beltcalc.design.checks import RULES, rules_table
from beltcalc.cli.main import cli
from beltcalc.sim.scenes.base import strand_check
from clichecks import ok, warnings

ROOT = Path(__file__).resolve().parents[1]
DRIVES = ROOT / "catalogs" / "drives"


def run(*args):
    return CliRunner().invoke(cli, list(args))


# --- the registry ---------------------------------------------------------------------------------

@pytest.mark.parametrize("key", list(RULES))
def test_every_rule_has_a_source_a_kind_and_a_limit(key):
    r = RULES[key]
    assert r.key == key and r.label and r.quantity and r.met_by
    assert r.kind in ("min", "max")
    assert len(r.source) > 10                       # a document (page, table) or "our rule" / "assumed"
    assert (r.limit is None) != (r.limit_name == "")   # a number, or the data it is named by, never both
    if r.limit is not None:
        assert math.isfinite(r.limit)


def test_a_fixed_limit_is_never_given_again():
    with pytest.raises(ValueError, match="fixed limit 6"):
        RULES["chain_safety"].check(5.0, 5.0)
    with pytest.raises(ValueError, match="fixed limit 0.9"):
        RULES["damping_fit"].check(0.5, quantity="r^2")
    with pytest.raises(ValueError, match="not 'kg'"):
        RULES["motor_peak_torque"].check(1.0, 2.0, unit="kg")
    # a fixed limit's rule reads the same whatever the command; the case is in the detail
    a = RULES["chain_safety"].check(5.0, detail="F = K_s F_pull + q v^2")
    b = RULES["chain_safety"].check(5.0, detail="F the peak force of a strand")
    assert a.rule.split("; ")[0] == b.rule.split("; ")[0] == RULES["chain_safety"].text()
    assert (a.limit, a.kind, a.unit) == (b.limit, b.kind, b.unit) == (6.0, "min", "1")


def _check_calls(path: Path) -> list[tuple[int, str]]:
    """Calls of :class:`Check` or of a subclass defined in the file: a check not made by a rule."""
    tree = ast.parse(path.read_text(), str(path))
    names = {"Check"} | {n.name for n in ast.walk(tree) if isinstance(n, ast.ClassDef)
                         and any(getattr(b, "id", getattr(b, "attr", None)) == "Check" for b in n.bases)}
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
            if name in names:
                out.append((node.lineno, name))
    return out


def test_every_check_in_the_code_base_is_made_from_the_registry():
    # a Check(...) outside checks.py would carry a limit and a rule text of its own
    found = {str(p.relative_to(ROOT)): calls for p in sorted((ROOT / "beltcalc").rglob("*.py"))
             if p.name != "checks.py" and (calls := _check_calls(p))}
    assert found == {}


def test_the_ast_scan_finds_a_check_made_by_hand(tmp_path):
    # the scan above can fail: a hand-made Check and a subclass's call are both found
    src = tmp_path / "m.py"
    src.write_text("from beltcalc.design.checks import Check\nclass C(Check): pass\n"
                   "a = Check('k', 'n', 1.0, 2.0, 'N')\nb = C('k', 'n', 1.0, 2.0, 'N')\n")
    assert _check_calls(src) == [(3, "Check"), (4, "C")]


def test_docs_table_is_the_registry():
    text = (ROOT / "docs" / "design_checks.md").read_text()
    assert rules_table() in text, "regenerate the table: python -c 'from beltcalc.design.checks import rules_table; " \
                                  "print(rules_table())'"
    rows = {m.group(1): m.group(0) for m in re.finditer(r"^\| `(\w+)` \|.*$", text, re.M)}
    for key, r in RULES.items():
        assert key in rows
        assert r.source.replace("|", "\\|") in rows[key]
        assert (f"| {r.limit:g} |" if r.limit is not None else f"| {r.limit_name.replace('|', chr(92) + '|')} |") \
            in rows[key]


# --- one chain rule: `chain` and the simulated strand -----------------------------------------------

BREAKING = 22200.0          # 10B-1, ISO 606 minimum tensile strength (catalogs/chains.toml)


@pytest.mark.parametrize("force", [3000.0, 3700.0, 3700.1, 4196.101134771084, 30.1e3])
def test_chain_and_the_strand_check_give_one_verdict_on_the_same_numbers(force):
    # F_B / F >= 6 <=> F <= 22.2 kN / 6 = 3700 N (by hand): pass up to 3700 N, FAIL above
    chain = load_catalog().chain("10B-1")
    assert chain.breaking_load == pytest.approx(BREAKING)
    speed = 100 * RPM
    v = 19 * chain.pitch * speed / (2 * math.pi)       # v = z p n
    power = (force - chain.mass * v * v) * v           # K_s = 1: K_s F_pull + q v^2 = force
    inp = ChainInputs(speed=speed, teeth_small=19, teeth_large=19, power=power)
    rating, safety = chain_checks(check_chain(chain, inp, power, power), power)
    assert safety.key == "safety"
    net, res = NS(strands=[NS(name="drive")]), NS(summary=lambda name, start: NS(max=force))
    strand, = strand_check(net, res, {"drive": (chain.breaking_load, "breaking load")})
    assert safety.value == pytest.approx(BREAKING / force, rel=1e-12)
    assert strand.value == pytest.approx(BREAKING / force, rel=1e-12)
    assert strand.verdict == safety.verdict == ("pass" if force <= BREAKING / 6 else "FAIL")
    assert (strand.limit, strand.kind, strand.unit) == (safety.limit, safety.kind, safety.unit) == (6.0, "min", "1")
    for c in (strand, safety):
        assert c.rule.startswith(RULES["chain_safety"].text() + "; ")
    assert strand.level == pytest.approx(BREAKING / 6)     # the plot's bound on the strand's force


@pytest.fixture(scope="module")
def roller_table():
    res = run("simulate", "roller-table", "--json")
    assert res.exit_code == 0, res.output
    return res, json.loads(res.stdout)


def test_default_roller_table_fails_chain_rule_as_chain_does(roller_table):
    # the README's default: the drive strand peaks at 4196 N (the element landing) on a 10B-1:
    # F_B / F = 22.2 kN / 4196 N = 5.29 < 6, the FAIL `chain` gives the same chain at that load
    res, obj = roller_table
    force = obj["strands"]["drive-sprocket1"]["force_max"]["value"]
    assert obj["inputs"]["chain_breaking_load"]["value"] == pytest.approx(BREAKING)
    strand = next(c for c in obj["checks"] if c["key"] == "strand_strength")
    assert strand["value"]["value"] == pytest.approx(BREAKING / force, rel=1e-12)
    assert strand["verdict"] == "FAIL" and strand["limit"]["value"] == 6.0
    # `chain` on the same chain at the same load: K_s = 1, power so that F_pull + q v^2 = 4196 N
    chain = load_catalog().chain("10B-1")
    v = 19 * chain.pitch * 100 / 60
    power = (force - chain.mass * v * v) * v
    out = json.loads(ok(run("chain", "--chain", "10B-1", "--teeth", "19", "--teeth-large", "19", "--speed", "100rpm",
                            "--service-factor", "1", "--design-factor", "1", "--power", f"{power!r}W",
                            "--json")).stdout)
    safety = next(c for c in out["checks"] if c["key"] == "safety")
    assert safety["value"]["value"] == pytest.approx(strand["value"]["value"], rel=1e-9)
    assert [safety[k] for k in ("verdict", "limit", "kind")] == [strand[k] for k in ("verdict", "limit", "kind")]
    assert safety["utilisation"]["value"] == pytest.approx(strand["utilisation"]["value"], rel=1e-9)
    assert safety["rule"].split("; ")[0] == strand["rule"].split("; ")[0]
    # the finding, as a warning (stderr and JSON) that says what to do
    said = [w for w in obj["warnings"] if w.startswith("strand breaking-load safety FAILS: 5.291 must be >= 6")]
    assert len(said) == 1 and "--set chain=12B-1" in said[0] and said[0] in warnings(res)


def test_twelve_b_passes_the_roller_table():
    # the warning's advice, checked: a 12B-1 (28.9 kN, 19.05 mm: larger sprockets, lower force) passes
    obj = json.loads(ok(run("simulate", "roller-table", "--set", "chain=12B-1", "--json")).stdout)
    strand = next(c for c in obj["checks"] if c["key"] == "strand_strength")
    force = obj["strands"]["drive-sprocket1"]["force_max"]["value"]
    assert strand["value"]["value"] == pytest.approx(28900.0 / force, rel=1e-12)
    assert strand["verdict"] == "pass" and strand["value"]["value"] == pytest.approx(8.5, abs=0.05)
    # its one warning: no maker's allowable dynamic (fatigue) load for the B series in
    # catalogs/chains.toml, so the fatigue check is unverified (rule chain_fatigue)
    fatigue, = [c for c in obj["checks"] if c["verdict"] != "pass"]
    assert fatigue["key"] == "strand_fatigue" and fatigue["verdict"] == "unverified"
    assert len(obj["warnings"]) == 1 and "12B-1" in obj["warnings"][0]


# --- one damping-fit rule: `tension` and a drive file ---------------------------------------------

def test_drive_file_damping_fit_below_r2_fails_as_in_tension(tmp_path):
    # the conveyor's belt spans on BRECO T20, with no `damping`: b is fitted to T20's F_tspec(n);
    # R^2 of the line through the origin does not depend on D, width or z_e (a scale of v and of
    # F), so the drive file's R^2 is tension's for the same belt, and it fails both
    path = tmp_path / "t20.toml"
    path.write_text((DRIVES / "conveyor.toml").read_text().replace("BRECO-AT10", "BRECO-T20"))
    res = run("simulate", "drive", str(path), "--json")
    assert res.exit_code == 0, res.output
    obj = json.loads(res.stdout)
    fit = next(c for c in obj["checks"] if c["key"] == "damping_fit")
    tension = json.loads(ok(run("tension", "--belt", "BRECO-T20", "--width", "25mm", "--json")).stdout)
    ref = next(c for c in tension["checks"] if c["key"] == "damping_fit")
    assert ref["verdict"] == fit["verdict"] == "FAIL"
    assert fit["value"]["value"] == pytest.approx(ref["value"]["value"], rel=1e-9)
    assert fit["value"]["value"] < fit["limit"]["value"] == ref["limit"]["value"] == RULES["damping_fit"].limit
    assert fit["rule"].split("; ")[0] == ref["rule"].split("; ")[0]
    assert "belt span upper" in fit["rule"] and "2 of 2 fitted spans" in fit["rule"]
    said = [w for w in obj["warnings"] if w.startswith("damping fit R^2 FAILS")]
    assert len(said) == 1 and said[0] in warnings(res) and "--set upper.damping" in said[0]
    # --strict: exit 1
    strict = run("simulate", "drive", str(path), "--strict")
    assert strict.exit_code == 1 and "damping fit R^2" in strict.stderr.splitlines()[-1]


def test_drive_file_with_damping_given_has_no_fit_check(tmp_path):
    # a span whose damping is given (or the catalog's value: the conveyor's AT10) is not fitted
    obj = json.loads(ok(run("simulate", "drive", "conveyor", "--json")).stdout)
    assert "damping_fit" not in {c["key"] for c in obj["checks"]}
    text = (DRIVES / "conveyor.toml").read_text().replace("BRECO-AT10", "BRECO-T20")
    assert text.count('width = "25 mm"\n') == 2
    path = tmp_path / "t20_damped.toml"
    path.write_text(text.replace('width = "25 mm"\n', 'width = "25 mm"\ndamping = "40 N*s/m"\n'))
    obj = json.loads(ok(run("simulate", "drive", str(path), "--json")).stdout)
    assert "damping_fit" not in {c["key"] for c in obj["checks"]}
    # the conveyor's 10B-1 strands: no allowable dynamic load published here, fatigue unverified
    assert [w for w in obj["warnings"] if "chain strand vs fatigue UNVERIFIED" not in w] == []
