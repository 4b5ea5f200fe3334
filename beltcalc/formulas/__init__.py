"""The formulas of the papers and the makers' catalogs, in SI floats: no catalog file, no
simulation, no command line.

:mod:`~beltcalc.formulas.belt` (belt models, from the paper and the makers' pages),
:mod:`~beltcalc.design.tension` (installation tension and bolt torque),
:mod:`~beltcalc.formulas.geometry` (centre distance, wrap, belt length),
:mod:`~beltcalc.formulas.chain` (roller chains, from the paper and ISO 606),
:mod:`~beltcalc.formulas.screw` (ball and lead screws),
:mod:`~beltcalc.formulas.profiles` (trapezoid and S-curve moves),
:mod:`~beltcalc.formulas.drive` (the rigid linear axis seen from the motor).
"""
