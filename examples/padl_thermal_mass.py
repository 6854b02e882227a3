"""What PAdL's thermal mass mu does (docs/results/padl-claims.md): T_conf's error, <xi>, Var xi and xi's
autocorrelation time for mu = 0.5 ... 50 against ABOBA, on the CPU, at gamma = 4.5 (h = 0.08) and gamma = 200
(h = 0.15).  About 10 s.  Usage: python examples/padl_thermal_mass.py"""
import numpy as np, openmm as mm, openmmdpd as dpd

def run(scheme, gamma, h, mu, seed):
    system, positions = dpd.soft_fluid(num_particles=500, density=3.0, seed=seed)
    integ = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, gamma, 1.0, h, scheme)
    integ.setRandomNumberSeed(seed)
    if scheme == "PAdL":
        integ.setPAdLThermalMass(mu)
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    ctx.setPositions(positions)
    dpd.set_velocities_to_temperature(ctx, dpd.REDUCED_TEMPERATURE, seed=seed)
    integ.step(int(20 / h))
    g, l, xi = [], [], []
    for _ in range(int(200 / h) // 5):
        integ.step(5)
        a, b = dpd.configurational_sums(ctx)
        g.append(a); l.append(b)
        xi.append(integ.getAdaptiveFriction() if scheme == "PAdL" else gamma)
    g, l, xi = map(np.array, (g, l, xi))
    tconf = g.mean() / l.mean() / 1.0
    ratios = [a.mean() / b.mean() for a, b in zip(np.array_split(g, 20), np.array_split(l, 20))]
    err = np.std(ratios, ddof=1) / np.sqrt(20)
    # xi's integrated autocorrelation time from its series (samples 5 steps apart)
    x = xi - xi.mean()
    if x.std() > 0:
        acf = np.correlate(x, x, "full")[len(x) - 1:] / (x.var() * len(x))
        cut = np.argmax(acf < 0.05) if np.any(acf < 0.05) else len(acf)
        tau = (1 + 2 * acf[1:cut].sum()) * 5 * h
    else:
        tau = 0.0
    return tconf, err, xi.mean(), xi.var(), tau

for gamma, h in ((4.5, 0.08), (200.0, 0.15)):
    t, e, *_ = run("ABOBA", gamma, h, 0, 7)
    print(f"gamma {gamma} h {h}: ABOBA T_conf {t:.4f} +- {e:.4f}", flush=True)
    for mu in (0.5, 2.0, 10.0, 50.0):
        t, e, m, v, tau = run("PAdL", gamma, h, mu, 7)
        print(f"gamma {gamma} h {h}: PAdL mu {mu:5.1f}: T_conf {t:.4f} +- {e:.4f}, <xi> {m:.3f} (gamma {gamma}), Var xi {v:.4f} (kT/mu {1/mu:.4f}), tau_xi {tau:.2f} ps", flush=True)
