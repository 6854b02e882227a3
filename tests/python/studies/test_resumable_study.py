"""A study killed halfway and run again gives the same results.json as an uninterrupted one, with any
number of Dask workers."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import openmm
import pytest

from openmmdpd_studies.efficiency.scene import METHOD_DESCRIPTIONS
from openmmdpd_studies.resumable_runs import code_files, fingerprint, run_resumable

SCENE = Path(__file__).resolve().parent / "data" / "tiny_soft_fluid.toml"
RUNS = 2 * 4  # methods x runs in the scene's "tiny" budget
#: Fields that come from the wall-clock timing of each method, which differs between any two invocations.
TIMING_FIELDS = ("seconds_per_step", "seconds_per_step_rounds", "efficiency", "scaled_efficiency")


def study(out: Path, workers: int) -> list:
    return [sys.executable, "-m", "openmmdpd_studies.efficiency", str(SCENE), "--budget", "tiny", "--out", str(out),
            "--workers", str(workers)]


def results_without_timings(out: Path) -> dict:
    results = json.loads((out / "results.json").read_text())
    for scene in results["scenes"]:
        for entry in scene["methods"].values():
            for field in TIMING_FIELDS:
                entry.pop(field, None)
    return results


def finished_runs(out: Path) -> int:
    return len(list((out / "runs").rglob("*.json")))


def test_a_killed_study_resumes_to_the_same_results(tmp_path):
    uninterrupted, resumed = tmp_path / "uninterrupted", tmp_path / "resumed"
    subprocess.run(study(uninterrupted, workers=2), check=True, capture_output=True, timeout=300)
    assert finished_runs(uninterrupted) == RUNS
    report = (uninterrupted / "report.md").read_text()  # it reads on its own: legend, machine, OpenMM, threads
    assert f"- **VV**: {METHOD_DESCRIPTIONS['VV']}" in report and f"- **ABOBA**: {METHOD_DESCRIPTIONS['ABOBA']}" in report
    assert "OpenMM-DPD" not in report  # only the scene's methods
    assert f"OpenMM {openmm.__version__}" in report and "1 thread(s) per run" in report and "logical cores" in report

    killed = subprocess.Popen(study(resumed, workers=1), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    deadline = time.monotonic() + 120
    while finished_runs(resumed) < 2 and killed.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(killed.pid, signal.SIGKILL)  # the client, its scheduler and its workers, mid-study
    killed.wait()
    done_when_killed = finished_runs(resumed)
    assert 2 <= done_when_killed < RUNS, f"the kill did not land halfway ({done_when_killed} of {RUNS} runs done)"
    assert not (resumed / "results.json").exists()

    rerun = subprocess.run(study(resumed, workers=1), check=True, capture_output=True, text=True, timeout=300)
    assert f"resuming, {done_when_killed} of {RUNS} runs already done" in rerun.stderr
    assert results_without_timings(resumed) == results_without_timings(uninterrupted)
    for method in results_without_timings(resumed)["scenes"][0]["methods"].values():  # real numbers, not empty tables
        errors = [point["relative_error"] for point in method["points"]]
        assert len(errors) >= 2 and all(0 < abs(e) < 1 for e in errors)


def double(x: float) -> float:
    return 2 * x


def test_a_saved_run_is_reused_only_for_the_same_arguments(tmp_path):
    from dask.distributed import Client

    runs: dict = {"a": (double, (1.5,)), "b": (double, (2.5,))}
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        assert run_resumable(client, runs, tmp_path, float, float, "test") == [3.0, 5.0]
        saved = json.loads((tmp_path / "a.json").read_text())
        assert saved == {"fingerprint": fingerprint(runs["a"]), "result": 3.0}
        (tmp_path / "a.json").write_text(json.dumps({"fingerprint": fingerprint(runs["a"]), "result": 99.0}))
        changed: dict = {"a": (double, (1.5,)), "b": (double, (4.0,))}
        assert run_resumable(client, changed, tmp_path, float, float, "test") == [99.0, 8.0]  # a reused, b rerun


def test_bad_worker_counts_are_refused():
    from openmmdpd_studies.resumable_runs import dask_client

    with pytest.raises(ValueError, match=r"workers = 0 is out of range; it must be an integer >= 1"):
        with dask_client(0):
            pass


def test_the_code_digest_covers_the_library_and_the_studies():
    # A saved run is reused only by the same code: the library's (its Python and compiled plugin) as well as
    # the studies', which are another installed package since the split.
    names = {name for name, _ in code_files()}
    assert {"openmmdpd/_dpd_integrator.py", "openmmdpd/libOpenMMDPDCPU.so",
            "openmmdpd_studies/resumable_runs.py", "openmmdpd_studies/efficiency/sweep.py"} <= names
    assert any(name.startswith("openmmdpd/_openmmdpd.") and name.endswith(".so") for name in names)
