"""One timed run of an OpenMM integrator on the soft DPD fluid (rho = 3, a = 25, r_c = 1, gamma = 4.5,
kT = 1, dt = 0.04, CPU platform); prints one JSON line.  Run by benchmarks/bench.py, one process per
run so that the peak memory is the run's own.

Usage: python child_openmm.py METHOD N THREADS STEPS
METHOD: ABOBA, VV, S1 (openmmdpd with DPDForce), ABOBA-CustomNonbonded (openmmdpd's ABOBA with the soft
force as a CustomNonbondedForce), OpenMM-Verlet-CustomNonbonded (OpenMM's VerletIntegrator with that force,
same step: OpenMM's own cost for the force alone), OpenMM-DPD (openmm.DPDIntegrator with the soft force as
a CustomNonbondedForce), OpenMM-arrays (an OpenMM VerletIntegrator and no force: OpenMM's own arrays,
the baseline of the memory per particle), ABOBA-bonded (ABOBA with chains of 10 beads: harmonic bonds
and angles beside the DPDForce, which the step evaluates itself), ABOBA-custombonded (the same plus a
CustomBondForce, which the step evaluates too), ABOBA-FENE (the chains' bonds FENE springs, a
CustomBondForce with a logarithm, and no angles: FENE's zero rest length lets bonded beads overlap,
where an angle's force diverges); a suffix -stress (ABOBA-stress, VV-stress, S1-stress)
turns stress accumulation on.
"""

import json
import resource
import sys
import time

import openmm as mm
import openmm.unit as unit

import openmmdpd as dpd
from openmmdpd_studies.efficiency.scene import replace_with_custom_soft_force

method, n, threads, steps = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
system, positions = dpd.soft_fluid(n, 3.0, seed=1)
stress = method.endswith("-stress")
if stress:
    method = method[:-len("-stress")]
if method in ("ABOBA-bonded", "ABOBA-custombonded", "ABOBA-FENE"):  # chains of 10 beads: bonds and angles (and custom bonds)
    bonds, angles, custom = mm.HarmonicBondForce(), mm.HarmonicAngleForce(), mm.CustomBondForce("0.5*k*r^2")
    custom.addPerBondParameter("k")
    fene = mm.CustomBondForce("-0.5*k*R0^2*log(1-(r/R0)^2)")
    fene.addPerBondParameter("k")
    fene.addPerBondParameter("R0")
    for chain in range(n // 10):
        first = 10 * chain
        for b in range(9):
            bonds.addBond(first + b, first + b + 1, 0.5, 50.0)
            fene.addBond(first + b, first + b + 1, [20.0, 3.0])
            if b % 2 == 0:
                custom.addBond(first + b, first + b + 1, [4.0])
            if b < 8:
                angles.addAngle(first + b, first + b + 1, first + b + 2, 3.14159, 3.0)
    chosen = {"ABOBA-bonded": (bonds, angles), "ABOBA-custombonded": (bonds, angles, custom), "ABOBA-FENE": (fene,)}
    for force in chosen[method]:
        system.addForce(force)
    # A melt, not a fluid with bonds across the box: each chain a random walk of 0.5 nm steps from its first bead.
    import numpy as np
    walk = np.random.default_rng(2).normal(size=(n // 10, 9, 3))
    walk *= 0.5 / np.linalg.norm(walk, axis=2, keepdims=True)
    start = np.array(positions.value_in_unit(unit.nanometer) if unit.is_quantity(positions) else positions, dtype=float)
    for chain in range(n // 10):
        start[10 * chain + 1:10 * chain + 10] = start[10 * chain] + np.cumsum(walk[chain], axis=0)
    positions = [mm.Vec3(*q) for q in start]
    method = "ABOBA"
if method in ("OpenMM-DPD", "ABOBA-CustomNonbonded", "OpenMM-Verlet-CustomNonbonded"):
    replace_with_custom_soft_force(system, 25.0, 1.0)
if method == "OpenMM-DPD":
    integrator = mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.04)
elif method == "OpenMM-Verlet-CustomNonbonded":
    integrator = mm.VerletIntegrator(0.04)
elif method == "ABOBA-CustomNonbonded":
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.04, "ABOBA")
elif method == "OpenMM-arrays":
    while system.getNumForces() > 0:
        system.removeForce(0)
    integrator = mm.VerletIntegrator(0.04)
else:
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.04, method)
    integrator.setStressAccumulation(stress)
context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": threads})
context.setPositions(positions)
context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 1)
integrator.step(3)
start = time.perf_counter()
integrator.step(steps)
seconds = (time.perf_counter() - start) / steps
print(json.dumps({"seconds_per_step": seconds, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
