"""Transport estimators and the transport scene file."""

from pathlib import Path

import numpy as np
import pytest

from openmmdpd.transport import mobility_from_msd, nemd_coefficient, norton_coefficient
from openmmdpd.transport.__main__ import decode_result, encode_result, run_name, tasks_of
from openmmdpd.transport.estimators import viscosity
from openmmdpd.transport.runner import Task, TaskResult
from openmmdpd.transport.scene import load_transport_scene

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "transport_lj_fluid.toml"


def test_nemd_and_norton_estimators_invert_a_linear_response():
    # A fluid with mobility 0.03: NEMD sees E[R] = 0.03 eta, Norton E[lambda] = r / 0.03.
    rng = np.random.default_rng(1)
    nemd = nemd_coefficient(8.0, [0.24 + 0.01 * rng.normal(size=400) for _ in range(2)], 1.0)
    norton = norton_coefficient(0.24, [8.0 + 0.3 * rng.normal(size=400) for _ in range(2)], 1.0)
    assert nemd.value == pytest.approx(0.03, abs=3 * nemd.error)
    assert norton.value == pytest.approx(0.03, abs=3 * norton.error)
    # Delta method: error of r/E[lambda] is r * SE / E[lambda]^2.
    assert norton.error == pytest.approx(0.24 * norton.mean_error / norton.mean**2)
    # The asymptotic variance of the NEMD estimator scales as eta^-2 for the same noise.
    same_noise = [0.01 * rng.normal(size=512) for _ in range(2)]
    small = nemd_coefficient(1.0, same_noise, 1.0)
    large = nemd_coefficient(10.0, same_noise, 1.0)
    assert small.asymptotic_variance / large.asymptotic_variance == pytest.approx(100.0)


def test_viscosity_formula():
    # eq. 87 with rho = 3, F_1 = 1/2, L_y = 2 pi, U_1 = 0.25: nu = 3 * 0.5 / 0.25 = 6.
    nu, error = viscosity(3.0, 0.5, 2 * np.pi, 0.25, 0.025)
    assert nu == pytest.approx(6.0) and error == pytest.approx(0.6)


def test_mobility_from_a_linear_msd():
    t = np.linspace(0.5, 20, 40)
    alpha, error = mobility_from_msd(t, [6 * 0.05 * t + 0.1, 6 * 0.07 * t - 0.1])
    assert alpha == pytest.approx(0.06)
    assert error == pytest.approx(0.01)


def test_transport_scene_and_its_tasks():
    scene = load_transport_scene(SCENE)
    assert scene.mobility_profile == "ColourDrift" and scene.frictions == [4.5, 40.5]
    assert {"reduced", "full"} <= set(scene.budgets)
    tasks = tasks_of(scene, runs=2)
    # per run: 2 MSD, 4+4 forcing strengths at the first friction, 1+1 at the second, 3 profiles x 2 methods x 2 frictions
    assert len(tasks) == 2 * (2 + 8 + 2 + 12)
    assert scene.box_height() == pytest.approx((500 / 0.85) ** (1 / 3))


def test_every_transport_run_has_its_own_file_and_survives_the_round_trip():
    import json

    tasks = tasks_of(load_transport_scene(SCENE), runs=2)
    assert len({run_name(task) for task in tasks}) == len(tasks)
    result = TaskResult(Task("Norton", 4.5, "ColourDrift", 0.2, 1), block_means=[0.1, 1 / 3])
    assert decode_result(json.loads(json.dumps(encode_result(result)))) == result
