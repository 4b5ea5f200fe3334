"""Tests of drive files (beltcalc.sim.drivefile): Friswell's textbook systems as openTorsion
tests them, belt spans from the catalog against `beltcalc tension`, --set addresses, rigid
couplings with their printed error, and one clear line for every malformed file."""

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from beltcalc.data.catalogs import builtin_dir, load_catalog
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.drivefile import DriveFile, DriveFileError, load_drive, undamped_frequencies

DRIVES = builtin_dir() / "drives"


def _eigh_hz(M, K):
    w2 = sla.eigh(np.asarray(K, float), np.asarray(M, float), eigvals_only=True)
    return sorted(math.sqrt(v) / (2 * math.pi) for v in w2 if v > 1e-9 * max(w2))


def test_friswell_five_disks_as_a_drive_file():
    # Friswell et al. example 9.7.1; openTorsion's test_friswell_ex971 prints 81.21, 141.21,
    # 378.95, 536.36 Hz (to 0.01 Hz); the independent reference is M and K typed here, eigh
    d = load_drive(DRIVES / "friswell_5_disks.toml")
    J = [3.5e-3, 3.5e-3, 3.5e-3, 0.15, 0.05]
    k = [12e3, 12e3, 14e3, 10e3]
    K = np.zeros((5, 5))
    for n, c in enumerate(k):
        K[n:n + 2, n:n + 2] += c * np.array([[1, -1], [-1, 1]])
    f = undamped_frequencies(d.network)
    assert f == pytest.approx(_eigh_hz(np.diag(J), K), rel=1e-9)
    assert f == pytest.approx([81.21, 141.21, 378.95, 536.36], abs=0.005)
    # undamped: the damped modes of the first-order system are the same frequencies
    assert [m[0] for m in d.network.modes()] == pytest.approx(f, rel=1e-9)


def test_friswell_branched_geared_system_as_a_drive_file():
    # Friswell et al. example 9.6.3; openTorsion prints 10.304, 20.479, 24.423 Hz. Reference:
    # the reduced matrices over (disk0, gear1, disk5, disk6), gears 3/4 at 1/1.6 of gear 1
    d = load_drive(DRIVES / "friswell_geared.toml")
    G = 68e9
    k1 = G * math.pi * 0.2 ** 4 / 32 / 2.5
    k2 = G * math.pi * 0.25 ** 4 / 32 / 3.5
    r = 1 / 1.6
    M = np.diag([3200.0, 200 + 200 + 2 * 800 * r ** 2, 450.0, 450.0])
    K = np.array([[k1, -k1, 0, 0],
                  [-k1, k1 + 2 * k2 * r ** 2, -k2 * r, -k2 * r],
                  [0, -k2 * r, k2, 0],
                  [0, -k2 * r, 0, k2]])
    f = undamped_frequencies(d.network)
    assert f == pytest.approx(_eigh_hz(M, K), rel=1e-9)
    assert f == pytest.approx([10.304, 20.479, 24.423], abs=5e-4)


def test_geared_drive_reports_every_node_including_the_merged_ones():
    d = load_drive(DRIVES / "friswell_geared.toml")
    r = simulate(d.network, d.t_end, d.samples, SolverConfig("exact"))
    np.testing.assert_allclose(r["omega_gear3"], r["omega_gear1"] / 1.6, rtol=1e-13, atol=1e-300)
    np.testing.assert_allclose(r["omega_gear4"], r["omega_gear1"] / 1.6, rtol=1e-13, atol=1e-300)
    np.testing.assert_allclose(r["omega_gear2"], r["omega_gear1"], rtol=1e-13, atol=1e-300)
    # the tap of 1000 N m for 10 ms on disk 5: its angular momentum 10 N m s is shared by all
    J_total = 3200 + 200 + 200 + (800 + 800 + 450 + 450) / 1.6 ** 2
    momentum = (3200 * r["omega_disk0"] + 400 * r["omega_gear1"] + 800 * 2 * r["omega_gear3"] / 1.6
                + 450 * (r["omega_disk5"] + r["omega_disk6"]) / 1.6)
    assert momentum[-1] == pytest.approx(-10.0 / 1.6, rel=1e-9)
    assert J_total > 0


def test_set_addresses_every_value():
    f = DriveFile(DRIVES / "friswell_5_disks.toml")
    names = [p.name for p in f.params()]
    assert {"t_end", "samples", "window", "k1.stiffness", "disk4.inertia", "tap.amplitude"} <= set(names)
    base = undamped_frequencies(f.build().network)
    stiff = undamped_frequencies(f.build({"k1.stiffness": 48e3}).network)
    assert stiff[-1] > base[-1]
    # every spring x4 and every inertia as given: frequencies x2
    all4 = {f"k{n}.stiffness": 4 * c for n, c in zip(range(1, 5), (12e3, 12e3, 14e3, 10e3))}
    assert undamped_frequencies(f.build(all4).network) == pytest.approx([2 * v for v in base], rel=1e-12)
    with pytest.raises(Exception, match=r"'k9.stiffness' is not a value of this drive file"):
        f.build({"k9.stiffness": 1.0})


def _write(tmp_path, text, name="d.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


BASE = """
[drive]
t_end = "1 s"

[[node]]
name = "a"
inertia = "1 kg*m^2"

[[node]]
name = "b"
inertia = "2 kg*m^2"
"""


@pytest.mark.parametrize("extra, pattern", [
    ('[[coupling]]\nname = "c"\nbetween = ["a", "b"]\n', r"coupling 'c': stiffness: missing"),
    ('[[spring]]\nname = "c"\n', r"unknown section \[spring\]"),
    ('[[coupling]]\nname = "c"\nbetween = ["a", "b"]\nstiffness = "5 N*m/rad"\nstifness = "1"\n',
     r"coupling 'c': stifness: unknown key"),
    ('[[coupling]]\nname = "c"\nbetween = ["a", "b"]\nstiffness = "5 kg"\n',
     r"coupling 'c': stiffness: '5 kg' is a mass, not a .*e.g. '5 N\*m/rad'"),
    ('[[coupling]]\nname = "c"\nbetween = ["a", "x"]\nstiffness = "5 N*m/rad"\n',
     r"coupling 'c': between: 'x' is not a node of this drive"),
    ('[[gear]]\nname = "g1"\nbetween = ["a", "b"]\nratio = 2\n[[gear]]\nname = "g2"\nbetween = ["b", "a"]\n'
     'ratio = 2\n', r"rigid gears form a loop with inconsistent ratios"),
    ('[[node]]\nname = "lost"\ninertia = "0 kg*m^2"\n', r"node\(s\) lost have no inertia and no spring path"),
    ('[[node]]\nname = "a"\ninertia = "1 kg*m^2"\n', r"node 'a': name: repeats the name of a node"),
    ('[[load]]\nnode = "a"\ntorque = "5 N*m"\nfrequency = "3 Hz"\norder = 2\n',
     r"load 'load1': order: give frequency .* or order .*, not both"),
    ('[[motor]]\nkind = "diesel"\nnode = "a"\n', r"motor 'motor1': kind: 'diesel' is not a kind; did you mean .*\(one of induction, prescribed"),
    ('[[chain_strand]]\nfrom = "a"\nto = "b"\nchain = "10B-1"\nlength = "1 m"\nstiffness = "1 MN"\n',
     r"chain_strand 'chain_strand1': from: node 'a' has no pitch diameter"),
    ('[[node]]\nname = "p"\ninertia = "1 kg*m^2"\npitch_diameter = "100 mm"\n'
     '[[belt_span]]\nfrom = "p"\nto = "p"\nbelt = "NOPE"\nwidth = "25 mm"\nlength = "1 m"\n',
     r"belt_span 'belt_span1': belt: unknown belt"),
    # read by the schema's fields (issue 29, step 5): a required text is not empty, a plain
    # number is a number, a table's example is in its column's unit, a frequency in its bounds
    ('[[node]]\nname = "p"\ninertia = "1 kg*m^2"\npitch_diameter = "100 mm"\n'
     '[[belt_span]]\nfrom = "p"\nto = "p"\nbelt = ""\nwidth = "25 mm"\nlength = "1 m"\n',
     r"belt_span 'belt_span1': belt: must not be empty \(belt profile"),
    ('[[coupling]]\nname = "c"\nbetween = ["a", "b"]\nstiffness = "5 N*m/rad"\nratio = true\n',
     r"coupling 'c': ratio: must be a number, not True$"),
    ('[[motor]]\nkind = "prescribed"\nnode = "a"\naccel = 5\n',
     r'motor \'motor1\': accel: must be a list of \[time, value\] pairs, e.g. \[\["0 s", "0 rad/s\^2"\], '),
    ('[[load]]\nnode = "a"\nfrequency = "-1 Hz"\n', r"load 'load1': frequency: -1 Hz is not allowed; it must be >= 0 Hz"),
    # flags through their fields too (a text "yes" was silently taken as false)
    ('[[coupling]]\nname = "c"\nbetween = ["a", "b"]\nstiffness = "5 N*m/rad"\nrigid = "yes"\n',
     r"coupling 'c': rigid: must be true or false, not 'yes'$"),
    ('[[node]]\nname = "p"\ninertia = "1 kg*m^2"\npitch_diameter = "100 mm"\n'
     '[[belt_span]]\nfrom = "p"\nto = "p"\nbelt = "AT10"\nwidth = "25 mm"\nlength = "1 m"\ntension_only = 0\n',
     r"belt_span 'belt_span1': tension_only: must be true or false, not 0$"),
])
def test_every_malformed_file_is_one_line_naming_file_element_and_key(tmp_path, extra, pattern):
    path = _write(tmp_path, BASE + "\n" + extra)
    with pytest.raises(DriveFileError) as info:
        DriveFile(path).build()
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(path) + ": ")
    assert info.match(pattern)


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
def test_a_drive_built_in_code_refuses_a_number_that_is_not_finite(bad):
    # SI floats are allowed there (DriveFile.from_data), an infinite or undefined one is not
    data = {"drive": {"t_end": 1.0}, "node": [{"name": "a", "inertia": 2.0}, {"name": "b", "inertia": 1.0}],
            "coupling": [{"name": "c", "between": ["a", "b"], "stiffness": bad}]}
    with pytest.raises(DriveFileError, match=r"^demo: coupling 'c': stiffness: '-?(inf|nan)' is not a finite number$"):
        DriveFile.from_data(data, "demo").build()
    data["coupling"][0]["stiffness"] = 5.0
    assert DriveFile.from_data(data, "demo").build().network.K[0, 0] == pytest.approx(5.0, rel=1e-15)


def test_not_toml_and_missing_file_are_one_line(tmp_path):
    with pytest.raises(DriveFileError, match=r"d.toml: not valid TOML"):
        DriveFile(_write(tmp_path, "[drive\nt_end = 1"))
    with pytest.raises(DriveFileError, match=r"nothere.toml: no such drive file"):
        DriveFile(tmp_path / "nothere.toml")


def test_belt_span_from_the_catalog_reproduces_tension_stiffness_and_the_two_mass_frequency(tmp_path):
    # BRECO AT10, 25 mm: k = C_spec / L, as `beltcalc tension` computes k_TB = C_spec / a;
    # a two-way span from a 30-tooth pulley to a 20 kg carriage gives the two-mass
    # frequency w^2 = k (1/m + r^2/J) (beltcalc.sim.scenes.linear_axis.two_mass_frequency)
    from beltcalc.formulas.belt import belt_stiffness, pulley_pitch_diameter
    from beltcalc.sim.scenes.linear_axis import two_mass_frequency

    belt = load_catalog().belt("BRECO-AT10")
    row = belt.width_row(0.025)
    path = _write(tmp_path, """
        [drive]
        t_end = "0.5 s"
        [[node]]
        name = "pulley"
        inertia = "2e-3 kg*m^2"
        teeth = 30
        belt = "BRECO-AT10"
        [[node]]
        name = "carriage"
        mass = "20 kg"
        [[belt_span]]
        name = "belt"
        from = "pulley"
        to = "carriage"
        belt = "BRECO-AT10"
        width = "25 mm"
        length = "1200 mm"
        pretension = "800 N"
        tension_only = false
        """)
    d = load_drive(path)
    k = belt_stiffness(row.C_spec, 1.2)
    r = pulley_pitch_diameter(30, belt.pitch) / 2
    c = d.network.couplings[0]
    assert c.C / r ** 2 == pytest.approx(k, rel=1e-14)
    # ... and k_TB of `beltcalc tension` for the same belt, width and span
    from beltcalc.design.tension import TensionInputs, design_tension

    rep = design_tension(TensionInputs(center_distance=1.2, width=0.025, mass=20.0, accel=1.0, tension_accel=0.1,
                                       tension_speed=0.005, mu=0.2, pulley_diameter=2 * r),
                         belt, load_catalog().thread("M10x1"))
    assert c.C / r ** 2 == pytest.approx(rep.stiffness, rel=1e-14)
    assert c.d / r ** 2 == pytest.approx(rep.damping, rel=1e-14)
    # half the span's mass (w_spec L) moves with each end: J + m L r^2 / 2 and m + m L / 2
    half = row.w_spec * 1.2 / 2
    assert undamped_frequencies(d.network)[0] == pytest.approx(
        two_mass_frequency(2e-3 + half * r ** 2, r, 20.0 + half, k), rel=1e-12)
    # damping as `beltcalc tension` takes it: the AT10 catalog's b_TB = 20 N s/m (no F_tspec table)
    assert c.d / r ** 2 == pytest.approx(belt.damping, rel=1e-14)
    assert any("catalog value" in n for n in d.notes)


def test_chain_sprockets_from_teeth_and_strand_from_the_chain_catalog(tmp_path):
    from beltcalc.formulas.chain import sprocket_pitch_diameter

    path = _write(tmp_path, """
        [drive]
        t_end = "0.2 s"
        [[node]]
        name = "s1"
        inertia = "0.01 kg*m^2"
        teeth = 19
        chain = "10B-1"
        [[node]]
        name = "s2"
        inertia = "0.03 kg*m^2"
        teeth = 38
        chain = "10B-1"
        [[chain_strand]]
        name = "tight"
        from = "s1"
        to = "s2"
        chain = "10B-1"
        length = "600 mm"
        pretension = "300 N"
        stiffness = "1.5 MN"
        damping_time = "2e-4 s"
        """)
    d = load_drive(path)
    s = d.network.strands[0]
    assert s.r_i == pytest.approx(sprocket_pitch_diameter(0.015875, 19) / 2, rel=1e-14)
    assert s.r_j == pytest.approx(sprocket_pitch_diameter(0.015875, 38) / 2, rel=1e-14)
    assert s.stiffness == pytest.approx(1.5e6 / 0.6, rel=1e-14)
    assert s.damping == pytest.approx(2e-4 * 1.5e6 / 0.6, rel=1e-14)
    assert d.limits["tight"][0] == pytest.approx(22.2e3, rel=1e-12)
    assert d.limits["tight"][1] == "breaking load"


def test_rigid_coupling_prints_what_it_costs(tmp_path):
    path = _write(tmp_path, BASE + """
        [[node]]
        name = "c"
        inertia = "0.5 kg*m^2"
        [[coupling]]
        name = "soft"
        between = ["a", "b"]
        stiffness = "1000 N*m/rad"
        [[coupling]]
        name = "stiff"
        between = ["b", "c"]
        stiffness = "1e7 N*m/rad"
        rigid = true
        """)
    d = load_drive(path)
    assert d.network.coords == ["a", "b"]
    (note,) = [n for n in d.notes if n.startswith("rigid:")]
    # flexible: sqrt(1000 (1/1 + 1/2.5)) with the stiff mode far above; rigid: J_b + J_c = 2.5
    rigid = math.sqrt(1000 * (1 / 1 + 1 / 2.5)) / (2 * math.pi)
    assert undamped_frequencies(d.network) == pytest.approx([rigid], rel=1e-12)
    flex = load_drive(path, stiff__stiffness=1e7)
    assert "stiff made rigid" in note and "others move by at most 0.00%" in note
    assert flex.network.coords == ["a", "b"]


def test_prescribed_move_from_a_motor_size_profile_reaches_its_distance(tmp_path):
    path = _write(tmp_path, """
        [drive]
        t_end = "1 s"
        samples = 1001
        [[node]]
        name = "motor"
        inertia = "1e-3 kg*m^2"
        [[node]]
        name = "load"
        inertia = "5e-3 kg*m^2"
        [[coupling]]
        name = "shaft"
        between = ["motor", "load"]
        stiffness = "50 N*m/rad"
        damping = "0.05 N*m*s/rad"
        [[motor]]
        kind = "prescribed"
        node = "motor"
        distance = "10 rad"
        max_speed = "20 rad/s"
        max_accel = "100 rad/s^2"
        jerk = "2000 rad/s^3"
        start = "0.1 s"
        """)
    d = load_drive(path)
    r = simulate(d.network, d.t_end, d.samples, SolverConfig("exact"))
    assert r["phi_motor"][-1] == pytest.approx(10.0, rel=1e-12)
    assert r["omega_motor"][-1] == pytest.approx(0.0, abs=1e-10)
    assert np.abs(r["omega_motor"]).max() == pytest.approx(20.0, rel=1e-12)
    assert any("S-curve move" in n for n in d.notes)


def test_the_format_reference_is_generated_from_the_registry():
    # docs/drive_files.md's key tables are the registry's (python -m beltcalc.sim.drivefile.docs)
    from beltcalc.sim.drivefile import KEYS
    from beltcalc.sim.drivefile.docs import PAGE, render

    doc = PAGE.read_text(encoding="utf-8")
    assert render(doc) == doc
    for section, keys in KEYS.items():
        assert (f"`[{section}]`" if section == "drive" else f"`[[{section}]]`") in doc
        for key in keys:
            assert f"| `{key}` |" in doc, (section, key)


def test_a_stale_or_missing_key_table_is_found():
    from beltcalc.sim.drivefile.docs import PAGE, main, render

    doc = PAGE.read_text(encoding="utf-8")
    stale = doc.replace("| `t_end` | s | yes | simulated time |", "| `t_end` | s |  | the run |")
    assert stale != doc
    assert render(stale) == doc
    with pytest.raises(ValueError, match="no key table for load"):
        render(doc.replace("<!-- keys: load -->", "<!-- keys: drive -->"))
    with pytest.raises(ValueError, match="'gone', which is no section"):
        render(doc.replace("<!-- keys: load -->", "<!-- keys: gone -->"))
    assert main(["check"]) == 0


def test_a_new_kind_is_one_class_and_one_registry_line(tmp_path, monkeypatch):
    # a kind of drive-file element of the test's own: a constant brake torque on a node. Its
    # class declares the section, the keys and the build; one line of ELEMENTS makes drive
    # files read it, check its keys, address its values and build it (a load against the
    # motion: the free node decelerates at T / J)
    from beltcalc.data.schema import Quantity, Text
    from beltcalc.sim.drivefile.kinds import Kind
    from beltcalc.sim.drivefile.registry import ELEMENTS
    from beltcalc.sim.elements import Load

    class BrakeKind(Kind):
        section = "brake"
        node_key = "node"
        keys = {"name": Text(help="unique name"), "node": Text(help="node it brakes", required=True),
                "torque": Quantity("N*m|N", help="braking torque", required=True, low=">=0")}

        @classmethod
        def build(cls, b, e):
            b.add(Load(b.node_name(e, "node"), b.need(e, "torque")))

    monkeypatch.setitem(ELEMENTS, "brake", BrakeKind)
    path = tmp_path / "brake.toml"
    path.write_text(textwrap.dedent("""
        [drive]
        t_end = "1 s"
        samples = 11

        [[node]]
        name = "w"
        inertia = "0.5 kg*m^2"

        [[brake]]
        name = "b"
        node = "w"
        torque = "2 N*m"
        """))
    f = DriveFile(path)
    assert [p.name for p in f.params()][-1] == "b.torque"
    net = f.build({"b.torque": 3.0}).network
    assert [(ld.node, ld.mean) for ld in net.loads] == [("w", 3.0)]
    r = simulate(net, 1.0, 11, SolverConfig("exact"), x0=np.array([0.0, 10.0]))
    np.testing.assert_allclose(r["omega_w"], 10.0 - 3.0 / 0.5 * r.t, rtol=1e-13)
    bare = tmp_path / "bare.toml"
    bare.write_text(path.read_text().replace('torque = "2 N*m"', 'torqe = "2 N*m"'))
    with pytest.raises(DriveFileError, match=r"2 problems: brake 'b': torqe: unknown key; did you mean torque"):
        DriveFile(bare)
    monkeypatch.delitem(ELEMENTS, "brake")
    with pytest.raises(DriveFileError, match=r"unknown section \[brake\]"):
        DriveFile(path)


DAMPED = """
[drive]
t_end = "0.5 s"
samples = 501

[[node]]
name = "disk"
inertia = "2 kg*m^2"

[[coupling]]
name = "shaft"
between = ["disk"]
stiffness = "8e4 N*m/rad"
damping = "4 N*m*s/rad"

[[load]]
node = "disk"
amplitude = "50 N*m"
frequency = "30 Hz"
"""


def test_a_torsional_damper_splits_the_mode_it_is_tuned_to(tmp_path):
    # [[damper]]: a ring J_d on k_d and c_d fixed to a node [DH56 sec. 3.2]. Tuned to the
    # disk's own frequency (k_d / J_d = k / J), the two undamped frequencies are the roots of
    # J J_d w^4 - (J_d (k + k_d) + J k_d) w^2 + k k_d = 0; and the drive is the one written
    # with the ring as a node and its spring as a coupling (the same network, to rounding)
    ring = '\n[[damper]]\nname = "ring"\nnode = "disk"\ninertia = "0.2 kg*m^2"\nstiffness = "8e3 N*m/rad"\n'
    damped = _write(tmp_path, DAMPED + ring + 'damping = "5 N*m*s/rad"\n', "damper.toml")
    by_hand = _write(tmp_path, DAMPED + '\n[[node]]\nname = "ring"\ninertia = "0.2 kg*m^2"\n\n[[coupling]]\n'
                     'name = "ring_spring"\nbetween = ["disk", "ring"]\nstiffness = "8e3 N*m/rad"\n'
                     'damping = "5 N*m*s/rad"\n', "by_hand.toml")
    J, k, Jd, kd = 2.0, 8e4, 0.2, 8e3
    a, b, c = J * Jd, -(Jd * (k + kd) + J * kd), k * kd
    roots = sorted((-b + s * math.sqrt(b * b - 4 * a * c)) / (2 * a) for s in (-1, 1))
    want = [math.sqrt(x) / (2 * math.pi) for x in roots]
    d = load_drive(str(damped))
    assert undamped_frequencies(d.network) == pytest.approx(want, rel=1e-12)
    assert want[0] < math.sqrt(k / J) / (2 * math.pi) < want[1]
    r, h = simulate(d.network, 0.5, 501, SolverConfig("exact")), simulate(load_drive(str(by_hand)).network, 0.5, 501,
                                                                          SolverConfig("exact"))
    for name in ("omega_disk", "omega_ring", "T_ring_spring", "T_shaft"):
        scale = float(np.abs(h[name]).max())
        np.testing.assert_allclose(r[name], h[name], rtol=0, atol=1e-12 * scale, err_msg=name)
    clash = _write(tmp_path, DAMPED + ring.replace('name = "ring"', 'name = "disk"'), "clash.toml")
    with pytest.raises(DriveFileError, match=r"damper 'disk': name: repeats the name of a node"):
        load_drive(str(clash))
    free = _write(tmp_path, DAMPED + ring.replace('stiffness = "8e3 N*m/rad"', ""), "free.toml")
    with pytest.raises(DriveFileError, match=r"damper 'ring': damping: give a stiffness or a damping"):
        load_drive(str(free))


def test_conveyor_example_runs_every_element_kind_to_its_static_balance():
    # steady state before the ripple starts (3 s): each drum shaft carries its 15 N m, the
    # motor (10:1 reducer, belt and chain 1:1) 30 N m / 10 = 3 N m, and runs where its
    # linearised characteristic gives 3 N m: w = w0 (1 - S_c M / (2 M_c))
    import beltcalc

    d = beltcalc.load_drive("conveyor")
    r = beltcalc.simulate(d)
    assert r.error_relative == pytest.approx(0.0, abs=1e-6)
    assert r.summary("T_drum1_shaft", 2.8, 3.0).mean == pytest.approx(15.0, rel=1e-4)
    assert r.summary("M_motor", 2.8, 3.0).mean == pytest.approx(3.0, rel=1e-4)
    w0 = 2 * math.pi * 50 / 2
    Mc = 2.3 * 1100 / (1440 * math.pi / 30)
    assert r.summary("omega_rotor", 2.8, 3.0).mean == pytest.approx(w0 * (1 - 0.2 * 3.0 / (2 * Mc)), rel=1e-5)
    # the pulley keyed to the sprocket turns with it (rigid hub), and the belt's tight and
    # slack spans differ by the belt's effective pull 15 N m / r
    np.testing.assert_allclose(r["omega_sprocket1"], r["omega_pulley2"], rtol=1e-14, atol=1e-12)
    r_pulley = 40 * 0.010 / math.pi / 2
    pull = r.summary("F_upper", 2.8, 3.0).mean - r.summary("F_lower", 2.8, 3.0).mean
    assert pull == pytest.approx(30.0 / r_pulley, rel=1e-4)


def test_a_load_frequency_in_hz_is_cycles_per_second(tmp_path):
    # docs/drive_files.md: a load's `frequency` is "rad/s or Hz"; "5 Hz" was refused as a
    # rotational speed (the rotating node's pick of the key's units) and --set too
    import json

    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    text = (Path(__file__).resolve().parent.parent / "catalogs/drives/conveyor.toml").read_text()
    assert 'frequency = "31.4 rad/s"' in text
    figures = {}
    for label, value in (("hz", "5 Hz"), ("rad", "31.41592653589793 rad/s")):
        path = tmp_path / f"{label}.toml"
        path.write_text(text.replace('frequency = "31.4 rad/s"', f'frequency = "{value}"'))
        res = CliRunner().invoke(cli, ["simulate", "drive", str(path), "--t-end", "1s", "--window", "0.5s",
                                       "--samples", "101", "--json"])
        assert res.exit_code == 0, res.output
        figures[label] = json.loads(res.stdout)["couplings"]
    res = CliRunner().invoke(cli, ["simulate", "drive", str(tmp_path / "rad.toml"), "--t-end", "1s", "--window",
                                   "0.5s", "--samples", "101", "--set", "drum2_load.frequency=5Hz", "--json"])
    assert res.exit_code == 0, res.output
    figures["set"] = json.loads(res.stdout)["couplings"]
    for name, fig in figures["rad"].items():
        for key in ("torque_amplitude", "torque_max"):
            want = fig[key]["value"]
            assert figures["hz"][name][key]["value"] == pytest.approx(want, rel=1e-12, abs=1e-12 * abs(want) + 1e-15)
            assert figures["set"][name][key]["value"] == pytest.approx(want, rel=1e-12, abs=1e-12 * abs(want) + 1e-15)
