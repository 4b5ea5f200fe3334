"""The ported code keeps its upstream notices (issue 29): ``numerics/expm.py`` and
``numerics/expm_degree.py`` port scipy's ``expm``, ``numerics/balance.py`` LAPACK's ``dgebal``,
``numerics/scalar.py`` scipy's ``brentq`` and bounded/golden searches; scipy's BSD license and
LAPACK's modified BSD license require the copyright notice, the conditions and the disclaimer to
stay with the source. Each names the upstream version it was ported from."""

import re
from importlib import metadata
from pathlib import Path

import pytest

NUMERICS = Path(__file__).resolve().parents[1] / "beltcalc" / "numerics"


def comment_text(path: Path) -> str:
    """The leading comment block of a module, without the ``#`` marks."""
    lines = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[2:] if line.startswith("# ") else "")
    return "\n".join(lines)


def squeeze(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("module", ["expm.py", "expm_degree.py", "scalar.py"])
def test_scipy_ports_carry_scipys_license(module):
    notice = squeeze(comment_text(NUMERICS / module))
    assert re.match(r"Ported from SciPy \d+\.\d+ \(scipy/", notice)
    # the license of the scipy this was ported from and is tested against, as installed
    installed = next(f for f in metadata.files("scipy") if f.name == "LICENSE.txt" and "dist-info" in str(f))
    license_text = squeeze(installed.read_text(encoding="utf-8").split("----")[0])
    assert license_text.startswith("Copyright (c) 2001-2002 Enthought, Inc.")
    assert license_text in notice


def test_the_lapack_port_carries_lapacks_license():
    notice = squeeze(comment_text(NUMERICS / "balance.py"))
    assert re.match(r"Ported from LAPACK \d+\.\d+ \(SRC/dgebal\.f\)", notice)
    for part in ("Copyright (c) 1992-2013 The University of Tennessee", "The University of California Berkeley",
                 "Redistributions of source code must retain the above copyright notice",
                 "THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS"):
        assert part in notice
