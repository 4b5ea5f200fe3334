r"""The steady response of a drive to a chain strand's polygon action, without a time run.

With both sprockets at their nominal speeds (omega_j = omega_i r_i / r_j on the mean radii
r = p z / (2 pi)), the strand's polygon action is periodic with the tooth period
2 pi / (z_i omega_i) [ISO 10823 sec. 5]. Linearised about that motion and the strand's mean
force F_bar, it drives the drive's linear part (:meth:`~beltcalc.sim.network.Network.first_order`,
every strand taut) with two generalized forces:

.. math::
    \delta Q(t) = -(c\,e_p + b\,\dot e_p)\,g
                 - \bar F\,\left[(e_{,i} - r_i)\,g_i + (e_{,j} + r_j)\,g_j\right]

the length pulse e_p = e - (r_i phi_i - r_j phi_j) through the strand's spring and damper
(g its mean-radius row), and the swing of its lever arms e_,i = de/dphi_i about the mean
radii under its mean force (g_i, g_j the sprockets' rows): the chain's speed ripple and the
strand force's torque ripple. Each is taken as its Fourier series over one tooth period,
harmonics k = 1..H at k times the tooth frequency. Each harmonic's response follows from
X_k = (j k Omega I - A)^{-1} B_k (:func:`beltcalc.sim.frequency.solve_jw`), an output y = c X_k,
and the strand's own force F_k = (c + j k Omega b)(g . Q_k + E_k).

The mean force is the static balance's where the drive has one (:func:`beltcalc.sim.frequency.mean_state`
with every strand taut), else the strand's pretension. The sum of the harmonics' amplitudes bounds
the ripple's half peak-to-peak from above.

References:

[ISO 10823] ISO 10823:2004, Guidance on the selection of roller chain drives: the polygon
    effect, chain speed between omega R cos(180 deg / z) and omega R.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import InputError, UnknownNameError, did_you_mean, require_positive

SAMPLES = 4096          # samples of one tooth period for the Fourier series


@dataclass(frozen=True)
class PolygonResponse:
    """The steady response to strand ``strand``'s polygon action with its ``from`` sprocket at
    ``speed`` [rad/s]: the tooth frequency [Hz], the mean force used [N] and where it comes
    from, per harmonic its frequency [Hz], the length pulse's complex amplitude [m], and each
    output's complex amplitude (``outputs[name][k]``, in ``units[name]``)."""

    strand: str
    speed: float
    tooth_frequency: float
    mean_force: float
    mean_force_origin: str
    frequencies: list[float]
    pulse: list[complex]
    outputs: dict[str, list[complex]]
    units: dict[str, str]

    def bound(self, name: str) -> float:
        """The sum of output ``name``'s harmonic amplitudes: an upper bound of its ripple."""
        return float(sum(abs(v) for v in self.outputs[name]))


def strand_geometry(drive, name: str):
    """The strand ``name`` of ``drive`` as a :class:`~beltcalc.sim.elements.polygon.PolygonStrand`:
    itself where it carries the polygon action, else built from a chain strand between two
    toothed nodes (the pitch from a node's pitch radius and teeth, p = 2 R sin(pi / z))."""
    from beltcalc.sim.elements.backlash import Contact
    from beltcalc.sim.elements.polygon import PolygonStrand

    net = drive.network
    strands = {s.name: s for s in net.tension_strands if not isinstance(s, Contact)}
    if name not in strands:
        raise UnknownNameError(f"{name!r} is not a strand of this drive; {did_you_mean(name, list(strands))}",
                               param="polygon")
    s = strands[name]
    if isinstance(s, PolygonStrand):
        return s
    teeth = getattr(drive, "teeth", {})
    if s.j is None or s.i not in teeth or s.j not in teeth:
        raise InputError(f"strand {name} does not run between two toothed nodes (give its nodes teeth): no polygon "
                         "action", param="polygon")
    z_i, z_j = teeth[s.i], teeth[s.j]
    pitch = 2 * s.r_i * math.sin(math.pi / z_i)
    length = getattr(drive, "lengths", {}).get(name)
    if length is None:
        raise InputError(f"strand {name} has no free length on record: no polygon geometry", param="polygon")
    return PolygonStrand(name, s.i, s.j, pitch, z_i, z_j, length, s.stiffness, s.damping, s.preload)


def harmonics_of(strand, speed: float, harmonics: int):
    """(tooth frequency [rad/s], E_k, L_i,k, L_j,k for k = 1..``harmonics``): the complex
    amplitudes of the length pulse [m] and of the lever arms' swings e_,i - r_i, e_,j + r_j
    [m] with sprocket ``i`` at ``speed`` [rad/s], from :data:`SAMPLES` samples of one tooth
    period (a signal sum_k Re(X_k e^{j k Omega t}))."""
    r_i, r_j = strand.mean_radii
    omega = strand.z_i * speed                   # the tooth frequency [rad/s]
    t = np.arange(SAMPLES) * (2 * math.pi / omega) / SAMPLES
    phi_i, phi_j = speed * t, speed * r_i / r_j * t
    e, e_i, e_j, *_ = strand.elongation(phi_i, phi_j)
    parts = [e - (r_i * phi_i - r_j * phi_j), e_i - r_i, e_j + r_j]
    coef = [2 * np.fft.rfft(p)[1:harmonics + 1] / SAMPLES for p in parts]
    return omega, coef[0], coef[1], coef[2]


def polygon_response(drive, name: str, speed: float, harmonics: int = 3, outputs: list[str] | None = None,
                     mean_force: float | None = None) -> PolygonResponse:
    """The :class:`PolygonResponse` of strand ``name`` with its ``from`` sprocket at ``speed``
    [rad/s], harmonics 1..``harmonics``, for ``outputs`` (default: every node's speed and the
    strand's force ``F_<name>``); ``mean_force`` [N] instead of the static balance's."""
    from beltcalc.sim.frequency import free_speed, mean_state, output_row, solve_jw

    require_positive("speed", speed, "rad/s")
    if not (isinstance(harmonics, int) and 1 <= harmonics <= 50):
        raise InputError(f"{harmonics!r} harmonics is not allowed; it must be a whole number 1..50",
                         param="harmonics")
    strand = strand_geometry(drive, name)
    net = drive.network
    n = net.n
    breaks = net.breaks(math.inf)
    A, B = net.first_order(None, (max(breaks) if breaks else 0.0) + 1.0)     # the inputs after every break
    if mean_force is None:
        origin = "the static balance, every strand taut"
        try:
            if free_speed(A):
                raise InputError("free", param="drive")
            x_bar = mean_state(A, B[:, 0])
            r_i, r_j = strand.mean_radii
            g = r_i * net.node_row(strand.i) - r_j * net.node_row(strand.j)
            mean_force = strand.preload + strand.stiffness * float(g @ x_bar[:n])
        except (InputError, np.linalg.LinAlgError):
            mean_force, origin = strand.preload, "the pretension (the drive's speed is set by no static balance)"
    else:
        origin = "given"
    omega, E, Li, Lj = harmonics_of(strand, speed, harmonics)
    r_i, r_j = strand.mean_radii
    row_i, row_j = net.node_row(strand.i), net.node_row(strand.j)
    g = r_i * row_i - r_j * row_j
    gain = 1.0 / net.mass
    for c in net.fixed:
        gain[c] = 0.0
    names = outputs or [f"omega_{nd.name}" for nd in net.nodes if nd.name not in net._massless] + [f"F_{name}"]
    lin = net.linear_rows()
    rows = {y: output_row(net, y, lin) for y in names if y != f"F_{name}"}
    out = {y: [] for y in names}
    freqs = []
    for k in range(harmonics):
        w = (k + 1) * omega
        spring = strand.stiffness + 1j * w * strand.damping
        b = np.zeros(net.size, dtype=complex)
        b[n:2 * n] = gain * (-spring * E[k] * g - mean_force * (Li[k] * row_i + Lj[k] * row_j))
        X = solve_jw(A, b[:, None], np.array([w]))[0, :, 0]
        for y in names:
            if y == f"F_{name}":
                out[y].append(complex(spring * (g @ X[:n] + E[k])))
            else:
                row, power, _ = rows[y]
                out[y].append(complex(row @ X * (1j * w) ** power))
        freqs.append(w / (2 * math.pi))
    units = {y: ("N" if y == f"F_{name}" else rows[y][2]) for y in names}
    return PolygonResponse(name, speed, omega / (2 * math.pi), mean_force, origin, freqs, list(E), out, units)
