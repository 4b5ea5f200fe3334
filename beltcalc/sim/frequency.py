"""The frequency domain of a drive: every pole, mode shapes with the element that holds the
most strain energy, the frequency response H(jw) = C (jw I - A)^-1 B from any input to any
output, the exact periodic steady state under constant and sinusoidal inputs, and Campbell
crossings. The network is linear between strand switches; here strands are taken taut (or
in a stated pattern). SI floats only.

The state matrix is the one the time simulation propagates (:meth:`Network.first_order`):
the same model in both domains. Eigenvalues come from ``numpy.linalg.eig`` of A (LAPACK
``geev``); H(jw) from batched complex solves of (jw I - A) X = B, or, for large drives,
from one Hessenberg reduction of A and a banded solve per frequency: never a loop of dense
inverses. The periodic steady state solves the same systems at each input frequency; the
mean solves A a = -B_0 with A's rigid-body null space split off (a drive that turns
steadily has a zero eigenvalue: its angle grows as Omega t).

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    induction motor's dynamic characteristic.
[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": the chain strands.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from beltcalc.errors import InputError, did_you_mean

SHARE_SHOWN = 0.10    # a mode's elements named with their share of its strain energy: those above 10 %
HESSENBERG_SIZE = 150        # states from which H(jw) uses one Hessenberg reduction


@dataclass(frozen=True)
class Pole:
    """One eigenvalue ``s`` [1/s] of the state matrix. ``kind``: ``"oscillatory"`` (a
    conjugate pair; ``frequency`` the undamped natural frequency |s|/2 pi [Hz],
    ``damped_frequency`` Im s / 2 pi, ``damping_ratio`` -Re s/|s|), ``"real"``
    (``time_constant`` -1/s [s]; negative: unstable) or ``"rigid"`` (s = 0 within rounding:
    the drive turns freely, or a free state)."""

    s: complex
    kind: str
    frequency: float | None = None
    damped_frequency: float | None = None
    damping_ratio: float | None = None
    time_constant: float | None = None


def _floor(lam: np.ndarray) -> float:
    # a rigid-body double eigenvalue 0 is split by rounding to about +-sqrt(eps) |A|
    return 1e-7 * max(1.0, float(np.max(np.abs(lam)))) if lam.size else 0.0


def _classify(s: complex, floor: float) -> Pole:
    s = complex(s)
    if abs(s) <= floor:
        return Pole(s, "rigid")
    if abs(s.imag) > floor:
        wn = abs(s)
        return Pole(s, "oscillatory", wn / (2 * math.pi), abs(s.imag) / (2 * math.pi), -s.real / wn)
    return Pole(s, "real", time_constant=-1.0 / s.real)


def poles(net, taut: tuple[bool, ...] | None = None) -> list[Pole]:
    """Every pole of the drive (strands taut unless ``taut`` says otherwise): rigid-body
    modes, then each oscillatory pair once (positive imaginary part) by frequency, then the
    real poles by time constant, longest first.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0), Inertia("b", 1.0)], [Coupling("c", "a", "b", 8.0, 0.4)])
    >>> [(p.kind, round(p.frequency or 0, 4)) for p in poles(net)]
    [('rigid', 0), ('rigid', 0), ('oscillatory', 0.6366)]
    """
    return poles_of(np.linalg.eigvals(net.state_matrix(taut)))


def poles_of(lam: np.ndarray) -> list[Pole]:
    """:func:`poles` of the eigenvalues ``lam`` of a state matrix (a study's batch computes
    them for a stack of runs at once: :func:`beltcalc.sim.batch.eigenvalues`)."""
    floor = _floor(lam)
    out = [_classify(s, floor) for s in lam if not (s.imag < -floor and abs(s) > floor)]
    rigid = [p for p in out if p.kind == "rigid"]
    osc = sorted((p for p in out if p.kind == "oscillatory"), key=lambda p: p.frequency)
    real = sorted((p for p in out if p.kind == "real"), key=lambda p: -p.time_constant)
    return rigid + osc + real


@dataclass(frozen=True)
class ModeShape:
    """An oscillatory mode: its pole; each node's amplitude relative to the largest and its
    phase against it [deg] (angles and positions alike: a drive with masses mixes rad and
    m); each coupling's and strand's share of the modal strain energy, and the element with
    the largest share."""

    pole: Pole
    amplitude: dict[str, float]
    phase: dict[str, float]
    energy: dict[str, float]
    dominant: str

    def shares(self, above: float = SHARE_SHOWN) -> list[tuple[str, float]]:
        """The elements holding over ``above`` of the mode's strain energy with their shares,
        largest first (the ones to stiffen); where none does, the largest alone."""
        big = sorted(((e, v) for e, v in self.energy.items() if v > above), key=lambda ev: -ev[1])
        return big or [(self.dominant, self.energy[self.dominant])]


def mode_shapes(net, taut: tuple[bool, ...] | None = None) -> list[ModeShape]:
    """The shape of every oscillatory mode (as :func:`poles` orders them), from the
    eigenvectors of A: node angles ``T v_phi``; strain energy of each spring an element
    stamps (a coupling, a carriage belt) ``C |g . v_phi|^2 / 2`` and of a taut strand
    ``c |G . v_phi|^2 / 2``.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0), Inertia("b", 3.0)], [Coupling("c", "a", "b", 8.0, 0.0)])
    >>> m, = mode_shapes(net)
    >>> round(m.amplitude["b"], 6), round(m.phase["b"]), m.dominant
    (0.333333, 180, 'c')
    """
    taut = net.taut if taut is None else tuple(taut)
    A = net.state_matrix(taut)
    lam, vec = np.linalg.eig(A)
    floor = _floor(lam)
    n = net.n
    # every spring an element stamps (couplings, a carriage belt held where it is, ...)
    springs = [(getattr(el, "name", "") or type(el).__name__, C, g) for el in net.elements
               for g, C, _ in el.matrices(net) if C]
    springs += [(s.name, s.stiffness, net._G[k]) for k, (s, on) in enumerate(zip(net.strands, taut)) if on]
    shapes = []
    for k in np.argsort(np.abs(lam)):
        s = lam[k]
        if not (s.imag > floor and abs(s) > floor):
            continue
        phi = vec[:n, k]
        nodes = net.T @ phi
        big = int(np.argmax(np.abs(nodes)))
        ref = nodes[big]
        rel = nodes / ref
        amplitude = {nd.name: float(abs(r)) for nd, r in zip(net.nodes, rel)}
        phase = {nd.name: -((180.0 - float(np.degrees(np.angle(r)))) % 360.0 - 180.0) for nd, r in zip(net.nodes, rel)}
        energies: dict[str, float] = {}
        for name, C, g in springs:
            energies[name] = energies.get(name, 0.0) + 0.5 * C * abs(g @ phi) ** 2
        total = sum(energies.values()) or 1.0
        energy = {name: e / total for name, e in energies.items()}
        dominant = max(energy, key=energy.get) if energy else ""
        shapes.append(ModeShape(_classify(s, floor), amplitude, phase, energy, dominant))
    return sorted(shapes, key=lambda m: m.pole.frequency)


# --- inputs and outputs by name -----------------------------------------------------------------
def input_column(net, name: str) -> np.ndarray:
    """B column of a named input: ``load:<node>`` (a torque [N m], or a force [N] on a
    translating node, acting *with* the motion) or ``supply:<motor>`` (the motor's
    synchronous speed omega_0 [rad/s], [M16 eq. 2]; ``supply`` alone for the one motor)."""
    col = np.zeros(net.size)
    kind, _, what = name.partition(":")
    if kind == "load" and what in net._node:
        net.require_inertia(what, "a load input")
        c, f = net.coord(what)
        col[net.n + c] = f / net.mass[c]
        return col
    if kind == "supply":
        motors = [m for m in net.motors if m.name == what or (not what and len(net.motors) == 1)]
        if motors:
            m = motors[0]
            col[net.state_index[id(m)]] = 2 * m.breakdown_torque * m.supply / m.sync_speed
            return col
    known = [f"load:{nd.name}" for nd in net.nodes if nd.name not in net._massless]
    known += [f"supply:{m.name}" for m in net.motors]
    raise InputError(f"{name!r} is not an input of this drive; {did_you_mean(str(name), known)}", param="input")


def output_row(net, name: str, rows: dict | None = None) -> tuple[np.ndarray, int, str]:
    """(row over the state, power of jw it is multiplied by, SI unit) of a named output:
    ``omega_<node>``/``v_<node>`` (speed), ``accel_<node>`` (jw x speed), ``phi_<node>``/
    ``x_<node>``, ``T_<coupling>``, ``F_<strand>`` (taut), ``M_<motor>``. ``rows``: the
    network's :meth:`~beltcalc.sim.network.Network.linear_rows`, if already at hand."""
    rows = net.linear_rows() if rows is None else rows
    if name in rows:
        units = dict(net.state_names())
        unit = units.get(name) or _unit_of(net, name)
        return rows[name], 0, unit
    if name.startswith("accel_"):
        node = name[6:]
        if node in net._node:
            speed = f"v_{node}" if net.node(node).translation else f"omega_{node}"
            row, _, unit = output_row(net, speed, rows)
            return row, 1, unit + "^2" if unit.endswith("/s") else unit + "/s"
    strands = {f"F_{s.name}": k for k, s in enumerate(net.strands)}
    if name in strands:
        _, force = net.strand_rows()
        return force[strands[name], :net.size].copy(), 0, "N"
    known = list(rows) + [f"accel_{nd.name}" for nd in net.nodes] + list(strands)
    raise InputError(f"{name!r} is not an output of this drive; {did_you_mean(str(name), known)}", param="output")


def _unit_of(net, name: str) -> str:
    if name.startswith("T_"):
        c = next(c for c in net.couplings if c.name == name[2:])
        return "N" if net.node(c.i).translation else "N m"
    kind, _, node = name.partition("_")
    translating = node in net._node and net.node(node).translation
    return {"phi": "rad", "x": "m", "omega": "rad/s", "v": "m/s"}.get(kind, "m" if translating else "rad")


def solve_jw(A: np.ndarray, B: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """X[k] = (j omega_k I - A)^-1 B for every frequency: batched complex solves in blocks,
    or, from :data:`HESSENBERG_SIZE` states, one Hessenberg reduction A = Q H Q^T and a
    banded (one subdiagonal) solve per frequency, O(n^2) each. Shape (len(omega), n, m).
    A frequency exactly on an undamped pole gives infinity.

    >>> X = solve_jw(np.array([[-1.0]]), np.array([[1.0]]), np.array([0.0, 1.0]))
    >>> np.round(X[:, 0, 0], 3).tolist()
    [(1+0j), (0.5-0.5j)]
    """
    omega = np.asarray(omega, dtype=float)
    n, m = B.shape
    out = np.empty((omega.size, n, m), dtype=complex)
    if n < HESSENBERG_SIZE:
        eye = np.eye(n)
        block = max(1, int(4e6 // max(n * n, 1)))
        for a in range(0, omega.size, block):
            w = omega[a:a + block]
            M = 1j * w[:, None, None] * eye[None] - A[None]
            try:
                out[a:a + block] = np.linalg.solve(M, np.broadcast_to(B, (w.size, n, m)))
            except np.linalg.LinAlgError:         # a frequency exactly on an undamped pole: |H| infinite
                for k in range(w.size):
                    try:
                        out[a + k] = np.linalg.solve(M[k], B)
                    except np.linalg.LinAlgError:
                        out[a + k] = complex(math.inf, 0.0)
        return out
    from scipy.linalg import hessenberg, solve_banded

    H, Q = hessenberg(A, calc_q=True)
    QB = Q.T @ B
    ab = np.zeros((n + 1, n), dtype=complex)      # banded storage: n - 1 above, 1 below
    for d in range(-1, n):                        # diagonal d of -H into row (n - 1) - d
        diag = -np.diagonal(H, offset=d) if d >= 0 else -np.diagonal(H, offset=-1)
        if d >= 0:
            ab[n - 1 - d, d:] = diag
        else:
            ab[n, :n - 1] = diag
    base = ab[n - 1].copy()
    for k, w in enumerate(omega):
        ab[n - 1] = base + 1j * w
        try:
            out[k] = Q @ solve_banded((1, n - 1), ab, QB, check_finite=False)
        except np.linalg.LinAlgError:
            out[k] = complex(math.inf, 0.0)
    return out


@dataclass
class Response:
    """H(jw) from each input to each output: ``H[k, i, j]`` at ``omega[k]`` from input j to
    output i, in the output's unit per the input's unit; ``peaks[(output, input)]`` the
    resonance peaks (frequency [Hz], magnitude, Q by the half-power bandwidth)."""

    omega: np.ndarray
    inputs: list[str]
    outputs: list[str]
    units: list[str]
    input_units: list[str]
    H: np.ndarray
    peaks: dict = field(default_factory=dict)

    def magnitude(self, output: str, input: str) -> np.ndarray:
        """|H| of one pair over omega."""
        return np.abs(self.H[:, self.outputs.index(output), self.inputs.index(input)])

    def phase(self, output: str, input: str) -> np.ndarray:
        """Phase of H [deg] of one pair over omega (unwrapped)."""
        return np.degrees(np.unwrap(np.angle(self.H[:, self.outputs.index(output), self.inputs.index(input)])))

    def pairs(self) -> list[tuple[str, str, str]]:
        """(output, input, unit of |H|) of every pair, output by output."""
        return [(y, u, ratio_unit(self.units[i], self.input_units[j]))
                for i, y in enumerate(self.outputs) for j, u in enumerate(self.inputs)]


def ratio_unit(output_unit: str, input_unit: str) -> str:
    """The unit of |H|: the output's per the input's, ``rad/s/(N m)``.

    >>> ratio_unit("rad/s", "N m"), ratio_unit("N m", "N m"), ratio_unit("rad", "N")
    ('rad/s/(N m)', '(N m)/(N m)', 'rad/N')
    """
    top = f"({output_unit})" if " " in output_unit else output_unit
    bottom = f"({input_unit})" if (" " in input_unit or "/" in input_unit) else input_unit
    return f"{top}/{bottom}"


def frequency_response(net, inputs: list[str], outputs: list[str], omega, taut=None) -> Response:
    """H(jw) = C (jw I - A)^-1 B of the named inputs and outputs (:func:`input_column`,
    :func:`output_row`) at the angular frequencies ``omega`` [rad/s], with the resonance
    peaks of each pair refined on the exact H (golden section) and their Q from the
    half-power frequencies (Q = f_0 / (f_2 - f_1)).

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0)], [Coupling("k", "a", None, 100.0, 0.2)])
    >>> r = frequency_response(net, ["load:a"], ["phi_a"], np.linspace(1, 20, 400))
    >>> (f, mag, q), = r.peaks[("phi_a", "load:a")]
    >>> round(f * 2 * math.pi, 3), round(q, 2)      # w_n sqrt(1 - 2 zeta^2), Q ~ 1 / (2 zeta)
    (9.999, 49.99)
    """
    omega = np.asarray(omega, dtype=float)
    if omega.ndim != 1 or omega.size < 2 or not np.all(np.isfinite(omega)) or np.any(omega < 0):
        raise InputError("the frequencies must be at least two finite values >= 0", param="frequencies")
    taut = net.taut if taut is None else tuple(taut)
    A = net.state_matrix(taut)
    B = np.column_stack([input_column(net, u) for u in inputs])
    lin = net.linear_rows()
    rows = [output_row(net, y, lin) for y in outputs]
    C = np.array([r for r, _, _ in rows])
    power = np.array([p for _, p, _ in rows])
    X = solve_jw(A, B, omega)
    on_pole = ~np.isfinite(X).all(axis=(1, 2))
    X[on_pole] = 0.0
    H = np.einsum("ij,kjm->kim", C, X) * (1j * omega[:, None, None]) ** power[None, :, None]
    H[on_pole] = complex(math.inf, 0.0)           # exactly on an undamped pole
    in_units = [_input_unit(net, u) for u in inputs]
    resp = Response(omega, list(inputs), list(outputs), [u for _, _, u in rows], in_units, H)

    def h(w, i, j):
        x = solve_jw(A, B[:, [j]], np.array([w]))[0, :, 0]
        if not np.all(np.isfinite(x)):           # exactly on an undamped pole
            return math.inf
        return abs(C[i] @ x * (1j * w) ** power[i])

    for i, y in enumerate(outputs):
        for j, u in enumerate(inputs):
            resp.peaks[(y, u)] = _peaks(omega, np.abs(H[:, i, j]), lambda w: h(w, i, j))
    return resp


def _input_unit(net, name: str) -> str:
    kind, _, what = name.partition(":")
    if kind == "load":
        return "N" if net.node(what).translation else "N m"
    return "rad/s"


def _peaks(omega: np.ndarray, mag: np.ndarray, h) -> list[tuple[float, float, float | None]]:
    """Local maxima of |H| on the grid, refined by golden section on ``h``; Q from where |H|
    falls to peak / sqrt(2) on each side (None where it does not inside the grid)."""
    from beltcalc.numerics.scalar import brentq, golden_minimum    # scipy's, bit for bit, without importing scipy.optimize

    out = []
    for k in range(1, mag.size - 1):
        if not (mag[k] > mag[k - 1] and mag[k] >= mag[k + 1]):
            continue
        x, fx = golden_minimum(lambda w: -h(w), omega[k - 1], omega[k], omega[k + 1], xtol=1e-12)
        w0, peak = float(x), float(-fx)
        half = peak / math.sqrt(2)
        lo = next((j for j in range(k, -1, -1) if mag[j] < half), None)
        hi = next((j for j in range(k, mag.size) if mag[j] < half), None)
        q = None
        if lo is not None and hi is not None:
            try:
                w1 = brentq(lambda w: h(w) - half, omega[lo], w0, xtol=1e-14 * w0)
                w2 = brentq(lambda w: h(w) - half, w0, omega[hi], xtol=1e-14 * w0)
                q = w0 / (w2 - w1) if w2 > w1 else math.inf       # an undamped mode: no bandwidth
            except ValueError:                                     # no sign change: |H| unbounded at the pole
                q = math.inf
        out.append((w0 / (2 * math.pi), peak, q))
    return out


# --- periodic steady state ------------------------------------------------------------------------
@dataclass
class SteadyState:
    """The periodic steady state of an LTI drive under constant and sinusoidal inputs:
    ``mean[y]`` and ``amplitude[y]`` of each output (half peak-to-peak: exact for one input
    frequency; with several the sum of the components, an upper bound, and ``exact`` False),
    ``components[y][w]`` the complex amplitude at each input frequency w [rad/s]."""

    mean: dict[str, float]
    amplitude: dict[str, float]
    components: dict[str, dict[float, complex]]
    units: dict[str, str]
    frequencies: list[float]
    exact: bool


def steady_state(net, outputs: list[str], t_after: float | None = None) -> SteadyState:
    """The exact periodic steady state (strands taut; the inputs of the last time piece,
    after ``t_after`` [s], default after every break point).

    Mean: A a = -B_0, with A's null space (the drive turning freely: its angle grows as
    Omega t) taken out: a = a_p + N beta, the speeds and torques unique. Each sinusoid
    ``B_s sin wt + B_c cos wt``: X = (jw I - A)^-1 (B_c - j B_s), y = Re(c X e^{jwt}).
    A taut strand's force is its pretension plus ``c delta + b delta'`` [RP eq. 8-11]. Refused
    (one line) where no periodic state exists: a ramp input that keeps growing, a drive that
    accelerates without bound, a drive whose speed no balance sets (it turns freely, or a
    node's motion is prescribed: its speed is what the history left it), a strand that
    would go slack.

    >>> from beltcalc.sim.network import Coupling, Inertia, Load, Network
    >>> net = Network([Inertia("a", 0.02)], [Coupling("g", "a", None, 50.0, 0.3), Load("a", 0.0, 0.5, 40.0)])
    >>> round(steady_state(net, ["phi_a"]).amplitude["phi_a"], 8)      # 0.5 / |C - J w^2 + j d w|
    0.02311251
    """
    if not net.linear:
        why = "; ".join(sorted({getattr(el, "nonlinear_reason", "loads locked to a shaft angle")
                                for el in net.elements if el.nonlinear_kind}))
        raise InputError(f"the drive is nonlinear ({why}): it has no LTI steady state; simulate it in time",
                         param="drive")
    breaks = net.breaks(math.inf)
    t_mid = (t_after if t_after is not None else (max(breaks) if breaks else 0.0)) + 1.0
    A, B = net.first_order(None, t_mid)
    if net.ramp and np.any(B[:, 1] != 0):
        raise InputError("an input still ramps after the last break point: no periodic steady state", param="drive")
    lin = net.linear_rows()
    rows = [output_row(net, y, lin) for y in outputs]
    mean_x = mean_state(A, B[:, 0])
    if free_speed(A):
        raise InputError("the drive's speed is set by no balance (it turns freely, or a node's motion is prescribed: "
                         "a double pole at 0), so its steady speed is what the history left it; no periodic steady "
                         "state", param="drive")
    freqs = net.frequencies()
    first = 1 + int(net.ramp)
    comps: dict[str, dict[float, complex]] = {y: {} for y in outputs}
    X = {}
    for k, w in enumerate(freqs):
        rhs = B[:, first + 2 * k + 1] - 1j * B[:, first + 2 * k]
        X[w] = solve_jw(A, rhs[:, None], np.array([w]))[0, :, 0]
    mean, amplitude, units = {}, {}, {}
    preload = {}                   # a strand's force has a constant part, its pretension (output_row leaves it out)
    if net.strands:
        force = net.strand_rows()[1]
        preload = {f"F_{s.name}": float(force[k, net.size]) for k, s in enumerate(net.strands)}
    for y, (row, power, unit) in zip(outputs, rows):
        mean[y] = float(row @ mean_x) + preload.get(y, 0.0) if power == 0 else 0.0
        for w in freqs:
            comps[y][w] = complex(row @ X[w] * (1j * w) ** power)
        amplitude[y] = float(sum(abs(c) for c in comps[y].values()))
        units[y] = unit
    _check_strands(net, mean_x, X)
    return SteadyState(mean, amplitude, comps, units, list(freqs), len(freqs) <= 1)


def mean_state(A: np.ndarray, b0: np.ndarray) -> np.ndarray:
    """A particular constant-input steady state: x = a + N beta t with A a = N beta - b0 and
    A N = 0 (a drive turning at a constant speed); refused where the constant inputs make
    the drive accelerate (the null space is defective: no balance). One system of
    :func:`mean_states`."""
    a, ok = mean_states(A[None], b0[None])
    if not ok[0]:
        raise InputError("the constant torques do not balance: the drive accelerates without bound (no motor "
                         "or ground holds it); no periodic steady state", param="drive")
    return a[0]


def free_speed(A: np.ndarray) -> bool:
    """True where A's zero eigenvalue is defective (a Jordan block: a speed that no balance
    sets, e.g. a drive with no motor or ground, whose angle grows as Omega t for any Omega).
    The rank decision of :func:`mean_states` (balanced, singular values at most ``1e-10
    s_max``), and its test of ``L^T N`` for a Jordan block.

    >>> free_speed(np.array([[0.0, 1.0], [0.0, 0.0]])), free_speed(np.array([[0.0, 1.0], [0.0, -2.0]]))
    (True, False)
    """
    from beltcalc.numerics.balance import balance

    m = A.shape[0]
    if m == 0:
        return False
    scale = balance(A)
    U, sv, Vt = np.linalg.svd(A / scale[:, None] * scale[None, :])
    k = int(np.sum(sv > 1e-10 * sv[0]))
    if k == m:
        return False
    return bool(np.linalg.svd(U[:, k:].T @ Vt[k:].T, compute_uv=False).min() < 1e-8)


def mean_states(A: np.ndarray, b0: np.ndarray, scale: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`mean_state` of a stack of systems ``A`` (R, m, m), ``b0`` (R, m) at once (a
    study's runs): ``(a, ok)``, ``ok[r]`` False where system r does not balance.

    Each ``A`` is balanced first (a diagonal similarity D^-1 A D of powers of two,
    :func:`beltcalc.numerics.balance.balance`), so that the rank decision is not swamped by a
    stiffness many decades above the rest (a stiff coupling's k/J of 1e16 beside a motor's
    1e2 would count the motor's modes as null). With the SVD ``A = U S V^T`` (one batched
    call), the null space is the singular values at most ``1e-10 s_max``: right ``N``, left
    ``L``. ``L^T N`` singular means a Jordan block at 0: the drive balances only if ``L^T b0
    = 0``. Otherwise ``beta = (L^T N)^-1 L^T b0`` and ``a`` is the least-squares solution of
    ``A a = N beta - b0`` over the other singular values (the pseudo-inverse with the same
    cut-off as the rank decision). Systems of one null dimension are solved together.
    ``scale`` (R, m): the balancing, where the caller has one for the stack."""
    from beltcalc.numerics.balance import balance

    R, m = b0.shape
    if scale is None:
        scale = balance(A) if R else np.ones((0, m))
    At = A / scale[:, :, None] * scale[:, None, :]
    bt = b0 / scale
    a = np.zeros((R, m))
    ok = np.ones(R, dtype=bool)
    if R == 0 or m == 0:
        return a, ok
    U, sv, Vt = np.linalg.svd(At)
    null = np.sum(sv <= 1e-10 * sv[:, :1], axis=1)
    for q in np.flatnonzero(np.bincount(null)):     # the null-space sizes present
        idx = np.flatnonzero(null == q)
        k = m - int(q)
        y = -bt[idx]
        if q:
            N = Vt[idx, k:].transpose(0, 2, 1)                 # right null spaces (R', m, q)
            L = U[idx, :, k:]                                   # left null spaces
            LN = L.transpose(0, 2, 1) @ N
            Lb = (L.transpose(0, 2, 1) @ bt[idx, :, None])[:, :, 0]
            jordan = np.linalg.svd(LN, compute_uv=False).min(axis=1) < 1e-8
            beta = np.zeros((idx.size, int(q)))
            if np.any(~jordan):
                beta[~jordan] = np.linalg.solve(LN[~jordan], Lb[~jordan, :, None])[:, :, 0]
            bad = jordan & (np.linalg.norm(Lb, axis=1) > 1e-12 * np.maximum(1.0, np.linalg.norm(bt[idx], axis=1)))
            ok[idx[bad]] = False
            y = y + (N @ beta[:, :, None])[:, :, 0]
        # the least-squares solution over the k kept singular values: V_k S_k^-1 U_k^T y
        c = (U[idx, :, :k].transpose(0, 2, 1) @ y[:, :, None])[:, :, 0] / sv[idx, :k]
        a[idx] = (Vt[idx, :k].transpose(0, 2, 1) @ c[:, :, None])[:, :, 0]
    return scale * a, ok


def _check_strands(net, mean_x: np.ndarray, X: dict) -> None:
    if not net.strands:
        return
    delta, force = net.strand_rows()
    m = net.size
    for k, s in enumerate(net.strands):
        f_mean = force[k, :m] @ mean_x + force[k, m]
        f_amp = sum(abs(force[k, :m] @ x) for x in X.values())
        if f_mean - f_amp <= 0:
            raise InputError(f"strand {s.name} would go slack in the steady state (force {f_mean:.4g} +- {f_amp:.4g} N): "
                             "the drive is not linear there; simulate it in time", param="drive")


# --- Campbell diagram -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Crossing:
    """An order line meeting a mode: the reference speed [rad/s] there, the order, the mode
    (1-based, as :func:`poles` lists the oscillatory ones), its frequency [Hz] and damping."""

    speed: float
    order: float
    mode: int
    frequency: float
    damping_ratio: float


def campbell(net, orders: list[float], speed_max: float, speed_min: float = 0.0) -> list[Crossing]:
    """Where excitation orders cross the natural frequencies between ``speed_min`` and
    ``speed_max`` [rad/s] of the reference shaft: an order k at shaft speed Omega excites
    k Omega / 2 pi [Hz], so it meets a mode of f [Hz] at Omega = 2 pi f / k. The linear
    model's poles do not depend on speed (the motor characteristic is linearised with a
    constant slope), so every mode is a horizontal line of the diagram.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0), Inertia("b", 1.0)], [Coupling("c", "a", "b", 2 * (2 * math.pi) ** 2, 0.0)])
    >>> [(round(c.speed, 6), c.order) for c in campbell(net, [1.0, 2.0], 10.0)]   # f = 2 Hz: order 1 at 12.6 rad/s
    [(6.283185, 2.0)]
    """
    out = []
    osc = [p for p in poles(net) if p.kind == "oscillatory"]
    for order in orders:
        if not order > 0:
            raise InputError(f"order {order:g}; orders must be > 0", param="orders")
        for k, p in enumerate(osc, 1):
            speed = float(2 * math.pi * p.frequency / order)
            if speed_min <= speed <= speed_max:
                out.append(Crossing(speed, order, k, p.frequency, p.damping_ratio))
    return sorted(out, key=lambda c: (c.speed, c.order))
