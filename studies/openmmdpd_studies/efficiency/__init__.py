"""The efficiency study of Shang (2021, sec. 3): error in the configurational temperature against
step size and against run time, for the plugin's schemes and OpenMM's own DPDIntegrator, from
declarative scene files.  Run it with ``python -m openmmdpd_studies.efficiency SCENE.toml ... --budget reduced``."""

from .scene import Budget, Scene, load_scene

__all__ = ["Budget", "Scene", "load_scene"]
