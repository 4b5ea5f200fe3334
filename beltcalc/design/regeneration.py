"""Regeneration: the braking energy of a duty cycle against the drive's DC-bus storage, and
the braking resistor it needs ([Yaskawa sec. 12.8.6]).

References
----------
[Yaskawa] Yaskawa Sigma-7 AC servo drive product manual (SIEP S800001 28), "Calculating the
    Required Capacity of Regenerative Resistors" ([Yaskawa sec. 12.8.6], "Selecting External
    Regenerative Resistor: Calculating the Regenerative Energy"): the energy a braking event
    returns is first stored in the SERVOPACK's DC-bus capacitors, E_C = C (U_max^2 - U_dc^2)
    / 2; the rest, E_K, goes to the regenerative resistor, whose required capacity is
    W_K = E_K / (0.2 T) (step 6; T the repeat cycle; note 1: 0.2 is the resistor's utilized
    load ratio of 20 %). Its average power E_K / T is the heat it sheds; its peak power the
    largest braking power.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from beltcalc.design.dutycycle import CycleDuty
from beltcalc.errors import InputError, require_positive, require_range

# [Yaskawa sec. 12.8.6] step 6, note 1: a regenerative resistor is rated for a utilized load
# ratio of 20 %, so its required capacity is W_K = E_K / (0.2 T), five times the cycle's average
# braking power.
RESISTOR_LOAD_RATIO = 0.2

@dataclass(frozen=True)
class Regeneration:
    """Braking energy of a cycle against the drive's storage, and the braking resistor.

    ``stored`` [J] the DC-bus capacitors take per braking event (None: not given, all of
    it goes to the resistor); ``resistor_energy`` E_K [J] per cycle; ``resistor_rating`` the
    resistor's required capacity W_K = E_K / (0.2 T) [W] ([Yaskawa sec. 12.8.6], the rating to buy);
    ``resistor_power`` its average power E_K / T over the cycle [W] (not a rating);
    ``resistor_peak_power`` [W]; ``resistance_max`` [ohm] the largest resistance that still
    takes the peak power at the chopper voltage (None without it).
    """

    braking_energy: float
    efficiency: float
    stored: float | None
    resistor_energy: float
    resistor_power: float
    resistor_peak_power: float
    resistance_max: float | None
    events: tuple[tuple[float, float, float], ...] = field(default=())  # (start, energy, to resistor)
    resistor_rating: float = 0.0


def capacitor_energy(capacitance: float, bus_voltage: float, chopper_voltage: float) -> float:
    r"""Energy the DC-bus capacitors take between the bus voltage and the chopper threshold [J].

    .. math:: E_C = \tfrac12 C (U_{max}^2 - U_{dc}^2)

    Notes
    -----
    [Yaskawa sec. 12.8.6]: the regenerative energy a SERVOPACK can absorb without a resistor. U_dc is the
    bus voltage at rest (about sqrt(2) x the mains voltage), U_max the voltage at which
    the braking chopper switches the resistor in.

    Examples
    --------
    >>> round(capacitor_energy(1.0e-3, 325.0, 380.0), 3)
    19.387
    """
    require_positive("dc_bus_capacitance", capacitance, "F")
    require_positive("dc_bus_voltage", bus_voltage, "V")
    if not chopper_voltage > bus_voltage:
        raise InputError(f"{chopper_voltage:g} V; the chopper voltage must be above the bus voltage "
                         f"({bus_voltage:g} V)", param="chopper_voltage")
    return 0.5 * capacitance * (chopper_voltage ** 2 - bus_voltage ** 2)


def regeneration(duty: CycleDuty, stored: float | None = None, efficiency: float = 1.0,
                 chopper_voltage: float | None = None) -> Regeneration:
    r"""Braking resistor of a cycle: energy, continuous and peak power.

    .. math::
        E_i = \eta \int_{event\,i} \max(-T\omega, 0)\,dt, \quad
        E_K = \sum_i \max(E_i - E_C, 0), \quad
        W_K = E_K / (0.2\, t_{cyc}), \quad P_{R,avg} = E_K / t_{cyc}, \quad
        P_{R,peak} = \eta \max(-T\omega), \quad R_{max} = U_{max}^2 / P_{R,peak}

    Notes
    -----
    [Yaskawa sec. 12.8.6]; W_K (step 6) is the capacity to buy: a resistor is rated for a 20 % utilized load
    ratio (:data:`RESISTOR_LOAD_RATIO`), so W_K is five times the average power. T is the
    motor's electromagnetic torque, so T omega already has the motor's
    modelled losses (b_M omega^2), the gearbox's back-driven efficiency and the friction
    taken off; ``efficiency`` is what is lost further on the way to the DC bus (winding
    and inverter; 1: the resistor must take all of it, the safe side). The capacitors
    are taken as empty again at the start of each braking event (the motoring between
    events draws them down), and as full when the peak occurs (the safe side for the
    peak power).
    """
    require_range("regen_efficiency", efficiency, "", 0.0, 1.0, low_open=True)
    cap = 0.0 if stored is None else stored
    rows = []
    total = 0.0
    for ev in duty.events:
        e = efficiency * ev.energy
        to_r = max(e - cap, 0.0)
        rows.append((ev.start, e, to_r))
        total += to_r
    peak = efficiency * duty.peak_braking_power
    r_max = None
    if chopper_voltage is not None and peak > 0:
        r_max = chopper_voltage ** 2 / peak
    return Regeneration(
        braking_energy=duty.braking_energy, efficiency=efficiency, stored=stored, resistor_energy=total,
        resistor_power=total / duty.cycle_time, resistor_peak_power=peak if total > 0 or stored is None else 0.0,
        resistance_max=r_max if total > 0 else None, events=tuple(rows),
        resistor_rating=total / (RESISTOR_LOAD_RATIO * duty.cycle_time))
