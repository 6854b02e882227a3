"""One run of one method over the step sizes of a scene: samples of the observables, or 'unstable'."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd.shear import streaming_profile

from .scene import OPENCL_METHODS, Budget, Scene


@dataclass
class RunResult:
    scene: str
    method: str
    step_size: float
    run: int
    unstable: bool = False
    message: str = ""
    gradient_squared: List[float] = field(default_factory=list)
    laplacian: List[float] = field(default_factory=list)
    kinetic: List[float] = field(default_factory=list)
    pressure: List[float] = field(default_factory=list)
    rdf_histogram: Optional[List[float]] = None
    rdf_samples: int = 0
    # Under shear, per sample interval: the interval's mean sigma_xy (symmetrised, kJ/mol/nm^3) with the
    # shipped estimator (all four parts; D + R = sum r (x) Delta p / h of the O sweep) and without the
    # random part (its mean is zero: same expectation, other variance); and the summed streaming profile.
    shear_stress: List[float] = field(default_factory=list)
    shear_stress_without_random: List[float] = field(default_factory=list)
    profile_sum: Optional[List[float]] = None
    profile_samples: int = 0
    box_height: float = 0.0


def method_platform(method: str, threads: int) -> Tuple[mm.Platform, dict]:
    """The platform a method runs on and its properties: the CPU with ``threads`` threads, or OpenCL in
    double precision for the OPENCL_METHODS."""
    if method in OPENCL_METHODS:
        return mm.Platform.getPlatformByName("OpenCL"), {"Precision": "double"}
    return mm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)}


def symmetric_xy(tensor: np.ndarray) -> float:
    return float(0.5 * (tensor[0, 1] + tensor[1, 0]))


def run_one(scene: Scene, method: str, step_size: float, run: int, budget: Budget, seed: int) -> RunResult:
    """Simulate budget.time time units; sample after the discarded fraction, at the positions the
    Context holds after each step (q^{n+1}).  Under shear the centre-of-mass velocity is removed at the
    start, and the stress is accumulated over every step after the discarded fraction (each sample is
    the mean over the steps since the previous one)."""
    result = RunResult(scene.name, method, float(step_size), run)
    system, positions, _ = scene.build(method, seed)
    integrator = scene.integrator(method, step_size, seed)
    context = mm.Context(system, integrator, *method_platform(method, 1))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    if scene.shear_rate > 0:  # a centre-of-mass velocity along y would carry the profile along x
        velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True)
        context.setVelocities(velocities - velocities.mean(axis=0))
    measure_shear = "shear_viscosity" in scene.observables
    total_steps = max(1, int(round(budget.time / step_size)))
    sample_steps = max(1, int(round(budget.sample_interval / step_size)))
    discard_steps = int(round(budget.discard * total_steps))
    histogram = np.zeros(scene.rdf_bins)
    try:
        integrator.step(discard_steps)
        if measure_shear:
            integrator.setStressAccumulation(True)
            previous = integrator.getStressStatistics()
            profile_sum = np.zeros(scene.profile_bins)
        for _ in range((total_steps - discard_steps) // sample_steps):
            integrator.step(sample_steps)
            if measure_shear:
                current = integrator.getStressStatistics()
                interval = current - previous
                previous = current
                total = interval.mean()
                result.shear_stress.append(symmetric_xy(total))
                result.shear_stress_without_random.append(symmetric_xy(total - interval.mean("random")))
                profile, result.box_height = streaming_profile(context, scene.shear_rate, scene.profile_bins)
                if np.isfinite(profile).all():  # a bin empty at this instant: the sample is left out
                    profile_sum += profile
                    result.profile_samples += 1
                if not np.isfinite(total).all():
                    raise mm.OpenMMException(f"non-finite stress at step {context.getStepCount()}")
            if "configurational_temperature" in scene.observables:
                gradient_squared, laplacian = dpd.configurational_sums(context)
                if not np.isfinite(gradient_squared):  # OpenMM's own integrators run on with NaN
                    raise mm.OpenMMException(f"non-finite forces at step {context.getStepCount()}")
                result.gradient_squared.append(gradient_squared)
                result.laplacian.append(laplacian)
            if "kinetic_temperature" in scene.observables:
                result.kinetic.append(dpd.kinetic_temperature(context) / dpd.REDUCED_TEMPERATURE)
            if "pressure" in scene.observables:
                result.pressure.append(dpd.virial_pressure(context))
            if "rdf" in scene.observables:
                histogram += dpd.pair_distance_histogram(context, scene.rdf_max_distance, scene.rdf_bins)
                result.rdf_samples += 1
    except mm.OpenMMException as error:
        result.unstable = True
        result.message = str(error).splitlines()[0]
    if "rdf" in scene.observables and not result.unstable:
        result.rdf_histogram = histogram.tolist()
    if measure_shear and not result.unstable:
        result.profile_sum = profile_sum.tolist()
    return result


def sweep(scene: Scene, method: str, run: int, budget: Budget, seed: int, error_ceiling: float = 0.5) -> List[RunResult]:
    """Step sizes upward until the method becomes unstable or its error passes error_ceiling."""
    results = []
    for step_size in scene.stepsize_grid(budget):
        result = run_one(scene, method, step_size, run, budget, seed)
        results.append(result)
        if result.unstable:
            break
        if result.laplacian and abs(np.mean(result.gradient_squared) / np.mean(result.laplacian) - 1) > error_ceiling:
            break
    return results


def _timing_context(scene: Scene, method: str, threads: int, warmup: int) -> Tuple[mm.Context, mm.Integrator]:
    """A Context of the method warmed up at the scene's timing step size, or at a smaller one for a
    method unstable there (the cost of a step does not depend on its size)."""
    for step_size in (scene.timing_stepsize, scene.stepsizes[0], scene.stepsizes[0] / 4):
        system, positions, _ = scene.build(method, seed=1)
        integrator = scene.integrator(method, step_size, seed=1)
        context = mm.Context(system, integrator, *method_platform(method, threads))
        context.setPositions(positions)
        context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 1)
        try:
            integrator.step(warmup)
            return context, integrator
        except mm.OpenMMException:
            continue
    raise RuntimeError(f"{method} is unstable at every timing step size of scene {scene.name}")


def interleaved_step_time_samples(integrators: Mapping[str, mm.Integrator], steps: int = 300,
                                  repeats: int = 5) -> Dict[str, List[float]]:
    """Wall time per step (s) of bound integrators with no observable, timed in turn (A B C A B C ...)
    so that a change in the machine's load falls on all of them alike: one sample per round and
    integrator, round k of every integrator at the same list index (so that ratios can be taken round
    by round).  The caller keeps their Contexts alive."""
    samples: Dict[str, List[float]] = {name: [] for name in integrators}
    for _ in range(repeats):
        for name, integrator in integrators.items():
            start = time.perf_counter()
            integrator.step(steps)
            samples[name].append((time.perf_counter() - start) / steps)
    return samples


def median_seconds_per_step(samples: Mapping[str, Sequence[float]]) -> Dict[str, float]:
    """The median over the rounds of each integrator's samples (interleaved_step_time_samples)."""
    return {name: float(np.median(values)) for name, values in samples.items()}


def interleaved_seconds_per_step(integrators: Mapping[str, mm.Integrator], steps: int = 300, repeats: int = 5) -> Dict[str, float]:
    """Wall time per step (s) of bound integrators, interleaved (interleaved_step_time_samples): the
    median over the repeats."""
    return median_seconds_per_step(interleaved_step_time_samples(integrators, steps, repeats))


def scene_timing_samples(scene: Scene, methods: Sequence[str], steps: int = 300, repeats: int = 5, threads: int = 1,
                         warmup: int = 50) -> Dict[str, List[float]]:
    """Per-round time per step (s) of each method of a scene, the methods interleaved
    (interleaved_step_time_samples)."""
    contexts = {method: _timing_context(scene, method, threads, warmup) for method in methods}
    return interleaved_step_time_samples({method: integrator for method, (_, integrator) in contexts.items()}, steps, repeats)


def scene_timings(scene: Scene, methods: Sequence[str], steps: int = 300, repeats: int = 5, threads: int = 1,
                  warmup: int = 50) -> Dict[str, float]:
    """Time per step of each method of a scene: the median of scene_timing_samples."""
    return median_seconds_per_step(scene_timing_samples(scene, methods, steps, repeats, threads, warmup))
