"""Signals held back while native code must not be interrupted.

Python raises KeyboardInterrupt (SIGINT) or the command line's Terminated (SIGTERM) between two
bytecodes, which may be in the middle of a sequence of native calls that leave a library's
objects half built: interrupting pyvista/VTK between creating a render window and closing it
crashed the interpreter with a segmentation fault (1 of 12 trials). `deferred_signals`
records SIGINT and SIGTERM inside its block and delivers them (to the handlers that were installed
before) when the block ends, so the interruption arrives at a clean point, a fraction of a second
later.
"""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def deferred_signals(signals=SIGNALS):
    """Hold back `signals` inside the block; deliver the first one received when it ends. Only
    the main thread receives signals: elsewhere (a Dask worker thread) this does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[tuple[int, object]] = []
    previous = {}
    try:
        for sig in signals:
            previous[sig] = signal.signal(sig, lambda s, frame: received.append((s, frame)))
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    if received:
        sig, frame = received[0]
        handler = previous[sig]
        if callable(handler):
            handler(sig, frame)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(sig)
