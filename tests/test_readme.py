"""The README's install-and-run commands: the test command is exactly what CI runs."""

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
    import doctest

    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False,
                              optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    assert result.attempted >= 15
    assert result.failed == 0
