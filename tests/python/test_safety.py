# Issue 48 ("Nothing silently wrong III"), the Python findings: a value the module accepts does
# what it says, a bad one is refused with a message naming it, and a Damper cannot be broken
# from a second thread or by Ctrl-C. Each test failed on main 78169b8 (a segfault or double
# free, a partial cycle recorded as a cycle, AttributeError, a silent override, empty records,
# cycle(-5) running every cycle, sweep(jobs=-3) running).
import json
import os
import signal
import threading

import numpy as np
import pytest

import vppdem
from conftest import SMALL
from test_studies import TINY


def test_a_second_thread_is_refused_while_a_stage_runs():
    # A stage runs without the interpreter lock; a call on the same Damper from another thread
    # used to race it (a second cycle() crashed with a segfault or "double free or corruption").
    # Now it is refused with a RuntimeError saying why, and the running stage is not disturbed.
    d = vppdem.Damper(settings=SMALL)
    started = threading.Event()
    errors, from_callback = [], []

    def progress(stage, done, total, time):
        if not started.is_set():
            # The progress callback runs on the running thread, between steps: a read is allowed
            # there, a stage is not (it would run inside the one running).
            from_callback.append(d.stage)
            try:
                d.cycle(1)
            except RuntimeError as e:
                from_callback.append(str(e))
            started.set()

    def run():
        try:
            d.prepare(progress=progress)
        except BaseException as e:  # noqa: B036 (reported below)
            errors.append(e)

    t = threading.Thread(target=run)
    t.start()
    try:
        assert started.wait(60)
        for call in (lambda: d.stage, lambda: d.W, lambda: d.summary(), lambda: d.save("never.ckpt"),
                     lambda: d.cycle(1), lambda: d.prepare()):
            with pytest.raises(RuntimeError, match=r"running prepare\(\) in another thread; one call at a time"):
                call()
    finally:
        t.join()
    assert not errors, errors
    assert from_callback[0] in ("fill", "compress")
    assert "called from within prepare() (its progress callback)" in from_callback[1]
    assert d.stage == "prepared"  # the run went on undisturbed, and the object is free again
    assert not os.path.exists("never.ckpt")
