"""Robustness campaigns, the TOML that ``neurotree campaign run`` reads, run from Python: on
this machine's cores, or as shards on a Ray cluster.

    campaign = nt.Campaign.load("campaigns/single_faults.toml")
    campaign.run("results.db")                      # every core here
    campaign.run("results.db", executor="ray")      # shards as Ray tasks
    campaign.run("results.db", ray_address="ray://head:10001")

Each variant runs in Rust with the GIL released, and its row goes into the SQLite file
``db`` as ``neurotree campaign run --db`` writes it (``neurotree campaign report`` reads
it). With Ray, each task runs its shard into a file of its own and sends the file back;
the rows are merged into ``db``, which therefore equals a local run row for row. A
campaign that names a tree file needs that file at the same path on every Ray node; one
on Nav2's navigator (the default) needs nothing but the package.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, List, Optional, Union

from . import _native

__all__ = ["Campaign"]

PathLike = Union[str, "os.PathLike[str]"]


def _run_shard(text: str, file: str, variants: List[int], threads: int) -> bytes:
    """Runs `variants` of the campaign `text` into a fresh results file: its bytes."""
    campaign = _native.Campaign.parse(text, file)
    with tempfile.TemporaryDirectory(prefix="neurotree-shard-") as folder:
        db = os.path.join(folder, "shard.db")
        campaign.run_variants(db, variants, threads)
        with open(db, "rb") as f:
            return f.read()


class Campaign:
    """A campaign file, read and checked (a bad file raises ValueError naming its line and
    column)."""

    def __init__(self, native: Any) -> None:
        self._native = native

    @staticmethod
    def load(path: PathLike) -> "Campaign":
        """Reads the campaign file at ``path``."""
        return Campaign(_native.Campaign.load(os.fspath(path)))

    @property
    def name(self) -> str:
        """Its name (the file's stem unless it says)."""
        return str(self._native.name)

    @property
    def variants(self) -> int:
        """How many variants it has."""
        return int(self._native.variants)

    def run(
        self,
        db: PathLike,
        *,
        executor: str = "local",
        ray_address: Optional[str] = None,
        limit: Optional[int] = None,
        threads: int = 0,
        shards: Optional[int] = None,
        resume: bool = False,
    ) -> int:
        """Runs the first ``limit`` variants (all by default) that ``db`` does not hold yet;
        the number run.

        ``executor="local"`` runs them here on ``threads`` threads (0: every core);
        ``executor="ray"`` (or any ``ray_address``, which ``ray.init`` is given) sends
        ``shards`` shards (by default twice the cluster's CPUs) to Ray tasks, each running
        its variants on ``threads`` threads (default 1), and merges their rows into ``db``.
        A ``db`` that holds some of the variants already is refused unless ``resume``.
        """
        db = os.fspath(db)
        todo: List[int] = list(self._native.todo(db, limit, resume))
        if executor == "local" and ray_address is None:
            self._native.run_variants(db, todo, threads)
            return len(todo)
        if executor not in ("ray", "local"):
            raise ValueError(f"executor is 'local' or 'ray', not {executor!r}")
        import ray  # an optional dependency: `pip install ray`

        if not ray.is_initialized():
            ray.init(address=ray_address, ignore_reinit_error=True)
        cpus = ray.cluster_resources().get("CPU", 1)  # type: ignore[no-untyped-call]
        count = shards or max(1, 2 * int(cpus))
        parts = [todo[i::count] for i in range(count) if todo[i::count]]
        task = ray.remote(_run_shard)
        text, file = str(self._native.text), os.fspath(self._native.file)
        futures = [task.remote(text, file, part, threads or 1) for part in parts]
        with tempfile.TemporaryDirectory(prefix="neurotree-merge-") as folder:
            paths = []
            for i, data in enumerate(ray.get(futures)):
                path = Path(folder) / f"shard{i}.db"
                path.write_bytes(data)
                paths.append(os.fspath(path))
            _native._merge_campaign_results(paths, db)
        return len(todo)
