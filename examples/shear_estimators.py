"""How much the estimator of the dissipative + random stress moves the Lees-Edwards viscosity of a split scheme
(issue 7; Shang 2021 sec. 3.2.3 does not say which one it used).

On the same trajectory, per sample interval:

(a) shipped: sigma_xy of all four parts the integrator accumulates every step, the D and R parts being the
    momentum the O sweep exchanges, sum r (x) Delta p / h;
(a') the same without its random part (the noise of each pair's affine update has mean zero, so the mean is
    the same; only the variance differs);
(b) the textbook explicit estimator: kinetic + conservative as in (a), plus the explicit dissipative force
    -gamma w_D(r) (e . v_ij) e at the end-of-step state (q^{n+1}, v^{n+1}) with lab-frame relative velocities,
    and the explicit random force's mean, zero.  Sampled at the interval's last step only (numpy, all pairs).

The sweep order of the O sweep is fixed by the engine (spatial cell order) and is not a user option, so it
is not varied here.

    python examples/shear_estimators.py [--time 10] [--steps 0.005 0.02 0.05]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd_studies.efficiency.statistics import block_standard_error

FRICTION, SHEAR_RATE, CUTOFF, REPULSION = 450.0, 0.2, 1.0, 25.0


def explicit_dissipative_stress_xy(positions: np.ndarray, peculiar_velocities: np.ndarray, box: np.ndarray) -> float:
    """sigma_xy (symmetrised) of the explicit dissipative forces -gamma (1-r)^2 (e . v_ij) e at this state:
    lab relative velocity v_ij = peculiar difference + kappa Delta_y e_x (Delta_y of the minimum image)."""
    upper = np.triu_indices(len(positions), 1)
    delta = positions[upper[0]] - positions[upper[1]]
    for axis in (2, 1, 0):  # minimum image in the reduced (sheared) box, as the plugin does
        delta -= np.floor(delta[:, axis] / box[axis, axis] + 0.5)[:, None] * box[axis]
    r = np.linalg.norm(delta, axis=1)
    near = (r < CUTOFF) & (r > 0)
    delta, r = delta[near], r[near]
    e = delta / r[:, None]
    relative = peculiar_velocities[upper[0][near]] - peculiar_velocities[upper[1][near]]
    relative[:, 0] += SHEAR_RATE * delta[:, 1]
    force = (-FRICTION * (1 - r) ** 2 * np.einsum("pk,pk->p", e, relative))[:, None] * e  # on i
    tensor = -np.einsum("pa,pb->ab", delta, force) / np.linalg.det(box)
    return 0.5 * (tensor[0, 1] + tensor[1, 0])


def run(scheme: str, step_size: float, total_time: float, seed: int, samples_wanted: int = 1000) -> dict:
    system, positions = dpd.soft_fluid(500, density=3.0, a=REPULSION, cutoff=CUTOFF, seed=seed)[:2]
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, CUTOFF, step_size, scheme)
    integrator.setRandomNumberSeed(seed)
    integrator.setLeesEdwards(SHEAR_RATE)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True)
    context.setVelocities(velocities - velocities.mean(axis=0))
    total_steps = int(round(total_time / step_size))
    integrator.step(total_steps // 5)  # the flow develops (20 % discarded, as in the study)
    integrator.setStressAccumulation(True)
    interval = max(1, (total_steps - total_steps // 5) // samples_wanted)
    shipped, without_random, explicit = [], [], []
    previous = integrator.getStressStatistics()
    for _ in range((total_steps - total_steps // 5) // interval):
        integrator.step(interval)
        current = integrator.getStressStatistics()
        chunk, previous = current - previous, current
        total = chunk.mean()
        shipped.append(0.5 * (total[0, 1] + total[1, 0]))
        no_random = total - chunk.mean("random")
        without_random.append(0.5 * (no_random[0, 1] + no_random[1, 0]))
        kinetic_conservative = chunk.mean("kinetic") + chunk.mean("conservative")
        state = context.getState(getPositions=True, getVelocities=True)
        box = state.getPeriodicBoxVectors(asNumpy=True)._value
        explicit.append(0.5 * (kinetic_conservative[0, 1] + kinetic_conservative[1, 0])
                        + explicit_dissipative_stress_xy(state.getPositions(asNumpy=True)._value,
                                                         state.getVelocities(asNumpy=True)._value, box))
    series = {"a": np.array(shipped), "a_without_R": np.array(without_random), "b_explicit": np.array(explicit)}
    out = {name: (s.mean() / SHEAR_RATE, block_standard_error(s) / SHEAR_RATE) for name, s in series.items()}
    difference = series["b_explicit"] - series["a"]
    out["b_minus_a"] = (difference.mean() / SHEAR_RATE, block_standard_error(difference) / SHEAR_RATE)
    out["samples"] = len(shipped)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--time", type=float, default=10.0, help="time units per run (20 %% discarded)")
    parser.add_argument("--steps", type=float, nargs="+", default=[0.005, 0.02, 0.05])
    parser.add_argument("--schemes", nargs="+", default=["S1", "ABOBA"])
    parser.add_argument("--seed", type=int, default=2021)
    args = parser.parse_args()
    print("| scheme | step | (a) shipped: D+R = sum r (x) Delta p / h | (a') without R | (b) explicit F_D at (q, v)^{n+1} "
          "| (b) - (a), paired | samples | wall s |")
    print("|---|---|---|---|---|---|---|---|")
    for scheme in args.schemes:
        for step_size in args.steps:
            start = time.perf_counter()
            out = run(scheme, step_size, args.time, args.seed)
            cells = " | ".join(f"{out[k][0]:.2f} ± {out[k][1]:.2f}" for k in ("a", "a_without_R", "b_explicit", "b_minus_a"))
            print(f"| {scheme} | {step_size} | {cells} | {out['samples']} | {time.perf_counter() - start:.0f} |", flush=True)


if __name__ == "__main__":
    main()
