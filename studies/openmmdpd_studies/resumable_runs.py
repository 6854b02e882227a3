"""Independent runs of a study on a Dask cluster, each saved to the output folder as it finishes, so
that re-running the same command skips what is done (a killed study resumes).

The studies (``python -m openmmdpd_studies.efficiency``, ``python -m openmmdpd_studies.transport``)
hand their runs to :func:`run_resumable`.  By default a ``dask.distributed.LocalCluster`` of
``--workers`` processes (one thread each) runs them; ``--scheduler ADDRESS`` sends them to a cluster
the user already runs (for example one started by ``dask-jobqueue`` on SLURM).  Each run carries its
own seed, so results do not depend on the number of workers or on the order in which runs finish.  A
saved run is reused only when its function, arguments (scene, budget, seed) and the installed code
(the library's, compiled plugin included, and the studies') are the same.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import hashlib
import json
import logging
import os
import sys
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple

from tqdm import tqdm

import openmmdpd

#: A run: the function, its arguments (picklable: they travel to the workers).
Run = Tuple[Callable[..., Any], Tuple[Any, ...]]


def add_cluster_arguments(parser: argparse.ArgumentParser, default_workers: int = 2) -> None:
    """Add ``--workers N`` and ``--scheduler ADDRESS`` to a study's command line."""
    parser.add_argument("--workers", type=int, default=default_workers,
                        help="worker processes of the local Dask cluster, one run (one thread) each")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="address of a running Dask scheduler (e.g. tcp://host:8786) to use instead of a local cluster")


@contextlib.contextmanager
def dask_client(workers: int, scheduler: Optional[str] = None) -> Iterator["distributed.Client"]:  # noqa: F821
    """A client of the scheduler at ``scheduler``, or of a new LocalCluster of ``workers`` processes
    with one thread each (closed on exit)."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers = {workers!r} is out of range; it must be an integer >= 1")
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        yield client


def code_files() -> List[Tuple[str, Path]]:
    """The files whose code a run's result depends on, each with the name it is digested under: the
    Python files and compiled libraries of the installed library ``openmmdpd`` and of this package."""
    files = []
    for package in (Path(openmmdpd.__file__).resolve().parent, Path(__file__).resolve().parent):
        for path in sorted(package.rglob("*")):
            if path.is_file() and path.suffix in (".py", ".so"):
                files.append((f"{package.name}/{path.relative_to(package)}", path))
    return files


@functools.lru_cache(maxsize=None)
def code_digest() -> str:
    """A digest of :func:`code_files`: results saved by another build of openmmdpd or another version
    of the studies are not reused."""
    digest = hashlib.sha256()
    for name, path in code_files():
        digest.update(name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def fingerprint(run: Run) -> str:
    """A digest of a run's function and arguments (dataclasses and numbers have stable reprs) and of
    the installed code: a saved result is reused only for the same run by the same build."""
    function, arguments = run
    text = f"{code_digest()}:{function.__module__}.{function.__qualname__}{arguments!r}"
    return hashlib.sha256(text.encode()).hexdigest()


def _load(path: Path, digest: str) -> Optional[Any]:
    try:
        saved = json.loads(path.read_text())
    except (OSError, ValueError):
        return None  # absent, or cut short by a kill before the rename (cannot happen) or by a full disk
    return saved["result"] if saved.get("fingerprint") == digest else None


def _save(path: Path, digest: str, encoded: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    partial.write_text(json.dumps({"fingerprint": digest, "result": encoded}))
    os.replace(partial, path)  # atomic: a file under its final name is always complete


def run_resumable(client: "distributed.Client", runs: Dict[str, Run], folder: Path,  # noqa: F821
                  encode: Callable[[Any], Any], decode: Callable[[Any], Any], description: str) -> List[Any]:
    """Run every ``runs[name]`` not yet saved in ``folder`` on the cluster; save each result as
    ``folder/<name>.json`` as soon as it finishes; return all results in the order of ``runs``.

    ``encode`` turns a result into JSON-able data and ``decode`` turns it back; JSON keeps floats
    exactly, so a resumed study computes the same numbers as an uninterrupted one.
    """
    from dask.distributed import as_completed

    digests = {name: fingerprint(run) for name, run in runs.items()}
    paths = {name: folder / f"{name}.json" for name in runs}
    encoded: Dict[str, Any] = {}
    for name in runs:
        saved = _load(paths[name], digests[name])
        if saved is not None:
            encoded[name] = saved
    missing = [name for name in runs if name not in encoded]
    if encoded:
        print(f"{description}: resuming, {len(encoded)} of {len(runs)} runs already done in {folder}", file=sys.stderr)
    futures = {client.submit(runs[name][0], *runs[name][1], key=f"{name.replace('/', '.')}-{digests[name][:16]}", pure=False): name
               for name in missing}
    with tqdm(total=len(runs), initial=len(encoded), desc=description, file=sys.stderr) as progress:
        for future in as_completed(list(futures)):
            name = futures[future]
            encoded[name] = encode(future.result())
            _save(paths[name], digests[name], encoded[name])
            future.release()
            progress.update()
    return [decode(encoded[name]) for name in runs]
