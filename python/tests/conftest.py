"""What the tests share: the command line built from this checkout."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli() -> Path:
    """The command line, built from this checkout (or the binary
    ``FAIRSURF_CLI`` names: CI's, which ``cargo test`` built)."""
    given = os.environ.get("FAIRSURF_CLI")
    if given:
        assert Path(given).is_file(), f"FAIRSURF_CLI={given}: no such file"
        return Path(given)
    subprocess.run(
        ["cargo", "build", "-q", "-p", "fairsurf-cli"], cwd=ROOT, check=True
    )
    return ROOT / "target" / "debug" / "fairsurf"
