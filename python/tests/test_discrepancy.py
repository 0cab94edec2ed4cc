"""The discrepancy analysis and the effect library from Python, against the command-line
tool's JSON and the README's list of effects."""

from __future__ import annotations

import json
import subprocess

import pytest

import drystone

# Small settings: seconds, not minutes (too small for a verdict to mean much).
SETTINGS = """
[discrepancy]
realizations = 2
extension_realizations = 3
null_realizations = 3
grid_points = 2
null_replicates = 20
check_replicates = 20
bootstrap = 100
effects = ["initial_lean"]
scatter = false
confirm = false
sigma = { angle_deg = 0.25, displacement_cm = 0.005 }
reading = { angle_deg = 0.25, displacement_cm = 0.01 }
"""


def _study(tmp_path, root, angles=((26.0, 33.5), (25.75, 34.0), (26.25, 33.0), (25.5, 34.5))):
    walls = root / "tests" / "discrepancy" / "walls"
    lines = ["specimen,group,collapse_angle_deg"]
    for i, (free, held) in enumerate(angles):
        lines += [f"FREE{i},FREE,{free}", f"HELD{i},HELD,{held}"]
    (tmp_path / "collapse.csv").write_text("\n".join(lines) + "\n")
    study = tmp_path / "study.toml"
    study.write_text(
        f"""version = 1
name = "small_walls_py"
seed = 7
realizations = 2
protocol = "tilt"
[tilt]
step_deg = 1.0
resolution_deg = 0.25
[[groups]]
name = "FREE"
wall = {json.dumps(str(walls / "small_free.toml"))}
[[groups]]
name = "HELD"
wall = {json.dumps(str(walls / "small_restrained.toml"))}
[measured]
collapse = "collapse.csv"
"""
        + SETTINGS
    )
    return study


def test_the_verdict_is_the_command_line_verdict(tmp_path, root, drystone_bin):
    study = _study(tmp_path, root)
    cli = subprocess.run(
        [str(drystone_bin), "discrepancy", str(study), "--json", "--out", str(tmp_path / "cli")],
        check=True,
        capture_output=True,
        text=True,
    )
    expected = json.loads(cli.stdout)
    got = drystone.discrepancy(study, out=tmp_path / "py")
    assert got.verdict in {"explained", "no_effect", "unexplained"}
    assert got.verdict == expected["verdict"]
    assert got.to_dict() == expected
    assert got.cause == (expected["cause"]["name"] if expected["cause"] else None)
    assert [c["name"] for c in got.candidates] == [c["name"] for c in expected["candidates"]]
    assert (tmp_path / "py" / "discrepancy.md").exists() or any((tmp_path / "py").iterdir())


def test_settings_are_checked_by_key(tmp_path, root):
    study = _study(tmp_path, root)
    with pytest.raises(drystone.InputError) as e:
        drystone.discrepancy(study, null_replicate=5)
    assert e.value.key == "null_replicate"
    with pytest.raises(drystone.InputError) as e:
        drystone.discrepancy(study, effects=["no_such_effect"])
    assert "no_such_effect" in str(e.value)


def test_bad_measured_data_names_file_line_and_column(tmp_path, root):
    study = _study(tmp_path, root, angles=((26.0, 33.5), (95.0, 34.0)))
    with pytest.raises(drystone.InputError) as e:
        drystone.discrepancy(study)
    assert e.value.file == str(tmp_path / "collapse.csv")
    assert (e.value.line, e.value.key) == (4, "collapse_angle_deg")


def test_the_effect_library_lists_the_readme_effects_with_their_parameters(root):
    readme = (root / "README.md").read_text()
    named = [
        "kn_scale",
        "base_stiffness",
        "bed_stiffness",
        "head_stiffness",
        "joint_closure",
        "seating_gap",
        "initial_lean",
        "edge_rounding",
        "restraint_stiffness",
        "transverse_dip",
    ]
    assert all(f"`{n}`" in readme for n in named)
    lib = {e.name: e for e in drystone.effects()}
    assert set(named) <= set(lib)
    for e in lib.values():
        assert e.description and 1 <= len(e.parameters) <= 2, e.name
        assert set(e.stages) <= {"layout", "joint_law", "restraints"} and e.stages, e.name
        for p in e.parameters:
            assert p["min"] < p["max"] and p["unit"] is not None and p["scale"] in ("linear", "log"), (e.name, p)
