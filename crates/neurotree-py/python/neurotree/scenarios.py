"""Scenario files, the TOML that ``neurotree test`` reads, run from Python: a tree, its mocks
and substitutions, blackboard values written before given ticks, and what must hold after
given ticks.

    result = nt.run_scenarios(["scenarios/patrol.toml"], registry=reg)
    assert result.passed, result.report()

Each file runs on a copy of ``registry``'s node types (the built-ins when none is given, or
your Python leaves and Nav2's models), with the mocks, rules and enums the file names; the
registry's own ``mock`` and ``substitute`` calls do not apply. A file that cannot be read or
parsed is a failed result whose problem names the file, line and column.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Iterable, Iterator, List, Optional, Sequence, Union, overload

from . import _native

__all__ = ["ScenarioResult", "ScenarioResults", "run_scenarios"]


@dataclass(frozen=True)
class ScenarioResult:
    """How one scenario went; true if it passed."""

    #: The scenario's ``name``, else its file's stem.
    name: str
    #: The scenario file, as given.
    file: str
    #: How long it took, in seconds.
    seconds: float
    #: Why it failed, one problem each (a problem may have several lines); empty if it passed.
    problems: List[str]
    _report: str

    @property
    def passed(self) -> bool:
        """``True`` if every expectation held."""
        return not self.problems

    def __bool__(self) -> bool:
        return self.passed

    def report(self) -> str:
        """What ``neurotree test`` prints for it: ``test NAME ... ok``, or ``... FAILED``
        with each problem indented below."""
        return self._report


class ScenarioResults(Sequence[ScenarioResult]):
    """The results of ``run_scenarios``, in the order of the files; true if all passed, so
    that ``assert results.passed, results.report()`` shows every failure."""

    def __init__(self, results: Iterable[ScenarioResult]) -> None:
        self._results = list(results)

    @overload
    def __getitem__(self, index: int) -> ScenarioResult: ...

    @overload
    def __getitem__(self, index: slice) -> List[ScenarioResult]: ...

    def __getitem__(self, index: Union[int, slice]) -> Union[ScenarioResult, List[ScenarioResult]]:
        return self._results[index]

    def __len__(self) -> int:
        return len(self._results)

    def __iter__(self) -> Iterator[ScenarioResult]:
        return iter(self._results)

    @property
    def passed(self) -> bool:
        """``True`` if every scenario passed."""
        return all(r.passed for r in self._results)

    @property
    def failed(self) -> List[ScenarioResult]:
        """The scenarios that failed."""
        return [r for r in self._results if not r.passed]

    def __bool__(self) -> bool:
        return self.passed

    def report(self) -> str:
        """What ``neurotree test`` prints: each scenario's report, then ``N passed, M failed``."""
        failed = len(self.failed)
        lines = [r.report() for r in self._results]
        lines.append(f"\n{len(self._results) - failed} passed, {failed} failed")
        return "\n".join(lines)

    def __repr__(self) -> str:
        failed = len(self.failed)
        return f"<ScenarioResults: {len(self._results) - failed} passed, {failed} failed>"


def run_scenarios(
    paths: Union[str, "os.PathLike[str]", Iterable[Union[str, "os.PathLike[str]"]]],
    *,
    registry: Optional[_native.Registry] = None,
    robot: Any = None,
) -> ScenarioResults:
    """Runs the scenario files at ``paths`` (one path, or several) on the node types of
    ``registry`` (the built-ins when ``None``), ticking each tree with ``robot`` as
    ``Tree.tick_once`` would; returns their results, which are true if all passed."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    rows = _native._run_scenarios([os.fspath(p) for p in paths], registry, robot)
    return ScenarioResults(
        ScenarioResult(name, file, seconds, problems, report)
        for name, file, seconds, problems, report in rows
    )
