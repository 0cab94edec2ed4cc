"""Studies from Python against the command-line tool: the main job's rows and CBL/SBL/SBR
means to the last digit, threads, progress, Ctrl-C and the journal, bad input."""

from __future__ import annotations

import os
import signal
import subprocess

import polars as pl
import pytest

import drystone

STUDY = "studies/tilting_table.toml"
# wall_time_s is the only column that is not a function of the seed.
TIMED = {"wall_time_s"}


def _journal_rows(out) -> int:
    lines = (out / "journal.jsonl").read_text().splitlines()
    return len(lines) - 1  # the header line


@pytest.fixture(scope="module")
def main_job(tmp_path_factory, root, drystone_bin):
    """The main job at 2 realizations per group, by the CLI and from Python."""
    base = tmp_path_factory.mktemp("main_job")
    subprocess.run(
        [str(drystone_bin), "run", STUDY, "--realizations", "2", "--out", str(base / "cli")],
        cwd=root,
        check=True,
        capture_output=True,
    )
    calls = []
    py = drystone.run_study(
        root / STUDY, realizations=2, out=base / "py", progress=lambda d, t, row: calls.append((d, t, row))
    )
    return base, py, calls


def test_the_main_job_from_python_is_the_command_line_run_to_the_last_digit(main_job):
    base, py, _ = main_job
    cli = pl.read_csv(base / "cli" / "realizations.csv")
    df = py.realizations
    assert isinstance(df, pl.DataFrame)
    assert df.columns == cli.columns
    assert df.height == cli.height == 6
    for c in ["index", "realization", "blocks", "steps", "iterations"]:
        assert df[c].to_list() == cli[c].to_list(), c
    for c in ["group", "status", "collapse_reason", "mechanism", "joint"]:
        assert df[c].fill_null("").to_list() == cli[c].fill_null("").to_list(), c
    for c in ["collapse_angle_deg", "first_unstable_deg", "disp_mean_5deg_cm", "disp_mean_10deg_cm", "dt_s"]:
        assert df[c].to_list() == cli[c].cast(pl.Float64).to_list(), c
    # The series are ';'-joined numbers in the CSV, lists here.
    joined = [";".join(repr(x) for x in v) for v in df["tilt_deg"].to_list()]
    assert [float(x) for s in joined for x in s.split(";") if x] == [
        float(x) for s in cli["tilt_deg"].fill_null("").to_list() for x in str(s).split(";") if x
    ]
    # The summaries: every statistic of every group identical, the CBL/SBL/SBR means first.
    cli_summary = drystone._read_summary(base / "cli" / "summary.csv")
    assert set(py.means()) == {"CBL", "SBL", "SBR"}
    cli_means = dict(zip(cli_summary["group"].to_list(), cli_summary["collapse_angle_deg_mean"].to_list()))
    assert py.means() == cli_means
    assert py.summary.columns == cli_summary.columns
    for c in py.summary.columns:
        a, b = py.summary[c].to_list(), cli_summary[c].to_list()
        assert [x if x == x else "nan" for x in a] == [x if x == x else "nan" for x in b], c
    assert (base / "py" / "report.md").exists() and (base / "py" / "manifest.json").exists()
    assert py.comparison and "CBL" in py.comparison


def test_progress_is_reported_once_per_realization(main_job):
    _, py, calls = main_job
    assert [d for d, _, _ in calls] == list(range(1, 7))
    assert {t for _, t, _ in calls} == {6}
    assert sorted(row["index"] for _, _, row in calls) == list(range(6))
    by_index = {row["index"]: row for _, _, row in calls}
    angles = py.realizations["collapse_angle_deg"].to_list()
    assert [by_index[i]["collapse_angle_deg"] for i in range(6)] == angles


def test_rows_do_not_depend_on_the_thread_count(main_job, root, tmp_path):
    _, py, _ = main_job
    one = drystone.run_study(drystone.Study.from_toml(root / STUDY, realizations=2), out=tmp_path / "t1", threads=1)
    cols = [c for c in py.realizations.columns if c not in TIMED]
    assert one.realizations.select(cols).equals(py.realizations.select(cols))


def test_ctrl_c_stops_the_run_and_the_journal_keeps_what_finished(main_job, root, tmp_path):
    _, py, _ = main_job
    out = tmp_path / "interrupted"
    seen = []

    def interrupt(done, total, row):
        seen.append(row["index"])
        if done == 1:
            os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C does

    # Python's own Ctrl-C handler, even where the test runner was started with SIGINT
    # ignored (a background job of a shell without job control).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            drystone.run_study(root / STUDY, realizations=2, out=out, threads=1, progress=interrupt)
    finally:
        signal.signal(signal.SIGINT, previous)
    kept = _journal_rows(out)
    assert 1 <= kept < 6, "one thread: the run stops after the realization that finished"
    assert not (out / "realizations.csv").exists()
    # Without resume the unfinished journal is refused, naming it.
    with pytest.raises(drystone.DrystoneError) as e:
        drystone.run_study(root / STUDY, realizations=2, out=out, threads=1)
    assert "journal" in str(e.value) and "--resume" in str(e.value)
    resumed = drystone.run_study(root / STUDY, realizations=2, out=out, resume=True)
    assert resumed.resumed == kept
    cols = [c for c in py.realizations.columns if c not in TIMED]
    assert resumed.realizations.select(cols).equals(py.realizations.select(cols))


def test_an_exception_in_the_progress_callback_stops_the_run(root, tmp_path):
    class Stop(Exception):
        pass

    def fail(done, total, row):
        raise Stop("enough")

    with pytest.raises(Stop):
        drystone.run_study(root / STUDY, realizations=1, out=tmp_path / "stop", threads=1, progress=fail)
    assert 1 <= _journal_rows(tmp_path / "stop") < 3


def test_bad_studies_are_input_errors(root, tmp_path):
    with pytest.raises(drystone.InputError) as e:
        drystone.run_study(tmp_path / "nope.toml")
    assert e.value.file == str(tmp_path / "nope.toml")
    with pytest.raises(drystone.InputError) as e:
        drystone.run_study(root / STUDY, realizations=0, out=tmp_path / "zero")
    assert e.value.key == "realizations"
    bad = tmp_path / "bad.toml"
    bad.write_text((root / STUDY).read_text().replace("seed = 20210917", "sead = 20210917"))
    with pytest.raises(drystone.InputError) as e:
        drystone.Study.from_toml(bad)
    assert e.value.key == "sead" and e.value.line is not None
    with pytest.raises(drystone.InputError):
        drystone.run_study(root / STUDY, shard="3/2", out=tmp_path / "shard")


def test_to_pandas_gives_the_same_table_where_pandas_is_installed(main_job):
    _, py, _ = main_job
    try:
        import pandas  # noqa: F401
        import pyarrow  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError):
            py.to_pandas()
        return
    pdf = py.to_pandas()
    assert list(pdf.columns) == py.realizations.columns
    assert pdf["collapse_angle_deg"].tolist() == py.realizations["collapse_angle_deg"].to_list()


def test_a_study_object_describes_its_file(root):
    st = drystone.Study.from_toml(root / STUDY, realizations=3)
    assert (st.name, st.seed, st.realizations, st.protocol) == ("tilting_table", 20210917, 3, "tilt")
    assert st.groups == ["CBL", "SBL", "SBR"] and st.items == 9
