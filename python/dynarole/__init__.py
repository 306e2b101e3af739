"""dynarole from Python: check, reverse, replay, parallelise, simulate, verify and view
self-reconfiguration sequences of modular robots.

Every function runs the code the ``dynarole`` command runs, in this process (the native
module ``dynarole._native``), with its options parsed by the command's own definitions: a
keyword ``no_nv=True`` is the flag ``--no-nv``, ``on_failure="retry"`` is
``--on-failure retry``, and a list repeats an option. The results hold the values the command
prints (``simulate``'s results equal ``simulate --json`` for the same arguments); bad input
raises a ``DynaroleError`` carrying the command's message (and, for a refused ``.dr`` file,
its located diagnostics).
"""

from __future__ import annotations

import html
import json
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

from . import _native

__all__ = [
    "CheckError",
    "Diagnostic",
    "DynaroleError",
    "InputError",
    "InternalError",
    "Parallelised",
    "Replay",
    "Runs",
    "SimulationResult",
    "Step",
    "UsageError",
    "Verification",
    "View",
    "campaign",
    "check",
    "parallelise",
    "replay",
    "reverse",
    "simulate",
    "verify",
    "view",
]

PathLike = Union[str, "os.PathLike[str]"]


# ---------------------------------------------------------------------------------------------
# Errors: the command line's exit codes as exception classes.


class DynaroleError(Exception):
    """A command that could not run; ``exit_code`` is the command line's (README.md)."""

    exit_code = 1

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


class InputError(DynaroleError):
    """Bad input (exit 1): a file that cannot be read, a configuration that does not fit."""

    exit_code = 1


class UsageError(DynaroleError):
    """Bad usage (exit 2): an unknown option, or a value out of its range."""

    exit_code = 2


class InternalError(DynaroleError):
    """A failure of dynarole or of a tool it runs (exit 4), not a verdict on the input."""

    exit_code = 4


@dataclass(frozen=True)
class Diagnostic:
    """One diagnostic of a ``.dr`` file, located as the command line shows it (1-based line
    and column, columns in characters)."""

    file: str
    line: int
    column: int
    code: str
    severity: str
    message: str
    label: str
    hint: Optional[str] = None

    @classmethod
    def _from(cls, value: Mapping[str, Any]) -> "Diagnostic":
        return cls(**{name: value[name] for name in cls.__dataclass_fields__})

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: {self.severity}[{self.code}]: {self.message}"


class CheckError(InputError):
    """A ``.dr`` file the checks refused (exit 1); ``diagnostics`` holds every one, located."""

    def __init__(self, message: str, diagnostics: Sequence[Diagnostic]) -> None:
        super().__init__(message)
        self.diagnostics = list(diagnostics)


_KINDS = {"input": InputError, "usage": UsageError, "internal": InternalError}


def _call(function: Callable[..., Any], *args: Any) -> Any:
    """Calls the native ``function``, its failures raised as this package's exceptions."""
    try:
        return function(*args)
    except _native.NativeFailure as failure:
        kind, message, diagnostics = failure.args
        if kind == "checked":
            located = [Diagnostic._from(d) for d in json.loads(diagnostics)]
            raise CheckError(message, located) from None
        raise _KINDS.get(kind, InternalError)(message) from None


# ---------------------------------------------------------------------------------------------
# Options: keywords become the subcommand's arguments.


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _value(value: Any) -> str:
    if isinstance(value, bool):
        raise UsageError(f"expected a value, not {value!r}")
    if isinstance(value, float):
        # repr is the shortest text that reads back as the same float.
        return repr(value)
    return os.fspath(value) if isinstance(value, os.PathLike) else str(value)


def _options(options: Mapping[str, Any]) -> list[str]:
    """``name=value`` as ``--name=value`` (``=`` so that a value starting with ``-`` stays a
    value), ``True`` as a flag, ``None`` and ``False`` left out, a list or tuple repeated."""
    argv: list[str] = []
    for name, value in options.items():
        if value is None or value is False:
            continue
        if value is True:
            argv.append(_flag(name))
        elif isinstance(value, (list, tuple)):
            argv.extend(f"{_flag(name)}={_value(v)}" for v in value)
        else:
            argv.append(f"{_flag(name)}={_value(value)}")
    return argv


def _sequences(sequences: Union[None, str, Iterable[str]]) -> list[str]:
    if sequences is None:
        return []
    if isinstance(sequences, str):
        return [sequences]
    return list(sequences)


def _argv(positional: Sequence[PathLike], options: Mapping[str, Any]) -> list[str]:
    """The options, then ``--`` and the positional arguments (a file named ``-x`` stays a file)."""
    return _options(options) + ["--"] + [os.fspath(p) for p in positional]


# ---------------------------------------------------------------------------------------------
# check and reverse


def check(
    path: PathLike,
    *,
    sequences: Union[None, str, Iterable[str]] = None,
    start: Optional[PathLike] = None,
    protocol: Optional[str] = None,
    plugins: Iterable[PathLike] = (),
) -> list[Diagnostic]:
    """``dynarole check``: the warnings of a file that checks; a file with errors raises
    ``CheckError`` carrying every diagnostic. With ``start`` (a configuration) the sequences
    are also replayed on the model, as ``check --from``."""
    options = {
        "sequence": _sequences(sequences),
        "from": start,
        "protocol": protocol,
        "plugin": list(plugins),
    }
    found = json.loads(_call(_native.check, _argv([path], options)))
    return [Diagnostic._from(d) for d in found]


def reverse(
    path: PathLike,
    sequence: str,
    *,
    name: Optional[str] = None,
    plugins: Iterable[PathLike] = (),
) -> str:
    """``dynarole reverse``: the text of the derived reverse sequence, as the command prints it."""
    return _call(
        _native.reverse,
        os.fspath(path),
        sequence,
        name,
        [os.fspath(p) for p in plugins],
    )


# ---------------------------------------------------------------------------------------------
# replay and parallelise


@dataclass(frozen=True)
class Step:
    """One statement as the model ran it (after any reversal), and its line in the source."""

    statement: str
    line: int


@dataclass(frozen=True)
class Replay:
    """What ``dynarole replay`` found: ``rejected`` statements the model refused (their errors
    in ``diagnostics`` with the warnings), the final configuration (the JSON object of its data
    file) and, with ``expect``, whether it matches (``difference`` says how it does not)."""

    sequences: list[str]
    statements: int
    rejected: int
    diagnostics: list[Diagnostic]
    steps: list[Step]
    final_configuration: dict[str, Any]
    matches_expected: Optional[bool]
    difference: Optional[str]

    @property
    def ok(self) -> bool:
        """Nothing refused, and the expected configuration reached (when one was given):
        what exit code 0 means for the command."""
        return self.rejected == 0 and self.matches_expected is not False


def replay(
    path: PathLike,
    sequences: Union[None, str, Iterable[str]],
    start: PathLike,
    expect: Optional[PathLike] = None,
    *,
    plugins: Iterable[PathLike] = (),
) -> Replay:
    """``dynarole replay``: the sequences (run in turn; ``None``: the file's first) on the
    kinematic model from the configuration ``start``, with no network."""
    options = {
        "sequence": _sequences(sequences),
        "from": start,
        "expect": expect,
        "plugin": list(plugins),
    }
    value = json.loads(_call(_native.replay, _argv([path], options)))
    return Replay(
        sequences=value["sequences"],
        statements=value["statements"],
        rejected=value["rejected"],
        diagnostics=[Diagnostic._from(d) for d in value["diagnostics"]],
        steps=[Step(**s) for s in value["steps"]],
        final_configuration=value["final_configuration"],
        matches_expected=value["matches_expected"],
        difference=value["difference"],
    )


@dataclass(frozen=True)
class Parallelised:
    """What ``dynarole parallelise`` writes: the whole ``.dr`` file (``text``) with the new
    sequence ``name``, its statements and groups, and the critical path with the robot's
    default timing before and after (``None`` where it cannot be estimated, the reasons in
    ``not_estimated``)."""

    text: str
    name: str
    statements: int
    groups: int
    critical_path_before_ms: Optional[int]
    critical_path_after_ms: Optional[int]
    not_estimated: list[str]


def parallelise(
    path: PathLike,
    sequence: str,
    start: PathLike,
    *,
    name: Optional[str] = None,
    protocol: Optional[str] = None,
    window: Optional[int] = None,
    plugins: Iterable[PathLike] = (),
) -> Parallelised:
    """``dynarole parallelise``: the most parallel form of ``sequence`` that is provably safe
    on the model from ``start``."""
    options = {
        "sequence": sequence,
        "from": start,
        "name": name,
        "protocol": protocol,
        "window": window,
        "plugin": list(plugins),
    }
    value = json.loads(_call(_native.parallelise, _argv([path], options)))
    return Parallelised(**value)


# ---------------------------------------------------------------------------------------------
# simulate


class SimulationResult:
    """One simulated run: the fields of ``simulate --json`` as attributes (``success``,
    ``outcome``, ``completion_ms``, ``counters``, ``violations``, ``seed``, ...), the whole
    report as ``to_dict()``; ``trace()`` and ``view()`` run the same seed again, recorded (the
    same inputs and seed give the same run, byte for byte)."""

    def __init__(self, report: str, argv: Sequence[str]) -> None:
        # The report's JSON text, parsed when first read: a sweep of many runs that reads a
        # few fields of each does not pay for parsing every final configuration up front.
        self._text = report
        self._parsed: Optional[dict[str, Any]] = None
        self._argv = argv
        self._recording: Optional[dict[str, Any]] = None

    @property
    def _report(self) -> dict[str, Any]:
        if self._parsed is None:
            self._parsed = json.loads(self._text)
        return self._parsed

    def to_dict(self) -> dict[str, Any]:
        """The report, equal to the JSON line ``simulate --json`` prints for this run."""
        return json.loads(self._text)

    def __getattr__(self, name: str) -> Any:
        # Only the report's fields come here: the object's own attributes are found first.
        if name.startswith("_"):
            raise AttributeError(name)
        report = self._report
        if name in report:
            return report[name]
        raise AttributeError(f"a simulation result has no field {name!r}")

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self._report))

    def __repr__(self) -> str:
        r = self._report
        return (
            f"<SimulationResult seed={r.get('seed')} outcome={r.get('outcome')!r} "
            f"completion_ms={r.get('completion_ms')}>"
        )

    def recording(self) -> dict[str, Any]:
        """The run's recording (the JSON ``--record`` writes), made by running its seed again."""
        if self._recording is None:
            with tempfile.TemporaryDirectory(prefix="dynarole-") as scratch:
                path = os.path.join(scratch, "run.json")
                argv = _rerun(self._argv, self._report["seed"], path)
                _call(_native.simulate, argv, lambda _: None)
                with open(path, encoding="utf-8") as f:
                    self._recording = json.load(f)
        return self._recording

    def trace(self) -> "pandas.DataFrame":  # noqa: F821
        """Every event of the run, one row each: ``time_ms``, ``module`` (its name, or ``-``),
        ``event``, ``state`` (the module's protocol state as its runtime describes it),
        ``detail`` and ``statement`` (its number, or missing): the lines ``--trace`` writes."""
        import pandas

        recording = self.recording()
        names = [m["name"] for m in recording["modules"]]
        rows = [
            {
                "time_ms": e["time_ms"],
                "module": names[e["module"]] if e["module"] is not None else "-",
                "event": e["event"],
                "state": e["state"],
                "detail": e["detail"],
                "statement": e["statement"],
            }
            for e in recording["events"]
        ]
        columns = ["time_ms", "module", "event", "state", "detail", "statement"]
        frame = pandas.DataFrame(rows, columns=columns)
        frame["statement"] = frame["statement"].astype("Int64")
        return frame

    def view(self) -> "View":
        """The run in the viewer (inline in a notebook, or saved as the page ``--html`` writes)."""
        return view(self)


def _rerun(argv: Sequence[str], seed: int, record: str) -> list[str]:
    """``argv`` for one run of ``seed``, recorded to ``record``, without its trace file."""
    kept = [
        a
        for a in argv
        if not a.startswith(("--seed=", "--repeat=", "--trace=", "--record=", "--html=", "--poses-at="))
    ]
    cut = kept.index("--")
    return kept[:cut] + [f"--seed={seed}", "--repeat=1", f"--record={record}"] + kept[cut:]


class Runs(list):
    """The runs of one ``simulate`` call, in seed order; ``to_frame()`` has a row per run."""

    def to_frame(self) -> "pandas.DataFrame":  # noqa: F821
        """One row per run: the report's scalar fields, the counters as ``counters.NAME``, and
        the number of violations."""
        import pandas

        rows = []
        for run in self:
            report = run.to_dict()
            row = {k: v for k, v in report.items() if not isinstance(v, (dict, list))}
            row.update({f"counters.{k}": v for k, v in report["counters"].items()})
            row["violations"] = len(report["violations"])
            rows.append(row)
        return pandas.DataFrame(rows)

    @property
    def success_rate(self) -> float:
        """The fraction of runs that reached the goal."""
        return sum(1 for r in self if r.success) / len(self) if self else 0.0


def simulate(
    path: PathLike,
    sequences: Union[None, str, Iterable[str]],
    start: PathLike,
    expect: Optional[PathLike] = None,
    *,
    loss: Optional[float] = None,
    scenario: Optional[PathLike] = None,
    seed: int = 0,
    repeat: int = 1,
    protocol: Optional[str] = None,
    trace: Optional[PathLike] = None,
    plugins: Iterable[PathLike] = (),
    **options: Any,
) -> Runs:
    """``dynarole simulate``: the generated C on every module, from ``start`` (sequences run
    in turn; ``None``: the file's first), over lossy links with the faults of ``scenario``;
    runs with seeds ``seed`` .. ``seed + repeat - 1``. Other options of the command go as
    keywords (``stepping="tickless"``, ``no_nv=True``, ``on_failure="retry"``, ``retries=5``,
    ``firmware="avr"``, ``record=PATH``, ``html=PATH``). Ctrl-C stops between runs."""
    named = {
        "sequence": _sequences(sequences),
        "from": start,
        "expect": expect,
        "loss": loss,
        "scenario": scenario,
        "seed": seed,
        "repeat": repeat,
        "protocol": protocol,
        "trace": trace,
        "plugin": list(plugins),
        "json": True,
    }
    for name in options:
        if name in named:
            raise UsageError(f"{name!r} is given twice")
    argv = _argv([path], {**named, **options})
    runs = Runs()
    _call(_native.simulate, argv, lambda report: runs.append(SimulationResult(report, argv)))
    return runs


# ---------------------------------------------------------------------------------------------
# campaign and verify


def _progress_printer(stream: Any) -> Callable[[int, int], None]:
    """Progress on ``stream`` (a notebook shows standard error in the cell): one line
    rewritten about twice a second, and the last count."""
    state = {"shown": -1, "at": 0.0}

    def show(done: int, total: int) -> None:
        now = time.monotonic()
        if total and done != state["shown"] and (now - state["at"] >= 0.5 or done == total):
            state.update(shown=done, at=now)
            stream.write(f"\rcampaign: {done}/{total} runs")
            if done == total:
                stream.write("\n")
            stream.flush()

    return show


def campaign(
    toml: PathLike,
    output: PathLike,
    *,
    jobs: Optional[int] = None,
    max_runs: Optional[int] = None,
    plots: bool = True,
    progress: Union[bool, Callable[[int, int], None]] = True,
) -> "pandas.DataFrame":  # noqa: F821
    """``dynarole campaign TOML -o OUTPUT``: every run of the campaign file (resumed from
    ``OUTPUT/runs.csv`` if it exists), then the rows of ``runs.csv`` as a DataFrame. Progress
    goes to standard error (a callable ``progress(done, total)`` gets it instead; ``False``:
    none). Ctrl-C stops the runs; those recorded stay and the campaign resumes from them."""
    import pandas

    options = {"output": output, "jobs": jobs, "max_runs": max_runs, "no_plots": not plots}
    if progress is True:
        told: Callable[[int, int], None] = _progress_printer(sys.stderr)
    elif progress is False:
        told = lambda done, total: None  # noqa: E731
    else:
        told = progress
    _call(_native.campaign, _argv([toml], options), told)
    return pandas.read_csv(os.path.join(os.fspath(output), "runs.csv"))


@dataclass(frozen=True)
class Verification:
    """``dynarole verify``'s verdict (``verified``, ``violated`` or ``inconclusive``) and its
    report, the text the command prints."""

    verdict: str
    report: str

    @property
    def verified(self) -> bool:
        return self.verdict == "verified"

    def __str__(self) -> str:
        return self.report


def verify(
    path: PathLike,
    sequences: Union[None, str, Iterable[str]],
    start: PathLike,
    *,
    protocol: Optional[str] = None,
    plugins: Iterable[PathLike] = (),
    **options: Any,
) -> Verification:
    """``dynarole verify``: spin proves (or refutes) the protocol's properties for the
    sequences on ``start``; needs spin (``scripts/ensure-spin``). Other options of the command
    go as keywords (``resets=1``, ``method="full"``, ``time_limit=60``, ``keep=DIR``). Ctrl-C
    stops the check, and spin or pan with it, within a tenth of a second of pan's poll."""
    named = {
        "sequence": _sequences(sequences),
        "from": start,
        "protocol": protocol,
        "plugin": list(plugins),
    }
    value = json.loads(_call(_native.verify, _argv([path], {**named, **options})))
    return Verification(verdict=value["verdict"], report=value["report"])


# ---------------------------------------------------------------------------------------------
# view


class View:
    """The viewer's self-contained page of one recording: shown inline in Jupyter, saved as
    the file ``--html`` writes."""

    def __init__(self, page: str, height: int = 640) -> None:
        self.html = page
        self.height = height

    def save(self, path: PathLike) -> None:
        """Writes the page (it opens from disk, with no network)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)

    def _repr_html_(self) -> str:
        # The page runs in its own frame; srcdoc takes it as an attribute value, escaped.
        return (
            f'<iframe srcdoc="{html.escape(self.html, quote=True)}" '
            f'style="width:100%;height:{int(self.height)}px;border:0" '
            'sandbox="allow-scripts"></iframe>'
        )


def view(recording_or_result: Union[PathLike, SimulationResult], *, height: int = 640) -> View:
    """The viewer for a recording file (``--record``) or a simulation result."""
    if isinstance(recording_or_result, SimulationResult):
        with tempfile.TemporaryDirectory(prefix="dynarole-") as scratch:
            path = os.path.join(scratch, "run.json")
            with open(path, "w", encoding="utf-8") as f:
                json.dump(recording_or_result.recording(), f)
            return View(_call(_native.view_html, path), height)
    return View(_call(_native.view_html, os.fspath(recording_or_result)), height)
