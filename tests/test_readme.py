"""The README: its install-and-run commands (the test command is exactly what CI runs), its
Python examples and docs/python.md's as doctests, its drive file, its links and its length."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def fenced_blocks(text: str) -> list[list[str]]:
    """The lines of every fenced code block (``` ... ```), in order."""
    blocks, current = [], None
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            if current is None:
                current = []
            else:
                blocks.append(current)
                current = None
        elif current is not None:
            current.append(line)
    assert current is None, "unclosed fenced block in README.md"
    return blocks


def readme_blocks() -> list[list[str]]:
    return fenced_blocks((ROOT / "README.md").read_text(encoding="utf-8"))


def ci_last_line() -> str:
    lines = [line for line in (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines() if line.strip()]
    return lines[-1]


def test_fenced_block_parser():
    text = "a\n```\none\n```\nb\n```toml\nx = 1\ny = 2\n```\n"
    assert fenced_blocks(text) == [["one"], ["x = 1", "y = 2"]]


def test_second_block_is_the_ci_command():
    blocks = readme_blocks()
    assert len(blocks) >= 2
    assert blocks[1] == [ci_last_line()]


def test_ci_runs_pytest_on_an_editable_install_with_test_extras():
    last = ci_last_line()
    assert 'pip install -e ".[test,plot]"' in last
    assert last.endswith("&& pytest")


def test_first_block_runs_beltcalc_tension():
    first = readme_blocks()[0]
    assert len(first) == 1
    assert first[0].rstrip().endswith("beltcalc tension")
    assert "pip install ." in first[0]


def test_python_examples_run_as_doctests():
    """The README's Python lines and docs/python.md's run as doctests."""
    import doctest

    attempted = {}
    for page in ("README.md", "docs/python.md"):
        result = doctest.testfile(str(ROOT / page), module_relative=False,
                                  optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
        assert result.failed == 0, page
        attempted[page] = result.attempted
    assert attempted["README.md"] >= 5 and attempted["docs/python.md"] >= 15, attempted


def test_the_readme_drive_file_is_the_shipped_one():
    """The README's complete drive file is catalogs/drives/minimal.toml, as it stands, and it
    runs by name with exit 0 (a newcomer's first try)."""
    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    shipped = (ROOT / "catalogs" / "drives" / "minimal.toml").read_text(encoding="utf-8")
    assert "```toml\n" + shipped.rstrip("\n") + "\n```" in text
    result = CliRunner().invoke(cli, ["simulate", "drive", "minimal"])
    assert result.exit_code == 0, result.output
    assert "Minimal drive: motor, coupling, belt, load" in result.stdout
    assert "warning" not in result.stderr


def test_the_readme_links_every_docs_page():
    """Each docs page is linked from the README, and every relative link of the README and the
    docs pages leads to a file that is there."""
    import re

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    for page in sorted((ROOT / "docs").glob("*.md")):
        assert f"](docs/{page.name})" in text, page.name
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text(encoding="utf-8")):
            if not target.startswith(("http://", "https://")):
                assert (page.parent / target).exists(), f"{page.relative_to(ROOT)}: {target}"


def test_the_readme_stays_short():
    assert len((ROOT / "README.md").read_text(encoding="utf-8").splitlines()) <= 300
