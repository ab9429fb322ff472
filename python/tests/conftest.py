"""Shared fixtures: the `strider` command built by cargo, to compare the package with it."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _strider_bin():
    if os.environ.get("STRIDER_BIN"):
        return Path(os.environ["STRIDER_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        p = target / profile / "strider"
        if p.is_file():
            return p
    found = shutil.which("strider")
    return Path(found) if found else None


@pytest.fixture(scope="session")
def strider_cli():
    """Runs the `strider` command (STRIDER_BIN, or the one cargo built) and returns its stdout."""
    exe = _strider_bin()
    if exe is None or not exe.is_file():
        pytest.fail(
            "no `strider` binary: run `cargo build -p strider-cli` (or set STRIDER_BIN) first"
        )

    def run(*args):
        p = subprocess.run(
            [str(exe), *map(str, args)], capture_output=True, text=True, timeout=900
        )
        assert p.returncode == 0, f"strider {' '.join(map(str, args))}: {p.stderr}"
        return p.stdout

    return run
