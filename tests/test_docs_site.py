"""The docs site (mkdocs.yml, docs/index.md): it builds with broken links, missing anchors,
pages left out of the nav and unresolved cross-references as errors (``mkdocs build
--strict``), its API pages come from the docstrings, and the strictness is real: a page with
a broken link, anchor or reference fails the same configuration.

Needs the docs extra (mkdocs, mkdocstrings[python]); the test extra names it, so CI builds the
site. Without it the tests are skipped.
"""

from __future__ import annotations

import ast
import html
import importlib.util
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "mkdocs.yml"


def _ext(name: str):
    """A module of docs/_ext (the site's hook and griffe extension), loaded from its file."""
    spec = importlib.util.spec_from_file_location(f"docs_ext_{name}", ROOT / "docs" / "_ext" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _exports() -> dict[str, str]:
    """beltcalc's lazily exported names -> the module each lives in (its ``_WHERE``)."""
    tree = ast.parse((ROOT / "beltcalc" / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", None) == "_WHERE":
            return ast.literal_eval(node.value)
    raise AssertionError("beltcalc/__init__.py has no _WHERE")


def test_the_test_extra_installs_the_docs_extra():
    """CI installs the README's ``.[test,plot]``: the test extra must bring the docs extra, so
    the strict build below runs in CI and is not skipped."""
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    assert "beltcalc[docs]" in extras["test"]
    assert {re.split(r"[\[<>=]", r)[0] for r in extras["docs"]} >= {"mkdocs", "mkdocstrings"}


def test_the_api_page_lists_every_export():
    """docs/api/index.md names each of ``beltcalc.__all__`` by the path it lives at: rendered
    there (``::: path``) or linked to its module's page (``[...][path]``)."""
    text = (ROOT / "docs" / "api" / "index.md").read_text(encoding="utf-8")
    for name, module in _exports().items():
        path = f"{module}.{name}"
        assert f"::: {path}\n" in text or f"][{path}]" in text, path


def test_the_extension_knows_the_api_pages():
    """mkdocs.yml's ``documented`` list (where a docstring's role may link) is the set of modules
    the API pages render (``::: module`` on a page of its own)."""
    config = CONFIG.read_text(encoding="utf-8")
    listed = set(re.findall(r"beltcalc[\w.]*", re.search(r"documented: \[([^\]]*)\]", config)[1]))
    pages = {m for page in (ROOT / "docs" / "api").glob("*.md") if page.name != "index.md"
             for m in re.findall(r"^::: ([\w.]+)$", page.read_text(encoding="utf-8"), flags=re.M)}
    assert listed == pages


PACKAGE = {
    "__init__.py": '''"""Exports :func:`run` and :class:`Thing`."""
_WHERE = {"run": "toy.api", "Thing": "toy.model"}
''',
    "api.py": '''"""The API: :func:`run`, :func:`~toy.api.run`, :func:`_helper`, :class:`pandas.DataFrame`,
:func:`toy.hidden.secret`, :func:`gone`, :math:`x^2`, :class:`Thing`.

.. math::

    x = 1

>>> run()
1
"""
from toy.model import Thing


def run():
    """Run it."""
    return 1


def _helper():
    """A helper."""
''',
    "model.py": '''class Thing:
    """A thing."""
''',
    "hidden.py": '''def secret():
    """Not on the site."""
''',
}


def test_a_role_links_where_its_target_is_on_the_site(tmp_path):
    """The griffe extension on a toy package: a role to a documented object is a link (one to a
    name that is not there too, so the strict build fails on it); a private helper, an object
    of a module without a page and an outside name are code; math and doctest blocks are fenced."""
    griffe = pytest.importorskip("griffe", reason="the docs extra (mkdocstrings[python]) brings griffe")
    (tmp_path / "toy").mkdir()
    for name, text in PACKAGE.items():
        (tmp_path / "toy" / name).write_text(text, encoding="utf-8")
    roles = _ext("rst_roles")
    pkg = griffe.load("toy", search_paths=[str(tmp_path)],
                      extensions=griffe.load_extensions(roles.RstRoles(documented=["toy.api"])))
    assert pkg.docstring.value == "Exports [`run`][toy.api.run] and [`Thing`][toy.model.Thing]."
    doc = pkg["api"].docstring.value
    assert doc.startswith("The API: [`run`][toy.api.run], [`run`][toy.api.run], `_helper`, `pandas.DataFrame`,\n"
                          "`toy.hidden.secret`, [`gone`][toy.api.gone], `x^2`, [`Thing`][toy.model.Thing].")
    assert "```tex\nx = 1\n```" in doc
    assert "```pycon\n>>> run()\n1\n```" in doc


@pytest.mark.parametrize("source, expected", [
    # a list right under a paragraph line gets its blank line; a two-space nested item, four
    ("Rules:\n- one\n  - nested\n  more\n- two\n", "Rules:\n\n- one\n    - nested\n    more\n- two\n"),
    # only "1." starts an ordered list under a paragraph (GitHub): "2." continues the paragraph
    ("see eq.\n2. the rest\n", "see eq.\n2. the rest\n"),
    # a paragraph after a blank line ends the list; a fenced block inside an item moves with it
    ("- a\n\ntext\n  - b\n", "- a\n\ntext\n  - b\n"),
    ("- a\n  ```\n  x = 1\n  ```\n", "- a\n    ```\n    x = 1\n    ```\n"),
])
def test_lists_read_as_github_reads_them(source, expected):
    pytest.importorskip("mkdocs", reason="the docs extra (mkdocs) runs the hook")
    github_lists = _ext("github_lists").github_lists
    assert "\n".join(github_lists(source.splitlines())) + "\n" == expected


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site, built the way a user builds it (``mkdocs build --strict``), in a temporary
    folder."""
    pytest.importorskip("mkdocs", reason="the docs extra (mkdocs) builds the site")
    pytest.importorskip("mkdocstrings", reason="the docs extra (mkdocstrings[python]) renders the API")
    out = tmp_path_factory.mktemp("site")
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(CONFIG), "-d", str(out)],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "WARNING" not in run.stderr, run.stderr
    return out


def test_every_page_is_on_the_site(site):
    for page in sorted((ROOT / "docs").rglob("*.md")):
        rel = page.relative_to(ROOT / "docs").with_suffix("")
        built = site / "index.html" if rel.name == "index" and rel.parent == Path(".") else (
            site / rel.parent / "index.html" if rel.name == "index" else site / rel / "index.html")
        assert built.is_file(), page


def _text(page: Path) -> str:
    """A built page's text outside code blocks."""
    body = re.sub(r"<pre.*?</pre>", "", page.read_text(encoding="utf-8"), flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", "", body))


def test_the_api_pages_come_from_the_docstrings(site):
    """Each exported name has its anchor on the site, and its docstring's first words are
    there; no reStructuredText role or directive is left in the text."""
    import beltcalc

    anchors = "".join(p.read_text(encoding="utf-8") for p in (site / "api").rglob("index.html"))
    text = " ".join(_text(p) for p in (site / "api").rglob("index.html"))
    for name, module in _exports().items():
        assert f'id="{module}.{name}"' in anchors, name
        doc = re.sub(r":\w+:`~?([^`]+)`", lambda m: m[1].rsplit(".", 1)[-1] if "~" in m[0] else m[1],
                     getattr(beltcalc, name).__doc__)
        first = " ".join(doc.split()[:4]).replace("`", "")
        assert first in " ".join(text.split()), (name, first)
    assert not re.search(r":(func|class|meth|attr|data|mod|math):`|\.\. math::", text)


def test_a_role_links_to_the_documented_object(site):
    """``:func:`simulate``` in sim/core.py's module docstring is a link to its anchor."""
    page = (site / "api" / "core" / "index.html").read_text(encoding="utf-8")
    assert re.search(r'<a [^>]*href="#beltcalc\.sim\.core\.simulate"', page)


BROKEN = {
    "a page that is not there": "[the missing page](missing.md)",
    "an anchor that is not there": "[a heading](other.md#no-such-heading)",
    "an anchor on the page itself": "[a heading](#no-such-heading)",
    "a reference to no object": "[`gone`][beltcalc.sim.core.gone]",
}


@pytest.mark.parametrize("link", list(BROKEN.values()), ids=list(BROKEN))
def test_a_broken_link_fails_the_build(tmp_path, link):
    """The site's own configuration (strict, its validation settings, its hooks and plugins),
    on a copy with two small pages: fine as they are, aborted with one broken link."""
    pytest.importorskip("mkdocs", reason="the docs extra (mkdocs) builds the site")
    pytest.importorskip("mkdocstrings", reason="the docs extra (mkdocstrings[python]) renders the API")
    from mkdocs.commands.build import build
    from mkdocs.config import load_config
    from mkdocs.exceptions import Abort

    def build_with(extra: str) -> None:
        docs = tmp_path / "docs"
        docs.mkdir(exist_ok=True)
        (docs / "index.md").write_text(f"# Home\n\n- a list\n  - nested\n\n[other](other.md#a-heading)\n{extra}\n",
                                       encoding="utf-8")
        (docs / "other.md").write_text("# Other\n\n## A heading\n\ntext\n", encoding="utf-8")
        config = load_config(str(CONFIG), docs_dir=str(docs), site_dir=str(tmp_path / "site"),
                             nav=[{"Home": "index.md"}, {"Other": "other.md"}], strict=True)
        build(config)

    build_with("")
    assert (tmp_path / "site" / "index.html").is_file()
    with pytest.raises(Abort, match="Aborted with 1 warnings in strict mode"):
        build_with(link)
