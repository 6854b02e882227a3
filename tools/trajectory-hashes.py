"""Print one hash per pinned trajectory: each scheme on Reference and on CPU with 1, 2 and 16 threads,
plain, as n x step(1), sheared, with stress accumulation, with bonds and angles, and with NEMD and
Norton (ABOBA), plus a type-pair friction table and a checkpoint continuation.  With ``--gpu OpenCL``
(or CUDA) the hashes of that platform in single, mixed and double precision instead, with two more
variants: a box of 7 cells a side (the grid's widest blocks) and a fluid dense enough that the O sweep's
regions overflow local memory (the sweep's global-memory path).

A refactoring that keeps the arithmetic keeps every line; compare two builds with
``diff <(python tools/trajectory-hashes.py) old-hashes.txt``.  The hash is SHA-256 over the final
positions and velocities (float64, System order) and the step count; it depends on the machine's
vector unit (AVX2 against AVX-512) or GPU, so hashes are compared between builds on one machine only.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from typing import Callable, Iterator, Sequence, Tuple

import numpy as np
import openmm

import openmmdpd as dpd

STEPS = 40


def fluid(bonded: bool, num_particles: int = 300, density: float = 3.0) -> Tuple[openmm.System, np.ndarray]:
    system, positions = dpd.soft_fluid(num_particles, density=density, seed=3)
    positions = positions.value_in_unit(positions.unit)
    if bonded:  # chains of 10 beads, bonds and angles across the periodic box
        box = system.getDefaultPeriodicBoxVectors()[0][0]._value
        bonds, angles = openmm.HarmonicBondForce(), openmm.HarmonicAngleForce()
        rng = np.random.default_rng(4)
        for chain in range(30):
            start = rng.uniform(0, box, 3)
            for bead in range(10):
                i = 10 * chain + bead
                positions[i] = (start + 0.5 * bead * np.array([1.0, 0.3, 0.1]) / 1.05) % box
                if bead > 0:
                    bonds.addBond(i - 1, i, 0.5, 100.0)
                if bead > 1:
                    angles.addAngle(i - 2, i - 1, i, np.pi, 5.0)
        bonds.setUsesPeriodicBoundaryConditions(True)
        angles.setUsesPeriodicBoundaryConditions(True)
        system.addForce(bonds)
        system.addForce(angles)
    return system, positions


def digest(context: openmm.Context) -> str:
    state = context.getState(getPositions=True, getVelocities=True)
    h = hashlib.sha256()
    h.update(np.asarray(state.getPositions(asNumpy=True)._value, dtype=np.float64).tobytes())
    h.update(np.asarray(state.getVelocities(asNumpy=True)._value, dtype=np.float64).tobytes())
    h.update(str(context.getStepCount()).encode())
    return h.hexdigest()[:16]


def run(scheme: str, platform: str, setting: str, variant: str) -> str:
    """One trajectory's hash; `setting` is the CPU's thread count or a GPU platform's precision."""
    sizes = {"7 cells": (1200, 3.0), "dense": (1200, 12.0)}
    system, positions = fluid(variant == "bonds", *sizes.get(variant, (300, 3.0)))
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.04, scheme)
    integrator.setRandomNumberSeed(11)
    if variant == "type-pairs":
        force = dpd.DPDForce.cast(system.getForce(0))
        for i in range(0, system.getNumParticles(), 2):
            force.setParticleType(i, 1)
            integrator.setParticleType(i, 1)
        force.addTypePair(0, 1, 40.0, 1.0)
        # PAdL adapts one friction for every pair: its type pair sets only the cutoff
        integrator.addTypePair(1, 1, 4.5 if scheme == "PAdL" else 40.5, 0.9)
    if variant == "sheared":
        integrator.setLeesEdwards(0.5)
    if variant == "stress":
        integrator.setStressAccumulation(True)
    if variant == "NEMD":
        integrator.setNEMD(dpd.ColourDrift(), 2.0)
    if variant == "Norton":
        integrator.setNorton(dpd.ColourDrift(), 0.1)
    properties = {"Threads": setting} if platform == "CPU" else {"Precision": setting} if platform != "Reference" else {}
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=5)
    if variant == "step(1)":
        for _ in range(STEPS):
            integrator.step(1)
    elif variant == "checkpoint":
        integrator.step(STEPS // 2)
        checkpoint = context.createCheckpoint()
        integrator.step(7)
        context.loadCheckpoint(checkpoint)
        integrator.step(STEPS - STEPS // 2)
    else:
        integrator.step(STEPS)
    return digest(context)


def configurations(gpu: str, precisions: Sequence[str]) -> Iterator[Tuple[str, str, str, str]]:
    variants = ["step(n)", "step(1)", "sheared", "stress", "bonds", "type-pairs", "checkpoint"]
    for scheme in dpd.SCHEMES:
        for variant in variants + (["NEMD", "Norton"] if scheme == "ABOBA" else []) + (["7 cells", "dense"] if gpu else []):
            if gpu:
                for precision in precisions:
                    yield scheme, gpu, precision, variant
                continue
            yield scheme, "Reference", "1", variant
            for threads in ("1", "2", "16"):
                yield scheme, "CPU", threads, variant


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gpu", choices=["OpenCL", "CUDA"], default="", help="hash this GPU platform's trajectories instead")
    parser.add_argument("--precision", nargs="+", choices=["single", "mixed", "double"], default=["single", "mixed", "double"],
                        help="with --gpu: the precisions (default: all three)")
    args = parser.parse_args()
    gpu = args.gpu
    for scheme, platform, setting, variant in configurations(gpu, args.precision):
        print(f"{scheme:6s} {platform:9s} {setting:>{6 if gpu else 2}s} {variant:11s} {run(scheme, platform, setting, variant)}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
