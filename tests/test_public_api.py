"""The public Python API (beltcalc.__all__): what a notebook user imports, pint quantities
where the library takes SI floats, SimResult.to_pandas, and a cheap `import beltcalc`."""

import subprocess
import sys

import numpy as np
import pytest

import beltcalc


def test_every_public_name_resolves():
    for name in beltcalc.__all__:
        assert getattr(beltcalc, name) is not None, name
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        beltcalc.nope  # noqa: B018


def test_import_beltcalc_loads_neither_numpy_nor_scipy_nor_pint():
    code = "import sys, beltcalc; print(sorted(m for m in ('numpy', 'scipy', 'pint') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_tension_inputs_take_pint_quantities_or_refuse_them_by_name():
    from beltcalc.units import ureg

    Q = ureg().Quantity
    cat = beltcalc.load_catalog()
    si = beltcalc.TensionInputs(center_distance=1.245, width=0.025, mass=50.0, accel=10.0, tension_accel=0.1,
                                tension_speed=0.005, mu=0.2, pulley_diameter=0.128)
    q = beltcalc.TensionInputs(center_distance=Q(1245, "mm"), width=Q(25, "mm"), mass=Q(50, "kg"),
                               accel=Q(10, "m/s^2"), tension_accel=Q(100, "mm/s^2"), tension_speed=Q(5, "mm/s"),
                               mu=0.2, pulley_diameter=Q(128, "mm"))
    a = beltcalc.design_tension(si, cat.belt("AT10"), cat.thread("M10x1"))
    b = beltcalc.design_tension(q, cat.belt("AT10"), cat.thread("M10x1"))
    assert b.tension_peak == pytest.approx(a.tension_peak, rel=1e-14)
    assert b.bolt.torque == pytest.approx(a.bolt.torque, rel=1e-14)
    with pytest.raises(beltcalc.InputError, match=r"^TensionInputs.mass = 50 m: it must be in kg$"):
        beltcalc.TensionInputs(center_distance=1.245, width=0.025, mass=Q(50, "m"), accel=10.0, tension_accel=0.1,
                               tension_speed=0.005, mu=0.2, pulley_diameter=0.128)


def test_load_drive_and_simulate_take_quantities():
    from beltcalc.units import ureg

    Q = ureg().Quantity
    a = beltcalc.load_drive("friswell_5_disks", k1__stiffness=24e3)
    b = beltcalc.load_drive("friswell_5_disks", k1__stiffness=Q(24, "kN*m/rad"))
    assert beltcalc.undamped_frequencies(b.network) == pytest.approx(beltcalc.undamped_frequencies(a.network),
                                                                     rel=1e-15)
    r = beltcalc.simulate(b, t_end=Q(50, "ms"), samples=51)
    assert float(r.t[-1]) == pytest.approx(0.05, rel=1e-15)
    with pytest.raises(beltcalc.InputError, match=r"give t_end to simulate a Network"):
        beltcalc.simulate(b.network)


def test_simresult_to_pandas():
    r = beltcalc.simulate(beltcalc.load_drive("friswell_5_disks"), samples=101)
    df = r.to_pandas()
    assert df.index.name == "t"
    np.testing.assert_array_equal(df["omega_disk3"].to_numpy(), r["omega_disk3"])
    assert df.attrs["units"]["T_k2"] == "N m"
    assert list(df.columns) == list(r.signals)


def test_to_pandas_without_pandas_says_how_to_get_it(monkeypatch):
    r = beltcalc.simulate(beltcalc.load_drive("friswell_5_disks"), samples=11)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(beltcalc.InputError, match=r'pip install "beltcalc\[data\]"'):
        r.to_pandas()


def test_a_formula_function_given_a_quantity_says_what_to_pass():
    from beltcalc.formulas.belt import belt_stiffness
    from beltcalc.units import ureg

    with pytest.raises(beltcalc.InputError, match=r"c_spec: 5 kN is a quantity; this function takes SI "
                                                  r"floats: pass x.to\('N'\).magnitude"):
        belt_stiffness(ureg().Quantity(5, "kN"), 1.0)
