"""Progress bars for runs: tqdm's when it is installed (an optional
dependency, `pip install tqdm`), else one plain line on stderr."""
import math
import sys
import time as clock


class Progress:
    """One line on stderr: time reached, steps, particle-steps per second, ETA.
    Redrawn in place on a terminal; otherwise (a log file, CI) a line at each
    tenth of the run and at its end, so that a long run's log stays short."""

    def __init__(self, end, particles, enabled=True, start=0.0):
        self.end, self.particles, self.enabled = end, particles, enabled
        self.start = start
        self.terminal = enabled and sys.stderr.isatty()
        self.started = clock.perf_counter()
        self.last_draw = 0.0
        self.first_step = None
        self.written_steps = None  # off a terminal: the step count of the last line
        self.tenths_written = -1   # off a terminal: the last tenth of the run a line said

    def update(self, solver, final=False):
        """Redraws (at most five times a second on a terminal); returns False
        so that it can serve as advance_to's progress callback."""
        if not self.enabled:
            return False
        if self.first_step is None:
            self.first_step = solver.step_count
        now = clock.perf_counter()
        if self.terminal and not (final or now - self.last_draw > 0.2):
            return False
        t, steps = solver.time, solver.step_count
        done = (t - self.start) / (self.end - self.start) if self.end > self.start else 1.0
        if not self.terminal:
            tenths = int(math.floor(10 * min(1.0, max(0.0, done)) + 1e-9))
            if final and steps == self.written_steps:
                return False  # the last line said it already
            if not final and tenths <= self.tenths_written:
                return False
            self.tenths_written = tenths
        self.last_draw = now
        wall = now - self.started
        rate = self.particles * (steps - self.first_step) / wall if wall > 0 else 0.0
        eta = wall * (1 - done) / done if done > 0 else float("nan")
        filled = int(30 * min(1.0, max(0.0, done)))
        line = "[%s%s] t = %.4g / %.4g s, %d steps, %.3g particle-steps/s, ETA %s" % (
            "#" * filled, "." * (30 - filled), t, self.end, steps, rate,
            "%.0f s" % eta if math.isfinite(eta) else "?")
        if self.terminal:
            sys.stderr.write("\r" + line + ("\n" if final else ""))
        else:
            sys.stderr.write(line + "\n")
            self.written_steps = steps
        sys.stderr.flush()
        return False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        pass


class TqdmProgress:
    """tqdm's bar over simulated time (s), with the step count."""

    def __init__(self, tqdm, solver, end):
        self.start = solver.time
        self.shown = self.start
        self.bar = tqdm(total=end - self.start, unit="s", unit_scale=False,
                        desc="t / %.4g s" % end, file=sys.stderr,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} s "
                                   "[{elapsed}<{remaining}{postfix}]")

    def update(self, solver):
        """advance_to's progress callback: moves the bar; never stops the run."""
        t = solver.time
        self.bar.update(t - self.shown)
        self.shown = t
        self.bar.set_postfix_str("%d steps" % solver.step_count, refresh=False)
        return False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.bar.close()


def bar_for(solver, end):
    """The bar advance_to(progress=True) draws: tqdm's, or the plain line."""
    try:
        from tqdm import tqdm
    except ImportError:
        bar = Progress(end, solver.particle_count, start=solver.time)
        bar.terminal = True  # a line redrawn in place, whatever stderr is
        return _Finishing(bar, solver)
    return TqdmProgress(tqdm, solver, end)


class _Finishing:
    """The plain bar, drawn a last time when the run ends."""

    def __init__(self, bar, solver):
        self.bar, self.solver = bar, solver

    def update(self, solver):
        return self.bar.update(solver)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.bar.update(self.solver, final=True)
