"""SimResult: time series of every state and output with names and units, summaries over a
steady window, how the run was solved, and CSV export."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Summary:
    """Statistics of one signal over a window: amplitude is half the peak-to-peak."""

    mean: float
    amplitude: float
    rms: float
    min: float
    max: float


@dataclass
class SimResult:
    """Signals (name -> array over ``t``) with their SI units, and the solve information.

    ``states`` is the state matrix (one column per sample, rows as the network's
    ``state_names``). ``errors`` holds an error estimate per speed signal, in that signal's
    unit (:func:`beltcalc.sim.core.estimate_error`); ``error_estimate`` is the one of
    ``error_signal`` (unit ``error_unit``), the largest relative to its scale
    (``error_relative`` of ``error_scale``: the largest speed of that unit over the run).
    None where no estimate was made. ``warnings`` are for the user (stderr, JSON).
    """

    t: np.ndarray
    signals: dict[str, np.ndarray]
    units: dict[str, str]
    method: str
    reason: str
    wall_time: float
    steps: int
    rhs_calls: int
    states: np.ndarray | None = None
    error_estimate: float | None = None
    error_reference: str = ""
    extra: dict = field(default_factory=dict)
    errors: dict = field(default_factory=dict)
    error_signal: str = ""
    error_unit: str = ""
    error_relative: float = 0.0
    error_scale: float = 0.0
    error_row: int = 0
    error_at: float = 0.0
    warnings: list = field(default_factory=list)
    integrals: np.ndarray | None = None
    rigid_integrals: tuple | None = None     # (R, Theta): the rotations re-based out of ``integrals``
    extremes: dict = field(default_factory=dict)
    linear_rows: dict = field(default_factory=dict)
    signal_integrals: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.signals[name]

    def window(self, start: float, end: float | None = None) -> np.ndarray:
        """Boolean mask of the samples with start <= t <= end."""
        end = self.t[-1] if end is None else end
        return (self.t >= start - 1e-12) & (self.t <= end + 1e-12)

    def summary(self, name: str, start: float, end: float | None = None) -> Summary:
        """Mean, amplitude (half peak-to-peak), RMS, min and max of a signal over a window.

        Off the exact solution where the run kept them (``watch`` of
        :func:`beltcalc.sim.core.simulate`): the mean of a signal linear in the state, or of
        a strand force, from the exact integral between the window's first and last
        samples, and min/max over
        ``[start, t_end]``; both then do not depend on the samples. Otherwise, and for the
        RMS, from the samples (the mean by the trapezoid rule)."""
        mask = self.window(start, end)
        y = self.signals[name][mask]
        if y.size == 0:
            raise ValueError(f"no samples in the window {start:g}..{end} s")
        lo, hi = float(y.min()), float(y.max())
        idx = np.nonzero(mask)[0]
        a, b = idx[0], idx[-1]
        # sampled: the trapezoid rule over the window (O(dt^2); the plain mean of the samples
        # is O(dt) off the integral)
        mean = float(np.trapezoid(y, self.t[idx]) / (self.t[b] - self.t[a])) if b > a else float(y[0])
        if self.integrals is not None and name in self.linear_rows and b > a:
            row = self.linear_rows[name]
            total = float(row @ (self.integrals[:, b] - self.integrals[:, a]))
            if self.rigid_integrals is not None:        # the rotations the run took out of the angles
                R, theta = self.rigid_integrals
                turn = R @ row
                # a torque or a force does not change under a rigid rotation: its row's product
                # with R is zero, and rounding of R (geared rotations) must not make it one of
                # eps x 1e6 N m/rad x 1e3 rad s (3e-8 N m on the roller table's shaft torques)
                turn[np.abs(turn) <= 64 * EPS * (np.abs(R) @ np.abs(row))] = 0.0
                total += float(turn @ (theta[:, b] - theta[:, a]))
            mean = total / (self.t[b] - self.t[a])
        elif name in self.signal_integrals and b > a:
            cum = self.signal_integrals[name]
            mean = float((cum[b] - cum[a]) / (self.t[b] - self.t[a]))
        if (end is None or end >= self.t[-1]) and (name, float(start)) in self.extremes:
            lo, hi = self.extremes[(name, float(start))]
        mean = min(max(mean, lo), hi)    # a mean lies within the extremes (rounding can put it outside)
        return Summary(mean, 0.5 * (hi - lo), float(np.sqrt(np.mean(y * y))), lo, hi)

    def settle_time(self, name: str, target: float, band: float, start: float = 0.0,
                    end: float | None = None) -> float | None:
        """The first time >= ``start`` after which ``|signal - target| <= band`` holds up to
        ``end`` [s]; None if it never settles inside the window."""
        mask = self.window(start, end)
        t, y = self.t[mask], self.signals[name][mask]
        outside = np.nonzero(np.abs(y - target) > band)[0]
        if outside.size == 0:
            return float(t[0]) if t.size else None
        last = outside[-1]
        return None if last + 1 >= t.size else float(t[last + 1])

    def to_pandas(self):
        """The signals as a :class:`pandas.DataFrame` indexed by time ``t`` [s], one column per
        signal in SI; ``df.attrs["units"]`` maps each column to its unit and
        ``df.attrs["method"]`` says how the run was solved. Needs pandas (``pip install
        "beltcalc[data]"``)."""
        try:
            import pandas as pd
        except ImportError:
            from beltcalc.errors import InputError

            raise InputError('SimResult.to_pandas needs pandas: pip install "beltcalc[data]"') from None
        df = pd.DataFrame({name: np.asarray(v) for name, v in self.signals.items()},
                          index=pd.Index(self.t, name="t"))
        df.attrs["units"] = dict(self.units)
        df.attrs["method"] = self.reason or self.method
        df.attrs["error_estimate"] = {"value": self.error_estimate, "unit": self.error_unit,
                                      "signal": self.error_signal}
        return df

    def plot(self, signals: list[str] | None = None, path=None, window: float | None = None):
        """A figure of signals over time: one panel per unit, one line per signal, in SI.

        Needs matplotlib (``pip install "beltcalc[plot]"``), imported here on its ``Agg``
        backend: no display is needed (:mod:`beltcalc.plots`).

        Parameters
        ----------
        signals : list of str, optional
            The signals to draw; default every node speed (``omega_NODE`` [rad/s],
            ``v_NODE`` [m/s]).
        path : str or Path, optional
            Also write the figure there: PNG, PDF or SVG, as the suffix names
            (:func:`beltcalc.plots.save_figure`). The figure is made outside pyplot: it
            shows in a notebook by being the cell's value, and no backend is switched.
        window : float, optional
            The start of a steady window [s], shaded up to the end of the run.

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import beltcalc
        >>> r = beltcalc.simulate(beltcalc.load_drive("minimal"))
        >>> fig = r.plot(["omega_rotor", "omega_pulley2", "M_motor"], window=2.0)
        >>> [ax.get_ylabel() for ax in fig.axes]
        ['[rad/s]', '[N m]']
        >>> [line.get_label() for line in fig.axes[0].get_lines()]
        ['omega_rotor', 'omega_pulley2']
        >>> [line.get_label() for line in r.plot().axes[0].get_lines()]       # every node's speed
        ['omega_rotor', 'omega_pulley1', 'omega_pulley2']
        """
        from beltcalc.errors import UnknownNameError, did_you_mean
        from beltcalc.plots import save_figure, signals_figure

        if signals is None:
            signals = [n for n in self.signals if (n.startswith("omega_") and self.units[n] == "rad/s")
                       or (n.startswith("v_") and self.units[n] == "m/s")]
        for name in signals:
            if name not in self.signals:
                raise UnknownNameError(f"no signal {name!r} in this result; {did_you_mean(name, self.signals)}",
                                       param="signals")
        fig = signals_figure(self, list(signals), window)
        if path is not None:
            save_figure(fig, path)
        return fig

    def csv_text(self, names: list[str] | None = None) -> str:
        """CSV with the units in the header (``t_s``, ``omega_3_rad_per_s``, ...)."""
        names = names or list(self.signals)
        header = ["t_s"] + [f"{n}_{unit_tag(self.units[n])}" for n in names]
        data = np.column_stack([self.t] + [self.signals[n] for n in names])
        lines = [",".join(header)]
        lines += [",".join(f"{v:.10g}" for v in row) for row in data]
        return "\n".join(lines) + "\n"


def unit_tag(unit: str) -> str:
    """'rad/s' -> 'rad_per_s', 'N m' -> 'N_m', 'rad/s^2' -> 'rad_per_s2'."""
    return unit.replace("/", "_per_").replace(" ", "_").replace("*", "_").replace("^", "")
