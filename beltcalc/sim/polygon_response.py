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
with every strand taut); where its speed is set by no balance of its own (a prescribed node), the
balance turning as a rigid body at the given speed (:func:`balanced_force`); else the strand's
pretension. The sum of the harmonics' amplitudes bounds the ripple's half peak-to-peak from above.

Validity: the solve holds the strand's lever arms and stiffness at their means; over a tooth period
they swing by about 1 - cos(pi / z) of themselves (2.2 % at 15 teeth), a time-periodic term it
leaves out. Against the nonlinear run of one strand in steady state (tests/test_polygon_response.py)
the first harmonic agrees to 0.14 %, the others to about 1 - cos(pi / z) of the first's amplitude.
A plain chain strand keeps the network's pitch-radius spring; its excitation is the polygon's on
the mean radii (their difference, 0.5 % at 19 teeth, is the plain model's own).

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
    if name not in getattr(drive, "lengths", {}):
        raise InputError(f"{name} is not a chain strand (a belt span or another strand: a belt wraps its pulleys "
                         "on their pitch circles, with no polygon action); name a [[chain_strand]]", param="polygon")
    teeth = getattr(drive, "teeth", {})
    if s.j is None or s.i not in teeth or s.j not in teeth:
        raise InputError(f"strand {name} does not run between two toothed nodes (give its nodes teeth): no polygon "
                         "action", param="polygon")
    z_i, z_j = teeth[s.i], teeth[s.j]
    pitch = 2 * s.r_i * math.sin(math.pi / z_i)
    other = 2 * s.r_j * math.sin(math.pi / z_j)
    if abs(other - pitch) > 1e-6 * pitch:
        raise InputError(f"strand {name}: the pitch radii of {s.i} ({z_i} teeth) and {s.j} ({z_j} teeth) give two "
                         f"pitches, {pitch * 1e3:.6g} mm and {other * 1e3:.6g} mm (give both nodes the strand's chain "
                         "instead of a pitch diameter): no polygon geometry", param="polygon")
    length = drive.lengths[name]
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


def balanced_force(net, strand, speed: float, A: np.ndarray, b0: np.ndarray) -> tuple[float, str]:
    """(the strand's mean force [N], where it comes from): the static balance of the drive's
    linear part (every strand taut) under its constant inputs ``b0``. Where the drive's speed is
    set by no balance of its own (a prescribed node, no motor: :func:`~beltcalc.sim.frequency.free_speed`),
    the balance turning as a rigid body with sprocket ``i`` at ``speed`` [rad/s] (a viscous
    load's torque then counts); where the constant torques do not balance, the pretension.
    The force is the strand's own stamped spring's, F_0 + c g x + b g x' (the pretensions of
    polygon strands, which their nonlinear part carries, added to ``b0``)."""
    from beltcalc.sim.elements.polygon import polygon_strands
    from beltcalc.sim.frequency import free_speed, mean_state

    n = net.n
    b0 = b0.copy()
    held = np.array([0.0 if c in net.fixed else 1.0 / net.mass[c] for c in range(n)])
    for p in polygon_strands(net):       # their pretension is in their nonlinear part, not in B
        b0[n:2 * n] -= held * p.deflection(net) * p.preload
    row = strand.deflection(net) if hasattr(strand, "deflection") else None
    if row is None:                      # a plain strand: its pitch radii
        row = strand.r_i * net.node_row(strand.i) - strand.r_j * net.node_row(strand.j)
    try:
        if not free_speed(A):
            x_bar = mean_state(A, b0)
            return strand.preload + strand.stiffness * float(row @ x_bar[:n]), "the static balance, every strand taut"
        z = rotation(net, strand.i, speed)
        cols = np.r_[0:n, 2 * n:net.size]             # the angles and extra states; the speeds are z
        v = np.zeros(net.size)
        v[:n] = z
        rhs = v - b0 - A[:, n:2 * n] @ z
        a = np.linalg.lstsq(A[:, cols], rhs, rcond=None)[0]
        scale = max(float(np.abs(b0).max(initial=0.0)), float(np.abs(A[:, n:2 * n] @ z).max(initial=0.0)), 1e-300)
        if np.abs(A[:, cols] @ a - rhs).max() > 1e-8 * scale:
            raise InputError("the constant torques do not balance", param="drive")
        force = strand.preload + strand.stiffness * float(row @ a[:n]) + strand.damping * float(row @ z)
        return force, "the static balance turning at --speed, every strand taut"
    except (InputError, np.linalg.LinAlgError):
        return strand.preload, "the pretension (the drive's constant torques do not balance)"


def rotation(net, node: str, speed: float) -> np.ndarray:
    """The rigid-body motion over the coordinates [rad/s] (no coupling or taut strand strained)
    that turns ``node`` at ``speed``: the least-norm one in the null space of M^-1/2 K M^-1/2
    (as :func:`beltcalc.sim.frequency_report.speed_ratio` finds it). Refused where none turns it."""
    s = 1.0 / np.sqrt(net.mass)
    w2, V = np.linalg.eigh(net.K * s[:, None] * s[None, :])
    floor = 1e-9 * max(1.0, float(np.max(np.abs(w2)))) if w2.size else 0.0
    N = s[:, None] * V[:, np.abs(w2) <= floor]
    a = net.node_row(node) @ N
    if not float(a @ a) > 0:
        raise InputError(f"node {node!r} turns in no rigid-body motion of the drive", param="speed")
    return N @ (a * (speed / float(a @ a)))


def polygon_response(drive, name: str, speed: float, harmonics: int = 3, outputs: list[str] | None = None,
                     mean_force: float | None = None) -> PolygonResponse:
    """The :class:`PolygonResponse` of strand ``name`` with its ``from`` sprocket at ``speed``
    [rad/s], harmonics 1..``harmonics``, for ``outputs`` (default: every node's speed and the
    strand's force ``F_<name>``); ``mean_force`` [N] instead of the static balance's."""
    from beltcalc.sim.frequency import output_row, solve_jw

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
        own = next(s for s in net.tension_strands if s.name == name)     # the strand the network stamps
        mean_force, origin = balanced_force(net, own, speed, A, B[:, 0])
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
