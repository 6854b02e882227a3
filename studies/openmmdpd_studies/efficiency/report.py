"""Tables, plots (matplotlib) and data files of an efficiency study."""

from __future__ import annotations

import csv
import json
import os
import platform
from collections import defaultdict
from pathlib import Path
from typing import Dict, List, Optional

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .claims import claims_json, claims_section, paper_claims  # noqa: E402
from .scene import METHOD_DESCRIPTIONS, OPENCL_METHODS, Scene  # noqa: E402
from .shear_report import add_viscosity_errors, shear_point, shear_section  # noqa: E402
from .statistics import configurational_relative_error, critical_step_size_range  # noqa: E402
from .sweep import RunResult  # noqa: E402


def summarize(scene: Scene, results: List[RunResult], timings: Dict[str, float],
              timing_rounds: Optional[Dict[str, List[float]]] = None) -> Dict:
    """Per method: the error at each step size (mean over runs, standard error), the step size at which
    it became unstable, the critical step size, the time per step (and, given ``timing_rounds``, its
    sample in every interleaved round) and the efficiency.  A point with the RDF keeps each run's
    histogram too (``rdf_run_histograms``, ``rdf_run_samples``): their scatter is the RDF's error bar."""
    by_method: Dict[str, Dict[float, List[RunResult]]] = defaultdict(lambda: defaultdict(list))
    for result in results:
        by_method[result.method][result.step_size].append(result)
    summary = {"scene": scene.name, "title": scene.title, "methods": {}}
    for method in scene.methods:
        points, unstable_at = [], None
        for step_size in sorted(by_method[method]):
            runs = by_method[method][step_size]
            if any(run.unstable for run in runs):
                unstable_at = step_size if unstable_at is None else min(unstable_at, step_size)
                continue
            point = {"step_size": step_size, "runs": len(runs)}
            if runs[0].laplacian:
                error, error_bar = configurational_relative_error([(np.array(r.gradient_squared), np.array(r.laplacian)) for r in runs])
                point.update(relative_error=error, error_bar=error_bar)
            if runs[0].kinetic:
                point["kinetic_temperature"] = float(np.mean([np.mean(r.kinetic) for r in runs]))
            if runs[0].pressure:
                point["pressure"] = float(np.mean([np.mean(r.pressure) for r in runs]))
            if runs[0].rdf_histogram is not None:
                point["rdf_histogram"] = np.sum([r.rdf_histogram for r in runs], axis=0).tolist()
                point["rdf_samples"] = int(sum(r.rdf_samples for r in runs))
                point["rdf_run_histograms"] = [list(r.rdf_histogram) for r in runs]
                point["rdf_run_samples"] = [int(r.rdf_samples) for r in runs]
            if runs[0].shear_stress:
                point.update(shear_point(runs, scene))
            points.append(point)
        stable = [p for p in points if unstable_at is None or p["step_size"] < unstable_at]
        critical, low, high = critical_step_size_range([p["step_size"] for p in stable], [p.get("relative_error", 0.0) for p in stable],
                                                       [p.get("error_bar", 0.0) for p in stable])
        limited_by = "accuracy"
        if critical is None and unstable_at is not None and stable:
            critical, limited_by = stable[-1]["step_size"], "stability"
        seconds = timings.get(method)
        summary["methods"][method] = {
            "points": points, "unstable_at": unstable_at, "critical_step_size": critical, "critical_range": [low, high],
            "critical_limited_by": limited_by,
            "seconds_per_step": seconds,
            "seconds_per_step_rounds": (timing_rounds or {}).get(method),
            "efficiency": critical / seconds if critical and seconds else None,
        }
    reference = next((m for m in ("VV", "S1", "ABOBA") if summary["methods"].get(m, {}).get("efficiency")), None)
    summary["efficiency_reference"] = reference
    for entry in summary["methods"].values():
        if reference and entry["efficiency"]:
            entry["scaled_efficiency"] = entry["efficiency"] / summary["methods"][reference]["efficiency"]
    if "shear_viscosity" in scene.observables:
        summary["shear_rate"] = scene.shear_rate
        add_viscosity_errors(summary, scene)
    return summary


def _label(value: Optional[float], fmt: str = "{:.3f}") -> str:
    return "—" if value is None else fmt.format(value)


def markdown_table(summary: Dict) -> str:
    reference = summary["efficiency_reference"]
    lines = [f"### {summary['title']}", "",
             f"| method | critical step size | time per step (ms) | scaled efficiency (vs {reference}) | unstable at |",
             "|---|---|---|---|---|"]
    for method, entry in summary["methods"].items():
        critical = _label(entry["critical_step_size"])
        if entry["critical_step_size"] is not None and entry["critical_limited_by"] == "stability":
            critical += " (last stable)"
        elif entry["critical_step_size"] is None and entry["points"]:
            critical = f"> {entry['points'][-1]['step_size']:.3f}"
        seconds = entry["seconds_per_step"]
        lines.append(f"| {method} | {critical} | {_label(seconds and 1000 * seconds)} | "
                     f"{_label(entry.get('scaled_efficiency') and 100 * entry['scaled_efficiency'], '{:.1f}%')} | "
                     f"{_label(entry['unstable_at'])} |")
    return "\n".join(lines)


def plot_errors(summary: Dict, folder: Path, error_key: str = "relative_error", bar_key: str = "error_bar",
                ylabel: str = "relative error in configurational temperature", tag: str = "") -> List[str]:
    """|error| (the points' error_key, with bar_key as error bar) against step size and against run time."""
    names = []
    for against in ("step_size", "run_time"):
        figure, axes = plt.subplots(figsize=(6.4, 4.6))
        all_h = []
        for method, entry in summary["methods"].items():
            points = [p for p in entry["points"] if error_key in p]
            if not points:
                continue
            h = np.array([p["step_size"] for p in points])
            error = np.abs([p[error_key] for p in points])
            bar = np.array([p[bar_key] for p in points])
            x = h if against == "step_size" else entry["seconds_per_step"] / h
            axes.errorbar(x, np.maximum(error, 1e-5), yerr=bar, marker="o", ms=4, capsize=2, label=method)
            if entry["unstable_at"] is not None:
                xu = entry["unstable_at"] if against == "step_size" else entry["seconds_per_step"] / entry["unstable_at"]
                axes.plot([xu], [0.5], marker="x", ms=9, color=axes.lines[-1].get_color(), ls="none")
            all_h.extend(h)
        if against == "step_size" and all_h:
            guide = np.array([min(all_h), max(all_h)])
            axes.plot(guide, 0.1 * (guide / guide[1]) ** 2, "k--", lw=1, label="second order")
        axes.axhline(0.1, color="grey", lw=0.8, ls=":")
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_xlabel("step size" if against == "step_size" else "CPU seconds per unit of simulated time")
        axes.set_ylabel(ylabel)
        axes.set_title(f"{summary['title']} (x: unstable)")
        axes.legend(fontsize=8)
        figure.tight_layout()
        name = f"error_vs_{against}_{tag}{summary['scene']}.png"
        figure.savefig(folder / name, dpi=110)
        plt.close(figure)
        names.append(name)
    return names


def plot_rdf(summary: Dict, scene: Scene, folder: Path) -> Optional[str]:
    from openmmdpd import radial_distribution

    n = int(scene.system["num_particles"])
    volume = n / scene.system["density"]
    curves = {m: [p for p in e["points"] if "rdf_histogram" in p] for m, e in summary["methods"].items()}
    curves = {m: c for m, c in curves.items() if c}
    if not curves:
        return None
    reference_method = "ABOBA" if "ABOBA" in curves else next(iter(curves))
    reference = curves[reference_method][0]
    r, g_reference = radial_distribution(np.array(reference["rdf_histogram"]), scene.rdf_max_distance, n, volume, reference["rdf_samples"])
    figure, axes = plt.subplots(1, len(curves), figsize=(3.6 * len(curves), 3.4), sharey=True, squeeze=False)
    for axis, (method, points) in zip(axes[0], curves.items()):
        colours = plt.cm.viridis(np.linspace(0, 0.9, len(points)))
        for colour, point in zip(colours, points):
            _, g = radial_distribution(np.array(point["rdf_histogram"]), scene.rdf_max_distance, n, volume, point["rdf_samples"])
            axis.plot(r, g, color=colour, lw=1, label=f"dt = {point['step_size']:.3f}")
        axis.plot(r, g_reference, "k--", lw=1.2, label=f"reference ({reference_method}, dt = {reference['step_size']:.3f})")
        axis.set_title(method, fontsize=9)
        axis.set_xlabel("r")
    axes[0][0].set_ylabel("g(r)")
    axes[0][-1].legend(fontsize=6)
    figure.suptitle(summary["title"], fontsize=10)
    figure.tight_layout()
    name = f"rdf_{summary['scene']}.png"
    figure.savefig(folder / name, dpi=110)
    plt.close(figure)
    return name


def machine_description() -> Dict[str, object]:
    """The processor, its logical cores, the operating system, Python's and OpenMM's versions."""
    import openmm

    processor = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            processor = next(line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"processor": processor, "logical_cores": os.cpu_count(), "system": platform.platform(),
            "python": platform.python_version(), "openmm": openmm.__version__}


def legend(scenes: List[Scene]) -> List[str]:
    methods = [m for m in METHOD_DESCRIPTIONS if any(m in scene.methods for scene in scenes)]
    return [f"- **{method}**: {METHOD_DESCRIPTIONS[method]}" for method in methods]


def write_report(folder: Path, scenes: List[Scene], summaries: List[Dict], budget_name: str, threads: int,
                 elapsed: float, command: str, workers: object = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    machine = machine_description()
    opencl = [m for m in OPENCL_METHODS if any(m in scene.methods for scene in scenes)]
    platforms = "CPU platform" + (f" ({', '.join(opencl)}: OpenCL platform, double precision; on a machine without a GPU, "
                                  "OpenCL on the CPU, whose times per step say nothing about GPUs)" if opencl else "")
    parts = ["# Efficiency study: error against step size and run time", "",
             f"Command: `{command}`  ", f"Budget: **{budget_name}**; {platforms}; {threads} thread(s) per run; "
             f"wall time {elapsed / 60:.1f} min.", "",
             f"Machine: {machine['processor']}, {machine['logical_cores']} logical cores, {machine['system']}; "
             f"OpenMM {machine['openmm']}, Python {machine['python']}. Runs on a Dask cluster "
             f"({workers if isinstance(workers, str) else f'{workers} local worker process(es)'}), one run and one "
             f"OpenMM thread per worker at a time; time per step measured in one process, one thread.", "",
             "Methods:", "", *legend(scenes), "",
             "Configurational temperature (Shang 2021 eq. 3.1) measured at the positions the Context holds after a "
             "step (q^{n+1}), never at ABOBA's half-step positions. Critical step size: 10% relative error, "
             "interpolated in log-log between bracketing step sizes (or the last stable step size when a method "
             "became unstable first). Time per step: wall time of 300 steps with no observable, the methods timed in turn (A B C A B C ...), median over the rounds, "
             "one thread, measured before the sweeps. Scaled efficiency = (critical step size / time per step) "
             "relative to the reference method. Error bars: standard error over independent runs.", ""]
    for scene, summary in zip(scenes, summaries):
        parts.append(markdown_table(summary))
        parts.append("")
        for name in plot_errors(summary, folder):
            parts.append(f"![{name}]({name})")
        rdf = plot_rdf(summary, scene, folder) if "rdf" in scene.observables else None
        if rdf:
            parts.append(f"![{rdf}]({rdf})")
        parts.append("")
        if "shear_viscosity" in scene.observables:
            parts += shear_section(summary, scene, folder, plot_errors)
    claims = paper_claims(scenes, summaries)
    parts += claims_section(claims)
    (folder / "report.md").write_text("\n".join(parts))
    results = {"budget": budget_name, "threads": threads, "machine": machine,
               "methods": {m: METHOD_DESCRIPTIONS[m] for m in METHOD_DESCRIPTIONS if any(m in sc.methods for sc in scenes)},
               "scenes": summaries}
    if claims:  # the table of the paper's claims (claims.py), where the scenes hold the methods it needs
        results["claims"] = claims_json(claims)
    (folder / "results.json").write_text(json.dumps(results, indent=1))
    with open(folder / "results.csv", "w", newline="") as file:
        writer = csv.writer(file)
        # The viscosity columns are empty for scenes without shear (Table 6's quantities otherwise).
        writer.writerow(["scene", "method", "step_size", "runs", "relative_error", "error_bar", "kinetic_temperature",
                         "seconds_per_step", "unstable_at", "critical_step_size", "shear_viscosity", "shear_viscosity_error_bar",
                         "viscosity_relative_error", "viscosity_error_bar", "viscosity_critical_step_size"])
        for summary in summaries:
            for method, entry in summary["methods"].items():
                for p in entry["points"]:
                    writer.writerow([summary["scene"], method, p["step_size"], p["runs"], p.get("relative_error"), p.get("error_bar"),
                                     p.get("kinetic_temperature"), entry["seconds_per_step"], entry["unstable_at"],
                                     entry["critical_step_size"], p.get("shear_viscosity"), p.get("shear_viscosity_error_bar"),
                                     p.get("viscosity_relative_error"), p.get("viscosity_error_bar"),
                                     entry.get("viscosity", {}).get("critical_step_size")])
    return folder / "report.md"
