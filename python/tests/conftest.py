"""Shared fixtures: the repository root, the `drystone` binary (for comparisons with the
command-line tool) and small layouts whose answers are known in closed form."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    """The release binary: $DRYSTONE_BIN, else $CARGO_TARGET_DIR/release/drystone, else
    target/release/drystone; built with cargo when none exists."""
    if os.environ.get("DRYSTONE_BIN"):
        return Path(os.environ["DRYSTONE_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "release" / "drystone"
    if not exe.exists():
        cargo = shutil.which("cargo")
        assert cargo, "the comparison with the command-line tool needs the drystone binary or cargo"
        subprocess.run([cargo, "build", "--release", "--locked"], cwd=ROOT, check=True)
    return exe


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def drystone_bin() -> Path:
    exe = _binary()
    assert exe.exists(), exe
    return exe


def box_layout(x: float, y: float, z: float, kn: float = 1e11, friction_deg: float = 60.0) -> str:
    """One block `x` long, `y` deep (out of plane) and `z` tall on the table, as layout
    JSON written by hand (independent of the generator)."""
    y0 = -y / 2.0
    v = [[a, b, c] for c in (0.0, z) for b in (y0, y0 + y) for a in (0.0, x)]
    return json.dumps(
        {
            "version": 1,
            "name": "one block",
            "materials": [
                {
                    "name": "stiff",
                    "density_kg_per_m3": 2000.0,
                    "kn_pa_per_m": kn,
                    "ks_pa_per_m": kn / 2.0,
                    "friction_deg": friction_deg,
                }
            ],
            "table": {"material": "stiff"},
            "blocks": [{"id": "b0", "material": "stiff", "vertices": v}],
        }
    )
