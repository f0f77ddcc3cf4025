"""Shared fixtures: tiny render options, the repository's CLI binary, a Dask cluster."""

from __future__ import annotations

import logging
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

#: Small enough that every render in the suite takes milliseconds, large
#: enough to have several tiles and every effect of the showcase scene.
SMALL = {"width": 48, "height": 32, "spp": 4}


@pytest.fixture(scope="session")
def small() -> dict:
    return dict(SMALL)


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `penumbra` binary of this repository, built from the same library
    sources as the extension (a no-op after `cargo test --release`)."""
    subprocess.run(
        ["cargo", "build", "--release", "--quiet", "-p", "penumbra-cli"], cwd=REPO, check=True
    )
    # Where cargo put it: $CARGO_TARGET_DIR when set (relative to the
    # repository, as cargo takes it), else the workspace's target/.
    target = REPO / os.environ.get("CARGO_TARGET_DIR", "target")
    return target / "release" / "penumbra"


@pytest.fixture(scope="session")
def client():
    """Two single-threaded worker processes, as on two machines."""
    import distributed

    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    ) as cluster, distributed.Client(cluster) as c:
        yield c
