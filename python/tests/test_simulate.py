"""simulate's results equal `simulate --json`'s for the same seeds; traces, views, campaigns
and interrupts."""

import os
import signal
import threading
import time

import pandas
import pytest

import dynarole
from conftest import ROOT, cli, json_lines

LOSSY = ROOT / "examples" / "scenarios" / "lossy.toml"


def cli_reports(*args):
    return json_lines(cli("simulate", *args, "--json", ok=False).stdout)


def test_reports_equal_the_commands_for_the_same_seeds(eight2car):
    program, start, goal = eight2car
    runs = dynarole.simulate(program, "eight2car", start, goal, loss=0.3, seed=7, repeat=3)
    printed = cli_reports(program, "--sequence", "eight2car", "--from", start, "--expect", goal,
                          "--loss", "0.3", "--seed", "7", "--repeat", "3")
    assert [r.to_dict() for r in runs] == printed
    assert [r.seed for r in runs] == [7, 8, 9]
    first = runs[0]
    assert first.success is printed[0]["success"]
    assert first.completion_ms == printed[0]["completion_ms"]
    assert first.counters == printed[0]["counters"]
    assert first.violations == [] and first.outcome == "success"


def test_scenario_protocol_and_other_options_reach_the_command(eight2car):
    program, start, goal = eight2car
    options = dict(scenario=LOSSY, protocol="lattice", no_nv=True, seed=3, repeat=2)
    runs = dynarole.simulate(program, ["eight2car", "car2eight"], start, start, **options)
    printed = cli_reports(program, "--sequence", "eight2car", "--sequence", "car2eight", "--from", start,
                          "--expect", start, "--scenario", LOSSY, "--protocol", "lattice", "--no-nv",
                          "--seed", "3", "--repeat", "2")
    assert [r.to_dict() for r in runs] == printed
    token = dynarole.simulate(program, "eight2car", start, goal, protocol="token", token_retries=32, loss=0.2, seed=1)
    assert token[0].to_dict() == cli_reports(program, "--sequence", "eight2car", "--from", start, "--expect", goal,
                                             "--protocol", "token", "--token-retries", "32", "--loss", "0.2",
                                             "--seed", "1")[0]


def test_a_run_that_misses_the_goal_is_a_result_not_an_error(eight2car):
    program, start, goal = eight2car
    runs = dynarole.simulate(program, "eight2car", start, start, seed=1)
    assert not runs[0].success and runs[0].outcome == "wrong-configuration"
    assert runs.success_rate == 0.0


def test_the_trace_is_the_trace_file_as_a_frame(eight2car, tmp_path):
    program, start, goal = eight2car
    [run] = dynarole.simulate(program, "eight2car", start, goal, loss=0.3, seed=5)
    frame = run.trace()
    path = tmp_path / "run.trace"
    cli("simulate", program, "--sequence", "eight2car", "--from", start, "--expect", goal,
        "--loss", "0.3", "--seed", "5", "--trace", path)
    lines = [l for l in path.read_text().splitlines() if not l.startswith("#")]
    assert isinstance(frame, pandas.DataFrame) and len(frame) == len(lines)
    for row, line in zip(frame.itertuples(), lines):
        time_ms, module, event = line.split()[:3]
        assert (f"{row.time_ms:.3f}", row.module, row.event) == (time_ms, module, event)
        assert row.state in line and row.detail in line


def test_the_view_is_the_page_html_writes(eight2car, tmp_path):
    program, start, goal = eight2car
    [run] = dynarole.simulate(program, "eight2car", start, goal, loss=0.3, seed=2)
    page = tmp_path / "run.html"
    record = tmp_path / "run.json"
    cli("simulate", program, "--sequence", "eight2car", "--from", start, "--expect", goal,
        "--loss", "0.3", "--seed", "2", "--html", page, "--record", record)
    shown = run.view()
    assert shown.html == page.read_text()
    assert dynarole.view(record).html == shown.html
    saved = tmp_path / "saved.html"
    shown.save(saved)
    assert saved.read_text() == page.read_text()
    inline = shown._repr_html_()
    assert inline.startswith("<iframe srcdoc=") and "<script" not in inline


def test_the_frame_of_the_runs_has_a_row_per_seed(eight2car):
    program, start, goal = eight2car
    runs = dynarole.simulate(program, "eight2car", start, goal, loss=0.3, seed=11, repeat=4)
    frame = runs.to_frame()
    assert list(frame["seed"]) == [11, 12, 13, 14]
    assert list(frame["completion_ms"]) == [r.completion_ms for r in runs]
    assert "counters.lost" in frame.columns


def interrupt_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_stops_a_long_simulation(eight2car):
    program, start, goal = eight2car
    timer = interrupt_after(0.5)
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        dynarole.simulate(program, "eight2car", start, goal, loss=0.3, repeat=10_000_000)
    timer.cancel()
    # Stopped at the next run's end, not after ten million runs.
    assert time.monotonic() - started < 60


CAMPAIGNS = ROOT / "examples" / "campaigns"


def test_a_campaign_gives_the_rows_of_runs_csv(tmp_path):
    ours = tmp_path / "ours"
    seen = []
    frame = dynarole.campaign(CAMPAIGNS / "smoke.toml", ours, jobs=2, max_runs=40, plots=False,
                              progress=lambda done, total: seen.append((done, total)))
    theirs = tmp_path / "theirs"
    cli("campaign", CAMPAIGNS / "smoke.toml", "-o", theirs, "-j", "2", "--max-runs", "40", "--no-plots")
    expected = pandas.read_csv(theirs / "runs.csv")
    assert len(frame) == len(expected) > 0
    pandas.testing.assert_frame_equal(frame.sort_values("run").reset_index(drop=True),
                                      expected.sort_values("run").reset_index(drop=True))
    assert seen and seen[-1][0] == len(frame)


def test_ctrl_c_stops_a_campaign_keeping_the_runs_recorded(tmp_path):
    out = tmp_path / "big"
    sent = []

    def interrupt_once_runs_are_recorded(done, total):
        # Ctrl-C once a run is recorded, however long the campaign's build takes on this machine.
        if done > 0 and not sent:
            sent.append(done)
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        dynarole.campaign(CAMPAIGNS / "extended.toml", out, jobs=2, plots=False,
                          progress=interrupt_once_runs_are_recorded)
    assert sent
    kept = pandas.read_csv(out / "runs.csv")
    assert 0 < len(kept)
    # Resumed: the runs recorded are not run again.
    more = dynarole.campaign(CAMPAIGNS / "extended.toml", out, jobs=2, plots=False, progress=False,
                             max_runs=5)
    assert len(more) == len(kept) + 5
