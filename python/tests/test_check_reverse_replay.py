"""check, reverse, replay and parallelise give what the command prints, value for value."""

import json
import re

import pytest

import dynarole
from conftest import ATRON, ROOT, cli


def test_a_file_that_checks_has_its_warnings_and_no_more(eight2car):
    program, start, _ = eight2car
    assert dynarole.check(program) == []
    warned = dynarole.check(program, sequences="eight2car", start=start)
    printed = cli("check", program, "--from", start, "--sequence", "eight2car").stderr
    assert len(warned) == printed.count("warning[") > 0
    for w in warned:
        assert w.severity == "warning"
        assert f"warning[{w.code}]: {w.message}" in printed
        assert f"{w.file}:{w.line}:{w.column}" in printed


BAD = "robot atron;\n\nsequence s {\n    M0.Joint.spin();\n}\n"


def test_a_refused_file_raises_with_the_diagnostics_the_command_renders(tmp_path):
    path = tmp_path / "bad.dr"
    path.write_text(BAD)
    with pytest.raises(dynarole.CheckError) as raised:
        dynarole.check(path)
    error = raised.value
    assert error.exit_code == 1
    first = error.diagnostics[0]
    assert (first.file, first.severity) == (str(path), "error")
    rendered = cli("check", path, ok=False)
    assert rendered.returncode == 1
    # The place the command renders (`--> FILE:LINE:COLUMN`) is the first diagnostic's.
    assert f"{path}:{first.line}:{first.column}" in rendered.stderr
    assert f"[{first.code}]" in rendered.stderr
    # The exception's text is what the command prints on standard error.
    assert error.message == rendered.stderr.strip()


def test_reverse_is_the_text_reverse_prints(eight2car):
    program, _, _ = eight2car
    assert dynarole.reverse(program, "eight2car") == cli("reverse", program, "eight2car").stdout
    named = dynarole.reverse(program, "eight2car", name="back")
    assert named == cli("reverse", program, "eight2car", "--name", "back").stdout


def test_replay_gives_the_final_configuration_and_the_steps(eight2car, tmp_path):
    program, start, goal = eight2car
    found = dynarole.replay(program, "eight2car", start, goal)
    out = tmp_path / "final.json"
    printed = cli("replay", program, "--sequence", "eight2car", "--from", start, "--expect", goal, "--out", out)
    assert found.final_configuration == json.loads(out.read_text())
    summary = re.search(r"(\d+) statements, (\d+) rejected", printed.stdout)
    assert (found.statements, found.rejected) == (int(summary[1]), int(summary[2]))
    assert found.ok and found.matches_expected and found.difference is None
    assert len(found.steps) == found.statements
    assert found.steps[0].statement.startswith("M") and found.steps[0].line > 0


def test_a_replay_that_misses_the_goal_says_how(eight2car):
    program, start, goal = eight2car
    found = dynarole.replay(program, "eight2car", start, start)
    assert not found.ok and found.matches_expected is False
    assert found.difference


def test_parallelise_writes_the_file_and_the_critical_paths_the_command_does(eight2car):
    program, start, _ = eight2car
    found = dynarole.parallelise(program, "eight2car", start)
    printed = cli("parallelise", program, "--sequence", "eight2car", "--from", start)
    assert found.text == printed.stdout
    assert found.name == "eight2car_parallel"
    line = re.search(r"(\d+) statements, (\d+) groups; critical path ([\d.]+) s before, ([\d.]+) s after", printed.stderr)
    assert (found.statements, found.groups) == (int(line[1]), int(line[2]))
    assert f"{found.critical_path_before_ms / 1000:.2f}" == line[3]
    assert f"{found.critical_path_after_ms / 1000:.2f}" == line[4]
    assert found.critical_path_after_ms <= found.critical_path_before_ms


def test_bad_options_are_usage_errors_and_missing_files_input_errors(eight2car, tmp_path):
    program, start, _ = eight2car
    with pytest.raises(dynarole.UsageError) as raised:
        dynarole.simulate(program, "eight2car", start, no_such_option=3)
    assert raised.value.exit_code == 2 and "--no-such-option" in raised.value.message
    with pytest.raises(dynarole.InputError) as raised:
        dynarole.replay(tmp_path / "missing.dr", None, start)
    assert "missing.dr" in raised.value.message
    with pytest.raises(dynarole.InputError) as raised:
        dynarole.simulate(program, "no_such_sequence", start)
    assert "no_such_sequence" in raised.value.message


def test_names_and_values_are_never_options_or_shell_words(eight2car, tmp_path):
    program, start, _ = eight2car
    # A file whose name starts with `-` and holds shell syntax is still only a file.
    odd = tmp_path / "-x; touch pwned $(id).dr"
    odd.write_text(program.read_text())
    assert dynarole.check(odd) == []
    assert not (tmp_path / "pwned").exists()
    with pytest.raises(dynarole.InputError):
        dynarole.simulate(program, "eight2car; rm -rf /", start)
