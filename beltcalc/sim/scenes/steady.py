"""The exact periodic steady state of a scene's drive (:func:`exact_steady_state`, or why
there is none) and whether its steady window has settled (:func:`settling_check`: the
slowest decaying pole against the time since the last input change, :func:`input_changes`).
SI floats only.
"""

from __future__ import annotations

import math
from typing import Sequence

from beltcalc.design.checks import RULES
from beltcalc.errors import InputError

#: What may be left of a start-up transient at the start of the steady window, relative to
#: the transient at its start: the slowest pole has decayed to this ln(1 / SETTLED) time
#: constants after the last input change (the registry's rule ``window_settled``, 0.1 %).
SETTLED = RULES["window_settled"].limit

#: States above which the settling check is not made: the poles of so large a drive (a
#: 100-roller table) cost seconds (a dense eigenvalue problem), more than some runs.
SETTLING_STATES = 800



def _decaying(p) -> bool:
    """A pole whose free motion decays (damping ratio above
    :data:`beltcalc.sim.frequency_report.UNDAMPED`, or a real pole's positive time constant)."""
    from beltcalc.sim.frequency_report import UNDAMPED

    if p.kind == "oscillatory":
        return p.damping_ratio > UNDAMPED
    return p.kind == "real" and p.time_constant > 0


def _pole_name(net, poles: list, p, taut=None) -> str:
    """A pole as a report names it: an oscillatory one by its mode number (as ``beltcalc
    modes`` numbers them), frequency, damping ratio and the element with the most strain
    energy (where the drive is small enough for its mode shapes); a real one by its time
    constant."""
    if p.kind != "oscillatory":
        return f"a real pole (time constant {p.time_constant:.4g} s)"
    k = [q for q in poles if q.kind == "oscillatory"].index(p) + 1
    where = ""
    if net.size <= SETTLING_STATES // 2:
        from beltcalc.sim.frequency import mode_shapes

        shapes = mode_shapes(net, taut)
        if k <= len(shapes) and shapes[k - 1].dominant:
            where = f", most strain energy in {shapes[k - 1].dominant}"
    return (f"mode {k} ({p.frequency:.4g} Hz, damping ratio {p.damping_ratio:.3g}, time constant "
            f"{-1.0 / p.s.real:.4g} s{where})")


def settling_check(net, window: float, t_end: float, taut=None, poles: list | None = None) -> list:
    r"""Has the start-up transient decayed by the start of the steady window?

    The free motion of the linear drive (strands ``taut``, default all) after the last input
    change ``t_b`` (a ramp's end, a load switched on; 0: the start from rest) decays as
    :math:`e^{\mathrm{Re}(s) t}` per pole s; the slowest decaying pole (largest time
    constant :math:`\tau = -1 / \mathrm{Re}\, s`; rigid-body and undamped poles never decay
    and do not count) leaves

    .. math:: r = e^{-(t_w - t_b) / \tau}

    of its start at the window's start :math:`t_w` (:math:`r = 1` where an input changes
    inside the window). The check is ``r <=`` :data:`SETTLED`, i.e.
    :math:`t_w - t_b \ge \ln(1000)\,\tau`; its rule names the pole and the ``window`` (and
    ``t_end``, for a window of the same length) that would pass. A drive above
    :data:`SETTLING_STATES` states is not checked (n/a, with the reason); one without a
    decaying pole has no check. ``poles``: the drive's (:func:`beltcalc.sim.frequency.poles`
    with ``taut``), where the caller has them.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0)], [Coupling("d", "a", None, 0.0, 4.0)])   # tau = J / d = 0.25 s
    >>> c, = settling_check(net, 1.0, 2.0)
    >>> round(c.value, 6), c.verdict         # e^-4
    (0.018316, 'FAIL')
    """
    if net.size > SETTLING_STATES:
        why = f"not checked: the drive has {net.size} states (more than {SETTLING_STATES}); its poles would cost more"
        return [RULES["window_settled"].check(None, reason=why + " than the run")]
    if poles is None:
        from beltcalc.sim.frequency import poles as every_pole

        poles = every_pole(net, taut)
    found = settling_residual(net, window, t_end, poles)
    if found is None:
        return []
    residual, slow, changes = found
    tau = -1.0 / slow.s.real
    need = math.log(1.0 / SETTLED) * tau
    last = max(changes) if changes else 0.0
    since = "the start from rest at 0 s" if not changes else f"the last input change at {last:.4g} s"
    length = t_end - window
    fix = (f"run with `window` >= {last + need:.4g} s and `t_end` >= {last + need + length:.4g} s (the same "
           f"{length:.4g} s window)")
    rule = f"an input changes at {last:.4g} s, inside the window (from {window:.4g} s); " if window < last else ""
    rule += (f"the slowest pole, {_pole_name(net, poles, slow, taut)}, decays to {SETTLED:g} of its start "
             f"{need:.4g} s (ln {1 / SETTLED:g} time constants) after {since}: {fix}")
    if taut is not None and not all(taut):
        slack = [s.name for s, on in zip(net.strands, taut) if not on]
        rule += f"; strands slack as at the end of the run: {', '.join(slack)}"
    return [RULES["window_settled"].check(residual, detail=rule)]


def settling_residual(net, window: float, t_end: float, poles: list) -> tuple[float, object, list] | None:
    """What :func:`settling_check` judges, without its words: (the residual r, the slowest
    decaying pole, the input changes before ``t_end``), or None where no pole decays. A
    study's batch asks this of every run (:mod:`beltcalc.sim.scenes.sewing`)."""
    decaying = [p for p in poles if _decaying(p)]
    if not decaying:
        return None
    slow = max(decaying, key=lambda p: -1.0 / p.s.real)
    changes = input_changes(net, t_end)
    last = max(changes) if changes else 0.0
    residual = 1.0 if window < last else math.exp(-(window - last) / (-1.0 / slow.s.real))
    return residual, slow, changes


def input_changes(net, t_end: float = math.inf) -> list[float]:
    """The break points in (0, ``t_end``) where an input really changes: the time piece after
    it has another (A, B) than the one before (a table point on a straight line, or a table
    that repeats its value, changes nothing).

    >>> from beltcalc.sim.network import Inertia, Load, Network
    >>> net = Network([Inertia("a", 1.0)], [Load("a", table=((0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 2.0)))])
    >>> net.breaks(math.inf), input_changes(net)       # on a line through 1 s, held from 2 s
    ([1.0, 2.0, 3.0], [2.0])
    """
    import numpy as np

    starts = [0.0] + net.breaks(t_end)
    mids = [0.5 * (a + b) for a, b in zip(starts, starts[1:])] + [starts[-1] + 1.0]
    out = []
    for k in range(1, len(starts)):
        (A0, B0), (A1, B1) = net.first_order(None, mids[k - 1]), net.first_order(None, mids[k])
        if not (np.array_equal(A0, A1) and np.array_equal(B0, B1)):
            out.append(starts[k])
    return out


def strands_at_end(net, result) -> tuple[bool, ...] | None:
    """Which strands are taut at the end of the run (force > 0); None: no strands."""
    if not net.strands:
        return None
    return tuple(bool(result[f"F_{s.name}"][-1] > 0) for s in net.strands)


def exact_steady_state(net, outputs: Sequence[str], window: float | None = None, poles: list | None = None):
    """``(ss, None)``: the exact periodic steady state of ``outputs``
    (:func:`beltcalc.sim.frequency.steady_state`: strands taut, the inputs after the last
    break point), or ``(None, why)``: one line saying why there is none, for a note.

    There is none where the drive is nonlinear; a node's motion is prescribed (its speed is
    what the move left it); an input changes after ``window`` [s] starts (the steady state
    of the later inputs is not what the window shows); a mode is undamped or unstable (its
    free motion never decays); or where :func:`~beltcalc.sim.frequency.steady_state`
    refuses (a drive that accelerates or turns freely, a strand that would go slack:
    ``mean - amplitude <= 0``). A speed loop's drive torque ``T_drive_<node>`` is
    ``feedforward + gain (reference - speed)`` with the tables' last values. ``poles``: the
    drive's with every strand taut, where the caller has them.
    """
    from beltcalc.sim import frequency as fr
    from beltcalc.sim.elements.switched import SpeedLoop

    if net.switched:
        names = ", ".join(el.name for el in net.switched)
        return None, f"the drive has elements with modes of their own ({names}): its steady state depends on them"
    if any(s.ki for s in net.speed_loops):
        return None, "a speed loop integrates its error: its steady torque is the load's, not a function of the speed"
    if not net.linear:
        why = "; ".join(sorted({getattr(el, "nonlinear_reason", "loads locked to a shaft angle")
                                for el in net.elements if el.nonlinear_kind}))
        return None, f"the drive is nonlinear ({why})"
    if net.fixed:
        nodes = ", ".join(p.node for p in net.fixed.values())
        return None, (f"the motion of {nodes} is prescribed: its steady speed is what the move left it, not a "
                      "balance of torques")
    changes = input_changes(net)
    if window is not None and changes and max(changes) > window:
        return None, (f"an input changes at {max(changes):.4g} s, after the window starts ({window:.4g} s): the "
                      "steady state of the later inputs is not what the window shows")
    if poles is None:
        poles = fr.poles(net)
    lasting = [p for p in poles if p.kind != "rigid" and not _decaying(p)]
    if lasting:
        p = lasting[0]
        what = (f"a mode at {p.frequency:.4g} Hz is undamped (damping ratio {p.damping_ratio:.2g})"
                if p.kind == "oscillatory" and abs(p.damping_ratio) <= 1e-9 else
                f"a pole is unstable (s = {p.s.real:.4g}{p.s.imag:+.4g}j 1/s)")
        return None, f"{what}: its free motion never decays"
    loops = {f"T_drive_{s.node}": s for s in net.speed_loops}
    speeds = {y: f"v_{loops[y].node}" if net.node(loops[y].node).translation else f"omega_{loops[y].node}"
              for y in outputs if y in loops}
    asked = list(dict.fromkeys([y for y in outputs if y not in loops] + list(speeds.values())))
    try:
        ss = fr.steady_state(net, asked)
    except InputError as exc:          # its own words, less the advice a time run has taken
        return None, exc.message.removesuffix("; simulate it in time")
    for y, speed in speeds.items():
        loop: SpeedLoop = loops[y]
        ff = loop.feedforward[-1][1] if loop.feedforward else 0.0
        ss.mean[y] = ff + loop.gain * (loop.reference[-1][1] - ss.mean[speed])
        ss.components[y] = {w: -loop.gain * c for w, c in ss.components[speed].items()}
        ss.amplitude[y] = float(sum(abs(c) for c in ss.components[y].values()))
        ss.units[y] = "N" if net.node(loop.node).translation else "N m"
    return ss, None

