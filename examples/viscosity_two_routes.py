"""Two independent routes to one shear viscosity of the soft DPD fluid (issue 7, last criterion).

Fluid: rho = 3, a = 25, r_c = 1, kT = 1, unit masses; ABOBA at one friction.

(1) Lees-Edwards: planar Couette flow at shear rate kappa in a cubic box, eta = <sigma_xy>/kappa
    (Shang 2021 eq. 3.4) with its blocking error (``sample_shear``, ``shear_viscosity``).
(2) Wu & Shang sinusoidal NEMD: forcing eta_f sin(2 pi y / L_y) e_x per particle, response R = U_1 eta_f,
    nu(k) = rho F_1 / U_1 (L_y / 2 pi)^2 (eq. 87).  ``DPDShearProfile`` forces the box's fundamental only,
    so the wavenumber k = 2 pi / L_y is varied by boxes elongated along y (L_x = L_z fixed, L_y = m L_x,
    same density).  The forcing of each box is chosen from the LE value so that the peak shear rate of the
    sinusoidal flow, k U, equals ``--peak-rate`` (default: the LE kappa): both routes see the same strain
    rates.  The equilibration of each box is 5 momentum-diffusion times rho / (eta k^2).
(3) nu(k) = nu0 + c k^2 by weighted least squares (``extrapolate_k_squared``); the table compares LE, the
    finite-k values and nu0 (difference in combined standard errors); a plot (nu vs k^2, LE as a band) and
    results.json go to --out.

    python examples/viscosity_two_routes.py --friction 4.5 --out out/visc_4.5
    python examples/viscosity_two_routes.py --friction 40.5 --time 80 --le-time 250 --out out/visc_40.5

--time is the sampled time per run of each NEMD box, --le-time that of each LE run (longer by default: for
equal cost the LE error is the larger).  The smallest box also runs at twice its forcing (U_1 must not
change: the linear regime).  The defaults, 3 runs, take about 4 minutes at gamma = 4.5, h = 0.02 on one
core (LE with stress accumulation ~1 us per particle-step, NEMD ~0.6 us).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd.shear import sample_shear, shear_viscosity
from openmmdpd_studies.efficiency.statistics import block_standard_error
from openmmdpd_studies.transport.estimators import extrapolate_k_squared, nemd_coefficient, viscosity

DENSITY, REPULSION, CUTOFF = 3.0, 25.0, 1.0


def fluid(lx: float, ly: float, seed: int):
    """The soft fluid in an L_x x L_y x L_x box at density 3 (L_y adjusted so that N / V = 3 exactly)."""
    n = int(round(DENSITY * lx * lx * ly))
    ly = n / (DENSITY * lx * lx)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(lx, 0, 0), mm.Vec3(0, ly, 0), mm.Vec3(0, 0, lx))
    for _ in range(n):
        system.addParticle(1.0)
    system.addForce(dpd.DPDForce(REPULSION, CUTOFF))
    positions = np.random.default_rng(seed).uniform(0.0, 1.0, size=(n, 3)) * np.array([lx, ly, lx])
    return system, positions, ly


def context_for(system, positions, integrator, seed):
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True)
    context.setVelocities(velocities - velocities.mean(axis=0))  # zero total momentum
    return context


def lees_edwards(friction, step, shear_rate, box, sample_time, equilibration, runs, seed, blocks=200):
    """eta and its error, pooled over independent runs (each with its blocking error)."""
    values, errors = [], []
    for run in range(runs):
        system, positions, _ = fluid(box, box, seed + run)
        integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, friction, CUTOFF, step, "ABOBA")
        integrator.setRandomNumberSeed(seed + run)
        integrator.setLeesEdwards(shear_rate)
        context = context_for(system, positions, integrator, seed + run)
        integrator.step(int(round(equilibration / step)))
        samples = sample_shear(context, integrator, blocks, max(1, int(round(sample_time / step / blocks))))
        eta, error = shear_viscosity(samples, shear_rate)
        values.append(eta)
        errors.append(error)
        del context
    values, errors = np.array(values), np.array(errors)
    blocked = float(np.sqrt(np.sum(errors**2)) / runs)
    scatter = float(values.std(ddof=1) / np.sqrt(runs)) if runs > 1 else float("nan")
    return float(values.mean()), (max(blocked, scatter) if runs > 1 else blocked), values.tolist(), errors.tolist(), blocked, scatter


def sinusoidal_nemd(friction, step, forcing, lx, ly, sample_time, equilibration, runs, seed, blocks=200):
    """nu(k) at k = 2 pi / L_y from NEMD with the sinusoidal profile (eq. 87), pooled over runs."""
    profile = dpd.ShearProfile("sinusoidal")
    block_means, n, height = [], 0, ly
    block_steps = max(1, int(round(sample_time / step / blocks)))
    for run in range(runs):
        system, positions, height = fluid(lx, ly, seed + run)
        n = system.getNumParticles()
        integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, friction, CUTOFF, step, "ABOBA")
        integrator.setRandomNumberSeed(seed + run)
        integrator.setNEMD(profile, forcing)
        context = context_for(system, positions, integrator, seed + run)
        integrator.step(int(round(equilibration / step)))
        integrator.resetTransportStatistics()
        previous = integrator.getTransportStatistics()
        means = []
        for _ in range(blocks):
            integrator.step(block_steps)
            current = integrator.getTransportStatistics()
            means.append((current.response_sum - previous.response_sum) / (current.steps - previous.steps))
            previous = current
        block_means.append(np.array(means))
        del context
    estimate = nemd_coefficient(forcing, block_means, block_steps * step)
    f1 = profile.getFirstFourierCoefficient()
    nu, nu_error = viscosity(DENSITY, f1, height, estimate.value, estimate.error)
    # the mode relaxes in rho / (eta k^2), up to ~25 time units in the longest box: longer than the blocks
    # (at most a run's eighth), so the blocked error may be low; the scatter of the runs' values is the check
    per_run = [viscosity(DENSITY, f1, height, float(np.mean(b)) / forcing, 1.0)[0] for b in block_means]
    scatter = float(np.std(per_run, ddof=1) / np.sqrt(len(per_run))) if len(per_run) > 1 else float("nan")
    return {"L_y": height, "N": n, "k": 2 * np.pi / height, "forcing": forcing, "U1": estimate.value,
            "U1_error": estimate.error, "peak_velocity": 2 * estimate.mean, "nu": nu, "nu_error_blocked": nu_error,
            "nu_runs": per_run, "nu_error_scatter": scatter,
            "nu_error": float(max(nu_error, scatter)) if np.isfinite(scatter) else nu_error}


def plot(path, le, le_error, boxes, fit, friction):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k2 = np.array([b["k"] ** 2 for b in boxes])
    fig, ax = plt.subplots(figsize=(5, 3.6))
    ax.axhspan(le - le_error, le + le_error, color="C1", alpha=0.3, label=f"Lees–Edwards η = {le:.3f} ± {le_error:.3f}")
    ax.axhline(le, color="C1", lw=1)
    ax.errorbar(k2, [b["nu"] for b in boxes], yerr=[b["nu_error"] for b in boxes], fmt="o", color="C0",
                label="sinusoidal NEMD ν(k), k = 2π/L_y")
    xs = np.linspace(0, k2.max() * 1.05, 50)
    ax.plot(xs, fit["nu0"] + fit["c"] * xs, "C0--", lw=1)
    ax.errorbar([0], [fit["nu0"]], yerr=[fit["nu0_error"]], fmt="s", color="C2",
                label=f"ν0 = {fit['nu0']:.3f} ± {fit['nu0_error']:.3f}")
    ax.set_xlabel("k² (nm⁻²)")
    ax.set_ylabel("viscosity (amu nm⁻¹ ps⁻¹)")
    ax.set_title(f"soft fluid ρ = 3, a = 25, γ = {friction}: two routes")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--friction", type=float, default=4.5)
    parser.add_argument("--step", type=float, default=None, help="step size (default 0.02 for gamma <= 10, else 0.01)")
    parser.add_argument("--time", type=float, default=None,
                        help="sampled time units per NEMD run and box (default 120 at h = 0.02, scaled by h / 0.02)")
    parser.add_argument("--le-time", type=float, default=None,
                        help="sampled time units per Lees-Edwards run (default 500 at h = 0.02, scaled by h / 0.02)")
    parser.add_argument("--runs", type=int, default=3, help="independent runs per box")
    parser.add_argument("--shear-rate", type=float, default=0.2, help="Lees-Edwards kappa")
    parser.add_argument("--peak-rate", type=float, default=None, help="peak shear rate k U of the sinusoidal flow (default kappa)")
    parser.add_argument("--lx", type=float, default=5.5, help="L_x = L_z of the NEMD boxes")
    parser.add_argument("--elongations", type=float, nargs="+", default=[1, 2, 3], help="L_y / L_x of the NEMD boxes")
    parser.add_argument("--le-box", type=float, default=7.0, help="edge of the cubic Lees-Edwards box")
    parser.add_argument("--seed", type=int, default=2021)
    parser.add_argument("--out", type=Path, default=Path("out/viscosity_two_routes"))
    args = parser.parse_args()
    step = args.step or (0.02 if args.friction <= 10 else 0.01)
    sample_time = args.time or 120.0 * step / 0.02
    le_time = args.le_time or 500.0 * step / 0.02
    peak_rate = args.peak_rate or args.shear_rate
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()

    le, le_error, le_runs, le_run_errors, le_blocked, le_scatter = lees_edwards(args.friction, step, args.shear_rate, args.le_box, le_time,
                                                        max(20.0, 0.1 * le_time), args.runs, args.seed)
    print(f"LE: eta = {le:.4f} ± {le_error:.4f} (blocked {le_blocked:.4f}, run scatter {le_scatter:.4f}; runs {np.round(le_runs, 4).tolist()}, {time.perf_counter() - start:.0f} s)", flush=True)

    boxes = []
    for m in args.elongations:
        ly = m * args.lx
        k = 2 * np.pi / ly
        forcing = peak_rate * le * k / DENSITY          # U = rho eta_f / (eta k^2), peak rate k U = peak_rate
        relaxation = DENSITY / (le * k * k)             # momentum diffusion time of the mode
        box = sinusoidal_nemd(args.friction, step, forcing, args.lx, ly, sample_time, max(20.0, 5 * relaxation),
                              args.runs, args.seed + 100 * int(m))
        box["relaxation_time"] = relaxation
        if m == args.elongations[0]:  # linearity: the same box at twice the forcing must give the same U_1
            double = sinusoidal_nemd(args.friction, step, 2 * forcing, args.lx, ly, sample_time, max(20.0, 5 * relaxation),
                                     args.runs, args.seed + 100 * int(m) + 50)
            box["linearity"] = {"forcing": 2 * forcing, "U1": double["U1"], "U1_error": double["U1_error"],
                                "nu": double["nu"], "nu_error": double["nu_error"]}
            print(f"linearity, L_y = {box['L_y']:.3f}: U1 = {box['U1']:.3f} ± {box['U1_error']:.3f} at forcing {forcing:.4f}, "
                  f"{double['U1']:.3f} ± {double['U1_error']:.3f} at {2 * forcing:.4f}", flush=True)
        boxes.append(box)
        print(f"L_y = {box['L_y']:.3f} (N = {box['N']}): k = {box['k']:.4f}, forcing {forcing:.4f}, "
              f"peak shear rate {box['k'] * box['peak_velocity']:.3f}, nu = {box['nu']:.4f} ± {box['nu_error']:.4f} "
              f"(blocked {box['nu_error_blocked']:.4f}, run scatter {box['nu_error_scatter']:.4f}) "
              f"({time.perf_counter() - start:.0f} s)", flush=True)

    fit = extrapolate_k_squared([b["k"] for b in boxes], [b["nu"] for b in boxes], [b["nu_error"] for b in boxes])
    difference = fit["nu0"] - le
    sigma = np.hypot(fit["nu0_error"], le_error)
    lines = [f"γ = {args.friction}, h = {step}, ABOBA, {args.runs} runs × {sample_time:g} time units per box; "
             f"LE κ = {args.shear_rate} in a {args.le_box}³ box; NEMD peak shear rate {peak_rate}",
             "", "Errors: the larger of the pooled blocked error and the scatter of the runs (both in the last column).", "",
             "| route | N | k (nm⁻¹) | k² | viscosity | blocked / run scatter |", "|---|---|---|---|---|---|",
             f"| Lees–Edwards ({args.runs} × {le_time:g} time units) | {int(round(DENSITY * args.le_box**3))} | 0 | 0 | "
             f"{le:.3f} ± {le_error:.3f} | {le_blocked:.3f} / {le_scatter:.3f} |"]
    for b in boxes:
        lines.append(f"| sinusoidal NEMD, L_y = {b['L_y']:.2f} | {b['N']} | {b['k']:.3f} | {b['k']**2:.3f} | "
                     f"{b['nu']:.3f} ± {b['nu_error']:.3f} | {b['nu_error_blocked']:.3f} / {b['nu_error_scatter']:.3f} |")
    lines.append(f"| ν0 = ν(k → 0), fit ν0 + c k² | | 0 | 0 | {fit['nu0']:.3f} ± {fit['nu0_error']:.3f} | |")
    linear = boxes[0]["linearity"]
    lines += ["", f"Linearity (L_y = {boxes[0]['L_y']:.2f}): U₁ = {boxes[0]['U1']:.3f} ± {boxes[0]['U1_error']:.3f} at forcing "
              f"{boxes[0]['forcing']:.4f}, {linear['U1']:.3f} ± {linear['U1_error']:.3f} at twice it "
              f"(ν = {linear['nu']:.3f} ± {linear['nu_error']:.3f})."]
    lines += ["", f"c = {fit['c']:.3f} ± {fit['c_error']:.3f} nm², χ² = {fit['chi2']:.2f} for {fit['dof']} dof; "
              f"ν0 − η_LE = {difference:+.3f} ± {sigma:.3f} = {difference / sigma:+.2f} σ "
              f"({'within' if abs(difference) <= 2 * sigma else 'NOT within'} 2σ)"]
    table = "\n".join(lines)
    print(table)
    plot(args.out / "viscosity_two_routes.png", le, le_error, boxes, fit, args.friction)
    with open(args.out / "results.json", "w") as file:
        json.dump({"friction": args.friction, "step_size": step, "runs": args.runs, "sample_time": sample_time, "le_time": le_time,
                   "lees_edwards": {"shear_rate": args.shear_rate, "box": args.le_box, "eta": le, "error": le_error,
                                    "runs": le_runs, "run_errors": le_run_errors,
                                    "error_blocked": le_blocked, "error_scatter": le_scatter},
                   "sinusoidal_nemd": boxes, "fit": fit, "difference": difference, "difference_sigma": difference / sigma,
                   "within_2_sigma": bool(abs(difference) <= 2 * sigma), "table": table,
                   "wall_seconds": time.perf_counter() - start}, file, indent=2)
    print(f"wrote {args.out}/results.json and viscosity_two_routes.png ({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
