"""openmmdpd_studies: the studies of the two papers as applications of the library ``openmmdpd``.

- :mod:`openmmdpd_studies.efficiency`: the efficiency study of Shang (2021, sec. 3), the sheared scene's
  viscosity tables and the claims about the paper's other methods
  (``python -m openmmdpd_studies.efficiency SCENE.toml ... --budget reduced --out DIR``);
- :mod:`openmmdpd_studies.transport`: transport coefficients with NEMD and stochastic Norton dynamics
  (Wu & Shang; ``python -m openmmdpd_studies.transport SCENE.toml --budget reduced --out DIR``);
- :mod:`openmmdpd_studies.padl_dynamics`: PAdL's dynamics against DPD's at the same mean friction (VACF,
  diffusion, Lees-Edwards viscosity), claim 9 of the claims table
  (``python -m openmmdpd_studies.padl_dynamics --out DIR``);
- :mod:`openmmdpd_studies.resumable_runs`: the runs of either study on a Dask cluster, saved as they
  finish so that a killed study resumes.

The studies import the library; the library imports none of them (``import openmmdpd`` needs neither
this package nor its dependencies: SciPy, Matplotlib, Dask and tqdm)."""
