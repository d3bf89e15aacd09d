"""How many of this process's cores are free for the engine's threads.

Each time step of the engine is phases that end when every thread has done its part: a thread
that is done waits for the other, and on cores that other processes keep busy the other is
often descheduled, so the whole step waits for its turn (a waiting thread does the tasks nobody
has started, but not the half-done task of a descheduled one). The engine therefore runs on no more threads than there are free cores: the cores it may run on
(`os.sched_getaffinity`) less the processor time that the other processes took on them since
the last look (`/proc/stat`, less this process's own time). Without `/proc/stat` (not Linux) it
does not limit the threads.

What other work asks of the cores (`others_runnable`) is read otherwise: processor time shows
what the others got, which beside this process is less than they want (two CPU-bound processes
and this one on 2 cores get 2/3 of a core each), so the plan's estimate counts the tasks ready
to run instead (`procs_running` in `/proc/stat`).
"""

from __future__ import annotations

import math
import os
import time
from typing import NamedTuple

CHECK_INTERVAL_S = 0.5  # how often the free cores are looked at again
FIRST_LOOK_S = 0.1  # the shortest first window: a window of fewer clock ticks is too coarse


class Sample(NamedTuple):
    """What the cores and this process had done by a moment."""

    wall_s: float
    own_s: float  # this process's processor time, all its threads
    busy_ticks: int  # of the cores this process may run on, in clock ticks
    all_ticks: int
    cores: int


def sample() -> Sample | None:
    """Now, or None where the cores' times cannot be read."""
    try:
        cpus = {f"cpu{k}" for k in os.sched_getaffinity(0)}
        with open("/proc/stat", "rb") as stat:
            lines = stat.read().decode().splitlines()
    except (AttributeError, OSError):
        return None
    busy = total = cores = 0
    for line in lines:
        name, _, rest = line.partition(" ")
        if name in cpus:
            ticks = [int(t) for t in rest.split()[:8]]  # user nice system idle iowait irq softirq steal
            total += sum(ticks)
            busy += sum(ticks) - ticks[3] - ticks[4]
            cores += 1
    if cores == 0:
        return None
    return Sample(time.monotonic(), time.process_time(), busy, total, cores)


def others_runnable() -> float | None:
    """The tasks ready to run now other than this one (the caller is running: `procs_running`
    less one), or None where `/proc/stat` cannot be read."""
    try:
        with open("/proc/stat", "rb") as stat:
            for line in stat.read().decode().splitlines():
                if line.startswith("procs_running "):
                    return max(0, int(line.split()[1]) - 1)
    except OSError:
        pass
    return None


def free_cores(before: Sample, after: Sample) -> int | None:
    """The cores the other processes left free between two samples, at least 1; None when the
    window holds no clock tick."""
    ticks = after.all_ticks - before.all_ticks
    wall = after.wall_s - before.wall_s
    if ticks <= 0 or wall <= 0:
        return None
    busy = after.cores * (after.busy_ticks - before.busy_ticks) / ticks
    others = busy - (after.own_s - before.own_s) / wall
    return max(1, math.floor(after.cores - others + 0.5))


class FreeCores:
    """The free cores of late, looked at again at most every CHECK_INTERVAL_S; one until the
    first look (a run's first steps) and in a process newly forked."""

    def __init__(self):
        self._start()

    def _start(self) -> None:
        self._pid = os.getpid()
        self._last = sample()
        self._next_s = time.monotonic() + FIRST_LOOK_S
        self.count = 1 if self._last is not None else None

    def now(self) -> int | None:
        """The free cores (None: unknown, no limit)."""
        if self._last is None:
            return None
        now_s = time.monotonic()
        if now_s < self._next_s:
            return self.count
        if os.getpid() != self._pid:
            self._start()
            return self.count
        latest = sample()
        if latest is not None:
            self.count = free_cores(self._last, latest) or self.count
            self._last = latest
        self._next_s = now_s + CHECK_INTERVAL_S
        return self.count
