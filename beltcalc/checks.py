"""The check layer: one :class:`Check` per design rule (value, limit, margin, verdict).

A check is ``value <= limit`` (``kind="max"``) or ``value >= limit`` (``kind="min"``).
Its utilisation is value/limit (max) or limit/value (min): 1 is exactly at the limit,
above 1 fails. A check that cannot be made (a table the catalog lacks, an input not
given) has verdict ``"n/a"`` and says why in ``reason``; it never fails silently.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Check:
    """One design check, SI values. ``rule`` says what is compared and where it comes from."""

    key: str
    name: str
    value: float | None
    limit: float | None
    unit: str
    kind: str = "max"          # "max": value <= limit; "min": value >= limit
    rule: str = ""
    reason: str = ""           # why it is n/a
    signals: tuple[str, ...] = ()   # time signals whose magnitude the limit bounds (a plot draws it there)

    @property
    def utilisation(self) -> float | None:
        """value / limit (max) or limit / value (min); None when n/a.

        >>> Check("t", "tooth shear", 50.0, 100.0, "N").utilisation
        0.5
        >>> Check("z", "teeth", 20.0, 15.0, "1", kind="min").utilisation
        0.75
        """
        if self.value is None or self.limit is None:
            return None
        if self.kind == "max":
            return self.value / self.limit if self.limit > 0 else float("inf")
        return self.limit / self.value if self.value > 0 else float("inf")

    @property
    def margin(self) -> float | None:
        """limit - value (max) or value - limit (min), in ``unit``; None when n/a."""
        if self.value is None or self.limit is None:
            return None
        return self.limit - self.value if self.kind == "max" else self.value - self.limit

    @property
    def verdict(self) -> str:
        """``"pass"``, ``"FAIL"`` or ``"n/a"``.

        >>> Check("t", "tooth shear", 150.0, 100.0, "N").verdict
        'FAIL'
        """
        u = self.utilisation
        if u is None:
            return "n/a"
        return "pass" if u <= 1.0 + 1e-12 else "FAIL"

    def warning(self) -> str:
        """The one-line warning of a failed check (no figure beyond a float printed as ``inf``).

        >>> Check("m", "belt mass", 0.14, 1e-320, "kg").warning()
        'belt mass FAILS: 0.14 kg must be <= 1e-320 kg (utilisation beyond any finite figure; )'
        """
        op = "<=" if self.kind == "max" else ">="
        unit = "" if self.unit in ("", "1") else f" {self.unit}"
        u = self.utilisation
        used = f"utilisation {u:.0%}" if u is not None and math.isfinite(u) else "utilisation beyond any finite figure"
        return (f"{self.name} FAILS: {figure(self.value)}{unit} must be {op} {figure(self.limit)}{unit} "
                f"({used}; {self.rule})")

    def to_dict(self) -> dict:
        """JSON-ready: values ``{"value", "unit"}``, utilisation and margin, verdict, rule
        (never NaN: None with the reason)."""
        return {"key": self.key, "name": self.name,
                "value": {"value": self.value, "unit": self.unit}, "limit": {"value": self.limit, "unit": self.unit},
                "kind": self.kind, "margin": {"value": self.margin, "unit": self.unit},
                "utilisation": {"value": self.utilisation, "unit": "1"}, "verdict": self.verdict,
                "rule": self.rule, **({"reason": self.reason} if self.reason else {})}


def figure(value: float | None, spec: str = ".4g") -> str:
    """``value`` for a sentence: formatted by ``spec``; one beyond a float (or none) in words.

    >>> figure(2688.04), figure(float("inf")), figure(float("nan"))
    ('2688', 'a figure beyond a float', 'no figure')
    """
    if value is None or math.isnan(value):
        return "no figure"
    if math.isinf(value):
        return "a figure beyond a float" if value > 0 else "a figure below any float"
    return format(value, spec)


def failures(checks) -> list[Check]:
    """The checks that fail."""
    return [c for c in checks if c.verdict == "FAIL"]
