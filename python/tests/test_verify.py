"""verify gives the verdict and the report the command prints (spin is installed by
scripts/ensure-spin, which scripts/test runs first)."""

import os
import re
import shutil
import signal
import threading
import time

import pytest

import dynarole
from conftest import ATRON, cli

VERIFY = ATRON / "verify"

def untimed(report):
    """The report without the figures that vary from run to run (seconds, memory)."""
    return re.sub(r"[\d.]+ s, \d+ MB", "T s, M MB", report)


needs_spin = pytest.mark.skipif(shutil.which("spin") is None, reason="spin is not installed (scripts/ensure-spin)")


@needs_spin
def test_a_proof_is_the_report_verify_prints():
    program, line = VERIFY / "ab_c.dr", VERIFY / "line3.json"
    found = dynarole.verify(program, None, line, resets=1, late=1)
    printed = cli("verify", program, "--from", line, "--resets", "1", "--late", "1")
    assert found.verified and found.verdict == "verified"
    assert untimed(found.report) == untimed(printed.stdout)
    assert "S1, S2, S3 (safety): verified" in found.report


@needs_spin
def test_a_refuted_protocol_is_a_verdict_not_an_error():
    program, line = VERIFY / "ab_c.dr", VERIFY / "line3.json"
    # The paper's protocol with its printed merge starts a statement too early.
    found = dynarole.verify(program, None, line, protocol="paper", merge="printed", late=0)
    printed = cli("verify", program, "--from", line, "--protocol", "paper", "--merge", "printed", "--late", "0", ok=False)
    assert printed.returncode == 1
    assert found.verdict == "violated" and not found.verified
    assert "S1 violated: M2 started #2" in found.report
    assert untimed(found.report) == untimed(printed.stdout)


def test_a_protocol_verify_cannot_model_is_a_usage_error():
    program, line = VERIFY / "ab_c.dr", VERIFY / "line3.json"
    printed = cli("verify", program, "--from", line, "--protocol", "token", ok=False)
    with pytest.raises(dynarole.DynaroleError) as raised:
        dynarole.verify(program, None, line, protocol="token")
    assert raised.value.exit_code == printed.returncode


@needs_spin
def test_ctrl_c_stops_a_long_check_and_its_tools():
    # The full model of the paper's eight modules with a reset searches for minutes.
    timer = threading.Timer(3.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        dynarole.verify(ATRON / "eight2car.dr", "eight2car", ATRON / "eight.json",
                        method="full", resets=1)
    timer.cancel()
    # Stopped within a poll of the tool running, not at its time limit of 600 s.
    assert time.monotonic() - started < 60
