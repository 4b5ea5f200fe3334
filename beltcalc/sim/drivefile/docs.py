"""The key tables of ``docs/drive_files.md``, generated from the registry (``ELEMENTS``): one table
per section, between the page's ``<!-- keys: SECTION -->`` and ``<!-- end keys -->`` lines
(each with a blank line to the table, so the comments stay HTML blocks of their own).
``python -m beltcalc.sim.drivefile.docs`` rewrites them in place (from a source checkout);
``check`` (an argument) only says whether the page is up to date (exit 1 if not), as the tests do.

>>> print(key_table("gear"))
| key | unit | required | meaning |
|---|---|---|---|
| `name` | text |  | unique name |
| `between` | names | yes | [node a, node b] |
| `ratio` |  | yes | speed of a / speed of b (phi_b = phi_a / ratio; negative: the pair reverses, as an external gear pair does) |
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from beltcalc.data.schema import Field, Flag, Names, Quantity, Table, Text, Whole
from beltcalc.sim.drivefile.registry import kind_of, sections

PAGE = Path(__file__).resolve().parents[3] / "docs" / "drive_files.md"
_BLOCK = re.compile(r"(<!-- keys: (\w+) -->\n)(.*?)(<!-- end keys -->)", re.S)


#: the docs' unit column of a key that is no quantity, by its field
TYPE_TEXT = {Text: "text", Whole: "int", Flag: "bool", Names: "names"}


def unit_text(spec: Field) -> str:
    """A key's unit as the docs write it: a quantity's SI unit, ``N*m|N`` as ``N*m or N``; a
    table as ``table of [s, N*m or N]``; else its type (``text``, ``int``, ``bool``,
    ``names``).

    >>> unit_text(Table(columns=(Quantity("s"), Quantity("rad/s^2|m/s^2"))))
    'table of [s, rad/s^2 or m/s^2]'
    """
    if isinstance(spec, Table):
        return f"table of [{', '.join(unit_text(c) for c in spec.columns)}]"
    if isinstance(spec, Quantity):
        return spec.unit.replace("|", " or ")
    return TYPE_TEXT[type(spec)]


def required_text(spec: Field) -> str:
    """``yes``, ``with `other``` (needed when another key is given), or nothing."""
    if spec.required:
        return "yes"
    return f"with `{spec.when}`" if spec.when else ""


def key_table(section: str) -> str:
    """The markdown table of ``section``'s keys, in the registry's order."""
    rows = ["| key | unit | required | meaning |", "|---|---|---|---|"]
    rows += [f"| `{key}` | {unit_text(spec)} | {required_text(spec)} | {spec.help} |"
             for key, spec in kind_of(section).keys.items()]
    return "\n".join(rows)


def render(page: str) -> str:
    """``page`` with every key table between its markers generated anew. A section of the
    registry without its table on the page is an error (the page must list every key)."""
    seen = set()

    def table(m: re.Match) -> str:
        if m[2] not in sections():
            raise ValueError(f"the page has a key table for {m[2]!r}, which is no section of drive files")
        seen.add(m[2])
        return f"{m[1]}\n{key_table(m[2])}\n\n{m[4]}"

    out = _BLOCK.sub(table, page)
    missing = [s for s in sections() if s not in seen]
    if missing:
        raise ValueError(f"the page has no key table for {', '.join(missing)} (add '<!-- keys: SECTION -->' and "
                         "'<!-- end keys -->' lines where each belongs)")
    return out


def main(argv: list[str]) -> int:
    """Rewrite the page's key tables (argument ``check``: only say whether they are up to date)."""
    text = PAGE.read_text(encoding="utf-8")
    new = render(text)
    if "check" in argv:
        print(f"{PAGE}: {'up to date' if new == text else 'stale: run python -m beltcalc.sim.drivefile.docs'}")
        return 0 if new == text else 1
    if new != text:
        PAGE.write_text(new, encoding="utf-8")
    print(f"{PAGE}: {'rewritten' if new != text else 'up to date'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
