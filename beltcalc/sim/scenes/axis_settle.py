"""The settling check of ``beltcalc motor-size --settle-band``: its move out and back on the
linear axis as a dynamic model, the belt's spans following the carriage
(:mod:`beltcalc.sim.scenes.linear_axis`, :mod:`beltcalc.sim.scenes.axis_stops`)."""

from __future__ import annotations

from beltcalc.errors import InputError
from beltcalc.sim.scenes.axis_stops import moves, reference_position, settling_checks, stop_figures
from beltcalc.sim.scenes.linear_axis import SCENE, build, prepare


def settle_cycle(inp, belt, motor, opts, band: float, catalog=None, cfg=None):
    """The settling of ``motor-size``'s move out and back on the axis as a dynamic model: the
    belt's two spans following the carriage, the motor an ideal servo, the move ``opts``
    (shaped as motor-size shapes it), the belt's stiffness and damping as ``beltcalc tension``
    finds them (the linear-axis scene's thread and tensioning values). Returns (stops
    (:class:`~beltcalc.sim.scenes.axis_stops.Stop`), the settling checks, the run) or raises :class:`InputError` where the
    cycle is not one horizontal move."""
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.design.tension import TensionInputs
    from beltcalc.sim.core import simulate
    from beltcalc.sim.methods import SolverConfig

    cat = load_catalog(catalog or ())
    v = SCENE.values()
    tin = TensionInputs(center_distance=inp.center_distance, width=inp.width, mass=inp.mass, accel=1.0,
                        tension_accel=v["tension_accel"], tension_speed=v["tension_speed"], mu=v["mu"],
                        pulley_diameter=1.0)
    if opts.cycle is not None or opts.incline:
        raise InputError("the settling check simulates one horizontal move, out and back (no --cycle, --segment or "
                         "--incline)", param="settle_band")
    model, _, _ = prepare(inp, belt, [motor], motor, tin, cat.thread(v["thread"]), opts=opts, spans="moving",
                          cycle="out-and-back", shaper_zeta=opts.shaper_zeta,
                          shaper_at=opts.shaper_at if opts.shaper_frequency is None else "end")
    net = build(model)
    t_end = moves(model)[-1][1] + model.profile.dwell + 1e-9
    samples = int(round(t_end / 1e-4)) + 1
    result = simulate(net, t_end, samples, cfg or SolverConfig())
    result.signals["following_error"] = result["x_carriage"] - reference_position(model, result.t)
    result.units["following_error"] = "m"
    stops = stop_figures(model, result, band)
    return stops, settling_checks(stops, band), result
