"""Progress of long calls (uascma.run_campaign): a callback, tqdm when it is installed, or plain lines.

The compiled core counts finished items (common/progress.h) and calls a reporter made here with
``(label, done, total, elapsed_s)`` from the calling thread, ten times a second at most, and once at the end.
What the user passes as ``progress=``:

* ``True`` (the default): a tqdm bar when the tqdm package is installed (``tqdm.auto``: a widget in a
  notebook), else a plain line on ``sys.stderr`` every 10 s or each further 5 % (at most one a second), as the
  command-line tool prints on a non-terminal stderr;
* ``False`` or ``None``: nothing;
* a callable ``progress(done, total)``: called with the counts (flights for a campaign).
"""
import sys
import time

from . import _uascma

# The same rule as the command-line tool on a non-terminal stderr (common/progress.h, ours).
LINE_PERIOD_S = _uascma._PROGRESS_LINE_PERIOD_S
LINE_STEP_FRACTION = _uascma._PROGRESS_LINE_STEP_FRACTION
LINE_MIN_GAP_S = _uascma._PROGRESS_LINE_MIN_GAP_S


def progress_line(label, done, total, elapsed_s):
    """One progress line, as the command-line tool prints it (common/progress.cc FormatProgressLine)."""
    return _uascma._format_progress_line(label, int(done), int(total), float(elapsed_s))


class _Lines:
    """Plain lines on a stream: every LINE_PERIOD_S, or sooner at each further LINE_STEP_FRACTION."""

    def __init__(self, stream=None):
        self._stream = stream
        self._last_time = None
        self._last_done = 0
        self._printed = 0
        self._last = None

    def __call__(self, label, done, total, elapsed_s):
        now = time.monotonic()
        if self._last_time is None:
            self._last_time = now
        self._last = (label, done, total, elapsed_s)
        since = now - self._last_time
        step = (done - self._last_done) / max(total, 1)
        if since >= LINE_PERIOD_S or (step >= LINE_STEP_FRACTION and since >= LINE_MIN_GAP_S):
            self._print(label, done, total, elapsed_s)
            self._last_time = now

    def _print(self, label, done, total, elapsed_s):
        stream = self._stream if self._stream is not None else sys.stderr
        print(progress_line(label, done, total, elapsed_s), file=stream, flush=True)
        self._last_done = done
        self._printed += 1

    def close(self):
        # Where the work ended, for a reader who saw it under way.
        if self._printed and self._last is not None and self._last[1] != self._last_done:
            self._print(*self._last)


class _Tqdm:
    def __init__(self, tqdm):
        self._tqdm = tqdm
        self._bar = None

    def __call__(self, label, done, total, elapsed_s):
        if self._bar is None or self._bar.total != total:
            if self._bar is not None:
                self._bar.close()
            self._bar = self._tqdm(total=total, desc=label, unit="flight")
        self._bar.update(done - self._bar.n)

    def close(self):
        if self._bar is not None:
            self._bar.close()


class _Callback:
    def __init__(self, fn):
        self._fn = fn

    def __call__(self, label, done, total, elapsed_s):
        self._fn(done, total)

    def close(self):
        pass


def make_reporter(progress):
    """The reporter for a user's ``progress=`` value: an object called (label, done, total, elapsed_s) with a
    close(), or None for no progress."""
    if progress is None or progress is False:
        return None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _Lines()
        return _Tqdm(tqdm)
    if callable(progress):
        return _Callback(progress)
    from ._uascma import InputError

    raise InputError(f"progress: progress: True, False, None or a callable progress(done, total), got {progress!r}")
