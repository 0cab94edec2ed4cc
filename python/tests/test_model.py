"""Walls, layouts, the tilting table and the lateral load from Python, against closed forms,
the wall files read independently (tomllib) and the command-line tool."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import drystone
from conftest import box_layout

tomllib = pytest.importorskip("tomllib") if sys.version_info >= (3, 11) else None


def test_generate_is_seeded_and_layouts_round_trip_through_json(root):
    wall = drystone.Wall.from_toml(root / "studies/walls/sbl.toml")
    a = wall.generate(seed=20210917, realization=0)
    again = wall.generate(seed=20210917, realization=0)
    other = wall.generate(seed=20210917, realization=1)
    assert a == again and a.to_json() == again.to_json()
    assert a.to_json() != other.to_json(), "irregular walls differ from one realization to the next"
    assert (a.seed, a.realization) == (20210917, 0)
    back = drystone.Layout.from_json(a.to_json())
    assert back == a and back.to_json() == a.to_json()
    assert back.seed is None
    # The arrays describe the same blocks as the JSON text.
    spec = json.loads(a.to_json())
    assert a.block_ids == [b["id"] for b in spec["blocks"]]
    assert a.materials == [b["material"] for b in spec["blocks"]]
    assert len(a) == len(spec["blocks"]) == len(a.vertices)
    for arr, b in zip(a.vertices, spec["blocks"]):
        assert arr.shape == (len(b["vertices"]), 3) and arr.dtype == np.float64
        assert np.array_equal(arr, np.array(b["vertices"]))
    off = a.vertex_offsets
    assert off[0] == 0 and off[-1] == a.vertices_flat.shape[0]
    assert np.array_equal(a.vertices_flat[off[3] : off[4]], a.vertices[3])
    assert a.wedge.dtype == np.bool_ and a.wedge.shape == (len(a),)
    assert a.wedge.any(), "the SBL wall has wedge stones"


def test_a_layout_saved_to_a_file_reads_back(tmp_path, root):
    layout = drystone.Wall.from_toml(root / "studies/walls/cbl.toml").generate(seed=1)
    layout.save(tmp_path / "l.json")
    assert drystone.Layout.from_file(tmp_path / "l.json") == layout


@pytest.mark.skipif(tomllib is None, reason="tomllib is Python 3.11+")
def test_the_envelope_of_the_generated_blocks_is_the_wall_file_geometry(root):
    path = root / "studies/walls/cbl.toml"
    with open(path, "rb") as f:
        geometry = tomllib.load(f)["geometry"]
    wall = drystone.Wall.from_toml(path)
    assert (wall.length_m, wall.height_m) == (geometry["length_m"], geometry["height_m"])
    b = wall.generate(seed=20210917).bounds
    assert b.shape == (2, 3)
    assert b[1, 0] - b[0, 0] == pytest.approx(geometry["length_m"], abs=1e-9)
    assert b[1, 1] - b[0, 1] == pytest.approx(geometry["base_width_m"], abs=1e-9)
    assert b[0, 2] == pytest.approx(0.0, abs=1e-12) and b[1, 2] == pytest.approx(geometry["height_m"], abs=1e-9)


@pytest.mark.skipif(tomllib is None, reason="tomllib is Python 3.11+")
def test_a_wall_from_a_dict_is_the_wall_of_the_file(root):
    path = root / "studies/walls/sbl.toml"
    with open(path, "rb") as f:
        spec = tomllib.load(f)
    from_dict = drystone.Wall.from_dict(spec, path=path)
    from_file = drystone.Wall.from_toml(path)
    assert from_dict.generate(5, 2).to_json() == from_file.generate(5, 2).to_json()
    spec["geometry"]["lenght_m"] = spec["geometry"].pop("length_m")
    with pytest.raises(drystone.InputError) as e:
        drystone.Wall.from_dict(spec, path=path)
    assert e.value.key == "lenght_m" and "lenght_m" in str(e.value)


def test_a_bad_wall_file_names_its_file_key_and_line(tmp_path, root):
    text = (root / "studies/walls/cbl.toml").read_text()
    assert "length_m = 1.5" in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("length_m = 1.5", "lenght_m = 1.5", 1))
    with pytest.raises(drystone.InputError) as e:
        drystone.Wall.from_toml(bad)
    line = 1 + text[: text.index("length_m = 1.5")].count("\n")
    assert (e.value.file, e.value.key, e.value.line) == (str(bad), "lenght_m", line)
    assert isinstance(e.value, drystone.DrystoneError)
    bad.write_text(text.replace("length_m = 1.5", "length_m = -1.5", 1))
    with pytest.raises(drystone.InputError) as e:
        drystone.Wall.from_toml(bad)
    assert e.value.key == "geometry.length_m" and str(bad) in str(e.value)
    with pytest.raises(drystone.InputError) as e:
        drystone.Wall.from_toml(tmp_path / "missing.toml")
    assert e.value.file == str(tmp_path / "missing.toml")


def test_bad_layouts_and_parameters_are_input_errors():
    with pytest.raises(drystone.InputError) as e:
        drystone.Layout.from_json(box_layout(0.3, 0.1, 0.3).replace('"friction_deg"', '"frictoin_deg"'))
    assert e.value.key == "frictoin_deg"
    with pytest.raises(drystone.InputError) as e:
        drystone.Layout.from_json(box_layout(0.3, 0.1, 0.3).replace("1e+11", "-1e+11").replace("100000000000.0", "-1e11"))
    assert "kn_pa_per_m" in e.value.key
    layout = drystone.Layout.from_json(box_layout(0.3, 0.1, 0.3))
    with pytest.raises(drystone.InputError) as e:
        drystone.tilt(layout, stepdeg=1.0)
    assert e.value.key == "stepdeg"
    with pytest.raises(drystone.InputError) as e:
        drystone.tilt(layout, step_deg=-1.0)
    assert "step_deg" in str(e.value)
    with pytest.raises(drystone.InputError):
        drystone.tilt(layout, solver="no_such_solver")


def test_the_former_penalty_keys_of_a_tilt_warn_and_run_as_the_solvers_own():
    # `tolerance`, `max_steps_per_increment` and `predictor` moved to the solver's `penalty`
    # dict; given as tilt parameters they still set it, with a DeprecationWarning.
    layout = drystone.Layout.from_json(box_layout(0.3, 0.1, 0.3, kn=1e8))
    with pytest.warns(DeprecationWarning) as record:
        old = drystone.tilt(layout, step_deg=2.0, resolution_deg=0.5, tolerance=1e-6, predictor=False)
    said = sorted(str(w.message).split(" is deprecated")[0] for w in record)
    assert said == ["tilt.predictor", "tilt.tolerance"]
    assert all("solver.penalty" in str(w.message) for w in record)
    new = drystone.tilt(
        layout, solver={"penalty": {"tolerance": 1e-6, "predictor": False}}, step_deg=2.0, resolution_deg=0.5
    )
    default = drystone.tilt(layout, step_deg=2.0, resolution_deg=0.5)
    assert old.collapse_angle_deg == new.collapse_angle_deg
    assert np.array_equal(old.displacement_m, new.displacement_m)
    assert np.array_equal(old.increment_steps, new.increment_steps)
    assert not np.array_equal(old.increment_steps, default.increment_steps)


def test_a_block_that_cannot_stand_is_a_solver_error():
    # A block floating 1 cm above the table touches nothing.
    text = json.loads(box_layout(0.3, 0.1, 0.3))
    for v in text["blocks"][0]["vertices"]:
        v[2] += 0.01
    with pytest.raises(drystone.SolverError):
        drystone.tilt(drystone.Layout.from_json(json.dumps(text)))


def test_a_stiff_block_topples_at_the_rigid_limit_less_its_elastic_rotation(tmp_path, drystone_bin):
    # 0.1125 m deep (y), 0.375 m tall: rigid limit tan α = 0.1125 / 0.375 = 0.3, 16.699°;
    # the no-tension Winkler base joint (Kn 1e11 Pa/m) lowers it to 16.31° (drystone verify).
    layout = drystone.Layout.from_json(box_layout(0.3, 0.1125, 0.375))
    res = drystone.tilt(layout, resolution_deg=0.0625)
    rigid = math.degrees(math.atan(0.1125 / 0.375))
    assert res.collapsed and res.first_unstable_deg - res.last_stable_deg <= 0.0625 + 1e-9
    assert res.last_stable_deg <= 16.31 + 0.02 and res.first_unstable_deg >= 16.31 - 0.02
    assert res.last_stable_deg < rigid
    assert res.collapse_angle_deg == res.last_stable_deg and res.bracket_reliable
    assert str(res.mechanism) == res.mechanism.kind == "toppling"
    assert res.mechanism.joint == "table/b0" and res.mechanism.blocks == ["b0"]
    n = len(res.alpha_deg)
    assert res.monitors == ["top_left", "top_centre", "top_right"]
    assert res.displacement_m.shape == (n, 3) and res.stable.shape == (n,)
    assert res.alpha_deg[0] == 0.0 and np.all(res.displacement_m[0] == 0.0)
    stable = res.alpha_deg[res.stable]
    assert np.all(np.diff(stable) > 0) and stable[-1] == res.last_stable_deg
    # The same numbers as the command-line tool, to the last digit.
    path = tmp_path / "block.json"
    layout.save(path)
    cli = subprocess.run(
        [str(drystone_bin), "tilt", str(path), "--json", "--resolution-deg", "0.0625"],
        check=True,
        capture_output=True,
        text=True,
    )
    expected = json.loads(cli.stdout)
    got = res.to_dict()
    keys = ("last_stable_deg", "first_unstable_deg", "collapse_reason", "bracket_reliable", "mechanism", "increments")
    for key in keys + ("steps", "dt_s"):
        assert got[key] == expected[key], key
    assert res.collapse_angle_deg == expected["collapse_angle_deg"]


def test_a_table_rolled_by_hand_equals_the_command_line(tmp_path, drystone_bin):
    # A slender block (0.1 m deep, 0.3 m tall) on a table rolled in 2-degree stops: the
    # kicks topple it at or below its static angle atan(1/3) = 18.43 deg.
    layout = drystone.Layout.from_json(box_layout(0.2, 0.1, 0.3))
    hand = {"increment_deg": 2.0, "rate_deg_per_s": 4.0, "ramp_s": 0.05, "hold_s": 0.3}
    res = drystone.tilt(layout, solver="nscd", by_hand=hand)
    assert res.first_unstable_deg is not None and res.collapse_angle_deg <= 18.44
    path = tmp_path / "slender.json"
    layout.save(path)
    cli = subprocess.run(
        [str(drystone_bin), "tilt", str(path), "--json", "--solver", "nscd", "--by-hand",
         "--hand-increment-deg", "2", "--hand-rate-deg-s", "4", "--hand-ramp-s", "0.05", "--hand-hold-s", "0.3"],
        check=True,
        capture_output=True,
        text=True,
    )
    expected = json.loads(cli.stdout)
    assert expected["by_hand"]["increment_deg"] == 2.0
    got = res.to_dict()
    for key in ("last_stable_deg", "first_unstable_deg", "collapse_reason", "mechanism", "increments", "steps"):
        assert got[key] == expected[key], key
    with pytest.raises(drystone.InputError, match="nscd"):
        drystone.tilt(layout, by_hand=True)
    with pytest.raises(drystone.InputError, match="ramp_s"):
        drystone.tilt(layout, solver="nscd", by_hand={"ramp_s": 0.0})


def test_a_uniform_pressure_has_its_closed_form_resultant():
    # 1 kPa on the −y face of a block 0.4 m long and 0.3 m tall: 120 N in +y.
    layout = drystone.Layout.from_json(box_layout(0.4, 0.15, 0.3))
    res = drystone.lateral(layout, pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert res.equilibrium and res.collapse_reason is None
    assert res.resultant_n.shape == (3,)
    assert abs(res.resultant_n[1]) == pytest.approx(1000.0 * 0.4 * 0.3, rel=1e-9)
    assert res.weight_n == pytest.approx(2000.0 * 0.4 * 0.15 * 0.3 * 9.81, rel=1e-9)
    assert res.displacement_m.shape == (3,)
    assert res.drift == pytest.approx(res.max_displacement_m / res.height_m, rel=1e-12)
    assert res.to_dict()["equilibrium"] is True


def test_a_block_pushed_over_collapses_below_its_rigid_statics(tmp_path, drystone_bin):
    # 1 kPa on the −y face of a block 0.4 m long, 0.2 m deep and 0.6 m tall (ρ 2000, Kn
    # 1e10 Pa/m): rigid overturning about the toe at λ = W B / (p L h²) = 1.308; the
    # no-tension joint's closure under the toe lowers it by a few per cent.
    layout = drystone.Layout.from_json(box_layout(0.4, 0.2, 0.6, kn=1e10))
    res = drystone.pushover(layout, pressure_base_pa=1000.0, pressure_top_pa=1000.0, pushover_resolution=0.005)
    rigid = 2000.0 * 0.4 * 0.2 * 0.6 * 9.81 * 0.2 / (1000.0 * 0.4 * 0.6**2)
    assert res.collapsed and res.collapse_reason is not None
    assert 0.9 * rigid < res.lambda_stable < res.lambda_unstable < rigid
    assert res.lambda_unstable - res.lambda_stable <= 0.005 * res.lambda_unstable + 1e-12
    assert res.mechanism is not None and str(res.mechanism) == "toppling"
    n = len(res.load_multiplier)
    assert res.stable.shape == (n,) and res.displacement_m.shape == (n, 3)
    assert res.load_multiplier[res.stable].max() == res.lambda_stable
    # The same bracket as the command-line tool.
    path = tmp_path / "block.json"
    layout.save(path)
    cli = subprocess.run(
        [str(drystone_bin), "lateral", str(path), "--pushover", "--json", "--pushover-resolution", "0.005",
         "--pressure-base-pa", "1000", "--pressure-top-pa", "1000"],
        check=True,
        capture_output=True,
        text=True,
    )
    expected = json.loads(cli.stdout)
    assert (res.lambda_stable, res.lambda_unstable) == (expected["lambda_stable"], expected["lambda_unstable"])
    # The service test does not run a pushover silently.
    with pytest.raises(drystone.InputError) as e:
        drystone.lateral(layout, pushover=True)
    assert e.value.key == "pushover"


def test_the_gil_is_released_while_a_wall_is_tilted(root):
    # A Python thread keeps counting while the tilting-table test runs: with the GIL held it
    # could not run for the whole test (seconds), only in the switch intervals around it.
    import threading
    import time

    layout = drystone.Wall.from_toml(root / "studies/walls/sbl.toml").generate(seed=20210917)
    count, stop = [0], [False]

    def spin():
        while not stop[0]:
            count[0] += 1

    t = threading.Thread(target=spin)
    t.start()
    time.sleep(0.05)
    before = count[0]
    t0 = time.perf_counter()
    res = drystone.tilt(layout)
    elapsed = time.perf_counter() - t0
    during = count[0] - before
    stop[0] = True
    t.join()
    assert res.collapsed and elapsed > 0.2
    assert during > 100_000, (during, elapsed)


def test_supports_is_the_table_the_solvers_follow():
    """`drystone.supports` answers as the runs do: a refused pair is refused by the run with
    the same reason, an accepted one runs; unknown names are input errors."""
    assert drystone.supports("tilt", "limit") == (True, "")
    runs, why = drystone.supports("tilt_by_hand", "penalty")
    assert not runs and "nscd" in why
    layout = drystone.Layout.from_json(box_layout(0.2, 0.1, 0.2))
    with pytest.raises(drystone.InputError) as e:
        drystone.tilt(layout, solver="penalty", by_hand={"increment_deg": 5.0})
    assert why in str(e.value)
    runs, why = drystone.supports("shake", "relaxation")
    assert not runs and "cascade of static solves" in why
    assert drystone.supports("pushover", "nscd")[0]
    with pytest.raises(drystone.InputError):
        drystone.supports("tilting", "penalty")
    with pytest.raises(drystone.InputError):
        drystone.supports("tilt", "rigid")


SOLVERS = ("penalty", "newton", "implicit", "accelerated", "relaxation", "nscd", "limit")


def test_every_solver_supports_admits_runs_and_every_other_is_refused_with_its_reason():
    """`drystone.supports(protocol, solver)` is what the functions do, pair by pair: an
    admitted solver runs (limit analysis too), a refused one raises the reason `supports`
    gives."""
    layout = drystone.Layout.from_json(box_layout(0.2, 0.1, 0.2))
    runs = {
        "tilt": lambda k: drystone.tilt(layout, solver=k, step_deg=2.0, resolution_deg=1.0),
        "lateral": lambda k: drystone.lateral(layout, solver=k, pressure_base_pa=100.0, pressure_top_pa=100.0),
        "pushover": lambda k: drystone.pushover(
            layout, solver=k, pressure_base_pa=1000.0, pressure_top_pa=1000.0, pushover_resolution=0.1
        ),
    }
    for protocol, run in runs.items():
        for k in SOLVERS:
            admitted, why = drystone.supports(protocol, k)
            if admitted:
                run(k)
            else:
                with pytest.raises(drystone.DrystoneError) as e:
                    run(k)
                assert why in str(e.value), (protocol, k)


def test_the_tilting_table_and_the_lateral_load_by_limit_analysis():
    """`tilt(solver="limit")`: α_max = atan λ at the rigid limit b / h, the command line's to
    the last digit; `lateral(solver="limit")`: whether λ reaches 1."""
    layout = drystone.Layout.from_json(box_layout(0.3, 0.1125, 0.375))
    res = drystone.tilt(layout, solver="limit")
    rigid = math.degrees(math.atan(0.1125 / 0.375))
    assert res.collapse_angle_deg == pytest.approx(rigid, rel=1e-4)
    assert res.last_stable_deg == res.first_unstable_deg == res.collapse_angle_deg
    assert res.collapsed and res.collapse_reason == "no_equilibrium" and str(res.mechanism) == "toppling"
    assert len(res.alpha_deg) == 0 and res.displacement_m.shape == (0, 0)
    assert res.to_dict()["limit_analysis"]["load_multiplier"] == pytest.approx(0.3, rel=1e-4)
    # λ = W B / (p L h²) = 1.308 at 1 kPa (the pushover's block): carried; at 2 kPa not.
    block = drystone.Layout.from_json(box_layout(0.4, 0.2, 0.6))
    held = drystone.lateral(block, solver="limit", pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert held.equilibrium and held.collapse_reason is None and held.max_displacement_m is None
    assert held.resultant_n[1] == pytest.approx(1000.0 * 0.4 * 0.6, rel=1e-9)
    fell = drystone.lateral(block, solver="limit", pressure_base_pa=2000.0, pressure_top_pa=2000.0)
    assert not fell.equilibrium and fell.collapse_reason == "no_equilibrium"


def test_the_tilting_table_by_limit_analysis_is_the_command_lines(tmp_path, drystone_bin):
    layout = drystone.Layout.from_json(box_layout(0.3, 0.1125, 0.375))
    path = tmp_path / "block.json"
    layout.save(path)
    cli = subprocess.run(
        [str(drystone_bin), "tilt", str(path), "--solver", "limit", "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    expected = json.loads(cli.stdout)
    res = drystone.tilt(layout, solver="limit")
    assert res.collapse_angle_deg == expected["collapse_angle_deg"]
    assert res.to_dict()["limit_analysis"]["load_multiplier"] == expected["load_multiplier"]


def test_the_pushover_by_nscd_and_by_limit_analysis_meet_the_rigid_statics():
    # The block of the test above, rigid: overturning about the toe at
    # λ = W B / (p L h²) = 1.308 (ρ 2000, L 0.4, B 0.2, h 0.6 m, p 1 kPa), by limit analysis
    # to the solver's tolerance and by nscd's bisection within its 1 % bracket.
    layout = drystone.Layout.from_json(box_layout(0.4, 0.2, 0.6))
    rigid = 2000.0 * 0.4 * 0.2 * 0.6 * 9.81 * 0.2 / (1000.0 * 0.4 * 0.6**2)
    lim = drystone.pushover(layout, solver="limit", pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert lim.lambda_stable == pytest.approx(rigid, rel=1e-4)
    assert lim.lambda_unstable == lim.lambda_stable and len(lim.load_multiplier) == 0
    rig = drystone.pushover(layout, solver="nscd", pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert rig.lambda_unstable is not None
    assert rig.lambda_stable <= rigid * 1.001 and rig.lambda_unstable >= rigid * 0.999
    assert rig.lambda_unstable - rig.lambda_stable <= 0.011 * rig.lambda_unstable
    assert rig.mechanism is not None and str(rig.mechanism) == "toppling"


def test_limit_analysis_parameters_are_reached_from_the_solver_dict():
    """The `limit` key of a solver dict is limit analysis's parameters (`[solver.limit]` in a
    study): a value out of range is refused naming the key, a good one runs."""
    layout = drystone.Layout.from_json(box_layout(0.4, 0.2, 0.6))
    rigid = 2000.0 * 0.4 * 0.2 * 0.6 * 9.81 * 0.2 / (1000.0 * 0.4 * 0.6**2)
    solver = {"kind": "limit", "limit": {"non_associative": False, "max_iterations": 3}}
    lim = drystone.pushover(layout, solver=solver, pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert lim.lambda_stable == pytest.approx(rigid, rel=1e-4)
    bad = {"kind": "limit", "limit": {"relaxation": 2.0}}
    with pytest.raises(Exception) as e:
        drystone.pushover(layout, solver=bad, pressure_base_pa=1000.0, pressure_top_pa=1000.0)
    assert "relaxation" in str(e.value)


def test_in_plane_rocks_a_monolith_at_its_closed_form():
    """A 1.0 x 0.2 x 1.2 m block under 0.5 MPa rocks about its toe at
    V = N_total L / (2 H0), by limit analysis exactly and by the penalty DEM on rigid
    joints (Kn 1e13 Pa/m) within 1.5 %: the plane model reads 39.13 kN at the default
    unbalanced-force ratio and at 1e-6 alike, 1.0 % below the rigid bound (the joints'
    finite stiffness moves the toe's resultant inwards)."""
    layout = drystone.Layout.from_json(box_layout(1.0, 0.2, 1.2, kn=1e13, friction_deg=45.0))
    n_total = 0.5e6 * 1.0 * 0.2 + 2000.0 * 9.81 * 1.0 * 0.2 * 1.2
    v = n_total * 1.0 / (2.0 * 1.325)
    la = drystone.in_plane(layout, solver="limit", sigma0_mpa=0.5, shear_span_m=1.325)
    assert la["result"]["peak_force_kn"] * 1e3 == pytest.approx(v, rel=1e-6)
    assert la["result"]["mechanism"]["kind"] == "rocking"
    dem = drystone.in_plane(layout, sigma0_mpa=0.5, shear_span_m=1.325, drift_pct=1.0)
    assert dem["result"]["positive"]["peak_force_kn"] * 1e3 == pytest.approx(v, rel=0.015)
    assert dem["force_kn"].shape == dem["drift_pct"].shape == dem["top_mm"].shape
    with pytest.raises(drystone.InputError, match="sigma0_mpa"):
        drystone.in_plane(layout, sigma0_mpa=-1.0, shear_span_m=1.325)
    rigid = drystone.in_plane(layout, solver="nscd", sigma0_mpa=0.5, shear_span_m=1.325, drift_pct=0.2)
    assert rigid["method"] == "nscd"
    assert rigid["result"]["positive"]["peak_force_kn"] * 1e3 == pytest.approx(v, rel=0.01)


def test_compression_reads_a_blocks_two_joints_in_series():
    """A 1.0 x 0.2 x 1.2 m block between the table and the loading beam on linear joints
    (Kn 1e10 Pa/m) shortens on its two joints in series: the vertical modulus is Kn H / 2,
    on every cycle's loading branch; nscd (rigid contacts) is refused by name."""
    layout = drystone.Layout.from_json(box_layout(1.0, 0.2, 1.2, kn=1e10, friction_deg=45.0))
    r = drystone.compression(layout, sigma0_mpa=0.5, cycles=2)
    e = 1e10 * 1.2 / 2.0 * 1e-6
    assert r["result"]["wall_vertical_modulus_mpa"] == pytest.approx(e, rel=0.01)
    for s in r["result"]["loading_secants_mpa"]:
        assert s == pytest.approx(e, rel=0.01)
    assert r["stress_mpa"].shape == r["shortening_mm"].shape == r["force_kn"].shape
    with pytest.raises(drystone.SolverError, match="penalty"):
        drystone.compression(layout, solver="nscd", sigma0_mpa=0.5)
    with pytest.raises(drystone.InputError, match="cycles"):
        drystone.compression(layout, sigma0_mpa=0.5, cycles=0)
