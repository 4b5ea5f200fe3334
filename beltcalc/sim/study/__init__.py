"""Studies of a scene: grids over several parameters, tolerance (Monte Carlo) studies and
work-precision, in this process or on Dask, each run reduced to its summary row.

Above the scenes (:mod:`beltcalc.sim.scenes`), below the command line; nothing under it
imports it. One module per topic, each imported where it is used (this package imports none
of them, so a command loads only what its study needs):

- :mod:`~beltcalc.sim.study.plan`: what to run (:class:`~beltcalc.sim.study.plan.Plan`, the
  distributions of ``--vary``, each run's draws from its own place in one stream, the chunks'
  size);
- :mod:`~beltcalc.sim.study.runs`: one chunk of runs, one row each (batched exact
  propagation where the scene declares it, else the scene's single run);
- :mod:`~beltcalc.sim.study.execution`: every chunk, in this process or on Dask
  (:mod:`~beltcalc.sim.study.cluster`);
- :mod:`~beltcalc.sim.study.fold`: a tolerance study's runs folded where they run, merged in
  constant memory into the same summary whatever the chunks;
- :mod:`~beltcalc.sim.study.tolerance`: a tolerance study's limits, the study itself;
- :mod:`~beltcalc.sim.study.sweeps`: grids of a scene, their rows in a
  :class:`~beltcalc.sim.study.sweeps.Sweep`;
- :mod:`~beltcalc.sim.study.workprecision`: every method against the exact solution.
"""
