"""`make demo`: the paper's soft DPD fluid (Shang 2021 sec. 3.1: N = 500, density 3, a = 25, r_c = 1,
kT = 1, gamma = 4.5, dt = 0.05) with each scheme for a short run, on OpenMM's CPU platform.

Prints, per scheme, the kinetic and configurational temperature (eq. 3.1, measured at the positions
the Context holds after a step) with block-averaged error bars, and the time per step measured
without observables; then the time per step of OpenMM's own integrators on the same scene for
comparison.  Usage: python examples/demo.py [--steps N] [--threads T]
"""

from __future__ import annotations

import argparse
from typing import Callable, Dict, List, Tuple

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd_studies.efficiency.sweep import interleaved_seconds_per_step

FRICTION = 4.5
STEP_SIZE = 0.05
SEED = 2021


def block_mean_and_error(values: np.ndarray, blocks: int = 10) -> Tuple[float, float]:
    """Mean and its standard error from the scatter of block means (correlated samples)."""
    block_means = np.array([block.mean() for block in np.array_split(values, blocks)])
    return float(values.mean()), float(block_means.std(ddof=1) / np.sqrt(blocks))


def ratio_mean_and_error(numerator: np.ndarray, denominator: np.ndarray, blocks: int = 10) -> Tuple[float, float]:
    """<numerator>/<denominator> and its standard error from per-block ratios."""
    ratios = np.array([n.mean() / d.mean() for n, d in zip(np.array_split(numerator, blocks), np.array_split(denominator, blocks))])
    return float(numerator.mean() / denominator.mean()), float(ratios.std(ddof=1) / np.sqrt(blocks))


def make_context(integrator: mm.Integrator, threads: int, system: mm.System = None, positions=None) -> mm.Context:
    if system is None:
        system, positions = dpd.soft_fluid(num_particles=500, density=3.0, seed=SEED)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, SEED)
    return context


def sample_scheme(scheme: str, steps: int, threads: int) -> Dict[str, float]:
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP_SIZE, scheme)
    integrator.setRandomNumberSeed(SEED)
    context = make_context(integrator, threads)
    integrator.step(int(10.0 / STEP_SIZE))  # 10 time units to equilibrate from random positions
    kinetic: List[float] = []
    gradient_squared: List[float] = []
    laplacian: List[float] = []
    for _ in range(steps // 5):
        integrator.step(5)
        kinetic.append(dpd.kinetic_temperature(context) / dpd.REDUCED_TEMPERATURE)
        g2, lap = dpd.configurational_sums(context)
        gradient_squared.append(g2)
        laplacian.append(lap)
    kinetic_mean, kinetic_error = block_mean_and_error(np.array(kinetic))
    # k_B T_conf in kJ/mol equals T_conf / REDUCED_TEMPERATURE, i.e. 1 at the target.
    conf_mean, conf_error = ratio_mean_and_error(np.array(gradient_squared), np.array(laplacian))
    return dict(kinetic=kinetic_mean, kinetic_error=kinetic_error, conf=conf_mean, conf_error=conf_error)


def interleaved_timings(threads: int) -> Dict[str, float]:
    """Time per step of our three schemes and of OpenMM's own integrators on the same scene (the soft
    force as a CustomNonbondedForce for the peers), all Contexts alive and timed in turn."""
    system, positions = dpd.soft_fluid(num_particles=500, density=3.0, seed=SEED)
    custom = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(system))
    custom.removeForce(0)
    soft = mm.CustomNonbondedForce("0.5*a*rc*(1-r/rc)^2; a=25; rc=1")
    soft.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
    soft.setCutoffDistance(1.0)
    for _ in range(custom.getNumParticles()):
        soft.addParticle([])
    custom.addForce(soft)
    makers: Dict[str, Tuple[mm.System, Callable[[], mm.Integrator]]] = {
        f"openmmdpd {scheme} + DPDForce": (system, lambda scheme=scheme: dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP_SIZE, scheme))
        for scheme in dpd.SCHEMES}
    makers.update({
        "OpenMM VerletIntegrator + CustomNonbondedForce": (custom, lambda: mm.VerletIntegrator(STEP_SIZE)),
        "OpenMM DPDIntegrator + CustomNonbondedForce": (custom, lambda: mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP_SIZE)),
        "openmmdpd ABOBA + CustomNonbondedForce": (custom, lambda: dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP_SIZE, "ABOBA")),
    })
    contexts, integrators = [], {}
    for name, (base, create) in makers.items():
        integrator = create()
        clone = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(base))
        contexts.append(make_context(integrator, threads, clone, positions))  # kept alive while timing
        integrator.step(20)
        integrators[name] = integrator
    return interleaved_seconds_per_step(integrators, 200, repeats=5)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=2000, help="sampled steps per scheme (default 2000 = 100 time units)")
    parser.add_argument("--threads", type=int, default=1, help="CPU platform threads (default 1)")
    args = parser.parse_args()
    print(f"Soft DPD fluid: N = 500, density 3, a = 25, r_c = 1, kT = 1, gamma = {FRICTION}, dt = {STEP_SIZE}; "
          f"CPU platform, {args.threads} thread(s)")
    print(f"{args.steps} steps sampled every 5 after 200 steps of equilibration; error bars: 1 standard error from 10 blocks; "
          "configurational temperature (eq. 3.1) at q^(n+1)\n")
    print(f"| scheme | kinetic kT | configurational kT | rel. error of conf. kT | ms/step |")
    print(f"|---|---|---|---|---|")
    times = interleaved_timings(args.threads)
    for scheme in dpd.SCHEMES:
        r = sample_scheme(scheme, args.steps, args.threads)
        print(f"| {scheme} | {r['kinetic']:.4f} ± {r['kinetic_error']:.4f} | {r['conf']:.4f} ± {r['conf_error']:.4f} "
              f"| {100 * (r['conf'] - 1):+.2f}% | {1000 * times[f'openmmdpd {scheme} + DPDForce']:.3f} |", flush=True)
    print("\nTime per step on the same scene (all integrators timed in turn, A B C ..., median of 5 x 200 steps):\n")
    print("| integrator and force | ms/step |")
    print("|---|---|")
    for name, seconds in times.items():
        print(f"| {name} | {1000 * seconds:.3f} |", flush=True)


if __name__ == "__main__":
    main()
