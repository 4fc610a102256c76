"""``neurotree.Campaign``: a campaign run from Python equals ``neurotree campaign run``'s row
for row, locally and as shards on a local Ray cluster (127.0.0.1)."""

from __future__ import annotations

import os
import pathlib
import sqlite3

import pytest

import neurotree as nt

CAMPAIGN = """
name = "python"
seed = 5
sample = 8
max_ticks = 600
[factors]
goal = ["20.5,6.5", "15.5,2.5"]
seed = { from = 0, to = 3 }
faults = ["none", "ComputePathToPose=FAILURE@1#106", "FollowPath=FAILURE@2"]
"""


def rows(db: pathlib.Path) -> list[tuple[object, ...]]:
    with sqlite3.connect(db) as conn:
        return list(conn.execute("SELECT * FROM variants ORDER BY variant"))


@pytest.fixture
def campaign(tmp_path: pathlib.Path) -> nt.Campaign:
    file = tmp_path / "python.toml"
    file.write_text(CAMPAIGN, encoding="utf-8")
    return nt.Campaign.load(file)


def test_a_local_run_writes_one_row_per_variant_and_refuses_to_repeat(
    campaign: nt.Campaign, tmp_path: pathlib.Path
) -> None:
    db = tmp_path / "local.db"
    assert campaign.variants == 8
    assert campaign.run(db, limit=5, threads=2) == 5
    first = rows(db)
    assert [r[0] for r in first] == [1, 2, 3, 4, 5]
    assert {r[2] for r in first} <= {"SUCCESS", "FAILURE"}
    with pytest.raises(ValueError, match="--resume"):
        campaign.run(db)
    assert campaign.run(db, resume=True, threads=1) == 3
    assert rows(db)[:5] == first
    assert len(rows(db)) == 8


def test_a_bad_file_names_its_line_and_column(tmp_path: pathlib.Path) -> None:
    file = tmp_path / "bad.toml"
    file.write_text("grid = true\n[factors]\nseed = [-1]\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"bad.toml:3:8: error: a seed is a whole number"):
        nt.Campaign.load(file)


def test_shards_on_a_local_ray_cluster_give_the_local_rows(
    campaign: nt.Campaign, tmp_path: pathlib.Path
) -> None:
    if os.environ.get("NEUROTREE_REQUIRE_RAY"):
        import ray  # CI installs it: the test must run, not skip
    else:
        ray = pytest.importorskip("ray")
    local = tmp_path / "local.db"
    campaign.run(local, threads=1)
    ray.init(address="local", num_cpus=2, include_dashboard=False, _node_ip_address="127.0.0.1")
    try:
        clustered = tmp_path / "ray.db"
        assert campaign.run(clustered, executor="ray", shards=3) == 8
    finally:
        ray.shutdown()
    assert rows(clustered) == rows(local)
