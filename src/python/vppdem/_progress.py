"""Progress of a running call (a bar, a line now and then, or the user's callable) and the call
itself, run with the progress callback the engine calls."""

import sys


class _Bar:
    """What both progress callbacks share: the user's callable, or a tqdm bar when tqdm is
    installed and progress is True (else lines on stderr)."""

    def __init__(self, progress):
        self.user = progress if callable(progress) else None
        self.bar = None
        self.tqdm = None
        if progress is True:
            try:
                from tqdm import tqdm

                self.tqdm = tqdm
            except ImportError:
                pass

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _duration(s):
    """A time in seconds as the command's progress line writes it (12s, 3m05s, 2h10m)."""
    if s < 60:
        return f"{s:.0f}s"
    if s < 3600:
        return f"{int(s // 60)}m{int(s) % 60:02d}s"
    return f"{int(s // 3600)}h{(int(s) % 3600) // 60:02d}m"


# The stages that end when the sample is at rest: their total is the most they can take.
def _at_most(stage):
    return stage.startswith(("prepare: fill", "prepare: re-fill")) or stage == "vacuum"


class _Progress(_Bar):
    """The callback handed to the C++ stages (called every 256 steps, with the lock held). Each
    stage (each re-fill is one) counts its steps from its start, so its percent never goes back;
    the time left is the stage's steps left over their rate since the stage began here."""

    def __init__(self, progress):
        super().__init__(progress)
        self.stage = None
        self.last = 0.0
        self.since = (0.0, 0)  # the stage's first call here: (clock [s], steps)

    def __call__(self, stage, done, total, time):
        if self.user is not None:
            self.user(stage, done, total, time)
            return
        if self.tqdm is not None:
            if stage != self.stage:
                self.close()
                self.bar = self.tqdm(total=total, desc=stage, unit="step")
                self.stage = stage
            self.bar.n = min(done, total)
            self.bar.refresh()
            return
        import time as _t

        now = _t.monotonic()
        if stage != self.stage:
            self.since = (now, done)
        if now - self.last > 2.0 or stage != self.stage:
            self.last, self.stage = now, stage
            t0, d0 = self.since
            rate = (done - d0) / (now - t0) if now > t0 and done > d0 else 0.0
            left = "?" if rate <= 0 else _duration((max(total, done) - done) / rate)
            bound = "at most " if _at_most(stage) else ""
            print(f"[{stage}] {100.0 * min(done, total) / max(total, 1):5.1f}%  t = {time:.6g} s  "
                  f"{rate:.0f} steps/s  {bound}{left} left", file=sys.stderr)


class _CaseProgress(_Bar):
    """The callback of a sweep or calibration: (done, total, case) after each finished case,
    called from the study's threads with the lock held."""

    def __call__(self, done, total, case):
        if self.user is not None:
            self.user(done, total, case)
            return
        if self.tqdm is not None:
            if self.bar is None:
                self.bar = self.tqdm(total=total, desc="cases", unit="case")
            self.bar.n = min(done, total)
            self.bar.set_postfix_str(case)
            return
        print(f"[{done}/{total}] {case}", file=sys.stderr)


def _run(call, progress, *args, callback=_Progress, **kwargs):
    """call(*args, hook, **kwargs): hook a `callback` made from progress (None when progress is
    None or False), closed (its bar) however the call ends."""
    hook = None if progress is None or progress is False else callback(progress)
    try:
        return call(*args, hook, **kwargs)
    finally:
        if hook is not None:
            hook.close()
