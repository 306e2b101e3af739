"""Per-run cost of dynarole.simulate against `dynarole simulate --json` (scripts/bench-python)."""

import os
import statistics
import subprocess
import sys
import time

import dynarole

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EXAMPLES = os.path.join(ROOT, "robots", "atron", "examples")
PROGRAM = os.path.join(EXAMPLES, "eight2car.dr")
START, GOAL = os.path.join(EXAMPLES, "eight.json"), os.path.join(EXAMPLES, "car.json")
SMALL, ROUNDS = 10, 5


def command(repeat):
    started = time.perf_counter()
    subprocess.run(
        [os.environ["DYNAROLE"], "simulate", PROGRAM, "--sequence", "eight2car", "--from", START,
         "--expect", GOAL, "--loss", "0.3", "--seed", "1", "--repeat", str(repeat), "--json"],
        check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - started


def package(repeat):
    started = time.perf_counter()
    runs = dynarole.simulate(PROGRAM, "eight2car", START, GOAL, loss=0.3, seed=1, repeat=repeat)
    assert len(runs) == repeat
    return time.perf_counter() - started


def package_read(repeat):
    """The same, with every report's every field read (each parsed from its JSON)."""
    started = time.perf_counter()
    runs = dynarole.simulate(PROGRAM, "eight2car", START, GOAL, loss=0.3, seed=1, repeat=repeat)
    assert sum(r.success for r in runs) <= repeat
    return time.perf_counter() - started


def per_run(measure, n):
    big = statistics.median(measure(n) for _ in range(ROUNDS))
    small = statistics.median(measure(SMALL) for _ in range(ROUNDS))
    return (big - small) / (n - SMALL) * 1e3, big


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    cli_ms, cli_total = per_run(command, n)
    py_ms, py_total = per_run(package, n)
    read_ms, read_total = per_run(package_read, n)
    print(f"eight2car, loss 0.3, {n} seeds, median of {ROUNDS} rounds")
    print(f"  command line: {cli_total:.3f} s in all, {cli_ms:.4f} ms per run")
    print(f"  Python:       {py_total:.3f} s in all, {py_ms:.4f} ms per run")
    print(f"  Python / command line per run: {py_ms / cli_ms:.3f}x")
    print(f"  Python, every report read: {read_total:.3f} s in all, {read_ms:.4f} ms per run "
          f"({read_ms / cli_ms:.3f}x)")


if __name__ == "__main__":
    main()
