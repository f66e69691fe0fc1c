"""What the tests share: the command line built from this checkout."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli() -> Path:
    """The command line, built from this checkout."""
    subprocess.run(
        ["cargo", "build", "-q", "-p", "fairsurf-cli"], cwd=ROOT, check=True
    )
    return ROOT / "target" / "debug" / "fairsurf"
