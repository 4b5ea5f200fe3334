"""An mkdocs hook for the docs site (mkdocs.yml): lists read as GitHub reads them.

The pages are written for GitHub, whose Markdown (CommonMark) nests a list item indented to
its parent's text (two spaces under ``- ``) and lets a list start right under a paragraph
line. Python-Markdown, which mkdocs and mkdocstrings use, nests only at four spaces and
wants a blank line first, so such a list would render flat or as one paragraph. This hook
adds a Markdown preprocessor, to the pages and (through the shared extension list) to the
docstrings mkdocstrings renders, that doubles the indentation of the lines inside a list
and puts a blank line before a list that follows a paragraph line. The files stay as they
are.
"""

from __future__ import annotations

import re

from markdown import Extension, Markdown
from markdown.preprocessors import Preprocessor
from mkdocs.plugins import event_priority

ITEM = re.compile(r"^(\s*)([-*+]|\d+[.)])\s+\S")
FENCE = re.compile(r"^\s*(```|~~~)")


def github_lists(lines: list[str]) -> list[str]:
    """The lines with GitHub's list rules in Python-Markdown's terms (see the module)."""
    out: list[str] = []
    in_list = False
    blank = True
    fence_shift: int | None = None          # inside a fenced block: the spaces its fence gained
    for line in lines:
        if fence_shift is not None:
            out.append(" " * fence_shift + line if line.strip() else line)
            if FENCE.match(line):
                fence_shift = None
            continue
        item = ITEM.match(line)
        indent = len(line) - len(line.lstrip())
        if not line.strip():
            out.append(line)
            blank = True
            continue
        if item and indent == 0:
            # a top-level item right under a paragraph line (GitHub: only "1." starts an
            # ordered list there)
            starts = item[2][0] in "-*+" or item[2][:-1] == "1"
            if not in_list and out and out[-1].strip() and starts and not out[-1].lstrip().startswith(("|", "#")):
                out.append("")
            in_list = in_list or starts
        elif indent == 0 and blank:            # a paragraph after a blank line ends the list
            in_list = False
        shift = indent if in_list and indent > 0 else 0
        if FENCE.match(line):
            fence_shift = shift
        out.append(" " * shift + line)
        blank = False
    return out


class _GithubLists(Preprocessor):
    def run(self, lines: list[str]) -> list[str]:
        return github_lists(lines)


class GithubListsExtension(Extension):
    """The Python-Markdown extension: runs before the fenced-code and list processors."""

    def extendMarkdown(self, md: Markdown) -> None:      # noqa: N802 (Python-Markdown's name)
        md.preprocessors.register(_GithubLists(md), "github_lists", 40)


@event_priority(100)          # before mkdocstrings reads the extension list
def on_config(config, **kwargs):
    config.markdown_extensions.append(GithubListsExtension())
    return config
