"""docs/equations.md and the citation keys (issue 29, step 8; STYLE.md, "Citation keys").

Every formula's docstring cites its source by one key, the same everywhere (``[W21 eq. 12]``,
``[M16 eq. 2]``, ``[RP eq. 8-11]``, ``[C04 eq. 3.22]``, ``[Shigley eq. 17-32]``), so one grep
finds a formula by its paper's equation. ``docs/_ext/equations.py`` writes the page from the
docstrings; these tests keep the page equal to its output, every key a known source, the old
spellings (``Eq. (17) of [1]``, ``Rusek & Popenda, eq. 8``) out of the converted modules, and
the equations the issue names where they are.
"""

from __future__ import annotations

import ast
import functools
import importlib.util
import io
import re
import subprocess
import sys
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("docs_ext_equations", ROOT / "docs" / "_ext" / "equations.py")
eq = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = eq              # its dataclasses look their module up
_spec.loader.exec_module(eq)

# Modules that may still hold the old spellings: none since the reshaping (switching and the
# linear algebra were the last); a name is a module or a package.
NOT_YET_CONVERTED: frozenset[str] = frozenset()


def _converted(path: Path) -> bool:
    rel = path.relative_to(ROOT).with_suffix("").as_posix()
    return not any(rel == name or rel.startswith(name + "/") for name in NOT_YET_CONVERTED)


#: Old spellings of a citation: an equation, figure, section or table named outside a key, a
#: numbered reference local to its module, or an author's name with a locator.
OLD_SPELLINGS = [
    re.compile(r"\b[Ee]qs?(?:\.\s*\(?|\s*\(|\s+)\d+"),              # eq. 5, Eq. (17), eqs. 3-4, eq (5
    re.compile(r"\b[Ee]q(?!7\b)\d+"),                           # eq5 (``eq7`` is the name of a model)
    re.compile(r"\b[Ee]quations?\s*\(?\d+"),                   # Equation (14)
    re.compile(r"\bFigs?\.\s*\d+"),                            # Fig. 8
    re.compile(r"\bRef\.\s*\["),                               # Ref. [1]
    re.compile(r"(?<![\w\]\)])\[\d+\]"),                       # [1], [1]_: a module's own numbering
    re.compile(r"(?<!DESIGN\.md )\b[Ss]ection \d+"),           # Section 17-5 (DESIGN.md's own are fine)
    re.compile(r"\bTables? \d+"),                              # Table 17-23
    re.compile(r"\b(?:Wojtkowiak|Mamatova|Rusek|Popenda|Crowder|Shigley|Biagiotti)\b[^\n]{0,40}?"
               r"\b(?:eq|Eq|Fig|[Ss]ection|[Tt]able|Example)\b"),   # Rusek & Popenda, eq. 8
]
#: A bracket that reads as a citation (a locator after the key) whatever its key.
CANDIDATE = re.compile(r"\[([^\[\]\n]+?) (?:eq\.|Fig\.|table|sec\.|p\.|Example|clause|note)\s[^\[\]\n]*\]")


def _files() -> list[Path]:
    return [path for _, path in eq.modules()]


@functools.lru_cache(maxsize=None)
def _cited() -> tuple:
    """The generator's rows for beltcalc, read once for the tests here."""
    return tuple(eq.cited())


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


@functools.lru_cache(maxsize=None)
def _texts(path: Path) -> list[tuple[str, str]]:
    """(what, text) of a module's docstrings (doctest lines left out) and of its comments."""
    source = path.read_text(encoding="utf-8")
    module = next(name for name, p in eq.modules() if p == path)
    out = [(name, "\n".join(line for line in doc.splitlines()
                            if not line.lstrip().startswith((">>>", "..."))))
           for name, doc in eq.docstrings(ast.parse(source), module)]
    out += [(f"{_rel(path)}:{tok.start[0]}", tok.string)
            for tok in tokenize.generate_tokens(io.StringIO(source).readline) if tok.type == tokenize.COMMENT]
    return out


def old_spellings(text: str) -> list[str]:
    """The old spellings in ``text``, once its key citations are taken out."""
    bare = eq.CITATION.sub("", text)
    return [m[0] for pattern in OLD_SPELLINGS for m in pattern.finditer(bare)]


# --- the page --------------------------------------------------------------------------------------

def test_the_page_is_the_generators_output():
    page = (ROOT / "docs" / "equations.md").read_text(encoding="utf-8")
    assert page == eq.render(list(_cited())), "docs/equations.md is stale: run python docs/_ext/equations.py"


def test_check_mode_fails_on_a_stale_page_and_passes_on_the_fresh_one(tmp_path, capsys):
    package = tmp_path / "toy"
    package.mkdir()
    (package / "__init__.py").write_text('"""A toy."""\n')
    (package / "axis.py").write_text(
        '"""An axis.\n\nReferences:\n\n[W21] the paper.\n"""\n\n\n'
        'def x(force, k):\n    """Pretension displacement [m].\n\n    [W21 eq. 12].\n    """\n    return force / k\n')
    page, args = tmp_path / "equations.md", ["--package", str(package), "--page", str(tmp_path / "equations.md")]
    assert eq.main(["--check", *args]) == 1                          # no page yet
    assert eq.main(args) == 0 and eq.main(["--check", *args]) == 0   # written, then fresh
    assert "| W21 eq. 12 | `toy.axis.x` | Pretension displacement [m]. |" in page.read_text()
    assert "`toy.axis` |" not in page.read_text()                    # the header's [W21] defines, not cites
    page.write_text(page.read_text().replace("W21 eq. 12", "W21 eq. 13"))
    capsys.readouterr()
    assert eq.main(["--check", *args]) == 1
    out = capsys.readouterr()
    assert "-| W21 eq. 13 |" in out.out and "+| W21 eq. 12 |" in out.out and "stale" in out.err


def test_the_script_runs_as_the_docs_say():
    run = subprocess.run([sys.executable, "docs/_ext/equations.py", "--check"], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr


def test_the_page_is_in_the_site_and_linked_from_its_index():
    assert re.search(r"^\s*- [^:\n]+: equations\.md$", (ROOT / "mkdocs.yml").read_text(encoding="utf-8"), re.M)
    assert "(equations.md)" in (ROOT / "docs" / "index.md").read_text(encoding="utf-8")


# --- the keys ---------------------------------------------------------------------------------------

def test_every_key_in_the_code_is_a_known_source():
    unknown = {(name, m[1]) for path in _files() for name, text in _texts(path)
               for m in CANDIDATE.finditer(text) if m[1] not in eq.SOURCES}
    assert not unknown, f"add these keys to SOURCES in docs/_ext/equations.py (or fix them): {sorted(unknown)}"


def test_every_known_source_is_cited():
    assert set(eq.SOURCES) == {c.key for c in _cited()}


def test_a_citation_is_on_one_line():
    """``grep "W21 eq. 12"`` finds only a citation that is not wrapped."""
    keys = "|".join(re.escape(k) for k in eq.SOURCES)
    wrapped = re.compile(rf"\[(?:{keys})(?:\s*\n|[^\[\]\n]*\n[^\[\]]*\])")
    broken = [(name, m[0]) for path in _files() for name, text in _texts(path) for m in wrapped.finditer(text)]
    assert not broken


def test_no_citation_touches_another_bracket():
    """Markdown (the API pages) reads ``[m] [RP eq. 16]`` as a link to a reference "RP eq. 16"."""
    keys = "|".join(re.escape(k) for k in eq.SOURCES)
    touching = re.compile(rf"\][ \t]*\n?[ \t]*\[(?:{keys})[\] ]|\[(?:{keys})(?: [^\[\]\n]+)?\][ \t]*\n?[ \t]*\[")
    found = [(name, m[0]) for path in _files() for name, text in _texts(path) for m in touching.finditer(text)]
    assert not found


@pytest.mark.parametrize("path", [p for p in _files() if _converted(p)], ids=_rel)
def test_a_module_writes_the_long_form_of_each_key_it_cites(path):
    """Once, in its docstring's header, beginning as SOURCES' long form does."""
    texts = _texts(path)
    keys = {m[1] for _, text in texts for m in eq.CITATION.finditer(text)}
    header = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    defined = {m[1]: " ".join(header[m.end():].split()) for m in eq.DEFINITION.finditer(header)}
    assert keys <= set(defined), f"no [KEY] line in the module docstring for {sorted(keys - set(defined))}"
    for key, text in defined.items():
        assert text.startswith(eq.SOURCES[key].long), (key, text[:120])
    assert len(re.findall(r"^\[[A-Z][^\]\n]*\] ", header, re.M)) == len(defined), \
        "a key defined twice, or an unknown one"


@pytest.mark.parametrize("path", [p for p in _files() if _converted(p)], ids=_rel)
def test_no_old_spelling_is_left(path):
    found = [(name, old) for name, text in _texts(path) for old in old_spellings(text)]
    assert not found


def test_the_not_yet_converted_list_names_modules_that_exist():
    for name in NOT_YET_CONVERTED:
        assert any(not _converted(p) for p in _files() if _rel(p).startswith(name)), name


@pytest.mark.parametrize("text, found", [
    ("Eq. (17) of [1].", ["Eq. (17", "[1]"]),
    ("Rusek & Popenda, eq. 8", ["eq. 8", "Rusek & Popenda, eq"]),
    ("Wojtkowiak et al. 2021, section 3.2 and Fig. 8", ["Fig. 8", "section 3", "Wojtkowiak et al. 2021, section"]),
    ("Shigley Table 17-20's C' region, eqs. 3-4; eq12", ["eqs. 3", "eq12", "Table 17", "Shigley Table"]),
    ("[W21 eq. 12], [RP eq. 8-11], [Shigley table 17-23], [M16 Fig. 5]; DESIGN.md section 2.5; eq7", []),
])
def test_the_old_spelling_check_finds_them(text, found):
    assert old_spellings(text) == found


# --- where the equations are (the issue's examples) -----------------------------------------------------

@pytest.mark.parametrize("citation, where", [
    ("W21 eq. 12", "beltcalc.formulas.belt.pretension_displacement"),
    ("W21 eq. 14", "beltcalc.formulas.belt.teeth_on_span"),
    ("W21 eq. 29", "beltcalc.design.sizing.move_energy"),
    ("M16 eq. 2", "beltcalc.sim.elements.InductionMotor"),
    ("M16 eq. 3-7", "beltcalc.sim.elements.Coupling"),
    ("M16 eq. 2", "beltcalc.sim.frequency.input_column"),
    ("RP eq. 8-11", "beltcalc.sim.network.strands.StrandModes.strand_forces"),
    ("RP eq. 3", "beltcalc.sim.network.assembly.series_stiffness"),
    ("RP eq. 16", "beltcalc.formulas.chain.placement_factor"),
    ("C04 eq. 3.21, 3.22, 3.27", "beltcalc.formulas.drive.BeltAxis.inertia_parts"),
    ("Shigley eq. 17-32", "beltcalc.design.chain_select.rated_power_link_plate"),
    ("Shigley eq. 17-1", "beltcalc.formulas.geometry.belt_pitch_length"),
    ("BM08 eq. 3.25", "beltcalc.formulas.profiles.move_by_time"),
])
def test_the_issues_equations_are_found_where_they_are(citation, where):
    assert citation in {f"{c.key} {c.locator}" for c in _cited() if c.where == where}
    module = where.split(".")
    files = [f for k in range(len(module), 1, -1)
             for f in (ROOT.joinpath(*module[:k]).with_suffix(".py"), ROOT.joinpath(*module[:k], "__init__.py"))]
    assert f"[{citation}]" in next(f for f in files if f.exists()).read_text(encoding="utf-8")
