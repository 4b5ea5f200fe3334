"""Writes docs/equations.md: every formula of beltcalc, by the source it comes from.

A docstring cites its source by one key (STYLE.md, "Citation keys"): ``[W21 eq. 12]``,
``[C04 eq. 3.22, 3.27]``, ``[RP eq. 8-11]``, ``[Shigley table 17-23]``, ``[M16 Fig. 5]``, or
``[BRECO]`` for a document as a whole. :data:`SOURCES` holds every key and its long form;
a module that cites a key writes the long form once, in its docstring's header, on an
unindented line ``[KEY] long form...`` (a definition, not a citation).

This reads the module, class and function docstrings of ``beltcalc/**/*.py`` with ``ast``
(nothing is imported) and writes, per source, the equations cited, where (the dotted name)
and the first paragraph of the citing docstring::

    python docs/_ext/equations.py            # writes docs/equations.md
    python docs/_ext/equations.py --check    # exit 1, with a diff, when the page is stale

``tests/test_equations_doc.py`` keeps the page equal to this script's output and every key
in the code a key of :data:`SOURCES`.
"""

from __future__ import annotations

import argparse
import ast
import difflib
import re
import sys
import unicodedata
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "beltcalc"
PAGE = ROOT / "docs" / "equations.md"


@dataclass(frozen=True)
class Source:
    key: str
    group: str
    long: str


#: Every citation key, in the page's order, with its long form (authors, title, year).
SOURCES: dict[str, Source] = {s.key: s for s in (
    Source("W21", "Papers the models come from",
           'D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the Power '
           'Consumption of the Automatic Device for Belt Perforation Based on the Dynamic Model", '
           'Energies 14 (2021) 317'),
    Source("M16", "Papers the models come from",
           'D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness '
           'Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016)'),
    Source("RP", "Papers the models come from",
           'A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller table unit '
           'with rotation of rollers transmitted by chain transmission"'),
    Source("C04", "Textbooks",
           "R. Crowder, Electric Drives and Electromechanical Systems, Newnes (2006)"),
    Source("Miner45", "Papers the models come from",
           'M. A. Miner, "Cumulative damage in fatigue", J. Appl. Mech. 12 (1945) A159-A164'),
    Source("Shigley", "Textbooks",
           "R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed., McGraw-Hill (2011)"),
    Source("B56", "Textbooks", "R. C. Binder, Mechanics of the Roller Chain Drive, Prentice-Hall (1956)"),
    Source("DH56", "Textbooks", "J. P. Den Hartog, Mechanical Vibrations, 4th ed., McGraw-Hill (1956)"),
    Source("F88", "Textbooks",
           "A. F. Filippov, Differential Equations with Discontinuous Righthand Sides, Kluwer (1988)"),
    Source("U96", "Textbooks",
           "F. E. Udwadia, R. E. Kalaba, Analytical Dynamics: A New Approach, Cambridge University Press (1996)"),
    Source("AM08", "Textbooks",
           "K. J. Astrom, R. M. Murray, Feedback Systems, Princeton University Press (2008)"),
    Source("OEM99", "Papers the models come from",
           'M. Otter, H. Elmqvist, S. E. Mattsson, "Hybrid modeling in Modelica based on the synchronous data '
           'flow principle", Proc. IEEE CACSD (1999) 151-157'),
    Source("HW96", "Textbooks",
           "E. Hairer, G. Wanner, Solving Ordinary Differential Equations II: Stiff and Differential-Algebraic "
           "Problems, 2nd ed., Springer (1996)"),
    Source("SS90", "Papers the models come from",
           'N. C. Singer, W. P. Seering, "Preshaping command inputs to reduce system vibration", '
           'J. Dyn. Sys., Meas., Control 112 (1990) 76-82'),
    Source("SSS94", "Papers the models come from",
           'W. Singhose, W. Seering, N. Singer, "Residual vibration reduction using vector diagrams to '
           'generate shaped inputs", J. Mech. Design 116 (1994) 654-659'),
    Source("BM08", "Textbooks",
           "L. Biagiotti, C. Melchiorri, Trajectory Planning for Automatic Machines and Robots, Springer (2008)"),
    Source("ISO 606", "Standards",
           "ISO 606:2004, Short-pitch transmission precision roller and bush chains, attachments and "
           "associated chain sprockets"),
    Source("ISO 10823", "Standards", "ISO 10823:2004, Guidance on the selection of roller chain drives"),
    Source("ASTM E1049", "Standards",
           "ASTM E1049-85 (reapproved 2017), Standard Practices for Cycle Counting in Fatigue Analysis"),
    Source("FKM12", "Standards",
           "FKM Guideline, Analytical Strength Assessment of Components, 6th ed., VDMA (2012)"),
    Source("VDI 2230", "Standards",
           "VDI 2230 Part 1 (2015), Systematic calculation of highly stressed bolted joints"),
    Source("BRECO", "Makers' catalogs and manuals",
           "BRECO/BRECOFLEX timing-belt design pages (belt-pilot.com, id=1702)"),
    Source("BRECOflex23", "Makers' catalogs and manuals",
           'BRECOflex CO., "Timing Belt Repeatability for Linear Drives", blog, 21 April 2023 '
           '(brecoflex.com/blog/timing-belt-repeatability-for-linear-drives)'),
    Source("Elatech", "Makers' catalogs and manuals",
           "Elatech timing-belt catalogue (Goodyear Elatech PT belt division)"),
    Source("Tsubaki belts", "Makers' catalogs and manuals",
           "Tsubakimoto Chain, technical data, synchronous belts"),
    Source("Tsubaki chains", "Makers' catalogs and manuals", "U.S. Tsubaki, Roller Chain General Catalog"),
    Source("Tsubaki glossary", "Makers' catalogs and manuals",
           "Tsubakimoto Europe, support / general info / glossary (tsubaki.de)"),
    Source("Tsubaki guide", "Makers' catalogs and manuals",
           "Tsubakimoto Chain Co., The Complete Guide to Chain, sec. 2.2.2 (chain-guide.com)"),
    Source("Gates 508C", "Makers' catalogs and manuals", "Gates 508C sonic tension meter manual"),
    Source("MISUMI", "Makers' catalogs and manuals", "MISUMI timing pulleys, AT5 pitch-diameter table"),
    Source("Yaskawa", "Makers' catalogs and manuals",
           "Yaskawa Sigma-7 AC servo drive product manual (SIEP S800001 28)"),
    Source("Diamond guide", "Makers' catalogs and manuals", "Diamond Chain, technical engineering guide"),
    Source("Diamond FAQ", "Makers' catalogs and manuals", "Diamond Chain, FAQ (diamondchain.com/faq)"),
    Source("McGuire", "Makers' catalogs and manuals", 'McGuire Bearing Company, "Better chain performance"'),
    Source("HKK", "Makers' catalogs and manuals", 'HKK Chain, engineering information, "Installation"'),
    Source("MSL", "Model libraries", "Modelica Association, Modelica Standard Library 4.0.0 (2020)"),
    Source("NR3", "Numerical methods",
           "W. H. Press, S. A. Teukolsky, W. T. Vetterling, B. P. Flannery, Numerical Recipes, 3rd ed., "
           "Cambridge University Press (2007)"),
    Source("MVL03", "Numerical methods",
           'C. Moler and C. Van Loan, "Nineteen dubious ways to compute the exponential of a matrix, '
           'twenty-five years later", SIAM Review 45 (2003) 3-49'),
    Source("AH09", "Numerical methods",
           'A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix '
           'exponential", SIAM J. Matrix Anal. Appl. 31 (2009) 970-989'),
    Source("Hig05", "Numerical methods",
           'N. J. Higham, "The scaling and squaring method for the matrix exponential revisited", '
           'SIAM J. Matrix Anal. Appl. 26 (2005) 1179-1193'),
    Source("Hig08", "Numerical methods",
           "N. J. Higham, Functions of Matrices: Theory and Computation, SIAM (2008)"),
    Source("Osb60", "Numerical methods",
           'E. E. Osborne, "On pre-conditioning of matrices", J. ACM 7 (1960) 338-345'),
    Source("PR69", "Numerical methods",
           'B. N. Parlett, C. Reinsch, "Balancing a matrix for calculation of eigenvalues and eigenvectors", '
           'Numer. Math. 13 (1969) 293-304'),
    Source("JLL14", "Numerical methods",
           'R. James, J. Langou, B. R. Lowery, "On matrix balancing and eigenvector computation", '
           'arXiv:1401.5766 (2014)'),
    Source("VL78", "Numerical methods",
           'C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE Trans. Automat. '
           'Control 23 (1978) 395-404'),
    Source("FR88", "Numerical methods",
           'R. T. Farouki and V. T. Rajan, "Algorithms for polynomials in Bernstein form", Comput. Aided '
           'Geom. Des. 5 (1988) 1-26'),
    Source("Guy65", "Numerical methods",
           'R. J. Guyan, "Reduction of stiffness and mass matrices", AIAA Journal 3 (1965) 380'),
    Source("CGL79", "Numerical methods",
           'T. F. Chan, G. H. Golub, R. J. LeVeque, "Updating formulae and a pairwise algorithm for computing '
           'sample variances", Stanford report STAN-CS-79-773 (1979)'),
    Source("Coh97", "Numerical methods",
           'E. Cohen, "Size-estimation framework with applications to transitive closure and reachability", '
           'J. Comput. System Sci. 55 (1997) 441-453'),
    Source("HSF92", "Numerical methods",
           'S. F. Hummel, E. Schonberg, L. E. Flynn, "Factoring: a method for scheduling parallel loops", '
           'Commun. ACM 35(8) (1992) 90-101'),
    Source("SMDS11", "Numerical methods",
           'J. K. Salmon, M. A. Moraes, R. O. Dror, D. E. Shaw, "Parallel random numbers: as easy as 1, 2, 3", '
           'Proc. SC11 (2011), article 16'),
    Source("Wil27", "Numerical methods",
           'E. B. Wilson, "Probable inference, the law of succession, and statistical inference", '
           'J. Amer. Statist. Assoc. 22 (1927) 209-212'),
)}

_KEYS = "|".join(re.escape(k) for k in sorted(SOURCES, key=len, reverse=True))
#: A citation: a known key, alone or with a locator (``eq. 12``, ``Fig. 8``, ``table 17-23``).
CITATION = re.compile(rf"\[({_KEYS})(?: ([^\[\]\n]+))?\]")
#: A definition in a module's header: the key alone at the start of an unindented line, then
#: its long form (so a module docstring never starts a line with a bare key and a space).
DEFINITION = re.compile(rf"^\[({_KEYS})\] ", re.M)
_ROLE = re.compile(r":(?:func|class|meth|mod|attr|data|obj|exc|math):`~?([^`]+)`")
_LOCATOR_ORDER = ("eq.", "Fig.", "table", "sec.", "Example", "clause", "p.")
_WIDTH = 160                 # the "what" column: the docstring's first paragraph, cut to this


@dataclass(frozen=True)
class Cited:
    key: str
    locator: str             # "" for the document as a whole
    where: str               # dotted name of the module, class or function
    what: str                # the docstring's first paragraph


def modules(package: Path = PACKAGE) -> Iterator[tuple[str, Path]]:
    """(dotted module name, path) of every module of ``package``, sorted by name."""
    for path in sorted(package.rglob("*.py")):
        parts = path.relative_to(package.parent).with_suffix("").parts
        yield ".".join(parts[:-1] if parts[-1] == "__init__" else parts), path


def docstrings(tree: ast.Module, module: str) -> Iterator[tuple[str, str]]:
    """(dotted name, docstring) of a module and every class and function in it, nested ones too."""
    def walk(node: ast.AST, prefix: str) -> Iterator[tuple[str, str]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = f"{prefix}.{child.name}"
                doc = ast.get_docstring(child)
                if doc:
                    yield name, doc
                yield from walk(child, name)
    doc = ast.get_docstring(tree)
    if doc:
        yield module, doc
    yield from walk(tree, module)


def citations(doc: str, module: bool = False) -> Iterator[tuple[str, str]]:
    """(key, locator) of every citation in a docstring; the definitions in a ``module``
    docstring's header are not citations."""
    for line in doc.splitlines():
        m = DEFINITION.match(line) if module else None
        for c in CITATION.finditer(line, m.end() if m else 0):
            yield c[1], c[2] or ""


def summary(doc: str) -> str:
    """The docstring's first paragraph on one line, numpydoc roles as code, cut at :data:`_WIDTH`."""
    text = " ".join(doc.split("\n\n", 1)[0].split())
    text = _ROLE.sub(r"`\1`", text)
    if len(text) > _WIDTH:
        text = text[:_WIDTH].rsplit(" ", 1)[0] + " ..."
    return text


def cited(package: Path = PACKAGE) -> list[Cited]:
    """Every citation in ``package``'s docstrings, once per (key, locator, where)."""
    seen: dict[tuple[str, str, str], Cited] = {}
    for module, path in modules(package):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for where, doc in docstrings(tree, module):
            for key, locator in citations(doc, module=where == module):
                seen.setdefault((key, locator, where), Cited(key, locator, where, summary(doc)))
    return list(seen.values())


def _natural(text: str) -> tuple:
    kind = next((i for i, k in enumerate(_LOCATOR_ORDER) if text.startswith(k)), len(_LOCATOR_ORDER))
    return (kind, [(0, int(t), "") if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", text) if t])


def slug(text: str) -> str:
    """The anchor Python-Markdown's ``toc`` gives a heading (its default ``slugify``)."""
    text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    return re.sub(r"[-\s]+", "-", re.sub(r"[^\w\s-]", "", text).strip().lower())


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def render(rows: list[Cited]) -> str:
    """The page: the sources by group, then a table per cited source."""
    by_key: dict[str, list[Cited]] = {}
    for r in rows:
        by_key.setdefault(r.key, []).append(r)
    out = ["# Equations by source", "",
           "<!-- Generated by docs/_ext/equations.py from the docstrings of beltcalc: do not edit.",
           "     After changing a citation run `python docs/_ext/equations.py`. -->", "",
           "Every formula's docstring cites its source by one key, the same everywhere: "
           "`[W21 eq. 12]` is equation 12 of Wojtkowiak et al. 2021. So one search finds a formula "
           "by its paper's equation (`grep -rn \"W21 eq. 12\" beltcalc`), and this page lists, per "
           "source, each equation cited, where in beltcalc (module, class or function) and what "
           "that docstring is about. A key alone (`[BRECO]`) cites the document as a whole.", ""]
    group = None
    for key, src in SOURCES.items():
        if key not in by_key:
            continue
        if src.group != group:
            group = src.group
            out += ["", f"**{group}**", ""]
        out.append(f"- [{key}](#{slug(key)}): {src.long}.")
    for key, src in SOURCES.items():
        if key not in by_key:
            continue
        out += ["", f"## {key}", "", f"{src.long}.", "", "| equation | where | what |", "|---|---|---|"]
        for r in sorted(by_key[key], key=lambda r: (_natural(r.locator), r.where)):
            cite = f"{key} {r.locator}" if r.locator else key
            out.append(f"| {_cell(cite)} | `{r.where}` | {_cell(r.what)} |")
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 with a diff when the page is stale")
    parser.add_argument("--page", type=Path, default=PAGE, help="the page (default: docs/equations.md)")
    parser.add_argument("--package", type=Path, default=PACKAGE, help="the package read (default: beltcalc)")
    args = parser.parse_args(argv)
    text = render(cited(args.package))
    if not args.check:
        args.page.write_text(text, encoding="utf-8")
        return 0
    old = args.page.read_text(encoding="utf-8") if args.page.exists() else ""
    if old == text:
        return 0
    sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), text.splitlines(True),
                                               str(args.page), "generated"))
    print(f"{args.page} is stale: run python docs/_ext/equations.py", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
