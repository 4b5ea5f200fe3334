"""Design of a drive from catalog data: what the design calculations report.

:mod:`beltcalc.design.motor_report`: the report of a sized motor duty cycle (its sections
of rows, its JSON object, the torque profile's samples and CSV, the torque-speed zone's
plot data, a sweep's table).
"""
