"""Progress of long commands: a bar on a terminal (rich), one line per finished item off it.

Both go to stderr, so that stdout holds only the result (a table or JSON)."""
from __future__ import annotations

import sys
import time

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress as Bar, TextColumn, TimeElapsedColumn

from .terminal import is_terminal


class Progress:
    """Progress over ``items``: a rich bar on stderr when stderr is a terminal, otherwise one line
    per finished item (``[3/37] <label> (2.1 s)``) on stderr; nothing when ``enabled`` is False.

    ``label(item)`` names an item.  Iterating yields the items; an item is finished when the
    next one is asked for (or the loop ends).  ``items`` may be a lazy iterable with a ``len``
    (e.g. items in the order their parallel results come back, :mod:`lmidsl.studies.parallel`):
    it is not read ahead, and an item's time runs from the previous item's end to its own."""

    def __init__(self, items, description: str, label=str, enabled: bool = True):
        if not hasattr(items, "__len__"):
            items = list(items)
        self.items, self.description, self.label, self.enabled = items, description, label, enabled

    def __iter__(self):
        if not self.enabled or not len(self.items):
            yield from self.items
            return
        if is_terminal(sys.stderr):
            yield from self._bar()
        else:
            yield from self._lines()

    def _lines(self):
        total = len(self.items)
        t0 = time.perf_counter()
        for i, item in enumerate(self.items, 1):
            yield item
            print(f"{self.description} [{i}/{total}] {self.label(item)} "
                  f"({time.perf_counter() - t0:.1f} s)", file=sys.stderr, flush=True)
            t0 = time.perf_counter()

    def _bar(self):
        console = Console(file=sys.stderr)
        columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                   TimeElapsedColumn(), TextColumn("{task.fields[item]}"))
        with Bar(*columns, console=console, transient=True) as bar:
            task = bar.add_task(self.description, total=len(self.items), item="")
            for item in self.items:
                bar.update(task, item=self.label(item))
                yield item
                bar.advance(task)


def progress(items, description: str, label=str, enabled: bool = True) -> Progress:
    """:class:`Progress` over ``items``."""
    return Progress(items, description, label, enabled)


class Stages:
    """Progress through the named stages of one long job (e.g. ``verify``: synthesis, analysis,
    exact figure, Monte Carlo): a spinner naming the stage on a terminal, one line per finished
    stage on stderr off it.  Call it with each stage's name as it starts; use it as a context
    manager (the last stage finishes on exit)."""

    def __init__(self, description: str, enabled: bool = True):
        self.description, self.enabled = description, enabled
        self.stage, self.t0, self.status = None, 0.0, None

    def __enter__(self):
        if self.enabled and is_terminal(sys.stderr):
            self.status = Console(file=sys.stderr).status(self.description)
            self.status.start()
        return self

    def __call__(self, stage: str) -> None:
        if not self.enabled:
            return
        self._finish()
        self.stage, self.t0 = stage, time.perf_counter()
        if self.status is not None:
            self.status.update(f"{self.description}: {stage}")

    def _finish(self):
        if self.stage is not None and self.status is None:
            print(f"{self.description}: {self.stage} done ({time.perf_counter() - self.t0:.1f} s)",
                  file=sys.stderr, flush=True)
        self.stage = None

    def __exit__(self, *exc):
        if exc[0] is None:
            self._finish()
        if self.status is not None:
            self.status.stop()
        return False
