"""A griffe extension for the docs site (mkdocs.yml): the docstrings' reStructuredText
constructs, as numpydoc writes them, rendered by mkdocstrings' Markdown.

- A role ``:func:`name``` (``class``, ``meth``, ``attr``, ``data``, ``mod``, ``obj``,
  ``exc``; a leading ``~`` shows the last part only) becomes a cross-reference
  ``[`name`][full.path]`` where its target lies in the documented API (the modules in the
  ``documented`` option and the names ``beltcalc`` exports), so a target that is not there
  (a renamed or removed name) fails the strict build; a target outside the documented API
  (a private helper, a module without a page) becomes code, ```name```.
- ``:math:`x``` becomes code; a ``.. math::`` directive becomes a fenced block of its TeX.
- A doctest block (``>>>`` lines and their output) outside an ``Examples`` section becomes a
  fenced ``pycon`` block, as Sphinx shows it (the Examples sections griffe renders itself).

Only the rendering changes: the docstrings stay as they are, and pytest's doctests and
``help()`` read them as before.
"""

from __future__ import annotations

import ast
import re
from typing import Any

import griffe

ROLE = re.compile(r":(func|class|meth|attr|data|mod|obj|exc|math):`([^`]+)`")
HEADING_RULE = re.compile(r"^\s*-{3,}\s*$")


class RstRoles(griffe.Extension):
    """Rewrites every docstring of the loaded package once it is loaded (see the module)."""

    def __init__(self, documented: list[str] | None = None) -> None:
        super().__init__()
        self.documented = list(documented or [])

    def on_package(self, *, pkg: griffe.Module, **kwargs: Any) -> None:
        documented = self.documented + [f"{module}.{name}" for name, module in _exports(pkg).items()]
        for obj in _walk(pkg):
            if obj.docstring is not None:
                obj.docstring.value = _markdown(obj.docstring.value, obj, pkg, documented)


def _walk(obj: griffe.Object):
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _walk(member)


def _markdown(text: str, obj: griffe.Object, pkg: griffe.Module, documented: list[str]) -> str:
    text = ROLE.sub(lambda m: _role(m[1], m[2], obj, pkg, documented), text)
    return _blocks(text)


def _role(role: str, target: str, obj: griffe.Object, pkg: griffe.Module, documented: list[str]) -> str:
    if role == "math":
        return f"`{target}`"
    short = target.startswith("~")
    target = target.lstrip("~.")
    shown = target.rsplit(".", 1)[-1] if short else target
    path, found = _resolve(target, obj, pkg)
    if path is None:                                  # outside the package (numpy, pandas): code
        return f"`{shown}`"
    public = not any(part.startswith("_") for part in path.split("."))
    listed = any(path == d or path.startswith(d + ".") for d in documented)
    # a documented target links (and one that is not there fails the strict build); an object
    # without a docstring, which mkdocstrings does not show, and the rest are code
    if public and listed and (found is None or found.has_docstrings):
        return f"[`{shown}`][{path}]"
    return f"`{shown}`"


def _resolve(target: str, obj: griffe.Object, pkg: griffe.Module):
    """(canonical path, object) of ``target`` as seen from ``obj``: a full dotted path, or a
    name looked up in ``obj``, its parents and their imports (the package's lazy exports in
    ``_WHERE`` too). A name not found: the path it would have (object None); one outside the
    package: (None, None)."""
    parts = target.split(".")
    if parts[0] == pkg.name:
        return _follow(pkg, parts[1:])
    scope: griffe.Object | None = obj
    while scope is not None:
        if parts[0] in scope.members:
            return _follow(scope, parts)
        if scope is pkg and parts[0] in _exports(pkg):
            return _follow(pkg, _exports(pkg)[parts[0]].split(".")[1:] + parts)
        scope = scope.parent
    if len(parts) > 1:
        return None, None
    return f"{obj.module.path}.{target}", None


def _follow(scope: griffe.Object, parts: list[str]):
    """Walk ``parts`` down from ``scope``; where a part is not there (an instance attribute set
    outside ``__init__``), the path it would have."""
    for k, part in enumerate(parts):
        try:
            member = scope.members[part]
            scope = member.final_target if member.is_alias else member
        except (KeyError, griffe.AliasResolutionError, griffe.CyclicAliasError):
            return ".".join([scope.path, *parts[k:]]), None
    return scope.path, scope


def _exports(pkg: griffe.Module) -> dict[str, str]:
    where = pkg.members.get("_WHERE")
    if where is None or where.is_alias or where.value is None:
        return {}
    return ast.literal_eval(str(where.value))


def _blocks(text: str) -> str:
    """Fence ``.. math::`` directives and doctest blocks outside an Examples section."""
    lines = text.splitlines()
    out: list[str] = []
    in_examples = False
    i = 0
    while i < len(lines):
        line = lines[i]
        stripped = line.strip()
        if i + 1 < len(lines) and stripped and HEADING_RULE.match(lines[i + 1]):
            in_examples = stripped == "Examples"
        indent = line[: len(line) - len(line.lstrip())]
        if stripped.startswith(".. math::"):
            body = [stripped[len(".. math::"):].strip()]
            i += 1
            while i < len(lines) and (not lines[i].strip() or len(lines[i]) - len(lines[i].lstrip()) > len(indent)):
                body.append(lines[i].strip())
                i += 1
            while body and not body[-1]:
                body.pop()
            while body and not body[0]:
                body.pop(0)
            out += [f"{indent}```tex", *[f"{indent}{b}" if b else "" for b in body], f"{indent}```", ""]
            continue
        if stripped.startswith(">>>") and not in_examples:
            out.append(f"{indent}```pycon")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append(f"{indent}```")
            continue
        out.append(line)
        i += 1
    return "\n".join(out)
