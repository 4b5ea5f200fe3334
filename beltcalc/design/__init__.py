"""Design of a drive from catalog data: what the design calculations report.

:mod:`~beltcalc.design.belt_drive` (belt selection and its checks),
:mod:`~beltcalc.design.tension` (installation tension and bolt torque from a catalog belt),
:mod:`~beltcalc.design.chain_select` (chain selection from the makers' ratings),
:mod:`~beltcalc.design.checks` (one check per design rule: value, limit, margin, verdict),
:mod:`~beltcalc.design.motors` and :mod:`~beltcalc.design.gearboxes` (their catalogs),
:mod:`~beltcalc.design.sizing` (the axis's motor sizing), :mod:`~beltcalc.design.dutycycle`
(peak and RMS torque of a duty cycle, regeneration), :mod:`~beltcalc.design.motor_report`
(the report of a sized motor duty cycle: its sections of rows, its JSON object, the torque
profile's samples and CSV, the torque-speed zone's plot data, a sweep's table).
"""
