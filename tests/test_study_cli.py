"""Studies on the command line (issue 17): --sweep repeated (a grid), --vary/--runs/--seed (a
tolerance study), --limit, rows streamed to --csv/--parquet, --json summary, --strict, --plot,
--workers/--scheduler; the output contract of README's "Output contract"."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import ok, one_error_line, read_csv, warnings

SEWING = ("simulate", "sewing", "--steady-state-only")
VARY = ("--vary", "C4=normal(260N*m/rad,5%)", "--vary", "M3_0=uniform(0.09N*m,0.11N*m)")


def run(*args: str, **kw):
    return CliRunner().invoke(cli, list(args), **kw)


def test_a_tolerance_study_as_json_and_its_rows_as_csv(tmp_path):
    path = tmp_path / "rows.csv"
    result = ok(run(*SEWING, *VARY, "--runs", "300", "--seed", "3", "--workers", "1", "--json", "--csv", str(path)))
    out = json.loads(result.stdout)
    assert out["study"] == "tolerance" and out["runs"] == 300 and out["seed"] == 3 and out["execution"] == "in-process"
    # one check run per chunk goes alone, the rest from batched exact propagation
    prof = out["execution_profile"]
    assert prof["how"] == "in-process" and prof["workers"] == 1 and prof["chunks"] * prof["runs_per_chunk"] >= 300
    assert out["propagation"].startswith(f"batched exact propagation for {300 - prof['chunks']} of 300 runs")
    assert prof["compute_wall"]["unit"] == "s" and prof["compute_wall"]["value"] > 0
    assert prof["client_cpu_per_run"]["value"] == pytest.approx(prof["client_cpu"]["value"] / 300)
    assert [p["name"] for p in out["parameters"]] == ["C4", "M3_0"]
    assert out["parameters"][0]["distribution"]["sd"] == {"value": pytest.approx(13.0), "unit": "N*m/rad"}
    assert out["inputs"]["C4"] == {"text": "normal(260N*m/rad,5%)", "value": 260.0, "unit": "N*m/rad", "origin": "vary"}
    assert out["inputs"]["J3"]["origin"].startswith("scene")
    speed = out["outputs"]["steady_main_speed_mean_rad_per_s"]
    assert speed["unit"] == "rad/s" and speed["n"] == 300
    for stat in ("mean", "sd", "p1", "p5", "p50", "p95", "p99", "min", "max", "nominal"):
        assert speed[stat]["unit"] == "rad/s" and isinstance(speed[stat]["value"], float)
    assert speed["influence"][0]["input"] == "M3_0" and speed["influence"][0]["src"]["value"] < -0.99
    assert out["failures"] == {"runs": 0, "reasons": []} and out["warnings"] == []
    assert "reservoir" in out["reservoir"]["note"]
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    assert header[:3] == ["C4_N_m_per_rad", "M3_0_N_m", "steady_main_speed_mean_rad_per_s"]
    assert header[-3:] == ["failed_checks", "warnings", "error"] and len(lines) == 301
    speeds = [float(line.split(",")[2]) for line in lines[1:]]
    assert sum(speeds) / 300 == pytest.approx(speed["mean"]["value"], rel=1e-12)
    assert result.stderr.splitlines() == [f"wrote {path}"]
    # the same seed gives the same rows
    again = tmp_path / "again.csv"
    ok(run(*SEWING, *VARY, "--runs", "300", "--seed", "3", "--workers", "1", "--csv", str(again)))
    assert again.read_text() == path.read_text()


def test_a_study_without_spread_gives_the_single_run():
    single = json.loads(ok(run(*SEWING, "--set", "C4=250N*m/rad", "--json")).stdout)
    out = json.loads(ok(run(*SEWING, "--vary", "C4=normal(250N*m/rad,0%)", "--vary", "J3=uniform(0.29e-3kg*m^2,"
                            "0.29e-3kg*m^2)", "--runs", "5", "--json")).stdout)
    got = out["outputs"]["steady_main_speed_amplitude_rad_per_s"]
    want = single["steady_state"]["main_shaft"]["speed_amplitude"]["value"]
    # to rounding, not bit for bit: the study's batched path sums on stacks of matrices, in
    # another order under some BLAS kernels (an sd of 2.5e-16 rad/s under OpenBLAS Haswell);
    # 1e-9, the method's error (tests/test_study.py)
    assert got["min"]["value"] == pytest.approx(want, rel=1e-9)
    assert got["max"]["value"] == pytest.approx(want, rel=1e-9)
    assert got["sd"]["value"] == pytest.approx(0.0, abs=1e-9 * want)


def test_failed_runs_are_rows_with_their_reason(tmp_path):
    path = tmp_path / "rows.csv"
    result = ok(run(*SEWING, "--vary", "J1=normal(1.1e-5kg*m^2,200%)", "--runs", "200", "--json", "--csv", str(path)))
    out = json.loads(result.stdout)
    lines = path.read_text().splitlines()[1:]
    failed = [line for line in lines if "must be > 0" in line]
    assert len(lines) == 200 and 40 < len(failed) < 80 and out["failures"]["runs"] == len(failed)
    reason = out["failures"]["reasons"][0]["reason"]
    assert reason.startswith("J1: ") and "must be > 0" in reason
    said = warnings(result)
    assert any(w.startswith(f"{len(failed)} of 200 runs failed") and "--vary J1" in w for w in said)
    assert out["warnings"] == said
    # --strict: a failed run fails the study, and nothing is written
    bad = tmp_path / "strict.csv"
    fail = run(*SEWING, "--vary", "J1=normal(1.1e-5kg*m^2,200%)", "--runs", "50", "--strict", "--csv", str(bad))
    assert fail.exit_code == 1 and fail.stderr.splitlines()[-1].startswith("Error: --strict")
    assert not bad.exists() and [p for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_a_limit_gives_the_failing_fraction_with_its_confidence_interval(tmp_path):
    args = (*SEWING, *VARY, "--runs", "400", "--limit", "steady_main_speed_amplitude_rad_per_s<=1.8636rad/s")
    result = ok(run(*args, "--json"))
    out = json.loads(result.stdout)
    (lim,) = out["limits"]
    assert lim["key"] == "steady_main_speed_amplitude_rad_per_s" and lim["evaluated"] == 400
    assert 0 < lim["failed"] < 400
    p = lim["failed"] / 400
    assert lim["fraction"]["value"] == pytest.approx(p)
    assert lim["ci95"][0]["value"] < p < lim["ci95"][1]["value"]
    assert any(w.startswith("limit steady_main_speed_amplitude_rad_per_s<=1.8636rad/s fails in")
               for w in warnings(result))
    text = ok(run(*args)).stdout
    assert "limits" in text and "95% confidence" in text and "moved most by" in text
    assert "[rad/s]" in text and "[rpm]" in text          # display units, as a single run's table
    fail = run(*args, "--strict", "--csv", str(tmp_path / "x.csv"))
    assert fail.exit_code == 1 and "fails in" in fail.stderr.splitlines()[-1]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, code, fragments", [
    (["--vary", "C4=normal(260,5%)"], 2, ["--vary", "C4 needs units"]),
    (["--vary", "C4=foo(1,2)"], 2, ["--vary", "normal(MEAN"]),
    (["--vary", "C4=normal(260N*m/rad,5%)", "--sweep", "C2=1N*m/rad:2N*m/rad:2"], 2, ["--vary", "--sweep"]),
    (["--runs", "10"], 2, ["--runs goes with --vary"]),
    (["--vary", "C4=normal(260N*m/rad,5%)", "--limit", "nope>=1"], 2, ["--limit", "'nope'", "not a column"]),
    (["--vary", "C4=normal(260N*m/rad,5%)", "--limit", "steady_main_speed_mean_rad_per_s>=1"], 2,
     ["--limit", "needs a unit"]),
    (["--sweep", "C4=1N*m/rad:2N*m/rad:2", "--sweep", "C4=1N*m/rad:3N*m/rad:2"], 2, ["--sweep", "C4 swept twice"]),
])
def test_study_options_are_checked(args, code, fragments):
    one_error_line(run(*SEWING, *args), code, *fragments)


def test_parquet_without_pyarrow_is_one_line(monkeypatch, tmp_path):
    import builtins

    real = builtins.__import__

    def no_pyarrow(name, *a, **kw):
        if name == "pyarrow" or name.startswith("pyarrow."):
            raise ImportError(name)
        return real(name, *a, **kw)

    monkeypatch.setattr(builtins, "__import__", no_pyarrow)
    one_error_line(run(*SEWING, *VARY, "--runs", "3", "--parquet", str(tmp_path / "r.parquet")), 1,
                   "--parquet needs pyarrow", "beltcalc[data]")
    assert list(tmp_path.iterdir()) == []


def test_parquet_holds_the_rows_of_the_csv(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    csv_path, pq_path = tmp_path / "r.csv", tmp_path / "r.parquet"
    result = ok(run(*SEWING, *VARY, "--runs", "260", "--workers", "1", "--csv", str(csv_path), "--parquet",
                    str(pq_path)))
    assert result.stderr.splitlines() == [f"wrote {csv_path}", f"wrote {pq_path}"]
    table = pq.read_table(pq_path)
    header = csv_path.read_text().splitlines()[0].split(",")
    assert table.column_names == header and table.num_rows == 260
    first = csv_path.read_text().splitlines()[1].split(",")
    assert table.column("steady_main_speed_mean_rad_per_s")[0].as_py() == float(first[2])


def test_a_study_plot_has_histograms_and_a_tornado(tmp_path):
    png = tmp_path / "study.png"
    result = ok(run(*SEWING, *VARY, "--runs", "100", "--plot", str(png), "--limit",
                    "steady_main_speed_amplitude_rad_per_s<=1.9rad/s"))
    assert f"wrote {png}" in result.stderr and png.stat().st_size > 10_000


def test_a_grid_of_two_sweeps(tmp_path):
    path = tmp_path / "grid.csv"
    result = ok(run(*SEWING, "--sweep", "C4=100N*m/rad:300N*m/rad:3", "--sweep", "M3_0=0.1N*m:0.12N*m:2", "--json",
                    "--csv", str(path)))
    out = json.loads(result.stdout)
    assert out["study"] == "sweep"
    assert out["parameters"] == [{"name": "C4", "unit": "N*m/rad", "values": [100.0, 200.0, 300.0]},
                                 {"name": "M3_0", "unit": "N*m", "values": [0.1, 0.12]}]
    keys = [c["key"] for c in out["columns"]]
    assert keys[:2] == ["C4_N_m_per_rad", "M3_0_N_m"] and len(out["rows"]) == 6
    assert [r[:2] for r in out["rows"]] == [[c, m] for c in (100.0, 200.0, 300.0) for m in (0.1, 0.12)]
    single = json.loads(ok(run(*SEWING, "--set", "C4=300N*m/rad", "--set", "M3_0=0.1N*m", "--json")).stdout)
    row = dict(zip(keys, out["rows"][4]))
    assert row["steady_main_speed_amplitude_rad_per_s"] == single["steady_state"]["main_shaft"]["speed_amplitude"]["value"]
    header, table = read_csv(path)
    assert header == keys and len(table["C4_N_m_per_rad"]) == 6
    text = ok(run(*SEWING, "--sweep", "C4=100N*m/rad:300N*m/rad:3", "--sweep", "M3_0=0.1N*m:0.12N*m:2")).stdout
    assert "sweep of C4 x M3_0" in text and "[N m/rad]" in text
    png = tmp_path / "grid.png"
    ok(run(*SEWING, "--sweep", "C4=100N*m/rad:300N*m/rad:3", "--sweep", "M3_0=0.1N*m:0.12N*m:2", "--plot", str(png)))
    assert png.stat().st_size > 10_000


def test_a_grid_point_that_fails_to_solve_is_a_row(monkeypatch):
    # a solver failure at one point (not an impossible value of the swept parameter) is that
    # point's row with the reason; the other points are reported
    from dataclasses import replace

    from beltcalc.errors import SimulationError
    from beltcalc.sim.scenes import SCENES

    real = SCENES["sewing"].run

    def flaky(values, cfg, **kw):
        if values["C4"] == 200.0:
            raise SimulationError("method exact: the run needs too many steps")
        return real(values, cfg, **kw)

    monkeypatch.setitem(SCENES, "sewing", replace(SCENES["sewing"], run=flaky))
    result = ok(run("simulate", "sewing", "--steady-state-only", "--sweep", "C4=100N*m/rad:300N*m/rad:3", "--json"))
    out = json.loads(result.stdout)
    assert out["rows"][1][1:] == [None] * (len(out["columns"]) - 1) and out["rows"][0][1] is not None
    assert out["errors"] == [{"point": {"value": 200.0, "unit": "N*m/rad"},
                              "error": "method exact: the run needs too many steps"}]
    assert any("the run failed: method exact" in w and "C4 = 200" in w for w in warnings(result))


def test_without_dask_a_large_study_says_so(monkeypatch):
    import beltcalc.sim.study.execution as execution

    monkeypatch.setattr(execution, "dask_available", lambda: False)
    result = run(*SEWING, *VARY, "--runs", "201", "--workers", "2", "--json")
    assert result.exit_code == 0
    assert [line for line in result.stderr.splitlines() if line.startswith("note: ")] == [
        'note: dask is not installed: the 201 runs go in this process, one at a time (pip install '
        '"beltcalc[dist]" for a local cluster of processes)']
    assert json.loads(result.stdout)["execution"] == "in-process"


def test_one_and_two_workers_give_the_same_rows(tmp_path):
    pytest.importorskip("distributed")
    one, two = tmp_path / "one.csv", tmp_path / "two.csv"
    args = (*SEWING, *VARY, "--vary", "J1=normal(1.1e-5kg*m^2,150%)", "--runs", "500", "--seed", "11")
    ok(run(*args, "--workers", "1", "--csv", str(one)))
    out = json.loads(ok(run(*args, "--workers", "2", "--csv", str(two), "--json")).stdout)
    assert out["execution"] == "dask local cluster, 2 workers"
    assert two.read_text() == one.read_text()


def test_without_workers_a_study_goes_to_a_local_cluster_only_where_its_runs_repay_its_start(tmp_path, monkeypatch):
    # no --workers: the first chunk (one batch group of 250 runs) runs here and times a run; the
    # other 350 (about 0.4 s here) stay here, under what 2 workers must save to repay their
    # start. With the start taken as free they go to the workers. Either way the rows and every
    # statistic are those of --workers 1, bit for bit
    pytest.importorskip("distributed")
    import os

    import beltcalc.sim.study.execution as execution

    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    args = (*SEWING, *VARY, "--runs", "600", "--seed", "4", "--json")
    paths = {k: tmp_path / f"{k}.csv" for k in ("one", "here", "there")}
    one = json.loads(ok(run(*args, "--workers", "1", "--csv", str(paths["one"]))).stdout)
    here = json.loads(ok(run(*args, "--csv", str(paths["here"]))).stdout)
    assert here["execution"] == "in-process" and here["execution_profile"]["chunks"] >= 2
    assert here["execution_profile"]["why"].startswith("the first 250 runs timed a run: the other 350 take about")
    assert "under the 2 s a cluster of 2 workers must save" in here["execution_profile"]["why"]
    monkeypatch.setattr(execution, "START_S", 0.0)
    monkeypatch.setattr(execution, "START_S_PER_WORKER", 0.0)
    there = json.loads(ok(run(*args, "--csv", str(paths["there"]))).stdout)
    assert there["execution"] == "dask local cluster, 2 workers"
    assert "over the 0 s a cluster of 2 workers must save" in there["execution_profile"]["why"]
    assert there["execution_profile"]["chunks"] >= 3
    for out in (here, there):
        assert out["outputs"] == one["outputs"] and out["limits"] == one["limits"]
    assert paths["here"].read_text() == paths["there"].read_text() == paths["one"].read_text()


def test_an_existing_scheduler_from_the_option_or_the_environment(tmp_path, monkeypatch):
    # a cluster started here (worker threads in this process) stands for a remote one
    distributed = pytest.importorskip("distributed")
    one = tmp_path / "one.csv"
    args = (*SEWING, *VARY, "--runs", "60", "--seed", "2")
    ok(run(*args, "--workers", "1", "--csv", str(one)))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None,
                                  scheduler_port=0) as cluster:
        for extra, env in ((["--scheduler", cluster.scheduler_address], {}),
                           ([], {"DASK_SCHEDULER_ADDRESS": cluster.scheduler_address})):
            path = tmp_path / "remote.csv"
            out = json.loads(ok(run(*args, *extra, "--csv", str(path), "--json", env=env)).stdout)
            assert out["execution"] == f"dask scheduler {cluster.scheduler_address}"
            assert path.read_text() == one.read_text()


def test_a_study_on_a_scheduler_and_a_worker_started_as_their_own_processes(tmp_path):
    """``dask scheduler`` and ``dask worker`` started as separate processes on the loopback (as on
    a machine of their own, docs/studies.md), the study sent with --scheduler: the same rows as in
    this process; both stopped after."""
    import os
    import shutil
    import signal
    import subprocess
    import sys
    import time

    pytest.importorskip("distributed")
    dask = shutil.which("dask", path=os.path.dirname(sys.executable)) or shutil.which("dask")
    if dask is None:
        pytest.skip("the dask command is not installed")
    info = tmp_path / "scheduler.json"
    env = {**os.environ, "DASK_DISTRIBUTED__WORKER__DAEMON": "False"}
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                               "--scheduler-file", str(info)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              env=env, start_new_session=True)]
    try:
        deadline = time.monotonic() + 60
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        procs.append(subprocess.Popen([dask, "worker", address, "--nworkers", "1", "--nthreads", "1",
                                       "--no-dashboard", "--host", "127.0.0.1"], stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL, env=env, start_new_session=True))
        from distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(1, timeout=60)
        args = (*SEWING, *VARY, "--runs", "40", "--seed", "3")
        here, there = tmp_path / "here.csv", tmp_path / "there.csv"
        mine = json.loads(ok(run(*args, "--workers", "1", "--csv", str(here), "--json")).stdout)
        out = json.loads(ok(run(*args, "--scheduler", address, "--csv", str(there), "--json")).stdout)
        assert out["execution"] == f"dask scheduler {address}" and out["execution_profile"]["workers"] == 1
        assert there.read_text() == here.read_text()
        assert out["outputs"] == mine["outputs"] and out["limits"] == mine["limits"]
    finally:
        for p in reversed(procs):
            os.killpg(p.pid, signal.SIGTERM)
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=20)
    assert all(p.poll() is not None for p in procs)
