"""Ctrl-C during a long run: the kernel polls gtet_options.cancel between BRIO rounds, the
binding takes the GIL back for a moment and runs Python's signal handlers, and
KeyboardInterrupt comes out of gigatet.Delaunay early, with nothing leaked (the leak test
covers the error paths) and the next run unaffected."""
import _thread
import threading
import time

import numpy as np
import pytest

import gigatet


@pytest.mark.skipif(not gigatet._gigatet.HAVE_CANCEL, reason="library without gtet_options.cancel")
def test_keyboard_interrupt_stops_the_run():
    p = np.random.default_rng(2).random((1000000, 3))
    t = time.perf_counter()
    full = gigatet.Delaunay(p, threads=1)
    whole = time.perf_counter() - t
    timer = threading.Timer(0.05, _thread.interrupt_main)
    t = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        gigatet.Delaunay(p, threads=1)
        time.sleep(5)  # not reached when the kernel stopped; else the handler runs here
    stopped = time.perf_counter() - t
    timer.join()
    assert stopped < 0.8 * whole, "stopped after %.2f s of a %.2f s run" % (stopped, whole)
    again = gigatet.Delaunay(p[:20000])
    again.check()
    assert full.nsimplex > 0
