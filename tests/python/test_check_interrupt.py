"""Ctrl-C during a long check (NOTES.md Q63, E246): Delaunay.check polls Python's signal
handlers through gtet_check_options.cancel on the calling thread, inside the checker's long
loops too, so a SIGINT sent during the full empty-sphere test (O(n*m): tens of seconds for this
mesh) comes out as KeyboardInterrupt within a fraction of a second, and the mesh and the next
check are unaffected."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import gigatet

pytestmark = pytest.mark.skipif(not gigatet._gigatet.HAVE_CANCEL,
                                reason="library without gtet_options.cancel")


def _sigint_after(delay):
    """Send SIGINT to this process after delay seconds; returns the thread and a list that
    receives the time it was sent."""
    sent = []

    def fire():
        time.sleep(delay)
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    t = threading.Thread(target=fire, daemon=True)
    t.start()
    return t, sent


def test_sigint_stops_full_check():
    # 20000 points: the full test compares each of ~130000 tets with every vertex (~2.6e9
    # insphere tests), far longer than the 1 s allowed below
    d = gigatet.Delaunay(np.random.default_rng(63).random((20000, 3)))
    t, sent = _sigint_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        d.check(full=True)
        time.sleep(10)  # not reached when the check stopped; else the handler runs here
    stopped = time.perf_counter()
    t.join()
    assert sent, "the signal was not sent"
    assert stopped - sent[0] < 1.0, "KeyboardInterrupt %.2f s after SIGINT" % (stopped - sent[0])
    assert d.check()["ok"]  # the mesh and the next check are unaffected

